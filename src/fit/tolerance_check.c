/* The surface of a cut and its distances to the input both ways (tolerance_internal.h): the
 * VC1 build, its singular patches, and the capped closest-point walks over both BVHs, in
 * parallel chunks (deterministic: each chunk's walks start from no triangle). */
#include "fit/tolerance_internal.h"
#include "surfkit/bezier.h"
#include "analysis/bvh_internal.h"
#include "smooth/smooth_internal.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Distances
 * ------------------------------------------------------------------------------------------- */

void sk__tol_check_buf_free(check_buf *b)
{
    sk__free(b->fw);
    sk__free(b->vw);
    sk__tol_prev_free(&b->prev);
    sk__free(b->fd);
    sk__free(b->vd);
    sk__free(b->fh);
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
    /* the refinement's incremental checks (NULL otherwise): */
    const uint32_t *face_patch; /* soup face -> patch: record the witnesses b->fw, b->vw */
    const uint32_t *prev2new;   /* last round's patch -> the new patch over its corners (NULL:
                                   no last round) */
    const double *moved;        /* per last round's patch: how far it moved at most */
    const size_t *pf, *goff;    /* per patch: its soup faces, its groups in b->sd */
    const uint32_t *keep;       /* per patch: the identical last round's patch (or SK_INVALID) */
    size_t patches;
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

/* The witness of a sample within T for the incremental checks: the patch of the surface
 * triangle found (SK_INVALID beyond T). */
static uint32_t witness(const walk *w, double d, uint32_t face)
{
    return d <= w->c->tol && face != SK_INVALID ? w->face_patch[face] : SK_INVALID;
}

/* The last round's witnesses of nw samples all in patches that are still there, moved by at most
 * m with m + d <= T (d: the samples' bound within T): true, *d raised by m (the bound on the
 * distance to the witness triangle where it is now) and the witnesses renumbered. */
static bool witnesses_stay(const walk *w, uint32_t *wit, size_t nw, double *d)
{
    if (!w->prev2new)
        return false;
    double m = 0;
    for (size_t k = 0; k < nw; ++k) {
        if (wit[k] == SK_INVALID || w->prev2new[wit[k]] == SK_INVALID)
            return false;
        m = fmax(m, w->moved[wit[k]]);
    }
    if (!(*d + m <= w->c->tol))
        return false;
    *d += m;
    for (size_t k = 0; k < nw; ++k)
        wit[k] = w->prev2new[wit[k]];
    return true;
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
        uint32_t *wit = w->face_patch ? w->b->fw + nn * f : NULL;
        w->b->fh[f] = SK_INVALID;
        if (wit && witnesses_stay(w, wit, nn, &w->b->fd[f]))
            continue;
        w->b->fd[f] = 0;
        if (w->stop && flag_get(w->stop))
            continue;
        const uint32_t *t = c->tri + 3 * f;
        double worst = 0, p[3];
        for (size_t k = 0; k < nn; ++k) {
            uint32_t face = SK_INVALID;
            bary_point(c->bary[k], P + 3 * (size_t)t[0], P + 3 * (size_t)t[1],
                       P + 3 * (size_t)t[2], p);
            double d = sk__bvh_distance_capped(w->bs, p, c->tol, &hint, &face);
            worst = fmax(worst, d);
            if (wit)
                wit[k] = witness(w, d, face);
        }
        w->b->fd[f] = worst;
        w->b->fh[f] = hint;
        if (w->stop && worst > c->tol)
            flag_set(w->stop);
    }
}

/* the triangle a walk of one of v's faces ended on in this check (else SK_INVALID): a nearer
 * first guess than the vertex before (the input's vertex order need not follow its faces') */
static uint32_t face_hint(const walk *w, uint32_t v)
{
    const sk_mesh *m = w->c->fine;
    uint32_t h = m->v_halfedge[v];
    if (h == SK_INVALID)
        return SK_INVALID;
    uint32_t f = m->h_face[h] != SK_INVALID ? m->h_face[h] : m->h_face[h ^ 1u];
    return f != SK_INVALID ? w->b->fh[f] : SK_INVALID;
}

/* The mesh side, per fine vertex: b->vd (0 for the alive ones: the surface interpolates them) */
static void mesh_vertices(const walk *w, size_t begin, size_t end)
{
    const double *P = w->c->fine->positions;
    uint32_t hint = SK_INVALID;
    for (size_t v = begin; v < end; ++v) {
        uint32_t *wit = w->face_patch ? w->b->vw + v : NULL;
        if (w->alive[v]) {
            w->b->vd[v] = 0;
            if (wit)
                *wit = SK_INVALID; /* when it is dead again (a finer base): measured */
            continue;
        }
        if (wit && witnesses_stay(w, wit, 1, &w->b->vd[v]))
            continue;
        w->b->vd[v] = 0;
        if (w->stop && flag_get(w->stop))
            continue;
        uint32_t face = SK_INVALID, fh = face_hint(w, (uint32_t)v);
        if (fh != SK_INVALID)
            hint = fh;
        w->b->vd[v] = sk__bvh_distance_capped(w->bs, P + 3 * v, w->c->tol, &hint, &face);
        if (wit)
            *wit = witness(w, w->b->vd[v], face);
    }
}

/* The largest distance to the mesh of the samples of the surface's face t (deg corners, a fan),
 * and in *wf the fine face nearest to the worst */
static double face_worst(const tol_ctx *c, const double *Q, const uint32_t *t, size_t deg,
                         uint32_t *hint, uint32_t *wf)
{
    const size_t nn = (size_t)c->n * (size_t)c->n;
    double worst = -1;
    uint32_t face = SK_INVALID;
    for (size_t fan = 1; fan + 1 < deg; ++fan)
        for (size_t k = 0; k < nn; ++k) {
            double p[3];
            bary_point(c->bary[k], Q + 3 * (size_t)t[0], Q + 3 * (size_t)t[fan],
                       Q + 3 * (size_t)t[fan + 1], p);
            double d = sk__bvh_distance_capped(c->mesh_bvh, p, c->tol, hint, &face);
            if (d > worst) {
                worst = d;
                *wf = face;
            }
        }
    return worst;
}

/* The surface side (the search: up to the first sample beyond T): b->sd per tessellation vertex, then per tessellation face (the largest
 * distance of its samples to the mesh, bounded within T, exact beyond) and b->sf, the fine face
 * nearest to the worst of them. */
static void surface_samples(const walk *w, size_t begin, size_t end)
{
    const tol_ctx *c = w->c;
    const sk_soup *ts = w->ts;
    const size_t ntv = ts->num_vertices;
    const double *Q = ts->positions;
    uint32_t hint = SK_INVALID;
    for (size_t g = begin; g < end; ++g) {
        double worst = -1;
        uint32_t wf = SK_INVALID;
        if (w->stop && flag_get(w->stop)) {
            /* the search: this surface already misses T */
        } else if (g < ntv) {
            worst = sk__bvh_distance_capped(c->mesh_bvh, Q + 3 * g, c->tol, &hint, &wf);
        } else {
            const uint32_t *t = ts->face_indices + ts->face_offsets[g - ntv];
            size_t deg = ts->face_offsets[g - ntv + 1] - ts->face_offsets[g - ntv];
            worst = face_worst(c, Q, t, deg, &hint, &wf);
        }
        w->b->sd[g] = worst;
        w->b->sf[g] = wf;
        if (w->stop && worst > c->tol)
            flag_set(w->stop);
    }
}

/* The incremental check's surface side, per patch: its groups in b->sd, b->sf (its grid
 * vertices in the order its faces first use them, then its tessellation faces, as
 * surface_samples). A patch over the same corners as one of the last round's, moved by at most m,
 * keeps the bound d of a group with d + m <= T as d + m (its points moved by at most m); the
 * others are measured. */
enum { INCR_MAX_TESS = 8 }; /* tolerance.c: incremental only up to tessellation 8 */

static void patch_groups(const walk *w, size_t begin, size_t end)
{
    const tol_ctx *c = w->c;
    const sk_soup *ts = w->ts;
    const tol_prev *pv = &w->b->prev;
    const double *Q = ts->positions;
    uint32_t ids[(INCR_MAX_TESS + 1) * (INCR_MAX_TESS + 1)], hint = SK_INVALID;
    for (size_t p = begin; p < end; ++p) {
        size_t g = w->goff[p], ng = w->goff[p + 1] - g, f0 = w->pf[p], f1 = w->pf[p + 1];
        size_t nvert = ng - (f1 - f0), u = 0;
        uint32_t q = w->keep[p];
        if (q != SK_INVALID && pv->goff[q + 1] - pv->goff[q] != ng)
            q = SK_INVALID;
        for (size_t f = f0; f < f1; ++f)
            for (uint32_t k = ts->face_offsets[f]; k < ts->face_offsets[f + 1]; ++k) {
                uint32_t id = ts->face_indices[k];
                size_t i = 0;
                while (i < u && ids[i] != id)
                    ++i;
                if (i == u && u < nvert)
                    ids[u++] = id;
            }
        for (size_t k = 0; k < ng; ++k, ++g) {
            double m = q != SK_INVALID ? w->moved[q] : INFINITY;
            double old = q != SK_INVALID ? pv->sd[pv->goff[q] + k] : INFINITY;
            if (k < nvert && k >= u) { /* no such vertex (a degenerate patch) */
                w->b->sd[g] = -1;
                w->b->sf[g] = SK_INVALID;
            } else if (old + m <= c->tol) {
                w->b->sd[g] = old < 0 ? old : old + m;
                w->b->sf[g] = pv->sf[pv->goff[q] + k];
            } else if (k < nvert) {
                w->b->sf[g] = SK_INVALID;
                w->b->sd[g] = sk__bvh_distance_capped(c->mesh_bvh, Q + 3 * (size_t)ids[k], c->tol,
                                                      &hint, &w->b->sf[g]);
            } else {
                size_t f = f0 + (k - nvert);
                w->b->sf[g] = SK_INVALID;
                w->b->sd[g] = face_worst(c, Q, ts->face_indices + ts->face_offsets[f],
                                         ts->face_offsets[f + 1] - ts->face_offsets[f], &hint,
                                         &w->b->sf[g]);
            }
        }
    }
}

/* room for n surface sample groups in b->sd, b->sf */
static sk_status reserve_groups(check_buf *b, size_t n, sk_error *err)
{
    if (n <= b->cap_s)
        return SK_OK;
    sk__free(b->sd);
    sk__free(b->sf);
    b->sd = sk__malloc_array(n ? n : 1, sizeof *b->sd);
    b->sf = sk__malloc_array(n ? n : 1, sizeof *b->sf);
    b->cap_s = n;
    if (b->sd && b->sf)
        return SK_OK;
    b->cap_s = 0;
    return sk__fail(err, SK_ERR_NOMEM, "out of memory");
}

/* The mesh side's largest distance; with bad, the fine vertices beyond T (their own distance or
 * a face of theirs) flagged */
static double mesh_side_max(const tol_ctx *c, const check_buf *b, uint8_t *bad)
{
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
    return mx;
}

/* Distances both ways between a surface's triangles ts and the fine mesh (mesh_faces,
 * mesh_vertices, surface_samples: exact beyond T, bounded within it). With bad, the fine
 * vertices where the tolerance is exceeded (their own distance, or a face of theirs, or the
 * input face nearest to a surface sample beyond T) are collected into bad (a flag per fine
 * vertex); without (the search), the check stops at the first sample beyond T (mesh side first).
 * inc (the refinement's incremental check, else NULL: w's fields from face_patch on) sets the
 * surface side in groups per patch. *max_out: the largest distance found (exact when beyond T). */
static sk_status check_soup(tol_ctx *c, const sk_soup *ts, const uint8_t *alive, check_buf *b,
                            uint8_t *bad, const walk *inc, double *max_out, sk_error *err)
{
    sk_bvh *bs = NULL;
    size_t need = inc ? inc->goff[inc->patches] : ts->num_faces + ts->num_vertices;
    sk_status st = sk_bvh_build(ts, &bs, err);
    if (st)
        goto done;
    int stop = 0;
    walk w = {c, bs, ts, alive, b, bad ? NULL : &stop, NULL, NULL, NULL, NULL, NULL, NULL, 0};
    if (inc) {
        w = *inc;
        w.bs = bs;
    }
    if ((st = reserve_groups(b, need, err)))
        goto done;
    for_chunks(&w, c->nf, mesh_faces);
    for_chunks(&w, c->nv, mesh_vertices);
    double mx = mesh_side_max(c, b, bad);
    if (!bad && mx > c->tol) { /* the search needs no more: the mesh side already misses T */
        *max_out = mx;
        goto done;
    }
    for_chunks(&w, inc ? inc->patches : need, inc ? patch_groups : surface_samples);
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

/* The incremental check's layout of the surface side: per patch its soup faces (pf) and its
 * groups (goff: the grid vertices, then the faces), soup face -> patch; false when the
 * tessellation is not laid out patch by patch as expected (then a full check). */
static bool patch_layout(const sk_patch_set *set, unsigned n, const sk_soup *ts, size_t *pf,
                         size_t *goff, uint32_t *face_patch)
{
    pf[0] = goff[0] = 0;
    for (size_t p = 0; p < set->count; ++p) {
        bool quad = set->patches[p].kind == SK_PATCH_TENSOR;
        size_t nf = quad ? 2 * (size_t)n * n : (size_t)n * n;
        size_t nv = quad ? (size_t)(n + 1) * (n + 1) : (size_t)(n + 1) * (n + 2) / 2;
        pf[p + 1] = pf[p] + nf;
        goff[p + 1] = goff[p] + nv + nf;
        if (pf[p + 1] > ts->num_faces)
            return false;
        for (size_t f = pf[p]; f < pf[p + 1]; ++f)
            face_patch[f] = (uint32_t)p;
    }
    return pf[set->count] == ts->num_faces;
}

/* This round's surface side becomes the last round's (b->sd, b->sf and goff handed over) */
static sk_status remember(tol_ctx *c, const sk_smooth *s, const uint32_t *m2f, check_buf *b,
                          size_t **goff, sk_error *err)
{
    double *sd = b->sd;
    uint32_t *sf = b->sf;
    size_t cap = b->cap_s;
    b->sd = b->prev.sd;
    b->sf = b->prev.sf;
    b->cap_s = b->prev.cap_s;
    b->prev.sd = sd;
    b->prev.sf = sf;
    b->prev.cap_s = cap;
    sk__free(b->prev.goff);
    b->prev.goff = *goff;
    *goff = NULL;
    return sk__tol_remember(s, m2f, c->nv, &b->prev, err);
}

/* a paired patch counted as moved far (sk_tolerance_try.moved_far): by this share of T */
#define FAR_MOVE 0.1

/* The refinement's check of a surface, reusing what stayed from the last round: the patches
 * the VC1 build gave bit for bit again keep their surface side, and the input samples whose
 * triangle within T lies in such a patch keep their bound. What it flags in bad and whether it
 * is within T are those of the full check (a distance beyond T is always measured again, and a
 * bound within T stays one while its triangle is there), up to the rounding of tessellation
 * vertices shared with a changed patch; only the bounds within T may differ. *done: false when
 * the tessellation's layout is not the expected one (nothing checked). */
static sk_status check_incremental(tol_ctx *c, const sk_smooth *s, const uint32_t *m2f,
                                   const sk_soup *ts, const uint8_t *alive, check_buf *b,
                                   uint8_t *bad, double *max_out, bool *done, sk_error *err)
{
    const sk_patch_set *set = &s->surface;
    size_t np = set->count, nn = (size_t)c->n * (size_t)c->n, kept = 0;
    size_t *pf = sk__malloc_array(np + 1, sizeof *pf), *goff = sk__malloc_array(np + 1, sizeof *goff);
    uint32_t *face_patch = sk__malloc_array(ts->num_faces ? ts->num_faces : 1, sizeof *face_patch);
    uint32_t *keep = sk__malloc_array(np ? np : 1, sizeof *keep);
    uint32_t *prev2new = sk__malloc_array(b->prev.count ? b->prev.count : 1, sizeof *prev2new);
    double *moved = sk__malloc_array(b->prev.count ? b->prev.count : 1, sizeof *moved);
    if (!b->fw) {
        b->fw = sk__malloc_array(nn * c->nf, sizeof *b->fw);
        b->vw = sk__malloc_array(c->nv, sizeof *b->vw);
        b->prev.valid = false;
    }
    sk_status st = SK_OK;
    *done = false;
    if (!pf || !goff || !face_patch || !keep || !prev2new || !moved || !b->fw || !b->vw) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto out;
    }
    if (!patch_layout(set, c->tess, ts, pf, goff, face_patch))
        goto out;
    sk__tol_match(s, m2f, &b->prev, keep, prev2new, moved, &kept);
    walk w = {c, NULL, ts, alive, b, NULL, face_patch, b->prev.valid ? prev2new : NULL, moved,
              pf, goff, keep, np};
    if ((st = check_soup(c, ts, alive, b, bad, &w, max_out, err)))
        goto out;
    b->reused_patches = kept;
    b->checked_patches = np;
    b->unmoved_patches = b->far_patches = 0;
    for (size_t q = 0; b->prev.valid && q < b->prev.count; ++q)
        if (prev2new[q] != SK_INVALID) {
            b->unmoved_patches += moved[q] == 0;
            b->far_patches += moved[q] >= FAR_MOVE * c->tol;
        }
    if ((st = remember(c, s, m2f, b, &goff, err)))
        goto out;
    *done = true;
out:
    sk__free(pf);
    sk__free(goff);
    sk__free(face_patch);
    sk__free(keep);
    sk__free(prev2new);
    sk__free(moved);
    return st;
}

/* check_soup of the surface's tessellation (incremental in the refinement rounds) */
static sk_status check(tol_ctx *c, const sk_smooth *s, const uint32_t *m2f, const uint8_t *alive,
                       check_buf *b, uint8_t *bad, double *max_out, sk_error *err)
{
    sk_soup *ts = NULL;
    bool done = false;
    sk_status st = sk_patch_set_tessellate(&s->surface, c->tess, &ts, err);
    b->reused_patches = b->checked_patches = b->unmoved_patches = b->far_patches = 0;
    if (!st && bad && c->incremental)
        st = check_incremental(c, s, m2f, ts, alive, b, bad, max_out, &done, err);
    if (!st && !done) {
        b->prev.valid = false; /* b->fd and the witnesses no longer agree */
        st = check_soup(c, ts, alive, b, bad, NULL, max_out, err);
    }
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
        st = check_soup(c, ts, alive, b, NULL, NULL, max_out, err);
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

/* out[p] := whether patch p is singular, the test of sk_smooth_patch_shapes (its overshoot and
 * fairness are not needed here) */
static void singular_patches(const sk_smooth *s, uint8_t *out)
{
    ptrdiff_t np = (ptrdiff_t)s->surface.count;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 256)
#endif
    for (ptrdiff_t p = 0; p < np; ++p)
        out[p] = sk__patch_singular(s, (size_t)p, NULL);
}

/* Builds and measures the surface of the cut alive (parity fixed first). A VC1 failure
 * (SK_ERR_NUMERIC, SK_ERR_TOPOLOGY) is returned as *vc1_status with SK_OK; other errors (memory,
 * cancel) are returned. */
/* The cut's ids of the fine vertex pairs hint (pairs not both in the cut dropped): a new array
 * (NULL when out of memory), *n the pairs kept */
static uint32_t *hint_to_cut(const tol_ctx *c, const tol_hint *h, size_t *n)
{
    uint32_t *out = sk__malloc_array(2 * h->n + 1, sizeof *out);
    *n = 0;
    for (size_t k = 0; out && k < h->n; ++k) {
        uint32_t a = c->f2m[h->pairs[2 * k]], b = c->f2m[h->pairs[2 * k + 1]];
        if (a == SK_INVALID || b == SK_INVALID)
            continue;
        out[2 * *n] = a;
        out[2 * *n + 1] = b;
        ++*n;
    }
    return out;
}

/* h := the deleted edges of s as fine vertex pairs (those with a vertex the VC1 build added
 * left out) */
static sk_status hint_from_surface(const sk_smooth *s, const uint32_t *m2f, tol_hint *h,
                                   sk_error *err)
{
    size_t built = s->config->num_vertices - s->stats.split_edges;
    if (s->num_deleted > h->cap) {
        sk__free(h->pairs);
        h->pairs = sk__malloc_array(2 * s->num_deleted, sizeof *h->pairs);
        h->cap = h->pairs ? s->num_deleted : 0;
        if (!h->pairs) {
            h->n = 0;
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
        }
    }
    h->n = 0;
    for (size_t k = 0; k < s->num_deleted; ++k) {
        uint32_t a = s->deleted[2 * k], b = s->deleted[2 * k + 1];
        if (a >= built || b >= built)
            continue;
        h->pairs[2 * h->n] = m2f[a];
        h->pairs[2 * h->n + 1] = m2f[b];
        ++h->n;
    }
    return SK_OK;
}

sk_status sk__tol_build_surface(tol_ctx *c, uint8_t *alive, check_buf *b, uint8_t *bad,
                               tol_hint *hint, cut_result *r, sk_status *vc1_status,
                               size_t *vertices, sk_tolerance_stats *stats, sk_error *err)
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
    size_t nh = 0;
    uint32_t *h = hint && hint->n ? hint_to_cut(c, hint, &nh) : NULL;
    if (hint && hint->n && !h) {
        sk_mesh_destroy(&m);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    st = sk__smooth_build_hinted(m, &c->so, h, nh, &r->s, &e);
    sk__free(h);
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
    if (hint && (st = hint_from_surface(r->s, r->m2f, hint, err)))
        return st;
    r->patches = r->s->surface.count;
    /* singular patches: the surface has no tangent plane there; refine around them */
    uint8_t *singular = sk__malloc_array(r->patches ? r->patches : 1, 1);
    if (!singular)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    singular_patches(r->s, singular);
    size_t built = r->s->config->num_vertices - r->s->stats.split_edges;
    for (size_t p = 0; p < r->patches; ++p) {
        if (!singular[p])
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
    sk__free(singular);
    if (!st)
        st = check(c, r->s, r->m2f, alive, b, bad, &r->max, err);
    stats->seconds_check += sk_seconds() - t1;
    stats->checked_patches += b->checked_patches;
    stats->reused_patches += b->reused_patches;
    r->met = !st && r->max <= c->tol;
    return st;
}
