/* Robust orientation test, written for surfkit in the manner of Shewchuk's adaptive predicates
 * (but with two stages only):
 *
 *  1. Filter: det = (ax - cx)(by - cy) - (ay - cy)(bx - cx) in floating point. Each of the two
 *     subtractions, the two products and the final difference is rounded once, so
 *     |det - exact| <= (3 eps + 16 eps^2) * (|(ax-cx)(by-cy)| + |(ay-cy)(bx-cx)|)
 *     (Shewchuk's ccwerrboundA, eps = 2^-53). If |det| exceeds this bound its sign is right.
 *  2. Exact: expand the determinant into the six products of input coordinates
 *         ax by - ax cy - cx by - ay bx + ay cx + cy bx
 *     (the cx cy terms cancel), make each product exact as a sum of two doubles with fma
 *     (p = a*b, e = fma(a, b, -p): a*b = p + e exactly), and add the twelve doubles into a
 *     non-overlapping expansion with error-free two-sums. The sign of the expansion is the sign
 *     of its largest component. Exact for all finite inputs barring overflow / underflow of the
 *     products. */
#include "surfkit/param.h"

#include <float.h>
#include <math.h>

static void two_sum(double a, double b, double *s, double *e)
{
    double x = a + b;
    double bv = x - a;
    double av = x - bv;
    *s = x;
    *e = (a - av) + (b - bv);
}

/* Adds b to the expansion e[0..n) (increasing magnitude, no zeros); returns the new length. */
static int grow_expansion(double *e, int n, double b)
{
    double q = b;
    int m = 0;
    for (int i = 0; i < n; ++i) {
        double s, h;
        two_sum(q, e[i], &s, &h);
        if (h != 0.0)
            e[m++] = h;
        q = s;
    }
    if (q != 0.0 || m == 0)
        e[m++] = q;
    return m;
}

static int orient2d_exact(const double a[2], const double b[2], const double c[2])
{
    const double f[6][2] = {{a[0], b[1]}, {a[0], -c[1]}, {-c[0], b[1]},
                            {-a[1], b[0]}, {a[1], c[0]}, {c[1], b[0]}};
    double e[13];
    int n = 0;
    for (int k = 0; k < 6; ++k) {
        double p = f[k][0] * f[k][1];
        double r = fma(f[k][0], f[k][1], -p);
        n = grow_expansion(e, n, r);
        n = grow_expansion(e, n, p);
    }
    for (int i = n - 1; i >= 0; --i)
        if (e[i] != 0.0)
            return e[i] > 0 ? 1 : -1;
    return 0;
}

int sk_orient2d(const double a[2], const double b[2], const double c[2])
{
    double l = (a[0] - c[0]) * (b[1] - c[1]);
    double r = (a[1] - c[1]) * (b[0] - c[0]);
    double det = l - r;
    const double eps = DBL_EPSILON / 2; /* 2^-53 */
    double bound = (3.0 * eps + 16.0 * eps * eps) * (fabs(l) + fabs(r));
    if (det > bound)
        return 1;
    if (-det > bound)
        return -1;
    if (!isfinite(det))
        return det > 0 ? 1 : (det < 0 ? -1 : 0);
    return orient2d_exact(a, b, c);
}
