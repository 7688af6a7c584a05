/* Fan triangulation of the faces of a soup or a half-edge mesh, for the modules that work on
 * triangles (BVH, deviation sampling, self-intersections, field maps, the viewer). */
#ifndef SK_MESH_FAN_H
#define SK_MESH_FAN_H

#include "surfkit/mesh.h"

/* Face f with corners i0 .. i(m-1) becomes the m - 2 triangles (i0, ic, ic+1), c = 1 .. m-2, in
 * face order; faces with fewer than 3 corners give none. *tri gets 3 vertex indices per triangle
 * and, when face is not NULL, *face the face of each (both allocated with sk__malloc_array, never
 * NULL on success even for 0 triangles; free with sk__free); *nt the count. Indices are copied,
 * not checked. SK_ERR_ARG beyond UINT32_MAX / 2 triangles, SK_ERR_NOMEM. */
sk_status sk__soup_fan_triangles(const sk_soup *s, uint32_t **tri, uint32_t **face, size_t *nt,
                                 sk_error *err);

/* The same over the live faces of a half-edge mesh (corners from f_halfedge around h_next);
 * *face holds mesh face ids. */
sk_status sk__mesh_fan_triangles(const sk_mesh *m, uint32_t **tri, uint32_t **face, size_t *nt,
                                 sk_error *err);

#endif
