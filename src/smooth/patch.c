/* Quartic / cubic triangular and bicubic Bezier patches: evaluation, first derivatives and
 * normals by de Casteljau; the normal-cone regularity test of Ginkel, Peters, Umlauf. */
#include "smooth/smooth_internal.h"
#include "core/vec.h"

#include <string.h>

static void tri_eval(const double *b, int n, double u, double v, double pos[3], double du[3],
                     double dv[3])
{
    double work[15 * 3];
    double a = 1.0 - u - v;
    memcpy(work, b, sizeof(double) * 3 * sk__patch_points(SK_PATCH_TRIANGLE, n));
    /* de Casteljau: level l has degree l; point (j, k) of level l-1 from (j,k), (j+1,k), (j,k+1) */
    for (int l = n; l > 1; --l) {
        for (int k = 0; k <= l - 1; ++k)
            for (int j = 0; j <= l - 1 - k; ++j) {
                const double *p0 = work + 3 * sk__tri_index(l, j, k);
                const double *p1 = work + 3 * sk__tri_index(l, j + 1, k);
                const double *p2 = work + 3 * sk__tri_index(l, j, k + 1);
                double *o = work + 3 * sk__tri_index(l - 1, j, k);
                for (int x = 0; x < 3; ++x)
                    o[x] = a * p0[x] + u * p1[x] + v * p2[x];
            }
    }
    const double *p0 = work, *p1 = work + 3, *p2 = work + 6; /* (0,0), (1,0), (0,1) of level 1 */
    for (int x = 0; x < 3; ++x) {
        if (pos)
            pos[x] = a * p0[x] + u * p1[x] + v * p2[x];
        if (du)
            du[x] = n * (p1[x] - p0[x]);
        if (dv)
            dv[x] = n * (p2[x] - p0[x]);
    }
}

/* cubic de Casteljau of 4 points: value and derivative */
static void cubic(double q[4][3], double t, double val[3], double der[3])
{
    double a[3][3], b[2][3];
    for (int i = 0; i < 3; ++i)
        for (int x = 0; x < 3; ++x)
            a[i][x] = (1 - t) * q[i][x] + t * q[i + 1][x];
    for (int i = 0; i < 2; ++i)
        for (int x = 0; x < 3; ++x)
            b[i][x] = (1 - t) * a[i][x] + t * a[i + 1][x];
    for (int x = 0; x < 3; ++x) {
        if (val)
            val[x] = (1 - t) * b[0][x] + t * b[1][x];
        if (der)
            der[x] = 3.0 * (b[1][x] - b[0][x]);
    }
}

static void quad_eval(const double *b, double u, double v, double pos[3], double du[3],
                      double dv[3])
{
    double rowp[4][3], rowd[4][3], q[4][3];
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i)
            memcpy(q[i], b + 3 * (i + 4 * j), sizeof q[i]);
        cubic(q, u, rowp[j], rowd[j]);
    }
    double t[3];
    cubic(rowp, v, pos ? pos : t, dv ? dv : t);
    if (du)
        cubic(rowd, v, du, NULL);
}

void sk_patch_eval(const sk_smooth *s, size_t p, double u, double v, double pos[3], double du[3],
                   double dv[3], double normal[3])
{
    const sk_patch *pa = s->patches + p;
    const double *b = s->points + 3 * (size_t)pa->first;
    double a[3], c[3];
    if (pa->kind == SK_PATCH_QUAD)
        quad_eval(b, u, v, pos, du ? du : a, dv ? dv : c);
    else
        tri_eval(b, pa->degree, u, v, pos, du ? du : a, dv ? dv : c);
    if (normal) {
        sk__cross3(normal, du ? du : a, dv ? dv : c);
        sk__normalize3(normal);
    }
}

/* u- and v-differences of the control net (directions corners[0]->[1] and [0]->[2] or [0]->[3]) */
static int net_differences(const sk_patch *pa, const double *b, double du[][3], double dv[][3],
                           int *ndu, int *ndv)
{
    int nu = 0, nv = 0;
    if (pa->kind == SK_PATCH_QUAD) {
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 3; ++i)
                sk__sub3(du[nu++], b + 3 * (i + 1 + 4 * j), b + 3 * (i + 4 * j));
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i)
                sk__sub3(dv[nv++], b + 3 * (i + 4 * (j + 1)), b + 3 * (i + 4 * j));
    } else {
        int n = pa->degree;
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n - k; ++j) {
                const double *p0 = b + 3 * sk__tri_index(n, j, k);
                sk__sub3(du[nu++], b + 3 * sk__tri_index(n, j + 1, k), p0);
                sk__sub3(dv[nv++], b + 3 * sk__tri_index(n, j, k + 1), p0);
            }
    }
    *ndu = nu;
    *ndv = nv;
    return 0;
}

bool sk__patch_cone_regular(const sk_smooth *s, size_t p)
{
    const sk_patch *pa = s->patches + p;
    const double *b = s->points + 3 * (size_t)pa->first;
    double du[12][3], dv[12][3], axis[3] = {0, 0, 0};
    int nu, nv;
    net_differences(pa, b, du, dv, &nu, &nv);
    /* axis: the sum of all cross products (Lemma 3: the normal lies in their cone) */
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double x[3];
            sk__cross3(x, du[i], dv[j]);
            sk__add3(axis, axis, x);
        }
    if (sk__normalize3(axis) == 0.0)
        return false;
    /* the cone excludes 0 if every generator that is not zero lies strictly on the axis side
     * (zero generators, e.g. collapsed differences, add nothing to the cone) */
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double x[3];
            sk__cross3(x, du[i], dv[j]);
            double len = sk__norm3(x);
            if (len == 0.0)
                continue;
            if (sk__dot3(x, axis) <= 1e-12 * len)
                return false;
        }
    return true;
}
