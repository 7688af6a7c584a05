/* VC1 surfaces within a tolerance over coarse levels of the progressive mesh (tolerance.h).
 *
 * Every surface is built over a "cut" of the hierarchy: the coarsest mesh with a set of the
 * vertex splits applied, in the order the hierarchy applies them (levels upwards, within a level
 * in reverse record order). A vertex is "alive" when its split is applied; a split needs its w0,
 * first and last alive, so wanting a vertex wants those first (the dependency closure). Level j
 * is the cut of every vertex born at level j or below. The local refinement wants the vertices
 * of the input faces that are out of tolerance (on either side), rebuilds the cut from scratch
 * (so the order stays that of the hierarchy) and builds its VC1 surface again.
 *
 * A closed component needs an even vertex count for the edge deletion; a cut with an odd count
 * gets one more split there (one whose dependencies are alive). */
#include "surfkit/tolerance.h"
#include "surfkit/analysis.h"
#include "surfkit/bezier.h"
#include "surfkit/deviation.h"
#include "surfkit/hierarchy.h"
#include "hierarchy/hierarchy_internal.h"
#include "analysis/bvh_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_FAILED_ROUNDS = 3 };

typedef struct tol_ctx {
    const sk_mesh *fine;
    size_t nv, nf;
    const uint32_t *tri;       /* 3 per fine face (compact triangle mesh) */
    double *normals;           /* fine normals, 3 per vertex */
    sk_hierarchy *hier;
    size_t levels;
    uint32_t *birth;           /* level at which each fine vertex appears (0 = coarsest) */
    sk_vertex_split *rec;      /* per fine vertex born above 0: its split, ids in fine numbering */
    uint32_t *order;           /* fine vertices born above 0, in application order */
    size_t num_order;
    uint32_t *coarse_fine;     /* coarsest vertex -> fine vertex */
    uint32_t *comp;            /* fine vertex -> component */
    uint8_t *comp_closed;      /* per component */
    size_t num_comps;
    uint32_t *ring_off, *ring; /* fine one-rings (neighbours) */
    uint32_t *f2m;             /* scratch: fine -> mixed vertex */
    size_t *comp_count;        /* scratch per component */
    sk_bvh *mesh_bvh;
    double tol;
    int n;                     /* face samples per edge */
    double bary[64 * 64][2];
    unsigned tess;
    sk_smooth_opts so;
    sk_status last_fail;       /* the last VC1 failure and its message */
    char last_msg[SK_ERROR_MESSAGE_SIZE];
} tol_ctx;

/* ---------------------------------------------------------------------------------------------
 * Hierarchy in fine numbering
 * ------------------------------------------------------------------------------------------- */

static sk_status index_hierarchy(tol_ctx *c, sk_error *err)
{
    size_t L = c->levels, nv = c->nv;
    sk_status st = SK_OK;
    uint32_t *cur = sk__malloc_array(nv, sizeof *cur), *prev = sk__malloc_array(nv, sizeof *prev);
    size_t *off = sk__calloc_array(L + 1, sizeof *off);
    c->birth = sk__calloc_array(nv, sizeof *c->birth);
    c->rec = sk__calloc_array(nv, sizeof *c->rec);
    c->order = sk__malloc_array(nv + 1, sizeof *c->order);
    if (!cur || !prev || !off || !c->birth || !c->rec || !c->order) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t j = 0; j + 1 < L; ++j) {
        size_t ns = 0;
        sk_hierarchy_splits(c->hier, j, &ns);
        off[j + 1] = off[j] + ns;
    }
    c->num_order = off[L > 0 ? L - 1 : 0];
    for (size_t v = 0; v < nv; ++v)
        cur[v] = (uint32_t)v;
    for (size_t j = L - 1; j-- > 0;) {
        /* cur: level j + 1 -> fine; prev becomes level j -> fine */
        size_t nfine = sk_hierarchy_level_info(c->hier, j + 1).vertices, ns = 0;
        const uint32_t *map = sk_hierarchy_vertex_map(c->hier, j);
        for (size_t u = 0; u < nfine; ++u)
            if (map[u] != SK_INVALID)
                prev[map[u]] = cur[u];
        const sk_vertex_split *sp = sk_hierarchy_splits(c->hier, j, &ns);
        for (size_t k = 0; k < ns; ++k) {
            uint32_t v = cur[sp[k].v];
            sk_vertex_split r = sp[k];
            r.v = v;
            r.w0 = prev[r.w0];
            r.first = prev[r.first];
            r.last = prev[r.last];
            for (int q = 0; q < 3; ++q)
                r.parent[q] = prev[r.parent[q]];
            c->rec[v] = r;
            c->birth[v] = (uint32_t)(j + 1);
            c->order[off[j] + (ns - 1 - k)] = v; /* reverse record order, as sk_hierarchy_split */
        }
        uint32_t *t = cur;
        cur = prev;
        prev = t;
    }
    /* cur: level 0 -> fine */
    size_t nc = sk_hierarchy_coarsest(c->hier)->num_vertices;
    c->coarse_fine = sk__malloc_array(nc ? nc : 1, sizeof *c->coarse_fine);
    if (!c->coarse_fine) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    memcpy(c->coarse_fine, cur, nc * sizeof *cur);
done:
    sk__free(cur);
    sk__free(prev);
    sk__free(off);
    return st;
}

/* Components (per vertex), whether each is closed, and the one-rings of the fine mesh. */
static sk_status index_mesh(tol_ctx *c, sk_error *err)
{
    const sk_mesh *m = c->fine;
    size_t nv = c->nv, nh = m->num_halfedges;
    c->comp = sk__malloc_array(nv, sizeof *c->comp);
    c->ring_off = sk__calloc_array(nv + 1, sizeof *c->ring_off);
    c->ring = sk__malloc_array(nh ? nh : 1, sizeof *c->ring);
    uint32_t *stack = sk__malloc_array(nv ? nv : 1, sizeof *stack);
    sk_status st = SK_OK;
    if (!c->comp || !c->ring_off || !c->ring || !stack) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t h = 0; h < nh; ++h)
        c->ring_off[m->h_vertex[h ^ 1u] + 1]++;
    for (size_t v = 0; v < nv; ++v)
        c->ring_off[v + 1] += c->ring_off[v];
    for (size_t v = 0; v < nv; ++v) {
        uint32_t h0 = m->v_halfedge[v], h = h0;
        size_t k = c->ring_off[v];
        if (h0 != SK_INVALID)
            do {
                c->ring[k++] = m->h_vertex[h];
                h = sk_cw_out(m, h);
            } while (h != h0 && k < c->ring_off[v + 1]);
    }
    for (size_t v = 0; v < nv; ++v)
        c->comp[v] = SK_INVALID;
    size_t nc = 0;
    for (size_t s = 0; s < nv; ++s) {
        if (c->comp[s] != SK_INVALID)
            continue;
        size_t top = 0;
        stack[top++] = (uint32_t)s;
        c->comp[s] = (uint32_t)nc;
        while (top) {
            uint32_t v = stack[--top];
            for (uint32_t k = c->ring_off[v]; k < c->ring_off[v + 1]; ++k)
                if (c->comp[c->ring[k]] == SK_INVALID) {
                    c->comp[c->ring[k]] = (uint32_t)nc;
                    stack[top++] = c->ring[k];
                }
        }
        ++nc;
    }
    c->num_comps = nc;
    c->comp_closed = sk__malloc_array(nc ? nc : 1, 1);
    c->comp_count = sk__malloc_array(nc ? nc : 1, sizeof *c->comp_count);
    if (!c->comp_closed || !c->comp_count) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    memset(c->comp_closed, 1, nc);
    for (size_t h = 0; h < nh; ++h)
        if (m->h_face[h] == SK_INVALID)
            c->comp_closed[c->comp[m->h_vertex[h]]] = 0;
    for (size_t v = 0; v < nv; ++v)
        if (m->v_halfedge[v] == SK_INVALID)
            c->comp_closed[c->comp[v]] = 0; /* an isolated vertex: no surface to build */
done:
    sk__free(stack);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * Cuts
 * ------------------------------------------------------------------------------------------- */

/* One step of refinement towards v: makes alive the splits on v's dependency chain (v, its w0,
 * first and last, theirs, ...) whose own dependencies are all alive already, i.e. the coarsest
 * missing collapses around v. stamp/stamp_value mark the vertices visited in this round.
 * Returns the number of vertices made alive. */
static size_t want_step(const tol_ctx *c, uint8_t *alive, uint32_t v, uint32_t *stack,
                        uint32_t *stamp, uint32_t stamp_value)
{
    size_t top = 0, added = 0;
    if (alive[v] || stamp[v] == stamp_value)
        return 0;
    stamp[v] = stamp_value;
    stack[top++] = v;
    while (top) {
        uint32_t x = stack[--top];
        const sk_vertex_split *r = &c->rec[x];
        uint32_t dep[3] = {r->w0, r->first, r->last};
        bool ready = true;
        for (int q = 0; q < 3; ++q)
            if (alive[dep[q]] != 1) {
                ready = false;
                if (!alive[dep[q]] && stamp[dep[q]] != stamp_value) {
                    stamp[dep[q]] = stamp_value;
                    stack[top++] = dep[q];
                }
            }
        if (ready) {
            alive[x] = 2; /* alive from the next build on (not a dependency in this round) */
            ++added;
        }
    }
    return added;
}

/* Closed components with an odd number of alive vertices get one more: the first vertex in
 * application order whose split is ready. Returns the number added. */
static size_t fix_parity(const tol_ctx *c, uint8_t *alive)
{
    size_t *cnt = c->comp_count, added = 0;
    memset(cnt, 0, c->num_comps * sizeof *cnt);
    for (size_t v = 0; v < c->nv; ++v)
        cnt[c->comp[v]] += alive[v];
    for (size_t k = 0; k < c->num_order; ++k) {
        uint32_t v = c->order[k], q = c->comp[v];
        if (alive[v] || !c->comp_closed[q] || cnt[q] % 2 == 0)
            continue;
        const sk_vertex_split *r = &c->rec[v];
        if (alive[r->w0] && alive[r->first] && alive[r->last]) {
            alive[v] = 1;
            cnt[q]++;
            ++added;
        }
    }
    return added;
}

/* The mesh of the cut: the coarsest mesh with the splits of the alive vertices. Vertices whose
 * split does not fit (not expected) are cleared from alive. m2f (room for every fine vertex)
 * gets mixed -> fine. */
static sk_status build_cut(tol_ctx *c, uint8_t *alive, sk_mesh **out, uint32_t *m2f,
                           sk_error *err)
{
    const sk_mesh *co = sk_hierarchy_coarsest(c->hier);
    sk_mesh *m = NULL;
    sk_status st = sk_mesh_copy(co, &m, err);
    if (st)
        return st;
    sk__free(m->normals);
    sk__free(m->uvs);
    m->normals = NULL;
    m->uvs = NULL;
    sk_mesh_set_wedge_uvs(m, 0, NULL, NULL, NULL);
    size_t na = 0;
    for (size_t v = 0; v < c->nv; ++v)
        na += alive[v];
    size_t ns = na - co->num_vertices;
    if ((st = sk_mesh_reserve(m, na, m->num_halfedges + 6 * ns, m->num_faces + 2 * ns, err)))
        goto fail;
    for (size_t v = 0; v < c->nv; ++v)
        c->f2m[v] = SK_INVALID;
    for (size_t k = 0; k < co->num_vertices; ++k) {
        c->f2m[c->coarse_fine[k]] = (uint32_t)k;
        m2f[k] = c->coarse_fine[k];
    }
    for (size_t k = 0; k < c->num_order; ++k) {
        uint32_t v = c->order[k];
        if (!alive[v])
            continue;
        sk_vertex_split s = c->rec[v];
        s.w0 = c->f2m[s.w0];
        s.first = c->f2m[s.first];
        s.last = c->f2m[s.last];
        uint32_t id = SK_INVALID;
        if (s.w0 != SK_INVALID && s.first != SK_INVALID && s.last != SK_INVALID) {
            s.parent[0] = s.parent[1] = s.parent[2] = s.w0; /* no attributes to carry */
            id = sk__vertex_split(m, &s);
        }
        if (id == SK_INVALID) {
            alive[v] = 0;
            continue;
        }
        c->f2m[v] = id;
        m2f[id] = v;
    }
    if ((st = sk_mesh_add_normals(m, err)))
        goto fail;
    for (size_t k = 0; k < m->num_vertices; ++k)
        memcpy(m->normals + 3 * k, c->normals + 3 * (size_t)m2f[k], 3 * sizeof(double));
    *out = m;
    return SK_OK;
fail:
    sk_mesh_destroy(&m);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * Distances
 * ------------------------------------------------------------------------------------------- */

typedef struct check_buf {
    double *fd;     /* per fine face: largest distance of its samples to the surface */
    double *vd;     /* per fine vertex (dead ones): distance to the surface */
    double *sd;     /* per surface sample group: largest distance to the mesh */
    uint32_t *sf;   /* ... and the fine face nearest to the worst of them */
    size_t cap_s;
} check_buf;

static void check_buf_free(check_buf *b)
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

/* Distances both ways between the surface s and the fine mesh (mesh_faces, mesh_vertices,
 * surface_samples: exact
 * beyond T, bounded within it). With bad, the fine vertices where the tolerance is exceeded
 * (their own distance, or a face of theirs) are collected into bad (a flag per fine vertex);
 * without (the search), the check stops at the first sample of the mesh side beyond T.
 * *max_out: the largest distance found (exact when beyond T). */
static sk_status check(tol_ctx *c, const sk_smooth *s, const uint8_t *alive, check_buf *b,
                       uint8_t *bad, double *max_out, sk_error *err)
{
    sk_soup *ts = NULL;
    sk_bvh *bs = NULL;
    sk_status st = sk_patch_set_tessellate(&s->surface, c->tess, &ts, err);
    if (!st)
        st = sk_bvh_build(ts, &bs, err);
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
    sk_soup_destroy(&ts);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * One surface of a cut
 * ------------------------------------------------------------------------------------------- */

typedef struct cut_result {
    sk_smooth *s;
    size_t singular;   /* singular patches (sk_smooth_patch_shapes) */
    uint32_t *m2f;     /* mixed -> fine, for the config's vertices */
    double max;
    size_t patches;
    bool met;
} cut_result;

static void cut_result_free(cut_result *r)
{
    sk_smooth_destroy(&r->s);
    sk__free(r->m2f);
    memset(r, 0, sizeof *r);
    r->max = INFINITY;
}

static void record_try(sk_tolerance_stats *stats, size_t level, bool refined, sk_status status,
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
static sk_status build_surface(tol_ctx *c, uint8_t *alive, check_buf *b, uint8_t *bad,
                               cut_result *r, sk_status *vc1_status, size_t *vertices,
                               sk_tolerance_stats *stats, sk_error *err)
{
    cut_result_free(r);
    *vc1_status = SK_OK;
    stats->parity_splits += fix_parity(c, alive);
    sk_mesh *m = NULL;
    r->m2f = sk__malloc_array(c->nv, sizeof *r->m2f);
    if (!r->m2f)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    sk_status st = build_cut(c, alive, &m, r->m2f, err);
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

/* ---------------------------------------------------------------------------------------------
 * The driver
 * ------------------------------------------------------------------------------------------- */

static void ctx_free(tol_ctx *c)
{
    sk__free(c->normals);
    sk_hierarchy_destroy(&c->hier);
    sk__free(c->birth);
    sk__free(c->rec);
    sk__free(c->order);
    sk__free(c->coarse_fine);
    sk__free(c->comp);
    sk__free(c->comp_closed);
    sk__free(c->ring_off);
    sk__free(c->ring);
    sk__free(c->f2m);
    sk__free(c->comp_count);
    sk_bvh_destroy(&c->mesh_bvh);
    sk__free((void *)c->tri);
}

/* alive := every vertex born at level <= j */
static void level_cut(const tol_ctx *c, size_t j, uint8_t *alive)
{
    for (size_t v = 0; v < c->nv; ++v)
        alive[v] = c->birth[v] <= j;
}

/* within T and without singular patches: a surface the CLI writes (its continuity report
 * fails on a singular patch) */
static bool cut_ok(const cut_result *r)
{
    return r->s && r->met && r->singular == 0;
}

/* keeps the better of best and r (within T without singular patches first, then within T, then
 * fewer singular patches, then fewer patches when within T, else the smaller deviation); r is
 * emptied either way */
static void keep_better(cut_result *best, cut_result *r, bool *best_refined, bool r_refined)
{
    bool better = !best->s ||
                  (cut_ok(r) && !cut_ok(best)) ||
                  (cut_ok(r) == cut_ok(best) &&
                   ((r->met && !best->met) ||
                    (r->met == best->met &&
                     (r->singular < best->singular ||
                      (r->singular == best->singular &&
                       (r->met ? r->patches < best->patches : r->max < best->max))))));
    if (r->s && better) {
        cut_result_free(best);
        *best = *r;
        *best_refined = r_refined;
        memset(r, 0, sizeof *r);
        r->max = INFINITY;
    } else {
        cut_result_free(r);
    }
}

/* One run of the tolerance route: the context, the best surface so far and the scratch of the
 * refinement rounds. */
typedef struct tol_run {
    sk_tolerance_opts o;
    sk_tolerance_stats *stats;
    unsigned refine_levels, max_rounds;
    tol_ctx c;
    cut_result best, r, at_hi;
    bool best_refined;
    uint8_t *alive, *bad, *fresh;
    uint32_t *stack, *stamp, stamp_value;
    check_buf b;
    sk_soup *fine_soup, *ts;
} tol_run;

static void run_free(tol_run *t)
{
    cut_result_free(&t->best);
    cut_result_free(&t->r);
    cut_result_free(&t->at_hi);
    check_buf_free(&t->b);
    sk__free(t->alive);
    sk__free(t->bad);
    sk__free(t->fresh);
    sk__free(t->stack);
    sk__free(t->stamp);
    sk_soup_destroy(&t->ts);
    sk_soup_destroy(&t->fine_soup);
    ctx_free(&t->c);
}

static sk_status check_input(const sk_mesh *mesh, const sk_tolerance_opts *o, sk_error *err)
{
    if (!mesh || mesh->num_faces == 0)
        return sk__fail(err, SK_ERR_ARG, "no mesh");
    if (o->smooth.scheme != SK_SMOOTH_VC1)
        return sk__fail(err, SK_ERR_ARG, "the tolerance route builds VC1 surfaces only");
    if (!(o->tolerance >= 0) || !(o->tolerance_rel >= 0) || o->face_samples < 0 ||
        o->face_samples > 64 || o->tess > 64)
        return sk__fail(err, SK_ERR_ARG, "bad tolerance options (tolerance %g, relative %g, face "
                        "samples %d, tessellation %u)", o->tolerance, o->tolerance_rel,
                        o->face_samples, o->tess);
    if (mesh->num_deleted_vertices || mesh->num_deleted_faces)
        return sk__fail(err, SK_ERR_ARG, "the mesh has deleted elements (compact it first)");
    for (size_t f = 0; f < mesh->num_faces; ++f)
        if (sk_mesh_face_size(mesh, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu is not a triangle (the tolerance "
                            "route needs a triangle mesh)", f);
    return SK_OK;
}

/* The face samples of the deviation check: c->n x c->n sub-triangle centroids per face. */
static void sample_pattern(tol_ctx *c)
{
    size_t k = 0;
    for (int i = 0; i < c->n; ++i)
        for (int j = 0; i + j < c->n; ++j, ++k) {
            c->bary[k][0] = (i + 1.0 / 3.0) / c->n;
            c->bary[k][1] = (j + 1.0 / 3.0) / c->n;
        }
    for (int i = 0; i + 1 < c->n; ++i)
        for (int j = 0; i + j + 1 < c->n; ++j, ++k) {
            c->bary[k][0] = (i + 2.0 / 3.0) / c->n;
            c->bary[k][1] = (j + 2.0 / 3.0) / c->n;
        }
}

/* The context: options, samples, tolerance, fine normals, the hierarchy and its indexes, the
 * input's BVH. */
static sk_status setup(tol_run *t, const sk_mesh *mesh, sk_error *err)
{
    sk_status st = SK_OK;
    t->refine_levels = t->o.refine_levels ? t->o.refine_levels : 6;
    t->max_rounds = t->o.max_rounds ? t->o.max_rounds : 32;
    t->c.fine = mesh;
    t->c.nv = mesh->num_vertices;
    t->c.nf = mesh->num_faces;
    t->c.so = t->o.smooth;
    t->c.so.progress = NULL;
    t->c.so.progress_user = NULL;
    t->c.so.estimate_normals = false; /* every cut carries the fine normals */
    t->c.so.allow_split = true; /* only where no split of the hierarchy evens a closed component */
    t->c.n = t->o.face_samples ? t->o.face_samples : 2;
    t->c.tess = t->o.tess ? t->o.tess : 4;
    sample_pattern(&t->c);
    t->stats->diagonal = sk_mesh_diagonal(mesh);
    double rel = t->o.tolerance_rel > 0 ? t->o.tolerance_rel : 1e-3;
    t->c.tol = t->o.tolerance > 0 ? t->o.tolerance : rel * t->stats->diagonal;
    t->stats->tolerance = t->c.tol;
    t->stats->input_faces = t->c.nf;

    /* fine normals */
    t->c.normals = sk__malloc_array(3 * t->c.nv, sizeof *t->c.normals);
    uint32_t *tri = sk__malloc_array(3 * t->c.nf, sizeof *tri);
    t->c.tri = tri;
    t->c.f2m = sk__malloc_array(t->c.nv, sizeof *t->c.f2m);
    t->alive = sk__malloc_array(t->c.nv, 1);
    t->bad = sk__calloc_array(t->c.nv, 1);
    t->stack = sk__malloc_array(t->c.nv, sizeof *t->stack);
    t->stamp = sk__calloc_array(t->c.nv, sizeof *t->stamp);
    t->b.fd = sk__malloc_array(t->c.nf, sizeof *t->b.fd);
    t->b.vd = sk__malloc_array(t->c.nv, sizeof *t->b.vd);
    if (!t->c.normals || !tri || !t->c.f2m || !t->alive || !t->bad || !t->stack || !t->stamp ||
        !t->b.fd || !t->b.vd)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t f = 0; f < t->c.nf; ++f) {
        uint32_t h = mesh->f_halfedge[f];
        for (int q = 0; q < 3; ++q, h = mesh->h_next[h])
            tri[3 * f + q] = mesh->h_vertex[h ^ 1u];
    }
    double ta = sk_seconds();
    if (mesh->normals && !t->o.smooth.estimate_normals)
        memcpy(t->c.normals, mesh->normals, 3 * t->c.nv * sizeof *t->c.normals);
    else if ((st = sk_mesh_vertex_normals(mesh, t->o.smooth.normals, t->c.normals, err)))
        return st;
    double tb = sk_seconds();
    t->stats->seconds_normals = tb - ta;

    /* the hierarchy down to a handful of faces */
    sk_hierarchy_opts ho = {0};
    ho.seed = t->o.seed ? t->o.seed : 1;
    ho.target_faces = 8;
    /* coarse triangles that stay close to the fine normals and no valence-3 vertices: VC1 over
     * them has far fewer singular patches and spikes (measured on the sphere at 1e-2 of the
     * diagonal: 79 patches, against 210 with the hierarchy's defaults of 90 degrees and 3) */
    ho.collapse.max_normal_deviation_deg =
        t->o.collapse.max_normal_deviation_deg > 0 ? t->o.collapse.max_normal_deviation_deg : 15;
    ho.collapse.min_valence = t->o.collapse.min_valence ? t->o.collapse.min_valence : 4;
    if ((st = sk_hierarchy_build(mesh, &ho, &t->c.hier, err)))
        return st;
    t->c.levels = sk_hierarchy_num_levels(t->c.hier);
    t->stats->levels = t->c.levels;
    if ((st = index_hierarchy(&t->c, err)) || (st = index_mesh(&t->c, err)))
        return st;
    if ((st = sk_mesh_to_soup(mesh, &t->fine_soup, err)) ||
        (st = sk_bvh_build(t->fine_soup, &t->c.mesh_bvh, err)))
        return st;
    t->stats->seconds_hierarchy = sk_seconds() - tb;
    return SK_OK;
}

/* The search: the coarsest level that meets T (*coarsest_met; the number of levels when none
 * does), assuming finer levels are closer; the best surface seen is kept in t->best. */
static sk_status search_levels(tol_run *t, size_t *coarsest_met, sk_error *err)
{
    sk_status st = SK_OK;
    /* invariant: the levels below lo miss T (or have no VC1 surface); hi meets T when hi_met */
    size_t L = t->c.levels, lo = 0, hi = L - 1;
    bool hi_met = false;
    cut_result *at_hi = &t->at_hi; /* the surface of the met level hi */
    for (;;) {
        bool last = lo >= hi; /* only hi is left: the input itself (or a met level) */
        if (last && hi_met)
            break;
        size_t j = last ? hi : lo + (hi - lo) / 2, end = last ? hi + 1 : hi;
        sk_status vs = SK_OK;
        /* from the middle upwards to the first level where VC1 can be built */
        for (; j < end; ++j) {
            level_cut(&t->c, j, t->alive);
            size_t nvert = 0;
            if ((st = build_surface(&t->c, t->alive, &t->b, NULL, &t->r, &vs, &nvert, t->stats,
                                    err)))
                return st;
            t->stats->levels_tried++;
            record_try(t->stats, j, false, vs, nvert, &t->r);
            if ((st = sk__progress(t->o.progress, t->o.progress_user,
                                   0.5 * (double)t->stats->levels_tried / (double)(L + 1), err)))
                return st;
            if (vs == SK_OK)
                break;
            t->stats->failed_levels++;
        }
        if (j >= end) { /* nothing builds in [mid, end) */
            if (last)
                break;
            lo = hi;
            continue;
        }
        t->stats->singular_levels += t->r.singular > 0;
        if (t->r.met) {
            hi = j;
            hi_met = true;
            cut_result_free(at_hi);
            *at_hi = t->r;
            memset(&t->r, 0, sizeof t->r);
            t->r.max = INFINITY;
        } else {
            keep_better(&t->best, &t->r, &t->best_refined, false);
            if (last)
                break; /* the input itself misses T */
            lo = j + 1;
        }
    }
    *coarsest_met = hi_met ? hi : L;
    if (at_hi->s)
        keep_better(&t->best, at_hi, &t->best_refined, false);
    t->stats->coarsest_met = *coarsest_met < L ? *coarsest_met : L - 1;
    t->stats->level_met = hi_met;
    return SK_OK;
}

/* Marks alive (2, then 1) the splits that bring back the bad vertices, or where they are all
 * there, their neighbours; t->fresh := what was added. Returns how many. */
static size_t split_back(tol_run *t)
{
    size_t added = 0;
    tol_ctx *c = &t->c;
    ++t->stamp_value;
    for (size_t v = 0; v < c->nv; ++v)
        if (t->bad[v] && !t->alive[v])
            added += want_step(c, t->alive, (uint32_t)v, t->stack, t->stamp, t->stamp_value);
    if (added == 0) {
        /* the out-of-tolerance faces are all there: refine around them */
        ++t->stamp_value;
        for (size_t v = 0; v < c->nv; ++v)
            if (t->bad[v])
                for (uint32_t k = c->ring_off[v]; k < c->ring_off[v + 1]; ++k)
                    if (!t->alive[c->ring[k]])
                        added += want_step(c, t->alive, c->ring[k], t->stack, t->stamp,
                                           t->stamp_value);
    }
    memset(t->fresh, 0, c->nv);
    for (size_t v = 0; v < c->nv; ++v)
        if (t->alive[v] == 2) {
            t->alive[v] = 1;
            t->fresh[v] = 1;
        }
    return added;
}

/* Local refinement from a few levels below the coarsest met: split back where T is exceeded,
 * one collapse level at a time, until T holds, nothing is left to split or it stops paying. */
static sk_status refine(tol_run *t, size_t coarsest_met, sk_error *err)
{
    size_t base = coarsest_met > t->refine_levels ? coarsest_met - t->refine_levels : 0;
    t->stats->base_level = base;
    level_cut(&t->c, base, t->alive);
    size_t failures = 0;
    sk_status st = SK_OK;
    uint8_t *fresh = t->fresh; /* vertices made alive by the last round (to widen after a failure) */
    for (unsigned round = 0; round < t->max_rounds; ++round) {
        sk_status vs = SK_OK;
        size_t nvert = 0;
        memset(t->bad, 0, t->c.nv);
        if ((st = build_surface(&t->c, t->alive, &t->b, t->bad, &t->r, &vs, &nvert, t->stats,
                                err)))
            return st;
        t->stats->rounds++;
        record_try(t->stats, base, true, vs, nvert, &t->r);
        if ((st = sk__progress(t->o.progress, t->o.progress_user,
                               0.5 + 0.5 * (double)(round + 1) / t->max_rounds, err)))
            return st;
        if (vs != SK_OK) {
            t->stats->failed_rounds++;
            if (++failures > MAX_FAILED_ROUNDS)
                break;
            bool any = false;
            for (size_t v = 0; v < t->c.nv && !any; ++v)
                any = fresh[v];
            if (!any) { /* the base itself has no VC1 surface: a finer base */
                if (base + 1 >= coarsest_met)
                    break;
                t->stats->base_level = ++base;
                level_cut(&t->c, base, t->alive);
                continue;
            }
            /* widen: the neighbours of what the last round added */
            for (size_t v = 0; v < t->c.nv; ++v)
                if (fresh[v])
                    for (uint32_t k = t->c.ring_off[v]; k < t->c.ring_off[v + 1]; ++k)
                        t->bad[t->c.ring[k]] = 1;
        } else {
            /* within T with singular patches: go on splitting around them (they are in bad)
             * while that lowers their number (some meshes have singular patches even at the
             * input level: VC1 over cow.off has 15) */
            bool ok = cut_ok(&t->r);
            bool worse = t->best.met && t->r.patches >= t->best.patches &&
                         (cut_ok(&t->best) || (t->r.met && t->r.singular >= t->best.singular));
            keep_better(&t->best, &t->r, &t->best_refined, true);
            if (ok || worse)
                break;
        }
        size_t added = split_back(t);
        if (added == 0)
            break; /* the input mesh around every offending face */
    }
    return st;
}

/* The result against the input, as sk_deviation measures it; *out and *fine_ids handed out. */
static sk_status finish(tol_run *t, sk_smooth **out, uint32_t **fine_ids, sk_error *err)
{
    if (!t->best.s)
        return sk__fail(err, t->c.last_fail ? t->c.last_fail : SK_ERR_NUMERIC,
                        "no level of the hierarchy has a VC1 surface (the last failure: %.160s)",
                        t->c.last_msg);
    double te = sk_seconds();
    sk_status st = SK_OK;
    /* the result against the input, as sk_deviation measures it */
    sk_deviation_opts dop = {0};
    dop.face_samples = t->c.n;
    if ((st = sk_patch_set_tessellate(&t->best.s->surface, t->c.tess, &t->ts, err)) ||
        (st = sk_deviation(t->ts, t->fine_soup, &dop, &t->stats->deviation, NULL, err)))
        return st;
    t->stats->seconds_deviation = sk_seconds() - te;
    t->stats->refined = t->best_refined;
    t->stats->vertices = t->best.s->config->num_vertices;
    t->stats->patches = t->best.s->surface.count;
    t->stats->met = t->stats->deviation.hausdorff <= t->c.tol;
    if (fine_ids) {
        size_t nc = t->best.s->config->num_vertices;
        uint32_t *ids = sk__malloc_array(nc ? nc : 1, sizeof *ids);
        if (!ids)
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
        size_t built = t->stats->vertices - t->best.s->stats.split_edges;
        for (size_t k = 0; k < nc; ++k)
            ids[k] = k < built ? t->best.m2f[k] : SK_INVALID;
        *fine_ids = ids;
    }
    *out = t->best.s;
    t->best.s = NULL;
    if (!t->stats->met)
        return sk__fail(err, SK_WARN_TOLERANCE, "the tolerance %g is not met: the closest surface "
                      "found is %g from the mesh (%zu patches)", t->c.tol,
                      t->stats->deviation.hausdorff, t->stats->patches);
    sk__ok(err);
    return SK_OK;
}

sk_status sk_smooth_tolerance(const sk_mesh *mesh, const sk_tolerance_opts *opts,
                              sk_smooth **out, uint32_t **fine_ids,
                              sk_tolerance_stats *stats_out, sk_error *err)
{
    tol_run t;
    memset(&t, 0, sizeof t);
    if (opts)
        t.o = *opts;
    *out = NULL;
    if (fine_ids)
        *fine_ids = NULL;
    sk_tolerance_stats stats_local;
    t.stats = stats_out ? stats_out : &stats_local;
    memset(t.stats, 0, sizeof *t.stats);
    t.best.max = t.r.max = t.at_hi.max = INFINITY;
    sk_status st = check_input(mesh, &t.o, err);
    if (st)
        return st;
    size_t coarsest_met = 0;
    if ((st = setup(&t, mesh, err)))
        goto done;
    double tc = sk_seconds();
    if ((st = search_levels(&t, &coarsest_met, err)))
        goto done;
    double td = sk_seconds();
    t.stats->seconds_search = td - tc;
    if (coarsest_met < t.c.levels && coarsest_met > 0) {
        if (!(t.fresh = sk__calloc_array(t.c.nv, 1))) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        if ((st = refine(&t, coarsest_met, err)))
            goto done;
    }
    t.stats->seconds_refine = sk_seconds() - td;
    st = finish(&t, out, fine_ids, err);
done:
    run_free(&t);
    return st;
}
