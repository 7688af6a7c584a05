/* sk_soup_triangulate: quads by the shorter diagonal, ear clipping of larger polygons (also
 * non-convex, in a tilted plane), corner uvs kept, faces that are not polygons copied as they
 * are, and a closed quad cube that becomes a closed triangle mesh. */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static sk_soup *soup_of(const double *pos, size_t nv, const uint32_t *idx, const size_t *sizes,
                        size_t nf)
{
    sk_soup *s = NULL;
    assert_int_equal(sk_soup_create(nv, nf, 0, false, false, &s, NULL), SK_OK);
    for (size_t v = 0; v < nv; ++v)
        assert_int_equal(sk_soup_push_vertex(s, pos + 3 * v, NULL, NULL), SK_OK);
    for (size_t f = 0, o = 0; f < nf; o += sizes[f++])
        assert_int_equal(sk_soup_push_face(s, idx + o, sizes[f]), SK_OK);
    return s;
}

/* normal (not unit) of triangle f of a triangle soup */
static void tri_normal(const sk_soup *s, size_t f, double n[3])
{
    const uint32_t *t = s->face_indices + s->face_offsets[f];
    const double *a = s->positions + 3 * t[0], *b = s->positions + 3 * t[1],
                 *c = s->positions + 3 * t[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1],
                                                                    c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
}

static void given_a_rhombus_then_the_shorter_diagonal_splits_it(void **state)
{
    (void)state;
    /* diagonal 0-2 is 4 long, 1-3 is 2 long */
    const double pos[] = {-2, 0, 0, 0, -1, 0, 2, 0, 0, 0, 1, 0};
    const uint32_t idx[] = {0, 1, 2, 3};
    const size_t sizes[] = {4};
    sk_soup *s = soup_of(pos, 4, idx, sizes, 1), *t = NULL;
    sk_triangulate_stats st;
    assert_int_equal(sk_soup_triangulate(s, &t, &st, NULL), SK_OK);
    assert_int_equal(st.quads, 1);
    assert_int_equal(st.polygons, 0);
    assert_int_equal(st.triangles, 2);
    assert_int_equal(t->num_faces, 2);
    assert_int_equal(t->num_vertices, 4);
    const uint32_t want[] = {1, 2, 3, 1, 3, 0};
    assert_memory_equal(t->face_indices, want, sizeof want);
    for (size_t f = 0; f < 2; ++f) {
        double n[3];
        tri_normal(t, f, n);
        assert_true(n[2] > 0); /* the quad's orientation (counter-clockwise seen from +z) */
    }
    sk_soup_destroy(&t);
    sk_soup_destroy(&s);
}

static void given_a_nonconvex_hexagon_in_a_tilted_plane_then_ears_cover_it(void **state)
{
    (void)state;
    /* an L shape (area 3) in the plane z = x + y, counter-clockwise seen from above */
    const double xy[][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    double pos[18];
    for (int i = 0; i < 6; ++i) {
        pos[3 * i] = xy[i][0];
        pos[3 * i + 1] = xy[i][1];
        pos[3 * i + 2] = xy[i][0] + xy[i][1];
    }
    const uint32_t idx[] = {0, 1, 2, 3, 4, 5};
    const size_t sizes[] = {6};
    sk_soup *s = soup_of(pos, 6, idx, sizes, 1), *t = NULL;
    sk_triangulate_stats st;
    assert_int_equal(sk_soup_triangulate(s, &t, &st, NULL), SK_OK);
    assert_int_equal(st.polygons, 1);
    assert_int_equal(t->num_faces, 4);
    double area = 0;
    int boundary_uses[6] = {0};
    for (size_t f = 0; f < 4; ++f) {
        double n[3];
        tri_normal(t, f, n);
        /* the plane's upward normal (-1, -1, 1): every triangle keeps the orientation */
        double up = (-n[0] - n[1] + n[2]) / sqrt(3.0);
        assert_true(up > 1e-12);
        area += up / 2;
        const uint32_t *v = t->face_indices + t->face_offsets[f];
        for (int k = 0; k < 3; ++k)
            if ((v[k] + 1) % 6 == v[(k + 1) % 3])
                boundary_uses[v[k]]++;
    }
    /* the projected area 3 scaled by |(-1,-1,1)| = sqrt(3) */
    assert_true(fabs(area - 3 * sqrt(3.0)) < 1e-12);
    for (int i = 0; i < 6; ++i)
        assert_int_equal(boundary_uses[i], 1); /* each polygon edge in exactly one triangle */
    /* the reflex corner 3 is not clipped as an ear: no triangle (2, 3, 4) */
    for (size_t f = 0; f < 4; ++f) {
        const uint32_t *v = t->face_indices + t->face_offsets[f];
        assert_false(v[0] == 2 && v[1] == 3 && v[2] == 4);
    }
    sk_soup_destroy(&t);
    sk_soup_destroy(&s);
}

static void given_corner_uvs_then_every_corner_keeps_its_uv(void **state)
{
    (void)state;
    const double pos[] = {0, 0, 0, 1, 0, 0, 1, 3, 0, 0, 3, 0, 2, 0, 0};
    const uint32_t idx[] = {0, 1, 2, 3, 1, 4, 2};
    const size_t sizes[] = {4, 3};
    sk_soup *s = soup_of(pos, 5, idx, sizes, 2), *t = NULL;
    const double uv[] = {0, 0, 0.5, 0, 0.5, 1, 0, 1, 0.9, 0.1, 1, 0, 0.8, 0.8};
    const uint32_t corner[] = {0, 1, 2, 3, 4, 5, 6}; /* vertex 1 has two uvs: 1 and 4 */
    assert_int_equal(sk_soup_set_corner_uvs(s, 7, uv, corner), SK_OK);
    assert_int_equal(sk_soup_triangulate(s, &t, NULL, NULL), SK_OK);
    assert_int_equal(t->num_faces, 3);
    assert_non_null(t->corner_uv);
    assert_int_equal(t->num_wedge_uvs, 7);
    for (size_t f = 0; f < 3; ++f) {
        for (uint32_t c = t->face_offsets[f]; c < t->face_offsets[f + 1]; ++c) {
            uint32_t v = t->face_indices[c], w = t->corner_uv[c];
            if (f < 2) /* from the quad: its corner of v */
                assert_int_equal(w, v);
            else /* the triangle is copied: corners 4, 5, 6 */
                assert_int_equal(w, 4 + (c - t->face_offsets[f]));
        }
    }
    sk_soup_destroy(&t);
    sk_soup_destroy(&s);
}

static void given_defective_faces_then_they_are_copied_for_validation(void **state)
{
    (void)state;
    const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t idx[] = {0, 1, 0, 1, 2, 3, 9, 0, 1, 2};
    const size_t sizes[] = {2, 5, 3};
    sk_soup *s = soup_of(pos, 4, idx, sizes, 3), *t = NULL;
    sk_triangulate_stats st;
    assert_int_equal(sk_soup_triangulate(s, &t, &st, NULL), SK_OK);
    assert_int_equal(st.quads + st.polygons, 0);
    assert_int_equal(t->num_faces, 3);
    assert_int_equal(t->face_offsets[3], 10);
    assert_memory_equal(t->face_indices, idx, sizeof idx);
    sk_validation rep;
    assert_int_equal(sk_soup_validate(t, &rep, NULL), SK_OK);
    assert_int_equal(rep.out_of_range.count, 1);
    assert_int_equal(rep.small_faces.count, 1);
    sk_soup_destroy(&t);
    sk_soup_destroy(&s);
}

static void given_the_quad_cube_then_a_closed_triangle_mesh(void **state)
{
    (void)state;
    const double pos[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                          -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    const uint32_t idx[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                            1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    const size_t sizes[] = {4, 4, 4, 4, 4, 4};
    sk_soup *s = soup_of(pos, 8, idx, sizes, 6), *t = NULL;
    sk_triangulate_stats st;
    assert_int_equal(sk_soup_triangulate(s, &t, &st, NULL), SK_OK);
    assert_int_equal(st.quads, 6);
    assert_int_equal(st.triangles, 12);
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_from_soup(t, &m, NULL), SK_OK);
    sk_topology top;
    assert_int_equal(sk_mesh_topology(m, &top, NULL, NULL), SK_OK);
    assert_int_equal(top.faces, 12);
    assert_int_equal(top.edges, 18);
    assert_int_equal(top.boundary_loops, 0);
    assert_int_equal(top.euler_characteristic, 2);
    /* outward: every triangle's normal points away from the centre */
    for (size_t f = 0; f < t->num_faces; ++f) {
        double n[3];
        tri_normal(t, f, n);
        const double *a = t->positions + 3 * t->face_indices[t->face_offsets[f]];
        assert_true(n[0] * a[0] + n[1] * a[1] + n[2] * a[2] > 0);
    }
    sk_mesh_destroy(&m);
    sk_soup_destroy(&t);
    sk_soup_destroy(&s);
}

/* an allocator that fails its k-th call and counts the blocks alive */
typedef struct failing {
    long count, fail_at, live;
} failing;

static void *f_malloc(void *user, size_t n)
{
    failing *c = user;
    if (++c->count == c->fail_at)
        return NULL;
    void *p = malloc(n);
    c->live += p != NULL;
    return p;
}

static void *f_realloc(void *user, void *p, size_t n)
{
    failing *c = user;
    if (++c->count == c->fail_at)
        return NULL;
    void *q = realloc(p, n);
    c->live += q && !p;
    return q;
}

static void f_free(void *user, void *p)
{
    failing *c = user;
    c->live -= p != NULL;
    free(p);
}

static void given_kth_allocation_fails_then_out_of_memory_and_nothing_leaks(void **state)
{
    (void)state;
    /* the prism (quads and hexagons) with corner uvs and per-vertex normals */
    double pos[36], nrm[36];
    for (int i = 0; i < 12; ++i) {
        double a = (i % 6) * 3.14159265358979 / 3;
        pos[3 * i] = nrm[3 * i] = cos(a);
        pos[3 * i + 1] = nrm[3 * i + 1] = sin(a);
        pos[3 * i + 2] = i / 6;
        nrm[3 * i + 2] = 0;
    }
    const uint32_t idx[] = {5, 4, 3, 2, 1, 0, 6, 7, 8, 9, 10, 11, 0, 1, 7, 6, 1, 2, 8, 7,
                            2, 3, 9, 8, 3, 4, 10, 9, 4, 5, 11, 10, 5, 0, 6, 11};
    failing cnt = {0, 0, 0};
    const sk_allocator alloc = {f_malloc, f_realloc, f_free, &cnt};
    long total = 0;
    for (long k = 0;; ++k) {
        cnt.count = cnt.live = 0;
        cnt.fail_at = k;
        sk_set_allocator(&alloc);
        sk_soup *s = NULL, *t = NULL;
        sk_status st = sk_soup_create(12, 8, 0, true, false, &s, NULL);
        for (int v = 0; st == SK_OK && v < 12; ++v)
            st = sk_soup_push_vertex(s, pos + 3 * v, nrm + 3 * v, NULL);
        for (int f = 0, o = 0; st == SK_OK && f < 8; o += f < 2 ? 6 : 4, ++f)
            st = sk_soup_push_face(s, idx + o, f < 2 ? 6 : 4);
        double uv[72];
        uint32_t corner[36];
        for (int c = 0; c < 36; ++c)
            uv[2 * c] = c, uv[2 * c + 1] = -c, corner[c] = (uint32_t)(35 - c);
        if (st == SK_OK)
            st = sk_soup_set_corner_uvs(s, 36, uv, corner);
        long before = cnt.count;
        bool built = st == SK_OK;
        sk_triangulate_stats ts;
        if (built)
            st = sk_soup_triangulate(s, &t, &ts, NULL);
        if (built && st == SK_OK) {
            assert_int_equal(t->num_faces, 20);
            assert_int_equal(ts.triangles, 20);
            for (uint32_t c = 0; c < t->face_offsets[20]; ++c) /* corner uvs followed */
                assert_true(t->wedge_uvs[2 * t->corner_uv[c]] >= 0);
        } else {
            assert_int_equal(st, SK_ERR_NOMEM);
            assert_null(t);
        }
        sk_soup_destroy(&t);
        sk_soup_destroy(&s);
        sk_set_allocator(NULL);
        assert_int_equal(cnt.live, 0);
        if (k == 0)
            total = cnt.count; /* no failure: every allocation of the run */
        if (k > 0 && k >= total)
            break;
        if (k == 0)
            assert_true(total > before); /* the triangulation allocates */
    }
    assert_true(total > 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_a_rhombus_then_the_shorter_diagonal_splits_it),
        cmocka_unit_test(given_a_nonconvex_hexagon_in_a_tilted_plane_then_ears_cover_it),
        cmocka_unit_test(given_corner_uvs_then_every_corner_keeps_its_uv),
        cmocka_unit_test(given_defective_faces_then_they_are_copied_for_validation),
        cmocka_unit_test(given_the_quad_cube_then_a_closed_triangle_mesh),
        cmocka_unit_test(given_kth_allocation_fails_then_out_of_memory_and_nothing_leaks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
