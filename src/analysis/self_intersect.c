/* Self-intersections (intersect.h): every fan triangle is tested against the triangles of the
 * BVH whose boxes overlap its box, unless they belong to the same or to neighbouring groups (the
 * BVH is asked once per group, for the box of its triangles, and what it gives is tested against
 * each of them: the same tests as one query per triangle, far fewer walks); the
 * exact test is by signed volumes: an edge pq of one triangle crosses triangle abc when p and q
 * lie strictly on opposite sides of abc's plane and the line pq passes strictly inside abc (the
 * three volumes (p, q, a, b), (p, q, b, c), (p, q, c, a) have one sign). Two triangles in general
 * position cross exactly when an edge of one crosses the other: each end of their common segment
 * lies on an edge of one of them. */
#include "surfkit/intersect.h"
#include "analysis/bvh_internal.h"
#include "analysis/intersect_internal.h"
#include "core/internal.h"
#include "mesh/fan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static bool edge_crosses(const double *p, const double *q, const double *t)
{
    const double *a = t, *b = t + 3, *c = t + 6;
    double s1 = orient3d(a, b, c, p), s2 = orient3d(a, b, c, q);
    if (!((s1 < 0 && s2 > 0) || (s1 > 0 && s2 < 0)))
        return false;
    double v1 = orient3d(p, q, a, b), v2 = orient3d(p, q, b, c), v3 = orient3d(p, q, c, a);
    return (v1 > 0 && v2 > 0 && v3 > 0) || (v1 < 0 && v2 < 0 && v3 < 0);
}

static bool triangles_cross(const double *s, const double *t)
{
    for (int e = 0; e < 3; ++e) {
        int f = (e + 1) % 3;
        if (edge_crosses(s + 3 * e, s + 3 * f, t) || edge_crosses(t + 3 * e, t + 3 * f, s))
            return true;
    }
    return false;
}

/* Pairs found by one thread */
typedef struct pairs {
    uint64_t *key; /* (smaller group << 32) | larger group */
    size_t n, cap;
    bool nomem;
} pairs;

static void pairs_push(pairs *p, uint64_t key)
{
    if (p->n && p->key[p->n - 1] == key) /* consecutive repeats are common: skip them */
        return;
    if (p->n == p->cap) {
        size_t cap = p->cap ? 2 * p->cap : 256;
        uint64_t *k = sk__realloc_array(p->key, cap, sizeof *k);
        if (!k) {
            p->nomem = true;
            return;
        }
        p->key = k;
        p->cap = cap;
    }
    p->key[p->n++] = key;
}

typedef struct visit_ctx {
    const sk_soup *surface, *groups;
    const uint32_t *face_group;
    uint32_t face, group;
    const double *tri; /* 9 corners of the query triangle */
    pairs *out;
    size_t tests;
} visit_ctx;

static uint32_t group_of(const visit_ctx *c, uint32_t f)
{
    return c->face_group ? c->face_group[f] : f;
}

static bool neighbours(const sk_soup *g, uint32_t a, uint32_t b)
{
    const uint32_t *ia = g->face_indices + g->face_offsets[a], *ib = g->face_indices + g->face_offsets[b];
    size_t na = sk_soup_face_size(g, a), nb = sk_soup_face_size(g, b);
    for (size_t i = 0; i < na; ++i)
        for (size_t j = 0; j < nb; ++j)
            if (ia[i] == ib[j])
                return true;
    return false;
}

static int visit(void *user, const double corners[9], uint32_t face)
{
    visit_ctx *c = user;
    if (face <= c->face) /* each face pair once; never a face with itself */
        return 0;
    uint32_t g = group_of(c, face);
    if (g == c->group || neighbours(c->groups, c->group, g))
        return 0;
    ++c->tests;
    if (triangles_cross(c->tri, corners)) {
        uint32_t lo = g < c->group ? g : c->group, hi = g < c->group ? c->group : g;
        pairs_push(c->out, ((uint64_t)lo << 32) | hi);
    }
    return 0;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static sk_status check_groups(const sk_soup *surface, const uint32_t *face_group,
                              const sk_soup *groups, sk_error *err)
{
    for (size_t f = 0; face_group && f < surface->num_faces; ++f)
        if (face_group[f] >= groups->num_faces)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "face %zu is in group %u but there are %zu groups", f, face_group[f],
                            groups->num_faces);
    if (!face_group && groups->num_faces < surface->num_faces)
        return sk__fail(err, SK_ERR_TOPOLOGY, "%zu groups for %zu faces", groups->num_faces,
                        surface->num_faces);
    return SK_OK;
}

/* Sorts and de-duplicates the pairs, fills the report. */
static void summarize(pairs *all, size_t num_groups, sk_intersection_report *rep, sk_error *err,
                      sk_status *st)
{
    if (all->n) /* (qsort wants a valid pointer even for no elements) */
        qsort(all->key, all->n, sizeof *all->key, cmp_u64);
    size_t m = 0;
    for (size_t i = 0; i < all->n; ++i)
        if (m == 0 || all->key[i] != all->key[m - 1])
            all->key[m++] = all->key[i];
    rep->pairs = m;
    for (size_t i = 0; i < m && rep->num_examples < SK_INTERSECT_EXAMPLES; ++i, ++rep->num_examples) {
        rep->examples[2 * i] = (uint32_t)(all->key[i] >> 32);
        rep->examples[2 * i + 1] = (uint32_t)all->key[i];
    }
    uint8_t *seen = sk__calloc_array(num_groups + 1, 1);
    if (!seen) {
        *st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        return;
    }
    for (size_t i = 0; i < m; ++i) {
        uint32_t a = (uint32_t)(all->key[i] >> 32), b = (uint32_t)all->key[i];
        rep->groups += !seen[a] + (a != b && !seen[b]);
        seen[a] = seen[b] = 1;
    }
    sk__free(seen);
}

/* One group's triangles (fan triangles ids[0, n)) against the BVH: the triangles of other,
 * non-neighbouring groups whose boxes overlap the group's box are gathered (cand), then each
 * triangle of the group is tested against those of a later face with an overlapping box: the
 * tests of one query per triangle. A box that is not finite falls back to those queries. */
typedef struct group_cand {
    const double *corners;
    uint32_t face;
} group_cand;

typedef struct group_ctx {
    visit_ctx *c;
    group_cand *cand;
    size_t n, cap;
    uint32_t memo_group;
    bool memo_skip, nomem;
} group_ctx;

static int gather(void *user, const double corners[9], uint32_t face)
{
    group_ctx *G = user;
    uint32_t g = group_of(G->c, face);
    if (g != G->memo_group) {
        G->memo_group = g;
        G->memo_skip = g == G->c->group || neighbours(G->c->groups, G->c->group, g);
    }
    if (G->memo_skip)
        return 0;
    if (G->n == G->cap) {
        size_t cap = G->cap ? 2 * G->cap : 256;
        group_cand *p = sk__realloc_array(G->cand, cap, sizeof *p);
        if (!p) {
            G->nomem = true;
            return 1;
        }
        G->cand = p;
        G->cap = cap;
    }
    G->cand[G->n++] = (group_cand){corners, face};
    return 0;
}

/* corners and box of fan triangle t */
static void fan_box(const sk_soup *surface, const uint32_t *tri_v, size_t t, double tri[9],
                    double lo[3], double hi[3])
{
    const uint32_t *v = tri_v + 3 * t;
    for (int q = 0; q < 3; ++q)
        memcpy(tri + 3 * q, surface->positions + 3 * (size_t)v[q], 3 * sizeof *tri);
    for (int d = 0; d < 3; ++d) {
        lo[d] = tri[d] < tri[3 + d] ? tri[d] : tri[3 + d];
        lo[d] = lo[d] < tri[6 + d] ? lo[d] : tri[6 + d];
        hi[d] = tri[d] > tri[3 + d] ? tri[d] : tri[3 + d];
        hi[d] = hi[d] > tri[6 + d] ? hi[d] : tri[6 + d];
    }
}

static void group_tests(const sk_bvh *bvh, const uint32_t *tri_v, const uint32_t *tri_f,
                        const uint32_t *ids, size_t n, group_ctx *G)
{
    visit_ctx *c = G->c;
    double tri[9], lo[3], hi[3], glo[3], ghi[3];
    bool finite = true;
    c->face = tri_f[ids[0]];
    c->group = group_of(c, c->face);
    for (size_t i = 0; i < n; ++i) {
        fan_box(c->surface, tri_v, ids[i], tri, lo, hi);
        for (int d = 0; d < 3; ++d) {
            glo[d] = i == 0 || lo[d] < glo[d] ? lo[d] : glo[d];
            ghi[d] = i == 0 || hi[d] > ghi[d] ? hi[d] : ghi[d];
            finite = finite && isfinite(lo[d]) && isfinite(hi[d]);
        }
    }
    G->n = 0;
    G->memo_group = SK_INVALID;
    if (finite)
        sk__bvh_overlaps(bvh, glo, ghi, gather, G);
    for (size_t i = 0; i < n && !G->nomem; ++i) {
        fan_box(c->surface, tri_v, ids[i], tri, lo, hi);
        c->face = tri_f[ids[i]];
        c->tri = tri;
        if (!finite) {
            sk__bvh_overlaps(bvh, lo, hi, visit, c);
            continue;
        }
        for (size_t k = 0; k < G->n; ++k) {
            const double *t = G->cand[k].corners;
            if (G->cand[k].face <= c->face)
                continue;
            bool apart = false; /* the BVH's own test of a triangle against a box */
            for (int d = 0; d < 3 && !apart; ++d) {
                double l = t[3 + d] < t[6 + d] ? t[3 + d] : t[6 + d];
                double h = t[3 + d] > t[6 + d] ? t[3 + d] : t[6 + d];
                apart = (t[d] < l ? t[d] : l) > hi[d] || (t[d] > h ? t[d] : h) < lo[d];
            }
            if (apart)
                continue;
            ++c->tests;
            if (triangles_cross(tri, t)) {
                uint32_t g = group_of(c, G->cand[k].face);
                uint32_t a = g < c->group ? g : c->group, b = g < c->group ? c->group : g;
                pairs_push(c->out, ((uint64_t)a << 32) | b);
            }
        }
    }
}

/* the fan triangles in group order: group g's are ids[start[g], start[g + 1]) */
static sk_status by_group(const visit_ctx *c, const uint32_t *tri_f, size_t nt, size_t ng,
                          uint32_t **start, uint32_t **ids, sk_error *err)
{
    *start = sk__calloc_array(ng + 2, sizeof **start);
    *ids = sk__malloc_array(nt + 1, sizeof **ids);
    if (!*start || !*ids)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t t = 0; t < nt; ++t)
        (*start)[group_of(c, tri_f[t]) + 2]++;
    for (size_t g = 0; g < ng; ++g)
        (*start)[g + 2] += (*start)[g + 1];
    for (size_t t = 0; t < nt; ++t)
        (*ids)[(*start)[group_of(c, tri_f[t]) + 1]++] = (uint32_t)t;
    return SK_OK;
}

sk_status sk_self_intersections(const sk_soup *surface, const uint32_t *face_group,
                                const sk_soup *groups, sk_intersection_report *rep,
                                sk_error *err)
{
    double t0 = sk_seconds();
    memset(rep, 0, sizeof *rep);
    if (!groups)
        groups = surface;
    sk_bvh *bvh = NULL;
    sk_status st = sk_bvh_build(surface, &bvh, err);
    if (!st)
        st = check_groups(surface, face_group, groups, err);
    uint32_t *tri_v = NULL, *tri_f = NULL;
    size_t nt = 0;
    if (!st)
        st = sk__soup_fan_triangles(surface, &tri_v, &tri_f, &nt, err);
    if (st) {
        sk_bvh_destroy(&bvh);
        return st;
    }
    pairs all = {0};
    bool nomem = false;
    size_t tests = 0;
    size_t ng = face_group ? groups->num_faces : surface->num_faces;
    uint32_t *gstart = NULL, *gids = NULL;
    visit_ctx c0 = {surface, groups, face_group, 0, 0, NULL, NULL, 0};
    if ((st = by_group(&c0, tri_f, nt, ng, &gstart, &gids, err)) != SK_OK)
        nomem = true;
    long ngl = nomem ? 0 : (long)ng;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel reduction(+ : tests) reduction(|| : nomem)
#endif
    {
        pairs mine = {0};
        visit_ctx c = {surface, groups, face_group, 0, 0, NULL, &mine, 0};
        group_ctx G = {.c = &c};
#if defined(SK_HAVE_OPENMP)
#pragma omp for schedule(dynamic, 64)
#endif
        for (long g = 0; g < ngl; ++g)
            if (gstart[g + 1] > gstart[g])
                group_tests(bvh, tri_v, tri_f, gids + gstart[g], gstart[g + 1] - gstart[g], &G);
        tests += c.tests;
        nomem = nomem || mine.nomem || G.nomem;
#if defined(SK_HAVE_OPENMP)
#pragma omp critical
#endif
        {
            for (size_t i = 0; i < mine.n && !nomem; ++i)
                pairs_push(&all, mine.key[i]);
        }
        sk__free(mine.key);
        sk__free(G.cand);
    }
    sk__free(gstart);
    sk__free(gids);
    sk_bvh_destroy(&bvh);
    sk__free(tri_v);
    sk__free(tri_f);
    if (nomem || all.nomem) {
        sk__free(all.key);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    rep->triangle_tests = tests;
    summarize(&all, groups->num_faces, rep, err, &st);
    sk__free(all.key);
    rep->seconds = sk_seconds() - t0;
    return st;
}

/* The triangles of group g (fan ids[0, n)) whose boxes meet box b: their corners (9 each) and
 * boxes (lo xyz, hi xyz) into tri and tbox; returns their number */
static size_t near_box(const sk_soup *surface, const uint32_t *tri_v, const uint32_t *ids,
                       size_t n, const double *b, double *tri, double *tbox)
{
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
        double *t = tri + 9 * m, *lo = tbox + 6 * m, *hi = lo + 3;
        fan_box(surface, tri_v, ids[i], t, lo, hi);
        bool apart = false;
        for (int d = 0; d < 3 && !apart; ++d)
            apart = lo[d] > b[3 + d] || hi[d] < b[d];
        m += !apart;
    }
    return m;
}

/* whether a triangle of group a crosses one of group b: the triangles of each that meet the
 * other's box, tested in pairs with overlapping boxes (the early reject of most pairs: two
 * patches whose control-point boxes touch at a corner) */
static bool pair_crosses(const sk_soup *surface, const uint32_t *tri_v, const uint32_t *gstart,
                         const uint32_t *gids, const double *gbox, uint32_t a, uint32_t b,
                         double *buf, size_t *tests)
{
    size_t na = gstart[a + 1] - gstart[a], nb = gstart[b + 1] - gstart[b];
    double *ta = buf, *ba = ta + 9 * na, *tb = ba + 6 * na, *bb = tb + 9 * nb;
    size_t ma = near_box(surface, tri_v, gids + gstart[a], na, gbox + 6 * (size_t)b, ta, ba);
    if (!ma)
        return false;
    size_t mb = near_box(surface, tri_v, gids + gstart[b], nb, gbox + 6 * (size_t)a, tb, bb);
    for (size_t i = 0; i < ma; ++i)
        for (size_t j = 0; j < mb; ++j) {
            const double *p = ba + 6 * i, *q = bb + 6 * j;
            bool apart = false;
            for (int d = 0; d < 3 && !apart; ++d)
                apart = p[d] > q[3 + d] || q[d] > p[3 + d];
            if (apart)
                continue;
            ++*tests;
            if (triangles_cross(ta + 9 * i, tb + 9 * j))
                return true;
        }
    return false;
}

sk_status sk__self_intersections_pairs(const sk_soup *surface, const uint32_t *face_group,
                                       size_t num_groups, const uint64_t *cand_pairs, size_t npairs,
                                       sk_intersection_report *rep, bool *fallback,
                                       sk_error *err)
{
    double t0 = sk_seconds();
    memset(rep, 0, sizeof *rep);
    *fallback = false;
    uint32_t *tri_v = NULL, *tri_f = NULL, *gstart = NULL, *gids = NULL;
    double *gbox = NULL;
    uint8_t *hit = NULL;
    pairs all = {0};
    size_t nt = 0, tests = 0, ng = num_groups;
    sk_status st = sk__soup_fan_triangles(surface, &tri_v, &tri_f, &nt, err);
    visit_ctx c0 = {surface, NULL, face_group, 0, 0, NULL, NULL, 0};
    if (!st)
        st = by_group(&c0, tri_f, nt, ng, &gstart, &gids, err);
    if (!st && (!(gbox = sk__malloc_array(6 * ng + 1, sizeof *gbox)) ||
                !(hit = sk__calloc_array(npairs + 1, 1))))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t most = 0; /* the most triangles in a group */
    for (size_t g = 0; !st && g < ng; ++g) {
        double tri[9], lo[3], hi[3], *b = gbox + 6 * g;
        size_t n = gstart[g + 1] - gstart[g];
        most = n > most ? n : most;
        for (int d = 0; d < 3; ++d)
            b[d] = INFINITY, b[3 + d] = -INFINITY;
        for (size_t i = 0; i < n; ++i) {
            fan_box(surface, tri_v, gids[gstart[g] + i], tri, lo, hi);
            for (int d = 0; d < 3; ++d) {
                b[d] = lo[d] < b[d] ? lo[d] : b[d];
                b[3 + d] = hi[d] > b[3 + d] ? hi[d] : b[3 + d];
            }
        }
        for (int d = 0; d < 3; ++d)
            if (n && !(isfinite(b[d]) && isfinite(b[3 + d])))
                *fallback = true;
    }
    if (st || *fallback)
        goto done;
    bool nomem = false;
    long npl = (long)npairs;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel reduction(+ : tests) reduction(|| : nomem)
#endif
    {
        double *buf = sk__malloc_array(30 * most + 1, sizeof *buf); /* 2 x (9 + 6) per triangle */
        nomem = !buf;
#if defined(SK_HAVE_OPENMP)
#pragma omp for schedule(dynamic, 256)
#endif
        for (long k = 0; k < npl; ++k)
            if (buf)
                hit[k] = pair_crosses(surface, tri_v, gstart, gids, gbox,
                                      (uint32_t)(cand_pairs[k] >> 32), (uint32_t)cand_pairs[k], buf, &tests);
        sk__free(buf);
    }
    if (nomem) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t k = 0; k < npairs; ++k)
        if (hit[k])
            pairs_push(&all, cand_pairs[k]);
    if (all.nomem) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    rep->triangle_tests = tests;
    summarize(&all, ng, rep, err, &st);
    rep->seconds = sk_seconds() - t0;
done:
    sk__free(all.key);
    sk__free(hit);
    sk__free(gbox);
    sk__free(gstart);
    sk__free(gids);
    sk__free(tri_v);
    sk__free(tri_f);
    return st;
}
