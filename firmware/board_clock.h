/* The board's clock in a result (docs/protocol/serial.md, Result.time_unix_s).
 * Header-only: the board application and the serial test device
 * (tests/monitor/pv_test_device.cpp) apply the same rule. */
#ifndef PV_BOARD_CLOCK_H
#define PV_BOARD_CLOCK_H

#include <stdint.h>

/* 2024-01-01T00:00:00Z: any earlier clock reading is an unset clock. */
#define PV_BOARD_PLAUSIBLE_UNIX_S INT64_C(1704067200)

/* A result's time_unix_s from the board clock's reading: a board without a
 * battery-backed clock or network time starts in 1970, and such a reading
 * is no date: 0, "clock not set" (pitvol-monitor prints clock-not-set). */
static inline uint64_t pv_board_result_time(int64_t clock_unix_s) {
  return clock_unix_s >= PV_BOARD_PLAUSIBLE_UNIX_S ? (uint64_t)clock_unix_s : 0u;
}

#endif
