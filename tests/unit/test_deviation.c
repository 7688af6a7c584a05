/* Closest points and two-sided deviation: the BVH against brute force with an independent
 * point-triangle distance, hand-made cases with known distances (parallel planes, a mesh against
 * itself, an inscribed icosahedron against a fine sphere), and bad input. */
#include "testutil.h"
#include "surfkit/deviation.h"
#include "analysis/bvh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Distance from p to the triangle (a, b, c) computed another way than the library: the projection
 * to the plane when it lies inside (by the signs of the sub-areas), else the nearest of the three
 * segments. */
static double seg_dist(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], L = 0, t = 0;
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ap[k] = p[k] - a[k];
        L += ab[k] * ab[k];
        t += ab[k] * ap[k];
    }
    t = L > 0 ? fmax(0, fmin(1, t / L)) : 0;
    double d = 0;
    for (int k = 0; k < 3; ++k) {
        double e = a[k] + t * ab[k] - p[k];
        d += e * e;
    }
    return sqrt(d);
}

static double tri_dist(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double u[3], v[3], n[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double best = fmin(seg_dist(p, a, b), fmin(seg_dist(p, b, c), seg_dist(p, c, a)));
    if (nn == 0)
        return best;
    for (int k = 0; k < 3; ++k)
        n[k] /= nn;
    double h = (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2];
    double q[3] = {p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]};
    const double *P[3] = {a, b, c};
    int inside = 1;
    for (int e = 0; e < 3; ++e) {
        const double *s = P[e], *t = P[(e + 1) % 3];
        double w[3] = {t[0] - s[0], t[1] - s[1], t[2] - s[2]};
        double r[3] = {q[0] - s[0], q[1] - s[1], q[2] - s[2]};
        double cr = (w[1] * r[2] - w[2] * r[1]) * n[0] + (w[2] * r[0] - w[0] * r[2]) * n[1] +
                    (w[0] * r[1] - w[1] * r[0]) * n[2];
        if (cr < 0)
            inside = 0;
    }
    return inside ? fabs(h) : best;
}

static void bvh_matches_brute_force(void **state)
{
    (void)state;
    sk_soup *s = skt_read_soup(skt_shared_mesh("lion-head.off"));
    sk_bvh *bvh = NULL;
    sk_error err;
    assert_int_equal(sk_bvh_build(s, &bvh, &err), SK_OK);
    assert_int_equal(sk_bvh_triangles(bvh), s->num_faces);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < s->num_vertices; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], s->positions[3 * v + k]);
            hi[k] = fmax(hi[k], s->positions[3 * v + k]);
        }
    srand(7);
    for (int q = 0; q < 300; ++q) {
        double p[3];
        for (int k = 0; k < 3; ++k) { /* the box grown by half its size on each side */
            double ext = hi[k] - lo[k];
            p[k] = lo[k] - 0.5 * ext + 2.0 * ext * rand() / (double)RAND_MAX;
        }
        sk_closest cl;
        sk_bvh_closest(bvh, p, &cl);
        double best = INFINITY;
        for (size_t f = 0; f < s->num_faces; ++f) {
            const uint32_t *t = s->face_indices + s->face_offsets[f];
            best = fmin(best, tri_dist(p, s->positions + 3 * t[0], s->positions + 3 * t[1],
                                       s->positions + 3 * t[2]));
        }
        assert_true(fabs(cl.distance - best) <= 1e-12 * (1 + best));
        /* the point is on the face it names, at the distance it says */
        const uint32_t *t = s->face_indices + s->face_offsets[cl.face];
        double on = tri_dist(cl.point, s->positions + 3 * t[0], s->positions + 3 * t[1],
                             s->positions + 3 * t[2]);
        assert_true(on <= 1e-12 * (1 + best));
        double d = 0;
        for (int k = 0; k < 3; ++k)
            d += (cl.point[k] - p[k]) * (cl.point[k] - p[k]);
        assert_true(fabs(sqrt(d) - cl.distance) <= 1e-12 * (1 + best));
    }
    sk_bvh_destroy(&bvh);
    assert_null(bvh);
    sk_soup_destroy(&s);
}

/* The capped walk (the tolerance route's check): exact beyond the cap, within it a distance to a
 * real triangle between the exact distance and the cap; the hint carried from point to point
 * and the face it names agree with the distance. */
static void capped_distance(void **state)
{
    (void)state;
    sk_soup *s = skt_read_soup(skt_shared_mesh("lion-head.off"));
    sk_bvh *bvh = NULL;
    assert_int_equal(sk_bvh_build(s, &bvh, NULL), SK_OK);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < s->num_vertices; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], s->positions[3 * v + k]);
            hi[k] = fmax(hi[k], s->positions[3 * v + k]);
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double caps[] = {0, 1e-3, 1e-2, 5e-2, 10};
    uint32_t hint = SK_INVALID;
    size_t bounded = 0, exact = 0;
    srand(11);
    for (int q = 0; q < 400; ++q) {
        double p[3];
        for (int k = 0; k < 3; ++k) { /* near the surface: a vertex moved by up to 2% */
            size_t v = (size_t)rand() % s->num_vertices;
            p[k] = s->positions[3 * v + k] + 0.02 * diag * (rand() / (double)RAND_MAX - 0.5);
            if (k == 0)
                memcpy(p, s->positions + 3 * v, sizeof p);
        }
        double best = INFINITY;
        for (size_t f = 0; f < s->num_faces; ++f) {
            const uint32_t *t = s->face_indices + s->face_offsets[f];
            best = fmin(best, tri_dist(p, s->positions + 3 * t[0], s->positions + 3 * t[1],
                                       s->positions + 3 * t[2]));
        }
        double cap = caps[q % 5] * diag;
        uint32_t face = SK_INVALID;
        double d = sk__bvh_distance_capped(bvh, p, cap, &hint, &face);
        assert_true(face < s->num_faces && hint < sk_bvh_triangles(bvh));
        const uint32_t *t = s->face_indices + s->face_offsets[face];
        double on = tri_dist(p, s->positions + 3 * t[0], s->positions + 3 * t[1],
                             s->positions + 3 * t[2]);
        assert_true(fabs(on - d) <= 1e-12 * (1 + d));
        if (best > cap) {
            assert_true(fabs(d - best) <= 1e-12 * (1 + best));
            ++exact;
        } else {
            assert_true(d >= best - 1e-12 * (1 + best) && d <= cap * (1 + 1e-12));
            bounded += d > best + 1e-12 * (1 + best);
        }
    }
    /* both branches are exercised, and the walk did stop early somewhere */
    assert_true(exact > 100 && bounded > 0);
    sk_bvh_destroy(&bvh);
    sk_soup_destroy(&s);
}

/* An n x n grid of quads on [0,1]^2 at height z (quads: the fan split is exercised). */
static sk_soup *grid(int n, double z)
{
    sk_soup *s = NULL;
    assert_int_equal(sk_soup_create(0, 0, 0, false, false, &s, NULL), SK_OK);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double p[3] = {(double)i / n, (double)j / n, z};
            assert_int_equal(sk_soup_push_vertex(s, p, NULL, NULL), SK_OK);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = (uint32_t)(j * (n + 1) + i);
            uint32_t q[4] = {a, a + 1, a + (uint32_t)n + 2, a + (uint32_t)n + 1};
            assert_int_equal(sk_soup_push_face(s, q, 4), SK_OK);
        }
    return s;
}

static void parallel_planes(void **state)
{
    (void)state;
    sk_soup *a = grid(7, 0.0), *b = grid(4, 0.25);
    sk_deviation_report r;
    double *vd = malloc(a->num_vertices * sizeof *vd);
    sk_error err;
    assert_int_equal(sk_deviation(b, a, NULL, &r, vd, &err), SK_OK);
    /* every sample of either plane is exactly 0.25 from the other (same square) */
    assert_true(fabs(r.hausdorff - 0.25) < 1e-15);
    assert_true(fabs(r.mesh_to_surface.mean - 0.25) < 1e-15);
    assert_true(fabs(r.mesh_to_surface.rms - 0.25) < 1e-15);
    assert_true(fabs(r.surface_to_mesh.max - 0.25) < 1e-15);
    /* vertices + 2 triangles per quad x 4 samples */
    assert_int_equal(r.mesh_to_surface.samples, 64 + 49 * 2 * 4);
    assert_int_equal(r.surface_to_mesh.samples, 25 + 16 * 2 * 4);
    for (size_t v = 0; v < a->num_vertices; ++v)
        assert_true(fabs(vd[v] - 0.25) < 1e-15);
    /* all distances equal the maximum: the last histogram bin holds them all */
    assert_int_equal(r.mesh_to_surface.histogram[SK_DEVIATION_BINS - 1], r.mesh_to_surface.samples);
    assert_true(fabs(r.diagonal - sqrt(2.0)) < 1e-15);
    free(vd);
    sk_soup_destroy(&a);
    sk_soup_destroy(&b);
}

static void mesh_against_itself(void **state)
{
    (void)state;
    sk_soup *s = skt_read_soup(skt_shared_mesh("cow.off"));
    sk_deviation_report r;
    sk_deviation_opts o = {.face_samples = 3};
    assert_int_equal(sk_deviation(s, s, &o, &r, NULL, NULL), SK_OK);
    assert_true(r.hausdorff < 1e-12 * r.diagonal);
    assert_int_equal(r.mesh_to_surface.samples, s->num_vertices + 9 * s->num_faces);
    sk_soup_destroy(&s);
}

/* The icosahedron inscribed in the unit sphere against a fine triangulation of the sphere: the
 * farthest sphere points from the icosahedron are above its face centres, at 1 - r_in from it
 * (r_in the distance of a face plane from the centre); the icosahedron's own farthest points
 * from the sphere are its face centres, at about the same distance. */
static void icosahedron_in_sphere(void **state)
{
    (void)state;
    sk_mesh *ico = skt_read_mesh(skt_shared_mesh("icosahedron.off"));
    sk_mesh *fine = NULL;
    sk_subdiv_opts so = {.scheme = SK_SUBDIV_MIDPOINT, .iterations = 5};
    assert_int_equal(sk_mesh_subdivide(ico, &so, &fine, NULL), SK_OK);
    for (size_t v = 0; v < fine->num_vertices; ++v) {
        double *p = fine->positions + 3 * v;
        double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int k = 0; k < 3; ++k)
            p[k] /= l;
    }
    sk_soup *a = NULL, *b = NULL;
    assert_int_equal(sk_mesh_to_soup(ico, &a, NULL), SK_OK);
    assert_int_equal(sk_mesh_to_soup(fine, &b, NULL), SK_OK);
    /* distance of the face planes from the centre, from the first face */
    double r_in = INFINITY;
    for (size_t f = 0; f < a->num_faces; ++f) {
        const uint32_t *t = a->face_indices + a->face_offsets[f];
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int q = 0; q < 3; ++q)
                c[q] += a->positions[3 * t[k] + q] / 3.0;
        r_in = fmin(r_in, sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]));
    }
    sk_deviation_report r;
    sk_deviation_opts o = {.face_samples = 4};
    assert_int_equal(sk_deviation(b, a, &o, &r, NULL, NULL), SK_OK);
    double expect = 1 - r_in; /* 0.2052... for vertices on the unit sphere */
    assert_true(expect > 0.2 && expect < 0.21);
    /* the fine sphere lies inside the unit sphere and outside the icosahedron; its samples
     * include points at most ~1e-3 from the face-centre directions */
    assert_true(r.surface_to_mesh.max <= expect + 1e-12);
    assert_true(r.surface_to_mesh.max >= expect - 2e-3);
    assert_true(r.hausdorff >= expect - 2e-3 && r.hausdorff <= expect + 1e-12);
    /* the icosahedron's vertices lie on the fine sphere (exactly at its vertices) */
    assert_true(r.mesh_to_surface.max <= expect + 1e-12);
    sk_soup_destroy(&a);
    sk_soup_destroy(&b);
    sk_mesh_destroy(&ico);
    sk_mesh_destroy(&fine);
}

static void bad_input(void **state)
{
    (void)state;
    sk_soup *a = grid(2, 0.0), *b = grid(2, 1.0);
    sk_deviation_report r;
    sk_error err;
    b->face_indices[3] = 99;
    assert_int_equal(sk_deviation(a, b, NULL, &r, NULL, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "mesh: face 0 has index 99"));
    b->face_indices[3] = 0;
    a->positions[4] = NAN;
    assert_int_equal(sk_deviation(a, b, NULL, &r, NULL, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "surface: vertex 1 has a non-finite coordinate"));
    a->positions[4] = 0;
    sk_deviation_opts o = {.face_samples = -1};
    assert_int_equal(sk_deviation(a, b, &o, &r, NULL, &err), SK_ERR_ARG);
    sk_soup *e = NULL;
    assert_int_equal(sk_soup_create(0, 0, 0, false, false, &e, NULL), SK_OK);
    assert_int_equal(sk_deviation(e, b, NULL, &r, NULL, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "surface: no faces"));
    sk_soup_destroy(&e);
    sk_soup_destroy(&a);
    sk_soup_destroy(&b);
}

/* Given two grids, when sk_deviation is asked for its hierarchies, then it hands over one per side
 * (surface: 2 x 16 fan triangles, mesh: 2 x 49) that measure the same distances as a fresh
 * build; after a failure both are NULL. */
static void hands_over_bvhs(void **state)
{
    (void)state;
    sk_soup *a = grid(7, 0.0), *b = grid(4, 0.25);
    sk_bvh *bs = (sk_bvh *)&bs, *bm = (sk_bvh *)&bm; /* not NULL: must be overwritten */
    sk_deviation_opts o = {.surface_bvh = &bs, .mesh_bvh = &bm};
    sk_deviation_report r;
    assert_int_equal(sk_deviation(b, a, &o, &r, NULL, NULL), SK_OK);
    assert_non_null(bs);
    assert_non_null(bm);
    assert_int_equal(sk_bvh_triangles(bs), 32);
    assert_int_equal(sk_bvh_triangles(bm), 98);
    double p[3] = {0.3, 0.6, 1.0};
    assert_true(fabs(sk_bvh_distance(bs, p) - 0.75) < 1e-15);
    assert_true(fabs(sk_bvh_distance(bm, p) - 1.0) < 1e-15);
    sk_bvh_destroy(&bs);
    sk_bvh_destroy(&bm);
    a->face_indices[3] = 999;
    bs = bm = (sk_bvh *)&o;
    assert_int_equal(sk_deviation(b, a, &o, &r, NULL, NULL), SK_ERR_TOPOLOGY);
    assert_null(bs);
    assert_null(bm);
    sk_soup_destroy(&a);
    sk_soup_destroy(&b);
}

static int cancel_at_half(void *user, double fraction)
{
    (void)user;
    return fraction > 0.5;
}

static void cancelled(void **state)
{
    (void)state;
    sk_soup *s = skt_read_soup(skt_shared_mesh("bunny00.off"));
    sk_deviation_opts o = {.progress = cancel_at_half};
    sk_deviation_report r;
    assert_int_equal(sk_deviation(s, s, &o, &r, NULL, NULL), SK_ERR_CANCELLED);
    sk_soup_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bvh_matches_brute_force), cmocka_unit_test(parallel_planes),
        cmocka_unit_test(mesh_against_itself),     cmocka_unit_test(icosahedron_in_sphere),
        cmocka_unit_test(bad_input),               cmocka_unit_test(cancelled),
        cmocka_unit_test(hands_over_bvhs),         cmocka_unit_test(capped_distance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
