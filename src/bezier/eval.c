/* Bezier patches: evaluation by de Casteljau (triangles, curves) and Bernstein sums (tensor
 * patches), first derivatives and normals, boundary curves. */
#include "bezier/bezier_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

void sk__curve_eval(const double *cp, unsigned n, double t, double pt[3], double d[3])
{
    double w[3 * (SK_PATCH_MAX_DEGREE + 1)];
    memcpy(w, cp, 3 * (n + 1) * sizeof(double));
    for (unsigned r = n; r >= 1; --r) {
        if (r == 1 && d)
            for (int c = 0; c < 3; ++c)
                d[c] = (double)n * (w[3 + c] - w[c]);
        for (unsigned i = 0; i < r; ++i)
            for (int c = 0; c < 3; ++c)
                w[3 * i + c] = (1.0 - t) * w[3 * i + c] + t * w[3 * (i + 1) + c];
    }
    if (n == 0 && d)
        d[0] = d[1] = d[2] = 0.0;
    memcpy(pt, w, 3 * sizeof(double));
}

/* The first level of de Casteljau reads the control points in place (no copy of the net).
 * Inlined with a constant degree for the quartic triangles of VC1 (the report evaluates them
 * densely): the same operations in the same order, so the same results to the bit. */
static inline __attribute__((always_inline)) void tri_eval_n(const double *cp, const unsigned n,
                                                             double v, double w, double pt[3],
                                                             double d1[3], double d2[3])
{
    double u = 1.0 - v - w;
    double net[3 * (SK_PATCH_MAX_DEGREE + 1) * (SK_PATCH_MAX_DEGREE + 2) / 2];
    const double *src = cp;
    for (unsigned r = n; r > 1; --r) { /* degree r -> r - 1 (indices shrink) */
        for (unsigned k = 0; k < r; ++k) {
            unsigned row = sk_tri_index(r, 0, k), up = sk_tri_index(r, 0, k + 1);
            unsigned orow = sk_tri_index(r - 1, 0, k);
            for (unsigned j = 0; j + k < r; ++j) {
                const double *a = src + 3 * (row + j); /* b_{i+1,j,k} */
                const double *b = a + 3;               /* b_{i,j+1,k} */
                const double *c = src + 3 * (up + j);  /* b_{i,j,k+1} */
                double *o = net + 3 * (orow + j);
                for (int x = 0; x < 3; ++x)
                    o[x] = u * a[x] + v * b[x] + w * c[x];
            }
        }
        src = net;
    }
    const double *b100 = src, *b010 = src + 3 * sk_tri_index(1, 1, 0),
                 *b001 = src + 3 * sk_tri_index(1, 0, 1);
    for (int x = 0; x < 3; ++x) {
        pt[x] = u * b100[x] + v * b010[x] + w * b001[x];
        if (d1)
            d1[x] = (double)n * (b010[x] - b100[x]);
        if (d2)
            d2[x] = (double)n * (b001[x] - b100[x]);
    }
}

void sk__tri_eval(const double *cp, unsigned n, double v, double w, double pt[3], double d1[3],
                  double d2[3])
{
    if (n == 0) {
        memcpy(pt, cp, 3 * sizeof(double));
        if (d1)
            d1[0] = d1[1] = d1[2] = 0.0;
        if (d2)
            d2[0] = d2[1] = d2[2] = 0.0;
        return;
    }
    if (n == 4)
        tri_eval_n(cp, 4, v, w, pt, d1, d2);
    else
        tri_eval_n(cp, n, v, w, pt, d1, d2);
}

/* constant degrees (bicubic and quartic patches, their derivatives) inlined: same results */
void sk__bernstein(unsigned n, double t, double *B, double *dB)
{
    switch (n) {
    case 3: sk__bernstein_n(3, t, B, dB); break;
    case 4: sk__bernstein_n(4, t, B, dB); break;
    default: sk__bernstein_n(n, t, B, dB); break;
    }
}

/* Tensor patch: sums over the Bernstein bases in s and t (point and both derivatives). */
static inline __attribute__((always_inline)) void tensor_eval_n(const double *cp,
                                                                const unsigned du,
                                                                const unsigned dv, double s,
                                                                double t, double pt[3],
                                                                double ds[3], double dt[3])
{
    double Bs[SK_PATCH_MAX_DEGREE + 1], dBs[SK_PATCH_MAX_DEGREE + 1];
    double Bt[SK_PATCH_MAX_DEGREE + 1], dBt[SK_PATCH_MAX_DEGREE + 1];
    sk__bernstein_n(du, s, Bs, dBs);
    sk__bernstein_n(dv, t, Bt, dBt);
    double P[3] = {0, 0, 0}, S[3] = {0, 0, 0}, T[3] = {0, 0, 0};
    for (unsigned j = 0; j <= dv; ++j) {
        const double *row = cp + 3 * sk_tensor_index(du, 0, j);
        double r[3] = {0, 0, 0}, dr[3] = {0, 0, 0};
        for (unsigned i = 0; i <= du; ++i)
            for (int x = 0; x < 3; ++x) {
                r[x] += Bs[i] * row[3 * i + x];
                dr[x] += dBs[i] * row[3 * i + x];
            }
        for (int x = 0; x < 3; ++x) {
            P[x] += Bt[j] * r[x];
            S[x] += Bt[j] * dr[x];
            T[x] += dBt[j] * r[x];
        }
    }
    memcpy(pt, P, sizeof P);
    if (ds)
        memcpy(ds, S, sizeof S);
    if (dt)
        memcpy(dt, T, sizeof T);
}

/* the bicubic patches of VC1 with constant degrees inlined (same results) */
static void tensor_eval(const double *cp, unsigned du, unsigned dv, double s, double t,
                        double pt[3], double ds[3], double dt[3])
{
    if (du == 3 && dv == 3)
        tensor_eval_n(cp, 3, 3, s, t, pt, ds, dt);
    else
        tensor_eval_n(cp, du, dv, s, t, pt, ds, dt);
}

double sk_bezier_eval(sk_patch_kind kind, unsigned degree, unsigned degree_v, const double *cp,
                      double a, double b, double pt[3], double du[3], double dv[3],
                      double normal[3])
{
    double P[3], D1[3], D2[3], n[3];
    if (kind == SK_PATCH_TRIANGLE)
        sk__tri_eval(cp, degree, a, b, P, D1, D2);
    else
        tensor_eval(cp, degree, degree_v, a, b, P, D1, D2);
    sk__cross3(n, D1, D2);
    double len = sk__norm3(n);
    if (pt)
        memcpy(pt, P, sizeof P);
    if (du)
        memcpy(du, D1, sizeof D1);
    if (dv)
        memcpy(dv, D2, sizeof D2);
    if (normal) {
        if (len > 0.0)
            sk__scale3(normal, n, 1.0 / len);
        else
            normal[0] = normal[1] = normal[2] = 0.0;
    }
    return len;
}

double sk_patch_eval(const sk_patch_set *set, size_t i, double a, double b, double pt[3],
                     double du[3], double dv[3], double normal[3])
{
    const sk_patch *p = &set->patches[i];
    return sk_bezier_eval((sk_patch_kind)p->kind, p->degree, p->degree_v, sk_patch_cp(set, i), a, b,
                          pt, du, dv, normal);
}

unsigned sk_patch_edge_curve(const sk_patch_set *set, size_t pi, unsigned c, double *cp)
{
    const sk_patch *p = &set->patches[pi];
    const double *b = sk_patch_cp(set, pi);
    unsigned n = p->degree;
    if (p->kind == SK_PATCH_TRIANGLE) {
        for (unsigned i = 0; i <= n; ++i) {
            unsigned idx = c == 0 ? sk_tri_index(n, i, 0)           /* w = 0: corner 0 -> 1 */
                           : c == 1 ? sk_tri_index(n, n - i, i)     /* u = 0: corner 1 -> 2 */
                                    : sk_tri_index(n, 0, n - i);    /* v = 0: corner 2 -> 0 */
            memcpy(cp + 3 * i, b + 3 * idx, 3 * sizeof(double));
        }
        return n;
    }
    unsigned du = p->degree, dv = p->degree_v, m = (c % 2 == 0) ? du : dv;
    for (unsigned i = 0; i <= m; ++i) {
        unsigned s, t;
        switch (c) {
        case 0: s = i; t = 0; break;
        case 1: s = du; t = i; break;
        case 2: s = du - i; t = dv; break;
        default: s = 0; t = dv - i; break;
        }
        memcpy(cp + 3 * i, b + 3 * sk_tensor_index(du, s, t), 3 * sizeof(double));
    }
    return m;
}

void sk_patch_edge_point(const sk_patch_set *set, size_t i, unsigned c, double t, double pt[3])
{
    double cp[3 * (SK_PATCH_MAX_DEGREE + 1)];
    unsigned n = sk_patch_edge_curve(set, i, c, cp);
    sk__curve_eval(cp, n, t, pt, NULL);
}
