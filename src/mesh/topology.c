/* Topology and geometry queries on the half-edge mesh: boundary loops, components, Euler
 * characteristic and genus, face normals and areas, edge lengths, bounding box. */
#include "surfkit/mesh.h"
#include "core/internal.h"
#include "core/vec.h"
#include "mesh/mesh_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

uint32_t sk__uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

void sk__uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = sk__uf_find(parent, a);
    b = sk__uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

void sk_loops_free(sk_loops *loops)
{
    sk__free(loops->offsets);
    sk__free(loops->halfedges);
    sk__free(loops->lengths);
    loops->offsets = NULL;
    loops->halfedges = NULL;
    loops->lengths = NULL;
    loops->count = 0;
}

sk_status sk_mesh_boundary_loops(const sk_mesh *m, sk_loops *loops, sk_error *err)
{
    size_t nh = m->num_halfedges, nb = 0, count = 0;
    loops->count = 0;
    loops->offsets = NULL;
    loops->lengths = NULL;
    for (size_t h = 0; h < nh; ++h)
        nb += !m->e_deleted[h / 2] && m->h_face[h] == SK_INVALID;
    uint8_t *seen = sk__calloc_array(nh, 1);
    loops->halfedges = sk__malloc_array(nb, sizeof(uint32_t));
    loops->offsets = sk__malloc_array(nb + 1, sizeof(uint32_t));
    loops->lengths = sk__malloc_array(nb, sizeof(double));
    if (!seen || !loops->halfedges || !loops->offsets || !loops->lengths) {
        sk__free(seen);
        sk_loops_free(loops);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    uint32_t k = 0;
    loops->offsets[0] = 0;
    for (size_t h0 = 0; h0 < nh; ++h0) {
        if (m->e_deleted[h0 / 2] || m->h_face[h0] != SK_INVALID || seen[h0])
            continue;
        double len = 0.0;
        uint32_t h = (uint32_t)h0;
        do {
            seen[h] = 1;
            loops->halfedges[k++] = h;
            len += sk_mesh_edge_length(m, h >> 1);
            h = m->h_next[h];
        } while (h != h0 && k < nb);
        loops->lengths[count] = len;
        loops->offsets[++count] = k;
    }
    loops->count = count;
    sk__free(seen);
    return SK_OK;
}

sk_status sk_mesh_topology(const sk_mesh *m, sk_topology *top, uint32_t *face_component,
                           sk_error *err)
{
    size_t nv = m->num_vertices, nh = m->num_halfedges, nf = m->num_faces;
    uint32_t *parent = sk__malloc_array(nv, sizeof(uint32_t));
    uint32_t *cid = sk__malloc_array(nv, sizeof(uint32_t));
    long *chi = NULL, *bnd = NULL;
    if (!parent || !cid) {
        sk__free(parent);
        sk__free(cid);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t v = 0; v < nv; ++v)
        parent[v] = (uint32_t)v;
    for (size_t h = 0; h < nh; h += 2)
        if (!m->e_deleted[h / 2])
            sk__uf_union(parent, m->h_vertex[h], m->h_vertex[h + 1]);
    size_t nc = 0;
    for (size_t v = 0; v < nv; ++v) {
        cid[v] = SK_INVALID;
        if (!m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID && sk__uf_find(parent, (uint32_t)v) == v)
            cid[v] = (uint32_t)nc++;
    }
    chi = sk__calloc_array(nc ? nc : 1, sizeof(long));
    bnd = sk__calloc_array(nc ? nc : 1, sizeof(long));
    if (!chi || !bnd) {
        sk__free(parent);
        sk__free(cid);
        sk__free(chi);
        sk__free(bnd);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    top->vertices = top->edges = top->faces = top->boundary_loops = 0;
    for (size_t v = 0; v < nv; ++v) {
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        top->vertices++;
        chi[cid[sk__uf_find(parent, (uint32_t)v)]]++;
    }
    for (size_t h = 0; h < nh; h += 2) {
        if (m->e_deleted[h / 2])
            continue;
        top->edges++;
        chi[cid[sk__uf_find(parent, m->h_vertex[h])]]--;
    }
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_deleted[f])
            continue;
        top->faces++;
        uint32_t c = cid[sk__uf_find(parent, m->h_vertex[m->f_halfedge[f]])];
        chi[c]++;
        if (face_component)
            face_component[f] = c;
    }
    sk_loops loops;
    sk_status st = sk_mesh_boundary_loops(m, &loops, err);
    if (st == SK_OK) {
        for (size_t i = 0; i < loops.count; ++i)
            bnd[cid[sk__uf_find(parent, m->h_vertex[loops.halfedges[loops.offsets[i]]])]]++;
        top->boundary_loops = loops.count;
        sk_loops_free(&loops);
    }
    top->components = nc;
    top->euler_characteristic = 0;
    top->genus = 0;
    for (size_t c = 0; c < nc; ++c) {
        top->euler_characteristic += chi[c];
        top->genus += (2 - chi[c] - bnd[c]) / 2; /* orientable: chi = 2 - 2g - b */
    }
    sk__free(parent);
    sk__free(cid);
    sk__free(chi);
    sk__free(bnd);
    return st;
}

double sk_mesh_face_normal(const sk_mesh *m, uint32_t f, double n[3])
{
    /* Newell's method: exact for planar polygons, the cross product for triangles */
    n[0] = n[1] = n[2] = 0.0;
    uint32_t h0 = m->f_halfedge[f], h = h0;
    do {
        const double *a = m->positions + 3 * (size_t)sk_from(m, h);
        const double *b = m->positions + 3 * (size_t)m->h_vertex[h];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
        h = m->h_next[h];
    } while (h != h0);
    return sk__normalize3(n);
}

double sk_mesh_face_area(const sk_mesh *m, uint32_t f)
{
    double n[3];
    return 0.5 * sk_mesh_face_normal(m, f, n);
}

double sk_mesh_edge_length(const sk_mesh *m, uint32_t e)
{
    return sk__dist3(m->positions + 3 * (size_t)m->h_vertex[2 * e],
                     m->positions + 3 * (size_t)m->h_vertex[2 * e + 1]);
}

void sk_mesh_bbox(const sk_mesh *m, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; ++k) {
        lo[k] = DBL_MAX;
        hi[k] = -DBL_MAX;
    }
    for (size_t v = 0; v < m->num_vertices; ++v) {
        if (m->v_deleted[v])
            continue;
        for (int k = 0; k < 3; ++k) {
            double x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    }
}

sk_status sk_mesh_check_scale(const sk_mesh *m, sk_error *err)
{
    double lo[3], hi[3];
    sk_mesh_bbox(m, lo, hi);
    if (lo[0] > hi[0])
        return SK_OK; /* no vertex */
    double big = 0.0;
    for (int k = 0; k < 3; ++k) {
        big = fabs(lo[k]) > big ? fabs(lo[k]) : big;
        big = fabs(hi[k]) > big ? fabs(hi[k]) : big;
    }
    if (!(big <= SK_COORD_MAX))
        return sk__fail(err, SK_ERR_TOPOLOGY,
                        "a coordinate of magnitude %.3g is out of the supported range (at most "
                        "%.0e): rescale the mesh", big, SK_COORD_MAX);
    double d = sk__dist3(lo, hi);
    if (d > 0.0 && d < SK_COORD_MIN_SIZE)
        return sk__fail(err, SK_ERR_TOPOLOGY,
                        "the mesh is %.3g across, below the supported size (at least %.0e): "
                        "rescale the mesh", d, SK_COORD_MIN_SIZE);
    return SK_OK;
}

double sk_mesh_diagonal(const sk_mesh *m)
{
    double lo[3], hi[3];
    sk_mesh_bbox(m, lo, hi);
    if (lo[0] > hi[0])
        return 0.0;
    return sk__dist3(lo, hi);
}
