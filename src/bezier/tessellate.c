/* Tessellation of a patch set into a triangle soup with the exact patch normals, watertight along
 * shared sides: every patch gets a grid of n segments per side; the vertices on a side whose two
 * corners carry ids are keyed by that pair of ids and created once (on the first patch with the
 * side, evaluated there), the corner vertices by their corner id, so neighbouring patches use the
 * same vertices and a closed patch network gives a closed manifold mesh. */
#include "bezier/bezier_internal.h"
#include "core/internal.h"

#include <stdlib.h>
#include <string.h>

/* Open-addressing map from a pair of ids to the first soup vertex made for it: (c, SK_INVALID)
 * for the corner c, (a, b) with a < b for the n - 1 inner vertices of the side between corners a
 * and b, stored consecutively from a toward b. */
typedef struct vmap {
    uint64_t *keys; /* UINT64_MAX = empty */
    uint32_t *vals;
    size_t cap, n;
} vmap;

static size_t vmap_slot(const vmap *m, uint64_t key)
{
    uint64_t h = key * 0x9E3779B97F4A7C15ULL;
    size_t j = (size_t)(h ^ (h >> 29)) & (m->cap - 1);
    while (m->keys[j] != UINT64_MAX && m->keys[j] != key)
        j = (j + 1) & (m->cap - 1);
    return j;
}

static bool vmap_init(vmap *m, size_t expected)
{
    m->cap = 64;
    while (m->cap < 2 * expected + 2)
        m->cap *= 2;
    m->n = 0;
    m->keys = sk__malloc_array(m->cap * sizeof *m->keys, 1);
    m->vals = sk__malloc_array(m->cap * sizeof *m->vals, 1);
    if (!m->keys || !m->vals)
        return false;
    memset(m->keys, 0xff, m->cap * sizeof *m->keys);
    return true;
}

/* The vertex stored for key, or SK_INVALID. */
static uint32_t vmap_get(const vmap *m, uint64_t key)
{
    size_t j = vmap_slot(m, key);
    return m->keys[j] == key ? m->vals[j] : SK_INVALID;
}

/* Stores key -> val (the map never fills: its capacity is twice the keys it may get). */
static void vmap_put(vmap *m, uint64_t key, uint32_t val)
{
    size_t j = vmap_slot(m, key);
    if (m->keys[j] != key)
        m->n++;
    m->keys[j] = key;
    m->vals[j] = val;
}

static uint64_t pair_key(uint32_t a, uint32_t b)
{
    return (uint64_t)a << 32 | b;
}

/* Where grid point g of a patch lies on its boundary: corner c (side = -1), or point s
 * (1..n-1, counted from corner `side`) of side `side` (corner = -1); both -1 inside. */
typedef struct grid_place {
    int corner, side;
    unsigned s;
} grid_place;

static grid_place place_triangle(unsigned n, unsigned j, unsigned k)
{
    unsigned i = n - j - k;
    grid_place g = {-1, -1, 0};
    if (j == 0 && k == 0)
        g.corner = 0;
    else if (j == n)
        g.corner = 1;
    else if (k == n)
        g.corner = 2;
    else if (k == 0)
        g.side = 0, g.s = j;     /* corner 0 -> 1 */
    else if (i == 0)
        g.side = 1, g.s = k;     /* corner 1 -> 2 */
    else if (j == 0)
        g.side = 2, g.s = n - k; /* corner 2 -> 0 */
    return g;
}

static grid_place place_tensor(unsigned n, unsigned i, unsigned j)
{
    grid_place g = {-1, -1, 0};
    bool lo_i = i == 0, hi_i = i == n, lo_j = j == 0, hi_j = j == n;
    if ((lo_i || hi_i) && (lo_j || hi_j))
        g.corner = lo_j ? (lo_i ? 0 : 1) : (hi_i ? 2 : 3);
    else if (lo_j)
        g.side = 0, g.s = i;
    else if (hi_i)
        g.side = 1, g.s = j;
    else if (hi_j)
        g.side = 2, g.s = n - i;
    else if (lo_i)
        g.side = 3, g.s = n - j;
    return g;
}

typedef struct tess {
    const sk_patch_set *set;
    unsigned n;
    sk_soup *soup;
    vmap map;
} tess;

/* The soup vertex of grid point (a, b) of patch p with parameters (u, v): shared through the map
 * where the place has ids, else new. */
static sk_status grid_vertex(tess *T, size_t p, grid_place g, double u, double v, uint32_t *out)
{
    const sk_patch *pa = &T->set->patches[p];
    unsigned nc = sk_patch_num_corners(pa);
    uint64_t key = UINT64_MAX;
    uint32_t offset = 0;
    if (g.corner >= 0 && pa->corner_ids[g.corner] != SK_INVALID) {
        key = pair_key(pa->corner_ids[g.corner], SK_INVALID);
    } else if (g.side >= 0) {
        uint32_t a = pa->corner_ids[g.side], b = pa->corner_ids[((unsigned)g.side + 1) % nc];
        if (a != SK_INVALID && b != SK_INVALID && a != b) {
            key = a < b ? pair_key(a, b) : pair_key(b, a);
            offset = (a < b ? g.s : T->n - g.s) - 1;
        }
    }
    if (key != UINT64_MAX) {
        uint32_t first = vmap_get(&T->map, key);
        if (first != SK_INVALID) {
            *out = first + offset;
            return SK_OK;
        }
    }
    /* new vertex; a side's n - 1 vertices are made together, in order from the smaller id */
    size_t count = g.corner < 0 && key != UINT64_MAX ? T->n - 1 : 1;
    uint32_t first = (uint32_t)T->soup->num_vertices;
    for (size_t s = 0; s < count; ++s) {
        double a = u, b = v;
        if (count > 1) { /* parameters of point s + 1 from the smaller id along this side */
            uint32_t c0 = pa->corner_ids[g.side], c1 = pa->corner_ids[((unsigned)g.side + 1) % nc];
            unsigned along = c0 < c1 ? (unsigned)s + 1 : T->n - 1 - (unsigned)s;
            double t = (double)along / T->n;
            static const double tri[3][4] = {{0, 1, 0, 0}, {1, -1, 0, 1}, {0, 0, 1, -1}};
            static const double quad[4][4] = {{0, 1, 0, 0}, {1, 0, 0, 1}, {1, -1, 1, 0},
                                              {0, 0, 1, -1}};
            const double *c = nc == 3 ? tri[g.side] : quad[g.side];
            a = c[0] + c[1] * t;
            b = c[2] + c[3] * t;
        }
        double x[3], nn[3];
        sk_patch_eval(T->set, p, a, b, x, NULL, NULL, nn);
        sk_status st = sk_soup_push_vertex(T->soup, x, nn, NULL);
        if (st)
            return st;
    }
    if (key != UINT64_MAX)
        vmap_put(&T->map, key, first);
    *out = first + offset;
    return SK_OK;
}

/* Grid vertices of patch p into ids (local index as the patch's own net of degree n). */
static sk_status patch_grid(tess *T, size_t p, uint32_t *ids)
{
    unsigned n = T->n;
    sk_status st = SK_OK;
    if (T->set->patches[p].kind == SK_PATCH_TENSOR) {
        for (unsigned j = 0; j <= n && st == SK_OK; ++j)
            for (unsigned i = 0; i <= n && st == SK_OK; ++i)
                st = grid_vertex(T, p, place_tensor(n, i, j), (double)i / n, (double)j / n,
                                 &ids[sk_tensor_index(n, i, j)]);
        return st;
    }
    for (unsigned k = 0; k <= n && st == SK_OK; ++k)
        for (unsigned j = 0; j + k <= n && st == SK_OK; ++j)
            st = grid_vertex(T, p, place_triangle(n, j, k), (double)j / n, (double)k / n,
                             &ids[sk_tri_index(n, j, k)]);
    return st;
}

static sk_status patch_faces(tess *T, size_t p, const uint32_t *ids)
{
    unsigned n = T->n;
    sk_status st = SK_OK;
    if (T->set->patches[p].kind == SK_PATCH_TENSOR) {
        for (unsigned j = 0; j < n && st == SK_OK; ++j)
            for (unsigned i = 0; i < n && st == SK_OK; ++i) {
                uint32_t a = ids[sk_tensor_index(n, i, j)], b = ids[sk_tensor_index(n, i + 1, j)],
                         c = ids[sk_tensor_index(n, i + 1, j + 1)],
                         d = ids[sk_tensor_index(n, i, j + 1)];
                uint32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
                if ((st = sk_soup_push_face(T->soup, t1, 3)) == SK_OK)
                    st = sk_soup_push_face(T->soup, t2, 3);
            }
        return st;
    }
    for (unsigned k = 0; k < n && st == SK_OK; ++k)
        for (unsigned j = 0; j < n - k && st == SK_OK; ++j) {
            uint32_t a = ids[sk_tri_index(n, j, k)], b = ids[sk_tri_index(n, j + 1, k)],
                     c = ids[sk_tri_index(n, j, k + 1)];
            uint32_t t1[3] = {a, b, c};
            st = sk_soup_push_face(T->soup, t1, 3);
            if (st == SK_OK && j + 1 < n - k) {
                uint32_t t2[3] = {b, ids[sk_tri_index(n, j + 1, k + 1)], c};
                st = sk_soup_push_face(T->soup, t2, 3);
            }
        }
    return st;
}

sk_status sk_patch_set_tessellate(const sk_patch_set *set, unsigned n, sk_soup **out,
                                  sk_error *err)
{
    if (!set || !out || n == 0 || n > 1024)
        return sk__fail(err, SK_ERR_ARG, "sk_patch_set_tessellate: bad arguments (n = %u)", n);
    size_t nv = 0, nf = 0, keys = 0;
    for (size_t p = 0; p < set->count; ++p) {
        bool quad = set->patches[p].kind == SK_PATCH_TENSOR;
        nv += quad ? (size_t)(n + 1) * (n + 1) : (size_t)(n + 1) * (n + 2) / 2;
        nf += quad ? 2 * (size_t)n * n : (size_t)n * n;
        keys += quad ? 8 : 6;
    }
    if (nv > UINT32_MAX - 1)
        return sk__fail(err, SK_ERR_ARG, "tessellation too large (%zu vertices)", nv);
    tess T = {.set = set, .n = n};
    uint32_t *ids = sk__malloc_array((size_t)(n + 1) * (n + 1) * sizeof *ids, 1);
    sk_status st = SK_ERR_NOMEM;
    if (ids && vmap_init(&T.map, keys))
        st = sk_soup_create(nv, nf, 3 * nf, true, false, &T.soup, err);
    for (size_t p = 0; p < set->count && st == SK_OK; ++p)
        if ((st = patch_grid(&T, p, ids)) == SK_OK)
            st = patch_faces(&T, p, ids);
    sk__free(ids);
    sk__free(T.map.keys);
    sk__free(T.map.vals);
    if (st != SK_OK) {
        sk_soup_destroy(&T.soup);
        return sk__fail(err, st, "out of memory tessellating");
    }
    *out = T.soup;
    sk__ok(err);
    return SK_OK;
}
