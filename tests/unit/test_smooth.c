/* VC1 surfaces on the shared meshes: every interior vertex odd, normal jumps at rounding level,
 * exact interpolation, regular patches on the clean meshes; PN triangles show real jumps. */
#include "testutil.h"
#include "surfkit/smooth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void report(const char *name, const sk_smooth *s, const sk_continuity_report *r)
{
    print_message("%-20s %-3s tri %6zu quad %6zu del %5zu/%5zu jump max %.2e mean %.2e gap %.2e "
                  "verr %.1e nerr %.1e singular %zu uncert %zu angle-viol %zu failed %zu "
                  "fallback %zu it %zu dev %.3f sing-before %zu repaired %zu\n",
                  name, s->scheme == SK_SMOOTH_PN ? "pn" : "vc1", s->stats.deletion.triangles,
                  s->stats.deletion.quads, s->stats.deletion.deleted_edges,
                  s->stats.deletion.lower_bound, r->max_normal_jump_deg, r->mean_normal_jump_deg,
                  r->max_gap, r->max_vertex_error, r->max_normal_error_deg, r->singular_patches,
                  r->uncertified_patches, s->stats.angle_violations, s->stats.failed_vertices,
                  s->stats.fallback_solves, s->stats.max_iterations,
                  s->stats.mean_target_deviation, s->stats.singular_before_repair,
                  s->stats.repaired_vertices);
}

static sk_smooth *build(const char *name, sk_smooth_scheme scheme, sk_continuity_report *rep)
{
    sk_mesh *m = skt_read_mesh(skt_shared_mesh(name));
    sk_smooth_opts o = {0};
    o.scheme = scheme;
    sk_smooth *s = NULL;
    sk_error err = {0};
    if (sk_smooth_build(m, &o, &s, &err) != SK_OK)
        fail_msg("%s: %s", name, err.message);
    sk_continuity_opts co = {0};
    co.samples = 16;
    assert_int_equal(sk_smooth_continuity(s, &co, rep, &err), SK_OK);
    report(name, s, rep);
    sk_mesh_destroy(&m);
    return s;
}

static void check_vc1(const char *name, bool clean)
{
    sk_continuity_report r;
    sk_smooth *s = build(name, SK_SMOOTH_VC1, &r);
    double diag = sk_mesh_diagonal(s->config);
    /* the VC1 property holds to rounding wherever the angle bounds hold; a vertex that violates
     * them (rough scans) must be reported in problems */
    if (s->stats.angle_violations == 0)
        assert_true(r.max_normal_jump_deg < 1e-7);
    else
        assert_true(s->num_problems >= s->stats.angle_violations);
    assert_true(r.max_gap < 1e-12 * diag);
    assert_true(r.max_vertex_error < 1e-12 * diag);
    if (s->stats.angle_violations == 0)
        assert_true(r.max_normal_error_deg < 1e-7);
    assert_int_equal(s->stats.failed_vertices, 0);
    if (clean)
        assert_int_equal(s->stats.angle_violations, 0);
    if (clean)
        assert_int_equal(r.singular_patches, 0);
    /* the regularity repair never makes things worse */
    assert_true(r.singular_patches <= s->stats.singular_before_repair);
    /* every interior vertex odd (but those on a G0 crease: boundary-like, chains per sector,
     * no parity, docs/creases.md) */
    bool *on_crease = calloc(s->config->num_vertices + 1, sizeof *on_crease);
    assert_non_null(on_crease);
    for (uint32_t e = 0; s->crease_edge && e < s->config->num_halfedges / 2; ++e)
        if (s->crease_edge[e])
            on_crease[sk_from(s->config, 2 * e)] = on_crease[sk_to(s->config, 2 * e)] = true;
    for (uint32_t v = 0; v < s->config->num_vertices; ++v)
        if (!sk_is_boundary_v(s->config, v) && !on_crease[v])
            assert_true(sk_mesh_valence(s->config, v) & 1u);
    free(on_crease);
    sk_smooth_destroy(&s);
}

static void test_clean_closed(void **state)
{
    (void)state;
    check_vc1("icosahedron.off", true);
    check_vc1("sphere.off", true);
    if (!getenv("SK_TEST_QUICK"))
        check_vc1("bunny00.off", true);
}

static void test_rough_closed(void **state)
{
    (void)state;
    check_vc1("cube.off", false);
    check_vc1("cow.off", false);
    check_vc1("knot1.off", false);
    if (!getenv("SK_TEST_QUICK"))
        check_vc1("armadillo.off", false);
}

static void test_disks(void **state)
{
    (void)state;
    const char *disks[] = {"lion-head.off", "mushroom.off", "nefertiti.off", "paraboloid-patch.off",
                           "patch-01.off", "three_peaks.off"};
    for (size_t i = 0; i < sizeof disks / sizeof disks[0]; ++i)
        check_vc1(disks[i], false);
}

/* cow.off vertex 2751 and lion-head.off vertex 1343 once violated the angle bounds of section 4
 * (78 and 152 degree normal jumps next to them): at both the least-squares fit of (8) folded two
 * tangents onto one line because the target lengths were very unequal (lion-head: valence 3, one
 * target 4.4 times the others; cow: a long quad with r_m 16 times its neighbours', nu = -16.6 and
 * -0.06). Relaxing the target lengths towards their mean fixes both: VC1 to rounding, no problems. */
static void test_former_violations(void **state)
{
    (void)state;
    const char *names[] = {"cow.off", "lion-head.off"};
    for (size_t i = 0; i < 2; ++i) {
        sk_continuity_report r;
        sk_smooth *s = build(names[i], SK_SMOOTH_VC1, &r);
        assert_int_equal(s->stats.angle_violations, 0);
        assert_int_equal(s->stats.failed_vertices, 0);
        assert_int_equal(s->num_problems, 0);
        assert_true(r.max_normal_jump_deg < 1e-7);
        assert_true(r.max_normal_error_deg < 1e-7);
        sk_smooth_destroy(&s);
    }
}

/* side_param and side_of as the report defines them, for an independent check of its sampling */
static void side_param(int kind, int side, double t, double *u, double *v)
{
    static const double tri[3][4] = {{0, 1, 0, 0}, {1, -1, 0, 1}, {0, 0, 1, -1}};
    static const double quad[4][4] = {{0, 1, 0, 0}, {1, 0, 0, 1}, {1, -1, 1, 0}, {0, 0, 1, -1}};
    const double *c = kind == SK_PATCH_TRIANGLE ? tri[side] : quad[side];
    *u = c[0] + c[1] * t;
    *v = c[2] + c[3] * t;
}

static int side_of(const sk_mesh *m, uint32_t f, uint32_t h)
{
    int i = 0;
    for (uint32_t g = m->f_halfedge[f]; g != h; g = m->h_next[g])
        ++i;
    return i;
}

/* The report samples edges from the boundary rows of the control nets; the same samples through
 * the general evaluator sk_patch_eval give the same largest normal jump. */
static void test_report_sampling(void **state)
{
    (void)state;
    const char *names[] = {"sphere.off", "cow.off"};
    for (int i = 0; i < 2; ++i)
        for (int scheme = 0; scheme < 2; ++scheme) {
            sk_continuity_report r;
            sk_smooth *s = build(names[i], scheme ? SK_SMOOTH_PN : SK_SMOOTH_VC1, &r);
            const sk_mesh *m = s->config;
            double mx = 0.0, gap = 0.0, cmx = 0.0;
            for (uint32_t e = 0; e < m->num_halfedges / 2; ++e) {
                uint32_t h = 2 * e, o = h + 1, f = m->h_face[h], g = m->h_face[o];
                if (f == SK_INVALID || g == SK_INVALID)
                    continue;
                /* a G0 crease edge counts in the crease figures, not in the G1 one */
                bool crease = s->crease_edge && s->crease_edge[e];
                for (int k = 0; k <= 16; ++k) {
                    double t = k / 16.0, u, v, x1[3], x2[3], n1[3], n2[3];
                    side_param(s->surface.patches[f].kind, side_of(m, f, h), t, &u, &v);
                    sk_patch_eval(&s->surface, f, u, v, x1, NULL, NULL, n1);
                    side_param(s->surface.patches[g].kind, side_of(m, g, o), 1.0 - t, &u, &v);
                    sk_patch_eval(&s->surface, g, u, v, x2, NULL, NULL, n2);
                    double d = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
                    double cx = n1[1] * n2[2] - n1[2] * n2[1], cy = n1[2] * n2[0] - n1[0] * n2[2],
                           cz = n1[0] * n2[1] - n1[1] * n2[0];
                    double jump = atan2(sqrt(cx * cx + cy * cy + cz * cz), d) * 180.0 / M_PI;
                    /* skip the corners of angle-violation vertices, where the normal is not
                     * defined (degenerate tangents) and rounding decides its direction */
                    if (s->stats.angle_violations && (k == 0 || k == 16))
                        continue;
                    if (crease)
                        cmx = fmax(cmx, jump);
                    else
                        mx = fmax(mx, jump);
                    gap = fmax(gap, sqrt((x1[0] - x2[0]) * (x1[0] - x2[0]) +
                                         (x1[1] - x2[1]) * (x1[1] - x2[1]) +
                                         (x1[2] - x2[2]) * (x1[2] - x2[2])));
                }
            }
            if (s->stats.angle_violations == 0 || scheme)
                assert_true(fabs(mx - r.max_normal_jump_deg) <= 1e-6 * fmax(1.0, mx) + 1e-9);
            else
                assert_true(mx <= r.max_normal_jump_deg + 1e-6);
            assert_true(gap <= r.max_gap + 1e-12);
            assert_true(cmx <= r.max_crease_jump_deg + 1e-6);
            sk_smooth_destroy(&s);
        }
}

static void test_pn_baseline(void **state)
{
    (void)state;
    const char *names[] = {"sphere.off", "cow.off"};
    for (int i = 0; i < 2; ++i) {
        sk_continuity_report r;
        sk_smooth *s = build(names[i], SK_SMOOTH_PN, &r);
        assert_true(r.max_normal_jump_deg > (i == 0 ? 0.3 : 1.0)); /* degrees, not rounding */
        assert_true(r.max_vertex_error < 1e-12 * sk_mesh_diagonal(s->config));
        sk_smooth_destroy(&s);
    }
}

/* The tessellation of a closed surface is closed: every patch side is tessellated once and its
 * vertices are shared by both neighbours, so the soup builds a manifold mesh with one component,
 * no boundary and the genus of the input; a disk keeps exactly its boundary loop. Positions of a
 * shared side come from one patch, so they lie on the other one to rounding (the report's gap). */
static void test_watertight_tessellation(void **state)
{
    (void)state;
    const struct {
        const char *name;
        sk_smooth_scheme scheme;
        long genus;
        size_t loops;
    } cases[] = {{"sphere.off", SK_SMOOTH_VC1, 0, 0}, {"cow.off", SK_SMOOTH_VC1, 0, 0},
                 {"sphere.off", SK_SMOOTH_PN, 0, 0}, {"nefertiti.off", SK_SMOOTH_VC1, 0, 1}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        sk_continuity_report r;
        sk_smooth *s = build(cases[i].name, cases[i].scheme, &r);
        const unsigned n = 4;
        sk_soup *soup = NULL;
        sk_mesh *t = NULL;
        sk_error err = {0};
        assert_int_equal(sk_patch_set_tessellate(&s->surface, n, &soup, &err), SK_OK);
        if (sk_mesh_from_soup(soup, &t, &err) != SK_OK)
            fail_msg("%s: tessellation is not a manifold: %s", cases[i].name, err.message);
        sk_topology top;
        assert_int_equal(sk_mesh_topology(t, &top, NULL, &err), SK_OK);
        assert_int_equal(top.components, 1);
        assert_int_equal(top.boundary_loops, cases[i].loops);
        assert_int_equal(top.genus, cases[i].genus);
        /* vertices: one per config vertex, n - 1 per config edge, the patch interiors */
        const sk_mesh *c = s->config;
        size_t inner = 0, tri = 0;
        for (size_t p = 0; p < s->surface.count; ++p) {
            bool quad = s->surface.patches[p].kind == SK_PATCH_TENSOR;
            inner += quad ? (n - 1) * (n - 1) : (n - 1) * (n - 2) / 2;
            tri += quad ? 2 * n * n : n * n;
        }
        assert_int_equal(soup->num_vertices, c->num_vertices + (n - 1) * sk_num_edges(c) + inner);
        assert_int_equal(soup->num_faces, tri);
        sk_mesh_destroy(&t);
        sk_soup_destroy(&soup);
        sk_smooth_destroy(&s);
    }
}

/* Two spheres that overlap: their smooth surfaces cross, along a circle; one sphere alone and
 * the two apart do not. The check sees patch pairs of different components (no shared corner). */
static size_t crossing_pairs(double shift)
{
    sk_soup *a = skt_read_soup(skt_shared_mesh("sphere.off")), *two = NULL;
    size_t nv = a->num_vertices;
    assert_int_equal(sk_soup_create(2 * nv, 2 * a->num_faces, 6 * a->num_faces, false, false, &two,
                                    NULL), SK_OK);
    for (int c = 0; c < 2; ++c)
        for (size_t v = 0; v < nv; ++v) {
            double p[3] = {a->positions[3 * v] + c * shift, a->positions[3 * v + 1],
                           a->positions[3 * v + 2]};
            assert_int_equal(sk_soup_push_vertex(two, p, NULL, NULL), SK_OK);
        }
    for (int c = 0; c < 2; ++c)
        for (size_t f = 0; f < a->num_faces; ++f) {
            uint32_t t[3];
            for (int k = 0; k < 3; ++k)
                t[k] = a->face_indices[a->face_offsets[f] + (size_t)k] + (uint32_t)(c * nv);
            assert_int_equal(sk_soup_push_face(two, t, 3), SK_OK);
        }
    sk_mesh *m = NULL;
    sk_smooth *s = NULL;
    sk_continuity_report r;
    assert_int_equal(sk_mesh_from_soup(two, &m, NULL), SK_OK);
    assert_int_equal(sk_smooth_build(m, NULL, &s, NULL), SK_OK);
    assert_int_equal(sk_smooth_continuity(s, NULL, &r, NULL), SK_OK);
    assert_true(r.pass_intersections == (r.intersecting_pairs == 0));
    for (size_t i = 0; i < r.num_intersection_examples; ++i) /* one patch of each sphere */
        assert_true((r.intersection_examples[2 * i] < s->surface.count / 2) !=
                    (r.intersection_examples[2 * i + 1] < s->surface.count / 2));
    size_t n = r.intersecting_pairs;
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&two);
    sk_soup_destroy(&a);
    return n;
}

static void test_self_intersections(void **state)
{
    (void)state;
    double d = 0;
    sk_soup *a = skt_read_soup(skt_shared_mesh("sphere.off"));
    for (size_t v = 0; v < a->num_vertices; ++v) /* the radius */
        d = fmax(d, fabs(a->positions[3 * v]));
    sk_soup_destroy(&a);
    assert_int_equal(crossing_pairs(3 * d), 0);   /* apart */
    assert_true(crossing_pairs(d) > 10);          /* overlapping by half */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clean_closed),
        cmocka_unit_test(test_rough_closed),
        cmocka_unit_test(test_disks),
        cmocka_unit_test(test_former_violations),
        cmocka_unit_test(test_pn_baseline),
        cmocka_unit_test(test_report_sampling),
        cmocka_unit_test(test_watertight_tessellation),
        cmocka_unit_test(test_self_intersections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
