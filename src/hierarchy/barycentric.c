/* Barycentric tracking of a removed vertex (Hormann, Greiner, Campagna, sections 1 and 3).
 *
 * The one-ring W0..Wn of V is flattened by the exponential map of section 1:
 *     |w_i - v| = |W_i - V|,   gamma_i = 2 pi Gamma_i / sum_j Gamma_j,
 * with v at the origin, w0 on the positive x axis and Gamma_i the angle between W_i - V and
 * W_i+1 - V. The collapse V -> W0 leaves the triangles (w0, w_i, w_i+1), 1 <= i <= n-1; the one
 * that contains v is the parent triangle and v = rho w0 + sigma w_i + tau w_i+1 with
 * rho, sigma, tau >= 0 and rho + sigma + tau = 1 (section 3).
 *
 * Finding the parent: v lies on the segment from w0 through the origin to the polygon edge
 * (w_i, w_i+1) that the ray at angle pi crosses, so that fan triangle holds v whenever its angular
 * span is below pi. When rounding (or a ring that is not star-shaped from w0) leaves v slightly
 * outside, the coordinates are clamped to [0, 1] and renormalised; when it is clearly outside
 * (more than 1e-9), every fan triangle is tried and v is projected onto the nearest one (closest
 * point, its barycentric coordinates).
 *
 * Boundary vertex (documented choice): V's faces span a half disk, so the angles are scaled to sum
 * to pi instead of 2 pi. Then w0, v and w_n are collinear and v lies on the edge (w0, w_n), which is
 * the new boundary edge after the collapse: the parent is (w0, w_n-1, w_n) with sigma = 0,
 * rho = |w_n| / (|w0| + |w_n|), tau = |w0| / (|w0| + |w_n|), exactly, without trigonometry. */
#include "hierarchy/hierarchy_internal.h"
#include "core/vec.h"

#include <math.h>

/* Closest point of triangle (a, b, c) to the origin, as barycentric coordinates l[3] (the usual
 * Voronoi-region case analysis); returns its squared distance. */
static double closest_to_origin(const double a[2], const double b[2], const double c[2], double l[3])
{
    double ab[2] = {b[0] - a[0], b[1] - a[1]}, ac[2] = {c[0] - a[0], c[1] - a[1]};
    double ap[2] = {-a[0], -a[1]}, bp[2] = {-b[0], -b[1]}, cp[2] = {-c[0], -c[1]};
    double d1 = sk__dot2(ab, ap), d2 = sk__dot2(ac, ap);
    double d3 = sk__dot2(ab, bp), d4 = sk__dot2(ac, bp);
    double d5 = sk__dot2(ab, cp), d6 = sk__dot2(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (d1 <= 0.0 && d2 <= 0.0) {
        l[0] = 1.0, l[1] = 0.0, l[2] = 0.0;
    } else if (d3 >= 0.0 && d4 <= d3) {
        l[0] = 0.0, l[1] = 1.0, l[2] = 0.0;
    } else if (d6 >= 0.0 && d5 <= d6) {
        l[0] = 0.0, l[1] = 0.0, l[2] = 1.0;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double t = d1 / (d1 - d3);
        l[0] = 1.0 - t, l[1] = t, l[2] = 0.0;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double t = d2 / (d2 - d6);
        l[0] = 1.0 - t, l[1] = 0.0, l[2] = t;
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        l[0] = 0.0, l[1] = 1.0 - t, l[2] = t;
    } else {
        double s = va + vb + vc;
        if (!(s > 0.0)) { /* degenerate triangle */
            l[0] = 1.0, l[1] = 0.0, l[2] = 0.0;
        } else {
            l[1] = vb / s;
            l[2] = vc / s;
            l[0] = 1.0 - l[1] - l[2];
        }
    }
    double x = l[0] * a[0] + l[1] * b[0] + l[2] * c[0], y = l[0] * a[1] + l[1] * b[1] + l[2] * c[1];
    return x * x + y * y;
}

/* Barycentric coordinates of the origin in (a, b, c); false when the triangle is degenerate. */
static bool origin_coords(const double a[2], const double b[2], const double c[2], double l[3])
{
    double e1[2] = {b[0] - a[0], b[1] - a[1]}, e2[2] = {c[0] - a[0], c[1] - a[1]};
    double d = sk__cross2(e1, e2);
    if (!(fabs(d) > 0.0))
        return false;
    l[0] = sk__cross2(b, c) / d;
    l[1] = sk__cross2(c, a) / d;
    l[2] = sk__cross2(a, b) / d;
    return isfinite(l[0]) && isfinite(l[1]) && isfinite(l[2]);
}

/* Clamp to >= 0 and renormalise to sum 1. */
static void clamp_coords(double l[3])
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        l[k] = l[k] > 0.0 ? l[k] : 0.0;
        s += l[k];
    }
    if (s > 0.0) {
        l[0] /= s;
        l[1] /= s;
        l[2] = 1.0 - l[0] - l[1];
        if (l[2] < 0.0)
            l[2] = 0.0;
    } else {
        l[0] = 1.0, l[1] = 0.0, l[2] = 0.0;
    }
}

#define SK_BARY_OUTSIDE 1e-9 /* a coordinate below -this: v is really outside the fan triangle */

void sk__barycentric(const sk_mesh *m, uint32_t v, const uint32_t *ring, size_t count, bool closed,
                     double *scratch, uint32_t parent[3], double bary[3])
{
    const double *P = m->positions, *pv = P + 3 * (size_t)v;
    size_t n = count - 1; /* ring W0..Wn */
    double *r = scratch, *theta = scratch + count, *w = scratch + 2 * count + 1;
    parent[0] = ring[0];
    if (!closed) {
        parent[1] = ring[n - 1];
        parent[2] = ring[n];
        double r0 = sk__dist3(P + 3 * (size_t)ring[0], pv), rn = sk__dist3(P + 3 * (size_t)ring[n], pv);
        double s = r0 + rn;
        bary[0] = s > 0.0 ? rn / s : 1.0;
        bary[1] = 0.0;
        bary[2] = s > 0.0 ? 1.0 - bary[0] : 0.0;
        return;
    }
    /* lengths and angles Gamma_i (section 1) */
    double e0[3], ek[3], en[3];
    sk__sub3(e0, P + 3 * (size_t)ring[0], pv);
    r[0] = sk__norm3(e0);
    double total = 0.0;
    theta[0] = 0.0;
    sk__scale3(ek, e0, 1.0);
    for (size_t k = 0; k < count; ++k) {
        if (k + 1 < count) {
            sk__sub3(en, P + 3 * (size_t)ring[k + 1], pv);
            r[k + 1] = sk__norm3(en);
        } else {
            sk__scale3(en, e0, 1.0);
        }
        total += sk__angle3(ek, en);
        theta[k + 1] = total;
        sk__scale3(ek, en, 1.0);
    }
    double scale = total > 0.0 ? 2.0 * M_PI / total : 0.0;
    size_t i = 1;
    for (size_t k = 2; k <= n - 1; ++k)
        if (theta[k] * scale <= M_PI)
            i = k;
    double l[3];
    double a[2] = {r[0], 0.0};
    double b[2] = {r[i] * cos(theta[i] * scale), r[i] * sin(theta[i] * scale)};
    double c[2] = {r[i + 1] * cos(theta[i + 1] * scale), r[i + 1] * sin(theta[i + 1] * scale)};
    if (scale > 0.0 && origin_coords(a, b, c, l) && l[0] >= -SK_BARY_OUTSIDE &&
        l[1] >= -SK_BARY_OUTSIDE && l[2] >= -SK_BARY_OUTSIDE) {
        clamp_coords(l);
    } else {
        /* projection onto the nearest fan triangle */
        for (size_t k = 0; k <= n; ++k) {
            double t = theta[k] * scale;
            w[2 * k] = r[k] * cos(t);
            w[2 * k + 1] = r[k] * sin(t);
        }
        double best = INFINITY, lk[3];
        i = 1;
        l[0] = 1.0, l[1] = 0.0, l[2] = 0.0;
        for (size_t k = 1; k + 1 <= n; ++k) {
            double d2 = closest_to_origin(w, w + 2 * k, w + 2 * k + 2, lk);
            if (d2 < best) {
                best = d2;
                i = k;
                l[0] = lk[0], l[1] = lk[1], l[2] = lk[2];
            }
        }
        clamp_coords(l);
    }
    parent[1] = ring[i];
    parent[2] = ring[i + 1];
    bary[0] = l[0];
    bary[1] = l[1];
    bary[2] = l[2];
}
