/* System (4) of Cottin & van Damme: the interior control points around each vertex, and the
 * assembly of the patches (quartic triangles, bicubic quads) from the cubic boundary curves and
 * the interior points. */
#include "smooth/vc1_internal.h"

#include <string.h>

/* "Natural" interior point of face(h) at from(h), used only to fix the free point of a boundary
 * chain: the parallelogram completion of the two (native-degree) edge points at the corner, i.e.
 * the control net without twist at that corner. */
static void natural_interior(const sk__vc1_work *W, uint32_t h, double c[3])
{
    const sk_mesh *m = W->m;
    const double *V = m->positions + 3 * (size_t)sk_from(m, h);
    const double *a = W->P + 3 * (size_t)h, *b = W->P + 3 * (size_t)sk_opp(m->h_prev[h]);
    double delta = sk__face_delta(m, m->h_face[h]); /* native edge point = V + Delta (P - V) */
    for (int x = 0; x < 3; ++x)
        c[x] = V[x] + delta * (a[x] - V[x]) + delta * (b[x] - V[x]);
}

/* System (4): C_{m+1} - nu^m C_m = B_m around v (here: C of the patch after edge m minus nu times
 * C of the patch before it). Unique for an odd cycle; a boundary chain leaves C of its first patch
 * free, chosen to minimise the sum of |C_k - natural_k|^2 over the chain. */
void sk__vc1_interior_points(sk__vc1_work *W, uint32_t v)
{
    uint32_t E[SK_VSYS_MAX];
    if (W->crease_v && W->crease_v[v]) { /* a chain per sector (crease.c) */
        sk__vc1_crease_interior_points(W, v);
        return;
    }
    int closed, n = sk__vc1_ordered_edges(W->m, v, E, &closed);
    if (n <= 0 || n > SK_VSYS_MAX)
        return;
    sk__vc1_interior_star(W, v, E, n, closed);
}

void sk__vc1_interior_star(sk__vc1_work *W, uint32_t v, const uint32_t *E, int n, int closed)
{
    const sk_mesh *m = W->m;
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
static void edge_cubic(const sk__vc1_work *W, uint32_t h, double c[4][3])
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

void sk__vc1_patch_header(const sk_mesh *m, uint32_t f, sk_patch *pa)
{
    uint32_t h[4];
    h[0] = m->f_halfedge[f];
    for (int i = 1; i < 4; ++i)
        h[i] = m->h_next[h[i - 1]];
    int n = h[3] == h[0] ? 3 : 4;
    pa->kind = n == 3 ? SK_PATCH_TRIANGLE : SK_PATCH_TENSOR;
    pa->degree = n == 3 ? 4 : 3;
    pa->degree_v = n == 3 ? 0 : 3;
    pa->tag = f;
    for (int i = 0; i < 4; ++i)
        pa->corner_ids[i] = i < n ? sk_from(m, h[i]) : SK_INVALID;
}

void sk__vc1_assemble_patch(const sk__vc1_work *W, uint32_t f, double *b)
{
    const sk_mesh *m = W->m;
    uint32_t h[4];
    h[0] = m->f_halfedge[f];
    for (int i = 1; i < 4; ++i)
        h[i] = m->h_next[h[i - 1]];
    int n = h[3] == h[0] ? 3 : 4;
    double c[4][3];
    if (n == 3) {
        double q[5][3];
        edge_cubic(W, h[0], c); /* corner 0 -> 1: b_{4-t, t, 0} */
        elevate(c, q);
        for (int t = 0; t <= 4; ++t)
            memcpy(b + 3 * sk_tri_index(4, (unsigned)t, 0), q[t], sizeof q[t]);
        edge_cubic(W, h[1], c); /* corner 1 -> 2: b_{0, 4-t, t} */
        elevate(c, q);
        for (int t = 0; t <= 4; ++t)
            memcpy(b + 3 * sk_tri_index(4, 4 - (unsigned)t, (unsigned)t), q[t], sizeof q[t]);
        edge_cubic(W, h[2], c); /* corner 2 -> 0: b_{t, 0, 4-t} */
        elevate(c, q);
        for (int t = 0; t <= 4; ++t)
            memcpy(b + 3 * sk_tri_index(4, 0, 4 - (unsigned)t), q[t], sizeof q[t]);
        memcpy(b + 3 * sk_tri_index(4, 1, 1), W->C + 3 * (size_t)h[0], 3 * sizeof(double)); /* b211 */
        memcpy(b + 3 * sk_tri_index(4, 2, 1), W->C + 3 * (size_t)h[1], 3 * sizeof(double)); /* b121 */
        memcpy(b + 3 * sk_tri_index(4, 1, 2), W->C + 3 * (size_t)h[2], 3 * sizeof(double)); /* b112 */
    } else {
        /* sides (0,0)->(3,0), (3,0)->(3,3), (3,3)->(0,3), (0,3)->(0,0) of the bicubic net */
        for (unsigned side = 0; side < 4; ++side) {
            edge_cubic(W, h[side], c);
            for (unsigned t = 0; t < 4; ++t) {
                unsigned i = side == 0 ? t : side == 1 ? 3 : side == 2 ? 3 - t : 0;
                unsigned j = side == 0 ? 0 : side == 1 ? t : side == 2 ? 3 : 3 - t;
                memcpy(b + 3 * sk_tensor_index(3, i, j), c[t], sizeof c[t]);
            }
        }
        static const unsigned inner[4][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}}; /* next to corner */
        for (unsigned k = 0; k < 4; ++k)
            memcpy(b + 3 * sk_tensor_index(3, inner[k][0], inner[k][1]),
                   W->C + 3 * (size_t)h[k], 3 * sizeof(double));
    }
}
