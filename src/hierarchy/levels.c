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
 * sk_mesh_compact, which gives the fine -> coarse vertex map. */
#include "hierarchy/hierarchy_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

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
    free(rb->out);
    free(rb->ring);
    free(rb->len2);
    free(rb->scratch);
}

/* A growable list of split records. */
typedef struct split_list {
    sk_vertex_split *items;
    size_t count, cap;
} split_list;

static sk_vertex_split *split_push(split_list *l)
{
    if (l->count == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 1024;
        sk_vertex_split *p = sk__realloc_array(l->items, cap, sizeof *p);
        if (!p)
            return NULL;
        l->items = p;
        l->cap = cap;
    }
    return &l->items[l->count++];
}

/* Everything one simplification pass needs, allocated once for the finest level. */
typedef struct level_work {
    uint32_t *perm;
    uint8_t *lock;
    uint32_t *stamp;
    uint32_t *valence;
    ring_buffers rb;
    split_list splits;
    sk__collapse_ctx ctx;
    sk__rng rng;
} level_work;

/* One pass of the paper's rule over mesh m; appends a record per collapse to w->splits (with
 * level i+1 = current numbering). Returns false when a buffer cannot grow. */
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

    for (size_t i = 0; i < nv; ++i) {
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
        sk_vertex_split *s = split_push(&w->splits);
        if (!s)
            return false;
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
    return SK_OK;
}

void sk_hierarchy_destroy(sk_hierarchy **hp)
{
    if (!hp || !*hp)
        return;
    sk_hierarchy *h = *hp;
    for (size_t i = 0; i < h->num_levels; ++i) {
        free(h->levels[i].fine_to_coarse);
        free(h->levels[i].splits);
    }
    free(h->levels);
    sk_mesh_destroy(&h->coarsest);
    free(h);
    *hp = NULL;
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

    level_work w;
    memset(&w, 0, sizeof w);
    sk_mesh *m = NULL;
    sk__level *trans = NULL; /* transitions, finest first */
    size_t ntrans = 0;
    sk_hierarchy *hier = NULL;
    double t_start = now_seconds();
    if ((st = sk_mesh_copy(mesh, &m, err)))
        goto done;
    if (m->num_deleted_vertices || m->num_deleted_edges || m->num_deleted_faces)
        if ((st = sk_mesh_compact(m, NULL, NULL, err)))
            goto done;
    size_t nv0 = m->num_vertices, nf0 = m->num_faces;
    w.perm = sk__malloc_array(nv0, sizeof(uint32_t));
    w.lock = sk__malloc_array(nv0, 1);
    w.stamp = sk__malloc_array(nv0, sizeof(uint32_t));
    w.valence = sk__malloc_array(nv0, sizeof(uint32_t));
    /* at most log_{1/(1 - min_reduction)}(faces) transitions; 64 covers every sane case and the
       array grows when needed */
    size_t cap_trans = 64;
    trans = calloc(cap_trans, sizeof *trans);
    if (!w.perm || !w.lock || !w.stamp || !w.valence || !trans) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
        goto done;
    }
    sk__collapse_ctx_init(&w.ctx, &opts.collapse);
    sk__rng_seed(&w.rng, opts.seed);
    double finest_seconds = now_seconds() - t_start;

    for (;;) {
        size_t faces = m->num_faces, nv = m->num_vertices;
        if (opts.max_levels && ntrans + 1 >= opts.max_levels)
            break;
        if (opts.target_faces && faces <= opts.target_faces)
            break;
        double t0 = now_seconds();
        w.splits.count = 0;
        if (!simplify_level(m, &w)) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
            goto done;
        }
        if (w.splits.count == 0)
            break;
        if (ntrans == cap_trans) {
            sk__level *p = sk__realloc_array(trans, 2 * cap_trans, sizeof *trans);
            if (!p) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
                goto done;
            }
            memset(p + cap_trans, 0, cap_trans * sizeof *p);
            trans = p;
            cap_trans *= 2;
        }
        sk__level *L = &trans[ntrans++];
        L->fine_to_coarse = sk__malloc_array(nv, sizeof(uint32_t));
        L->splits = sk__malloc_array(w.splits.count, sizeof(sk_vertex_split));
        if (!L->fine_to_coarse || !L->splits) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
            goto done;
        }
        if ((st = sk_mesh_compact(m, L->fine_to_coarse, NULL, err)))
            goto done;
        const uint32_t *map = L->fine_to_coarse;
        for (size_t k = 0; k < w.splits.count; ++k) {
            sk_vertex_split *s = &w.splits.items[k];
            s->w0 = map[s->w0];
            s->first = map[s->first];
            s->last = map[s->last];
            for (int j = 0; j < 3; ++j)
                s->parent[j] = map[s->parent[j]];
        }
        memcpy(L->splits, w.splits.items, w.splits.count * sizeof(sk_vertex_split));
        L->num_splits = w.splits.count;
        L->vertices = m->num_vertices;
        L->faces = m->num_faces;
        L->seconds = now_seconds() - t0;
        if (opts.on_level && opts.on_level(opts.on_level_user, ntrans, m)) {
            st = sk__fail(err, SK_ERR_CANCELLED, "cancelled");
            goto done;
        }
        if ((st = sk__progress(opts.progress, opts.progress_user,
                               nf0 ? 1.0 - (double)m->num_faces / (double)nf0 : 1.0, err)))
            goto done;
        if ((double)(faces - m->num_faces) < min_reduction * (double)faces)
            break;
    }

    hier = calloc(1, sizeof *hier);
    if (!hier || !(hier->levels = calloc(ntrans + 1, sizeof(sk__level)))) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the hierarchy");
        goto done;
    }
    hier->num_levels = ntrans + 1;
    sk__level *fin = &hier->levels[ntrans];
    fin->vertices = nv0;
    fin->faces = nf0;
    fin->seconds = finest_seconds;
    for (size_t k = 0; k < ntrans; ++k) { /* transition k makes level ntrans - 1 - k */
        hier->levels[ntrans - 1 - k] = trans[k];
        memset(&trans[k], 0, sizeof trans[k]);
    }
    hier->coarsest = m;
    m = NULL;
    st = SK_OK;
    *out = hier;
    hier = NULL;

done:
    if (trans) {
        for (size_t k = 0; k < ntrans; ++k) {
            free(trans[k].fine_to_coarse);
            free(trans[k].splits);
        }
        free(trans);
    }
    sk_hierarchy_destroy(&hier);
    sk_mesh_destroy(&m);
    free(w.perm);
    free(w.lock);
    free(w.stamp);
    free(w.valence);
    free(w.splits.items);
    ring_free(&w.rb);
    return st;
}
