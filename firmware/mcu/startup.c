/* Cortex-M7 reset and fault handling for the bare-metal test app on
 * qemu-system-arm -M mps2-an500. The vector table sits at 0 (the code RAM);
 * reset enables the FPU (the core is built for hard float) and enters
 * newlib's rdimon crt0 (_start), which zeroes .bss, sets up semihosting
 * (files, argv, exit) and calls main. A fault ends the run through
 * semihosting with a failure, so CTest sees it instead of a hang. */
#include <stdint.h>

extern uint32_t __stack_top; /* mps2_an500.ld */
extern void _start(void);    /* newlib rdimon crt0 */

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)

static void semihost_exit_failure(void) {
  /* SYS_EXIT (0x18) with ADP_Stopped_RunTimeErrorUnknown (0x20023). */
  register uint32_t r0 __asm__("r0") = 0x18u;
  register uint32_t r1 __asm__("r1") = 0x20023u;
  __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
  for (;;) {
  }
}

void Reset_Handler(void) {
  SCB_CPACR |= (0xFu << 20); /* CP10, CP11: full access to the FPU */
  __asm__ volatile("dsb\n\tisb" ::: "memory");
  _start();
  semihost_exit_failure(); /* _start does not return */
}

void Fault_Handler(void) { semihost_exit_failure(); }

__attribute__((section(".vectors"), used)) void (*const pv_vectors[16])(void) = {
    (void (*)(void))(&__stack_top),
    Reset_Handler,
    Fault_Handler, /* NMI */
    Fault_Handler, /* HardFault */
    Fault_Handler, /* MemManage */
    Fault_Handler, /* BusFault */
    Fault_Handler, /* UsageFault */
    0, 0, 0, 0,
    Fault_Handler, /* SVCall */
    Fault_Handler, /* DebugMon */
    0,
    Fault_Handler, /* PendSV */
    Fault_Handler, /* SysTick */
};
