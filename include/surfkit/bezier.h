/* The patch layer: one vocabulary of polynomial patches shared by every surface kind (VC1, PN,
 * later B-spline fits) and every consumer (continuity report, tessellator, pictures, IGES, STEP,
 * OBJ free-form).
 *
 * A patch set is a pool: small patch headers (kind, degree(s), corner labels, a tag) over ONE
 * shared array of control points. A quartic triangle costs its header (32 bytes) and 15 points;
 * nothing is sized for the largest degree.
 *
 * Patch kinds: triangular Bezier patches of total degree n, tensor-product Bezier patches of
 * degree du x dv (evaluated by de Casteljau / Bernstein sums); the exact split of a triangle into
 * three tensor patches that CAD systems read without singular points. */
#ifndef SURFKIT_BEZIER_H
#define SURFKIT_BEZIER_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { SK_PATCH_TRIANGLE = 0, SK_PATCH_TENSOR = 1 } sk_patch_kind;

#define SK_PATCH_MAX_DEGREE 8

/* One patch of a set. Control points, 3 doubles each, start at points[3 * first] of the set:
 *  - triangle of degree n: b_{ijk}, i + j + k = n, at index sk_tri_index(n, j, k); corner 0 is
 *    b_{n00} (barycentric u = 1), corner 1 b_{0n0} (v = 1), corner 2 b_{00n} (w = 1);
 *  - tensor of degree du x dv: b_{ij} (i along s, j along t) at index sk_tensor_index(du, i, j);
 *    corners in order (0,0), (1,0), (1,1), (0,1).
 * Corners are ordered counter-clockwise seen from the side the surface normal points to
 * (triangle: d/dv x d/dw; tensor: d/ds x d/dt). corner_ids are optional labels of the corners
 * (mesh vertex ids) that the writers and the tessellator use to share vertices and edges between
 * neighbouring patches; SK_INVALID when unknown (corner_ids[3] of a triangle is SK_INVALID).
 * tag is an optional label of the patch (VC1 and PN: the face of their configuration mesh);
 * SK_INVALID when unset. */
typedef struct sk_patch {
    uint8_t kind;     /* sk_patch_kind */
    uint8_t degree;   /* triangle: n; tensor: du */
    uint8_t degree_v; /* tensor: dv; 0 for triangles */
    uint8_t reserved;
    uint32_t tag;
    size_t first;     /* index of the first control point in the set's points */
    uint32_t corner_ids[4];
} sk_patch;

/* The pool. A zeroed struct is an empty set; free it with sk_patch_set_free. The arrays may be
 * read directly; grow them only through the functions below. */
typedef struct sk_patch_set {
    size_t count;          /* patches */
    sk_patch *patches;
    size_t num_points;     /* control points */
    double *points;        /* 3 doubles per control point */
    size_t patch_capacity, point_capacity;
} sk_patch_set;

/* Index of b_{ijk} (i = n - j - k) in a triangle's control points: rows by k, then j. The one
 * control-point index formula of surfkit's triangles. */
static inline unsigned sk_tri_index(unsigned n, unsigned j, unsigned k)
{
    return k * (2 * n + 3 - k) / 2 + j;
}

/* Index of b_{ij} of a tensor patch of degree du x dv: i along s varies fastest. */
static inline unsigned sk_tensor_index(unsigned du, unsigned i, unsigned j)
{
    return j * (du + 1) + i;
}

static inline unsigned sk_bezier_num_points(sk_patch_kind kind, unsigned degree, unsigned degree_v)
{
    return kind == SK_PATCH_TRIANGLE ? (degree + 1) * (degree + 2) / 2
                                     : (degree + 1) * (degree_v + 1);
}

static inline unsigned sk_patch_num_points(const sk_patch *p)
{
    return sk_bezier_num_points((sk_patch_kind)p->kind, p->degree, p->degree_v);
}

static inline unsigned sk_patch_num_corners(const sk_patch *p)
{
    return p->kind == SK_PATCH_TRIANGLE ? 3 : 4;
}

/* Control points of patch i of the set. */
static inline double *sk_patch_cp(const sk_patch_set *set, size_t i)
{
    return set->points + 3 * set->patches[i].first;
}

/* Makes room for `patches` more patches and `points` more control points (no reallocation while
 * adding that many). */
SK_API sk_status sk_patch_set_reserve(sk_patch_set *set, size_t patches, size_t points, sk_error *err);

/* Appends a patch of the given kind and degree(s) (at most SK_PATCH_MAX_DEGREE; degree_v is
 * ignored for triangles). cp (sk_patch_num_points * 3 doubles) may be NULL: the points are then
 * zero. corner_ids (3 for a triangle, 4 for a tensor patch) may be NULL: SK_INVALID. The tag is
 * SK_INVALID. *index (may be NULL) receives the patch's index. cp and corner_ids may point into
 * the set. */
SK_API sk_status sk_patch_set_add(sk_patch_set *set, sk_patch_kind kind, unsigned degree,
                                  unsigned degree_v, const double *cp, const uint32_t *corner_ids,
                                  size_t *index, sk_error *err);

/* Empties the set, keeping its memory. */
SK_API void sk_patch_set_clear(sk_patch_set *set);

/* Frees the arrays and zeroes the set (NULL-safe). */
SK_API void sk_patch_set_free(sk_patch_set *set);

/* Point, first derivatives and unit normal of patch i at a parameter:
 *  - triangle: (a, b) are the barycentric coordinates v and w (u = 1 - v - w); du, dv receive the
 *    derivatives along the directions (corner 0 -> corner 1) and (corner 0 -> corner 2);
 *  - tensor: (a, b) = (s, t) in [0, 1]^2.
 * Any output may be NULL. Returns the length of the cross product of the derivatives (0 at a
 * singular point, where the normal is left zero). */
SK_API double sk_patch_eval(const sk_patch_set *set, size_t i, double a, double b, double pt[3],
                            double du[3], double dv[3], double normal[3]);

/* The same on a raw control net laid out as above (cp: 3 doubles per point). */
SK_API double sk_bezier_eval(sk_patch_kind kind, unsigned degree, unsigned degree_v, const double *cp,
                             double a, double b, double pt[3], double du[3], double dv[3],
                             double normal[3]);

/* Point of the boundary curve of patch i from corner c to corner c + 1 at t in [0, 1]. */
SK_API void sk_patch_edge_point(const sk_patch_set *set, size_t i, unsigned c, double t, double pt[3]);

/* Control points (degree + 1 of them, 3 doubles each) of the boundary curve of patch i from
 * corner c to corner c + 1; returns the curve's degree. */
SK_API unsigned sk_patch_edge_curve(const sk_patch_set *set, size_t i, unsigned c, double *cp);

/* Appends to dst three tensor patches of degree n x n that split the triangular patch i of src
 * (degree n) exactly: sub-patch q covers the quadrilateral (corner q, midpoint of edge q..q+1,
 * centroid, midpoint of edge q-1..q) of the triangle's domain, mapped bilinearly; each
 * sub-patch's (s, t) = (0, 0) is at corner q, s runs toward the midpoint of edge (q, q+1), t
 * toward the midpoint of edge (q-1, q), so sub-patch corners are [corner q, mid(q, q+1), centroid,
 * mid(q-1, q)], counter-clockwise. No sub-patch has a singular point where the triangle has none.
 * Corner ids are copied for corner q only (the others are SK_INVALID); tags are copied. dst may
 * be src. */
SK_API sk_status sk_patch_split_triangle(const sk_patch_set *src, size_t i, sk_patch_set *dst,
                                         sk_error *err);

/* Appends to dst one tensor patch of degree n x n equal to the triangle i of src under the map
 * (s, t) -> barycentric (1 - s, s (1 - t), s t); the side s = 0 collapses to corner 0 (a singular
 * point there). For CAD systems that want one surface per triangle; sk_patch_split_triangle is
 * the regular alternative. dst may be src. */
SK_API sk_status sk_patch_triangle_to_degenerate_tensor(const sk_patch_set *src, size_t i,
                                                        sk_patch_set *dst, sk_error *err);

/* Appends to dst patch i of src elevated to the given degree(s) (the same surface). dst may be
 * src. */
SK_API sk_status sk_patch_elevate(const sk_patch_set *src, size_t i, unsigned degree, unsigned degree_v,
                                  sk_patch_set *dst, sk_error *err);

/* Appends to dst the tensor patches equal to the patches of src, in order: tensor patches copied,
 * triangles split in three (sk_patch_split_triangle) or, with degenerate, one patch with a
 * collapsed side each. dst must not be src. */
SK_API sk_status sk_patch_set_to_tensor(const sk_patch_set *src, bool degenerate, sk_patch_set *dst,
                                        sk_error *err);

/* Tessellates every patch into a grid of n segments per side (triangles: n^2 triangles, tensor
 * patches: 2 n^2) with the exact patch normals, as a triangle soup with normals. Watertight:
 * where two patches share a side (the same two corner ids), the side's vertices are evaluated
 * once (on the first patch that has the side) and used by both, and patches sharing a corner id
 * share its vertex; so a closed patch network gives a closed manifold tessellation. Sides and
 * corners without ids get their own vertices. */
SK_API sk_status sk_patch_set_tessellate(const sk_patch_set *set, unsigned n, sk_soup **out,
                                         sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
