/* The hierarchical solver of the linear methods against the direct one: on every shared disk and
 * for every linear method, the same uv to 1e-8 of the layout size and the same flip count, with
 * the multilevel path really taken (more than one level, a residual at the tolerance). Also the
 * direct solver's orderings agree with each other; the same for the algebraic multigrid, also
 * on subdivided disks. SK_TEST_QUICK=1 keeps the small meshes. */
#include "testutil.h"

#include "surfkit/param.h"
#include "surfkit/subdivide.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *meshes[] = {"nefertiti.off", "patch-01.off", "paraboloid-patch.off",
                               "three_peaks.off", "mushroom.off", "lion-head.off"};

/* Every linear method on m solved directly and by `solver` (coarsest level of at most
 * `coarse` vertices): the multilevel path taken (at least min_levels levels, converged), the same
 * uv to 1e-8 of the layout, the same flips and MIPS sum. */
static void compare_with_direct(const sk_mesh *m, const char *name, sk_linear_solver solver,
                                size_t coarse, size_t min_levels)
{
    size_t nv = m->num_vertices;
    double *ud = calloc(2 * nv, sizeof *ud), *uh = calloc(2 * nv, sizeof *uh);
    for (int method = SK_PARAM_TUTTE; method <= SK_PARAM_LSCM; ++method) {
        sk_param_opts o = {0};
        o.method = (sk_param_method)method;
        sk_error err;
        sk_param_stats sd, sh;
        if (sk_param_linear(m, &o, ud, &sd, &err) != SK_OK)
            fail_msg("%s %s direct: %s", name, sk_param_method_name(o.method), err.message);
        o.solver = solver;
        o.coarse_vertices = coarse; /* a real hierarchy even on the small meshes */
        if (sk_param_linear(m, &o, uh, &sh, &err) != SK_OK)
            fail_msg("%s %s solver %d: %s", name, sk_param_method_name(o.method), (int)solver,
                     err.message);
        /* the multilevel path was taken and converged */
        if (sh.levels < min_levels)
            fail_msg("%s %s: %zu levels", name, sk_param_method_name(o.method), sh.levels);
        assert_true(sh.iterations >= 1);
        assert_true(sh.residual <= 1e-12);
        assert_true(sh.solve.factor_nnz < sd.solve.factor_nnz);
        double d = skt_uv_difference(nv, ud, uh);
        if (!(d <= 1e-8))
            fail_msg("%s %s: solver %d differs from direct by %.3g of the layout", name,
                     sk_param_method_name(o.method), (int)solver, d);
        sk_param_metrics rd, rh;
        assert_int_equal(sk_param_metrics_compute(m, ud, &rd, NULL), SK_OK);
        assert_int_equal(sk_param_metrics_compute(m, uh, &rh, NULL), SK_OK);
        assert_int_equal(rd.flipped, rh.flipped);
        if (!(fabs(rd.mips_sum - rh.mips_sum) <= 1e-6 * rd.mips_sum))
            fail_msg("%s %s: MIPS sum %.12g direct, %.12g solver %d (uv %.3g)", name,
                     sk_param_method_name(o.method), rd.mips_sum, rh.mips_sum, (int)solver, d);
    }
    free(ud);
    free(uh);
}

static void agree_on_shared(sk_linear_solver solver, size_t coarse)
{
    const char *quick = getenv("SK_TEST_QUICK");
    bool q = quick && quick[0] == '1';
    for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; ++i) {
        if (q && (!strcmp(meshes[i], "lion-head.off") || !strcmp(meshes[i], "mushroom.off")))
            continue;
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(meshes[i]));
        compare_with_direct(m, meshes[i], solver, coarse, 3);
        sk_mesh_destroy(&m);
    }
}

static void test_agrees_with_direct(void **state)
{
    (void)state;
    agree_on_shared(SK_LINEAR_HIERARCHICAL, 60);
}

/* The algebraic multigrid against the direct solve: on the shared disks (coarsest level at most
 * 60 vertices), and on Loop-subdivided disks with the default coarse size (3000 unknowns) that
 * still get 3 or more levels: three_peaks and the lion head subdivided twice (about 32k and 67k
 * vertices). SK_TEST_QUICK=1 (the ASan run): three_peaks subdivided once, coarsest level at most
 * 200 vertices. */
static void test_amg_agrees_with_direct(void **state)
{
    (void)state;
    agree_on_shared(SK_LINEAR_AMG, 60);
    const char *quick = getenv("SK_TEST_QUICK");
    bool q = quick && quick[0] == '1';
    const char *big[] = {"three_peaks.off", "lion-head.off"};
    for (size_t i = 0; i < (q ? 1u : 2u); ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(big[i])), *s = NULL;
        sk_subdiv_opts so = {SK_SUBDIV_LOOP, q ? 1 : 2, NULL, NULL};
        assert_int_equal(sk_mesh_subdivide(m, &so, &s, NULL), SK_OK);
        compare_with_direct(s, big[i], SK_LINEAR_AMG, q ? 200 : 0, 3);
        sk_mesh_destroy(&s);
        sk_mesh_destroy(&m);
    }
}

/* A tighter tolerance gives a smaller residual and more iterations; a budget of one iteration
 * is reported as not converged. */
static void test_tolerance_and_budget(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("three_peaks.off"));
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_param_opts o = {0};
    o.method = SK_PARAM_FLOATER;
    o.solver = SK_LINEAR_HIERARCHICAL;
    o.coarse_vertices = 100;
    sk_param_stats loose, tight;
    o.tolerance = 1e-6;
    assert_int_equal(sk_param_linear(m, &o, uv, &loose, NULL), SK_OK);
    o.tolerance = 1e-13;
    assert_int_equal(sk_param_linear(m, &o, uv, &tight, NULL), SK_OK);
    assert_true(loose.residual <= 1e-6);
    assert_true(tight.residual <= 1e-13);
    assert_true(tight.iterations > loose.iterations);
    o.max_iterations = 1;
    sk_error err;
    assert_int_equal(sk_param_linear(m, &o, uv, NULL, &err), SK_ERR_NUMERIC);
    assert_non_null(strstr(err.message, "residual"));
    free(uv);
    sk_mesh_destroy(&m);
}

/* Small meshes (under twice coarse_vertices) are solved directly: one level, no iteration. */
static void test_small_mesh_direct(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_param_opts o = {0};
    o.method = SK_PARAM_HARMONIC;
    o.solver = SK_LINEAR_HIERARCHICAL;
    sk_param_stats st;
    assert_int_equal(sk_param_linear(m, &o, uv, &st, NULL), SK_OK);
    assert_int_equal(st.levels, 1);
    assert_int_equal(st.iterations, 0);
    free(uv);
    sk_mesh_destroy(&m);
}

/* SK_LINEAR_AUTO: with the crossover below the mesh's free vertices it runs AMG (levels,
 * iterations, its own tolerance 1e-10, the direct uv to 1e-8), at or above them direct (the
 * same uv as direct, exactly, and a direct residual at rounding level); the default crossover
 * keeps a small mesh direct and LSCM direct; an AMG solve that does not converge (budget of one
 * iteration) is redone directly and leaves no error behind. */
static void test_auto_route(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("three_peaks.off"));
    size_t nv = m->num_vertices;
    double *ud = calloc(2 * nv, sizeof *ud), *ua = calloc(2 * nv, sizeof *ua);
    for (int method = SK_PARAM_TUTTE; method <= SK_PARAM_LSCM; ++method) {
        sk_param_opts o = {0};
        o.method = (sk_param_method)method;
        o.coarse_vertices = 100;
        sk_param_stats sd, sa;
        assert_int_equal(sk_param_linear(m, &o, ud, &sd, NULL), SK_OK);
        assert_int_equal(sd.solver, SK_LINEAR_DIRECT);
        assert_true(sd.residual > 0 && sd.residual <= 1e-12);
        o.solver = SK_LINEAR_AUTO;
        o.auto_vertices = sd.interior / 2; /* AMG */
        assert_int_equal(sk_param_linear(m, &o, ua, &sa, NULL), SK_OK);
        assert_int_equal(sa.solver, SK_LINEAR_AMG);
        assert_true(sa.levels >= 2 && sa.iterations >= 1 && sa.residual <= 1e-10);
        assert_true(skt_uv_difference(nv, ud, ua) <= 1e-8);
        o.auto_vertices = sd.interior + 1; /* direct */
        assert_int_equal(sk_param_linear(m, &o, ua, &sa, NULL), SK_OK);
        assert_int_equal(sa.solver, SK_LINEAR_DIRECT);
        assert_int_equal(sa.iterations, 0);
        assert_memory_equal(ud, ua, 2 * nv * sizeof *ud);
        o.auto_vertices = 0; /* the default crossover: far above this mesh */
        assert_int_equal(sk_param_linear(m, &o, ua, &sa, NULL), SK_OK);
        assert_int_equal(sa.solver, SK_LINEAR_DIRECT);
        o.auto_vertices = 1;
        o.max_iterations = 1; /* AMG stops unconverged: redone directly, no stale message */
        sk_error err = {0};
        assert_int_equal(sk_param_linear(m, &o, ua, &sa, &err), SK_OK);
        assert_int_equal(sa.solver, SK_LINEAR_DIRECT);
        assert_int_equal(err.status, SK_OK);
        assert_string_equal(err.message, "");
        assert_memory_equal(ud, ua, 2 * nv * sizeof *ud);
        o.solver = SK_LINEAR_AMG; /* asked for by name: the failure is reported */
        assert_int_equal(sk_param_linear(m, &o, ua, &sa, NULL), SK_ERR_NUMERIC);
    }
    assert_string_equal(sk_linear_solver_name(SK_LINEAR_AUTO), "auto");
    assert_string_equal(sk_linear_solver_name(SK_LINEAR_AMG), "amg");
    assert_string_equal(sk_linear_solver_name((sk_linear_solver)99), "unknown");
    free(ud);
    free(ua);
    sk_mesh_destroy(&m);
}

/* Every ordering of both direct solvers, and the simplicial Cholesky, give the same solution of
 * a mesh system. */
static void test_orderings_agree(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("mushroom.off"));
    size_t nv = m->num_vertices;
    double *w = calloc(m->num_halfedges, sizeof *w);
    assert_int_equal(sk_param_weights(m, SK_PARAM_FLOATER, w, NULL), SK_OK);
    for (int sym = 0; sym < 2; ++sym) {
        /* rows: sum_j w_ij (x_i - x_j) + x_i = 1 over all vertices (regularized: definite) */
        sk_triplets t = {0};
        for (size_t v = 0; v < nv; ++v) {
            uint32_t h0 = m->v_halfedge[v], h = h0;
            double diag = 1;
            do {
                uint32_t j = sk_to(m, h);
                double wij = sym ? 1.0 : w[h];
                diag += wij;
                if (!sym || j < v)
                    assert_int_equal(sk_triplets_add(&t, (uint32_t)v, j, -wij), SK_OK);
                h = sk_cw_out(m, h);
            } while (h != h0);
            assert_int_equal(sk_triplets_add(&t, (uint32_t)v, (uint32_t)v, diag), SK_OK);
        }
        sk_sparse *a = NULL;
        assert_int_equal(sk_sparse_from_triplets(nv, &t, sym ? SK_SPARSE_LOWER : SK_SPARSE_FULL,
                                                 &a, NULL), SK_OK);
        double *b = malloc(nv * sizeof *b), *x0 = malloc(nv * sizeof *x0),
               *x = malloc(nv * sizeof *x);
        for (size_t v = 0; v < nv; ++v)
            b[v] = m->positions[3 * v] + 0.5 * m->positions[3 * v + 2];
        sk_ordering ords[] = {SK_ORDERING_DEFAULT, SK_ORDERING_AUTO, SK_ORDERING_AMD,
                              SK_ORDERING_METIS, SK_ORDERING_NESDIS};
        size_t nord = sizeof ords / sizeof ords[0];
        for (size_t k = 0; k < nord + 1; ++k) {
            /* the last pass: the default ordering with a simplicial factor */
            sk_solver_opts so = {k < nord ? ords[k] : SK_ORDERING_DEFAULT, k == nord, NULL};
            sk_solver *s = NULL;
            sk_error err;
            sk_status st = sk_solver_create_opts(a, sym ? SK_SOLVER_CHOLESKY : SK_SOLVER_LU, &so,
                                                 &s, &err);
            if (st == SK_OK)
                st = sk_solver_factorize(s, a, &err);
            if (st == SK_OK)
                st = sk_solver_solve(s, 1, b, k ? x : x0, &err);
            if (st != SK_OK)
                fail_msg("ordering %d (%s): %s", (int)so.ordering, sym ? "cholmod" : "umfpack",
                         err.message);
            sk_solve_stats ss;
            sk_solver_stats(s, &ss);
            assert_true(ss.factor_nnz >= a->nnz / (sym ? 1 : 2));
            sk_solver_destroy(&s);
            for (size_t v = 0; k && v < nv; ++v)
                assert_true(fabs(x[v] - x0[v]) <= 1e-10 * (1 + fabs(x0[v])));
        }
        free(b);
        free(x0);
        free(x);
        sk_sparse_destroy(&a);
        sk_triplets_free(&t);
    }
    free(w);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_agrees_with_direct),
        cmocka_unit_test(test_amg_agrees_with_direct),
        cmocka_unit_test(test_tolerance_and_budget),
        cmocka_unit_test(test_small_mesh_direct),
        cmocka_unit_test(test_auto_route),
        cmocka_unit_test(test_orderings_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
