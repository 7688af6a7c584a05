/* Monotonic clock for the timings in reports and benchmarks, and the process's CPU clock. */
#define _POSIX_C_SOURCE 200809L
#include "surfkit/core.h"

#include <time.h>

double sk_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double sk_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
