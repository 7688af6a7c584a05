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
 * has fewer than the plain construction. Then the corners of the patches still singular and
 * their neighbours again; then both ends of every edge of a patch still singular together
 * (repair_pairs), and those corners with a wider grid of variants (measured on the cow: the pairs
 * 8 -> 6 singular patches, the wide grid 9 -> 8; armadillo 3 -> 0). Sequential in vertex order:
 * deterministic. */

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
 * ones, stopping once the count reaches limit (the variant cannot win then). limit 0: every patch
 * assembled, none tested; else a patch is assembled just before its test, so the ones after the
 * stop keep stale points (nothing reads them before the rebuild with limit 0 that ends every
 * try). faces lists the ones singular before first, so a losing variant is usually found out
 * after a few tests; first (per patch) holds the sample that failed last (see
 * sk__patch_singular_from): a patch still singular fails there again, mostly. */
static size_t rebuild_local(sk_smooth *s, sk__vc1_work *W, uint8_t *first, const uint32_t *verts,
                            size_t nverts, const uint32_t *faces, size_t nf, size_t limit)
{
    for (size_t i = 0; i < nverts; ++i)
        sk__vc1_interior_points(W, verts[i]);
    size_t bad = 0;
    for (size_t i = 0; i < nf && (limit == 0 || bad < limit); ++i) {
        sk__vc1_assemble_patch(W, faces[i], sk_patch_cp(&s->surface, faces[i]));
        if (limit)
            bad += sk__patch_singular_from(s, faces[i], NULL, first + faces[i]);
    }
    return bad;
}

#define LOCAL_FACES 4096

/* the wider grid of the last round, tried only around the patches still singular after the
 * first two: blends 0, 1/4, 1/2, 3/4, 1 times length scales from 0.3 to 3.2 (the table's
 * blends are among these: see variant_at) */
static const double wide_blends[] = {0.0, 0.25, 0.5, 0.75, 1.0};
#define N_BLENDS (sizeof wide_blends / sizeof wide_blends[0])
static const double wide_scales[] = {0.3, 0.45, 0.6, 0.85, 1.15, 1.5, 2.0, 2.6, 3.2};
#define N_WIDE_S (sizeof wide_scales / sizeof wide_scales[0])
#define N_WIDE (N_BLENDS * N_WIDE_S)

/* entry of blend b in wide_blends (-1: none) */
static int blend_index(double b)
{
    for (size_t i = 0; i < N_BLENDS; ++i)
        if (wide_blends[i] == b)
            return (int)i;
    return -1;
}

/* The repair's state. A vertex's variant solutions depend only on fixed data (its targets, ratios
 * and normal), so they are kept once solved (`cache`, per vertex a slot of N_VARIANTS entries of
 * code, w1 and P of its edges) and reused when the vertex is tried again in round 2 and for the
 * winner. A vertex tried without gain is skipped later while none of the patches around it and
 * its neighbours changed since (the same try would give the same result): `tried` holds the tick
 * of that try, `changed` per patch the tick of the last gain that moved it (the wide round's
 * variants are not the table's: it neither skips nor caches). Crease vertices are
 * cached too: their sectors' fixed ends are their crease edges' wire frame targets, fixed data
 * (cow: they were solved afresh each time, half of the repair's CPU). */
typedef struct repair_ctx {
    sk_smooth *s;
    sk__vc1_work *W;
    uint8_t *status, *sing, *mark, *first; /* first: see rebuild_local */
    uint32_t *faces, *tried, *changed, *slot; /* slot: per vertex 1 + its cache slot, 0 none */
    double *cache;
    size_t cache_used, cache_cap, nsing, repaired;
    size_t late_budget; /* local rebuilds the wide and the pair rounds may still do */
    uint32_t tick;
} repair_ctx;

/* cache entry of variant t at vertex v (n edges): [0] code (-1 not solved yet), [1 .. n] w1,
 * then 3 n coordinates of P; NULL when v is not cached (out of memory) */
static double *cache_entry(repair_ctx *R, uint32_t v, int n, int t)
{
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

/* vertex v's solution of blend b and length scale ls into W, kept in (or taken from) its cache
 * entry slot (-1: none); returns its code */
static int solve_cached(repair_ctx *R, uint32_t v, const uint32_t *E, int n, int slot, double b,
                        double ls)
{
    sk__vc1_work *W = R->W;
    double *c = slot >= 0 ? cache_entry(R, v, n, slot) : NULL;
    if (c && c[0] >= 0.0) {
        for (int k = 0; k < n; ++k) {
            W->w1[E[k]] = c[1 + k];
            memcpy(W->P + 3 * (size_t)E[k], c + 1 + n + 3 * k, 3 * sizeof(double));
        }
        return (int)c[0];
    }
    sk__vsys sys;
    int code = sk__vc1_solve_vertex(W, v, &sys, b, ls);
    if (c) {
        c[0] = code;
        for (int k = 0; k < n; ++k) {
            c[1 + k] = W->w1[E[k]];
            memcpy(c + 1 + n + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
        }
    }
    return code;
}

/* The variant (blend b, length scale ls) of v's system into W; returns its code. At a vertex
 * without creases it is ls times the solution of blend b: (8) is homogeneous in the p (targets
 * scaled by ls scale the least-squares solution by ls, w unchanged) and neither the solver (it
 * works in units of the mean target length) nor the angle bounds see the scale, so one solve per
 * blend (cached in entry blend_index(b)) serves every scale. A crease vertex's fixed ends do not
 * scale: solved per variant, cached in entry table_t (-1: none). */
static int variant_at(repair_ctx *R, uint32_t v, const uint32_t *E, int n, double b, double ls,
                      int table_t)
{
    sk__vc1_work *W = R->W;
    if (W->crease_v && W->crease_v[v])
        return solve_cached(R, v, E, n, table_t, b, ls);
    int code = solve_cached(R, v, E, n, blend_index(b), b, 1.0);
    const double *V = W->m->positions + 3 * (size_t)v;
    for (int k = 0; k < n && ls != 1.0; ++k) {
        double *P = W->P + 3 * (size_t)E[k];
        for (int x = 0; x < 3; ++x)
            P[x] = V[x] + ls * (P[x] - V[x]);
    }
    return code;
}

/* variant t of the table */
static int variant_solution(repair_ctx *R, uint32_t v, const uint32_t *E, int n, int t)
{
    return variant_at(R, v, E, n, repair_variants[t][0], repair_variants[t][1], t);
}

/* the solution (tangents and weights) of v's edges E, saved or restored */
static void save_solution(const sk__vc1_work *W, const uint32_t *E, int n, double *P, double *w)
{
    for (int k = 0; k < n; ++k) {
        memcpy(P + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
        w[k] = W->w1[E[k]];
    }
}

static void restore_solution(sk__vc1_work *W, const uint32_t *E, int n, const double *P,
                             const double *w)
{
    for (int k = 0; k < n; ++k) {
        memcpy(W->P + 3 * (size_t)E[k], P + 3 * k, 3 * sizeof(double));
        W->w1[E[k]] = w[k];
    }
}

/* variant t of v's system into W: of the table (cached), or of the wide grid */
static int try_variant(repair_ctx *R, uint32_t v, const uint32_t *E, int n, int wide, int t)
{
    if (!wide)
        return variant_solution(R, v, E, n, t);
    return variant_at(R, v, E, n, wide_blends[(size_t)t / N_WIDE_S],
                      wide_scales[(size_t)t % N_WIDE_S], -1);
}

/* the patches faces[0, nf) rebuilt after a gain: their flags and change ticks */
static void take_gain(repair_ctx *R, const uint32_t *faces, size_t nf)
{
    for (size_t i = 0; i < nf; ++i) {
        uint8_t now = sk__patch_singular_from(R->s, faces[i], NULL, R->first + faces[i]);
        R->nsing = R->nsing - R->sing[faces[i]] + now;
        R->sing[faces[i]] = now;
        R->changed[faces[i]] = R->tick;
    }
    ++R->repaired;
}

/* singular faces first (see rebuild_local); returns how many */
static size_t singular_first(const uint8_t *sing, uint32_t *faces, size_t nf)
{
    size_t before = 0;
    for (size_t i = 0; i < nf; ++i)
        if (sing[faces[i]]) {
            uint32_t t = faces[before];
            faces[before++] = faces[i];
            faces[i] = t;
        }
    return before;
}

/* One try at candidate v: the variants of its vertex system (the table, or the wide grid within
 * the late budget), the best kept if it leaves fewer singular patches around v. */
static void repair_vertex(repair_ctx *R, uint32_t v, int wide)
{
    sk__vc1_work *W = R->W;
    const sk_mesh *m = W->m;
    uint32_t verts[SK_VSYS_MAX + 1], *faces = R->faces;
    size_t nverts;
    size_t nf = local_faces(m, v, R->mark, faces, LOCAL_FACES, verts, &nverts);
    uint32_t newest = 0;
    for (size_t i = 0; i < nf; ++i)
        newest = R->changed[faces[i]] > newest ? R->changed[faces[i]] : newest;
    size_t before = singular_first(R->sing, faces, nf);
    if (before == 0 || (!wide && R->tried[v] && newest < R->tried[v]))
        return;
    ++R->tick;
    /* the plain solution of v, to restore */
    uint32_t E[SK_VSYS_MAX];
    int closed, n = sk__vc1_ordered_edges(m, v, E, &closed);
    double P0[3 * SK_VSYS_MAX], w0[SK_VSYS_MAX];
    save_solution(W, E, n, P0, w0);
    size_t best = before;
    int best_variant = -1, best_code = R->status[v];
    int nvar = wide ? (int)N_WIDE : (int)N_VARIANTS;
    for (int t = 0; t < nvar; ++t) {
        if (wide && R->late_budget == 0)
            break;
        R->late_budget -= wide != 0;
        int code = try_variant(R, v, E, n, wide, t);
        if (code > R->status[v] || code >= 2)
            continue; /* never trade regularity for an angle violation or a failed system */
        size_t after = rebuild_local(R->s, W, R->first, verts, nverts, faces, nf, best);
        if (after < best) {
            best = after;
            best_variant = t;
            best_code = code;
        }
        if (best == 0)
            break; /* nothing left to gain: the later variants cannot do better */
    }
    if (best_variant >= 0) {
        try_variant(R, v, E, n, wide, best_variant);
        R->status[v] = (uint8_t)best_code;
        R->tried[v] = 0;
    } else {
        if (!wide)
            R->tried[v] = R->tick;
        restore_solution(W, E, n, P0, w0);
    }
    rebuild_local(R->s, W, R->first, verts, nverts, faces, nf, 0);
    /* restored: the same solution gives the same patches, their flags stand */
    if (best_variant >= 0)
        take_gain(R, faces, nf);
}

/* The faces of a pair a, b (R->faces: the union of both neighbourhoods, singular first; then
 * fb: the faces b's solution moves (around b and its neighbours), then fa: the others of the
 * union (they depend on a's solution alone), each singular first) and their vertices. */
typedef struct pair_faces {
    uint32_t *all, *fb, *fa, verts[2 * SK_VSYS_MAX + 2];
    size_t nall, nfb, nfa, na, nb;
} pair_faces;

static void gather_pair(repair_ctx *R, uint32_t a, uint32_t b, pair_faces *F)
{
    const sk_mesh *m = R->W->m;
    F->all = R->faces, F->fb = R->faces + LOCAL_FACES, F->fa = F->fb + LOCAL_FACES / 2;
    size_t nf = local_faces(m, a, R->mark, F->all, LOCAL_FACES / 2, F->verts, &F->na);
    F->nfb = local_faces(m, b, R->mark, F->fb, LOCAL_FACES / 2, F->verts + F->na, &F->nb);
    F->nall = nf;
    for (size_t i = 0; i < F->nfb; ++i)
        R->mark[F->fb[i]] = 1;
    F->nfa = 0;
    for (size_t i = 0; i < nf; ++i)
        if (!R->mark[F->all[i]])
            F->fa[F->nfa++] = F->all[i];
    for (size_t i = 0; i < F->nfb; ++i)
        R->mark[F->fb[i]] = 0;
    for (size_t i = 0; i < nf; ++i)
        R->mark[F->all[i]] = 1;
    for (size_t i = 0; i < F->nfb; ++i)
        if (!R->mark[F->fb[i]])
            F->all[F->nall++] = F->fb[i];
    for (size_t i = 0; i < nf; ++i)
        R->mark[F->all[i]] = 0;
    singular_first(R->sing, F->fb, F->nfb);
    singular_first(R->sing, F->fa, F->nfa);
}

/* The last resort for a patch still singular: the variants at both ends a, b of one of its
 * edges together (the boundary curve and the cross-boundary tangents along ab come from the two
 * vertex systems at once; one end alone was tried before). Keeps the best pair when it lowers
 * the singular patches around a and b. For each variant of a, the patches that b does not move
 * are rebuilt and tested once (their count is the same for every variant of b; when it reaches
 * the best, no variant of b can win), then for each variant of b only the patches it moves: the
 * same counts and choices as rebuilding all of them each time. */
static void repair_pair(repair_ctx *R, uint32_t a, uint32_t b)
{
    sk__vc1_work *W = R->W;
    const sk_mesh *m = W->m;
    uint8_t *status = R->status, *sing = R->sing;
    pair_faces F;
    gather_pair(R, a, b, &F);
    size_t before = singular_first(sing, F.all, F.nall);
    if (before == 0)
        return;
    ++R->tick;
    uint32_t Ea[SK_VSYS_MAX], Eb[SK_VSYS_MAX];
    int closed, n_a = sk__vc1_ordered_edges(m, a, Ea, &closed);
    int n_b = sk__vc1_ordered_edges(m, b, Eb, &closed);
    double Pa[3 * SK_VSYS_MAX], wa[SK_VSYS_MAX], Pb[3 * SK_VSYS_MAX], wb[SK_VSYS_MAX];
    save_solution(W, Ea, n_a, Pa, wa);
    save_solution(W, Eb, n_b, Pb, wb);
    size_t best = before;
    int best_s = -1, best_t = -1, code_a = status[a], code_b = status[b];
    for (int t = -1; t < (int)N_VARIANTS && best; ++t) {
        int ca = status[a];
        if (t >= 0) {
            ca = variant_solution(R, a, Ea, n_a, t);
            if (ca > status[a] || ca >= 2)
                continue;
        } else
            restore_solution(W, Ea, n_a, Pa, wa);
        size_t fixed = SIZE_MAX; /* singular patches b does not move, once rebuilt */
        for (int u = 0; u < (int)N_VARIANTS && best; ++u) {
            int cb = variant_solution(R, b, Eb, n_b, u);
            if (cb > status[b] || cb >= 2)
                continue;
            if (R->late_budget == 0)
                break; /* the bound of LATE_BUDGET */
            R->late_budget--;
            if (fixed == SIZE_MAX)
                fixed = rebuild_local(R->s, W, R->first, F.verts, F.na, F.fa, F.nfa, best);
            if (fixed >= best)
                continue; /* no variant of b can win with this one of a */
            size_t after = fixed + rebuild_local(R->s, W, R->first, F.verts + F.na, F.nb, F.fb,
                                                 F.nfb, best - fixed);
            if (after < best)
                best = after, best_s = t, best_t = u, code_a = ca, code_b = cb;
        }
    }
    if (best_t >= 0) {
        if (best_s >= 0)
            variant_solution(R, a, Ea, n_a, best_s);
        else
            restore_solution(W, Ea, n_a, Pa, wa);
        variant_solution(R, b, Eb, n_b, best_t);
        status[a] = (uint8_t)code_a;
        status[b] = (uint8_t)code_b;
    } else {
        restore_solution(W, Ea, n_a, Pa, wa);
        restore_solution(W, Eb, n_b, Pb, wb);
    }
    rebuild_local(R->s, W, R->first, F.verts, F.na + F.nb, F.all, F.nall, 0);
    if (best_t >= 0)
        take_gain(R, F.all, F.nall);
}

/* the pair round: every edge of every patch still singular */
static void repair_pairs(repair_ctx *R)
{
    const sk_mesh *m = R->W->m;
    for (uint32_t f = 0; f < m->num_faces && R->nsing && R->late_budget; ++f) {
        if (!R->sing[f])
            continue;
        uint32_t h0 = m->f_halfedge[f], h = h0;
        do {
            uint32_t a = sk_from(m, h), b = sk_to(m, h);
            if (R->status[a] != 3 && R->status[b] != 3)
                repair_pair(R, a, b);
            h = m->h_next[h];
        } while (h != h0 && R->sing[f]);
    }
}

/* candidates of the later rounds: the corners of the patches still singular and their
 * neighbours */
static void mark_around_singular(const sk_smooth *s, const sk_mesh *m, const uint8_t *sing,
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

/* The wide and the pair rounds together do at most LATE_BUDGET local rebuilds per patch of the
 * surface (the cow with the input's triangulation kept, 44-49 singular patches left, whole build
 * CPU: 1.6 s before these rounds, 4.4 s with them unbounded, 2.9 s with this bound; the default
 * cow keeps its 8 -> 6 at 1.1 s) */
#define LATE_BUDGET 1

/* rounds of the repair: the corners of the singular patches, then the patches still singular
 * and their neighbours with the same variants, then (after the pair round) with the wide grid */
#define REPAIR_ROUNDS 3

/* the ids of the patches still singular (s->stats.singular_after_repair of them) */
static sk_status list_singular(sk_smooth *s, const uint8_t *sing, uint32_t **out, sk_error *err)
{
    size_t n = s->stats.singular_after_repair, k = 0;
    if (!out || n == 0)
        return SK_OK;
    if (!(*out = sk__malloc_array(n, sizeof **out)))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the regularity repair");
    for (size_t p = 0; p < s->surface.count && k < n; ++p)
        if (sing[p])
            (*out)[k++] = (uint32_t)p;
    return SK_OK;
}

sk_status sk__vc1_repair_regularity(sk_smooth *s, sk__vc1_work *W, uint8_t *status,
                                    const uint8_t *known, uint32_t **singular, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t np = s->surface.count, nv = m->num_vertices;
    sk_status st = SK_OK;
    repair_ctx R = {.s = s, .W = W, .status = status, .late_budget = LATE_BUDGET * np};
    uint8_t *cand = sk__calloc_array(nv + 1, 1);
    R.sing = sk__malloc_array(np + 1, 1);
    R.mark = sk__calloc_array(np + 1, 1);
    R.first = sk__calloc_array(np + 1, 1);
    R.faces = sk__malloc_array(2 * LOCAL_FACES, sizeof *R.faces); /* see pair_faces */
    R.tried = sk__calloc_array(nv + 1, sizeof *R.tried);
    R.slot = sk__calloc_array(nv + 1, sizeof *R.slot);
    R.changed = sk__calloc_array(np + 1, sizeof *R.changed);
    if (!cand || !R.sing || !R.mark || !R.first || !R.faces || !R.tried || !R.slot || !R.changed) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in the regularity repair");
        goto done;
    }
    long npl = (long)np;
    size_t nsing = 0;
    uint8_t *sing = R.sing;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : nsing) if (npl >= SK_SMOOTH_TEAM_MIN)
#endif
    for (long p = 0; p < npl; ++p) {
        sing[p] = known && known[p] != SK_SING_UNKNOWN ? known[p]
                                                       : sk__patch_singular(s, (size_t)p, NULL);
        nsing += sing[p];
    }
    s->stats.singular_before_repair = nsing;
    R.nsing = nsing;
    if (nsing) /* only the repair's solves repeat (optional: without it every solve runs) */
        W->memo = sk__vsys_memo_create();
    for (size_t p = 0; p < np && nsing; ++p)
        if (sing[p])
            for (unsigned i = 0; i < sk_patch_num_corners(&s->surface.patches[p]); ++i)
                cand[s->surface.patches[p].corner_ids[i]] = 1;
    for (int round = 0; round < REPAIR_ROUNDS && R.nsing; ++round) {
        if (round == 2) /* the pairs first: they gained more than the wide grid */
            repair_pairs(&R);
        if (round > 0)
            mark_around_singular(s, m, sing, cand);
        for (uint32_t v = 0; v < nv && R.nsing; ++v)
            if (cand[v] && status[v] != 3)
                repair_vertex(&R, v, round == 2);
    }
    s->stats.repaired_vertices = R.repaired;
    s->stats.singular_after_repair = R.nsing;
    st = list_singular(s, sing, singular, err);
done:
    sk__free(cand);
    sk__free(R.sing);
    sk__free(R.mark);
    sk__free(R.first);
    sk__free(R.faces);
    sk__free(R.tried);
    sk__free(R.slot);
    sk__free(R.changed);
    sk__free(R.cache);
    sk__vsys_memo_destroy(W->memo);
    W->memo = NULL;
    return st;
}
