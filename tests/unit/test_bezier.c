/* Bezier patches: evaluation against the Bernstein sum, derivatives against finite differences,
 * degree elevation, the exact triangle -> three tensor patches split. */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double rnd(void) { return (double)rand() / RAND_MAX - 0.5; }

/* Appends a patch with random control points and corner ids 10, 11, 12 (, 13); returns its index. */
static size_t random_patch(sk_patch_set *set, sk_patch_kind kind, unsigned du, unsigned dv)
{
    const uint32_t ids[4] = {10, 11, 12, 13};
    size_t k;
    assert_int_equal(sk_patch_set_add(set, kind, du, dv, NULL, ids, &k, NULL), SK_OK);
    double *cp = sk_patch_cp(set, k);
    for (unsigned i = 0; i < 3 * sk_patch_num_points(&set->patches[k]); ++i)
        cp[i] = rnd();
    return k;
}

static double fact(unsigned n) { return n ? n * fact(n - 1) : 1.0; }

static void given_triangle_then_eval_is_the_bernstein_sum(void **state)
{
    (void)state;
    srand(1);
    sk_patch_set set = {0};
    size_t p = random_patch(&set, SK_PATCH_TRIANGLE, 4, 0);
    const double *cp = sk_patch_cp(&set, p);
    double v = 0.2, w = 0.3, u = 0.5, pt[3], ref[3] = {0, 0, 0};
    for (unsigned k = 0; k <= 4; ++k)
        for (unsigned j = 0; j + k <= 4; ++j) {
            unsigned i = 4 - j - k;
            double b = fact(4) / (fact(i) * fact(j) * fact(k)) * pow(u, i) * pow(v, j) * pow(w, k);
            for (int x = 0; x < 3; ++x)
                ref[x] += b * cp[3 * sk_tri_index(4, j, k) + (unsigned)x];
        }
    sk_patch_eval(&set, p, v, w, pt, NULL, NULL, NULL);
    for (int x = 0; x < 3; ++x)
        assert_true(fabs(pt[x] - ref[x]) < 1e-14);
    /* corners */
    sk_patch_eval(&set, p, 1, 0, pt, NULL, NULL, NULL);
    for (int x = 0; x < 3; ++x)
        assert_true(fabs(pt[x] - cp[3 * sk_tri_index(4, 4, 0) + (unsigned)x]) < 1e-15);
    sk_patch_set_free(&set);
}

static void given_patches_then_derivatives_match_finite_differences(void **state)
{
    (void)state;
    srand(2);
    sk_patch_set ps = {0};
    random_patch(&ps, SK_PATCH_TRIANGLE, 4, 0);
    random_patch(&ps, SK_PATCH_TENSOR, 3, 3);
    const double h = 1e-6;
    for (size_t k = 0; k < 2; ++k) {
        double a = 0.25, b = 0.35, p0[3], d1[3], d2[3], pa[3], pb[3], ma[3], mb[3];
        sk_patch_eval(&ps, k, a, b, p0, d1, d2, NULL);
        sk_patch_eval(&ps, k, a + h, b, pa, NULL, NULL, NULL);
        sk_patch_eval(&ps, k, a - h, b, ma, NULL, NULL, NULL);
        sk_patch_eval(&ps, k, a, b + h, pb, NULL, NULL, NULL);
        sk_patch_eval(&ps, k, a, b - h, mb, NULL, NULL, NULL);
        for (int x = 0; x < 3; ++x) {
            assert_true(fabs(d1[x] - (pa[x] - ma[x]) / (2 * h)) < 1e-7);
            assert_true(fabs(d2[x] - (pb[x] - mb[x]) / (2 * h)) < 1e-7);
        }
    }
    sk_patch_set_free(&ps);
}

static void when_elevated_then_the_surface_is_unchanged(void **state)
{
    (void)state;
    srand(3);
    sk_patch_set set = {0};
    size_t t = random_patch(&set, SK_PATCH_TRIANGLE, 3, 0), q = random_patch(&set, SK_PATCH_TENSOR, 3, 2);
    size_t te = set.count, qe = te + 1;
    assert_int_equal(sk_patch_elevate(&set, t, 4, 0, &set, NULL), SK_OK);
    assert_int_equal(sk_patch_elevate(&set, q, 4, 4, &set, NULL), SK_OK);
    assert_int_equal(set.patches[te].degree, 4);
    assert_int_equal(set.patches[qe].degree_v, 4);
    for (int s = 0; s <= 4; ++s)
        for (int r = 0; r + s <= 4; ++r) {
            double a = r / 4.0, b = s / 4.0, p1[3], p2[3];
            sk_patch_eval(&set, t, a, b, p1, NULL, NULL, NULL);
            sk_patch_eval(&set, te, a, b, p2, NULL, NULL, NULL);
            for (int x = 0; x < 3; ++x)
                assert_true(fabs(p1[x] - p2[x]) < 1e-14);
            sk_patch_eval(&set, q, a, b, p1, NULL, NULL, NULL);
            sk_patch_eval(&set, qe, a, b, p2, NULL, NULL, NULL);
            for (int x = 0; x < 3; ++x)
                assert_true(fabs(p1[x] - p2[x]) < 1e-14);
        }
    sk_patch_set_free(&set);
}

static void when_triangle_is_split_then_three_tensor_patches_reproduce_it(void **state)
{
    (void)state;
    srand(4);
    sk_patch_set ts = {0}, sub = {0};
    size_t t = random_patch(&ts, SK_PATCH_TRIANGLE, 4, 0);
    assert_int_equal(sk_patch_split_triangle(&ts, t, &sub, NULL), SK_OK);
    const double E[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double worst = 0.0;
    for (unsigned q = 0; q < 3; ++q) {
        assert_int_equal(sub.patches[q].kind, SK_PATCH_TENSOR);
        assert_int_equal(sub.patches[q].degree, 4);
        assert_int_equal(sub.patches[q].corner_ids[0], ts.patches[t].corner_ids[q]);
        unsigned qn = (q + 1) % 3, qp = (q + 2) % 3;
        for (int i = 0; i <= 10; ++i)
            for (int j = 0; j <= 10; ++j) {
                double s = i / 10.0, r = j / 10.0, bary[3], p1[3], p2[3];
                for (int x = 0; x < 3; ++x)
                    bary[x] = (1 - s) * (1 - r) * E[q][x] + s * (1 - r) * 0.5 * (E[q][x] + E[qn][x]) +
                              s * r / 3.0 + (1 - s) * r * 0.5 * (E[q][x] + E[qp][x]);
                sk_patch_eval(&ts, t, bary[1], bary[2], p1, NULL, NULL, NULL);
                sk_patch_eval(&sub, q, s, r, p2, NULL, NULL, NULL);
                for (int x = 0; x < 3; ++x)
                    worst = fmax(worst, fabs(p1[x] - p2[x]));
            }
    }
    if (worst > 1e-13)
        fail_msg("split deviates by %g", worst);
    /* neighbouring sub-patches share their inner edge: sub q edge 1 (mid -> centroid) is
     * sub q+1 edge 2 reversed (centroid -> mid) */
    for (unsigned q = 0; q < 3; ++q)
        for (int i = 0; i <= 8; ++i) {
            double a[3], b[3];
            sk_patch_edge_point(&sub, q, 1, i / 8.0, a);
            sk_patch_edge_point(&sub, (q + 1) % 3, 2, 1.0 - i / 8.0, b);
            for (int x = 0; x < 3; ++x)
                assert_true(fabs(a[x] - b[x]) < 1e-13);
        }
    /* orientation: sub-patch normals agree with the triangle's */
    double n1[3], n2[3];
    sk_patch_eval(&ts, t, 0.1, 0.1, NULL, NULL, NULL, n1);
    sk_patch_eval(&sub, 0, 0.2, 0.2, NULL, NULL, NULL, n2);
    assert_true(n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2] > 0.0);
    sk_patch_set_free(&ts);
    sk_patch_set_free(&sub);
}

static void given_edges_then_edge_curves_run_corner_to_corner(void **state)
{
    (void)state;
    srand(5);
    sk_patch_set ps = {0};
    random_patch(&ps, SK_PATCH_TRIANGLE, 4, 0);
    random_patch(&ps, SK_PATCH_TENSOR, 3, 3);
    const double tri_corner[3][2] = {{0, 0}, {1, 0}, {0, 1}}, quad_corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (size_t k = 0; k < 2; ++k) {
        unsigned nc = sk_patch_num_corners(&ps.patches[k]);
        for (unsigned c = 0; c < nc; ++c) {
            const double *a = k == 0 ? tri_corner[c] : quad_corner[c];
            const double *b = k == 0 ? tri_corner[(c + 1) % nc] : quad_corner[(c + 1) % nc];
            for (int i = 0; i <= 4; ++i) {
                double t = i / 4.0, p1[3], p2[3];
                sk_patch_edge_point(&ps, k, c, t, p1);
                sk_patch_eval(&ps, k, a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), p2, NULL,
                              NULL, NULL);
                for (int x = 0; x < 3; ++x)
                    assert_true(fabs(p1[x] - p2[x]) < 1e-14);
            }
        }
    }
    sk_patch_set_free(&ps);
}

/* The pool: small headers, points back to back, defaults for missing corner ids, cp that points
 * into the set itself survives the growth of the set, bad patches refused. */
static void given_a_set_when_patches_added_then_points_are_pooled(void **state)
{
    (void)state;
    srand(6);
    assert_true(sizeof(sk_patch) <= 32);
    sk_patch_set set = {0};
    size_t t = random_patch(&set, SK_PATCH_TRIANGLE, 4, 0), q = random_patch(&set, SK_PATCH_TENSOR, 3, 3);
    assert_int_equal(set.count, 2);
    assert_int_equal(set.num_points, 15 + 16);
    assert_int_equal(set.patches[t].first, 0);
    assert_int_equal(set.patches[q].first, 15);
    assert_int_equal(set.patches[t].corner_ids[3], SK_INVALID); /* a triangle has 3 corners */
    assert_int_equal(set.patches[q].corner_ids[3], 13);
    assert_int_equal(set.patches[t].tag, SK_INVALID);
    size_t k;
    assert_int_equal(sk_patch_set_add(&set, SK_PATCH_TENSOR, 2, 1, NULL, NULL, &k, NULL), SK_OK);
    assert_int_equal(set.patches[k].corner_ids[0], SK_INVALID);
    for (unsigned i = 0; i < 3 * 6; ++i)
        assert_true(sk_patch_cp(&set, k)[i] == 0.0);
    /* copies of patch t from its own storage, enough to make the arrays move */
    double ref[3 * 15];
    memcpy(ref, sk_patch_cp(&set, t), sizeof ref);
    for (int r = 0; r < 200; ++r)
        assert_int_equal(sk_patch_set_add(&set, SK_PATCH_TRIANGLE, 4, 0, sk_patch_cp(&set, t),
                                          set.patches[t].corner_ids, &k, NULL), SK_OK);
    assert_int_equal(set.num_points, 15 + 16 + 6 + 200 * 15);
    assert_memory_equal(sk_patch_cp(&set, k), ref, sizeof ref);
    assert_int_equal(set.patches[k].corner_ids[2], 12);
    sk_error err;
    assert_int_equal(sk_patch_set_add(&set, SK_PATCH_TRIANGLE, SK_PATCH_MAX_DEGREE + 1, 0, NULL,
                                      NULL, NULL, &err), SK_ERR_ARG);
    size_t before = set.count;
    sk_patch_set_clear(&set);
    assert_int_equal(set.count, 0);
    assert_int_equal(set.num_points, 0);
    assert_true(set.patch_capacity >= before);
    sk_patch_set_free(&set);
    assert_null(set.patches);
    assert_null(set.points);
}

/* On the CAD path a quartic triangle becomes three biquartic tensor patches: 3 headers and
 * 3 x 25 points (about 1.9 KB, against 4 x 1,976 bytes with the old fixed-size patches), the
 * same surface; tensor patches are copied with their corner ids. */
static void given_a_set_when_converted_to_tensor_then_triangles_split_in_three(void **state)
{
    (void)state;
    srand(7);
    sk_patch_set set = {0}, ts = {0};
    random_patch(&set, SK_PATCH_TRIANGLE, 4, 0);
    random_patch(&set, SK_PATCH_TENSOR, 3, 3);
    set.patches[0].tag = 42;
    assert_int_equal(sk_patch_set_to_tensor(&set, false, &ts, NULL), SK_OK);
    assert_int_equal(ts.count, 4);
    assert_int_equal(ts.num_points, 3 * 25 + 16);
    size_t bytes = 3 * (sizeof(sk_patch) + 25 * 3 * sizeof(double));
    assert_true(bytes < 2000);
    for (size_t q = 0; q < 3; ++q) {
        assert_int_equal(ts.patches[q].kind, SK_PATCH_TENSOR);
        assert_int_equal(ts.patches[q].tag, 42);
        assert_int_equal(ts.patches[q].corner_ids[0], 10 + q);
    }
    assert_int_equal(ts.patches[3].corner_ids[2], 12);
    assert_memory_equal(sk_patch_cp(&ts, 3), sk_patch_cp(&set, 1), 16 * 3 * sizeof(double));
    /* the centroid of the triangle is corner 2 of every sub-patch */
    double c[3], p[3];
    sk_patch_eval(&set, 0, 1.0 / 3.0, 1.0 / 3.0, c, NULL, NULL, NULL);
    for (size_t q = 0; q < 3; ++q) {
        sk_patch_eval(&ts, q, 1.0, 1.0, p, NULL, NULL, NULL);
        for (int x = 0; x < 3; ++x)
            assert_true(fabs(p[x] - c[x]) < 1e-14);
    }
    sk_patch_set_clear(&ts);
    assert_int_equal(sk_patch_set_to_tensor(&set, true, &ts, NULL), SK_OK);
    assert_int_equal(ts.count, 2);
    assert_int_equal(ts.patches[0].corner_ids[3], ts.patches[0].corner_ids[0]);
    assert_int_equal(sk_patch_set_to_tensor(&set, false, &set, NULL), SK_ERR_ARG);
    sk_patch_set_free(&set);
    sk_patch_set_free(&ts);
}

/* Two triangles sharing the side between corner ids 1 and 2 (traversed in opposite directions)
 * and a tensor patch sharing the side 2-3 with the second: the tessellation has one vertex per
 * corner id, n - 1 per shared side, so it is connected along the sides; without corner ids every
 * patch has its own vertices. */
static void given_neighbouring_patches_when_tessellated_then_shared_sides_share_vertices(void **state)
{
    (void)state;
    const double P[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}};
    sk_patch_set lin = {0}, used = {0};
    const uint32_t t0[3] = {0, 1, 2}, t1[3] = {1, 3, 2}, q0[4] = {2, 3, 5, 4};
    const uint32_t *tri[2] = {t0, t1};
    for (int t = 0; t < 2; ++t) {
        double cp[9];
        for (int k = 0; k < 3; ++k)
            memcpy(cp + 3 * (k == 0 ? sk_tri_index(1, 0, 0) : k == 1 ? sk_tri_index(1, 1, 0)
                                                              : sk_tri_index(1, 0, 1)),
                   P[tri[t][k]], sizeof P[0]);
        size_t k;
        assert_int_equal(sk_patch_set_add(&lin, SK_PATCH_TRIANGLE, 1, 0, cp, tri[t], &k, NULL), SK_OK);
        assert_int_equal(sk_patch_elevate(&lin, k, 4, 0, &used, NULL), SK_OK); /* quartic */
    }
    /* quad over (0,1) (1,1) (1,2) (0,2): corner 5 is (1,2) */
    const double Q[4][3] = {{0, 1, 0}, {1, 1, 0}, {0, 2, 0}, {1, 2, 0}}; /* (0,0) (1,0) (0,1) (1,1) */
    assert_int_equal(sk_patch_set_add(&used, SK_PATCH_TENSOR, 1, 1, &Q[0][0], q0, NULL, NULL), SK_OK);
    const unsigned n = 4;
    sk_soup *soup = NULL;
    assert_int_equal(sk_patch_set_tessellate(&used, n, &soup, NULL), SK_OK);
    /* 6 corner ids; sides 0-1 1-2 2-0 | 1-3 3-2 (2-1 shared) | 3-5 5-4 4-2 (2-3 shared): 8
     * distinct sides of n - 1 inner points each; interiors 3 + 3 + 9 */
    size_t sides = 8;
    assert_int_equal(soup->num_vertices, 6 + sides * (n - 1) + 3 + 3 + 9);
    assert_int_equal(soup->num_faces, n * n + n * n + 2 * n * n);
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_from_soup(soup, &m, NULL), SK_OK);
    sk_topology top;
    assert_int_equal(sk_mesh_topology(m, &top, NULL, NULL), SK_OK);
    assert_int_equal(top.components, 1);
    assert_int_equal(top.boundary_loops, 1);
    /* the shared points lie on both patches: the midpoint of side 1-2 is (0.5, 0.5, 0) */
    bool found = false;
    for (size_t v = 0; v < soup->num_vertices; ++v)
        found |= fabs(soup->positions[3 * v] - 0.5) < 1e-15 && fabs(soup->positions[3 * v + 1] - 0.5) < 1e-15;
    assert_true(found);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&soup);
    /* without corner ids: separate grids */
    for (size_t i = 0; i < used.count; ++i)
        for (int c = 0; c < 4; ++c)
            used.patches[i].corner_ids[c] = SK_INVALID;
    assert_int_equal(sk_patch_set_tessellate(&used, n, &soup, NULL), SK_OK);
    assert_int_equal(soup->num_vertices, 15 + 15 + 25);
    sk_soup_destroy(&soup);
    sk_patch_set_free(&used);
    sk_patch_set_free(&lin);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_triangle_then_eval_is_the_bernstein_sum),
        cmocka_unit_test(given_patches_then_derivatives_match_finite_differences),
        cmocka_unit_test(when_elevated_then_the_surface_is_unchanged),
        cmocka_unit_test(when_triangle_is_split_then_three_tensor_patches_reproduce_it),
        cmocka_unit_test(given_edges_then_edge_curves_run_corner_to_corner),
        cmocka_unit_test(given_a_set_when_patches_added_then_points_are_pooled),
        cmocka_unit_test(given_a_set_when_converted_to_tensor_then_triangles_split_in_three),
        cmocka_unit_test(given_neighbouring_patches_when_tessellated_then_shared_sides_share_vertices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
