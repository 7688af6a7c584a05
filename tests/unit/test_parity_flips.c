/* The parity pass of the VC1 construction (edge_flips.c, sk_smooth_opts.parity_flips): after the
 * quality flips, edges are flipped where that makes even interior vertices odd and keeps the
 * shape, so the edge deletion needs fewer deletions; the surface keeps the same vertices, is G1
 * to rounding, regular and interpolating; crease vertices and their neighbours are left alone. */
#include "testutil.h"
#include "surfkit/smooth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct parity_run {
    sk_smooth_stats st;
    sk_continuity_report r;
    size_t vertices, g0_creases;
    double diag;
} parity_run;

static parity_run build(const char *name, bool parity)
{
    sk_mesh *m = skt_read_mesh(skt_shared_mesh(name));
    sk_smooth_opts o = {0};
    o.parity_flips = parity;
    sk_smooth *s = NULL;
    sk_error err = {0};
    if (sk_smooth_build(m, &o, &s, &err) != SK_OK)
        fail_msg("%s: %s", name, err.message);
    parity_run p;
    memset(&p, 0, sizeof p);
    sk_continuity_opts co = {.intersection_tess = (unsigned)-1};
    assert_int_equal(sk_smooth_continuity(s, &co, &p.r, &err), SK_OK);
    p.st = s->stats;
    p.vertices = s->config->num_vertices;
    p.diag = sk_mesh_diagonal(s->config);
    for (uint32_t e = 0; s->crease_edge && e < sk_num_edges(s->config); ++e)
        p.g0_creases += s->crease_edge[e] != 0;
    assert_int_equal(p.vertices, m->num_vertices);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&m);
    return p;
}

/* Given knot1 (a clean closed mesh, 2864 even vertices after the quality flips), when its VC1
 * surface is built with the parity pass, then the pass flips edges, a tenth or more of the even
 * vertices become odd (2864 -> 2292), fewer edges are deleted than the lower bound without the pass (#even / 2),
 * and the surface is as exact as without: no singular patch, normal jumps and normal errors at
 * rounding level, every vertex interpolated. */
static void test_parity_knot(void **state)
{
    (void)state;
    parity_run off = build("knot1.off", false), on = build("knot1.off", true);
    print_message("knot1: even %zu -> %zu, deleted %zu -> %zu (bound %zu -> %zu), parity flips "
                  "%zu, singular %zu -> %zu\n",
                  off.st.deletion.even_vertices, on.st.deletion.even_vertices,
                  off.st.deletion.deleted_edges, on.st.deletion.deleted_edges,
                  off.st.deletion.lower_bound, on.st.deletion.lower_bound,
                  on.st.parity_flipped_edges, off.r.singular_patches, on.r.singular_patches);
    assert_int_equal(off.st.parity_flipped_edges, 0);
    assert_true(on.st.parity_flipped_edges > 0);
    assert_true(on.st.flipped_edges >= on.st.parity_flipped_edges);
    assert_true(10 * on.st.deletion.even_vertices <= 9 * off.st.deletion.even_vertices);
    assert_true(on.st.deletion.deleted_edges < off.st.deletion.lower_bound);
    assert_int_equal(on.r.singular_patches, 0);
    assert_true(on.r.max_normal_jump_deg < 1e-7);
    assert_true(on.r.max_normal_error_deg < 1e-7);
    assert_true(on.r.max_vertex_error <= 1e-12 * on.diag);
}

/* Given the cube (every vertex on a crease), when it is built with the parity pass, then nothing
 * is flipped for parity and its 12 edges stay G0 creases. */
static void test_parity_cube_creases(void **state)
{
    (void)state;
    parity_run on = build("cube.off", true);
    assert_int_equal(on.st.parity_flipped_edges, 0);
    assert_int_equal(on.g0_creases, 12);
    assert_int_equal(on.r.singular_patches, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parity_knot),
        cmocka_unit_test(test_parity_cube_creases),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
