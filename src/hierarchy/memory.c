/* Large work arrays of the hierarchy: a transparent-huge-page hint.
 *
 * Building the hierarchy of a million-triangle mesh touches a few hundred megabytes of fresh memory
 * (the working mesh, split records, vertex maps). On virtual machines a first-touch page fault can
 * cost over 10 microseconds per 4 KiB page, which made page faults the largest single cost of the
 * build (perf: pvm_irq_enable under exc_page_fault). Asking for transparent huge pages on the big
 * arrays (madvise MADV_HUGEPAGE, Linux only; a no-op elsewhere or when THP is off) takes one fault
 * per 2 MiB instead. It changes no result. */
#if defined(__linux__)
#define _DEFAULT_SOURCE 1
#include <sys/mman.h>
#endif

#include "hierarchy/hierarchy_internal.h"
#include "core/internal.h"

#include <stdint.h>

void sk__huge_hint(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < ((size_t)4 << 20))
        return;
    uintptr_t a = ((uintptr_t)p + 4095u) & ~(uintptr_t)4095u;
    uintptr_t b = ((uintptr_t)p + bytes) & ~(uintptr_t)4095u;
    if (b > a)
        (void)madvise((void *)a, b - a, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

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
