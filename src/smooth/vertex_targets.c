/* The vertex systems of the VC1 construction (Cottin & van Damme, section 4, eq. (8)) set up
 * from the wire frame targets in each vertex's tangent plane, with the target blending that keeps
 * the tangent control points within the angle bounds alpha < angle / pi < 1 - alpha. */
#include "smooth/vc1_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

int sk__vc1_ordered_edges(const sk_mesh *m, uint32_t v, uint32_t *E, int *closed)
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

/* A vertex's star between the set-up of its system and the solve's use */
typedef struct vertex_frame {
    uint32_t E[SK_VSYS_MAX];
    double e1[3], e2[3];
    double orig[2 * SK_VSYS_MAX]; /* the targets before blending */
    double blend;
} vertex_frame;

/* v's system (8) from its star (not at a crease vertex); 0 when v has more than SK_VSYS_MAX edges */
static int vertex_setup(const sk__vc1_work *W, uint32_t v, sk__vsys *sys, vertex_frame *F,
                        double blend, double lscale)
{
    const sk_mesh *m = W->m;
    uint32_t *E = F->E;
    int closed, n = sk__vc1_ordered_edges(m, v, E, &closed);
    if (n <= 0 || n > SK_VSYS_MAX)
        return 0;
    sys->fixed_first = sys->fixed_last = 0;
    const double *V = m->positions + 3 * (size_t)v, *nv = W->normals + 3 * (size_t)v;
    double *e1 = F->e1, *e2 = F->e2;
    sk__tangent_basis(nv, e1, e2);
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
            sys->du[k] = sk__face_delta(m, m->h_face[h]);
            sys->dd[k] = sk__face_delta(m, m->h_face[sk_opp(h)]);
            sys->nu[k] = W->nu[h];
        } else {
            sys->du[k] = sys->dd[k] = 1.0;
            sys->nu[k] = -1.0;
        }
    }
    memcpy(F->orig, sys->pstar, sizeof(double) * (size_t)(2 * n));
    if (blend > 0.0)
        blend_targets(F->orig, sys->pstar, n, closed, W->alpha, blend, 0.0);
    F->blend = blend;
    return n;
}

/* The angle bounds alpha pi < angle < pi (1 - alpha) at every corner of the solution, as
 * sk__vsys_angles decides them; a corner whose cross product is positive and whose cosine is
 * inside (-cos(alpha pi), cos(alpha pi)) by a relative margin of 1e-9 (far above the rounding of
 * the atan2 there) is within them for certain, so the atan2s are taken only when one is not. */
static int angle_bounds_met(const sk__vsys *s, double alpha)
{
    int n = s->n_edges, pairs = s->closed ? n : n - 1, sure = 1;
    double c = cos(alpha * M_PI) * (1.0 - 1e-9);
    for (int k = 0; k < pairs && sure; ++k) {
        const double *a = s->p + 2 * k, *b = s->p + 2 * ((k + 1) % n);
        double cr = a[0] * b[1] - a[1] * b[0], dt = a[0] * b[0] + a[1] * b[1];
        double ll = sqrt((a[0] * a[0] + a[1] * a[1]) * (b[0] * b[0] + b[1] * b[1]));
        sure = cr > 0.0 && fabs(dt) < c * ll;
    }
    if (sure)
        return 1;
    double lo, hi;
    sk__vsys_angles(s, &lo, &hi);
    return !(lo <= alpha * M_PI || hi >= M_PI * (1.0 - alpha));
}

/* After the solve (ok: its return value): the angle bounds, met by relaxed targets where needed;
 * W->P and W->w1 of v's edges written; sk__vc1_solve_vertex's code */
static int vertex_finish(sk__vc1_work *W, uint32_t v, sk__vsys *sys, const vertex_frame *F, int ok)
{
    const sk_mesh *m = W->m;
    const uint32_t *E = F->E;
    const double *orig = F->orig, *e1 = F->e1, *e2 = F->e2, blend = F->blend;
    const double *V = m->positions + 3 * (size_t)v;
    int n = sys->n_edges, closed = sys->closed;
    int bad = ok != 0 || !angle_bounds_met(sys, W->alpha);
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
        ok = sk__vsys_solve_memo(sys, W->memo);
        bad = ok != 0 || !angle_bounds_met(sys, W->alpha);
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

int sk__vc1_solve_vertex(sk__vc1_work *W, uint32_t v, sk__vsys *sys, double blend, double lscale)
{
    if (W->crease_v && W->crease_v[v]) /* cut into sectors at its crease edges (crease.c) */
        return sk__vc1_solve_crease_vertex(W, v, sys, blend, lscale);
    vertex_frame F;
    if (!vertex_setup(W, v, sys, &F, blend, lscale))
        return 3;
    return vertex_finish(W, v, sys, &F, sk__vsys_solve_memo(sys, W->memo));
}

void sk__vc1_solve_vertices(sk__vc1_work *W, const uint32_t *v, int count, sk__vsys *sys,
                            int *code)
{
    vertex_frame F[SK_VC1_VERTEX_CHUNK];
    sk__vsys *batch[SK_VC1_VERTEX_CHUNK] = {NULL};
    int at[SK_VC1_VERTEX_CHUNK], ret[SK_VC1_VERTEX_CHUNK], nb = 0;
    for (int i = 0; i < count; ++i) {
        code[i] = -1;
        if (W->memo || (W->crease_v && W->crease_v[v[i]]))
            code[i] = sk__vc1_solve_vertex(W, v[i], &sys[i], 0.0, 1.0);
        else if (!vertex_setup(W, v[i], &sys[i], &F[i], 0.0, 1.0))
            code[i] = 3;
        else {
            at[nb] = i;
            batch[nb++] = &sys[i];
        }
    }
    sk__vsys_solve_lanes(batch, nb, ret);
    for (int b = 0; b < nb; ++b)
        code[at[b]] = vertex_finish(W, v[at[b]], &sys[at[b]], &F[at[b]], ret[b]);
}

void sk__vc1_blend_targets(const double *orig, double *out, int n, int closed, double alpha,
                           double b, double lb)
{
    blend_targets(orig, out, n, closed, alpha, b, lb);
}

void sk__bound_ratios(const sk_mesh *m, double *r, double max_ratio)
{
    /* Any positive r per face gives ratios nu = -r_up / r_down that satisfy the product condition
     * (5) around every vertex (the product telescopes), so r may be changed freely. A sliver or a
     * long quad next to small faces makes r_up / r_down extreme (cow: 110), which makes the
     * recurrence (8) stiff and its fitted tangents fold. r is replaced by its lower Lipschitz
     * envelope in log r over the face adjacency: log r_f <- min over faces g of (log r_g +
     * log(max_ratio) * distance(f, g)), so that neighbouring ratios stay within max_ratio while
     * faces that already satisfy the bound next to all their neighbours keep their r. Computed
     * by forward and backward relaxation sweeps (at most SK_RATIO_SWEEPS pairs; the VC1 property
     * does not depend on reaching the bound). */
    size_t nf = m->num_faces;
    long nfl = (long)nf;
    double L = log(max_ratio);
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl > 100000)
#endif
    for (long f = 0; f < nfl; ++f)
        if (!m->f_deleted[f])
            r[f] = log(r[f]); /* all positive: checked by the caller */
    for (int sweep = 0; sweep < 2 * SK_RATIO_SWEEPS; ++sweep) {
        int changed = 0;
        for (size_t i = 0; i < nf; ++i) {
            size_t f = sweep & 1 ? nf - 1 - i : i;
            if (m->f_deleted[f])
                continue;
            uint32_t h0 = m->f_halfedge[f], h = h0;
            double lo = r[f];
            do {
                uint32_t g = m->h_face[sk_opp(h)];
                if (g != SK_INVALID && r[g] + L < lo)
                    lo = r[g] + L;
                h = m->h_next[h];
            } while (h != h0);
            if (lo < r[f]) {
                r[f] = lo;
                changed = 1;
            }
        }
        if (!changed)
            break;
    }
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl > 100000)
#endif
    for (long f = 0; f < nfl; ++f)
        if (!m->f_deleted[f])
            r[f] = exp(r[f]);
}
