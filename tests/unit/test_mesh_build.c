/* Half-edge mesh construction, invariants, one-ring order, compaction, soup round trip. */
#include "testutil.h"

#include <math.h>
#include <string.h>

/* octahedron: closed, 6 vertices, 8 faces */
static const double octa_pos[] = {0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 0, 0, -1};
static const uint32_t octa_idx[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1,
                                    5, 2, 1, 5, 3, 2, 5, 4, 3, 5, 1, 4};
static const uint32_t tri_off[] = {0, 3, 6, 9, 12, 15, 18, 21, 24};

static sk_mesh *octahedron(size_t nfaces)
{
    sk_mesh *m = NULL;
    sk_error err;
    assert_int_equal(sk_mesh_from_faces(6, octa_pos, nfaces, tri_off, octa_idx, &m, &err), SK_OK);
    assert_int_equal(sk_mesh_check(m, &err), SK_OK);
    return m;
}

static void given_closed_octahedron_then_topology_is_sphere(void **state)
{
    (void)state;
    sk_mesh *m = octahedron(8);
    sk_topology t;
    assert_int_equal(sk_mesh_topology(m, &t, NULL, NULL), SK_OK);
    assert_int_equal(t.vertices, 6);
    assert_int_equal(t.edges, 12);
    assert_int_equal(t.faces, 8);
    assert_int_equal(t.boundary_loops, 0);
    assert_int_equal(t.components, 1);
    assert_int_equal(t.euler_characteristic, 2);
    assert_int_equal(t.genus, 0);
    for (uint32_t v = 0; v < 6; ++v) {
        assert_int_equal(sk_mesh_valence(m, v), 4);
        assert_false(sk_is_boundary_v(m, v));
    }
    for (uint32_t h = 0; h < m->num_halfedges; ++h)
        assert_int_equal(sk_from(m, sk_opp(h)), sk_to(m, h));
    sk_mesh_destroy(&m);
    assert_null(m);
}

static void given_upper_half_then_one_boundary_loop_in_order(void **state)
{
    (void)state;
    sk_mesh *m = octahedron(4);
    sk_loops lp;
    assert_int_equal(sk_mesh_boundary_loops(m, &lp, NULL), SK_OK);
    assert_int_equal(lp.count, 1);
    assert_int_equal(lp.offsets[1], 4);
    assert_true(fabs(lp.lengths[0] - 4 * sqrt(2.0)) < 1e-12);
    /* consecutive boundary half-edges chain head to tail */
    for (uint32_t i = 0; i < 4; ++i) {
        uint32_t h = lp.halfedges[i], hn = lp.halfedges[(i + 1) % 4];
        assert_int_equal(sk_to(m, h), sk_from(m, hn));
        assert_true(sk_is_boundary_h(m, h));
    }
    sk_loops_free(&lp);
    /* boundary vertex: its half-edge is the boundary one, fan has valence 3 (1..4 ring) */
    for (uint32_t v = 1; v <= 4; ++v) {
        assert_true(sk_is_boundary_v(m, v));
        assert_int_equal(sk_mesh_valence(m, v), 3);
    }
    assert_int_equal(sk_mesh_valence(m, 0), 4);
    sk_topology t;
    sk_mesh_topology(m, &t, NULL, NULL);
    assert_int_equal(t.euler_characteristic, 1);
    assert_int_equal(t.vertices, 5); /* vertex 5 is isolated */
    sk_mesh_destroy(&m);
}

static void when_one_ring_is_walked_then_neighbours_are_in_cyclic_order(void **state)
{
    (void)state;
    sk_mesh *m = octahedron(8);
    /* around the apex 0 the ring is 1 2 3 4 in face order; ccw turns agree with face orientation */
    uint32_t h0 = m->v_halfedge[0], h = h0, ring[4];
    for (int i = 0; i < 4; ++i) {
        ring[i] = sk_to(m, h);
        h = sk_ccw_out(m, h);
    }
    assert_int_equal(h, h0);
    for (int i = 0; i < 4; ++i) {
        uint32_t a = ring[i], b = ring[(i + 1) % 4];
        assert_int_equal(b, a % 4 + 1); /* 1->2->3->4->1 */
    }
    sk_mesh_destroy(&m);
}

static void given_defects_then_build_fails_naming_them(void **state)
{
    (void)state;
    sk_mesh *m = NULL;
    sk_error err;
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    const uint32_t off2[] = {0, 3, 6}, off3[] = {0, 3, 6, 9};
    const uint32_t conflict[] = {0, 1, 2, 0, 1, 3};
    assert_int_equal(sk_mesh_from_faces(5, p, 2, off2, conflict, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "same direction"));
    assert_null(m);
    const uint32_t fin[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    assert_int_equal(sk_mesh_from_faces(5, p, 3, off3, fin, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "non-manifold"));
    const uint32_t range[] = {0, 1, 7};
    assert_int_equal(sk_mesh_from_faces(5, p, 1, off2, range, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "index 7"));
    const uint32_t rep[] = {0, 1, 1};
    assert_int_equal(sk_mesh_from_faces(5, p, 1, off2, rep, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "twice"));
    /* bowtie through vertex 0 with boundary on both fans */
    const uint32_t bow[] = {0, 1, 2, 0, 3, 4};
    assert_int_equal(sk_mesh_from_faces(5, p, 2, off2, bow, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "vertex 0"));
    double bad[15];
    memcpy(bad, p, sizeof bad);
    bad[4] = NAN;
    const uint32_t ok[] = {0, 1, 2};
    assert_int_equal(sk_mesh_from_faces(5, bad, 1, off2, ok, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "non-finite"));
}

static void given_two_closed_fans_at_a_vertex_then_build_fails(void **state)
{
    (void)state;
    /* two tetrahedra sharing vertex 0 only: every edge manifold, vertex 0 has two closed fans */
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};
    const uint32_t idx[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 5, 4, 0, 4, 6, 0, 6, 5, 4, 5, 6};
    const uint32_t off[] = {0, 3, 6, 9, 12, 15, 18, 21, 24};
    sk_mesh *m = NULL;
    sk_error err;
    assert_int_equal(sk_mesh_from_faces(7, p, 8, off, idx, &m, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "vertex 0"));
}

static void given_quads_and_triangles_then_faces_keep_their_size(void **state)
{
    (void)state;
    /* a square split as one quad + two triangles */
    const double p[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    const uint32_t idx[] = {0, 1, 4, 3, 1, 2, 5, 1, 5, 4};
    const uint32_t off[] = {0, 4, 7, 10};
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_from_faces(6, p, 3, off, idx, &m, NULL), SK_OK);
    assert_int_equal(sk_mesh_face_size(m, 0), 4);
    assert_int_equal(sk_mesh_face_size(m, 1), 3);
    double n[3];
    assert_true(fabs(sk_mesh_face_area(m, 0) - 1.0) < 1e-15);
    sk_mesh_face_normal(m, 0, n);
    assert_true(fabs(n[2] - 1.0) < 1e-15);
    sk_soup *s = NULL;
    assert_int_equal(sk_mesh_to_soup(m, &s, NULL), SK_OK);
    assert_int_equal(s->num_faces, 3);
    assert_int_equal(sk_soup_face_size(s, 0), 4);
    assert_memory_equal(s->face_indices, idx, sizeof idx);
    sk_soup_destroy(&s);
    sk_mesh_destroy(&m);
}

static void when_elements_are_deleted_then_compact_renumbers(void **state)
{
    (void)state;
    sk_mesh *m = octahedron(8);
    sk_mesh *c = NULL;
    assert_int_equal(sk_mesh_copy(m, &c, NULL), SK_OK);
    /* add an isolated vertex, delete it, compact: same mesh again */
    double q[3] = {5, 5, 5};
    uint32_t v = sk_mesh_new_vertex(c, q);
    assert_int_equal(v, 6);
    c->v_deleted[v] = 1;
    c->num_deleted_vertices = 1;
    uint32_t vmap[7];
    assert_int_equal(sk_mesh_compact(c, vmap, NULL, NULL), SK_OK);
    assert_int_equal(vmap[6], SK_INVALID);
    assert_int_equal(vmap[5], 5);
    assert_int_equal(c->num_vertices, 6);
    assert_int_equal(sk_mesh_check(c, NULL), SK_OK);
    assert_memory_equal(c->h_vertex, m->h_vertex, m->num_halfedges * sizeof(uint32_t));
    sk_mesh_destroy(&c);
    sk_mesh_destroy(&m);
}

static void given_real_meshes_then_built_mesh_agrees_with_validation(void **state)
{
    (void)state;
    const char *names[] = {"lion-head.off", "knot1.off", "mask_cone.off", "pig.off", "eight.off"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        sk_soup *s = skt_read_soup(skt_shared_mesh(names[i]));
        sk_validation r;
        assert_int_equal(sk_soup_validate(s, &r, NULL), SK_OK);
        sk_mesh *m = NULL;
        sk_error err;
        if (sk_mesh_from_soup(s, &m, &err) != SK_OK)
            fail_msg("%s: %s", names[i], err.message);
        assert_int_equal(sk_mesh_check(m, NULL), SK_OK);
        sk_topology t;
        assert_int_equal(sk_mesh_topology(m, &t, NULL, NULL), SK_OK);
        assert_int_equal(t.edges, r.edges);
        assert_int_equal(t.boundary_loops, r.boundary_loops);
        assert_int_equal(t.components, r.components);
        assert_int_equal(t.euler_characteristic, r.euler_characteristic);
        assert_int_equal(t.genus, r.genus);
        sk_mesh_destroy(&m);
        sk_soup_destroy(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_closed_octahedron_then_topology_is_sphere),
        cmocka_unit_test(given_upper_half_then_one_boundary_loop_in_order),
        cmocka_unit_test(when_one_ring_is_walked_then_neighbours_are_in_cyclic_order),
        cmocka_unit_test(given_defects_then_build_fails_naming_them),
        cmocka_unit_test(given_two_closed_fans_at_a_vertex_then_build_fails),
        cmocka_unit_test(given_quads_and_triangles_then_faces_keep_their_size),
        cmocka_unit_test(when_elements_are_deleted_then_compact_renumbers),
        cmocka_unit_test(given_real_meshes_then_built_mesh_agrees_with_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
