/* Thread independence of MIPS: the local steps of one colour run in parallel over fixed blocks and
 * every sum the stopping rules compare (energies, a sweep's decrease) adds fixed blocks in order,
 * so one thread and two give the same uv to the bit, flip-free. The mesh (lion-head, Loop x1:
 * 66.7k triangles) has colours above one block, so the parallel paths run; SK_TEST_QUICK=1 (the
 * sanitizer run, no OpenMP) keeps to lion-head itself. */
#include "testutil.h"

#include <stdlib.h>
#include <string.h>

/* libgomp's, when the library is built with OpenMP (weak: absent in the SK_OPENMP=OFF build) */
void omp_set_num_threads(int n) __attribute__((weak));
int omp_get_max_threads(void) __attribute__((weak));

static bool quick(void)
{
    const char *q = getenv("SK_TEST_QUICK");
    return q && *q && strcmp(q, "0") != 0;
}

static sk_mesh *test_mesh(void)
{
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("lion-head.off"));
    if (quick())
        return m;
    sk_mesh *fine = NULL;
    sk_subdiv_opts so = {.scheme = SK_SUBDIV_LOOP, .iterations = 1};
    assert_int_equal(sk_mesh_subdivide(m, &so, &fine, NULL), SK_OK);
    sk_mesh_destroy(&m);
    return fine;
}

static void set_threads(int n)
{
    if (omp_set_num_threads)
        omp_set_num_threads(n);
}

/* Hierarchical MIPS (the default schedule: global steps on the coarse levels, certified stop)
 * with 1 and with 2 threads. */
static void given_lion_when_hierarchical_with_one_and_two_threads_then_same_uv(void **state)
{
    (void)state;
    sk_mesh *m = test_mesh();
    size_t n2 = 2 * m->num_vertices;
    double *uv[2] = {malloc(n2 * sizeof(double)), malloc(n2 * sizeof(double))};
    sk_hparam_stats s[2];
    int saved = omp_get_max_threads ? omp_get_max_threads() : 1;
    for (int k = 0; k < 2; ++k) {
        set_threads(k + 1);
        sk_hparam_opts o = {.seed = 7};
        assert_int_equal(sk_param_hierarchical(m, &o, uv[k], &s[k], NULL), SK_OK);
    }
    set_threads(saved);
    assert_int_equal(s[0].steps, s[1].steps);
    assert_true(s[0].energy == s[1].energy);
    /* certified near convergence on the subdivided lion; lion-head itself (quick) stops at
     * a looser bound (3.6e-3: the bound is loose where no map is nearly conformal) */
    assert_true(s[0].gap_bound <= (quick() ? 1e-2 : 1e-3));
    assert_memory_equal(uv[0], uv[1], n2 * sizeof(double));
    sk_param_metrics pm;
    assert_int_equal(sk_param_metrics_compute(m, uv[1], &pm, NULL), SK_OK);
    assert_int_equal(pm.flipped, 0);
    for (int k = 0; k < 2; ++k) {
        sk_hparam_stats_release(&s[k]);
        free(uv[k]);
    }
    sk_mesh_destroy(&m);
}

/* Plain sweeps from a Floater start (no hierarchy, no global step): the running energy (the sum of
 * the sweeps' decreases) and the stop on it agree for 1 and 2 threads. */
static void given_lion_when_sweeps_with_one_and_two_threads_then_same_uv_and_energy(void **state)
{
    (void)state;
    sk_mesh *m = test_mesh();
    size_t n2 = 2 * m->num_vertices;
    double *start = malloc(n2 * sizeof(double)), *uv[2] = {malloc(n2 * sizeof(double)),
                                                           malloc(n2 * sizeof(double))};
    sk_param_opts po = {.method = SK_PARAM_FLOATER, .boundary.shape = SK_BOUNDARY_CIRCLE};
    assert_int_equal(sk_param_linear(m, &po, start, NULL, NULL), SK_OK);
    sk_mips_stats s[2];
    int saved = omp_get_max_threads ? omp_get_max_threads() : 1;
    for (int k = 0; k < 2; ++k) {
        set_threads(k + 1);
        memcpy(uv[k], start, n2 * sizeof(double));
        sk_mips_opts o = {.boundary = SK_BOUNDARY_FREE, .max_sweeps = quick() ? 4 : 6, .seed = 3};
        assert_int_equal(sk_param_mips(m, &o, uv[k], &s[k], NULL), SK_OK);
    }
    set_threads(saved);
    assert_int_equal(s[0].sweeps, s[1].sweeps);
    assert_true(s[0].energy == s[1].energy);
    assert_true(s[1].energy < s[1].energy_start);
    assert_memory_equal(uv[0], uv[1], n2 * sizeof(double));
    free(start);
    for (int k = 0; k < 2; ++k)
        free(uv[k]);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_lion_when_hierarchical_with_one_and_two_threads_then_same_uv),
        cmocka_unit_test(given_lion_when_sweeps_with_one_and_two_threads_then_same_uv_and_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
