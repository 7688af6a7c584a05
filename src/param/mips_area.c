/* MIPS with an area term (Degener, Meseth, Klein, "An adaptable surface parameterization method",
 * 2003; the area-aware MIPS of Hormann & Greiner's later work):
 *
 *     E_t = M_t * F(d_t),  M_t = sigma1/sigma2 + sigma2/sigma1 (mips_energy.c (*)),
 *     F(d) = (d + 1/d)^theta,  d_t = sigma1 sigma2 * k = (A_uv / A) * k,
 *
 * with k the mesh's 3D area over its uv area at the start, so that d = 1 is the mean area scale
 * and the energy has no preferred overall size beyond the start's (a renormalization of uv by 2^e
 * multiplies k by 4^-e: the energy is then unchanged). F is smallest (2^theta) at d = 1 and
 * grows like d^theta and d^-theta away from it: shrinking or swelling a triangle costs as a
 * stretched one does. F is infinite where A_uv <= 0 as M is, so the local steps stay flip-free.
 *
 * As a function of one vertex x, with a = sum c |dq|^2 (quadratic) and b = 2 A_uv (linear, its
 * gradient gb constant), M = a / b and d = s b (s = k / (2A)):
 *     grad E = F grad M + M F' s gb,
 *     hess E = F hess M + F' s (grad M gb^T + gb grad M^T) + M F'' s^2 gb gb^T.
 * Not convex in general: the local step falls back to gradient descent where H is not positive
 * definite, and its Armijo line search keeps every step a descent. */
#include "core/internal.h"
#include "core/vec.h"
#include "param/mips_internal.h"

#include <math.h>

void sk__mips_area_setup(sk__mips_ctx *c, double theta, const double *uv)
{
    double a3 = 0.0, auv = 0.0;
    for (size_t t = 0; t < c->nt; ++t) {
        const uint32_t *v = c->tri + 3 * t;
        const double *p0 = uv + 2 * (size_t)v[0], *p1 = uv + 2 * (size_t)v[1],
                     *p2 = uv + 2 * (size_t)v[2];
        double e1[2] = {p1[0] - p0[0], p1[1] - p0[1]}, e2[2] = {p2[0] - p0[0], p2[1] - p0[1]};
        a3 += 1.0 / c->s3[t];
        auv += fabs(sk__cross2(e1, e2));
    }
    c->area_theta = theta;
    c->area_k = auv > 0.0 ? a3 / auv : 1.0;
}

/* F(d) and its first two derivatives in d (d > 0); sqrt for the atlas's theta 0.5 (pow was a
 * tenth of the 832k atlas's CPU time). */
static double area_factor(double d, double theta, double *f1, double *f2)
{
    double id = 1.0 / d, u = d + id, du = 1.0 - id * id, ddu = 2.0 * id * id * id;
    double f = theta == 1.0 ? u : theta == 0.5 ? sqrt(u) : pow(u, theta);
    double fu = theta == 1.0 ? 1.0 : theta * f / u;
    *f1 = fu * du;
    *f2 = (theta - 1.0) * fu / u * du * du + fu * ddu;
    return f;
}

double sk__mips_area_tri_energy(const sk__mips_ctx *c, size_t t, const double *uv)
{
    double twice, m = sk__mips_tri_terms(c, t, uv, &twice), f1, f2;
    if (!isfinite(m))
        return m;
    return m * area_factor(twice * c->s3[t] * c->area_k, c->area_theta, &f1, &f2);
}

double sk__mips_area_ring_energy(const sk__mips_ctx *c, uint32_t v, const double *uv,
                                 const double x[2], double g[2], double H[3])
{
    double e = 0.0, theta = c->area_theta, k = c->area_k;
    if (g) {
        g[0] = g[1] = 0.0;
        H[0] = H[1] = H[2] = 0.0;
    }
    for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
        const sk__mips_corner *r = c->rec + i;
        double m, b, gm[2], gb[2], hm[3];
        if (!sk__mips_corner_terms(r, uv, x, g != NULL, &m, &b, gm, gb, hm))
            return INFINITY;
        double s = r->s3 * k, f1, f2;
        double f = area_factor(s * b, theta, &f1, &f2);
        e += m * f;
        if (g) {
            double p = f1 * s, q = m * f2 * s * s;
            g[0] += f * gm[0] + m * p * gb[0];
            g[1] += f * gm[1] + m * p * gb[1];
            H[0] += f * hm[0] + 2.0 * p * gm[0] * gb[0] + q * gb[0] * gb[0];
            H[1] += f * hm[1] + p * (gm[0] * gb[1] + gb[0] * gm[1]) + q * gb[0] * gb[1];
            H[2] += f * hm[2] + 2.0 * p * gm[1] * gb[1] + q * gb[1] * gb[1];
        }
    }
    return e;
}
