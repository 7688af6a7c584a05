/* Large work arrays of the hierarchy, with the transparent-huge-page hint of src/core/huge_pages.c
 * (page faults were the largest single cost of building a million-triangle hierarchy). */
#include "hierarchy/hierarchy_internal.h"
#include "core/internal.h"

#include <stdint.h>

void *sk__alloc_huge(size_t n, size_t size)
{
    void *p = sk__malloc_array(n, size);
    if (p)
        sk__huge_hint(p, n * size);
    return p;
}

void sk__mesh_huge_hint(sk_mesh *m)
{
    size_t nv = m->cap_vertices, nh = m->cap_halfedges, nf = m->cap_faces;
    sk__huge_hint(m->positions, nv * 3 * sizeof(double));
    if (m->normals)
        sk__huge_hint(m->normals, nv * 3 * sizeof(double));
    if (m->uvs)
        sk__huge_hint(m->uvs, nv * 2 * sizeof(double));
    sk__huge_hint(m->v_halfedge, nv * sizeof(uint32_t));
    sk__huge_hint(m->v_deleted, nv);
    sk__huge_hint(m->h_vertex, nh * sizeof(uint32_t));
    sk__huge_hint(m->h_next, nh * sizeof(uint32_t));
    sk__huge_hint(m->h_prev, nh * sizeof(uint32_t));
    sk__huge_hint(m->h_face, nh * sizeof(uint32_t));
    sk__huge_hint(m->e_deleted, nh / 2);
    sk__huge_hint(m->f_halfedge, nf * sizeof(uint32_t));
    sk__huge_hint(m->f_deleted, nf);
}
