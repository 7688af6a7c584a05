/* Small dense LAPACK calls run in loops over vertices and patches; OpenBLAS's own threads only slow
 * them down (issue 17: cow smooth 20.2 s with the default threads, 12.2 s with one), so the
 * pipelines made of such calls run with one BLAS thread and restore the caller's setting; so do the
 * sparse factorizations and solves (src/solve/solver.c: the measurement is there). */
#include "core/internal.h"

#include <cblas.h>
#ifdef SK_HAVE_OPENMP
#include <omp.h>
#endif

int sk__blas_serial_begin(void)
{
#ifdef SK_HAVE_OPENMP
    if (omp_in_parallel())
        return 1; /* a thread of a parallel loop (the atlas's charts): leave the setting alone,
                   * setting it from several threads at once would race */
#endif
    int n = openblas_get_num_threads();
    if (n > 1)
        openblas_set_num_threads(1);
    return n;
}

void sk__blas_serial_end(int saved)
{
    if (saved > 1)
        openblas_set_num_threads(saved);
}
