/* Bezier patches: evaluation by de Casteljau, boundary curves, degree elevation, and the exact
 * split of a triangular patch into three tensor-product patches (for CAD export). */
#include "surfkit/bezier.h"
#include "core/internal.h"
#include "core/vec.h"
#include "smooth/smooth_internal.h"

#include <lapacke.h>
#include <string.h>

/* de Casteljau on a curve of degree n: point and derivative at t. */
static void curve_eval(const double *cp, unsigned n, double t, double pt[3], double d[3])
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

/* de Casteljau on a triangle net of degree n at barycentric (u, v, w): reduce to degree 1, whose
 * three points give the point and the derivatives toward corners 1 and 2. The first level reads
 * the control points in place (no copy of the net). */
static void tri_eval(const double *cp, unsigned n, double v, double w, double pt[3], double d1[3],
                     double d2[3])
{
    double u = 1.0 - v - w;
    double net[3 * SK_PATCH_MAX_POINTS];
    if (n == 0) {
        memcpy(pt, cp, 3 * sizeof(double));
        if (d1)
            d1[0] = d1[1] = d1[2] = 0.0;
        if (d2)
            d2[0] = d2[1] = d2[2] = 0.0;
        return;
    }
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

/* Bernstein basis B_i^n(t), i = 0..n, and the derivatives dB_i^n/dt (dB may be NULL). */
void sk__bernstein(unsigned n, double t, double *B, double *dB)
{
    double s = 1.0 - t;
    B[0] = 1.0;
    for (unsigned r = 1; r <= n; ++r) {
        if (r == n && dB) { /* dB_i^n = n (B_{i-1}^{n-1} - B_i^{n-1}) */
            for (unsigned i = 0; i <= n; ++i)
                dB[i] = (double)n * ((i > 0 ? B[i - 1] : 0.0) - (i < n ? B[i] : 0.0));
        }
        double saved = 0.0;
        for (unsigned i = 0; i < r; ++i) {
            double tmp = B[i];
            B[i] = saved + s * tmp;
            saved = t * tmp;
        }
        B[r] = saved;
    }
    if (n == 0 && dB)
        dB[0] = 0.0;
}

/* Tensor patch: sums over the Bernstein bases in s and t (point and both derivatives). */
static void tensor_eval(const double *cp, unsigned du, unsigned dv, double s, double t,
                        double pt[3], double ds[3], double dt[3])
{
    double Bs[SK_PATCH_MAX_DEGREE + 1], dBs[SK_PATCH_MAX_DEGREE + 1];
    double Bt[SK_PATCH_MAX_DEGREE + 1], dBt[SK_PATCH_MAX_DEGREE + 1];
    sk__bernstein(du, s, Bs, dBs);
    sk__bernstein(dv, t, Bt, dBt);
    double P[3] = {0, 0, 0}, S[3] = {0, 0, 0}, T[3] = {0, 0, 0};
    for (unsigned j = 0; j <= dv; ++j) {
        const double *row = cp + 3 * j * (du + 1);
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

double sk_bezier_eval(sk_patch_kind kind, unsigned degree, unsigned degree_v, const double *cp,
                      double a, double b, double pt[3], double du[3], double dv[3],
                      double normal[3])
{
    double P[3], D1[3], D2[3], n[3];
    if (kind == SK_PATCH_TRIANGLE)
        tri_eval(cp, degree, a, b, P, D1, D2);
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

double sk_patch_eval(const sk_patch *p, double a, double b, double pt[3], double du[3],
                     double dv[3], double normal[3])
{
    return sk_bezier_eval(p->kind, p->degree, p->degree_v, p->cp, a, b, pt, du, dv, normal);
}

unsigned sk_patch_edge_curve(const sk_patch *p, unsigned c, double *cp)
{
    unsigned n = p->degree;
    if (p->kind == SK_PATCH_TRIANGLE) {
        for (unsigned i = 0; i <= n; ++i) {
            unsigned idx = c == 0 ? sk_tri_index(n, i, 0)           /* w = 0: corner 0 -> 1 */
                           : c == 1 ? sk_tri_index(n, n - i, i)     /* u = 0: corner 1 -> 2 */
                                    : sk_tri_index(n, 0, n - i);    /* v = 0: corner 2 -> 0 */
            memcpy(cp + 3 * i, p->cp + 3 * idx, 3 * sizeof(double));
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
        memcpy(cp + 3 * i, p->cp + 3 * (t * (du + 1) + s), 3 * sizeof(double));
    }
    return m;
}

void sk_patch_edge_point(const sk_patch *p, unsigned c, double t, double pt[3])
{
    double cp[3 * (SK_PATCH_MAX_DEGREE + 1)];
    unsigned n = sk_patch_edge_curve(p, c, cp);
    curve_eval(cp, n, t, pt, NULL);
}

/* Tensor patch of degree n x n equal to tri o X, where X maps (s, t) bilinearly onto the domain
 * quadrilateral with barycentric corners q[0..3] (order (0,0), (1,0), (1,1), (0,1)). The
 * composition has degree n in s and in t, so interpolating it at (n+1)^2 grid points is exact. */
static sk_status compose_bilinear(const sk_patch *tri, double q[4][3], sk_patch *out,
                                  sk_error *err)
{
    unsigned n = tri->degree, m = n + 1;
    double M[(SK_PATCH_MAX_DEGREE + 1) * (SK_PATCH_MAX_DEGREE + 1)];
    double R[3 * SK_PATCH_MAX_POINTS]; /* samples; then solved in place */
    lapack_int ipiv[SK_PATCH_MAX_DEGREE + 1];
    for (unsigned a = 0; a < m; ++a) { /* M[a][i] = B_i(a / n), row-major */
        double B[SK_PATCH_MAX_DEGREE + 1];
        sk__bernstein(n, n ? (double)a / n : 0.0, B, NULL);
        for (unsigned i = 0; i < m; ++i)
            M[a * m + i] = B[i];
    }
    for (unsigned b = 0; b < m; ++b)
        for (unsigned a = 0; a < m; ++a) {
            double s = n ? (double)a / n : 0.0, t = n ? (double)b / n : 0.0;
            double bary[3];
            for (int x = 0; x < 3; ++x)
                bary[x] = (1 - s) * (1 - t) * q[0][x] + s * (1 - t) * q[1][x] + s * t * q[2][x] +
                          (1 - s) * t * q[3][x];
            tri_eval(tri->cp, n, bary[1], bary[2], R + 3 * (b * m + a), NULL, NULL);
        }
    /* samples S = M C M^T (C indexed [j][i]): solve M Y = S^T-wise in two passes */
    double A[(SK_PATCH_MAX_DEGREE + 1) * (SK_PATCH_MAX_DEGREE + 1)];
    double rhs[(SK_PATCH_MAX_DEGREE + 1) * 3 * (SK_PATCH_MAX_DEGREE + 1)];
    for (int pass = 0; pass < 2; ++pass) {
        /* pass 0 solves along s (index a) for every row b; pass 1 along t (index b) */
        memcpy(A, M, sizeof(double) * m * m);
        for (unsigned r = 0; r < m; ++r)
            for (unsigned other = 0; other < m; ++other)
                for (int x = 0; x < 3; ++x) {
                    unsigned idx = pass == 0 ? other * m + r : r * m + other;
                    rhs[r * 3 * m + 3 * other + (unsigned)x] = R[3 * idx + (unsigned)x];
                }
        lapack_int info = LAPACKE_dgesv(LAPACK_ROW_MAJOR, (lapack_int)m, (lapack_int)(3 * m), A,
                                        (lapack_int)m, ipiv, rhs, (lapack_int)(3 * m));
        if (info == LAPACK_WORK_MEMORY_ERROR || info == LAPACK_TRANSPOSE_MEMORY_ERROR)
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
        if (info != 0)
            return sk__fail(err, SK_ERR_NUMERIC, "Bernstein interpolation failed (info %d)",
                            (int)info);
        for (unsigned r = 0; r < m; ++r)
            for (unsigned other = 0; other < m; ++other)
                for (int x = 0; x < 3; ++x) {
                    unsigned idx = pass == 0 ? other * m + r : r * m + other;
                    R[3 * idx + (unsigned)x] = rhs[r * 3 * m + 3 * other + (unsigned)x];
                }
    }
    memset(out, 0, sizeof *out);
    out->kind = SK_PATCH_TENSOR;
    out->degree = out->degree_v = n;
    memcpy(out->cp, R, 3 * m * m * sizeof(double));
    for (int c = 0; c < 4; ++c)
        out->corner_ids[c] = SK_INVALID;
    return SK_OK;
}

sk_status sk_patch_split_triangle(const sk_patch *tri, sk_patch out[3], sk_error *err)
{
    if (tri->kind != SK_PATCH_TRIANGLE || tri->degree > SK_PATCH_MAX_DEGREE)
        return sk__fail(err, SK_ERR_ARG, "not a triangular patch of degree <= %d",
                        SK_PATCH_MAX_DEGREE);
    static const double E[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (unsigned q = 0; q < 3; ++q) {
        unsigned qn = (q + 1) % 3, qp = (q + 2) % 3;
        double dom[4][3];
        for (int x = 0; x < 3; ++x) {
            dom[0][x] = E[q][x];
            dom[1][x] = 0.5 * (E[q][x] + E[qn][x]);
            dom[2][x] = 1.0 / 3.0;
            dom[3][x] = 0.5 * (E[q][x] + E[qp][x]);
        }
        sk_status st = compose_bilinear(tri, dom, &out[q], err);
        if (st)
            return st;
        out[q].corner_ids[0] = tri->corner_ids[q];
    }
    return SK_OK;
}

sk_status sk_patch_triangle_to_degenerate_tensor(const sk_patch *tri, sk_patch *out, sk_error *err)
{
    if (tri->kind != SK_PATCH_TRIANGLE || tri->degree > SK_PATCH_MAX_DEGREE)
        return sk__fail(err, SK_ERR_ARG, "not a triangular patch of degree <= %d",
                        SK_PATCH_MAX_DEGREE);
    double dom[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
    sk_status st = compose_bilinear(tri, dom, out, err);
    if (st == SK_OK) {
        out->corner_ids[0] = out->corner_ids[3] = tri->corner_ids[0];
        out->corner_ids[1] = tri->corner_ids[1];
        out->corner_ids[2] = tri->corner_ids[2];
    }
    return st;
}

sk_status sk_patch_elevate(const sk_patch *p, unsigned degree, unsigned degree_v, sk_patch *out,
                           sk_error *err)
{
    if (degree > SK_PATCH_MAX_DEGREE || degree_v > SK_PATCH_MAX_DEGREE || degree < p->degree ||
        (p->kind == SK_PATCH_TENSOR && degree_v < p->degree_v))
        return sk__fail(err, SK_ERR_ARG, "cannot elevate to a lower or too high degree");
    sk_patch cur = *p;
    if (p->kind == SK_PATCH_TRIANGLE) {
        while (cur.degree < degree) { /* b'_{ijk} = (i b_{i-1jk} + j b_{ij-1k} + k b_{ijk-1}) / (n+1) */
            unsigned n = cur.degree;
            sk_patch nx = cur;
            nx.degree = n + 1;
            for (unsigned k = 0; k <= n + 1; ++k)
                for (unsigned j = 0; j + k <= n + 1; ++j) {
                    unsigned i = n + 1 - j - k;
                    double *o = nx.cp + 3 * sk_tri_index(n + 1, j, k);
                    o[0] = o[1] = o[2] = 0.0;
                    for (int x = 0; x < 3; ++x) {
                        if (i)
                            o[x] += i * cur.cp[3 * sk_tri_index(n, j, k) + (unsigned)x];
                        if (j)
                            o[x] += j * cur.cp[3 * sk_tri_index(n, j - 1, k) + (unsigned)x];
                        if (k)
                            o[x] += k * cur.cp[3 * sk_tri_index(n, j, k - 1) + (unsigned)x];
                        o[x] /= (double)(n + 1);
                    }
                }
            cur = nx;
        }
        *out = cur;
        return SK_OK;
    }
    for (int dir = 0; dir < 2; ++dir) {
        while ((dir == 0 ? cur.degree : cur.degree_v) < (dir == 0 ? degree : degree_v)) {
            unsigned du = cur.degree, dv = cur.degree_v;
            sk_patch nx = cur;
            if (dir == 0)
                nx.degree = du + 1;
            else
                nx.degree_v = dv + 1;
            unsigned n = dir == 0 ? du : dv, lines = dir == 0 ? dv + 1 : du + 1;
            for (unsigned l = 0; l < lines; ++l)
                for (unsigned i = 0; i <= n + 1; ++i) {
                    double a = (double)i / (n + 1);
                    unsigned oi = dir == 0 ? l * (du + 2) + i : i * (du + 1) + l;
                    for (int x = 0; x < 3; ++x) {
                        double v = 0.0;
                        if (i > 0) {
                            unsigned pi = dir == 0 ? l * (du + 1) + i - 1 : (i - 1) * (du + 1) + l;
                            v += a * cur.cp[3 * pi + (unsigned)x];
                        }
                        if (i <= n) {
                            unsigned pi = dir == 0 ? l * (du + 1) + i : i * (du + 1) + l;
                            v += (1.0 - a) * cur.cp[3 * pi + (unsigned)x];
                        }
                        nx.cp[3 * oi + (unsigned)x] = v;
                    }
                }
            cur = nx;
        }
    }
    *out = cur;
    return SK_OK;
}
