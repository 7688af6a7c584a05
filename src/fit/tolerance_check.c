/* The surface of a cut and its distances to the input both ways (tolerance_internal.h): the
 * VC1 build, its singular patches, and the capped closest-point walks over both BVHs, in
 * parallel chunks (deterministic: each chunk's walks start from no triangle). */
#include "fit/tolerance_internal.h"
#include "surfkit/bezier.h"
#include "analysis/bvh_internal.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Distances
 * ------------------------------------------------------------------------------------------- */

void sk__tol_check_buf_free(check_buf *b)
{
    sk__free(b->fd);
    sk__free(b->vd);
    sk__free(b->sd);
    sk__free(b->sf);
    memset(b, 0, sizeof *b);
}

/* A flag the OpenMP workers share (the search's early stop). */
static int flag_get(const int *f)
{
    int v;
#if defined(SK_HAVE_OPENMP)
#pragma omp atomic read
#endif
    v = *f;
    return v;
}

static void flag_set(int *f)
{
#if defined(SK_HAVE_OPENMP)
#pragma omp atomic write
#endif
    *f = 1;
}

/* The point w a + u b + v c with (u, v) = bary */
static void bary_point(const double bary[2], const double *a, const double *b, const double *c,
                       double p[3])
{
    double u = bary[0], v = bary[1], w = 1 - u - v;
    for (int q = 0; q < 3; ++q)
        p[q] = w * a[q] + u * b[q] + v * c[q];
}

/* What the distance walks of one check share. Each chunk of CHUNK consecutive items starts its
 * walks from no triangle and carries the triangle found from one sample to the next. */
enum { CHUNK = 1024 };

typedef struct walk {
    const tol_ctx *c;
    const sk_bvh *bs;      /* the surface's tessellation */
    const sk_soup *ts;     /* ... and its soup */
    const uint8_t *alive;
    check_buf *b;
    int *stop;             /* the search: set at the first face beyond T, then the rest skipped */
} walk;

typedef void (*chunk_fn)(const walk *w, size_t begin, size_t end);

/* fn over [0, n) in chunks, in parallel */
static void for_chunks(const walk *w, size_t n, chunk_fn fn)
{
    ptrdiff_t chunks = (ptrdiff_t)((n + CHUNK - 1) / CHUNK);
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 1)
#endif
    for (ptrdiff_t k = 0; k < chunks; ++k) {
        size_t begin = (size_t)k * CHUNK, end = begin + CHUNK < n ? begin + CHUNK : n;
        fn(w, begin, end);
    }
}

/* The mesh side, per fine face: b->fd, its samples' largest distance to the surface. Distances
 * within T are only bounded (sk__bvh_distance_capped at T: a walk that stops at the first
 * triangle within T); those beyond T are exact. */
static void mesh_faces(const walk *w, size_t begin, size_t end)
{
    const tol_ctx *c = w->c;
    const size_t nn = (size_t)c->n * (size_t)c->n;
    const double *P = c->fine->positions;
    uint32_t hint = SK_INVALID;
    for (size_t f = begin; f < end; ++f) {
        w->b->fd[f] = 0;
        if (w->stop && flag_get(w->stop))
            continue;
        const uint32_t *t = c->tri + 3 * f;
        double worst = 0, p[3];
        for (size_t k = 0; k < nn; ++k) {
            bary_point(c->bary[k], P + 3 * (size_t)t[0], P + 3 * (size_t)t[1],
                       P + 3 * (size_t)t[2], p);
            worst = fmax(worst, sk__bvh_distance_capped(w->bs, p, c->tol, &hint, NULL));
        }
        w->b->fd[f] = worst;
        if (w->stop && worst > c->tol)
            flag_set(w->stop);
    }
}

/* The mesh side, per fine vertex: b->vd (0 for the alive ones: the surface interpolates them) */
static void mesh_vertices(const walk *w, size_t begin, size_t end)
{
    const double *P = w->c->fine->positions;
    uint32_t hint = SK_INVALID;
    for (size_t v = begin; v < end; ++v) {
        w->b->vd[v] = 0;
        if (!w->alive[v] && !(w->stop && flag_get(w->stop)))
            w->b->vd[v] = sk__bvh_distance_capped(w->bs, P + 3 * v, w->c->tol, &hint, NULL);
    }
}

/* The surface side: b->sd per tessellation vertex, then per tessellation face (the largest
 * distance of its samples to the mesh, bounded within T, exact beyond) and b->sf, the fine face
 * nearest to the worst of them. */
static void surface_samples(const walk *w, size_t begin, size_t end)
{
    const tol_ctx *c = w->c;
    const sk_soup *ts = w->ts;
    const size_t nn = (size_t)c->n * (size_t)c->n, ntv = ts->num_vertices;
    const double *Q = ts->positions;
    uint32_t hint = SK_INVALID;
    for (size_t g = begin; g < end; ++g) {
        double worst = -1;
        uint32_t wf = SK_INVALID, face = SK_INVALID;
        if (g < ntv) {
            worst = sk__bvh_distance_capped(c->mesh_bvh, Q + 3 * g, c->tol, &hint, &wf);
        } else {
            const uint32_t *t = ts->face_indices + ts->face_offsets[g - ntv];
            size_t deg = ts->face_offsets[g - ntv + 1] - ts->face_offsets[g - ntv];
            for (size_t fan = 1; fan + 1 < deg; ++fan)
                for (size_t k = 0; k < nn; ++k) {
                    double p[3];
                    bary_point(c->bary[k], Q + 3 * (size_t)t[0], Q + 3 * (size_t)t[fan],
                               Q + 3 * (size_t)t[fan + 1], p);
                    double d = sk__bvh_distance_capped(c->mesh_bvh, p, c->tol, &hint, &face);
                    if (d > worst) {
                        worst = d;
                        wf = face;
                    }
                }
        }
        w->b->sd[g] = worst;
        w->b->sf[g] = wf;
    }
}

/* Distances both ways between a surface's triangles ts and the fine mesh (mesh_faces,
 * mesh_vertices, surface_samples: exact beyond T, bounded within it). With bad, the fine vertices where the tolerance is exceeded
 * (their own distance, or a face of theirs) are collected into bad (a flag per fine vertex);
 * without (the search), the check stops at the first sample of the mesh side beyond T.
 * *max_out: the largest distance found (exact when beyond T). */
static sk_status check_soup(tol_ctx *c, const sk_soup *ts, const uint8_t *alive, check_buf *b,
                            uint8_t *bad, double *max_out, sk_error *err)
{
    sk_bvh *bs = NULL;
    sk_status st = sk_bvh_build(ts, &bs, err);
    if (st)
        goto done;
    size_t need = ts->num_faces + ts->num_vertices;
    if (need > b->cap_s) {
        sk__free(b->sd);
        sk__free(b->sf);
        b->sd = sk__malloc_array(need, sizeof *b->sd);
        b->sf = sk__malloc_array(need, sizeof *b->sf);
        b->cap_s = need;
        if (!b->sd || !b->sf) {
            b->cap_s = 0;
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
    }
    int stop = 0;
    walk w = {c, bs, ts, alive, b, bad ? NULL : &stop};
    for_chunks(&w, c->nf, mesh_faces);
    for_chunks(&w, c->nv, mesh_vertices);
    double mx = 0;
    for (size_t f = 0; f < c->nf; ++f) {
        mx = fmax(mx, b->fd[f]);
        if (bad && b->fd[f] > c->tol)
            for (int q = 0; q < 3; ++q)
                bad[c->tri[3 * f + q]] = 1;
    }
    for (size_t v = 0; v < c->nv; ++v) {
        mx = fmax(mx, b->vd[v]);
        if (bad && b->vd[v] > c->tol)
            bad[v] = 1;
    }
    if (!bad && mx > c->tol) { /* the search needs no more: the mesh side already misses T */
        *max_out = mx;
        goto done;
    }
    for_chunks(&w, need, surface_samples);
    for (size_t g = 0; g < need; ++g) {
        mx = fmax(mx, b->sd[g]);
        if (bad && b->sd[g] > c->tol && b->sf[g] < c->nf)
            for (int q = 0; q < 3; ++q)
                bad[c->tri[3 * (size_t)b->sf[g] + q]] = 1;
    }
    *max_out = mx;
done:
    sk_bvh_destroy(&bs);
    return st;
}

/* check_soup of the surface's tessellation */
static sk_status check(tol_ctx *c, const sk_smooth *s, const uint8_t *alive, check_buf *b,
                       uint8_t *bad, double *max_out, sk_error *err)
{
    sk_soup *ts = NULL;
    sk_status st = sk_patch_set_tessellate(&s->surface, c->tess, &ts, err);
    if (!st)
        st = check_soup(c, ts, alive, b, bad, max_out, err);
    sk_soup_destroy(&ts);
    return st;
}

sk_status sk__tol_check_linear(tol_ctx *c, uint8_t *alive, check_buf *b, double *max_out,
                               sk_error *err)
{
    sk_mesh *m = NULL;
    sk_soup *ts = NULL;
    uint32_t *m2f = sk__malloc_array(c->nv, sizeof *m2f);
    sk_status st = m2f ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (!st)
        st = sk__tol_build_cut(c, alive, &m, m2f, err);
    if (!st)
        st = sk_mesh_to_soup(m, &ts, err);
    if (!st)
        st = check_soup(c, ts, alive, b, NULL, max_out, err);
    sk_soup_destroy(&ts);
    sk_mesh_destroy(&m);
    sk__free(m2f);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * One surface of a cut
 * ------------------------------------------------------------------------------------------- */

void sk__tol_cut_result_free(cut_result *r)
{
    sk_smooth_destroy(&r->s);
    sk__free(r->m2f);
    memset(r, 0, sizeof *r);
    r->max = INFINITY;
}

void sk__tol_record_try(sk_tolerance_stats *stats, size_t level, bool refined, sk_status status,
                       size_t vertices, const cut_result *r)
{
    if (stats->num_tried < SK_TOLERANCE_MAX_TRIED) {
        sk_tolerance_try *t = &stats->tried[stats->num_tried];
        t->level = (uint32_t)level;
        t->refined = refined;
        t->status = status;
        t->vertices = vertices;
        t->patches = status ? 0 : r->patches;
        t->max_deviation = status ? NAN : r->max;
        t->singular = status ? 0 : r->singular;
        t->met = !status && r->met;
    }
    stats->num_tried++;
}

/* Builds and measures the surface of the cut alive (parity fixed first). A VC1 failure
 * (SK_ERR_NUMERIC, SK_ERR_TOPOLOGY) is returned as *vc1_status with SK_OK; other errors (memory,
 * cancel) are returned. */
sk_status sk__tol_build_surface(tol_ctx *c, uint8_t *alive, check_buf *b, uint8_t *bad,
                               cut_result *r, sk_status *vc1_status, size_t *vertices,
                               sk_tolerance_stats *stats, sk_error *err)
{
    sk__tol_cut_result_free(r);
    *vc1_status = SK_OK;
    stats->parity_splits += sk__tol_fix_parity(c, alive);
    sk_mesh *m = NULL;
    r->m2f = sk__malloc_array(c->nv, sizeof *r->m2f);
    if (!r->m2f)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    sk_status st = sk__tol_build_cut(c, alive, &m, r->m2f, err);
    if (st)
        return st;
    *vertices = m->num_vertices;
    double t0 = sk_seconds();
    sk_error e = {0};
    st = sk_smooth_build(m, &c->so, &r->s, &e);
    sk_mesh_destroy(&m);
    double t1 = sk_seconds();
    stats->seconds_vc1 += t1 - t0;
    if (st == SK_ERR_NUMERIC || st == SK_ERR_TOPOLOGY) {
        *vc1_status = st;
        memcpy(c->last_msg, e.message, sizeof c->last_msg);
        c->last_fail = st;
        sk_smooth_destroy(&r->s);
        return SK_OK;
    }
    if (st)
        return sk__fail(err, st, "%s", e.message);
    r->patches = r->s->surface.count;
    /* singular patches: the surface has no tangent plane there; refine around them */
    sk_patch_shape *shape = sk__malloc_array(r->patches ? r->patches : 1, sizeof *shape);
    if (!shape)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    st = sk_smooth_patch_shapes(r->s, 8, shape, err);
    size_t built = r->s->config->num_vertices - r->s->stats.split_edges;
    for (size_t p = 0; !st && p < r->patches; ++p) {
        if (!shape[p].singular)
            continue;
        r->singular++;
        const sk_patch *pa = &r->s->surface.patches[p];
        int nc = pa->kind == SK_PATCH_TENSOR ? 4 : 3;
        for (int q = 0; bad && q < nc; ++q) {
            uint32_t id = pa->corner_ids[q];
            if (id >= built)
                continue;
            uint32_t v = r->m2f[id];
            bad[v] = 1;
            for (uint32_t k = c->ring_off[v]; k < c->ring_off[v + 1]; ++k)
                bad[c->ring[k]] = 1;
        }
    }
    sk__free(shape);
    if (!st)
        st = check(c, r->s, alive, b, bad, &r->max, err);
    stats->seconds_check += sk_seconds() - t1;
    r->met = !st && r->max <= c->tol;
    return st;
}
