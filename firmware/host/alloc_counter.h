/* Allocations counted per zone since start (alloc_counter.c). */
#ifndef PV_ALLOC_COUNTER_H
#define PV_ALLOC_COUNTER_H
long pv_alloc_count(int zone);
#endif
