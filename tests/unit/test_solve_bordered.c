/* The bordered pair solve of src/solve/bordered.c (one factor of A for both halves, the border
 * coupling through the dense Schur complement) against CHOLMOD on the whole 2n x 2n matrix; bad
 * arguments and an indefinite coupling refused; and LSCM through it (the default direct route
 * from 5000 vertices) against the interleaved 2n x 2n factor of the other orderings. */
#include "testutil.h"

#include "solve/bordered.h"
#include "surfkit/param.h"
#include "surfkit/subdivide.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The graph Laplacian of a planar disk plus shift on the diagonal (lower-stored), its boundary
 * vertices numbered last; *k gets their number. */
static sk_sparse *disk_matrix(int rings, double shift, size_t *n, size_t *k)
{
    sk_mesh *m = skt_planar_disk(rings, 3);
    size_t nv = m->num_vertices, nb = 0;
    for (size_t v = 0; v < nv; ++v)
        nb += sk_is_boundary_v(m, (uint32_t)v);
    uint32_t *idx = malloc(nv * sizeof *idx);
    size_t in = 0, bn = nv - nb;
    for (size_t v = 0; v < nv; ++v)
        idx[v] = (uint32_t)(sk_is_boundary_v(m, (uint32_t)v) ? bn++ : in++);
    sk_triplets t = {0};
    for (size_t v = 0; v < nv; ++v) {
        uint32_t h0 = m->v_halfedge[v], h = h0;
        double deg = 0;
        do {
            uint32_t j = sk_to(m, h);
            deg += 1;
            if (idx[j] < idx[v])
                assert_int_equal(sk_triplets_add(&t, idx[v], idx[j], -1.0), SK_OK);
            h = sk_cw_out(m, h);
        } while (h != h0);
        assert_int_equal(sk_triplets_add(&t, idx[v], idx[v], deg + shift), SK_OK);
    }
    sk_sparse *a = NULL;
    assert_int_equal(sk_sparse_from_triplets(nv, &t, SK_SPARSE_LOWER, &a, NULL), SK_OK);
    sk_triplets_free(&t);
    free(idx);
    sk_mesh_destroy(&m);
    *n = nv;
    *k = nb;
    return a;
}

/* The whole 2n x 2n matrix [A, E C E^T; E C^T E^T, A], lower-stored. */
static sk_sparse *whole_matrix(const sk_sparse *a, size_t k, const double *c)
{
    size_t n = a->n, m = n - k;
    sk_triplets t = {0};
    for (size_t half = 0; half < 2; ++half)
        for (size_t j = 0; j < n; ++j)
            for (int p = a->colptr[j]; p < a->colptr[j + 1]; ++p)
                assert_int_equal(sk_triplets_add(&t, (uint32_t)(half * n + (size_t)a->rowind[p]),
                                                 (uint32_t)(half * n + j), a->values[p]),
                                 SK_OK);
    for (size_t r = 0; r < k; ++r) /* row y_{m+r}, column x_{m+s}: (C^T)(r, s) = C(s, r) */
        for (size_t s = 0; s < k; ++s)
            if (c[s + k * r] != 0)
                assert_int_equal(sk_triplets_add(&t, (uint32_t)(n + m + r), (uint32_t)(m + s),
                                                 c[s + k * r]),
                                 SK_OK);
    sk_sparse *w = NULL;
    assert_int_equal(sk_sparse_from_triplets(2 * n, &t, SK_SPARSE_LOWER, &w, NULL), SK_OK);
    sk_triplets_free(&t);
    return w;
}

/* A coupling with |C_ij| <= scale / k: ||C||_2 <= scale, so the pair stays definite for
 * scale < lambda_min(A). Zero when k = 0. */
static double *coupling(size_t k, double scale, unsigned seed)
{
    double *c = calloc(k ? k * k : 1, sizeof *c);
    unsigned s = seed;
    for (size_t i = 0; i < k * k; ++i) {
        s = s * 1103515245u + 12345u;
        c[i] = scale / (double)k * (2.0 * ((s >> 8) & 0xffff) / 65535.0 - 1.0);
    }
    return c;
}

static double max_abs(size_t n, const double *x)
{
    double d = 0;
    for (size_t i = 0; i < n; ++i)
        d = fmax(d, fabs(x[i]));
    return d;
}

/* given a disk's shifted Laplacian with its boundary last and a definite coupling,
 * when solved bordered (METIS and AMD), then the solution is CHOLMOD's on the whole matrix */
static void test_matches_whole_cholesky(void **state)
{
    (void)state;
    size_t n, k;
    sk_sparse *a = disk_matrix(12, 0.5, &n, &k);
    assert_true(k > 10 && k < n);
    double *c = coupling(k, 0.4, 7);
    sk_sparse *w = whole_matrix(a, k, c);
    double *b = malloc(2 * n * sizeof *b), *x = malloc(2 * n * sizeof *x),
           *ref = malloc(2 * n * sizeof *ref);
    for (size_t i = 0; i < 2 * n; ++i)
        b[i] = sin(0.37 * (double)i) + (i % 5 == 0 ? 1.0 : 0.0);
    assert_int_equal(sk_sparse_solve(w, SK_SOLVER_CHOLESKY, 1, b, ref, NULL, NULL), SK_OK);
    const sk_ordering ords[] = {SK_ORDERING_METIS, SK_ORDERING_AMD};
    for (size_t o = 0; o < 2; ++o) {
        sk_solve_stats ss;
        double res = -1, ord_s = -1;
        sk_error err;
        sk_status st = sk__solve_bordered_pair(a, k, c, ords[o], b, x, &ss, &ord_s, &res, &err);
        if (st)
            fail_msg("bordered: %s", err.message);
        for (size_t i = 0; i < 2 * n; ++i)
            x[i] -= ref[i];
        double d = max_abs(2 * n, x) / max_abs(2 * n, ref);
        if (!(d <= 1e-12))
            fail_msg("ordering %d: %.3g from the whole solve", (int)ords[o], d);
        assert_true(res >= 0 && res <= 1e-13);
        assert_true(ord_s >= 0);
        assert_int_equal(ss.n, 2 * n);
        assert_int_equal(ss.factorizations, 1);
        assert_true(ss.factor_nnz > a->nnz && ss.factor_nnz < w->nnz * 10);
    }
    free(b);
    free(x);
    free(ref);
    free(c);
    sk_sparse_destroy(&w);
    sk_sparse_destroy(&a);
}

/* given no border, then the halves are two solves with A; given every unknown on the border
 * (no interior), then the solution is still the whole matrix's */
static void test_no_border_and_all_border(void **state)
{
    (void)state;
    size_t n, k;
    sk_sparse *a = disk_matrix(5, 1.0, &n, &k);
    double *b = malloc(2 * n * sizeof *b), *x = malloc(2 * n * sizeof *x),
           *ref = malloc(2 * n * sizeof *ref);
    for (size_t i = 0; i < 2 * n; ++i)
        b[i] = cos(0.11 * (double)i * (double)i);
    for (int all = 0; all < 2; ++all) {
        size_t kk = all ? n : 0;
        double *c = coupling(kk, 0.8, 11);
        sk_sparse *w = whole_matrix(a, kk, c);
        assert_int_equal(sk_sparse_solve(w, SK_SOLVER_CHOLESKY, 1, b, ref, NULL, NULL), SK_OK);
        double res = -1;
        assert_int_equal(sk__solve_bordered_pair(a, kk, c, SK_ORDERING_AMD, b, x, NULL, NULL, &res,
                                                 NULL),
                         SK_OK);
        for (size_t i = 0; i < 2 * n; ++i)
            x[i] -= ref[i];
        double d = max_abs(2 * n, x) / max_abs(2 * n, ref);
        if (!(d <= 1e-12))
            fail_msg("border %zu of %zu: %.3g from the whole solve", kk, n, d);
        assert_true(res <= 1e-13);
        free(c);
        sk_sparse_destroy(&w);
    }
    free(b);
    free(x);
    free(ref);
    sk_sparse_destroy(&a);
}

/* given bad arguments or a coupling that makes the pair indefinite, then an error, no solution */
static void test_refusals(void **state)
{
    (void)state;
    size_t n, k;
    sk_sparse *a = disk_matrix(6, 0.1, &n, &k);
    double *b = calloc(2 * n, sizeof *b), *x = calloc(2 * n, sizeof *x);
    b[0] = 1;
    double *c = calloc(k * k, sizeof *c);
    sk_error err;
    assert_int_equal(sk__solve_bordered_pair(a, n + 1, c, SK_ORDERING_AMD, b, x, NULL, NULL, NULL,
                                             &err),
                     SK_ERR_ARG);
    assert_int_equal(sk__solve_bordered_pair(a, k, c, SK_ORDERING_GEOMETRIC, b, x, NULL, NULL,
                                             NULL, &err),
                     SK_ERR_ARG);
    a->storage = SK_SPARSE_FULL;
    assert_int_equal(sk__solve_bordered_pair(a, k, c, SK_ORDERING_AMD, b, x, NULL, NULL, NULL,
                                             &err),
                     SK_ERR_ARG);
    a->storage = SK_SPARSE_LOWER;
    /* C = 10 I: the pair has eigenvalues lambda(S_0) - 10 < 0 */
    for (size_t i = 0; i < k; ++i)
        c[i + k * i] = 10.0;
    assert_int_equal(sk__solve_bordered_pair(a, k, c, SK_ORDERING_AMD, b, x, NULL, NULL, NULL,
                                             &err),
                     SK_ERR_NUMERIC);
    assert_non_null(strstr(err.message, "positive definite"));
    free(b);
    free(x);
    free(c);
    sk_sparse_destroy(&a);
}

/* given disks of 5000 vertices or more (lion head, three peaks and
 * mushroom Loop-subdivided once), when LSCM runs direct with the default ordering (the
 * bordered route) and with METIS (the interleaved 2n x 2n factor), then the same uv to 1e-8 of
 * the layout, the same flips and MIPS sum, a smaller factor, and auto gives direct's bytes */
static void test_lscm_bordered_against_interleaved(void **state)
{
    (void)state;
    const char *quick = getenv("SK_TEST_QUICK");
    bool q = quick && quick[0] == '1';
    const char *names[] = {"lion-head.off", "three_peaks.off", "mushroom.off"};
    const int loops[] = {1, 1, 1};
    for (size_t i = 0; i < (q ? 1u : 3u); ++i) {
        sk_mesh *m0 = skt_read_mesh(skt_shared_mesh(names[i])), *m = NULL;
        sk_subdiv_opts so = {SK_SUBDIV_LOOP, loops[i], NULL, NULL};
        assert_int_equal(sk_mesh_subdivide(m0, &so, &m, NULL), SK_OK);
        size_t nv = m->num_vertices;
        assert_true(nv >= 5000);
        double *ub = calloc(2 * nv, sizeof *ub), *ui = calloc(2 * nv, sizeof *ui),
               *ua = calloc(2 * nv, sizeof *ua);
        sk_param_opts o = {.method = SK_PARAM_LSCM};
        sk_param_stats sb, si, sa;
        sk_error err;
        if (sk_param_linear(m, &o, ub, &sb, &err) != SK_OK)
            fail_msg("%s bordered: %s", names[i], err.message);
        o.ordering = SK_ORDERING_METIS;
        if (sk_param_linear(m, &o, ui, &si, &err) != SK_OK)
            fail_msg("%s interleaved: %s", names[i], err.message);
        o.ordering = SK_ORDERING_DEFAULT;
        o.solver = SK_LINEAR_AUTO;
        assert_int_equal(sk_param_linear(m, &o, ua, &sa, NULL), SK_OK);
        assert_memory_equal(ua, ub, 2 * nv * sizeof *ub);
        assert_int_equal(sb.solver, SK_LINEAR_DIRECT);
        assert_int_equal(sb.solve.n, si.solve.n);
        assert_true(sb.residual <= 1e-12);
        if (!(sb.solve.factor_nnz < si.solve.factor_nnz))
            fail_msg("%s: factor %zu bordered, %zu interleaved", names[i], sb.solve.factor_nnz,
                     si.solve.factor_nnz);
        double d = skt_uv_difference(nv, ui, ub);
        if (!(d <= 1e-8))
            fail_msg("%s: bordered LSCM differs by %.3g of the layout", names[i], d);
        sk_param_metrics rb, ri;
        assert_int_equal(sk_param_metrics_compute(m, ub, &rb, NULL), SK_OK);
        assert_int_equal(sk_param_metrics_compute(m, ui, &ri, NULL), SK_OK);
        assert_int_equal(rb.flipped, ri.flipped);
        assert_true(fabs(rb.mips_sum - ri.mips_sum) <= 1e-6 * ri.mips_sum);
        print_message("%-16s %6zu vertices: factor %zu bordered / %zu interleaved, uv %.2g\n",
                      names[i], nv, sb.solve.factor_nnz, si.solve.factor_nnz, d);
        free(ub);
        free(ui);
        free(ua);
        sk_mesh_destroy(&m);
        sk_mesh_destroy(&m0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_whole_cholesky),
        cmocka_unit_test(test_no_border_and_all_border),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_lscm_bordered_against_interleaved),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
