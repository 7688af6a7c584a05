/* Bezier patches: triangular (total degree n) and tensor-product (degree du x dv), evaluated by
 * de Casteljau; the exact split of a triangular patch into three tensor-product patches that CAD
 * systems read without singular points. The export writers take arrays of these. */
#ifndef SURFKIT_BEZIER_H
#define SURFKIT_BEZIER_H

#include "surfkit/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { SK_PATCH_TRIANGLE = 0, SK_PATCH_TENSOR = 1 } sk_patch_kind;

#define SK_PATCH_MAX_DEGREE 8
#define SK_PATCH_MAX_POINTS ((SK_PATCH_MAX_DEGREE + 1) * (SK_PATCH_MAX_DEGREE + 1))

/* Control points, 3 doubles each:
 *  - triangle of degree n: b_{ijk}, i + j + k = n, at index sk_tri_index(n, j, k); corner 0 is
 *    b_{n00} (barycentric u = 1), corner 1 b_{0n0} (v = 1), corner 2 b_{00n} (w = 1);
 *  - tensor of degree du x dv: b_{ij} (i along s, j along t) at index j * (du + 1) + i; corners in
 *    order (0,0), (1,0), (1,1), (0,1).
 * Corners are ordered counter-clockwise seen from the side the surface normal points to
 * (triangle: d/dv x d/dw at corner 0 direction; tensor: d/ds x d/dt). corner_ids are optional
 * labels of the corners (mesh vertex ids) the writers use to share vertices and edges between
 * neighbouring patches; SK_INVALID when unknown. */
typedef struct sk_patch {
    sk_patch_kind kind;
    unsigned degree;   /* triangle: n; tensor: du */
    unsigned degree_v; /* tensor: dv; unused for triangles */
    double cp[3 * SK_PATCH_MAX_POINTS];
    uint32_t corner_ids[4];
} sk_patch;

/* Index of b_{ijk} (i = n - j - k) in a triangle's control points: rows by k, then j. */
static inline unsigned sk_tri_index(unsigned n, unsigned j, unsigned k)
{
    return k * (2 * n + 3 - k) / 2 + j;
}

static inline unsigned sk_patch_num_points(const sk_patch *p)
{
    return p->kind == SK_PATCH_TRIANGLE ? (p->degree + 1) * (p->degree + 2) / 2
                                        : (p->degree + 1) * (p->degree_v + 1);
}

static inline unsigned sk_patch_num_corners(const sk_patch *p)
{
    return p->kind == SK_PATCH_TRIANGLE ? 3 : 4;
}

/* Point, first derivatives and unit normal at a parameter:
 *  - triangle: (a, b) are the barycentric coordinates v and w (u = 1 - v - w); du, dv receive the
 *    derivatives along the directions (corner 0 -> corner 1) and (corner 0 -> corner 2);
 *  - tensor: (a, b) = (s, t) in [0, 1]^2.
 * Any output may be NULL. Returns the length of the cross product of the derivatives (0 at a
 * singular point, where the normal is left zero). */
SK_API double sk_patch_eval(const sk_patch *p, double a, double b, double pt[3], double du[3],
                            double dv[3], double normal[3]);

/* The same on a raw control net laid out as in sk_patch (cp: 3 doubles per point). */
SK_API double sk_bezier_eval(sk_patch_kind kind, unsigned degree, unsigned degree_v, const double *cp,
                             double a, double b, double pt[3], double du[3], double dv[3],
                             double normal[3]);

/* Point of the boundary curve from corner c to corner c + 1 at parameter t in [0, 1]. */
SK_API void sk_patch_edge_point(const sk_patch *p, unsigned c, double t, double pt[3]);

/* Control points (degree + 1 of them, 3 doubles each) of the boundary curve from corner c to
 * corner c + 1; returns the curve's degree. */
SK_API unsigned sk_patch_edge_curve(const sk_patch *p, unsigned c, double *cp);

/* Splits a triangular patch of degree n exactly into three tensor patches of degree n x n: the
 * sub-patch q covers the quadrilateral (corner q, midpoint of edge q..q+1, centroid, midpoint of
 * edge q-1..q) of the triangle's domain, mapped bilinearly; each sub-patch's (s, t) = (0, 0) is at
 * corner q, s runs toward the midpoint of edge (q, q+1), t toward the midpoint of edge (q-1, q),
 * so sub-patch corners are [corner q, mid(q, q+1), centroid, mid(q-1, q)], counter-clockwise.
 * No sub-patch has a singular point where the triangle has none. corner_ids of the result are
 * copied for corner q only (the others become SK_INVALID). */
SK_API sk_status sk_patch_split_triangle(const sk_patch *tri, sk_patch out[3], sk_error *err);

/* One tensor patch of degree n x n equal to the triangle of degree n under the map
 * (s, t) -> barycentric (1 - s, s (1 - t), s t); the side s = 0 collapses to corner 0 (a singular point there). For CAD systems that want one surface per
 * triangle; sk_patch_split_triangle is the regular alternative. */
SK_API sk_status sk_patch_triangle_to_degenerate_tensor(const sk_patch *tri, sk_patch *out, sk_error *err);

/* Degree elevation of a tensor patch or a triangle patch to the given degree(s). */
SK_API sk_status sk_patch_elevate(const sk_patch *p, unsigned degree, unsigned degree_v, sk_patch *out,
                                  sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
