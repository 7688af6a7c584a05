/* LD_PRELOAD shim for bench/smooth.sh's before/after stage table: CLOCK_MONOTONIC reads the
 * process CPU time (all threads), so the library's stage seconds (sk_seconds) become CPU seconds,
 * comparable on a loaded machine. Not part of the library. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <time.h>

int clock_gettime(clockid_t id, struct timespec *ts)
{
    static int (*real)(clockid_t, struct timespec *);
    if (!real)
        *(void **)&real = dlsym(RTLD_NEXT, "clock_gettime");
    return real(id == CLOCK_MONOTONIC ? CLOCK_PROCESS_CPUTIME_ID : id, ts);
}
