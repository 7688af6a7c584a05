/* Overlapping uv triangles: a uniform grid over the bounding boxes, each candidate pair tested once
 * (in the cell holding the lower-left corner of the intersection of their boxes), decided by an
 * exact separating-axis test. Two convex polygons have disjoint interiors exactly when one of
 * them has an edge whose line leaves the other entirely on its closed outer side. */
#include "core/internal.h"
#include "surfkit/atlas.h"
#include "surfkit/param.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* A vertex shared by two triangles lies on the line of each edge it ends (orientation 0):
 * neighbours in a layout share two, and the exact stage of sk_orient2d, which an exactly zero
 * determinant always reaches, is skipped for them. */
static bool same_point(const double *a, const double *b)
{
    return a[0] == b[0] && a[1] == b[1];
}

/* True when the interiors of the counter-clockwise triangles a and b intersect. */
static bool interiors_meet(const double *a, const double *b)
{
    for (int pass = 0; pass < 2; ++pass) {
        const double *s = pass ? b : a, *t = pass ? a : b;
        for (int e = 0; e < 3; ++e) {
            const double *p = s + 2 * e, *q = s + 2 * ((e + 1) % 3);
            int inside = 0;
            for (int k = 0; k < 3 && !inside; ++k)
                inside = !same_point(t + 2 * k, p) && !same_point(t + 2 * k, q) &&
                         sk_orient2d(p, q, t + 2 * k) > 0;
            if (!inside)
                return false;
        }
    }
    return true;
}

sk_status sk_uv_overlaps(size_t n, const double *tri, size_t *count, uint32_t first[2],
                         sk_error *err)
{
    *count = 0;
    if (first)
        first[0] = first[1] = SK_INVALID;
    if (n < 2)
        return SK_OK;
    sk_status st = SK_OK;
    double *t = sk__malloc_array(6 * n, sizeof(double));
    double *box = sk__malloc_array(4 * n, sizeof(double));
    uint32_t *cstart = NULL, *items = NULL, *fill = NULL;
    uint32_t *corner = sk__malloc_array(2 * n, sizeof(uint32_t)); /* cell of the box's low corner */
    uint8_t *live = sk__calloc_array(n, 1);
    if (!t || !box || !live || !corner) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < n; ++i) {
        const double *s = tri + 6 * i;
        int o = sk_orient2d(s, s + 2, s + 4);
        if (o == 0)
            continue; /* no interior */
        live[i] = 1;
        /* store counter-clockwise */
        memcpy(t + 6 * i, s, 2 * sizeof(double));
        memcpy(t + 6 * i + 2, o > 0 ? s + 2 : s + 4, 2 * sizeof(double));
        memcpy(t + 6 * i + 4, o > 0 ? s + 4 : s + 2, 2 * sizeof(double));
        double *b = box + 4 * i;
        b[0] = fmin(s[0], fmin(s[2], s[4]));
        b[1] = fmin(s[1], fmin(s[3], s[5]));
        b[2] = fmax(s[0], fmax(s[2], s[4]));
        b[3] = fmax(s[1], fmax(s[3], s[5]));
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], b[k]);
            hi[k] = fmax(hi[k], b[2 + k]);
        }
    }
    if (!(lo[0] <= hi[0]))
        goto done;
    /* about one triangle per cell, square cells */
    double w = fmax(hi[0] - lo[0], 1e-300), h = fmax(hi[1] - lo[1], 1e-300);
    double cell = sqrt(w * h / (double)n);
    if (!(cell > 0))
        cell = fmax(w, h);
    size_t nx = (size_t)fmin(fmax(ceil(w / cell), 1.0), 4096.0);
    size_t ny = (size_t)fmin(fmax(ceil(h / cell), 1.0), 4096.0);
    double cx = w / (double)nx, cy = h / (double)ny;
#define CELL_X(x) ((size_t)fmin(fmax(floor(((x) - lo[0]) / cx), 0.0), (double)(nx - 1)))
#define CELL_Y(y) ((size_t)fmin(fmax(floor(((y) - lo[1]) / cy), 0.0), (double)(ny - 1)))
    cstart = sk__calloc_array(nx * ny + 1, sizeof(uint32_t));
    fill = sk__calloc_array(nx * ny, sizeof(uint32_t));
    if (!cstart || !fill) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!live[i])
            continue;
        const double *b = box + 4 * i;
        size_t x0 = CELL_X(b[0]), x1 = CELL_X(b[2]), y0 = CELL_Y(b[1]), y1 = CELL_Y(b[3]);
        corner[2 * i] = (uint32_t)x0;
        corner[2 * i + 1] = (uint32_t)y0;
        for (size_t y = y0; y <= y1; ++y)
            for (size_t x = x0; x <= x1; ++x)
                cstart[y * nx + x + 1]++;
        total += (x1 - x0 + 1) * (y1 - y0 + 1);
    }
    if (total >= UINT32_MAX) {
        st = sk__fail(err, SK_ERR_ARG, "too many grid entries");
        goto done;
    }
    for (size_t c = 0; c < nx * ny; ++c)
        cstart[c + 1] += cstart[c];
    items = sk__malloc_array(total ? total : 1, sizeof(uint32_t));
    if (!items) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < n; ++i) {
        if (!live[i])
            continue;
        const double *b = box + 4 * i;
        size_t x0 = corner[2 * i], x1 = CELL_X(b[2]), y0 = corner[2 * i + 1], y1 = CELL_Y(b[3]);
        for (size_t y = y0; y <= y1; ++y)
            for (size_t x = x0; x <= x1; ++x) {
                size_t c = y * nx + x;
                items[cstart[c] + fill[c]++] = (uint32_t)i;
            }
    }
    size_t found = 0;
    /* rows in parallel when no first pair is asked for (the atlas's final check: 1.6 s of the
     * 832k atlas on one thread) */
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : found) if (!first && n > 50000)
#endif
    for (size_t y = 0; y < ny; ++y)
        for (size_t x = 0; x < nx; ++x) {
            size_t c = y * nx + x;
            for (uint32_t p = cstart[c]; p < cstart[c + 1]; ++p)
                for (uint32_t q = p + 1; q < cstart[c + 1]; ++q) {
                    uint32_t i = items[p], j = items[q];
                    const double *bi = box + 4 * (size_t)i, *bj = box + 4 * (size_t)j;
                    if (bi[0] > bj[2] || bj[0] > bi[2] || bi[1] > bj[3] || bj[1] > bi[3])
                        continue;
                    /* the pair is tested in the cell of the lower-left corner of the overlap (the
                     * cell maps are monotone: that corner's cell is the larger of the two boxes'
                     * low-corner cells, kept per triangle instead of two divisions per pair) */
                    const uint32_t *ki = corner + 2 * (size_t)i, *kj = corner + 2 * (size_t)j;
                    if ((ki[0] > kj[0] ? ki[0] : kj[0]) != x || (ki[1] > kj[1] ? ki[1] : kj[1]) != y)
                        continue;
                    if (interiors_meet(t + 6 * (size_t)i, t + 6 * (size_t)j)) {
                        if (found == 0 && first) {
                            first[0] = i < j ? i : j;
                            first[1] = i < j ? j : i;
                        }
                        found++;
                    }
                }
        }
#undef CELL_X
#undef CELL_Y
    *count = found;
done:
    sk__free(t);
    sk__free(box);
    sk__free(live);
    sk__free(corner);
    sk__free(cstart);
    sk__free(fill);
    sk__free(items);
    return st;
}
