/* A transparent-huge-page hint for large fresh work arrays.
 *
 * Building a million-triangle hierarchy or VC1 surface touches hundreds of megabytes of fresh
 * memory. On virtual machines a first-touch page fault can cost over 10 microseconds per 4 KiB
 * page, which made page faults the largest single cost (perf: pvm_irq_enable under
 * exc_page_fault). madvise(MADV_HUGEPAGE) (Linux only; a no-op elsewhere or when THP is off) takes
 * one fault per 2 MiB instead. It changes no result. */
#if defined(__linux__)
#define _DEFAULT_SOURCE 1
#include <sys/mman.h>
#endif

#include "core/internal.h"

#include <pthread.h>
#include <stdint.h>

void sk__huge_hint(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < ((size_t)4 << 20))
        return;
    uintptr_t a = ((uintptr_t)p + 4095u) & ~(uintptr_t)4095u;
    uintptr_t b = ((uintptr_t)p + bytes) & ~(uintptr_t)4095u;
    if (b > a)
        (void)madvise((void *)a, b - a, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

/* The first touch of every page of [p, p + bytes) on a second thread (one written byte per 4 KiB:
 * the page fault, the kernel's zeroing, on a virtual machine the host's fault too), so that a
 * serial stage on this thread runs beside it: on a 2-core machine the second core is idle there.
 * The memory must be writable and unused until sk__prefault_end (its contents are not kept). */
_Static_assert(sizeof(pthread_t) <= sizeof(((sk__prefault *)0)->thread), "pthread_t fits");

static void *prefault_thread(void *arg)
{
    sk__prefault *pf = arg;
    volatile char *c = pf->p;
    for (size_t i = 0; i < pf->bytes; i += 4096)
        c[i] = 0;
    return NULL;
}

void sk__prefault_begin(sk__prefault *pf, void *p, size_t bytes)
{
    pf->p = p;
    pf->bytes = p ? bytes : 0;
    pf->running = pf->bytes > 0 && pthread_create((pthread_t *)pf->thread, NULL, prefault_thread,
                                                  pf) == 0;
}

void sk__prefault_end(sk__prefault *pf)
{
    if (pf->running)
        pthread_join(*(pthread_t *)pf->thread, NULL);
    pf->running = false;
}
