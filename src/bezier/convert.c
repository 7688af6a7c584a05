/* Exact conversions between patch kinds: a triangle as three tensor patches (or one with a
 * collapsed side) by interpolation of the composition with a bilinear map, degree elevation, and
 * a whole set as tensor patches (what the CAD writers emit). */
#include "bezier/bezier_internal.h"
#include "core/internal.h"

#include <lapacke.h>
#include <string.h>

/* Tensor patch of degree n x n equal to tri o X, where X maps (s, t) bilinearly onto the domain
 * quadrilateral with barycentric corners q[0..3] (order (0,0), (1,0), (1,1), (0,1)). The
 * composition has degree n in s and in t, so interpolating it at (n+1)^2 grid points is exact. */
static sk_status compose_bilinear(const double *tri, unsigned n, double q[4][3], double *out,
                                  sk_error *err)
{
    unsigned m = n + 1;
    double M[(SK_PATCH_MAX_DEGREE + 1) * (SK_PATCH_MAX_DEGREE + 1)];
    double R[3 * SK__PATCH_MAX_POINTS]; /* samples; then solved in place */
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
            sk__tri_eval(tri, n, bary[1], bary[2], R + 3 * sk_tensor_index(n, a, b), NULL, NULL);
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
    memcpy(out, R, 3 * m * m * sizeof(double));
    return SK_OK;
}

/* Copies the control net of triangle i of src (it may move when dst == src grows). */
static sk_status triangle_net(const sk_patch_set *src, size_t i, double *net, sk_error *err)
{
    const sk_patch *p = &src->patches[i];
    if (p->kind != SK_PATCH_TRIANGLE || p->degree > SK_PATCH_MAX_DEGREE)
        return sk__fail(err, SK_ERR_ARG, "not a triangular patch of degree <= %d",
                        SK_PATCH_MAX_DEGREE);
    memcpy(net, sk_patch_cp(src, i), 3 * sk_patch_num_points(p) * sizeof(double));
    return SK_OK;
}

sk_status sk_patch_split_triangle(const sk_patch_set *src, size_t i, sk_patch_set *dst,
                                  sk_error *err)
{
    double net[3 * SK__PATCH_MAX_POINTS], sub[3 * SK__PATCH_MAX_POINTS];
    sk_status st = triangle_net(src, i, net, err);
    if (st)
        return st;
    unsigned n = src->patches[i].degree;
    uint32_t ids[3], tag = src->patches[i].tag;
    memcpy(ids, src->patches[i].corner_ids, sizeof ids);
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
        uint32_t corners[4] = {ids[q], SK_INVALID, SK_INVALID, SK_INVALID};
        if ((st = compose_bilinear(net, n, dom, sub, err)) != SK_OK ||
            (st = sk__patch_set_add_tagged(dst, SK_PATCH_TENSOR, n, n, sub, corners, tag, err)))
            return st;
    }
    return SK_OK;
}

sk_status sk_patch_triangle_to_degenerate_tensor(const sk_patch_set *src, size_t i,
                                                 sk_patch_set *dst, sk_error *err)
{
    double net[3 * SK__PATCH_MAX_POINTS], out[3 * SK__PATCH_MAX_POINTS];
    sk_status st = triangle_net(src, i, net, err);
    if (st)
        return st;
    const sk_patch *p = &src->patches[i];
    unsigned n = p->degree;
    uint32_t tag = p->tag;
    uint32_t corners[4] = {p->corner_ids[0], p->corner_ids[1], p->corner_ids[2], p->corner_ids[0]};
    /* B^n_ijk(1 - s, s (1 - t), s t) = B^n_l(s) B^l_k(t) with l = j + k: row l (in s) is the
     * degree-l curve in t over b_{n-l, l-k, k}, k = 0..l, elevated to degree n. Exact where it
     * matters: row 0 is b_n00 repeated (the collapsed side), row n and the columns t = 0, 1 are the
     * triangle's own boundary control points. */
    for (unsigned l = 0; l <= n; ++l) {
        double c[2][3 * (SK_PATCH_MAX_DEGREE + 1)];
        int cur = 0;
        for (unsigned k = 0; k <= l; ++k)
            memcpy(c[cur] + 3 * k, net + 3 * sk_tri_index(n, l - k, k), 3 * sizeof(double));
        for (unsigned d = l; d < n; ++d, cur ^= 1) /* one elevation: degree d -> d + 1 */
            for (unsigned k = 0; k <= d + 1; ++k)
                for (unsigned x = 0; x < 3; ++x) {
                    /* c_k + a (c_{k-1} - c_k), a = k / (d + 1): equal neighbours stay exact */
                    double *o = &c[cur ^ 1][3 * k + x];
                    if (k == 0)
                        *o = c[cur][x];
                    else if (k == d + 1)
                        *o = c[cur][3 * d + x];
                    else
                        *o = c[cur][3 * k + x] + (double)k / (double)(d + 1) *
                                                     (c[cur][3 * (k - 1) + x] - c[cur][3 * k + x]);
                }
        for (unsigned b = 0; b <= n; ++b)
            memcpy(out + 3 * sk_tensor_index(n, l, b), c[cur] + 3 * b, 3 * sizeof(double));
    }
    return sk__patch_set_add_tagged(dst, SK_PATCH_TENSOR, n, n, out, corners, tag, err);
}

/* One degree elevation of a triangle net of degree n:
 * b'_{ijk} = (i b_{i-1jk} + j b_{ij-1k} + k b_{ijk-1}) / (n + 1). */
static void elevate_triangle(const double *cur, unsigned n, double *nx)
{
    for (unsigned k = 0; k <= n + 1; ++k)
        for (unsigned j = 0; j + k <= n + 1; ++j) {
            unsigned i = n + 1 - j - k;
            double *o = nx + 3 * sk_tri_index(n + 1, j, k);
            for (unsigned x = 0; x < 3; ++x) {
                double v = 0.0;
                if (i)
                    v += i * cur[3 * sk_tri_index(n, j, k) + x];
                if (j)
                    v += j * cur[3 * sk_tri_index(n, j - 1, k) + x];
                if (k)
                    v += k * cur[3 * sk_tri_index(n, j, k - 1) + x];
                o[x] = v / (double)(n + 1);
            }
        }
}

/* One degree elevation of a tensor net of degree du x dv in direction dir (0: s, 1: t). */
static void elevate_tensor(const double *cur, unsigned du, unsigned dv, int dir, double *nx)
{
    unsigned n = dir == 0 ? du : dv, lines = dir == 0 ? dv + 1 : du + 1;
    unsigned ndu = dir == 0 ? du + 1 : du;
    for (unsigned l = 0; l < lines; ++l)
        for (unsigned i = 0; i <= n + 1; ++i) {
            double a = (double)i / (n + 1);
            unsigned oi = dir == 0 ? sk_tensor_index(ndu, i, l) : sk_tensor_index(ndu, l, i);
            for (unsigned x = 0; x < 3; ++x) {
                double v = 0.0;
                if (i > 0) {
                    unsigned pi = dir == 0 ? sk_tensor_index(du, i - 1, l)
                                           : sk_tensor_index(du, l, i - 1);
                    v += a * cur[3 * pi + x];
                }
                if (i <= n) {
                    unsigned pi = dir == 0 ? sk_tensor_index(du, i, l) : sk_tensor_index(du, l, i);
                    v += (1.0 - a) * cur[3 * pi + x];
                }
                nx[3 * oi + x] = v;
            }
        }
}

sk_status sk_patch_elevate(const sk_patch_set *src, size_t i, unsigned degree, unsigned degree_v,
                           sk_patch_set *dst, sk_error *err)
{
    const sk_patch *p = &src->patches[i];
    bool tri = p->kind == SK_PATCH_TRIANGLE;
    if (degree > SK_PATCH_MAX_DEGREE || degree_v > SK_PATCH_MAX_DEGREE || degree < p->degree ||
        (!tri && degree_v < p->degree_v))
        return sk__fail(err, SK_ERR_ARG, "cannot elevate to a lower or too high degree");
    double buf[2][3 * SK__PATCH_MAX_POINTS];
    int cur = 0;
    memcpy(buf[cur], sk_patch_cp(src, i), 3 * sk_patch_num_points(p) * sizeof(double));
    unsigned du = p->degree, dv = tri ? 0 : p->degree_v;
    uint32_t corners[4], tag = p->tag;
    memcpy(corners, p->corner_ids, sizeof corners);
    sk_patch_kind kind = (sk_patch_kind)p->kind;
    for (; tri && du < degree; ++du, cur ^= 1)
        elevate_triangle(buf[cur], du, buf[cur ^ 1]);
    for (; !tri && du < degree; ++du, cur ^= 1)
        elevate_tensor(buf[cur], du, dv, 0, buf[cur ^ 1]);
    for (; !tri && dv < degree_v; ++dv, cur ^= 1)
        elevate_tensor(buf[cur], du, dv, 1, buf[cur ^ 1]);
    return sk__patch_set_add_tagged(dst, kind, du, dv, buf[cur], corners, tag, err);
}

sk_status sk_patch_set_to_tensor(const sk_patch_set *src, bool degenerate, sk_patch_set *dst,
                                 sk_error *err)
{
    if (src == dst)
        return sk__fail(err, SK_ERR_ARG, "sk_patch_set_to_tensor: dst must not be src");
    size_t n = 0, points = 0;
    for (size_t i = 0; i < src->count; ++i) {
        const sk_patch *p = &src->patches[i];
        unsigned d = p->degree;
        size_t copies = p->kind == SK_PATCH_TRIANGLE && !degenerate ? 3 : 1;
        n += copies;
        points += p->kind == SK_PATCH_TENSOR ? sk_patch_num_points(p) : copies * (d + 1) * (d + 1);
    }
    sk_status st = sk_patch_set_reserve(dst, n, points, err);
    for (size_t i = 0; i < src->count && st == SK_OK; ++i) {
        const sk_patch *p = &src->patches[i];
        if (p->kind == SK_PATCH_TENSOR)
            st = sk__patch_set_add_tagged(dst, SK_PATCH_TENSOR, p->degree, p->degree_v,
                                          sk_patch_cp(src, i), p->corner_ids, p->tag, err);
        else if (degenerate)
            st = sk_patch_triangle_to_degenerate_tensor(src, i, dst, err);
        else
            st = sk_patch_split_triangle(src, i, dst, err);
    }
    return st;
}
