/* Small dense LAPACK calls run in loops over vertices and patches; OpenBLAS's own threads only slow
 * them down (issue 17: cow smooth 20.2 s with the default threads, 12.2 s with one), so the
 * pipelines made of such calls run with one BLAS thread and restore the caller's setting. */
#include "core/internal.h"

#include <cblas.h>

int sk__blas_serial_begin(void)
{
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
