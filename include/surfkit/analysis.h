/* Differential-geometry estimates on meshes: vertex normals.
 *
 * Xu, Xu, Sun (Mathematics of Surfaces XI, "Convergence analysis of discrete differential geometry
 * operators over surfaces"): the mean, area- and angle-weighted averages of face normals converge
 * at O(h^2) only on special triangulations (valence n >= 4 with a regular ring for mean/area; even
 * valence with a centrally symmetric ring for the angle weights); valence 3 and irregular rings
 * give O(h). A local quadratic fit converges at O(h^2) whenever the fit is unique. */
#ifndef SURFKIT_ANALYSIS_H
#define SURFKIT_ANALYSIS_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SK_NORMALS_ANGLE = 0, /* angle-weighted average of face normals (default) */
    SK_NORMALS_AREA = 1,  /* area-weighted average */
    SK_NORMALS_MEAN = 2,  /* arithmetic mean of the unit face normals */
    SK_NORMALS_QUADRIC = 3 /* gradient of a local quadratic height-field fit (1-ring, 2-ring if
                              the 1-ring has fewer than 5 neighbours); where the fit is singular
                              (fewer than 5 neighbours, or neighbours that do not determine the
                              quadric, e.g. all on two lines through the vertex) the vertex keeps
                              its angle-weighted normal */
} sk_normal_method;

/* Parses "angle", "area", "mean", "quadric"; returns -1 for anything else. */
SK_API int sk_normal_method_from_name(const char *name);
SK_API const char *sk_normal_method_name(sk_normal_method method);

/* Unit vertex normals (3 per vertex, written to out) estimated from the faces around each vertex
 * (triangles or polygons; polygon corners use the cross product of their two edges). Isolated
 * vertices get (0, 0, 0). Fails with SK_ERR_NUMERIC naming the vertex when the faces around a
 * vertex cancel out (zero-length normal), SK_ERR_ARG for an unknown method. */
SK_API sk_status sk_mesh_vertex_normals(const sk_mesh *mesh, sk_normal_method method, double *out,
                                        sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
