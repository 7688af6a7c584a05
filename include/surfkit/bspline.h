/* Tensor-product B-spline surfaces: clamped knot vectors, control points on a grid.
 *
 *   S(u, v) = sum_i sum_j P[i + nu j] N_i,p(u) M_j,q(v),  (u, v) in [0, 1]^2
 *
 * N_i,p are the B-splines of degree p over knots_u (nu + p + 1 values, the first p + 1 equal to 0
 * and the last p + 1 equal to 1), M_j,q those of degree q over knots_v. The same surface as the
 * STEP entity B_SPLINE_SURFACE_WITH_KNOTS and IGES entity 128 (non-rational). */
#ifndef SURFKIT_BSPLINE_H
#define SURFKIT_BSPLINE_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_bspline_surface {
    int degree_u, degree_v;
    size_t nu, nv;     /* control points along u and v */
    double *knots_u;   /* nu + degree_u + 1 */
    double *knots_v;   /* nv + degree_v + 1 */
    double *points;    /* 3 * nu * nv, point (i, j) at 3 * (i + nu * j) */
} sk_bspline_surface;

/* A surface of the given degrees (1..7) with uniform clamped knots and nu x nv control points
 * (nu > degree_u, nv > degree_v), points zeroed. */
SK_API sk_status sk_bspline_create(int degree_u, int degree_v, size_t nu, size_t nv,
                                   sk_bspline_surface **out, sk_error *err);
SK_API void sk_bspline_destroy(sk_bspline_surface **s);

/* Position (and first derivatives; either may be NULL) at (u, v), clamped to [0, 1]^2. */
SK_API void sk_bspline_eval(const sk_bspline_surface *s, double u, double v, double pos[3],
                            double du[3], double dv[3]);

/* An n x n grid of the surface (n + 1 squared vertices with exact unit normals, 2 n^2
 * triangles). */
SK_API sk_status sk_bspline_tessellate(const sk_bspline_surface *s, unsigned n, sk_soup **out,
                                       sk_error *err);

/* The grid n for sk_bspline_tessellate whose chord error stays below tol / 20 by a bound from
 * the control net (second differences), at least 8 per knot span, 64 to 512; *chord (may be
 * NULL) receives the bound for that n. */
SK_API unsigned sk_bspline_tessellation_grid(const sk_bspline_surface *s, double tol,
                                             double *chord);

/* Index of the knot span holding t (knots[span] <= t < knots[span + 1], the last non-empty span
 * for t = 1) of a clamped knot vector with n control points and degree p. */
SK_API size_t sk_bspline_span(const double *knots, size_t n, int p, double t);

/* The p + 1 non-zero B-splines at t of span `span` and their derivatives up to order `nd`
 * (nd <= 2): ders[d * (p + 1) + k] is the d-th derivative of N_{span - p + k, p}(t). */
SK_API void sk_bspline_basis(const double *knots, size_t span, int p, double t, int nd, double *ders);

#ifdef __cplusplus
}
#endif
#endif
