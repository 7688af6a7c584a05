/* The patches that can cross another: a Bezier patch lies in the convex hull of its control
 * points, so in their bounding box, and so does every tessellation of it (its vertices are points
 * of the patch). Two patches sharing no corner can cross only if their boxes overlap; the
 * self-intersection test needs only the patches with such a box pair. On a smooth surface that is
 * a small share (bunny00: 8,749 of 64,330 patches), and the test's tessellation and BVH shrink
 * with it.
 *
 * Boxes are found in a uniform grid of cells as wide as the mean box extent, by sorting (cell,
 * patch) entries: two overlapping boxes share a cell. A box over more than BIG_CELLS cells (a
 * spike) is tested against every box instead; every patch of a cell with more than CROWDED
 * entries is a candidate outright (conservative).
 *
 * sk__patch_box_pairs gives the pairs themselves (boxes padded by PAIR_PAD of the largest
 * coordinate, far above the rounding of a tessellation's vertices, which are evaluated points of
 * the patch): a pair is taken in the one cell holding the low corner of the two boxes' overlap,
 * a big box's pairs by testing it against every box; a crowded cell gives no pairs (the caller
 * then tests the candidates of sk__patch_box_candidates). */
#include "smooth/smooth_internal.h"
#include "core/internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define BIG_CELLS 64
#define CROWDED 256
#define PAIR_PAD 1e-9
#define AXIS_CELLS ((1u << 21) - 1) /* 21 bits per axis in a 63-bit key */

static bool boxes_overlap(const double *a, const double *b)
{
    for (int k = 0; k < 3; ++k)
        if (a[k] > b[3 + k] || b[k] > a[3 + k])
            return false;
    return true;
}

static bool share_corner(const sk_patch *a, const sk_patch *b)
{
    unsigned na = sk_patch_num_corners(a), nb = sk_patch_num_corners(b);
    for (unsigned i = 0; i < na; ++i)
        for (unsigned j = 0; j < nb; ++j)
            if (a->corner_ids[i] == b->corner_ids[j])
                return true;
    return false;
}

/* box[6 p ..]: lo xyz, hi xyz of patch p's control points; returns the mean largest extent, NaN
 * when a control point is not finite */
static double patch_boxes(const sk_patch_set *set, double *box, double glo[3], double ghi[3])
{
    double ext = 0;
    for (int k = 0; k < 3; ++k)
        glo[k] = INFINITY, ghi[k] = -INFINITY;
    for (size_t p = 0; p < set->count; ++p) {
        const double *cp = sk_patch_cp(set, p);
        double *b = box + 6 * p;
        for (int k = 0; k < 3; ++k)
            b[k] = INFINITY, b[3 + k] = -INFINITY;
        for (unsigned i = 0; i < sk_patch_num_points(&set->patches[p]); ++i)
            for (int k = 0; k < 3; ++k) {
                if (!isfinite(cp[3 * i + k]))
                    return NAN; /* (fmin and fmax would skip it) */
                b[k] = fmin(b[k], cp[3 * i + k]);
                b[3 + k] = fmax(b[3 + k], cp[3 * i + k]);
            }
        double e = 0;
        for (int k = 0; k < 3; ++k) {
            e = fmax(e, b[3 + k] - b[k]);
            glo[k] = fmin(glo[k], b[k]);
            ghi[k] = fmax(ghi[k], b[3 + k]);
        }
        ext += e;
    }
    return set->count ? ext / (double)set->count : 0;
}

/* the cell range of box b along each axis */
static size_t cell_range(const double *b, const double glo[3], double h, uint32_t lo[3],
                         uint32_t hi[3])
{
    size_t cells = 1;
    for (int k = 0; k < 3; ++k) {
        lo[k] = (uint32_t)fmin((b[k] - glo[k]) / h, AXIS_CELLS);
        hi[k] = (uint32_t)fmin((b[3 + k] - glo[k]) / h, AXIS_CELLS);
        cells *= (size_t)(hi[k] - lo[k] + 1);
    }
    return cells;
}

/* pairs within each run of one cell key: overlapping boxes of patches sharing no corner */
/* One (cell key, patch) entry for every grid cell each patch's box (not big[p]) covers; the
 * arrays hold as many entries as cell_range counted. Returns the entry count. */
static size_t cell_keys(const double *box, const uint8_t *big, size_t np, const double glo[3],
                        double h, uint64_t *key, uint32_t *val)
{
    size_t m = 0;
    uint32_t lo[3], hi[3];
    for (size_t p = 0; p < np; ++p) {
        if (big[p])
            continue;
        cell_range(box + 6 * p, glo, h, lo, hi);
        for (uint64_t z = lo[2]; z <= hi[2]; ++z)
            for (uint64_t y = lo[1]; y <= hi[1]; ++y)
                for (uint64_t x = lo[0]; x <= hi[0]; ++x) {
                    key[m] = x | y << 21 | z << 42;
                    val[m++] = (uint32_t)p;
                }
    }
    return m;
}

static void mark_runs(const sk_patch_set *set, const double *box, const uint64_t *key,
                      const uint32_t *val, size_t n, uint8_t *cand)
{
    for (size_t r = 0, e; r < n; r = e) {
        for (e = r + 1; e < n && key[e] == key[r]; ++e)
            ;
        if (e - r > CROWDED) {
            for (size_t i = r; i < e; ++i)
                cand[val[i]] = 1;
            continue;
        }
        for (size_t i = r; i < e; ++i)
            for (size_t j = i + 1; j < e; ++j) {
                uint32_t a = val[i], b = val[j];
                if ((!cand[a] || !cand[b]) && boxes_overlap(box + 6 * (size_t)a, box + 6 * (size_t)b) &&
                    !share_corner(&set->patches[a], &set->patches[b]))
                    cand[a] = cand[b] = 1;
            }
    }
}

/* the boxes of over BIG_CELLS cells against every box; false when there are too many for that */
static bool mark_big(const sk_patch_set *set, const double *box, const uint8_t *big, size_t nbig,
                     uint8_t *cand)
{
    size_t np = set->count;
    if (nbig > 0 && nbig > (size_t)1e9 / np)
        return false;
    for (size_t a = 0; a < np && nbig; ++a) {
        if (!big[a])
            continue;
        for (size_t b = 0; b < np; ++b)
            if (b != a && boxes_overlap(box + 6 * a, box + 6 * b) &&
                !share_corner(&set->patches[a], &set->patches[b]))
                cand[a] = cand[b] = 1;
    }
    return true;
}

sk_status sk__patch_box_candidates(const sk_patch_set *set, uint8_t *cand, sk_error *err)
{
    size_t np = set->count;
    memset(cand, 0, np);
    double glo[3], ghi[3];
    double *box = sk__malloc_array(6 * np + 1, sizeof *box);
    if (!box)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    double h = patch_boxes(set, box, glo, ghi);
    if (!(h > 0) || !isfinite(h)) { /* all boxes points, or a non-finite point: test them all */
        memset(cand, 1, np);
        sk__free(box);
        return SK_OK;
    }
    for (int k = 0; k < 3; ++k) /* no more cells per axis than the key holds */
        h = fmax(h, (ghi[k] - glo[k]) / (AXIS_CELLS - 1));
    size_t n = 0, nbig = 0;
    uint32_t lo[3], hi[3];
    uint8_t *big = sk__calloc_array(np + 1, 1);
    for (size_t p = 0; big && p < np; ++p) {
        size_t c = cell_range(box + 6 * p, glo, h, lo, hi);
        big[p] = c > BIG_CELLS;
        n += big[p] ? 0 : c;
        nbig += big[p];
    }
    uint64_t *key = sk__malloc_array(n + 1, sizeof *key);
    uint32_t *val = sk__malloc_array(n + 1, sizeof *val);
    sk_status st = big && key && val ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t m = st ? 0 : cell_keys(box, big, np, glo, h, key, val);
    if (!st && sk__sort_u64_u32(key, val, m))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (!st) {
        mark_runs(set, box, key, val, m, cand);
        if (!mark_big(set, box, big, nbig, cand))
            memset(cand, 1, np);
    }
    sk__free(big);
    sk__free(key);
    sk__free(val);
    sk__free(box);
    return st;
}

/* A growing list of pair keys (smaller patch << 32 | larger) */
typedef struct pair_list {
    uint64_t *key;
    size_t n, cap;
    bool nomem;
} pair_list;

static void pair_push(pair_list *l, size_t a, size_t b)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 1024;
        uint64_t *k = sk__realloc_array(l->key, cap, sizeof *k);
        if (!k) {
            l->nomem = true;
            return;
        }
        l->key = k;
        l->cap = cap;
    }
    size_t lo = a < b ? a : b, hi = a < b ? b : a;
    l->key[l->n++] = (uint64_t)lo << 32 | hi;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* the pairs of each run of one cell key whose overlap has its low corner in that cell (so each
 * pair once); false at a crowded cell */
static bool pair_runs(const sk_patch_set *set, const double *box, const uint32_t *lo_cell,
                      const uint64_t *key, const uint32_t *val, size_t n, pair_list *out)
{
    for (size_t r = 0, e; r < n; r = e) {
        for (e = r + 1; e < n && key[e] == key[r]; ++e)
            ;
        if (e - r > CROWDED)
            return false;
        uint32_t cell[3] = {(uint32_t)(key[r] & AXIS_CELLS), (uint32_t)(key[r] >> 21 & AXIS_CELLS),
                            (uint32_t)(key[r] >> 42 & AXIS_CELLS)};
        for (size_t i = r; i < e; ++i)
            for (size_t j = i + 1; j < e; ++j) {
                uint32_t a = val[i], b = val[j];
                bool home = true;
                for (int k = 0; k < 3 && home; ++k) {
                    uint32_t la = lo_cell[3 * (size_t)a + k], lb = lo_cell[3 * (size_t)b + k];
                    home = (la > lb ? la : lb) == cell[k];
                }
                if (home && boxes_overlap(box + 6 * (size_t)a, box + 6 * (size_t)b) &&
                    !share_corner(&set->patches[a], &set->patches[b]))
                    pair_push(out, a, b);
            }
    }
    return true;
}

sk_status sk__patch_box_pairs(const sk_patch_set *set, uint64_t **pairs, size_t *npairs,
                              sk_error *err)
{
    size_t np = set->count;
    *pairs = NULL;
    *npairs = 0;
    double glo[3], ghi[3];
    double *box = sk__malloc_array(6 * np + 1, sizeof *box);
    uint32_t *lo_cell = sk__malloc_array(3 * np + 1, sizeof *lo_cell);
    uint8_t *big = sk__calloc_array(np + 1, 1);
    uint64_t *key = NULL;
    uint32_t *val = NULL;
    pair_list out = {0};
    sk_status st = box && lo_cell && big ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    double h = st ? NAN : patch_boxes(set, box, glo, ghi);
    if (!(h > 0) || !isfinite(h)) /* no pairs: the caller falls back to the candidates */
        goto done;
    double pad = 0;
    for (int k = 0; k < 3; ++k)
        pad = fmax(pad, fmax(fabs(glo[k]), fabs(ghi[k])));
    pad *= PAIR_PAD;
    for (size_t p = 0; p < np; ++p)
        for (int k = 0; k < 3; ++k)
            box[6 * p + k] -= pad, box[6 * p + 3 + k] += pad;
    for (int k = 0; k < 3; ++k) {
        glo[k] -= pad, ghi[k] += pad;
        h = fmax(h, (ghi[k] - glo[k]) / (AXIS_CELLS - 1));
    }
    size_t n = 0, nbig = 0;
    uint32_t lo[3], hi[3];
    for (size_t p = 0; p < np; ++p) {
        size_t c = cell_range(box + 6 * p, glo, h, lo, hi);
        memcpy(lo_cell + 3 * p, lo, sizeof lo);
        big[p] = c > BIG_CELLS;
        n += big[p] ? 0 : c;
        nbig += big[p];
    }
    if (nbig > 0 && nbig > (size_t)1e9 / np)
        goto done;
    key = sk__malloc_array(n + 1, sizeof *key);
    val = sk__malloc_array(n + 1, sizeof *val);
    if (!key || !val) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    size_t m = cell_keys(box, big, np, glo, h, key, val);
    if (sk__sort_u64_u32(key, val, m)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (!pair_runs(set, box, lo_cell, key, val, m, &out))
        goto done; /* crowded: no pairs */
    for (size_t a = 0; a < np && nbig; ++a) {
        if (!big[a])
            continue;
        for (size_t b = 0; b < np; ++b)
            if (b != a && boxes_overlap(box + 6 * a, box + 6 * b) &&
                !share_corner(&set->patches[a], &set->patches[b]))
                pair_push(&out, a, b);
    }
    if (out.nomem) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (out.n) /* sorted, each pair once (a pair of big boxes came twice) */
        qsort(out.key, out.n, sizeof *out.key, cmp_u64);
    size_t u = 0;
    for (size_t i = 0; i < out.n; ++i)
        if (u == 0 || out.key[i] != out.key[u - 1])
            out.key[u++] = out.key[i];
    *pairs = out.key;
    *npairs = u;
    out.key = NULL;
    if (!*pairs && !(*pairs = sk__malloc_array(1, sizeof **pairs)))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
done:
    sk__free(out.key);
    sk__free(key);
    sk__free(val);
    sk__free(big);
    sk__free(lo_cell);
    sk__free(box);
    return st;
}
