/* Loop and midpoint subdivision: counts, topology, the stencils on exact cases. */
#include "testutil.h"

#include <math.h>

static void given_lion_head_when_loop_twice_then_counts_follow_v_plus_e(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("lion-head.off"));
    sk_topology t0, t1;
    sk_mesh_topology(m, &t0, NULL, NULL);
    sk_subdiv_opts o = {.scheme = SK_SUBDIV_LOOP, .iterations = 2};
    sk_mesh *f = NULL;
    assert_int_equal(sk_mesh_subdivide(m, &o, &f, NULL), SK_OK);
    assert_int_equal(sk_mesh_check(f, NULL), SK_OK);
    sk_mesh_topology(f, &t1, NULL, NULL);
    assert_int_equal(t1.faces, 16 * t0.faces);
    /* one step: V' = V + E, E' = 2E + 3F */
    size_t v1 = t0.vertices + t0.edges, e1 = 2 * t0.edges + 3 * t0.faces;
    assert_int_equal(t1.vertices, v1 + e1);
    assert_int_equal(t1.euler_characteristic, t0.euler_characteristic);
    assert_int_equal(t1.boundary_loops, 1);
    sk_mesh_destroy(&f);
    sk_mesh_destroy(&m);
}

static void given_planar_grid_when_loop_then_stays_planar_and_interior_stencil_holds(void **state)
{
    (void)state;
    /* 4x4 vertices, z = 0 */
    double p[48];
    uint32_t idx[54], off[19];
    for (int j = 0, k = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i, ++k) {
            p[3 * k] = i;
            p[3 * k + 1] = j;
            p[3 * k + 2] = 0;
        }
    uint32_t n = 0, nf = 0;
    for (uint32_t j = 0; j < 3; ++j)
        for (uint32_t i = 0; i < 3; ++i) {
            uint32_t a = 4 * j + i, b = a + 1, c = a + 4, d = a + 5;
            uint32_t t[6] = {a, b, d, a, d, c};
            for (int q = 0; q < 6; ++q)
                idx[n++] = t[q];
            off[nf++] = n - 6;
            off[nf++] = n - 3;
        }
    off[nf] = n;
    sk_mesh *m = NULL, *f = NULL;
    assert_int_equal(sk_mesh_from_faces(16, p, nf, off, idx, &m, NULL), SK_OK);
    sk_subdiv_opts o = {0};
    assert_int_equal(sk_mesh_subdivide(m, &o, &f, NULL), SK_OK);
    for (size_t v = 0; v < f->num_vertices; ++v)
        assert_true(f->positions[3 * v + 2] == 0.0);
    /* interior vertex 5 = (1,1) has valence 6 with a symmetric ring: it stays put */
    assert_true(fabs(f->positions[15] - 1.0) < 1e-15 && fabs(f->positions[16] - 1.0) < 1e-15);
    /* boundary corner (0,0) has boundary neighbours (1,0) and (0,1): 3/4 v + 1/8 (b0 + b1) */
    assert_true(fabs(f->positions[0] - 0.125) < 1e-15 && fabs(f->positions[1] - 0.125) < 1e-15);
    sk_mesh_destroy(&f);
    sk_mesh_destroy(&m);
}

static void given_octahedron_when_midpoint_then_old_vertices_stay_and_new_at_midpoints(void **state)
{
    (void)state;
    const double p[] = {0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 0, 0, -1};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 5, 2, 1, 5, 3, 2, 5, 4, 3, 5, 1, 4};
    const uint32_t off[] = {0, 3, 6, 9, 12, 15, 18, 21, 24};
    sk_mesh *m = NULL, *f = NULL, *l = NULL;
    assert_int_equal(sk_mesh_from_faces(6, p, 8, off, idx, &m, NULL), SK_OK);
    sk_subdiv_opts o = {.scheme = SK_SUBDIV_MIDPOINT};
    assert_int_equal(sk_mesh_subdivide(m, &o, &f, NULL), SK_OK);
    assert_int_equal(f->num_vertices, 18);
    assert_int_equal(f->num_faces, 32);
    for (size_t v = 0; v < 6; ++v)
        for (int k = 0; k < 3; ++k)
            assert_true(f->positions[3 * v + k] == p[3 * v + k]);
    for (size_t v = 6; v < 18; ++v) { /* edge midpoints of the octahedron: |x|+|y|+|z| = 1 */
        const double *q = f->positions + 3 * v;
        assert_true(fabs(fabs(q[0]) + fabs(q[1]) + fabs(q[2]) - 1.0) < 1e-15);
    }
    /* Loop: even vertex of valence 4: beta = (5/8 - (3/8)^2) / 4; apex z = 1 - 4 beta */
    sk_subdiv_opts lo = {0};
    assert_int_equal(sk_mesh_subdivide(m, &lo, &l, NULL), SK_OK);
    double beta = (0.625 - 0.375 * 0.375) / 4.0;
    assert_true(fabs(l->positions[2] - (1.0 - 4.0 * beta)) < 1e-15);
    sk_mesh_destroy(&l);
    sk_mesh_destroy(&f);
    sk_mesh_destroy(&m);
}

static void given_quad_mesh_then_subdivision_refuses(void **state)
{
    (void)state;
    const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t idx[] = {0, 1, 2, 3}, off[] = {0, 4};
    sk_mesh *m = NULL, *f = NULL;
    sk_error err;
    assert_int_equal(sk_mesh_from_faces(4, p, 1, off, idx, &m, NULL), SK_OK);
    assert_int_equal(sk_mesh_subdivide(m, NULL, &f, &err), SK_ERR_TOPOLOGY);
    assert_null(f);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_lion_head_when_loop_twice_then_counts_follow_v_plus_e),
        cmocka_unit_test(given_planar_grid_when_loop_then_stays_planar_and_interior_stencil_holds),
        cmocka_unit_test(given_octahedron_when_midpoint_then_old_vertices_stay_and_new_at_midpoints),
        cmocka_unit_test(given_quad_mesh_then_subdivision_refuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
