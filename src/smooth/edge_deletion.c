/* Edge deletion (Cottin & van Damme, section 3): delete interior edges of a triangle mesh so that
 * every interior vertex is surrounded by an odd number of faces, and every face is a triangle or a
 * quad.
 *
 * Near-minimal deletions (a minimum T-join, T the even interior vertices, approximated): first
 * the largest matching we can find of the edges joining two even vertices (Karp-Sipser, then
 * augmenting paths; see match_adjacent), each such pair costing the one edge of the lower bound;
 * then Algorithm Initialise for the rest.
 *
 * Algorithm Initialise: multi-source search from the unpaired even vertices; every edge where two
 * searches meet (or a boundary vertex one search reaches: boundary vertices may stay even, so they
 * absorb a path) is a candidate pair, of length dist(u) + dist(v) + 1; candidates are taken
 * cheapest per even vertex fixed first while both ends are unpaired ("grow distances until pairs
 * meet"; see cand_key). Rounds repeat with the vertices still unpaired. The distances count the
 * cost in deleted edges: crossing a matched edge removes it (0-1 distances, see
 * initialise_search).
 *
 * Algorithm Reduce Path: (1) cut loops at repeated vertices, (2) replace two consecutive edges of
 * one triangle by its third edge (Fig. 3).
 *
 * Algorithm Delete Even Edges, step 2, in the equivalent edge-set form: deleting the union of all
 * paths changes the parity of the face count exactly at the path ends, and so does the symmetric
 * difference of the paths. Case (2a) (paths sharing edges): shared edges cancel (the paper re-routes
 * the two paths so that the common part is used by neither). Case (2b) (an edge of path I and an
 * edge of path J in one triangle at the intersection point): the two edges are replaced by the third
 * edge of their triangle, which is what the paper's re-definition followed by Reduce Path does.
 * Both steps keep the parity of every vertex and strictly shrink the deleted set, so the loop ends;
 * at the end no triangle holds two deleted edges, so every face is a triangle or a quad.
 *
 * Then cycle exchanges (see shortcut_paths): the deleted set is a T-join, and xor with a closed walk
 * that holds more deleted than kept edges keeps every parity and shrinks it (a walk along a path
 * closed by a shorter kept path, or two paths re-paired at their ends); case (2b) again after them.
 * How far the result is from the optimum: bench/tjoin.sh (the exact minimum T-join by LEMON). */
#include "surfkit/smooth.h"
#include "smooth/smooth_internal.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct path_store {
    uint32_t *v;     /* vertices of all paths */
    uint32_t *start; /* path i: v[start[i] .. start[i + 1]) */
    size_t nv, cap_v, np, cap_p;
} path_store;

static int ps_push_vertex(path_store *ps, uint32_t v)
{
    if (ps->nv == ps->cap_v) {
        size_t cap = ps->cap_v ? 2 * ps->cap_v : 1024;
        uint32_t *p = sk__realloc_array(ps->v, cap, sizeof *p);
        if (!p)
            return 0;
        ps->v = p;
        ps->cap_v = cap;
    }
    ps->v[ps->nv++] = v;
    return 1;
}

static int ps_close_path(path_store *ps)
{
    if (ps->np + 2 > ps->cap_p) {
        size_t cap = ps->cap_p ? 2 * ps->cap_p : 256;
        uint32_t *p = sk__realloc_array(ps->start, cap, sizeof *p);
        if (!p)
            return 0;
        if (ps->cap_p == 0)
            p[0] = 0;
        ps->start = p;
        ps->cap_p = cap;
    }
    ps->start[++ps->np] = (uint32_t)ps->nv;
    return 1;
}

/* True when a, b, c are the corners of one (triangle) face. */
static bool is_face(const sk_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t h = sk__find_halfedge(m, a, b);
    if (h == SK_INVALID)
        return false;
    if (m->h_face[h] != SK_INVALID && sk_to(m, m->h_next[h]) == c)
        return true;
    uint32_t o = sk_opp(h);
    return m->h_face[o] != SK_INVALID && sk_to(m, m->h_next[o]) == c;
}

/* the edge a - b exists and is flagged in mflag */
static bool matched_edge(const sk_mesh *m, const uint8_t *mflag, uint32_t a, uint32_t b)
{
    uint32_t h = sk__find_halfedge(m, a, b);
    return h != SK_INVALID && mflag[sk_edge(h)];
}

/* Reduce Path on the vertex list p[0..n): returns the new length. where (per vertex, SK_INVALID
 * on entry and on return): the position of a vertex in the kept part (paths at 1M triangles are
 * long enough that a linear scan for loops was most of the edge deletion). */
static size_t reduce_path(const sk_mesh *m, const uint8_t *forbid, const uint8_t *mflag,
                          uint32_t *p, size_t n, uint32_t *where, size_t *reductions)
{
    /* (1) loops: keep the first occurrence, drop everything up to the last occurrence */
    size_t k = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t v = p[i], j = where[v];
        if (j != SK_INVALID) {
            for (size_t t = j + 1; t < k; ++t)
                where[p[t]] = SK_INVALID;
            k = j + 1; /* cut the loop p[j] .. p[i] */
            ++*reductions;
            continue;
        }
        where[v] = (uint32_t)k;
        p[k++] = v;
    }
    for (size_t t = 0; t < k; ++t)
        where[p[t]] = SK_INVALID;
    n = k;
    /* (2) two consecutive edges of one triangle -> its third edge */
    k = 0;
    for (size_t i = 0; i < n; ++i) {
        p[k++] = p[i];
        while (k >= 3 && is_face(m, p[k - 3], p[k - 2], p[k - 1])) {
            uint32_t h = sk__find_halfedge(m, p[k - 3], p[k - 1]);
            if (h == SK_INVALID || sk_is_boundary_e(m, sk_edge(h)) || forbid[sk_edge(h)])
                break;
            /* a path that crosses a matched edge removes it: a short cut there would keep it
             * and add one (case (2b) still resolves the triangle after the union) */
            if (matched_edge(m, mflag, p[k - 3], p[k - 2]) ||
                matched_edge(m, mflag, p[k - 2], p[k - 1]))
                break;
            p[k - 2] = p[k - 1];
            --k;
            ++*reductions;
        }
    }
    return k;
}

/* Quads with a corner angle near pi make the vertex systems hard (the angle bound of section 4)
 * and the patches nearly singular; an edge whose deletion would make a quad corner larger than
 * this (sum of the two triangle angles at an end point) is avoided by the paths, except where an
 * even vertex has no other choice. */
#define SK_MAX_QUAD_CORNER_DEG 160.0

/* cosine and sine of the corner angle at from(h) in face(h) */
static void corner_cos_sin(const sk_mesh *m, uint32_t h, double *c, double *s)
{
    const double *v = m->positions + 3 * (size_t)sk_from(m, h);
    const double *a = m->positions + 3 * (size_t)sk_to(m, h);
    const double *b = m->positions + 3 * (size_t)sk_from(m, m->h_prev[h]);
    double x[3], y[3], k[3];
    for (int i = 0; i < 3; ++i) {
        x[i] = a[i] - v[i];
        y[i] = b[i] - v[i];
    }
    k[0] = x[1] * y[2] - x[2] * y[1];
    k[1] = x[2] * y[0] - x[0] * y[2];
    k[2] = x[0] * y[1] - x[1] * y[0];
    double n = sqrt((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) *
                    (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]));
    if (!(n > 0.0)) {
        *c = 1.0;
        *s = 0.0;
        return;
    }
    *c = (x[0] * y[0] + x[1] * y[1] + x[2] * y[2]) / n;
    *s = sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]) / n;
}

/* the corner angle at from(h) in face(h), in [0, pi] */
static double corner_angle(const sk_mesh *m, uint32_t h)
{
    double c, sn;
    corner_cos_sin(m, h, &c, &sn);
    return atan2(sn, c);
}

/* true when the two corners h1, h2 (angles in [0, pi]) sum to more than SK_MAX_QUAD_CORNER_DEG:
 * the sum is above pi when its sine is negative, else compare its cosine (no atan2 per edge) */
static bool corner_sum_above(const sk_mesh *m, uint32_t h1, uint32_t h2, double cos_max)
{
    double c1, s1, c2, s2;
    corner_cos_sin(m, h1, &c1, &s1);
    corner_cos_sin(m, h2, &c2, &s2);
    double cs = c1 * c2 - s1 * s2, sn = s1 * c2 + c1 * s2;
    return sn < 0.0 || cs < cos_max;
}

/* deleting interior edge e makes a quad corner above SK_MAX_QUAD_CORNER_DEG */
static bool deletion_forbidden(const sk_mesh *m, uint32_t e, double cos_max)
{
    uint32_t h = 2 * e, o = h + 1;
    return corner_sum_above(m, h, m->h_next[o], cos_max) ||
           corner_sum_above(m, o, m->h_next[h], cos_max);
}

/* largest quad corner (degrees) created by deleting interior edge e */
static double deletion_corner(const sk_mesh *m, uint32_t e)
{
    uint32_t h = 2 * e, o = h + 1;
    double at_a = corner_angle(m, h) + corner_angle(m, m->h_next[o]);
    double at_b = corner_angle(m, o) + corner_angle(m, m->h_next[h]);
    return fmax(at_a, at_b) * (180.0 / 3.14159265358979323846);
}

typedef struct cand {
    uint32_t len;
    uint32_t u, v; /* meeting edge (u, v), or v == SK_INVALID: u is a boundary vertex */
} cand;

/* A candidate's cost per even vertex it fixes, times 4: a pair fixes two at len edges (2 len), a
 * boundary path one (4 len, + 1 so that a pair of equal cost per vertex goes first). Sorting by
 * len alone takes a boundary path of length 1 before a pair of length 1 beside it, and so two
 * boundary paths where one pair would do. */
static uint64_t cand_key(const cand *c)
{
    return c->v == SK_INVALID ? 4 * (uint64_t)c->len + 1 : 2 * (uint64_t)c->len;
}

static int cand_cmp(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    uint64_t kx = cand_key(x), ky = cand_key(y);
    if (kx != ky)
        return kx < ky ? -1 : 1;
    if (x->u != y->u)
        return x->u < y->u ? -1 : 1;
    return (x->v > y->v) - (x->v < y->v);
}

static void merge_across_edge(sk_mesh *m, uint32_t e)
{
    uint32_t h = 2 * e, o = 2 * e + 1;
    uint32_t fh = m->h_face[h], fo = m->h_face[o];
    uint32_t hp = m->h_prev[h], hn = m->h_next[h], op = m->h_prev[o], on = m->h_next[o];
    m->h_next[hp] = on;
    m->h_prev[on] = hp;
    m->h_next[op] = hn;
    m->h_prev[hn] = op;
    uint32_t g = on;
    while (g != hn) {
        m->h_face[g] = fh;
        g = m->h_next[g];
    }
    m->f_halfedge[fh] = hn;
    uint32_t a = sk_from(m, h), b = sk_to(m, h);
    if (m->v_halfedge[a] == h)
        m->v_halfedge[a] = on;
    if (m->v_halfedge[b] == o)
        m->v_halfedge[b] = hn;
    m->e_deleted[e] = 1;
    m->f_deleted[fo] = 1;
    m->num_deleted_edges++;
    m->num_deleted_faces++;
}

/* Per vertex, everything one step of Initialise's search reads and writes, in one place: the
 * search visits the vertices in an order unrelated to their ids, and the state spread over
 * separate arrays cost a cache miss per array and neighbour (most of the edge deletion at 832k
 * triangles). The search numbers the vertices in breadth-first order (ed_state.perm: neighbours
 * get near ids, so their states share cache lines and pages); vs, adj, pred, via and mate use
 * those ids, src and the candidates the mesh's (the tie-breaks stay the mesh order's). dist,
 * src, pred, via: see initialise_search; mate: the matched edge's other end (ed_state.medge,
 * copied before the first round, cleared by the pairing); flags: ED_DONE, ED_BND. */
typedef struct ed_vstate {
    uint32_t dist, src, pred, via, mate, flags;
} ed_vstate;

#define ED_DONE 1u
#define ED_BND 2u

/* The state of one run: per-vertex and per-edge arrays, the paths, the statistics. */
typedef struct ed_state {
    const sk_mesh *m;
    size_t nv, ne, nf;
    uint8_t *even, *bnd; /* per vertex: even interior vertex, boundary vertex (or crease vertex) */
    const uint8_t *crease; /* per edge: a crease edge, kept (NULL = none) */
    const uint8_t *avoid;  /* per edge: not to be deleted (NULL = none), as forbid */
    uint8_t *dcnt;       /* per edge: deleted (after the union of the paths) */
    uint8_t *forbid;     /* per edge: deleting it makes a quad corner above the limit */
    uint32_t *queue, *pred, *partner;
    uint32_t *medge;     /* per vertex: its mate across a matched (deleted) edge, or SK_INVALID */
    uint8_t *mflag;      /* per edge: an edge of the matching of adjacent even vertices */
    ed_vstate *vs;       /* Initialise's 0-1 search (see initialise_search) */
    uint32_t *levelq;    /* the search's two level queues, nv + 1 entries each */
    uint32_t *adj_off, *adj; /* the search's graph: v's allowed neighbours adj[adj_off[v] ..) */
    uint32_t *perm, *iperm;  /* the search's vertex order: new id perm[v], vertex iperm[i] */
    uint32_t *remaining; /* even vertices not yet paired */
    size_t nrem;
    cand *cands;
    size_t nc, cap_c;
    path_store ps;
    bool try_all; /* the cycle exchanges try every even vertex in order (no pre-pass) */
    uint32_t *trace; /* when tracing: the vertex of every exchange applied, in order */
    size_t ntrace, cap_trace;
    bool tracing, trace_nomem;
    sk_edge_deletion_stats st;
} ed_state;

static sk_status ed_alloc(ed_state *S, sk_error *err)
{
    size_t nv = S->nv, ne = S->ne;
    S->even = sk__calloc_array(nv ? nv : 1, 1);
    S->bnd = sk__calloc_array(nv ? nv : 1, 1);
    S->queue = sk__malloc_array(nv + 1, sizeof *S->queue);
    S->pred = sk__malloc_array(nv + 1, sizeof *S->pred);
    S->partner = sk__malloc_array(nv + 1, sizeof *S->partner);
    S->remaining = sk__malloc_array(nv + 1, sizeof *S->remaining);
    S->dcnt = sk__calloc_array(ne ? ne : 1, 1);
    S->forbid = sk__calloc_array(ne ? ne : 1, 1);
    S->medge = sk__malloc_array(nv + 1, sizeof *S->medge);
    S->mflag = sk__calloc_array(ne ? ne : 1, 1);
    S->vs = sk__malloc_array(nv + 1, sizeof *S->vs);
    S->levelq = sk__malloc_array(2 * nv + 2, sizeof *S->levelq);
    S->adj_off = sk__malloc_array(nv + 1, sizeof *S->adj_off);
    S->adj = sk__malloc_array(2 * ne + 1, sizeof *S->adj);
    S->perm = sk__malloc_array(nv + 1, sizeof *S->perm);
    S->iperm = sk__malloc_array(nv + 1, sizeof *S->iperm);
    if (!S->medge || !S->mflag || !S->vs || !S->levelq || !S->adj_off || !S->adj || !S->perm || !S->iperm ||
        !S->even || !S->bnd || !S->queue || !S->pred ||
        !S->partner || !S->remaining || !S->dcnt || !S->forbid)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
    return SK_OK;
}

static void ed_free(ed_state *S)
{
    sk__free(S->even);
    sk__free(S->bnd);
    sk__free(S->dcnt);
    sk__free(S->forbid);
    sk__free(S->queue);
    sk__free(S->pred);
    sk__free(S->partner);
    sk__free(S->remaining);
    sk__free(S->medge);
    sk__free(S->mflag);
    sk__free(S->vs);
    sk__free(S->levelq);
    sk__free(S->adj_off);
    sk__free(S->adj);
    sk__free(S->perm);
    sk__free(S->iperm);
    sk__free(S->cands);
    sk__free(S->ps.v);
    sk__free(S->ps.start);
}

/* The even interior vertices (the N of section 3 are half their number), the boundary vertices,
 * and the edges whose deletion would make a quad corner above SK_MAX_QUAD_CORNER_DEG (avoided by
 * the paths; an even vertex with every edge forbidden keeps its best one). */
static void find_even_vertices(ed_state *S)
{
    const sk_mesh *m = S->m;
    S->nrem = 0;
    /* a vertex on a crease is cut into sectors whose systems are chains, like a boundary
     * vertex's: it needs no parity, and an edge joining two such vertices is never deleted */
    for (uint32_t e = 0; S->crease && e < S->ne; ++e)
        if (S->crease[e] && !m->e_deleted[e])
            S->bnd[sk_from(m, 2 * e)] = S->bnd[sk_to(m, 2 * e)] = 1;
    long nvl = (long)S->nv;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nvl > 100000)
#endif
    for (long i = 0; i < nvl; ++i) {
        uint32_t v = (uint32_t)i;
        S->partner[v] = SK_INVALID;
        S->medge[v] = SK_INVALID;
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        S->bnd[v] |= sk_is_boundary_v(m, v);
        S->even[v] = !S->bnd[v] && (sk_mesh_valence(m, v) & 1u) == 0;
    }
    for (uint32_t v = 0; v < S->nv; ++v)
        if (S->even[v])
            S->remaining[S->nrem++] = v;
    S->st.even_vertices = S->nrem;
    double cos_max = cos(SK_MAX_QUAD_CORNER_DEG * (3.14159265358979323846 / 180.0));
    long ne = (long)S->ne;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (ne > 100000)
#endif
    for (long e = 0; e < ne; ++e)
        if (!m->e_deleted[e] && !sk_is_boundary_e(m, (uint32_t)e))
            S->forbid[e] = deletion_forbidden(m, (uint32_t)e, cos_max) || (S->avoid && S->avoid[e]);
    for (size_t i = 0; i < S->nrem; ++i) {
        uint32_t v = S->remaining[i], h0 = m->v_halfedge[v], h = h0, best = SK_INVALID;
        double best_c = 1e300;
        bool any = false;
        do {
            any |= !S->forbid[sk_edge(h)];
            h = sk_cw_out(m, h);
        } while (h != h0 && !any);
        if (any)
            continue;
        do {
            uint32_t e = sk_edge(h);
            double c = deletion_corner(m, e);
            if (c < best_c) {
                best_c = c;
                best = e;
            }
            h = sk_cw_out(m, h);
        } while (h != h0 && !any);
        if (!any && best != SK_INVALID) {
            S->forbid[best] = 0;
            S->st.forced_edges++;
        }
    }
    S->st.lower_bound = (S->nrem + 1) / 2;
}

/* The counting argument: a closed component needs an even number of even vertices (checked on
 * the components of order_search_vertices: root, vertices, even vertices of the first that fails). */
typedef struct parity_fail {
    uint32_t root;
    size_t n_vert, n_even;
} parity_fail;

static sk_status parity_error(const parity_fail *pf, sk_error *err)
{
    return sk__fail(err, SK_ERR_TOPOLOGY,
                    "closed component of vertex %u: %zu vertices, odd, so its %zu even vertices "
                    "are odd in number (Euler: sum (6-n) V_n = 6 chi) and cannot be paired; no "
                    "edge deletion exists (--allow-split splits an edge)",
                    pf->root, pf->n_vert, pf->n_even);
}

static bool push_cand(ed_state *S, cand c)
{
    if (S->nc == S->cap_c) {
        size_t cap = S->cap_c ? 2 * S->cap_c : 4096;
        cand *p = sk__realloc_array(S->cands, cap, sizeof *p);
        if (!p)
            return false;
        S->cands = p;
        S->cap_c = cap;
    }
    S->cands[S->nc++] = c;
    return true;
}

/* One round of Initialise, the search: from every unpaired even vertex at once, over edges that
 * are not forbidden; a meeting edge of two searches, or a boundary vertex a search reaches, is a
 * candidate of length dist(u) + dist(v) + 1 (resp. dist).
 *
 * The distance counts what a path costs once it is added to the deleted set D (the matched edges
 * so far) as a symmetric difference: an edge not in D costs 1, an edge of D it crosses is removed
 * and saves 1. So after an edge x - a into a matched vertex a, the search steps on along a's
 * matched edge to its mate b at no cost (b inherits a's parity fix, a keeps one deleted edge):
 * distances are 0-1, and b remembers a in via[b]. Any path, whatever it crosses, changes the
 * parity exactly at its ends, so the result stays an edge deletion.
 *
 * The vertices are finished level by level, first in, first out within a level: a zero-cost step
 * appends to the current level's queue, a unit step to the next level's. (A double-ended queue,
 * zero-cost steps at its front, finishes the same distances, but near a near-perfect matching,
 * where most of the mesh is at distance 0 through alternating paths, the first source popped
 * claims all of it depth first, and a round pairs few sources: 12 rounds on bunny00 Loop x2.)
 * A vertex enters each level's queue at most once (its distance only drops from d + 1 to d). */
static sk_status initialise_search(ed_state *S, sk_error *err)
{
    uint32_t *cur = S->levelq, *next = S->levelq + S->nv + 1; /* levels d and d + 1 */
    size_t ch = 0, ct = 0, nt = 0;
    ed_vstate *vs = S->vs;
    const uint32_t *adj = S->adj, *off = S->adj_off;
    const uint32_t *iperm = S->iperm;
    for (uint32_t v = 0; v < S->nv; ++v) {
        vs[v].dist = vs[v].pred = vs[v].via = SK_INVALID;
        vs[v].flags &= ~ED_DONE;
    }
    for (size_t i = 0; i < S->nrem; ++i) {
        uint32_t v = S->remaining[i], vn = S->perm[v];
        vs[vn].dist = 0;
        vs[vn].src = v;
        cur[ct++] = vn;
    }
    S->nc = 0;
    for (;;) {
        if (ch == ct) {
            if (nt == 0)
                break;
            uint32_t *t = cur;
            cur = next;
            next = t;
            ch = 0;
            ct = nt;
            nt = 0;
        }
        uint32_t v = cur[ch++];
        ed_vstate *x = vs + v;
        if (x->flags & ED_DONE)
            continue;
        x->flags |= ED_DONE;
        if (x->flags & ED_BND) {
            /* boundary vertices end paths, the search does not pass them */
            if (!push_cand(S, (cand){x->dist, iperm[v], SK_INVALID}))
                return sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
            continue;
        }
        uint32_t dv = x->dist, sv = x->src, mv = x->mate;
        for (uint32_t k = off[v]; k < off[v + 1]; ++k) {
            uint32_t w = adj[k];
            ed_vstate *y = vs + w;
            if (mv == w) {
                /* a matched edge is only crossed right after entering its end */
            } else if (y->flags & ED_DONE) {
                /* a meeting edge, seen from its endpoint finished last */
                if (y->src != sv && !(y->flags & ED_BND) &&
                    !push_cand(S, (cand){dv + y->dist + 1, iperm[v], iperm[w]}))
                    return sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
            } else {
                if (y->dist == SK_INVALID) {
                    y->dist = dv + 1;
                    y->src = sv;
                    y->pred = v;
                    y->via = SK_INVALID;
                    next[nt++] = w;
                }
                uint32_t b = y->mate;
                ed_vstate *z = vs + b;
                if (b != SK_INVALID && !(z->flags & ED_DONE) &&
                    (z->dist == SK_INVALID || z->dist > dv)) {
                    z->dist = dv;
                    z->src = sv;
                    z->pred = v;
                    z->via = w;
                    cur[ct++] = b;
                }
            }
        }
    }
    return SK_OK;
}

/* The search's vertex order (once, before the matching): breadth first over the mesh from each
 * vertex not yet numbered, iperm doubling as the queue. Each search from a vertex with edges is
 * one component, on which the counting argument is checked: pf->root gets the first component
 * (by its lowest vertex) that fails it, SK_INVALID when none does. Reads the mesh, even and bnd
 * only (run_deletion runs it beside the matching). */
static void order_search_vertices(ed_state *S, parity_fail *pf)
{
    const sk_mesh *m = S->m;
    uint32_t *perm = S->perm, *iperm = S->iperm, k = 0;
    pf->root = SK_INVALID;
    for (uint32_t v = 0; v < S->nv; ++v)
        perm[v] = SK_INVALID;
    for (uint32_t s0 = 0; s0 < S->nv; ++s0) {
        if (perm[s0] != SK_INVALID)
            continue;
        uint32_t qh = k, start = k;
        size_t n_even = 0;
        bool has_boundary = false;
        perm[s0] = k;
        iperm[k++] = s0;
        while (qh < k) {
            uint32_t v = iperm[qh++], h0 = m->v_halfedge[v], h = h0;
            if (m->v_deleted[v] || h0 == SK_INVALID)
                continue;
            n_even += S->even[v];
            has_boundary |= S->bnd[v];
            do {
                uint32_t w = sk_to(m, h);
                if (perm[w] == SK_INVALID) {
                    perm[w] = k;
                    iperm[k++] = w;
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
        if (pf->root == SK_INVALID && !m->v_deleted[s0] && m->v_halfedge[s0] != SK_INVALID &&
            !has_boundary && (n_even & 1u))
            *pf = (parity_fail){s0, k - start, n_even};
    }
}

/* The search's per-vertex state: the mates (after the matching) and the boundary flags. */
static void search_states(ed_state *S)
{
    const uint32_t *perm = S->perm, *iperm = S->iperm;
    for (uint32_t i = 0; i < S->nv; ++i) {
        uint32_t v = iperm[i], mate = S->medge[v];
        S->vs[i].mate = mate == SK_INVALID ? SK_INVALID : perm[mate];
        S->vs[i].flags = S->bnd[v] ? ED_BND : 0u;
    }
}

/* The search's graph: for every vertex (in the search's order), its neighbours across edges that
 * are not forbidden, in the order of sk_cw_out from v_halfedge (the order the search relaxes
 * them, so ties resolve as they would over the half-edges). Rebuilt when the forbidden edges are
 * relaxed. */
static void build_search_graph(ed_state *S)
{
    const sk_mesh *m = S->m;
    uint32_t k = 0;
    for (uint32_t i = 0; i < S->nv; ++i) {
        uint32_t v = S->iperm[i], h0 = m->v_halfedge[v], h = h0;
        S->adj_off[i] = k;
        if (m->v_deleted[v] || h0 == SK_INVALID)
            continue;
        do {
            if (!S->forbid[sk_edge(h)])
                S->adj[k++] = S->perm[sk_to(m, h)];
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
    S->adj_off[S->nv] = k;
}

/* the search path from x (a search id) back to its source: x, (via), pred, ... as vertices */
static bool push_chain(ed_state *S, uint32_t x)
{
    for (; x != SK_INVALID; x = S->vs[x].pred) {
        if (!ps_push_vertex(&S->ps, S->iperm[x]))
            return false;
        if (S->vs[x].via != SK_INVALID && !ps_push_vertex(&S->ps, S->iperm[S->vs[x].via]))
            return false;
    }
    return true;
}

/* One round of Initialise, the pairing: candidates in cand_cmp's order while both ends are
 * unpaired; each pairing stores its path (a ... u, then v ... b). The matched edges a path crosses
 * leave the matching (a later round must not count them again). Returns the number of pairs made,
 * or -1 when out of memory. */
static long initialise_pair(ed_state *S)
{
    path_store *ps = &S->ps;
    qsort(S->cands, S->nc, sizeof *S->cands, cand_cmp);
    long paired = 0;
    for (size_t i = 0; i < S->nc; ++i) {
        cand c = S->cands[i];
        uint32_t un = S->perm[c.u], vn = c.v == SK_INVALID ? SK_INVALID : S->perm[c.v];
        uint32_t a = S->vs[un].src, b = vn == SK_INVALID ? SK_INVALID : S->vs[vn].src;
        if (S->partner[a] != SK_INVALID || (b != SK_INVALID && S->partner[b] != SK_INVALID))
            continue;
        size_t first = ps->nv;
        if (!push_chain(S, un))
            return -1;
        for (size_t i0 = first, i1 = ps->nv - 1; i0 < i1; ++i0, --i1) {
            uint32_t t = ps->v[i0];
            ps->v[i0] = ps->v[i1];
            ps->v[i1] = t;
        }
        if (b != SK_INVALID && !push_chain(S, vn))
            return -1;
        if (!ps_close_path(ps))
            return -1;
        for (size_t k = first; k < ps->nv; ++k) {
            uint32_t x = S->perm[ps->v[k]], y = S->vs[x].mate;
            if (y != SK_INVALID) {
                S->vs[x].mate = SK_INVALID;
                S->vs[y].mate = SK_INVALID;
            }
        }
        S->st.path_edges += ps->nv - first - 1;
        S->partner[a] = b == SK_INVALID ? c.u : b;
        if (b != SK_INVALID) {
            S->partner[b] = a;
            S->st.pairs++;
        } else {
            S->st.boundary_paths++;
        }
        ++paired;
    }
    return paired;
}

/* Matching of adjacent even vertices (before Initialise). Deleting the edge between two even
 * vertices fixes both at the cost of one edge, so the lower bound #even / 2 is met exactly when the
 * even vertices have a perfect matching in the graph G1 of the edges joining two of them (a
 * matching never puts two deleted edges into one triangle). The minimum T-join, of which the
 * lower bound is the ideal case, pairs as many even vertices as possible at distance 1, so the
 * largest matching of G1 comes first: Karp-Sipser (a vertex with one free neighbour is matched to
 * it; else the next free vertex to its free neighbour with the fewest free neighbours), then
 * augmenting paths found by bounded alternating breadth-first searches (no blossom shrinking, so
 * a few are missed). Only the even vertices still free go on to Initialise, whose shortest paths
 * may run through matched vertices (shared edges cancel, case (2a)). */

/* free even neighbour of v across an allowed edge */
static bool g1_edge(const ed_state *S, uint32_t h)
{
    uint32_t w = sk_to(S->m, h);
    return S->even[w] && S->partner[w] == SK_INVALID && !S->forbid[sk_edge(h)];
}

static void g1_match(ed_state *S, uint32_t a, uint32_t b, uint32_t *deg, uint32_t *stack,
                     size_t *sp)
{
    const sk_mesh *m = S->m;
    S->partner[a] = b;
    S->partner[b] = a;
    uint32_t ends[2] = {a, b};
    for (int k = 0; k < 2; ++k) {
        uint32_t h0 = m->v_halfedge[ends[k]], h = h0;
        do {
            if (g1_edge(S, h)) {
                uint32_t x = sk_to(m, h);
                if (--deg[x] == 1)
                    stack[(*sp)++] = x;
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
}

/* Karp-Sipser greedy matching of G1 (deg and stack: scratch of nv entries). */
static void g1_greedy(ed_state *S, uint32_t *deg, uint32_t *stack)
{
    const sk_mesh *m = S->m;
    size_t sp = 0;
    for (size_t i = 0; i < S->nrem; ++i) {
        uint32_t v = S->remaining[i], h0 = m->v_halfedge[v], h = h0, d = 0;
        do {
            d += g1_edge(S, h);
            h = sk_cw_out(m, h);
        } while (h != h0);
        deg[v] = d;
        if (d == 1)
            stack[sp++] = v;
    }
    size_t next = 0;
    for (;;) {
        uint32_t v = SK_INVALID;
        while (sp > 0 && v == SK_INVALID) {
            uint32_t x = stack[--sp];
            if (S->partner[x] == SK_INVALID && deg[x] > 0)
                v = x;
        }
        while (v == SK_INVALID && next < S->nrem) {
            uint32_t x = S->remaining[next++];
            if (S->partner[x] == SK_INVALID && deg[x] > 0)
                v = x;
        }
        if (v == SK_INVALID)
            break;
        uint32_t h0 = m->v_halfedge[v], h = h0, best = SK_INVALID;
        do {
            if (g1_edge(S, h) && (best == SK_INVALID || deg[sk_to(m, h)] < deg[best]))
                best = sk_to(m, h);
            h = sk_cw_out(m, h);
        } while (h != h0);
        g1_match(S, v, best, deg, stack, &sp);
    }
}

/* Vertices one alternating search may label before it gives up: the augmenting paths that
 * matter are short, and the bound keeps a search that finds none from scanning the mesh. */
#define SK_AUGMENT_MAX_LABELS 512

/* One alternating search in G1 from the free even vertex r; on success the augmenting path is
 * flipped (one more matched pair). stamp/label: per-vertex scratch, pred the search tree. */
static bool g1_augment(ed_state *S, uint32_t r, uint32_t *stamp, uint32_t cur)
{
    const sk_mesh *m = S->m;
    size_t qh = 0, qt = 0, labels = 1;
    stamp[r] = cur;
    S->pred[r] = SK_INVALID;
    S->queue[qt++] = r;
    while (qh < qt && labels < SK_AUGMENT_MAX_LABELS) {
        uint32_t x = S->queue[qh++]; /* an outer vertex: r, or reached through its matched edge */
        uint32_t h0 = m->v_halfedge[x], h = h0;
        do {
            uint32_t y = sk_to(m, h);
            if (S->even[y] && !S->forbid[sk_edge(h)] && y != S->partner[x] && stamp[y] != cur) {
                if (S->partner[y] == SK_INVALID) {
                    /* r ... x - y: unmatched and matched edges alternate; flip them */
                    uint32_t a = x, b = y;
                    for (;;) {
                        uint32_t inner = a == r ? SK_INVALID : S->pred[a];
                        S->partner[a] = b;
                        S->partner[b] = a;
                        if (a == r)
                            break;
                        b = inner;
                        a = S->pred[inner];
                    }
                    return true;
                }
                uint32_t z = S->partner[y];
                stamp[y] = cur;
                S->pred[y] = x;
                labels++;
                if (stamp[z] != cur) {
                    stamp[z] = cur;
                    S->pred[z] = y;
                    S->queue[qt++] = z;
                    labels++;
                }
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
    return false;
}

/* Passes over the free even vertices while they find augmenting paths. */
#define SK_AUGMENT_PASSES 4

static sk_status match_adjacent(ed_state *S, sk_error *err)
{
    size_t nv = S->nv;
    uint32_t *deg = sk__malloc_array(nv + 1, sizeof *deg);
    uint32_t *scratch = sk__malloc_array(nv + 1, sizeof *scratch);
    sk_status st = SK_OK;
    if (!deg || !scratch) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
        goto done;
    }
    g1_greedy(S, deg, scratch);
    /* scratch becomes the search stamp */
    memset(scratch, 0, (nv + 1) * sizeof *scratch);
    uint32_t cur = 0;
    for (int pass = 0; pass < SK_AUGMENT_PASSES; ++pass) {
        size_t found = 0;
        for (size_t i = 0; i < S->nrem; ++i) {
            uint32_t v = S->remaining[i];
            if (S->partner[v] == SK_INVALID && g1_augment(S, v, scratch, ++cur))
                found++;
        }
        S->st.augmenting_paths += found;
        if (found == 0)
            break;
    }
    /* the matched pairs as paths of one edge; the free vertices stay for Initialise */
    size_t k = 0;
    for (size_t i = 0; i < S->nrem; ++i) {
        uint32_t v = S->remaining[i], w = S->partner[v];
        if (w == SK_INVALID) {
            S->remaining[k++] = v;
            continue;
        }
        S->medge[v] = w;
        if (v > w)
            continue;
        S->mflag[sk_edge(sk__find_halfedge(S->m, v, w))] = 1;
        if (!ps_push_vertex(&S->ps, v) || !ps_push_vertex(&S->ps, w) || !ps_close_path(&S->ps)) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
            goto done;
        }
        S->st.pairs++;
        S->st.adjacent_pairs++;
        S->st.path_edges++;
    }
    S->nrem = k;
done:
    sk__free(deg);
    sk__free(scratch);
    return st;
}

/* Algorithm Initialise (section 3): pair the even vertices (or connect them to the boundary) by
 * growing distances until searches meet; rounds repeat with the vertices still unpaired. */
static sk_status initialise(ed_state *S, sk_error *err)
{
    bool relaxed_forbid = false;
    if (S->nrem > 0)
        search_states(S); /* the order and the graph: before the matching (run_deletion) */
    while (S->nrem > 0) {
        S->st.initialise_rounds++;
        sk_status st = initialise_search(S, err);
        if (st)
            return st;
        long paired = initialise_pair(S);
        if (paired < 0)
            return sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
        size_t k = 0;
        for (size_t i = 0; i < S->nrem; ++i)
            if (S->partner[S->remaining[i]] == SK_INVALID)
                S->remaining[k++] = S->remaining[i];
        S->nrem = k;
        if (paired == 0 && S->nrem > 0 && !relaxed_forbid) {
            /* the avoided edges cut some even vertex off: allow them all */
            memset(S->forbid, 0, S->ne);
            relaxed_forbid = true;
            build_search_graph(S);
            continue;
        }
        if (paired == 0 && S->nrem > 0)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "edge deletion: even vertex %u cannot be paired (no even partner or "
                            "boundary reachable)", S->remaining[0]);
    }
    return SK_OK;
}

/* Algorithm Reduce Path on every path, then the union of the paths with cancellation of shared
 * edges (Delete Even Edges, case (2a)); edges joining two boundary vertices are dropped (boundary
 * vertices may stay even). */
static sk_status reduce_paths(ed_state *S, sk_error *err)
{
    const sk_mesh *m = S->m;
    const path_store *ps = &S->ps;
    uint32_t *where = S->queue; /* free by now (the parity check's and the matching's queue) */
    for (size_t v = 0; v < S->nv; ++v)
        where[v] = SK_INVALID;
    for (size_t p = 0; p < ps->np; ++p) {
        uint32_t *pv = ps->v + ps->start[p];
        size_t n = reduce_path(m, S->forbid, S->mflag, pv, ps->start[p + 1] - ps->start[p],
                               where, &S->st.reductions);
        for (size_t i = 0; i + 1 < n; ++i) {
            uint32_t h = sk__find_halfedge(m, pv[i], pv[i + 1]);
            if (h == SK_INVALID)
                return sk__fail(err, SK_ERR_NUMERIC, "edge deletion: internal error, broken path");
            uint32_t e = sk_edge(h);
            if (S->dcnt[e])
                S->st.shared_edges++;
            S->dcnt[e] ^= 1u;
        }
    }
    for (uint32_t e = 0; e < S->ne; ++e)
        if (S->dcnt[e] && S->bnd[sk_from(m, 2 * e)] && S->bnd[sk_to(m, 2 * e)])
            S->dcnt[e] = 0;
    return SK_OK;
}

/* Algorithm Delete Even Edges, case (2b): a triangle holding two deleted edges gets its third edge
 * deleted instead (three: none). The faces are processed as a stack and re-pushed when an edge of
 * theirs changes (bounded by the strict decrease of the deleted set). */
static sk_status delete_even_edges(ed_state *S, sk_error *err)
{
    const sk_mesh *m = S->m;
    size_t nf = S->nf, nq = 0, cap_q = nf + 1;
    uint32_t *fq = sk__malloc_array(nf + 1, sizeof *fq);
    uint8_t *inq = sk__calloc_array(nf ? nf : 1, 1);
    sk_status st = SK_OK;
    if (!fq || !inq) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
        goto done;
    }
    for (uint32_t f = 0; f < nf; ++f)
        if (!m->f_deleted[f])
            fq[nq++] = f;
    memset(inq, 1, nf);
    while (nq > 0) {
        uint32_t f = fq[--nq];
        inq[f] = 0;
        uint32_t h[3];
        h[0] = m->f_halfedge[f];
        h[1] = m->h_next[h[0]];
        h[2] = m->h_next[h[1]];
        int cnt = 0, which[3];
        for (int i = 0; i < 3; ++i)
            if (S->dcnt[sk_edge(h[i])])
                which[cnt++] = i;
        if (cnt < 2)
            continue;
        S->st.triangle_fixes++;
        if (cnt == 3) {
            for (int i = 0; i < 3; ++i)
                S->dcnt[sk_edge(h[i])] = 0;
        } else {
            int third = 3 - which[0] - which[1];
            uint32_t et = sk_edge(h[third]);
            S->dcnt[sk_edge(h[which[0]])] = 0;
            S->dcnt[sk_edge(h[which[1]])] = 0;
            if (!sk_is_boundary_e(m, et) &&
                !(S->bnd[sk_from(m, 2 * et)] && S->bnd[sk_to(m, 2 * et)])) {
                S->dcnt[et] = 1;
                S->st.forced_edges += S->forbid[et];
            }
        }
        /* re-check the neighbouring faces */
        for (int i = 0; i < 3; ++i) {
            uint32_t g = m->h_face[sk_opp(h[i])];
            if (g == SK_INVALID || inq[g])
                continue;
            if (nq == cap_q) {
                cap_q *= 2;
                uint32_t *q2 = sk__realloc_array(fq, cap_q, sizeof *q2);
                if (!q2) {
                    st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
                    goto done;
                }
                fq = q2;
            }
            inq[g] = 1;
            fq[nq++] = g;
        }
    }
done:
    sk__free(fq);
    sk__free(inq);
    return st;
}

/* Local improvement of the deleted set D (a T-join: odd degree exactly at the even interior
 * vertices, the boundary free) by cycle exchanges: D is a minimum T-join exactly when no cycle C has
 * more than half of its edges in D (Guan's criterion for the postman problem; Edmonds & Johnson
 * 1973), and D xor C keeps every vertex's parity for any closed walk C. The closed walks tried,
 * from every even vertex x: W1 Q1 W2 Q2, W1 and W2 simple walks of at most SK_SHORTCUT_MAX_WALK
 * deleted edges, Q1 and Q2 shortest paths of at most SK_SHORTCUT_RADIUS kept edges that may be
 * deleted (not forbidden, not on the boundary, not joining two boundary vertices), Q2 ending at x:
 * with W2 and Q1 empty a shorter path replaces a part of a path, with W1 and W2 two whole paths
 * (x ... b, c ... d) it re-pairs their ends (x - d, b - c: the 2-opt move). The best exchange that
 * shrinks D is applied (its gain counted edge by edge, shared edges cancelling); each strictly
 * shrinks D, so the search ends; case (2b) runs again afterwards (Q may share a triangle with D). */
#define SK_SHORTCUT_MAX_WALK 8
#define SK_SHORTCUT_RADIUS 2
#define SK_SHORTCUT_MAX_WALKS 48

typedef struct walk_set {
    size_t n;
    uint32_t end[SK_SHORTCUT_MAX_WALKS], len[SK_SHORTCUT_MAX_WALKS];
    uint32_t h[SK_SHORTCUT_MAX_WALKS][SK_SHORTCUT_MAX_WALK];
} walk_set;

typedef struct bfs_ball {
    uint32_t *stamp, *dist, *pred, *queue; /* per vertex; pred: the half-edge into it */
    uint32_t cur;
    size_t n;                               /* vertices in queue[0 .. n) */
} bfs_ball;

typedef struct shortcut_ctx {
    ed_state *S;
    bfs_ball bx, by;
    uint8_t *onwalk, *etog;
    uint32_t cur_walk[SK_SHORTCUT_MAX_WALK];
    walk_set w1, w2;
    uint32_t list[4 * SK_SHORTCUT_MAX_WALK];
    size_t nlist; /* edges in list (the last exchange evaluated) */
} shortcut_ctx;

/* the best exchange found from one vertex: walk i of w1, z, walk j of w2 (SIZE_MAX: none), u */
typedef struct shortcut_move {
    long gain;
    size_t i, j;
    uint32_t z, u;
} shortcut_move;

/* the edge may join D by an exchange */
static bool shortcut_allowed(const ed_state *S, uint32_t e)
{
    const sk_mesh *m = S->m;
    return !S->dcnt[e] && !S->forbid[e] && !sk_is_boundary_e(m, e) &&
           !(S->bnd[sk_from(m, 2 * e)] && S->bnd[sk_to(m, 2 * e)]);
}

static bool has_deleted_edge(const ed_state *S, uint32_t v)
{
    const sk_mesh *m = S->m;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        if (S->dcnt[sk_edge(h)])
            return true;
        h = sk_cw_out(m, h);
    } while (h != h0);
    return false;
}

/* breadth first from x over the allowed edges, SK_SHORTCUT_RADIUS deep */
static void shortcut_ball(const ed_state *S, bfs_ball *B, uint32_t x)
{
    const sk_mesh *m = S->m;
    size_t qh = 0, qt = 0;
    B->cur++;
    B->stamp[x] = B->cur;
    B->dist[x] = 0;
    B->pred[x] = SK_INVALID;
    B->queue[qt++] = x;
    while (qh < qt) {
        uint32_t v = B->queue[qh++];
        if (B->dist[v] >= SK_SHORTCUT_RADIUS)
            continue;
        uint32_t g0 = m->v_halfedge[v], g = g0;
        do {
            uint32_t w = sk_to(m, g);
            if (B->stamp[w] != B->cur && shortcut_allowed(S, sk_edge(g))) {
                B->stamp[w] = B->cur;
                B->dist[w] = B->dist[v] + 1;
                B->pred[w] = g;
                B->queue[qt++] = w;
            }
            g = sk_cw_out(m, g);
        } while (g != g0);
    }
    B->n = qt;
}

/* every simple walk along D from v (depth edges so far) into W */
static void shortcut_walks(shortcut_ctx *C, walk_set *W, uint32_t v, uint32_t depth)
{
    const sk_mesh *m = C->S->m;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        uint32_t w = sk_to(m, h);
        if (C->S->dcnt[sk_edge(h)] && !C->onwalk[w] && W->n < SK_SHORTCUT_MAX_WALKS) {
            uint32_t k = depth + 1;
            C->cur_walk[depth] = h;
            W->end[W->n] = w;
            W->len[W->n] = k;
            memcpy(W->h[W->n], C->cur_walk, k * sizeof *C->cur_walk);
            W->n++;
            if (k < SK_SHORTCUT_MAX_WALK) {
                C->onwalk[w] = 1;
                shortcut_walks(C, W, w, k);
                C->onwalk[w] = 0;
            }
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
}

static void collect_walks(shortcut_ctx *C, walk_set *W, uint32_t v)
{
    W->n = 0;
    C->onwalk[v] = 1;
    shortcut_walks(C, W, v, 0);
    C->onwalk[v] = 0;
}

/* the closed walk W1 (walk i of w1), Q1 (z back to y in by), W2 (walk j of w2, or none), Q2 (u
 * back to x in bx) as an edge list; its exact gain (edges of D it removes minus edges it adds,
 * edges used twice cancelling); apply: toggle them */
static long exchange(shortcut_ctx *C, size_t i, uint32_t z, size_t j, uint32_t u, bool apply)
{
    const sk_mesh *m = C->S->m;
    size_t n = 0;
    for (uint32_t k = 0; k < C->w1.len[i]; ++k)
        C->list[n++] = sk_edge(C->w1.h[i][k]);
    for (uint32_t v = z; C->by.pred[v] != SK_INVALID; v = sk_from(m, C->by.pred[v]))
        C->list[n++] = sk_edge(C->by.pred[v]);
    for (uint32_t k = 0; j != SIZE_MAX && k < C->w2.len[j]; ++k)
        C->list[n++] = sk_edge(C->w2.h[j][k]);
    for (uint32_t v = u; C->bx.pred[v] != SK_INVALID; v = sk_from(m, C->bx.pred[v]))
        C->list[n++] = sk_edge(C->bx.pred[v]);
    C->nlist = n;
    for (size_t k = 0; k < n; ++k)
        C->etog[C->list[k]] ^= 1u;
    long gain = 0;
    for (size_t k = 0; k < n; ++k) {
        uint32_t e = C->list[k];
        if (C->etog[e]) {
            gain += C->S->dcnt[e] ? 1 : -1;
            if (apply)
                C->S->dcnt[e] ^= 1u;
            C->etog[e] = 0;
        }
    }
    return gain;
}

/* The best exchange from x on the current D (gain 0: none), read-only on S. *reach: a bound on
 * the hop distance from x of every vertex whose edges the search read (walk lengths plus ball
 * radii), so the answer stays the same while D keeps every edge within reach + 1 of x. */
static shortcut_move best_exchange(shortcut_ctx *C, uint32_t x, uint32_t *reach)
{
    const ed_state *S = C->S;
    shortcut_move b = {0, 0, SIZE_MAX, SK_INVALID, SK_INVALID};
    uint32_t r = SK_SHORTCUT_RADIUS;
    shortcut_ball(S, &C->bx, x);
    collect_walks(C, &C->w1, x);
    for (size_t i = 0; i < C->w1.n; ++i) {
        uint32_t y = C->w1.end[i];
        shortcut_ball(S, &C->by, y);
        r = r > C->w1.len[i] + SK_SHORTCUT_RADIUS ? r : C->w1.len[i] + SK_SHORTCUT_RADIUS;
        /* W2 and Q1 empty: Q2 from y */
        if (C->bx.stamp[y] == C->bx.cur && (long)C->w1.len[i] - (long)C->bx.dist[y] > b.gain) {
            long g = exchange(C, i, y, SIZE_MAX, y, false);
            if (g > b.gain)
                b = (shortcut_move){g, i, SIZE_MAX, y, y};
        }
        for (size_t q = 0; q < C->by.n; ++q) {
            uint32_t z = C->by.queue[q];
            if (!has_deleted_edge(S, z))
                continue;
            collect_walks(C, &C->w2, z);
            for (size_t j = 0; j < C->w2.n; ++j) {
                uint32_t u = C->w2.end[j], rz = C->w1.len[i] + C->by.dist[z] + C->w2.len[j];
                r = r > rz ? r : rz;
                if (C->bx.stamp[u] != C->bx.cur)
                    continue;
                long est = (long)C->w1.len[i] + (long)C->w2.len[j] - (long)C->by.dist[z] -
                           (long)C->bx.dist[u];
                if (est <= b.gain)
                    continue;
                long g = exchange(C, i, z, j, u, false);
                if (g > b.gain)
                    b = (shortcut_move){g, i, j, z, u};
            }
        }
    }
    *reach = r;
    return b;
}

/* after an exchange: near[v] = min(near[v], hops from v to an end of a toggled edge), up to
 * SK_SHORTCUT_NEAR (the largest reach + 1); queue: nv entries */
#define SK_SHORTCUT_NEAR (2 * SK_SHORTCUT_MAX_WALK + SK_SHORTCUT_RADIUS + 1)
static void mark_near(const shortcut_ctx *C, uint8_t *near, uint32_t *queue)
{
    const sk_mesh *m = C->S->m;
    size_t qh = 0, qt = 0;
    for (size_t k = 0; k < C->nlist; ++k)
        for (int end = 0; end < 2; ++end) {
            uint32_t v = end ? sk_to(m, 2 * C->list[k]) : sk_from(m, 2 * C->list[k]);
            if (near[v] != 0) {
                near[v] = 0;
                queue[qt++] = v;
            }
        }
    while (qh < qt) {
        uint32_t v = queue[qh++], h0 = m->v_halfedge[v], h = h0;
        if (near[v] >= SK_SHORTCUT_NEAR)
            continue;
        do {
            uint32_t w = sk_to(m, h);
            if (near[w] > near[v] + 1) {
                near[w] = (uint8_t)(near[v] + 1);
                queue[qt++] = w;
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
}

/* sk__edge_deletion_traced: one more exchange applied at x (trace_nomem when out of memory) */
static void trace_push(ed_state *S, uint32_t x)
{
    if (S->trace_nomem)
        return;
    if (S->ntrace == S->cap_trace) {
        size_t cap = S->cap_trace ? 2 * S->cap_trace : 64;
        uint32_t *t = sk__realloc_array(S->trace, cap, sizeof *t);
        if (!t) {
            S->trace_nomem = true;
            return;
        }
        S->trace = t;
        S->cap_trace = cap;
    }
    S->trace[S->ntrace++] = x;
}

/* One pass over the even vertices in order, each tried again after an exchange of its own, later
 * vertices seeing the earlier exchanges; returns the deleted edges saved. First, in parallel, the
 * best exchange of every even vertex on D as it is (pre[x]: reach, 0x80 when it gains); then in
 * order only the vertices that gained there or that an applied exchange came within their reach
 * of (for any other vertex the in-order search would read the same D and find nothing): the same
 * exchanges, in the same order, as trying every vertex in order. */
static size_t shortcut_pass(shortcut_ctx *C, const uint8_t *pre, uint8_t *near)
{
    ed_state *S = C->S;
    size_t saved = 0;
    for (uint32_t x = 0; x < S->nv; ++x) {
        if (!S->even[x] ||
            (!S->try_all && !(pre[x] & 0x80u) && near[x] > (pre[x] & 0x7fu) + 1))
            continue;
        for (;;) {
            uint32_t reach;
            shortcut_move b = best_exchange(C, x, &reach);
            if (b.gain <= 0)
                break;
            /* the winner's Q1 is in the ball of its own y, its W2 in the walks from z: rebuild */
            shortcut_ball(S, &C->by, C->w1.end[b.i]);
            if (b.j != SIZE_MAX)
                collect_walks(C, &C->w2, b.z);
            exchange(C, b.i, b.z, b.j, b.u, true);
            mark_near(C, near, S->queue); /* S->queue is free by now */
            saved += (size_t)b.gain;
            S->st.shortcuts++;
            if (S->tracing)
                trace_push(S, x);
        }
    }
    S->st.shortcut_savings += saved;
    return saved;
}

static void shortcut_ctx_free(shortcut_ctx *C)
{
    if (!C)
        return;
    bfs_ball *balls[2] = {&C->bx, &C->by};
    for (int k = 0; k < 2; ++k) {
        sk__free(balls[k]->stamp);
        sk__free(balls[k]->dist);
        sk__free(balls[k]->pred);
        sk__free(balls[k]->queue);
    }
    sk__free(C->onwalk);
    sk__free(C->etog);
    sk__free(C);
}

/* one searcher's scratch (NULL when out of memory) */
static shortcut_ctx *shortcut_ctx_create(ed_state *S)
{
    size_t nv = S->nv;
    shortcut_ctx *C = sk__calloc_array(1, sizeof *C);
    if (!C)
        return NULL;
    C->S = S;
    bfs_ball *balls[2] = {&C->bx, &C->by};
    bool ok = true;
    for (int k = 0; k < 2; ++k) {
        balls[k]->stamp = sk__calloc_array(nv + 1, sizeof *balls[k]->stamp);
        balls[k]->dist = sk__malloc_array(nv + 1, sizeof *balls[k]->dist);
        balls[k]->pred = sk__malloc_array(nv + 1, sizeof *balls[k]->pred);
        balls[k]->queue = sk__malloc_array(nv + 1, sizeof *balls[k]->queue);
        ok = ok && balls[k]->stamp && balls[k]->dist && balls[k]->pred && balls[k]->queue;
    }
    C->onwalk = sk__calloc_array(nv + 1, 1);
    C->etog = sk__calloc_array(S->ne + 1, 1);
    if (!ok || !C->onwalk || !C->etog) {
        shortcut_ctx_free(C);
        return NULL;
    }
    return C;
}

/* The vertices whose exchanges may gain (screen[v] = 1), by the tight components of D. A
 * component K of D (connected by deleted edges) with odd(K) its vertices of odd degree in D is
 * tight when |K| = |odd(K)| / 2 (a single edge between two even vertices). An exchange from x,
 * closed walk C = W1 Q1 W2 Q2, has C and D share only edges of W1 and W2 (Q1 and Q2 are kept
 * edges), walks along D from x and from a z within SK_SHORTCUT_RADIUS hops of W1's end y: the
 * components it meets are K(x) and K(z), their union U. D xor C is D outside U, plus U xor C,
 * whose odd vertices are odd(U) (C is closed); an edge set holds at least half as many edges as
 * it has odd vertices, so |U xor C| >= |odd(U)| / 2 = |U| when both components are tight: no
 * gain. So x may gain only when K(x) is not tight or holds a vertex within SK_SHORTCUT_RADIUS
 * hops (of any edges, a superset of the ball's) of a component that is not tight. At the lower
 * bound every component is tight (armadillo Loop x2: no vertex searched). comp, queue, hot:
 * scratch of nv + 1 entries (comp and queue uint32_t). */
static void shortcut_screen(const ed_state *S, uint8_t *screen, uint32_t *comp, uint32_t *queue,
                            uint8_t *hot)
{
    const sk_mesh *m = S->m;
    size_t nv = S->nv;
    memset(hot, 0, nv + 1);
    memset(screen, 0, nv + 1);
    for (size_t v = 0; v < nv; ++v)
        comp[v] = SK_INVALID;
    /* the components (comp: their first vertex; a vertex without deleted edges is one alone);
     * those that are not tight mark the vertices within 2 hops of theirs hot */
    for (uint32_t s0 = 0; s0 < nv; ++s0) {
        if (comp[s0] != SK_INVALID || m->v_deleted[s0] || m->v_halfedge[s0] == SK_INVALID)
            continue;
        size_t qh = 0, qt = 0, ends = 0, degs = 0;
        comp[s0] = s0;
        queue[qt++] = s0;
        while (qh < qt) {
            uint32_t v = queue[qh++], h0 = m->v_halfedge[v], h = h0, d = 0;
            do {
                if (S->dcnt[sk_edge(h)]) {
                    uint32_t w = sk_to(m, h);
                    d++;
                    if (comp[w] == SK_INVALID) {
                        comp[w] = s0;
                        queue[qt++] = w;
                    }
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
            degs += d;
            ends += d & 1u;
        }
        if (degs == ends) /* |K| = degs / 2 = |odd(K)| / 2: tight */
            continue;
        screen[s0] = 1;
        for (size_t i = 0; i < qt; ++i) {
            uint32_t v = queue[i], h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t w = sk_to(m, h), g0 = m->v_halfedge[w], g = g0;
                hot[w] = 1;
                do {
                    hot[sk_to(m, g)] = 1;
                    g = sk_cw_out(m, g);
                } while (g != g0);
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
    }
    /* a tight component holding a hot vertex is searched too */
    for (uint32_t v = 0; v < nv; ++v)
        if (hot[v] && comp[v] != SK_INVALID)
            screen[comp[v]] = 1;
    for (uint32_t v = 0; v < nv; ++v)
        hot[v] = comp[v] != SK_INVALID && S->even[v] && screen[comp[v]];
    memcpy(screen, hot, nv);
}

/* The pre-pass of shortcut_pass, one searcher per thread, over the even vertices that
 * shortcut_screen keeps (the others cannot gain on D as it is: pre[x] gets the largest reach any
 * search has, so the ordered pass tries them again after any exchange that could change that);
 * false when out of memory. */
#define SK_SHORTCUT_MAX_REACH (2 * SK_SHORTCUT_MAX_WALK + SK_SHORTCUT_RADIUS)
static bool shortcut_prescreen(ed_state *S, uint8_t *pre)
{
    long nv = (long)S->nv;
    int failed = 0;
    uint8_t *screen = sk__malloc_array(S->nv + 1, 1), *hot = sk__malloc_array(S->nv + 1, 1);
    uint32_t *comp = sk__malloc_array(S->nv + 1, sizeof *comp);
    uint32_t *queue = sk__malloc_array(S->nv + 1, sizeof *queue);
    if (!screen || !hot || !comp || !queue) {
        sk__free(screen);
        sk__free(hot);
        sk__free(comp);
        sk__free(queue);
        return false;
    }
    shortcut_screen(S, screen, comp, queue, hot);
    sk__free(hot);
    sk__free(comp);
    sk__free(queue);
    size_t searched = 0;
    for (long x = 0; x < nv; ++x) {
        searched += screen[x];
        if (S->even[x] && !screen[x])
            pre[x] = SK_SHORTCUT_MAX_REACH;
    }
    S->st.shortcut_searched = searched;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel reduction(| : failed) if (nv >= SK_SMOOTH_TEAM_MIN)
#endif
    {
        shortcut_ctx *C = shortcut_ctx_create(S);
        failed = C == NULL;
#ifdef SK_HAVE_OPENMP
#pragma omp for schedule(dynamic, 4096)
#endif
        for (long x = 0; x < nv; ++x) {
            uint32_t reach = 0;
            if (C && screen[x]) {
                shortcut_move b = best_exchange(C, (uint32_t)x, &reach);
                pre[x] = (uint8_t)(reach | (b.gain > 0 ? 0x80u : 0u));
            }
        }
        shortcut_ctx_free(C);
    }
    sk__free(screen);
    return !failed;
}

/* One pass of cycle exchanges (shortcut_pass; a second pass saved nothing more on the shared
 * meshes), then case (2b) when some applied. */
static sk_status shortcut_paths(ed_state *S, sk_error *err)
{
    uint8_t *pre = sk__calloc_array(S->nv + 1, 1), *near = sk__malloc_array(S->nv + 1, 1);
    shortcut_ctx *C = pre && near ? shortcut_ctx_create(S) : NULL;
    sk_status st = SK_OK;
    if (!C || (!S->try_all && !shortcut_prescreen(S, pre))) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
    } else {
        memset(near, 0xff, S->nv + 1);
        if (shortcut_pass(C, pre, near) > 0) {
            st = delete_even_edges(S, err);
        }
    }
    shortcut_ctx_free(C);
    sk__free(pre);
    sk__free(near);
    return st;
}

/* Every interior vertex is odd now; returns the number of deleted edges. */
static sk_status verify_odd(ed_state *S, sk_error *err)
{
    const sk_mesh *m = S->m;
    size_t nd = 0;
    for (uint32_t e = 0; e < S->ne; ++e)
        nd += S->dcnt[e];
    for (uint32_t v = 0; v < S->nv; ++v) {
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID || S->bnd[v])
            continue;
        size_t faces = 0;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        do {
            faces += 1 - S->dcnt[sk_edge(h)];
            h = sk_cw_out(m, h);
        } while (h != h0);
        if ((faces & 1u) == 0)
            return sk__fail(err, SK_ERR_NUMERIC,
                            "edge deletion: internal error, vertex %u is still even", v);
    }
    S->st.deleted_edges = nd;
    return SK_OK;
}

/* The triangle/quad mesh: m with the deleted edges merged away, and their end points. */
static sk_status build_config(ed_state *S, sk_mesh **out, uint32_t **deleted_out, sk_error *err)
{
    const sk_mesh *m = S->m;
    sk_mesh *res = NULL;
    size_t nd = S->st.deleted_edges;
    uint32_t *deleted = NULL;
    sk_status st = sk_mesh_copy(m, &res, err);
    if (st)
        goto done;
    deleted = sk__malloc_array(2 * nd + 1, sizeof *deleted);
    if (!deleted) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
        goto done;
    }
    nd = 0;
    for (uint32_t e = 0; e < S->ne; ++e) {
        if (!S->dcnt[e])
            continue;
        deleted[2 * nd] = sk_from(m, 2 * e);
        deleted[2 * nd + 1] = sk_to(m, 2 * e);
        ++nd;
        merge_across_edge(res, e);
    }
    if ((st = sk_mesh_compact(res, NULL, NULL, err)) != SK_OK)
        goto done;
    for (uint32_t f = 0; f < res->num_faces; ++f) {
        if (sk_mesh_face_size(res, f) == 3)
            S->st.triangles++;
        else
            S->st.quads++;
    }
    *out = res;
    res = NULL;
    if (deleted_out) {
        *deleted_out = deleted;
        deleted = NULL;
    }
done:
    sk__free(deleted);
    sk_mesh_destroy(&res);
    return st;
}

/* Algorithm Delete Even Edges of Cottin & van Damme (section 3) in the steps of the paper:
 * Initialise (pairs and their paths), Reduce Path, the union with cases (2a) and (2b). */
sk_status sk_edge_deletion(const sk_mesh *m, sk_mesh **out, uint32_t **deleted_out,
                           sk_edge_deletion_stats *stats, sk_error *err)
{
    return sk__edge_deletion_creases(m, NULL, out, deleted_out, stats, err);
}

/* The warm start (sk__edge_deletion_hinted): the hinted edges that m still has, that may be
 * deleted (interior, no crease, not joining two boundary-like vertices, not avoided) and that
 * share no triangle with another of them are deleted first; a vertex's parity then counts them,
 * so only the vertices whose parity they leave wrong are paired, by the paths of Initialise
 * (whose union with the hinted edges, as a symmetric difference, fixes the parity exactly
 * there). */
static void apply_hint(ed_state *S, const uint32_t *hint, size_t nhint)
{
    const sk_mesh *m = S->m;
    for (size_t k = 0; k < nhint; ++k) {
        uint32_t a = hint[2 * k], b = hint[2 * k + 1];
        if (a >= S->nv || b >= S->nv || m->v_deleted[a] || m->v_deleted[b] ||
            m->v_halfedge[a] == SK_INVALID || m->v_halfedge[b] == SK_INVALID)
            continue;
        uint32_t h = sk__find_halfedge(m, a, b);
        if (h == SK_INVALID)
            continue;
        uint32_t e = sk_edge(h);
        if (sk_is_boundary_e(m, e) || (S->crease && S->crease[e]) || S->forbid[e] ||
            (S->bnd[a] && S->bnd[b]) || S->dcnt[e])
            continue;
        bool clash = false; /* a triangle with two deleted edges */
        for (int side = 0; side < 2 && !clash; ++side) {
            uint32_t g = side ? sk_opp(h) : h;
            clash = S->dcnt[sk_edge(m->h_next[g])] || S->dcnt[sk_edge(m->h_prev[g])];
        }
        if (!clash)
            S->dcnt[e] = 1;
    }
    S->nrem = 0;
    for (uint32_t v = 0; v < S->nv; ++v) {
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID || S->bnd[v])
            continue;
        unsigned deg = 0;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        do {
            deg += S->dcnt[sk_edge(h)];
            h = sk_cw_out(m, h);
        } while (h != h0);
        S->even[v] ^= (uint8_t)(deg & 1u);
        if (S->even[v])
            S->remaining[S->nrem++] = v;
    }
}

sk_status sk__edge_deletion_creases(const sk_mesh *m, const uint8_t *crease, sk_mesh **out,
                                    uint32_t **deleted_out, sk_edge_deletion_stats *stats,
                                    sk_error *err)
{
    return sk__edge_deletion_hinted(m, crease, NULL, 0, NULL, out, deleted_out, stats, err);
}

static sk_status run_deletion(const sk_mesh *m, const uint8_t *crease, const uint32_t *hint,
                              size_t nhint, const uint8_t *avoid, bool try_all, uint32_t **trace,
                              size_t *ntrace, sk_mesh **out, uint32_t **deleted_out,
                              sk_edge_deletion_stats *stats, sk_error *err)
{
    *out = NULL;
    if (deleted_out)
        *deleted_out = NULL;
    for (size_t f = 0; f < m->num_faces; ++f)
        if (!m->f_deleted[f] && sk_mesh_face_size(m, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "edge deletion needs a triangle mesh, face %zu has %zu sides", f,
                            sk_mesh_face_size(m, (uint32_t)f));
    ed_state S = {.m = m, .nv = m->num_vertices, .ne = sk_num_edges(m), .nf = m->num_faces,
                  .crease = crease, .avoid = avoid, .try_all = try_all, .tracing = trace != NULL};
    sk_status st = ed_alloc(&S, err);
    if (st == SK_OK) {
        find_even_vertices(&S);
        parity_fail pf;
        sk_error merr = {0};
        sk_status mst = SK_OK;
        if (hint) { /* the hint changes the even vertices after the counting argument */
            order_search_vertices(&S, &pf);
            if (pf.root == SK_INVALID) {
                apply_hint(&S, hint, nhint);
                build_search_graph(&S);
                mst = match_adjacent(&S, &merr);
            }
        } else {
            /* the search's order (with the counting argument) and graph on one thread, the
             * matching of adjacent even vertices on the other: neither writes what the other
             * reads (the order and graph read the mesh, even, bnd, forbid) */
#ifdef SK_HAVE_OPENMP
#pragma omp parallel sections num_threads(2) if (S.nv >= SK_SMOOTH_TEAM_MIN)
#endif
            {
#ifdef SK_HAVE_OPENMP
#pragma omp section
#endif
                {
                    order_search_vertices(&S, &pf);
                    build_search_graph(&S);
                }
#ifdef SK_HAVE_OPENMP
#pragma omp section
#endif
                mst = match_adjacent(&S, &merr);
            }
        }
        if (pf.root != SK_INVALID) {
            st = parity_error(&pf, err);
        } else if (mst != SK_OK) {
            st = mst;
            if (err)
                *err = merr;
        }
    }
    if (st == SK_OK)
        st = initialise(&S, err);
    if (st == SK_OK)
        st = reduce_paths(&S, err);
    if (st == SK_OK)
        st = delete_even_edges(&S, err);
    if (st == SK_OK)
        st = shortcut_paths(&S, err);
    if (st == SK_OK)
        st = verify_odd(&S, err);
    if (st == SK_OK)
        st = build_config(&S, out, deleted_out, err);
    if (st == SK_OK && S.trace_nomem)
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
    if (st == SK_OK) {
        if (stats)
            *stats = S.st;
        if (trace) {
            *trace = S.trace;
            *ntrace = S.ntrace;
            S.trace = NULL;
        }
        sk__ok(err);
    }
    sk__free(S.trace);
    ed_free(&S);
    return st;
}

sk_status sk__edge_deletion_hinted(const sk_mesh *m, const uint8_t *crease, const uint32_t *hint,
                                   size_t nhint, const uint8_t *avoid, sk_mesh **out,
                                   uint32_t **deleted_out, sk_edge_deletion_stats *stats,
                                   sk_error *err)
{
    return run_deletion(m, crease, hint, nhint, avoid, false, NULL, NULL, out, deleted_out, stats,
                        err);
}

sk_status sk__edge_deletion_traced(const sk_mesh *m, bool try_all, uint32_t **trace,
                                   size_t *ntrace, sk_mesh **out, sk_edge_deletion_stats *stats,
                                   sk_error *err)
{
    *trace = NULL;
    *ntrace = 0;
    return run_deletion(m, NULL, NULL, 0, NULL, try_all, trace, ntrace, out, NULL, stats, err);
}
