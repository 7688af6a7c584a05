/* Internal mesh helpers shared by the files of src/mesh. */
#ifndef SK_MESH_INTERNAL_H
#define SK_MESH_INTERNAL_H

#include "surfkit/mesh.h"

/* An empty mesh with room for the given numbers of elements (NULL and err set on failure). */
sk_mesh *sk__mesh_alloc(size_t nv, size_t nh, size_t nf, sk_error *err);

/* Per-vertex normals and / or uvs for m (num_vertices entries each), allocated when m has none
 * and copied from these arrays; NULL leaves that attribute as it is. SK_ERR_NOMEM else SK_OK. */
sk_status sk__mesh_set_attributes(sk_mesh *m, const double *normals, const double *uvs,
                                  sk_error *err);

/* Union-find over n elements (path halving, union by index). */
uint32_t sk__uf_find(uint32_t *parent, uint32_t x);
void sk__uf_union(uint32_t *parent, uint32_t a, uint32_t b);

#endif
