/* Issue 17 (reliability): library-level regressions for the defects the hostile-input campaign
 * found; each test names the defect. */
#include "testutil.h"

#include "surfkit/analysis.h"
#include "surfkit/smooth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* OpenBLAS's own API (cblas.h would pull the whole BLAS interface in) */
void openblas_set_num_threads(int num_threads);
int openblas_get_num_threads(void);

static int blas_threads_seen(void *user, double fraction)
{
    if (fraction >= 1.0)
        return 0; /* the final call comes after the pipeline restored the caller's count */
    int *max_seen = user;
    int n = openblas_get_num_threads();
    if (n > *max_seen)
        *max_seen = n;
    return 0;
}

/* the small dense solves of smooth ran with every OpenBLAS thread (cow: 20.2 s instead of 12.2 s);
 * inside the pipeline one thread, afterwards the caller's count again */
static void given_four_blas_threads_then_smooth_runs_with_one_and_restores_four(void **state)
{
    (void)state;
    openblas_set_num_threads(4);
    assert_int_equal(openblas_get_num_threads(), 4);
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("sphere.off"));
    int seen = 0;
    sk_smooth_opts o = {.progress = blas_threads_seen, .progress_user = &seen};
    sk_smooth *s = NULL;
    assert_int_equal(sk_smooth_build(m, &o, &s, NULL), SK_OK);
    assert_int_equal(seen, 1);
    assert_int_equal(openblas_get_num_threads(), 4);
    sk_smooth_destroy(&s);
    /* the quadric normals (one 5x5 dgesv per vertex) likewise restore the count */
    double *n = malloc(3 * m->num_vertices * sizeof(double));
    assert_non_null(n);
    assert_int_equal(sk_mesh_vertex_normals(m, SK_NORMALS_QUADRIC, n, NULL), SK_OK);
    assert_int_equal(openblas_get_num_threads(), 4);
    free(n);
    sk_mesh_destroy(&m);
    openblas_set_num_threads(1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_four_blas_threads_then_smooth_runs_with_one_and_restores_four),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
