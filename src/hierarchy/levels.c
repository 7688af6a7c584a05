/* Hierarchy levels by half-edge collapses in random independent sets (Hormann, Greiner,
 * Campagna, section 3, "Building hierarchy levels"):
 *
 *     unlock all vertices of M~^{i+1}
 *     repeat
 *         choose unlocked vertex V by random
 *         collapse V to one of the neighbours W0
 *         lock surrounding vertices W0, ..., Wn
 *     until all remaining vertices are locked
 *
 * "By random" is a uniformly random permutation of the level's vertices (Fisher-Yates with sk__rng,
 * so a seed fixes the hierarchy), visited in order: the next unvisited unlocked vertex of a random
 * permutation is a uniform choice among the unlocked ones. A visited vertex that cannot be
 * collapsed legally counts as locked for the rest of the level (one pass, as the paper's loop ends
 * when every remaining vertex is locked).
 *
 * Choice of W0 (the paper leaves it open): the neighbour along the shortest edge among the legal
 * ones (sk__collapse_ok); ties keep the ring order. A boundary V only has its two boundary
 * neighbours as candidates.
 *
 * Locking V's ring makes the removed vertices of a level pairwise non-adjacent, so their
 * collapses touch disjoint sets of faces, commute, and the parent triangle (w0, w_i, w_i+1) of
 * each one is a face of the coarser level (section 3).
 *
 * Cost: O(valence) per visited vertex, no allocation inside the level loop; each level ends with
 * sk_mesh_compact, which gives the fine -> coarse vertex map. The random visiting order jumps all
 * over memory, so before the first level the working copy is renumbered in Morton (Z) order of the
 * vertex positions, with edges sorted by their first vertex: a one-ring then sits in a few cache
 * lines. The renumbering is undone in the records and map of the first transition, so the input
 * keeps its numbering; coarser levels are numbered in the spatial order. */
#include "hierarchy/hierarchy_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(__GNUC__)
#define SK_PREFETCH(p) __builtin_prefetch(p)
#else
#define SK_PREFETCH(p) ((void)0)
#endif


/* Scratch buffers sized for the largest valence seen so far. */
typedef struct ring_buffers {
    size_t cap;
    uint32_t *out;  /* outgoing half-edges */
    uint32_t *ring; /* ring vertex ids for the exponential map */
    double *len2;   /* candidate edge lengths */
    double *scratch;
} ring_buffers;

static bool ring_reserve(ring_buffers *rb, size_t n)
{
    if (n <= rb->cap)
        return true;
    size_t cap = rb->cap ? rb->cap : 32;
    while (cap < n)
        cap *= 2;
    uint32_t *out = sk__realloc_array(rb->out, cap, sizeof(uint32_t));
    if (out)
        rb->out = out;
    uint32_t *ring = sk__realloc_array(rb->ring, cap, sizeof(uint32_t));
    if (ring)
        rb->ring = ring;
    double *len2 = sk__realloc_array(rb->len2, cap, sizeof(double));
    if (len2)
        rb->len2 = len2;
    double *scratch = sk__realloc_array(rb->scratch, 4 * cap + 2, sizeof(double));
    if (scratch)
        rb->scratch = scratch;
    if (!out || !ring || !len2 || !scratch)
        return false;
    rb->cap = cap;
    return true;
}

static void ring_free(ring_buffers *rb)
{
    sk__free(rb->out);
    sk__free(rb->ring);
    sk__free(rb->len2);
    sk__free(rb->scratch);
}

/* Everything one simplification pass needs, allocated once for the finest level. */
typedef struct level_work {
    uint32_t *perm;
    uint8_t *lock;
    uint32_t *stamp;
    uint32_t *valence;
    ring_buffers rb;
    sk_vertex_split *splits; /* this level's records go here */
    size_t num_splits;
    sk__collapse_ctx ctx;
    sk__rng rng;
} level_work;

/* One pass of the paper's rule over mesh m; writes a record per collapse to w->splits (ids in the
 * current numbering = level i+1). Returns false when a buffer cannot grow. */
static bool simplify_level(sk_mesh *m, level_work *w)
{
    size_t nv = m->num_vertices;
    uint32_t *perm = w->perm, *vh = m->v_halfedge, *hv = m->h_vertex, *hn = m->h_next;
    uint8_t *lock = w->lock;
    const double *P = m->positions;

    memset(w->valence, 0, nv * sizeof(uint32_t));
    for (size_t h = 0; h < m->num_halfedges; ++h)
        w->valence[hv[h]]++;
    memset(lock, 0, nv);
    memset(w->stamp, 0, nv * sizeof(uint32_t));
    w->ctx.stamp = w->stamp;
    w->ctx.stamp_value = 0;
    w->ctx.valence = w->valence;
    /* Fisher-Yates: a uniformly random order of the vertices */
    for (size_t i = 0; i < nv; ++i)
        perm[i] = (uint32_t)i;
    for (size_t i = nv; i > 1; --i) {
        uint32_t j = sk__rng_below(&w->rng, (uint32_t)i);
        uint32_t t = perm[i - 1];
        perm[i - 1] = perm[j];
        perm[j] = t;
    }

    /* The random order defeats the caches: prefetch the vertex record 16 visits ahead and its
       first half-edge and position 8 visits ahead. */
    const uint32_t *hf = m->h_face;
    for (size_t i = 0; i < nv; ++i) {
        if (i + 16 < nv) {
            SK_PREFETCH(&vh[perm[i + 16]]);
            SK_PREFETCH(&lock[perm[i + 16]]);
        }
        if (i + 8 < nv) {
            uint32_t u = perm[i + 8], hu = vh[u];
            if (!lock[u] && hu != SK_INVALID) {
                SK_PREFETCH(&hf[hu]);
                SK_PREFETCH(&hn[hu ^ 1u]);
                SK_PREFETCH(&hv[hu]);
                SK_PREFETCH(&m->h_prev[hu]);
                SK_PREFETCH(P + 3 * (size_t)u);
            }
        }
        uint32_t v = perm[i];
        if (lock[v])
            continue;
        lock[v] = 1; /* visited: locked whether it collapses or not */
        uint32_t h0 = vh[v];
        if (h0 == SK_INVALID)
            continue;
        size_t val = w->valence[v];
        if (val < 3)
            continue;
        if (!ring_reserve(&w->rb, val + 1))
            return false;
        uint32_t *out = w->rb.out;
        double *len2 = w->rb.len2;
        /* candidates: the outgoing half-edges (only the two boundary ones for a boundary V),
         * sorted by length */
        size_t nc = 0;
        if (m->h_face[h0] == SK_INVALID) {
            out[nc++] = h0;
            out[nc++] = m->h_prev[h0] ^ 1u;
        } else {
            uint32_t y = h0;
            do {
                out[nc++] = y;
                y = hn[y ^ 1u];
            } while (y != h0 && nc < val);
        }
        const double *pv = P + 3 * (size_t)v;
        for (size_t k = 0; k < nc; ++k) {
            double d[3];
            sk__sub3(d, P + 3 * (size_t)hv[out[k]], pv);
            double l = sk__dot3(d, d);
            uint32_t hk = out[k];
            size_t j = k;
            while (j > 0 && len2[j - 1] > l) { /* insertion sort, stable */
                len2[j] = len2[j - 1];
                out[j] = out[j - 1];
                --j;
            }
            len2[j] = l;
            out[j] = hk;
        }
        sk__collapse_mark_ring(m, v, &w->ctx);
        uint32_t h = SK_INVALID;
        for (size_t k = 0; k < nc; ++k) {
            if (sk__collapse_ok(m, out[k], &w->ctx)) {
                h = out[k];
                break;
            }
        }
        if (h == SK_INVALID)
            continue;

        /* barycentric coordinates in the parent triangle, then the collapse */
        sk_vertex_split *s = &w->splits[w->num_splits++];
        bool closed;
        uint32_t *ring = w->rb.ring;
        size_t count = sk__collapse_ring(m, h, ring, &closed);
        sk__barycentric(m, v, ring, count, closed, w->rb.scratch, s->parent, s->bary);
        uint32_t o = h ^ 1u;
        s->v = v;
        s->w0 = hv[h];
        s->left_face = m->h_face[h] != SK_INVALID;
        s->right_face = m->h_face[o] != SK_INVALID;
        s->first = s->left_face ? hv[hn[h]] : hv[m->h_prev[h] ^ 1u];
        s->last = hv[hn[o]];
        memcpy(s->position, pv, sizeof s->position);
        sk__collapse(m, h, w->valence);
        for (size_t k = 0; k < count; ++k)
            lock[ring[k]] = 1;
    }
    return true;
}

/* Spreads the low 21 bits of x to every third bit. */
static uint64_t spread3(uint64_t x)
{
    x &= 0x1fffffULL;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

/* The working copy of the input: alive elements only (so numbered as sk_mesh_compact would),
 * vertices renumbered in Morton order of their positions, edges sorted by their smaller new
 * vertex, faces in their order. Built in one pass into fresh (huge-page hinted) arrays.
 * work_to_finest[w] receives the compacted input number of working vertex w. */
static sk_status working_copy(const sk_mesh *in, sk_mesh **out, uint32_t *work_to_finest,
                              sk_error *err)
{
    size_t nvi = in->num_vertices, nhi = in->num_halfedges, nfi = in->num_faces;
    size_t nv = nvi - in->num_deleted_vertices, ne = nhi / 2 - in->num_deleted_edges;
    size_t nf = nfi - in->num_deleted_faces;
    sk_mesh *m = NULL;
    uint64_t *keys = sk__malloc_array(nv, sizeof(uint64_t));
    uint32_t *vals = sk__malloc_array(nv, sizeof(uint32_t));
    uint32_t *vnew = sk__alloc_huge(nvi, sizeof(uint32_t));
    uint32_t *hnew = sk__alloc_huge(nhi / 2, sizeof(uint32_t)); /* per edge */
    uint32_t *fnew = sk__alloc_huge(nfi, sizeof(uint32_t));
    uint32_t *count = sk__calloc_array(nv + 1, sizeof(uint32_t));
    uint32_t *eold = sk__alloc_huge(ne ? ne : 1, sizeof(uint32_t)); /* new edge -> input edge */
    sk_status st = SK_OK;
    if (!keys || !vals || !vnew || !hnew || !fnew || !count || !eold)
        goto nomem;
    {
        double pos0 = 0.0;
        uint32_t off0 = 0, idx0 = 0;
        if ((st = sk_mesh_from_faces(0, &pos0, 0, &off0, &idx0, &m, err)))
            goto done;
    }
    if ((st = sk_mesh_reserve(m, nv, 2 * ne, nf, err)))
        goto done;
    if ((in->normals && (st = sk_mesh_add_normals(m, err))) || (in->uvs && (st = sk_mesh_add_uvs(m, err))))
        goto done;
    sk__mesh_huge_hint(m);

    /* vertices: Morton order of the positions (ties: input order) */
    double lo[3], hi[3], scale[3];
    sk_mesh_bbox(in, lo, hi);
    for (int k = 0; k < 3; ++k)
        scale[k] = hi[k] > lo[k] ? 2097151.0 / (hi[k] - lo[k]) : 0.0;
    size_t k = 0;
    for (size_t v = 0; v < nvi; ++v) {
        vnew[v] = SK_INVALID;
        if (in->v_deleted[v])
            continue;
        const double *p = in->positions + 3 * v;
        uint64_t c[3];
        for (int d = 0; d < 3; ++d) {
            double q = (p[d] - lo[d]) * scale[d];
            c[d] = q > 0.0 ? (q < 2097151.0 ? (uint64_t)q : 2097151u) : 0u;
        }
        keys[k] = spread3(c[0]) | spread3(c[1]) << 1 | spread3(c[2]) << 2;
        vals[k++] = (uint32_t)v;
    }
    if (sk__sort_u64_u32(keys, vals, nv))
        goto nomem;
    {
        size_t finest = 0;
        for (size_t v = 0; v < nvi; ++v) /* finest number = rank among the alive */
            if (!in->v_deleted[v])
                vnew[v] = (uint32_t)finest++;
        for (size_t j = 0; j < nv; ++j) {
            work_to_finest[j] = vnew[vals[j]];
        }
        for (size_t j = 0; j < nv; ++j)
            vnew[vals[j]] = (uint32_t)j;
    }
    /* edges: counting sort by the smaller new vertex */
    for (size_t e = 0; e < nhi / 2; ++e) {
        if (in->e_deleted[e])
            continue;
        uint32_t a = vnew[in->h_vertex[2 * e]], b = vnew[in->h_vertex[2 * e + 1]];
        count[(a < b ? a : b) + 1]++;
    }
    for (size_t j = 0; j < nv; ++j)
        count[j + 1] += count[j];
    for (size_t e = 0; e < nhi / 2; ++e) {
        hnew[e] = SK_INVALID;
        if (in->e_deleted[e])
            continue;
        uint32_t a = vnew[in->h_vertex[2 * e]], b = vnew[in->h_vertex[2 * e + 1]];
        uint32_t t = count[a < b ? a : b]++;
        hnew[e] = t;
        eold[t] = (uint32_t)e;
    }
    k = 0;
    for (size_t f = 0; f < nfi; ++f)
        fnew[f] = in->f_deleted[f] ? SK_INVALID : (uint32_t)k++;

#define HMAP(h) ((h) == SK_INVALID ? SK_INVALID : 2u * hnew[(h) >> 1] + ((h)&1u))
    for (size_t v = 0; v < nvi; ++v) {
        uint32_t t = vnew[v];
        if (t == SK_INVALID)
            continue;
        memcpy(m->positions + 3 * (size_t)t, in->positions + 3 * v, 3 * sizeof(double));
        if (in->normals)
            memcpy(m->normals + 3 * (size_t)t, in->normals + 3 * v, 3 * sizeof(double));
        if (in->uvs)
            memcpy(m->uvs + 2 * (size_t)t, in->uvs + 2 * v, 2 * sizeof(double));
        m->v_halfedge[t] = HMAP(in->v_halfedge[v]);
    }
    for (size_t t = 0; t < 2 * ne; ++t) { /* in the new order: sequential writes */
        uint32_t h = 2 * eold[t >> 1] + (uint32_t)(t & 1u), f = in->h_face[h];
        m->h_vertex[t] = vnew[in->h_vertex[h]];
        m->h_next[t] = HMAP(in->h_next[h]);
        m->h_prev[t] = HMAP(in->h_prev[h]);
        m->h_face[t] = f == SK_INVALID ? SK_INVALID : fnew[f];
    }
    for (size_t f = 0; f < nfi; ++f)
        if (fnew[f] != SK_INVALID)
            m->f_halfedge[fnew[f]] = HMAP(in->f_halfedge[f]);
#undef HMAP
    memset(m->v_deleted, 0, nv);
    memset(m->e_deleted, 0, ne);
    memset(m->f_deleted, 0, nf);
    m->num_vertices = nv;
    m->num_halfedges = 2 * ne;
    m->num_faces = nf;
    goto done;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
done:
    sk__free(keys);
    sk__free(vals);
    sk__free(vnew);
    sk__free(hnew);
    sk__free(fnew);
    sk__free(count);
    sk__free(eold);
    if (st)
        sk_mesh_destroy(&m);
    *out = m;
    return st;
}

/* Sorts the records by w0 (stable); idx needs n entries; *tmp is a reusable buffer. */
static sk_status sort_by_w0(sk_vertex_split *sp, size_t n, uint32_t *idx, sk_vertex_split **tmp,
                            size_t *cap, sk_error *err)
{
    if (n < 2)
        return SK_OK;
    if (n > *cap) {
        sk__free(*tmp);
        *tmp = sk__alloc_huge(n, sizeof(sk_vertex_split));
        *cap = *tmp ? n : 0;
    }
    uint64_t *keys = sk__malloc_array(n, sizeof(uint64_t));
    if (!*tmp || !keys) {
        sk__free(keys);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
    }
    for (size_t k = 0; k < n; ++k) {
        keys[k] = sp[k].w0;
        idx[k] = (uint32_t)k;
    }
    if (sk__sort_u64_u32(keys, idx, n)) {
        sk__free(keys);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
    }
    for (size_t k = 0; k < n; ++k)
        (*tmp)[k] = sp[idx[k]];
    memcpy(sp, *tmp, n * sizeof(sk_vertex_split));
    sk__free(keys);
    return SK_OK;
}

static sk_status check_input(const sk_mesh *m, sk_error *err)
{
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f];
        if (m->h_next[m->h_next[m->h_next[h]]] != h)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "the hierarchy needs a triangle mesh: face %zu has %zu sides", f,
                            sk_mesh_face_size(m, (uint32_t)f));
    }
    for (size_t v = 0; v < 3 * m->num_vertices; ++v)
        if (!m->v_deleted[v / 3] && !isfinite(m->positions[v]))
            return sk__fail(err, SK_ERR_NUMERIC, "vertex %zu has a non-finite coordinate", v / 3);
    /* outside the supported range the collapse tests silently reject every collapse (at 1e+-80
     * simplify exited 0 with no level made): refuse, naming the range */
    return sk_mesh_check_scale(m, err);
}

void sk_hierarchy_destroy(sk_hierarchy **hp)
{
    if (!hp || !*hp)
        return;
    sk_hierarchy *h = *hp;
    for (size_t i = 0; i < h->num_levels; ++i)
        sk__free(h->levels[i].fine_to_coarse);
    sk__free(h->levels);
    sk__free(h->split_store);
    sk_mesh_destroy(&h->coarsest);
    sk__free(h);
    *hp = NULL;
}

/* The state of one sk_hierarchy_build: the working mesh, the transitions made so far (finest
 * first) and the one store of split records. */
typedef struct build_state {
    level_work w;
    sk_mesh *m;
    sk__level *trans;
    size_t ntrans, cap_trans;
    sk_vertex_split *store, *sort_tmp;
    size_t sort_cap, stored;
    uint32_t *work_to_finest;
    size_t nv0, nf0, nh0;
} build_state;

#define NOMEM_MSG "out of memory building the hierarchy"

static void build_free(build_state *b)
{
    if (b->trans) {
        for (size_t k = 0; k < b->ntrans; ++k)
            sk__free(b->trans[k].fine_to_coarse);
        sk__free(b->trans);
    }
    sk_mesh_destroy(&b->m);
    sk__free(b->store);
    sk__free(b->sort_tmp);
    sk__free(b->work_to_finest);
    sk__free(b->w.perm);
    sk__free(b->w.lock);
    sk__free(b->w.stamp);
    sk__free(b->w.valence);
    ring_free(&b->w.rb);
}

/* Buffers, the working copy of the input (vertices in Morton order), the collapse rules. */
static sk_status build_begin(build_state *b, const sk_mesh *mesh, const sk_hierarchy_opts *opts,
                             sk_error *err)
{
    b->cap_trans = 64;
    size_t nv0 = b->nv0 = mesh->num_vertices - mesh->num_deleted_vertices, n = nv0 ? nv0 : 1;
    b->nf0 = mesh->num_faces - mesh->num_deleted_faces;
    b->work_to_finest = sk__alloc_huge(n, sizeof(uint32_t));
    /* every vertex is removed at most once: nv0 records in all; untouched pages cost nothing */
    b->store = sk__alloc_huge(n, sizeof(sk_vertex_split));
    b->trans = sk__calloc_array(b->cap_trans, sizeof *b->trans);
    if (!b->work_to_finest || !b->store || !b->trans)
        return sk__fail(err, SK_ERR_NOMEM, NOMEM_MSG);
    sk_status st = working_copy(mesh, &b->m, b->work_to_finest, err);
    if (st)
        return st;
    b->nh0 = b->m->num_halfedges;
    b->w.perm = sk__alloc_huge(n, sizeof(uint32_t));
    b->w.lock = sk__alloc_huge(n, 1);
    b->w.stamp = sk__alloc_huge(n, sizeof(uint32_t));
    b->w.valence = sk__alloc_huge(n, sizeof(uint32_t));
    if (!b->w.perm || !b->w.lock || !b->w.stamp || !b->w.valence)
        return sk__fail(err, SK_ERR_NOMEM, NOMEM_MSG);
    sk__collapse_ctx_init(&b->w.ctx, &opts->collapse);
    sk__rng_seed(&b->w.rng, opts->seed);
    return SK_OK;
}

/* A new transition for the level just simplified (nv vertices before): compacts the mesh, which
 * gives the fine -> coarse map, and renumbers the level's split records to the coarse ids (the
 * finest level keeps the input numbering for the removed vertices). */
static sk_status push_transition(build_state *b, size_t nv, sk__level **out, sk_error *err)
{
    if (b->ntrans == b->cap_trans) {
        sk__level *p = sk__realloc_array(b->trans, 2 * b->cap_trans, sizeof *b->trans);
        if (!p)
            return sk__fail(err, SK_ERR_NOMEM, NOMEM_MSG);
        memset(p + b->cap_trans, 0, b->cap_trans * sizeof *p);
        b->trans = p;
        b->cap_trans *= 2;
    }
    sk__level *L = &b->trans[b->ntrans++];
    L->fine_to_coarse = sk__alloc_huge(nv, sizeof(uint32_t));
    if (!L->fine_to_coarse)
        return sk__fail(err, SK_ERR_NOMEM, NOMEM_MSG);
    sk_status st = sk_mesh_compact(b->m, L->fine_to_coarse, NULL, err);
    if (st)
        return st;
    uint32_t *map = L->fine_to_coarse;
    sk_vertex_split *sp = b->w.splits;
    for (size_t k = 0; k < b->w.num_splits; ++k) {
        sp[k].w0 = map[sp[k].w0];
        sp[k].first = map[sp[k].first];
        sp[k].last = map[sp[k].last];
        for (int j = 0; j < 3; ++j)
            sp[k].parent[j] = map[sp[k].parent[j]];
    }
    if (b->ntrans == 1) { /* the finest level keeps the input numbering */
        for (size_t k = 0; k < b->w.num_splits; ++k)
            sp[k].v = b->work_to_finest[sp[k].v];
        for (size_t v = 0; v < nv; ++v) /* perm: finest -> coarse (perm is free here) */
            b->w.perm[b->work_to_finest[v]] = map[v];
        memcpy(map, b->w.perm, nv * sizeof(uint32_t));
    }
    *out = L;
    return SK_OK;
}

/* One level: simplify, record the transition, report progress. *more = false when no collapse
 * was possible or the level removed less than min_reduction of the faces. */
static sk_status next_level(build_state *b, const sk_hierarchy_opts *opts, double min_reduction,
                            bool *more, sk_error *err)
{
    sk_mesh *m = b->m;
    size_t faces = m->num_faces, nv = m->num_vertices;
    double t0 = sk_seconds();
    *more = false;
    b->w.splits = b->store + b->stored;
    b->w.num_splits = 0;
    if (!simplify_level(m, &b->w))
        return sk__fail(err, SK_ERR_NOMEM, NOMEM_MSG);
    if (b->w.num_splits == 0)
        return SK_OK;
    sk__level *L = NULL;
    sk_status st = push_transition(b, nv, &L, err);
    /* splits commute within a level: store them sorted by w0 (Morton order of the coarse
       level) so that the walk up applies them with good locality */
    if (!st)
        st = sort_by_w0(b->w.splits, b->w.num_splits, b->w.perm, &b->sort_tmp, &b->sort_cap, err);
    if (st)
        return st;
    L->splits = b->w.splits;
    L->num_splits = b->w.num_splits;
    L->halfedges = m->num_halfedges;
    b->stored += b->w.num_splits;
    L->vertices = m->num_vertices;
    L->faces = m->num_faces;
    L->seconds = sk_seconds() - t0;
    if (opts->on_level && opts->on_level(opts->on_level_user, b->ntrans, m))
        return sk__fail(err, SK_ERR_CANCELLED, "cancelled");
    st = sk__progress(opts->progress, opts->progress_user,
                      b->nf0 ? 1.0 - (double)m->num_faces / (double)b->nf0 : 1.0, err);
    *more = !st && (double)(faces - m->num_faces) >= min_reduction * (double)faces;
    return st;
}

/* Hands the levels, the split store and the coarsest mesh over to a new hierarchy. */
static sk_status build_finish(build_state *b, double finest_seconds, sk_hierarchy **out,
                              sk_error *err)
{
    size_t ntrans = b->ntrans;
    if (ntrans == 0) { /* no level below the input: give the input its numbering back */
        uint32_t *newid = b->w.perm;
        memcpy(newid, b->work_to_finest, b->nv0 * sizeof(uint32_t));
        sk_status st = sk__permute_vertices(b->m, newid, err);
        if (st)
            return st;
    }
    sk_hierarchy *hier = sk__calloc_array(1, sizeof *hier);
    if (!hier || !(hier->levels = sk__calloc_array(ntrans + 1, sizeof(sk__level)))) {
        sk_hierarchy_destroy(&hier);
        return sk__fail(err, SK_ERR_NOMEM, NOMEM_MSG);
    }
    hier->num_levels = ntrans + 1;
    sk__level *fin = &hier->levels[ntrans];
    fin->vertices = b->nv0;
    fin->faces = b->nf0;
    fin->halfedges = b->nh0;
    fin->seconds = finest_seconds;
    for (size_t k = 0; k < ntrans; ++k) { /* transition k makes level ntrans - 1 - k */
        hier->levels[ntrans - 1 - k] = b->trans[k];
        memset(&b->trans[k], 0, sizeof b->trans[k]);
    }
    hier->split_store = b->store;
    b->store = NULL;
    hier->coarsest = b->m;
    b->m = NULL;
    *out = hier;
    return SK_OK;
}

sk_status sk_hierarchy_build(const sk_mesh *mesh, const sk_hierarchy_opts *opts_in,
                             sk_hierarchy **out, sk_error *err)
{
    sk_hierarchy_opts opts = {0};
    if (opts_in)
        opts = *opts_in;
    double min_reduction = opts.min_reduction > 0 ? opts.min_reduction : 0.03;
    *out = NULL;
    if (!mesh)
        return sk__fail(err, SK_ERR_ARG, "no mesh");
    sk_status st = check_input(mesh, err);
    if (st)
        return st;
    double t_start = sk_seconds();
    build_state b;
    memset(&b, 0, sizeof b);
    if ((st = build_begin(&b, mesh, &opts, err)))
        goto done;
    double finest_seconds = sk_seconds() - t_start;
    for (bool more = true; more;) {
        if (opts.max_levels && b.ntrans + 1 >= opts.max_levels)
            break;
        if (opts.target_faces && b.m->num_faces <= opts.target_faces)
            break;
        if ((st = next_level(&b, &opts, min_reduction, &more, err)))
            goto done;
    }
    st = build_finish(&b, finest_seconds, out, err);
done:
    build_free(&b);
    return st;
}
