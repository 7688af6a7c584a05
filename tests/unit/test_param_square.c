/* Square boundary maps on ragged disks: a disk cut from a scan (bunny00, the 4,000 triangles
 * nearest to a vertex, a staircase boundary with many "ear" triangles) has triangles with all
 * three vertices on one side of the square, which the square map flattens (flipped, zero area),
 * whatever the corners. sk_param_split_side_edges splits the dividing edges: then Tutte, Floater
 * and mean value flip nothing there and on every shared disk, with the corners of
 * sk_param_square_corners; the split keeps the surface (same area, same vertices first). */
#include "testutil.h"
#include "surfkit/param.h"
#include "surfkit/parametrize.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The connected piece, around the nearest face, of the `target` faces of m whose centroids are
 * nearest to vertex `seed`. */
static sk_mesh *cut_disk(const sk_mesh *m, uint32_t seed, size_t target)
{
    size_t nf = m->num_faces;
    double *d = malloc(nf * sizeof *d);
    size_t *order = malloc(nf * sizeof *order);
    const double *c = m->positions + 3 * (size_t)seed;
    for (size_t f = 0; f < nf; ++f) {
        uint32_t h = m->f_halfedge[f], v[3] = {sk_from(m, h), sk_to(m, h), sk_to(m, sk_next(m, h))};
        double s = 0;
        for (int k = 0; k < 3; ++k) {
            double x = (m->positions[3 * v[0] + k] + m->positions[3 * v[1] + k] +
                        m->positions[3 * v[2] + k]) / 3 - c[k];
            s += x * x;
        }
        d[f] = s;
        order[f] = f;
    }
    /* the target-th smallest distance, from a sorted copy */
    double *sorted = malloc(nf * sizeof *sorted);
    memcpy(sorted, d, nf * sizeof *d);
    qsort(sorted, nf, sizeof *sorted, cmp);
    double limit = sorted[target - 1];
    uint8_t *in = calloc(nf, 1), *seen = calloc(nf, 1);
    size_t best = 0;
    for (size_t f = 0; f < nf; ++f) {
        in[f] = d[f] <= limit;
        if (d[f] < d[best])
            best = f;
    }
    /* flood over shared edges inside the selection */
    size_t *stack = order, top = 0, kept = 0;
    stack[top++] = best;
    seen[best] = 1;
    while (top) {
        size_t f = stack[--top];
        ++kept;
        uint32_t h0 = m->f_halfedge[f], h = h0;
        do {
            uint32_t o = h ^ 1;
            if (!sk_is_boundary_h(m, o)) {
                uint32_t g = m->h_face[o];
                if (in[g] && !seen[g]) {
                    seen[g] = 1;
                    stack[top++] = g;
                }
            }
            h = sk_next(m, h);
        } while (h != h0);
    }
    uint32_t *vmap = malloc(m->num_vertices * sizeof *vmap), nv = 0;
    for (size_t v = 0; v < m->num_vertices; ++v)
        vmap[v] = SK_INVALID;
    double *xyz = malloc(3 * m->num_vertices * sizeof *xyz);
    uint32_t *off = malloc((kept + 1) * sizeof *off), *idx = malloc(3 * kept * sizeof *idx);
    size_t t = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (!seen[f])
            continue;
        uint32_t h = m->f_halfedge[f], v[3] = {sk_from(m, h), sk_to(m, h), sk_to(m, sk_next(m, h))};
        for (int k = 0; k < 3; ++k) {
            if (vmap[v[k]] == SK_INVALID) {
                memcpy(xyz + 3 * nv, m->positions + 3 * (size_t)v[k], 3 * sizeof *xyz);
                vmap[v[k]] = nv++;
            }
            idx[3 * t + (size_t)k] = vmap[v[k]];
        }
        off[t] = (uint32_t)(3 * t);
        ++t;
    }
    off[t] = (uint32_t)(3 * t);
    sk_mesh *out = NULL;
    assert_int_equal(sk_mesh_from_faces(nv, xyz, t, off, idx, &out, NULL), SK_OK);
    free(d), free(order), free(sorted), free(in), free(seen), free(vmap), free(xyz), free(off),
        free(idx);
    return out;
}

static double total_area(const sk_mesh *m)
{
    double a = 0;
    for (size_t f = 0; f < m->num_faces; ++f)
        a += sk_mesh_face_area(m, (uint32_t)f);
    return a;
}

/* Triangles whose three vertices have u = 0, u = 1, v = 0 or v = 1 alike. */
static size_t on_one_side(const sk_mesh *m, const double *uv)
{
    size_t n = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        uint32_t h = m->f_halfedge[f], v[3] = {sk_from(m, h), sk_to(m, h), sk_to(m, sk_next(m, h))};
        for (int k = 0; k < 2; ++k)
            for (double side = 0; side <= 1; side += 1)
                if (uv[2 * v[0] + k] == side && uv[2 * v[1] + k] == side && uv[2 * v[2] + k] == side)
                    ++n;
    }
    return n;
}

/* Square map of m with the given corners and method; returns the flipped count. */
static size_t square_flips(const sk_mesh *m, const uint32_t c[4], sk_param_method method,
                           size_t *one_side)
{
    sk_param_opts o = {0};
    o.method = method;
    o.boundary.shape = SK_BOUNDARY_SQUARE;
    o.boundary.has_corners = true;
    memcpy(o.boundary.corners, c, 4 * sizeof *c);
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_error err;
    sk_status st = sk_param_linear(m, &o, uv, NULL, &err);
    if (st != SK_OK)
        fail_msg("%s", err.message);
    sk_param_metrics pm;
    assert_int_equal(sk_param_metrics_compute(m, uv, &pm, NULL), SK_OK);
    if (one_side)
        *one_side = on_one_side(m, uv);
    free(uv);
    return pm.flipped;
}

static void ragged_scan_disk(void **state)
{
    (void)state;
    sk_mesh *bunny = skt_read_mesh(skt_shared_mesh("bunny00.off"));
    const uint32_t seeds[] = {0, 5000, 20000};
    for (size_t i = 0; i < sizeof seeds / sizeof *seeds; ++i) {
        sk_mesh *disk = cut_disk(bunny, seeds[i], 4000);
        assert_int_equal(sk_param_check_disk(disk, NULL), SK_OK);
        uint32_t c[4];
        assert_int_equal(sk_param_square_corners(disk, c, NULL), SK_OK);
        size_t side0 = 0, flips0 = square_flips(disk, c, SK_PARAM_FLOATER, &side0);
        sk_mesh *split = NULL;
        size_t splits = 0;
        assert_int_equal(sk_param_split_side_edges(disk, c, &split, &splits, NULL), SK_OK);
        print_message("bunny00 cut at %u: %zu faces, corners %u %u %u %u: %zu triangles on one "
                      "side, %zu flipped; %zu edges split -> %zu faces\n", seeds[i],
                      disk->num_faces, c[0], c[1], c[2], c[3], side0, flips0, splits,
                      split->num_faces);
        /* the defect is there before the split (the cut is ragged enough) ... */
        assert_true(side0 > 0 && flips0 > 0 && splits > 0);
        /* ... and gone after it, for every method with the guarantee */
        assert_int_equal(split->num_vertices, disk->num_vertices + splits);
        assert_memory_equal(split->positions, disk->positions, 3 * disk->num_vertices * sizeof(double));
        assert_true(fabs(total_area(split) - total_area(disk)) < 1e-12 * total_area(disk));
        assert_int_equal(sk_param_check_disk(split, NULL), SK_OK);
        const sk_param_method methods[] = {SK_PARAM_TUTTE, SK_PARAM_FLOATER, SK_PARAM_MEAN_VALUE};
        for (int k = 0; k < 3; ++k) {
            size_t side = 1;
            assert_int_equal(square_flips(split, c, methods[k], &side), 0);
            assert_int_equal(side, 0);
        }
        sk_mesh_destroy(&split);
        sk_mesh_destroy(&disk);
    }
    sk_mesh_destroy(&bunny);
}

static void shared_disks(void **state)
{
    (void)state;
    const char *names[] = {"lion-head.off", "mushroom.off", "nefertiti.off", "paraboloid-patch.off",
                           "patch-01.off", "three_peaks.off"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(names[i]));
        uint32_t c[4];
        assert_int_equal(sk_param_square_corners(m, c, NULL), SK_OK);
        sk_mesh *split = NULL;
        size_t splits = 0;
        assert_int_equal(sk_param_split_side_edges(m, c, &split, &splits, NULL), SK_OK);
        for (int k = 0; k < 3; ++k) {
            const sk_param_method methods[] = {SK_PARAM_TUTTE, SK_PARAM_FLOATER, SK_PARAM_MEAN_VALUE};
            size_t side = 1;
            size_t flips = square_flips(split, c, methods[k], &side);
            if (flips || side)
                fail_msg("%s %d: %zu flipped, %zu on one side", names[i], k, flips, side);
        }
        print_message("%-22s corners %u %u %u %u, %zu edges split\n", names[i], c[0], c[1], c[2],
                      c[3], splits);
        sk_mesh_destroy(&split);
        sk_mesh_destroy(&m);
    }
}

static void bad_corners(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(6, 1), *out = NULL;
    uint32_t c[4];
    assert_int_equal(sk_param_square_corners(m, c, NULL), SK_OK);
    uint32_t swapped[4] = {c[1], c[0], c[2], c[3]};
    sk_error err;
    assert_int_equal(sk_param_split_side_edges(m, swapped, &out, NULL, &err), SK_ERR_ARG);
    assert_null(out);
    uint32_t inside[4] = {c[0], c[1], c[2], (uint32_t)m->num_vertices};
    assert_int_equal(sk_param_split_side_edges(m, inside, &out, NULL, &err), SK_ERR_ARG);
    sk_mesh_destroy(&m);
    m = skt_read_mesh(skt_shared_mesh("sphere.off"));
    assert_int_equal(sk_param_square_corners(m, c, &err), SK_ERR_TOPOLOGY);
    sk_mesh_destroy(&m);
}

/* sk_parametrize with the square boundary does the corner and split steps itself: the same
 * corners, splits and uv as the low-level calls done by hand, the split mesh in the stats, the
 * input vertices' uv in the caller's array; no split on a clean disk; given corners kept. */
static void pipeline_square(void **state)
{
    (void)state;
    sk_mesh *bunny = skt_read_mesh(skt_shared_mesh("bunny00.off"));
    sk_mesh *disk = cut_disk(bunny, 5000, 4000);
    uint32_t c[4];
    sk_mesh *split = NULL;
    size_t splits = 0;
    assert_int_equal(sk_param_square_corners(disk, c, NULL), SK_OK);
    assert_int_equal(sk_param_split_side_edges(disk, c, &split, &splits, NULL), SK_OK);
    assert_true(splits > 0);
    /* by hand: the split mesh with the corners given */
    sk_parametrize_opts o = {.boundary = {.shape = SK_BOUNDARY_SQUARE, .has_corners = true}};
    memcpy(o.boundary.corners, c, sizeof c);
    double *hand = calloc(2 * split->num_vertices, sizeof *hand);
    sk_parametrize_stats s;
    assert_int_equal(sk_parametrize(split, &o, hand, &s, NULL), SK_OK);
    assert_int_equal(s.split_edges, 0); /* nothing left to split */
    assert_null(s.split_mesh);
    sk_parametrize_stats_release(&s);
    /* the pipeline, corners not given */
    o.boundary.has_corners = false;
    double *uv = calloc(2 * disk->num_vertices, sizeof *uv);
    assert_int_equal(sk_parametrize(disk, &o, uv, &s, NULL), SK_OK);
    assert_int_equal(s.boundary, SK_BOUNDARY_SQUARE);
    assert_int_equal(s.flipped, 0);
    assert_int_equal(s.split_edges, splits);
    assert_non_null(s.split_mesh);
    assert_int_equal(s.split_mesh->num_vertices, disk->num_vertices + splits);
    assert_int_equal(s.split_mesh->num_faces, split->num_faces);
    assert_memory_equal(s.split_mesh->positions, split->positions,
                        3 * split->num_vertices * sizeof(double));
    assert_memory_equal(s.split_mesh->uvs, hand, 2 * split->num_vertices * sizeof(double));
    assert_memory_equal(uv, hand, 2 * disk->num_vertices * sizeof(double));
    sk_parametrize_stats_release(&s);
    assert_null(s.split_mesh);
    /* stats may be NULL: the split mesh is released inside, uv still written */
    memset(uv, 0, 2 * disk->num_vertices * sizeof *uv);
    assert_int_equal(sk_parametrize(disk, &o, uv, NULL, NULL), SK_OK);
    assert_memory_equal(uv, hand, 2 * disk->num_vertices * sizeof(double));
    /* MIPS with the square fixed splits too */
    o.method = SK_PARAM_MIPS;
    assert_int_equal(sk_parametrize(disk, &o, uv, &s, NULL), SK_OK);
    assert_int_equal(s.split_edges, splits);
    assert_int_equal(s.flipped, 0);
    sk_parametrize_stats_release(&s);
    free(uv);
    free(hand);
    sk_mesh_destroy(&split);
    sk_mesh_destroy(&disk);
    sk_mesh_destroy(&bunny);

    /* a clean disk: the sharpest-turn corners, no split, the input parametrized */
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("patch-01.off"));
    uv = calloc(2 * m->num_vertices, sizeof *uv);
    o = (sk_parametrize_opts){.boundary = {.shape = SK_BOUNDARY_SQUARE}};
    assert_int_equal(sk_parametrize(m, &o, uv, &s, NULL), SK_OK);
    assert_int_equal(s.split_edges, 0);
    assert_null(s.split_mesh);
    assert_int_equal(sk_param_square_corners(m, c, NULL), SK_OK);
    for (int k = 0; k < 4; ++k) /* normalized: the corners at the unit square's corners */
        assert_true(fabs(uv[2 * c[k]] - (k == 1 || k == 2)) < 1e-12 &&
                    fabs(uv[2 * c[k] + 1] - (k >= 2)) < 1e-12);
    sk_parametrize_stats_release(&s);
    /* corners given that are not in boundary order: refused */
    o.boundary.has_corners = true;
    uint32_t swapped[4] = {c[1], c[0], c[2], c[3]};
    memcpy(o.boundary.corners, swapped, sizeof swapped);
    sk_error err;
    assert_int_equal(sk_parametrize(m, &o, uv, &s, &err), SK_ERR_ARG);
    assert_null(s.split_mesh);
    sk_parametrize_stats_release(&s);
    free(uv);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ragged_scan_disk),
        cmocka_unit_test(shared_disks),
        cmocka_unit_test(bad_corners),
        cmocka_unit_test(pipeline_square),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
