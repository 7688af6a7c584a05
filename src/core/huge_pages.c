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
