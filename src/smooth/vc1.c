/* The VC1 construction of Cottin & van Damme (section 4): driver from a triangle mesh with normals
 * to the network of quartic triangles and bicubic quads. Also the parity split (--allow-split) and
 * the interior control points from system (4). */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>
#include <string.h>


void sk_smooth_destroy(sk_smooth **smooth)
{
    if (!smooth || !*smooth)
        return;
    sk_smooth *s = *smooth;
    sk_mesh_destroy(&s->config);
    sk__free(s->normals);
    sk__free(s->patches);
    sk__free(s->points);
    sk__free(s->deleted);
    sk__free(s->problems);
    sk__free(s);
    *smooth = NULL;
}

/* Tangent basis e1, e2 with e1 x e2 = n. */
static void tangent_basis(const double n[3], double e1[3], double e2[3])
{
    double a[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.6)
        a[0] = 0, a[1] = 1;
    sk__cross3(e1, a, n);
    sk__normalize3(e1);
    sk__cross3(e2, n, e1);
}

/* ---------------------------------------------------------------------------------------------
 * Parity split: a closed component with an odd number of vertices has no edge deletion (section 3);
 * its longest edge is split at the midpoint of its wire frame curve, which adds one vertex.
 * ------------------------------------------------------------------------------------------- */

static sk_status split_odd_components(const sk_mesh *m, const double *normals, sk_mesh **out,
                                      double **out_normals, size_t *splits, sk_error *err)
{
    size_t nv = m->num_vertices, nh = m->num_halfedges;
    uint32_t *comp = sk__malloc_array(nv + 1, sizeof *comp);
    uint32_t *queue = sk__malloc_array(nv + 1, sizeof *queue);
    uint32_t *split_h = NULL;
    size_t nsplit = 0, cap_split = 0;
    sk_status st = SK_OK;
    *out = NULL;
    *out_normals = NULL;
    *splits = 0;
    if (!comp || !queue) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t v = 0; v < nv; ++v)
        comp[v] = SK_INVALID;
    for (uint32_t s = 0; s < nv; ++s) {
        if (comp[s] != SK_INVALID || m->v_deleted[s] || m->v_halfedge[s] == SK_INVALID)
            continue;
        size_t qh = 0, qt = 0, count = 0;
        bool boundary = false;
        uint32_t longest = SK_INVALID;
        double best = -1.0;
        comp[s] = s;
        queue[qt++] = s;
        while (qh < qt) {
            uint32_t v = queue[qh++];
            ++count;
            boundary |= sk_is_boundary_v(m, v);
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t w = sk_to(m, h);
                if (comp[w] == SK_INVALID) {
                    comp[w] = s;
                    queue[qt++] = w;
                }
                double len = sk_mesh_edge_length(m, sk_edge(h));
                if (len > best) {
                    best = len;
                    longest = h;
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
        if (!boundary && (count & 1u)) {
            if (nsplit == cap_split) {
                cap_split = cap_split ? 2 * cap_split : 8;
                uint32_t *p = sk__realloc_array(split_h, cap_split, sizeof *p);
                if (!p) {
                    st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                    goto done;
                }
                split_h = p;
            }
            split_h[nsplit++] = longest;
        }
    }
    if (nsplit == 0)
        goto done;
    {
        /* wire frame targets of the whole mesh (only the split edges are used) */
        double *target = sk__malloc_array(nh, 3 * sizeof(double));
        size_t nf = m->num_faces, nv2 = nv + nsplit;
        double *pos = sk__malloc_array(nv2, 3 * sizeof(double));
        double *nrm = sk__malloc_array(nv2, 3 * sizeof(double));
        uint32_t *off = sk__malloc_array(nf + 2 * nsplit + 1, sizeof(uint32_t));
        uint32_t *idx = sk__malloc_array(3 * (nf + 2 * nsplit), sizeof(uint32_t));
        uint32_t *fsplit = sk__malloc_array(nf + 1, sizeof(uint32_t));
        if (!target || !pos || !nrm || !off || !idx || !fsplit) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        } else if ((st = sk__wireframe_targets(m, normals, target, err)) == SK_OK) {
            memcpy(pos, m->positions, nv * 3 * sizeof(double));
            memcpy(nrm, normals, nv * 3 * sizeof(double));
            for (size_t f = 0; f < nf; ++f)
                fsplit[f] = SK_INVALID;
            for (size_t i = 0; i < nsplit; ++i) {
                uint32_t h = split_h[i], o = sk_opp(h);
                const double *a = m->positions + 3 * (size_t)sk_from(m, h);
                const double *b = m->positions + 3 * (size_t)sk_to(m, h);
                const double *pa = target + 3 * (size_t)h, *pb = target + 3 * (size_t)o;
                double *x = pos + 3 * (nv + i), *n = nrm + 3 * (nv + i), tan[3];
                for (int k = 0; k < 3; ++k) {
                    x[k] = (a[k] + 3.0 * pa[k] + 3.0 * pb[k] + b[k]) / 8.0; /* cubic at t = 1/2 */
                    tan[k] = b[k] + pb[k] - pa[k] - a[k];                   /* its tangent */
                }
                sk__add3(n, normals + 3 * (size_t)sk_from(m, h), normals + 3 * (size_t)sk_to(m, h));
                sk__normalize3(tan);
                sk__axpy3(n, n, -sk__dot3(n, tan), tan);
                sk__normalize3(n);
                fsplit[m->h_face[h]] = (uint32_t)i;
                fsplit[m->h_face[o]] = (uint32_t)i;
            }
            size_t k = 0, nfo = 0;
            off[0] = 0;
            for (uint32_t f = 0; f < nf; ++f) {
                if (m->f_deleted[f])
                    continue;
                uint32_t h = m->f_halfedge[f];
                if (fsplit[f] != SK_INVALID) {
                    uint32_t e = sk_edge(split_h[fsplit[f]]);
                    while (sk_edge(h) != e)
                        h = m->h_next[h];
                    uint32_t a = sk_from(m, h), b = sk_to(m, h), c = sk_to(m, m->h_next[h]);
                    uint32_t x = (uint32_t)(nv + fsplit[f]);
                    idx[k++] = a, idx[k++] = x, idx[k++] = c, off[++nfo] = (uint32_t)k;
                    idx[k++] = x, idx[k++] = b, idx[k++] = c, off[++nfo] = (uint32_t)k;
                } else {
                    idx[k++] = sk_from(m, h);
                    idx[k++] = sk_to(m, h);
                    idx[k++] = sk_to(m, m->h_next[h]);
                    off[++nfo] = (uint32_t)k;
                }
            }
            st = sk_mesh_from_faces(nv2, pos, nfo, off, idx, out, err);
            if (st == SK_OK) {
                *out_normals = nrm;
                nrm = NULL;
                *splits = nsplit;
            }
        }
        sk__free(target);
        sk__free(pos);
        sk__free(nrm);
        sk__free(off);
        sk__free(idx);
        sk__free(fsplit);
    }
done:
    sk__free(comp);
    sk__free(queue);
    sk__free(split_h);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * Vertex systems and interior points
 * ------------------------------------------------------------------------------------------- */

/* Outgoing half-edges of v counter-clockwise; for a boundary vertex the first and the last are the
 * boundary edges and the patches lie between consecutive ones. Returns the count (0 if too many). */
static int ordered_edges(const sk_mesh *m, uint32_t v, uint32_t *E, int *closed)
{
    uint32_t h0 = m->v_halfedge[v];
    int n = 0;
    *closed = m->h_face[h0] != SK_INVALID;
    uint32_t start = *closed ? h0 : sk_ccw_out(m, h0), h = start;
    do {
        if (n == SK_VSYS_MAX)
            return 0;
        E[n++] = h;
        h = sk_ccw_out(m, h);
    } while (h != start);
    return n;
}

typedef struct vc1_work {
    const sk_mesh *m;
    const double *normals;
    const double *target; /* per half-edge */
    const double *r;      /* per face */
    double *P;            /* per half-edge: the cubic control point next to from(h) */
    double *w1;           /* per half-edge: w_1 of (8) at from(h), NaN on boundary edges */
    double *nu;           /* per half-edge: nu at from(h) (upper patch = face(h)) */
    double *C;            /* per half-edge: interior control point of face(h) at from(h) */
    double alpha;
} vc1_work;

static double face_delta(const sk_mesh *m, uint32_t f)
{
    return sk__delta(sk_mesh_face_size(m, f));
}

/* Blends the directions of the targets orig (2D, counter-clockwise) towards an even spread by b
 * in [0, 1] and their lengths towards their mean by lb in [0, 1], into out. */
static void blend_targets(const double *orig, double *out, int n, int closed, double alpha,
                          double b, double lb)
{
    double ang[SK_VSYS_MAX], len[SK_VSYS_MAX], acc = 0.0, mean = 0.0;
    for (int k = 0; k < n; ++k)
        mean += hypot(orig[2 * k], orig[2 * k + 1]) / n;
    for (int k = 0; k < n; ++k) {
        len[k] = (1.0 - lb) * hypot(orig[2 * k], orig[2 * k + 1]) + lb * mean;
        double a = atan2(orig[2 * k + 1], orig[2 * k]);
        if (k == 0) {
            acc = a;
        } else {
            double prev = ang[k - 1], d = a - prev;
            while (d <= 0.0)
                d += 2.0 * M_PI;
            while (d > 2.0 * M_PI)
                d -= 2.0 * M_PI;
            acc = prev + d;
        }
        ang[k] = acc;
    }
    double span = closed ? 2.0 * M_PI : ang[n - 1] - ang[0];
    if (!closed && span >= M_PI * (n - 1) * (1.0 - 2.0 * alpha))
        span = M_PI; /* a folded boundary fan: spread it over a half plane */
    int steps = closed ? n : n - 1;
    for (int k = 0; k < n; ++k) {
        double even = ang[0] + span * k / steps;
        double a = (1.0 - b) * ang[k] + b * even;
        out[2 * k] = len[k] * cos(a);
        out[2 * k + 1] = len[k] * sin(a);
    }
}

/* Solves vertex v's system; returns 0 ok, 1 angle violation, 2 not converged, 3 too many edges.
 * blend > 0 starts from targets blended by that much towards an even spread and lscale scales
 * their lengths (the regularity repair's variations); 0 and 1 give the plain construction. Where
 * the angle bounds fail, the targets are relaxed further (blend up to 1). */
static int solve_vertex_ex(vc1_work *W, uint32_t v, sk__vsys *sys, double blend, double lscale)
{
    const sk_mesh *m = W->m;
    uint32_t E[SK_VSYS_MAX];
    int closed, n = ordered_edges(m, v, E, &closed);
    if (n == 0)
        return 3;
    const double *V = m->positions + 3 * (size_t)v, *nv = W->normals + 3 * (size_t)v;
    double e1[3], e2[3];
    tangent_basis(nv, e1, e2);
    sys->n_edges = n;
    sys->closed = closed;
    sys->relaxed = blend > 0.0 || lscale != 1.0;
    for (int k = 0; k < n; ++k) {
        double d[3];
        sk__sub3(d, W->target + 3 * (size_t)E[k], V);
        sys->pstar[2 * k] = lscale * sk__dot3(d, e1);
        sys->pstar[2 * k + 1] = lscale * sk__dot3(d, e2);
        uint32_t h = E[k];
        if (!sk_is_boundary_e(m, sk_edge(h))) {
            sys->du[k] = face_delta(m, m->h_face[h]);
            sys->dd[k] = face_delta(m, m->h_face[sk_opp(h)]);
            sys->nu[k] = W->nu[h];
        } else {
            sys->du[k] = sys->dd[k] = 1.0;
            sys->nu[k] = -1.0;
        }
    }
    double orig[2 * SK_VSYS_MAX];
    memcpy(orig, sys->pstar, sizeof(double) * (size_t)(2 * n));
    if (blend > 0.0)
        blend_targets(orig, sys->pstar, n, closed, W->alpha, blend, 0.0);
    int ok = sk__vsys_solve(sys);
    double lo, hi;
    sk__vsys_angles(sys, &lo, &hi);
    int bad = ok != 0 || lo <= W->alpha * M_PI || hi >= M_PI * (1.0 - W->alpha);
    /* relax the targets locally: blend their directions towards an even spread (lengths kept)
     * until the solution meets the angle bounds */
    for (int t = 1; t <= 8 && bad; ++t) {
        /* t = 1..4: directions only; t = 5..8: directions evenly spread and the lengths blended
         * towards their mean as well (with very unequal target lengths the least-squares fit of
         * (8) can fold two tangents onto one line whatever their directions, e.g. at valence 3
         * where the solutions are one fixed configuration up to a linear map) */
        double b = t <= 4 ? 0.25 * t : 1.0, lb = t <= 4 ? 0.0 : 0.25 * (t - 4);
        if (b <= blend && lb == 0.0)
            continue;
        blend_targets(orig, sys->pstar, n, closed, W->alpha, b, lb);
        ok = sk__vsys_solve(sys);
        sk__vsys_angles(sys, &lo, &hi);
        bad = ok != 0 || lo <= W->alpha * M_PI || hi >= M_PI * (1.0 - W->alpha);
        sys->relaxed = 1;
    }
    memcpy(sys->pstar, orig, sizeof(double) * (size_t)(2 * n));
    for (int k = 0; k < n; ++k) {
        uint32_t h = E[k];
        double *P = W->P + 3 * (size_t)h;
        for (int x = 0; x < 3; ++x)
            P[x] = V[x] + sys->p[2 * k] * e1[x] + sys->p[2 * k + 1] * e2[x];
        W->w1[h] = sk_is_boundary_e(m, sk_edge(h)) ? NAN : sys->w[k];
    }
    if (ok != 0)
        return 2;
    if (bad)
        return 1;
    return 0;
}

static int solve_vertex(vc1_work *W, uint32_t v, sk__vsys *sys)
{
    return solve_vertex_ex(W, v, sys, 0.0, 1.0);
}

/* "Natural" interior point of face(h) at from(h), used only to fix the free point of a boundary
 * chain: the parallelogram completion of the two (native-degree) edge points at the corner, i.e.
 * the control net without twist at that corner. */
static void natural_interior(const vc1_work *W, uint32_t h, double c[3])
{
    const sk_mesh *m = W->m;
    const double *V = m->positions + 3 * (size_t)sk_from(m, h);
    const double *a = W->P + 3 * (size_t)h, *b = W->P + 3 * (size_t)sk_opp(m->h_prev[h]);
    double delta = face_delta(m, m->h_face[h]); /* native edge point = V + Delta (P - V) */
    for (int x = 0; x < 3; ++x)
        c[x] = V[x] + delta * (a[x] - V[x]) + delta * (b[x] - V[x]);
}

/* System (4): C_{m+1} - nu^m C_m = B_m around v (here: C of the patch after edge m minus nu times
 * C of the patch before it). Unique for an odd cycle; a boundary chain leaves C of its first patch
 * free, chosen to minimise the sum of |C_k - natural_k|^2 over the chain. */
static void interior_points(vc1_work *W, uint32_t v)
{
    const sk_mesh *m = W->m;
    uint32_t E[SK_VSYS_MAX];
    int closed, n = ordered_edges(m, v, E, &closed);
    if (n == 0)
        return;
    const double *V = m->positions + 3 * (size_t)v;
    int npatch = closed ? n : n - 1;
    /* C_k = alpha_k x + beta_k, patch k = face(E[k]) between E[k] and E[k+1] */
    double alpha[SK_VSYS_MAX], beta[SK_VSYS_MAX][3];
    /* patch k follows edge k; for a cycle the first constraint is edge 0 (patch n-1 -> patch 0):
     * start from x = C_{n-1}; for a chain start from x = C_0 and use edges 1 .. n-2 */
    int first = closed ? 0 : 1;
    double ap = 1.0, bp[3] = {0, 0, 0};
    if (!closed) {
        alpha[0] = 1.0;
        beta[0][0] = beta[0][1] = beta[0][2] = 0.0;
    }
    for (int k = first; k < npatch; ++k) {
        uint32_t h = E[k];
        double nu = W->nu[h];
        const double *P = W->P + 3 * (size_t)h, *R = W->P + 3 * (size_t)sk_opp(h);
        double w1 = W->w1[h], w2 = -nu * W->w1[sk_opp(h)];
        alpha[k] = nu * ap;
        for (int x = 0; x < 3; ++x) {
            double B = (1.0 - nu) * P[x] + (2.0 / 3.0) * w1 * (R[x] - P[x]) +
                       (1.0 / 3.0) * w2 * (V[x] - P[x]); /* B_m of eq. (4) */
            beta[k][x] = nu * bp[x] + B;
            bp[x] = beta[k][x];
        }
        ap = alpha[k];
    }
    double X[3];
    if (closed) {
        /* x = C_{n-1} = alpha_{n-1} x + beta_{n-1}, alpha_{n-1} = prod nu = -1 (eq. 5, M odd) */
        double den = 1.0 - alpha[n - 1];
        for (int x = 0; x < 3; ++x)
            X[x] = beta[n - 1][x] / den;
    } else {
        double num[3] = {0, 0, 0}, den = 0.0;
        for (int k = 0; k < npatch; ++k) {
            double c[3];
            natural_interior(W, E[k], c);
            for (int x = 0; x < 3; ++x)
                num[x] += alpha[k] * (c[x] - beta[k][x]);
            den += alpha[k] * alpha[k];
        }
        for (int x = 0; x < 3; ++x)
            X[x] = num[x] / den;
    }
    for (int k = 0; k < npatch; ++k) {
        double *C = W->C + 3 * (size_t)E[k];
        for (int x = 0; x < 3; ++x)
            C[x] = alpha[k] * X[x] + beta[k][x];
    }
}

/* cubic edge control points of half-edge h: from(h), P[h], P[opp h], to(h) */
static void edge_cubic(const vc1_work *W, uint32_t h, double c[4][3])
{
    const sk_mesh *m = W->m;
    memcpy(c[0], m->positions + 3 * (size_t)sk_from(m, h), sizeof c[0]);
    memcpy(c[1], W->P + 3 * (size_t)h, sizeof c[1]);
    memcpy(c[2], W->P + 3 * (size_t)sk_opp(h), sizeof c[2]);
    memcpy(c[3], m->positions + 3 * (size_t)sk_to(m, h), sizeof c[3]);
}

/* quartic elevation of a cubic: q_j = j/4 c_{j-1} + (1 - j/4) c_j */
static void elevate(double c[4][3], double q[5][3])
{
    for (int j = 0; j <= 4; ++j)
        for (int x = 0; x < 3; ++x)
            q[j][x] = (j > 0 ? j / 4.0 * c[j - 1][x] : 0.0) + (j < 4 ? (1.0 - j / 4.0) * c[j][x] : 0.0);
}

static void assemble_patch(const vc1_work *W, uint32_t f, sk_smooth_patch *pa, double *b)
{
    const sk_mesh *m = W->m;
    uint32_t h[4];
    h[0] = m->f_halfedge[f];
    for (int i = 1; i < 4; ++i)
        h[i] = m->h_next[h[i - 1]];
    int n = h[3] == h[0] ? 3 : 4;
    pa->kind = (uint8_t)n;
    pa->degree = n == 3 ? 4 : 3;
    for (int i = 0; i < 4; ++i)
        pa->corners[i] = i < n ? sk_from(m, h[i]) : SK_INVALID;
    double c[4][3];
    if (n == 3) {
        double q[5][3];
        edge_cubic(W, h[0], c); /* corner 0 -> 1: b_{4-t, t, 0} */
        elevate(c, q);
        for (int t = 0; t <= 4; ++t)
            memcpy(b + 3 * sk__tri_index(4, t, 0), q[t], sizeof q[t]);
        edge_cubic(W, h[1], c); /* corner 1 -> 2: b_{0, 4-t, t} */
        elevate(c, q);
        for (int t = 0; t <= 4; ++t)
            memcpy(b + 3 * sk__tri_index(4, 4 - t, t), q[t], sizeof q[t]);
        edge_cubic(W, h[2], c); /* corner 2 -> 0: b_{t, 0, 4-t} */
        elevate(c, q);
        for (int t = 0; t <= 4; ++t)
            memcpy(b + 3 * sk__tri_index(4, 0, 4 - t), q[t], sizeof q[t]);
        memcpy(b + 3 * sk__tri_index(4, 1, 1), W->C + 3 * (size_t)h[0], 3 * sizeof(double)); /* b211 */
        memcpy(b + 3 * sk__tri_index(4, 2, 1), W->C + 3 * (size_t)h[1], 3 * sizeof(double)); /* b121 */
        memcpy(b + 3 * sk__tri_index(4, 1, 2), W->C + 3 * (size_t)h[2], 3 * sizeof(double)); /* b112 */
    } else {
        edge_cubic(W, h[0], c);
        for (int t = 0; t < 4; ++t)
            memcpy(b + 3 * t, c[t], sizeof c[t]);
        edge_cubic(W, h[1], c);
        for (int t = 0; t < 4; ++t)
            memcpy(b + 3 * (3 + 4 * t), c[t], sizeof c[t]);
        edge_cubic(W, h[2], c);
        for (int t = 0; t < 4; ++t)
            memcpy(b + 3 * ((3 - t) + 12), c[t], sizeof c[t]);
        edge_cubic(W, h[3], c);
        for (int t = 0; t < 4; ++t)
            memcpy(b + 3 * (4 * (3 - t)), c[t], sizeof c[t]);
        memcpy(b + 3 * 5, W->C + 3 * (size_t)h[0], 3 * sizeof(double));
        memcpy(b + 3 * 6, W->C + 3 * (size_t)h[1], 3 * sizeof(double));
        memcpy(b + 3 * 10, W->C + 3 * (size_t)h[2], 3 * sizeof(double));
        memcpy(b + 3 * 9, W->C + 3 * (size_t)h[3], 3 * sizeof(double));
    }
}

/* ---------------------------------------------------------------------------------------------
 * Regularity repair. Every solution of the vertex systems (8) with the interior points of (4)
 * gives a VC1 surface, so the free choices (here: the targets a vertex system is fitted to) can
 * be spent on patch quality. For every corner vertex of a patch that the report's regularity test
 * finds singular, the vertex system is re-solved with varied targets (directions blended towards
 * an even spread, lengths scaled); the variant with the fewest singular patches among the faces
 * whose control points it moves (the faces around the vertex and its neighbours) is kept if it
 * has fewer than the plain construction. Sequential in vertex order: deterministic.
 * ------------------------------------------------------------------------------------------- */

static const double repair_variants[][2] = {
    /* blend, length scale */
    {0.25, 1.0}, {0.5, 1.0}, {1.0, 1.0}, {0.0, 0.75}, {0.0, 1.3}, {0.5, 0.75}, {0.5, 1.3},
    {0.0, 0.55}, {0.0, 1.7}, {1.0, 0.7},
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

static size_t rebuild_local(sk_smooth *s, vc1_work *W, const uint32_t *verts, size_t nverts,
                            const uint32_t *faces, size_t nf)
{
    for (size_t i = 0; i < nverts; ++i)
        interior_points(W, verts[i]);
    size_t bad = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t f = faces[i];
        assemble_patch(W, f, s->patches + f, s->points + 3 * (size_t)s->patches[f].first);
        bad += sk__patch_singular(s, f, NULL);
    }
    return bad;
}

#define LOCAL_FACES 4096

static sk_status repair_regularity(sk_smooth *s, vc1_work *W, uint8_t *status, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t np = s->num_patches, nv = m->num_vertices;
    uint8_t *sing = sk__malloc_array(np + 1, 1), *cand = sk__calloc_array(nv + 1, 1), *mark = sk__calloc_array(np + 1, 1);
    uint32_t *faces = sk__malloc_array(LOCAL_FACES, sizeof *faces);
    if (!sing || !cand || !mark || !faces) {
        sk__free(sing);
        sk__free(cand);
        sk__free(mark);
        sk__free(faces);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the regularity repair");
    }
    long npl = (long)np;
    size_t nsing = 0;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : nsing)
#endif
    for (long p = 0; p < npl; ++p) {
        sing[p] = sk__patch_singular(s, (size_t)p, NULL);
        nsing += sing[p];
    }
    s->stats.singular_before_repair = nsing;
    for (size_t p = 0; p < np && nsing; ++p)
        if (sing[p])
            for (int i = 0; i < s->patches[p].kind; ++i)
                cand[s->patches[p].corners[i]] = 1;
    size_t repaired = 0;
    for (int round = 0; round < 2 && nsing; ++round) {
    if (round == 1) {
        /* second round: the corners of the patches still singular and their neighbours */
        memset(cand, 0, nv);
        for (size_t p = 0; p < np; ++p)
            if (sing[p])
                for (int i = 0; i < s->patches[p].kind; ++i) {
                    uint32_t c = s->patches[p].corners[i], h0 = m->v_halfedge[c], h = h0;
                    cand[c] = 1;
                    do {
                        cand[sk_to(m, h)] = 1;
                        h = sk_cw_out(m, h);
                    } while (h != h0);
                }
    }
    for (uint32_t v = 0; v < nv && nsing; ++v) {
        if (!cand[v] || status[v] == 3)
            continue;
        uint32_t verts[SK_VSYS_MAX + 1];
        size_t nverts;
        size_t nf = local_faces(m, v, mark, faces, LOCAL_FACES, verts, &nverts);
        size_t before = 0;
        for (size_t i = 0; i < nf; ++i)
            before += sing[faces[i]];
        if (before == 0)
            continue;
        /* the plain solution of v, to restore */
        uint32_t E[SK_VSYS_MAX];
        int closed, n = ordered_edges(m, v, E, &closed);
        double P0[3 * SK_VSYS_MAX], w0[SK_VSYS_MAX];
        for (int k = 0; k < n; ++k) {
            memcpy(P0 + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
            w0[k] = W->w1[E[k]];
        }
        size_t best = before;
        int best_variant = -1, best_code = status[v];
        sk__vsys sys;
        for (int t = 0; t < (int)N_VARIANTS; ++t) {
            int code = solve_vertex_ex(W, v, &sys, repair_variants[t][0], repair_variants[t][1]);
            if (code > status[v] || code >= 2)
                continue; /* never trade regularity for an angle violation or a failed system */
            size_t after = rebuild_local(s, W, verts, nverts, faces, nf);
            if (after < best) {
                best = after;
                best_variant = t;
                best_code = code;
            }
        }
        if (best_variant >= 0) {
            solve_vertex_ex(W, v, &sys, repair_variants[best_variant][0],
                            repair_variants[best_variant][1]);
            status[v] = (uint8_t)best_code;
            ++repaired;
        } else {
            for (int k = 0; k < n; ++k) {
                memcpy(W->P + 3 * (size_t)E[k], P0 + 3 * k, 3 * sizeof(double));
                W->w1[E[k]] = w0[k];
            }
        }
        rebuild_local(s, W, verts, nverts, faces, nf);
        for (size_t i = 0; i < nf; ++i) {
            uint8_t now = sk__patch_singular(s, faces[i], NULL);
            nsing = nsing - sing[faces[i]] + now;
            sing[faces[i]] = now;
        }
    }
    }
    s->stats.repaired_vertices = repaired;
    sk__free(sing);
    sk__free(cand);
    sk__free(mark);
    sk__free(faces);
    return SK_OK;
}

static sk_status vc1_build(sk_smooth *s, double alpha, sk_error *err)
{
    sk_mesh *m = s->config;
    size_t nh = m->num_halfedges, nf = m->num_faces, nv = m->num_vertices;
    sk_status st = SK_OK;
    vc1_work W = {0};
    double *target = sk__malloc_array(nh, 3 * sizeof(double));
    double *r = sk__malloc_array(nf + 1, sizeof(double));
    W.P = sk__calloc_array(nh, 3 * sizeof(double));
    W.w1 = sk__malloc_array(nh, sizeof(double));
    W.nu = sk__malloc_array(nh, sizeof(double));
    W.C = sk__calloc_array(nh, 3 * sizeof(double));
    uint8_t *status = sk__calloc_array(nv ? nv : 1, 1);
    if (!target || !r || !W.P || !W.w1 || !W.nu || !W.C || !status) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
        goto done;
    }
    W.m = m;
    W.normals = s->normals;
    W.target = target;
    W.r = r;
    W.alpha = alpha;
    double t0 = sk_seconds();
    if ((st = sk__wireframe_targets(m, s->normals, target, err)) != SK_OK)
        goto done;
    sk__patch_ratios(m, target, r);
    for (size_t h = 0; h < nh; ++h) {
        uint32_t f = m->h_face[h], g = m->h_face[h ^ 1u];
        W.nu[h] = (f != SK_INVALID && g != SK_INVALID) ? sk__nu(r[f], r[g]) : NAN;
        if (f != SK_INVALID && g != SK_INVALID && !(r[f] > 0.0 && r[g] > 0.0)) {
            st = sk__fail(err, SK_ERR_NUMERIC,
                          "edge (%u, %u): a neighbouring patch has zero target area (r_m = 0 in "
                          "eq. 7), the wire frame targets are collinear",
                          sk_from(m, (uint32_t)h), sk_to(m, (uint32_t)h));
            goto done;
        }
    }
    /* the vertex systems (8) */
    double max_res = 0.0, dev_sum = 0.0;
    size_t max_it = 0, fallback = 0, dev_n = 0, relaxed = 0;
    long nvl = (long)nv;
    int too_many = -1;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 256) reduction(max : max_res) \
    reduction(+ : dev_sum, dev_n, fallback, relaxed) reduction(max : max_it)
#endif
    for (long i = 0; i < nvl; ++i) {
        uint32_t v = (uint32_t)i;
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        sk__vsys sys;
        int code = solve_vertex(&W, v, &sys);
        status[v] = (uint8_t)code;
        relaxed += (size_t)sys.relaxed;
        if (code == 3) {
#ifdef SK_HAVE_OPENMP
#pragma omp critical(sk_vc1_too_many)
#endif
            too_many = (int)v;
            continue;
        }
        max_res = fmax(max_res, sys.residual);
        max_it = (size_t)sys.iterations > max_it ? (size_t)sys.iterations : max_it;
        fallback += (size_t)sys.used_fallback;
        for (int k = 0; k < sys.n_edges; ++k) {
            double len = hypot(sys.pstar[2 * k], sys.pstar[2 * k + 1]);
            if (len > 0.0) {
                dev_sum += hypot(sys.p[2 * k] - sys.pstar[2 * k],
                                 sys.p[2 * k + 1] - sys.pstar[2 * k + 1]) / len;
                dev_n++;
            }
        }
    }
    if (too_many >= 0) {
        st = sk__fail(err, SK_ERR_TOPOLOGY, "vertex %d has more than %d edges", too_many,
                      SK_VSYS_MAX);
        goto done;
    }
    s->stats.vertex_systems = nv;
    s->stats.max_iterations = max_it;
    s->stats.fallback_solves = fallback;
    s->stats.relaxed_vertices = relaxed;
    s->stats.max_residual = max_res;
    s->stats.mean_target_deviation = dev_n ? dev_sum / (double)dev_n : 0.0;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static)
#endif
    for (long i = 0; i < nvl; ++i)
        if (!m->v_deleted[i] && m->v_halfedge[i] != SK_INVALID)
            interior_points(&W, (uint32_t)i);
    double t1 = sk_seconds();
    s->stats.seconds_systems = t1 - t0;
    /* patches */
    s->num_patches = nf;
    s->patches = sk__malloc_array(nf + 1, sizeof(sk_smooth_patch));
    size_t npts = 0;
    for (uint32_t f = 0; f < nf; ++f)
        npts += sk_mesh_face_size(m, f) == 3 ? 15 : 16;
    s->points = sk__malloc_array(npts + 1, 3 * sizeof(double));
    sk__huge_hint(s->points, (npts + 1) * 3 * sizeof(double));
    if (!s->patches || !s->points) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    npts = 0;
    for (uint32_t f = 0; f < nf; ++f) {
        s->patches[f].first = (uint32_t)npts;
        npts += sk_mesh_face_size(m, f) == 3 ? 15 : 16;
    }
    s->num_points = npts;
    long nfl = (long)nf;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static)
#endif
    for (long f = 0; f < nfl; ++f)
        assemble_patch(&W, (uint32_t)f, s->patches + f, s->points + 3 * (size_t)s->patches[f].first);
    s->stats.seconds_patches = sk_seconds() - t1;
    /* regularity repair (it re-solves vertex systems, so it counts as vertex-system time) */
    double t2 = sk_seconds();
    if ((st = repair_regularity(s, &W, status, err)) != SK_OK)
        goto done;
    s->stats.seconds_repair = sk_seconds() - t2;
    size_t nprob = 0;
    for (size_t v = 0; v < nv; ++v) {
        s->stats.angle_violations += status[v] == 1;
        s->stats.failed_vertices += status[v] == 2;
        nprob += status[v] != 0;
    }
    if (nprob) {
        s->problems = sk__malloc_array(nprob, sizeof(uint32_t));
        if (!s->problems) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        for (size_t v = 0; v < nv; ++v)
            if (status[v])
                s->problems[s->num_problems++] = (uint32_t)v;
    }
done:
    sk__free(target);
    sk__free(r);
    sk__free(W.P);
    sk__free(W.w1);
    sk__free(W.nu);
    sk__free(W.C);
    sk__free(status);
    return st;
}

sk_status sk_smooth_build(const sk_mesh *mesh, const sk_smooth_opts *opts_in, sk_smooth **out,
                          sk_error *err)
{
    sk_smooth_opts opts = {0};
    if (opts_in)
        opts = *opts_in;
    if (!mesh || !out)
        return sk__fail(err, SK_ERR_ARG, "sk_smooth_build: NULL argument");
    *out = NULL;
    if (opts.scheme != SK_SMOOTH_VC1 && opts.scheme != SK_SMOOTH_PN)
        return sk__fail(err, SK_ERR_ARG, "unknown smooth scheme %d", (int)opts.scheme);
    double alpha = opts.alpha > 0.0 ? opts.alpha : 0.01;
    sk_status st = SK_OK;
    sk_mesh *work = NULL;
    double *normals = NULL;
    sk_smooth *s = sk__calloc_array(1, sizeof *s);
    if (!s)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    int blas_threads = sk__blas_serial_begin(); /* per-vertex and per-patch dense solves */
    s->scheme = opts.scheme;
    size_t nv = mesh->num_vertices;
    for (uint32_t f = 0; f < mesh->num_faces; ++f)
        if (!mesh->f_deleted[f] && sk_mesh_face_size(mesh, f) != 3) {
            st = sk__fail(err, SK_ERR_TOPOLOGY, "face %u has %zu sides: a triangle mesh is needed",
                          f, sk_mesh_face_size(mesh, f));
            goto fail;
        }
    for (size_t i = 0; i < 3 * nv; ++i)
        if (!isfinite(mesh->positions[i])) {
            st = sk__fail(err, SK_ERR_NUMERIC, "vertex %zu has a non-finite coordinate", i / 3);
            goto fail;
        }
    if ((st = sk_mesh_check_scale(mesh, err)) != SK_OK)
        goto fail;
    /* normals */
    double t0 = sk_seconds();
    normals = sk__malloc_array(nv + 1, 3 * sizeof(double));
    if (!normals) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto fail;
    }
    if (mesh->normals && !opts.estimate_normals) {
        for (size_t v = 0; v < nv; ++v) {
            double *n = normals + 3 * v;
            memcpy(n, mesh->normals + 3 * v, 3 * sizeof(double));
            if (mesh->v_halfedge[v] != SK_INVALID &&
                (!isfinite(n[0] + n[1] + n[2]) || sk__normalize3(n) == 0.0)) {
                st = sk__fail(err, SK_ERR_NUMERIC, "vertex %zu has a zero or non-finite normal", v);
                goto fail;
            }
        }
    } else if ((st = sk_mesh_vertex_normals(mesh, opts.normals, normals, err)) != SK_OK) {
        goto fail;
    }
    s->stats.seconds_normals = sk_seconds() - t0;
    if ((st = sk__progress(opts.progress, opts.progress_user, 0.1, err)) != SK_OK)
        goto fail;

    if (opts.scheme == SK_SMOOTH_PN) {
        if ((st = sk_mesh_copy(mesh, &s->config, err)) != SK_OK ||
            (st = sk_mesh_compact(s->config, NULL, NULL, err)) != SK_OK)
            goto fail;
        s->normals = normals;
        normals = NULL;
        t0 = sk_seconds();
        if ((st = sk__pn_build(s, err)) != SK_OK)
            goto fail;
        s->stats.seconds_patches = sk_seconds() - t0;
        *out = s;
        sk__ok(err);
        sk__blas_serial_end(blas_threads);
        return sk__progress(opts.progress, opts.progress_user, 1.0, err);
    }

    /* parity split */
    const sk_mesh *base = mesh;
    if (opts.allow_split) {
        double *n2 = NULL;
        if ((st = split_odd_components(mesh, normals, &work, &n2, &s->stats.split_edges, err)) !=
            SK_OK)
            goto fail;
        if (work) {
            sk__free(normals);
            normals = n2;
            base = work;
        }
    }
    t0 = sk_seconds();
    if ((st = sk_edge_deletion(base, &s->config, &s->deleted, &s->stats.deletion, err)) != SK_OK)
        goto fail;
    s->num_deleted = s->stats.deletion.deleted_edges;
    s->stats.seconds_deletion = sk_seconds() - t0;
    s->normals = normals;
    normals = NULL;
    if ((st = sk__progress(opts.progress, opts.progress_user, 0.3, err)) != SK_OK)
        goto fail;
    if ((st = vc1_build(s, alpha, err)) != SK_OK)
        goto fail;
    sk_mesh_destroy(&work);
    *out = s;
    sk__ok(err);
    sk__blas_serial_end(blas_threads);
    return sk__progress(opts.progress, opts.progress_user, 1.0, err);
fail:
    sk_mesh_destroy(&work);
    sk__free(normals);
    sk_smooth_destroy(&s);
    sk__blas_serial_end(blas_threads);
    return st;
}
