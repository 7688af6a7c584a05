/* The cut graph of a disk with holes (src/atlas/charts.c, sk__chart_cut_holes). Given a 10 x 10
 * grid of unit squares (two triangles each) with two square holes, [2,4]^2 and [6,8] x [5,7],
 * when the chart of all its faces is cut, then each hole is joined to the outer boundary by a
 * shortest path (2 edges each: 4 edges, length 4), and the chart extracted with the cuts is one
 * disk (one boundary loop, Euler characteristic 1); cut once more, nothing changes (the chart
 * holds cuts already); a grid without holes is not cut. */
#include "testutil.h"
#include "atlas/atlas_internal.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define N 10

static bool in_hole(int i, int j, bool holes)
{
    return holes && ((i >= 2 && i < 4 && j >= 2 && j < 4) || (i >= 6 && i < 8 && j >= 5 && j < 7));
}

/* The grid of N x N unit squares, without the holes' squares when holes. */
static sk_mesh *grid(bool holes)
{
    double pos[3 * (N + 1) * (N + 1)];
    uint32_t idx[6 * N * N], off[2 * N * N + 1];
    size_t nf = 0;
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            double *p = pos + 3 * (size_t)(j * (N + 1) + i);
            p[0] = i;
            p[1] = j;
            p[2] = 0;
        }
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            if (in_hole(i, j, holes))
                continue;
            uint32_t a = (uint32_t)(j * (N + 1) + i), b = a + 1, c = a + N + 2, d = a + N + 1;
            const uint32_t t[6] = {a, b, c, a, c, d};
            for (int k = 0; k < 2; ++k, ++nf) {
                off[nf] = (uint32_t)(3 * nf);
                memcpy(idx + 3 * nf, t + 3 * k, 3 * sizeof(uint32_t));
            }
        }
    off[nf] = (uint32_t)(3 * nf);
    sk_mesh *m = NULL;
    sk_error err;
    if (sk_mesh_from_faces((N + 1) * (N + 1), pos, nf, off, idx, &m, &err))
        fail_msg("%s", err.message);
    return m;
}

/* Cuts the chart of all of m's faces: the edges cut and their length; the topology of the chart
 * extracted afterwards in *top. */
static size_t cut_all(const sk_mesh *m, sk__chart_work *w, double *len, sk_topology *top)
{
    size_t nf = m->num_faces, ncut = 0;
    uint32_t *faces = malloc(nf * sizeof(uint32_t));
    assert_non_null(faces);
    for (size_t f = 0; f < nf; ++f) {
        faces[f] = (uint32_t)f;
        w->label[f] = 1;
    }
    sk_error err;
    if (sk__chart_cut_holes(m, faces, nf, 1, w, &ncut, &err))
        fail_msg("%s", err.message);
    *len = 0;
    for (size_t e = 0; e < sk_num_edges(m); ++e)
        if (w->cut[e])
            *len += sk_mesh_edge_length(m, (uint32_t)e);
    sk_mesh *chart = NULL;
    uint32_t *vert_h = NULL;
    if (sk__chart_extract(m, faces, nf, 1, w, &chart, &vert_h, &err) ||
        sk_mesh_topology(chart, top, NULL, &err))
        fail_msg("%s", err.message);
    sk_mesh_destroy(&chart);
    sk__free(vert_h);
    free(faces);
    return ncut;
}

static void test_cut_holes(void **state)
{
    (void)state;
    sk_mesh *m = grid(true);
    sk__chart_work w;
    sk_error err;
    if (sk__chart_work_init(&w, m, &err))
        fail_msg("%s", err.message);
    double len = 0;
    sk_topology top;
    size_t ncut = cut_all(m, &w, &len, &top);
    print_message("grid with 2 holes: %zu edges cut, length %.6f, %zu boundary loops\n", ncut, len,
                  top.boundary_loops);
    assert_int_equal(ncut, 4);
    assert_true(fabs(len - 4) < 1e-12);
    assert_int_equal(top.components, 1);
    assert_int_equal(top.boundary_loops, 1);
    assert_int_equal(top.euler_characteristic, 1);
    assert_int_equal(cut_all(m, &w, &len, &top), 0); /* cut already */
    assert_true(fabs(len - 4) < 1e-12);
    sk__chart_work_free(&w);
    sk_mesh_destroy(&m);

    m = grid(false);
    if (sk__chart_work_init(&w, m, &err))
        fail_msg("%s", err.message);
    assert_int_equal(cut_all(m, &w, &len, &top), 0);
    assert_true(len == 0);
    assert_int_equal(top.boundary_loops, 1);
    sk__chart_work_free(&w);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cut_holes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
