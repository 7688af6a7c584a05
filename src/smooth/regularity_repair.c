/* Regularity repair of the VC1 construction. */
#include "smooth/vc1_internal.h"
#include "core/internal.h"

#include <string.h>

/* Every solution of the vertex systems (8) with the interior points of (4)
 * gives a VC1 surface, so the free choices (here: the targets a vertex system is fitted to) can
 * be spent on patch quality. For every corner vertex of a patch that the report's regularity test
 * finds singular, the vertex system is re-solved with varied targets (directions blended towards
 * an even spread, lengths scaled); the variant with the fewest singular patches among the faces
 * whose control points it moves (the faces around the vertex and its neighbours) is kept if it
 * has fewer than the plain construction. Sequential in vertex order: deterministic. */

static const double repair_variants[][2] = {
    /* blend, length scale */
    {0.25, 1.0}, {0.5, 1.0}, {1.0, 1.0}, {0.0, 0.75}, {0.0, 1.3}, {0.5, 0.75}, {0.5, 1.3},
    {0.0, 0.55}, {0.0, 1.7}, {1.0, 0.7},
    /* six more (measured: mushroom 2 -> 0 singular patches, armadillo 19 -> 14, cow 44 -> 41;
     * a third round gained nothing) */
    {0.25, 0.75}, {0.25, 1.3}, {1.0, 1.3}, {0.0, 0.4}, {0.5, 0.55}, {0.0, 2.2},
};
#define N_VARIANTS (sizeof repair_variants / sizeof repair_variants[0])

/* faces around v and around its neighbours, deduplicated with the marks array (cleared after) */
static size_t local_faces(const sk_mesh *m, uint32_t v, uint8_t *mark, uint32_t *faces,
                          size_t cap, uint32_t *verts, size_t *nverts)
{
    size_t nf = 0, nvv = 0;
    verts[nvv++] = v;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        verts[nvv++] = sk_to(m, h);
        h = sk_cw_out(m, h);
    } while (h != h0 && nvv < SK_VSYS_MAX + 1);
    for (size_t i = 0; i < nvv; ++i) {
        uint32_t g0 = m->v_halfedge[verts[i]], g = g0;
        do {
            uint32_t f = m->h_face[g];
            if (f != SK_INVALID && !mark[f] && nf < cap) {
                mark[f] = 1;
                faces[nf++] = f;
            }
            g = sk_cw_out(m, g);
        } while (g != g0);
    }
    for (size_t i = 0; i < nf; ++i)
        mark[faces[i]] = 0;
    *nverts = nvv;
    return nf;
}

/* Rebuilds the patches of faces after new vertex solutions at verts and counts the singular
 * ones, stopping once the count reaches limit (the variant cannot win then; the patches are all
 * assembled either way). faces lists the ones singular before first, so a losing variant is
 * usually found out after a few tests. */
static size_t rebuild_local(sk_smooth *s, sk__vc1_work *W, const uint32_t *verts, size_t nverts,
                            const uint32_t *faces, size_t nf, size_t limit)
{
    for (size_t i = 0; i < nverts; ++i)
        sk__vc1_interior_points(W, verts[i]);
    for (size_t i = 0; i < nf; ++i)
        sk__vc1_assemble_patch(W, faces[i], sk_patch_cp(&s->surface, faces[i]));
    size_t bad = 0;
    for (size_t i = 0; i < nf && bad < limit; ++i)
        bad += sk__patch_singular(s, faces[i], NULL);
    return bad;
}

#define LOCAL_FACES 4096

/* The repair's state. A vertex's variant solutions depend only on fixed data (its targets, ratios
 * and normal), so they are kept once solved (`cache`, per vertex a slot of N_VARIANTS entries of
 * code, w1 and P of its edges) and reused when the vertex is tried again in round 2 and for the
 * winner. A vertex tried without gain is skipped later while none of the patches around it and
 * its neighbours changed since (the same try would give the same result): `tried` holds the tick
 * of that try, `changed` per patch the tick of the last gain that moved it. Crease vertices
 * (whose sectors take fixed ends from their neighbours' state) are solved afresh each time. */
typedef struct repair_ctx {
    sk_smooth *s;
    sk__vc1_work *W;
    uint8_t *status, *sing, *mark;
    uint32_t *faces, *tried, *changed, *slot; /* slot: per vertex 1 + its cache slot, 0 none */
    double *cache;
    size_t cache_used, cache_cap, nsing, repaired;
    uint32_t tick;
} repair_ctx;

/* cache entry of variant t at vertex v (n edges): [0] code (-1 not solved yet), [1 .. n] w1,
 * then 3 n coordinates of P; NULL when v is not cached (crease vertex, out of memory) */
static double *cache_entry(repair_ctx *R, uint32_t v, int n, int t)
{
    if (R->W->crease_v && R->W->crease_v[v])
        return NULL;
    size_t per = 1 + 4 * (size_t)n;
    if (!R->slot[v]) {
        size_t need = R->cache_used + N_VARIANTS * per;
        if (need >= UINT32_MAX)
            return NULL;
        if (need > R->cache_cap) {
            size_t cap = need > 2 * R->cache_cap ? need : 2 * R->cache_cap;
            double *c = sk__realloc_array(R->cache, cap, sizeof(double));
            if (!c)
                return NULL;
            R->cache = c;
            R->cache_cap = cap;
        }
        for (size_t t2 = 0; t2 < N_VARIANTS; ++t2)
            R->cache[R->cache_used + t2 * per] = -1.0;
        R->slot[v] = (uint32_t)(R->cache_used + 1);
        R->cache_used = need;
    }
    return R->cache + (R->slot[v] - 1) + (size_t)t * per;
}

/* vertex v's solution of variant t into W (from the cache when solved before); returns its code */
static int variant_solution(repair_ctx *R, uint32_t v, const uint32_t *E, int n, int t)
{
    sk__vc1_work *W = R->W;
    double *c = cache_entry(R, v, n, t);
    if (c && c[0] >= 0.0) {
        for (int k = 0; k < n; ++k) {
            W->w1[E[k]] = c[1 + k];
            memcpy(W->P + 3 * (size_t)E[k], c + 1 + n + 3 * k, 3 * sizeof(double));
        }
        return (int)c[0];
    }
    sk__vsys sys;
    int code = sk__vc1_solve_vertex(W, v, &sys, repair_variants[t][0], repair_variants[t][1]);
    if (c) {
        c[0] = code;
        for (int k = 0; k < n; ++k) {
            c[1 + k] = W->w1[E[k]];
            memcpy(c + 1 + n + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
        }
    }
    return code;
}

/* One try at candidate v: the variants of its vertex system, the best kept if it leaves fewer
 * singular patches around v. */
static void repair_vertex(repair_ctx *R, uint32_t v)
{
    sk_smooth *s = R->s;
    sk__vc1_work *W = R->W;
    const sk_mesh *m = W->m;
    uint32_t verts[SK_VSYS_MAX + 1], *faces = R->faces;
    size_t nverts;
    size_t nf = local_faces(m, v, R->mark, faces, LOCAL_FACES, verts, &nverts);
    size_t before = 0;
    uint32_t newest = 0;
    for (size_t i = 0; i < nf; ++i) {
        newest = R->changed[faces[i]] > newest ? R->changed[faces[i]] : newest;
        if (R->sing[faces[i]]) { /* the singular faces first (see rebuild_local) */
            uint32_t t = faces[before];
            faces[before++] = faces[i];
            faces[i] = t;
        }
    }
    if (before == 0 || (R->tried[v] && newest < R->tried[v]))
        return;
    ++R->tick;
    /* the plain solution of v, to restore */
    uint32_t E[SK_VSYS_MAX];
    int closed, n = sk__vc1_ordered_edges(m, v, E, &closed);
    double P0[3 * SK_VSYS_MAX], w0[SK_VSYS_MAX];
    for (int k = 0; k < n; ++k) {
        memcpy(P0 + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
        w0[k] = W->w1[E[k]];
    }
    size_t best = before;
    int best_variant = -1, best_code = R->status[v];
    for (int t = 0; t < (int)N_VARIANTS; ++t) {
        int code = variant_solution(R, v, E, n, t);
        if (code > R->status[v] || code >= 2)
            continue; /* never trade regularity for an angle violation or a failed system */
        size_t after = rebuild_local(s, W, verts, nverts, faces, nf, best);
        if (after < best) {
            best = after;
            best_variant = t;
            best_code = code;
        }
        if (best == 0)
            break; /* nothing left to gain: the later variants cannot do better */
    }
    if (best_variant >= 0) {
        variant_solution(R, v, E, n, best_variant);
        R->status[v] = (uint8_t)best_code;
        R->tried[v] = 0;
        ++R->repaired;
    } else {
        R->tried[v] = R->tick;
        for (int k = 0; k < n; ++k) {
            memcpy(W->P + 3 * (size_t)E[k], P0 + 3 * k, 3 * sizeof(double));
            W->w1[E[k]] = w0[k];
        }
    }
    rebuild_local(s, W, verts, nverts, faces, nf, 0);
    /* restored: the same solution gives the same patches, their flags stand */
    for (size_t i = 0; i < nf && best_variant >= 0; ++i) {
        uint8_t now = sk__patch_singular(s, faces[i], NULL);
        R->nsing = R->nsing - R->sing[faces[i]] + now;
        R->sing[faces[i]] = now;
        R->changed[faces[i]] = R->tick;
    }
}

/* the candidates of round 2: the corners of the patches still singular and their neighbours */
static void round_two_candidates(const sk_smooth *s, const sk_mesh *m, const uint8_t *sing,
                                 uint8_t *cand)
{
    memset(cand, 0, m->num_vertices);
    for (size_t p = 0; p < s->surface.count; ++p)
        if (sing[p])
            for (unsigned i = 0; i < sk_patch_num_corners(&s->surface.patches[p]); ++i) {
                uint32_t c = s->surface.patches[p].corner_ids[i], h0 = m->v_halfedge[c];
                uint32_t h = h0;
                cand[c] = 1;
                do {
                    cand[sk_to(m, h)] = 1;
                    h = sk_cw_out(m, h);
                } while (h != h0);
            }
}

sk_status sk__vc1_repair_regularity(sk_smooth *s, sk__vc1_work *W, uint8_t *status,
                                    const uint8_t *known, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t np = s->surface.count, nv = m->num_vertices;
    sk_status st = SK_OK;
    repair_ctx R = {.s = s, .W = W, .status = status};
    uint8_t *cand = sk__calloc_array(nv + 1, 1);
    R.sing = sk__malloc_array(np + 1, 1);
    R.mark = sk__calloc_array(np + 1, 1);
    R.faces = sk__malloc_array(LOCAL_FACES, sizeof *R.faces);
    R.tried = sk__calloc_array(nv + 1, sizeof *R.tried);
    R.slot = sk__calloc_array(nv + 1, sizeof *R.slot);
    R.changed = sk__calloc_array(np + 1, sizeof *R.changed);
    if (!cand || !R.sing || !R.mark || !R.faces || !R.tried || !R.slot || !R.changed) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in the regularity repair");
        goto done;
    }
    long npl = (long)np;
    size_t nsing = 0;
    uint8_t *sing = R.sing;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : nsing)
#endif
    for (long p = 0; p < npl; ++p) {
        sing[p] = known && known[p] != SK_SING_UNKNOWN ? known[p]
                                                       : sk__patch_singular(s, (size_t)p, NULL);
        nsing += sing[p];
    }
    s->stats.singular_before_repair = nsing;
    R.nsing = nsing;
    for (size_t p = 0; p < np && nsing; ++p)
        if (sing[p])
            for (unsigned i = 0; i < sk_patch_num_corners(&s->surface.patches[p]); ++i)
                cand[s->surface.patches[p].corner_ids[i]] = 1;
    for (int round = 0; round < 2 && R.nsing; ++round) {
        if (round == 1)
            round_two_candidates(s, m, sing, cand);
        for (uint32_t v = 0; v < nv && R.nsing; ++v)
            if (cand[v] && status[v] != 3)
                repair_vertex(&R, v);
    }
    s->stats.repaired_vertices = R.repaired;
done:
    sk__free(cand);
    sk__free(R.sing);
    sk__free(R.mark);
    sk__free(R.faces);
    sk__free(R.tried);
    sk__free(R.slot);
    sk__free(R.changed);
    sk__free(R.cache);
    return st;
}
