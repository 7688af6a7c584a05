/* Loop subdivision and 1-to-4 midpoint refinement of triangle meshes. */
#include "surfkit/subdivide.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec.h"

/* Loop's original weight for an interior vertex of valence n. */
static double loop_beta(size_t n)
{
    double c = 0.375 + 0.25 * cos(2.0 * M_PI / (double)n);
    return (0.625 - c * c) / (double)n;
}

static void lerp_attr(double *dst, const double *a, const double *b, int dim)
{
    for (int k = 0; k < dim; ++k)
        dst[k] = 0.5 * (a[k] + b[k]);
}

static sk_status subdivide_once(const sk_mesh *m, bool loop, sk_mesh **out, sk_error *err)
{
    *out = NULL;
    size_t nv = m->num_vertices, ne = sk_num_edges(m), nf = m->num_faces;
    for (size_t f = 0; f < nf; ++f)
        if (!m->f_deleted[f] && sk_mesh_face_size(m, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "face %zu has %zu vertices: subdivision needs triangles", f,
                            sk_mesh_face_size(m, (uint32_t)f));
    if (nv + ne >= UINT32_MAX || 4 * nf >= UINT32_MAX / 3)
        return sk__fail(err, SK_ERR_ARG, "subdivided mesh too large for 32-bit indices");
    /* the refined faces as a soup: old vertices, then one per edge; four triangles per face */
    size_t nv2 = nv + ne;
    sk_soup *soup = NULL;
    sk_mesh *r = NULL;
    sk_status st = sk_soup_create(nv2, 4 * nf, 12 * nf, m->normals != NULL, m->uvs != NULL,
                                  &soup, err);
    if (st)
        goto done;
    double *pos = soup->positions, *nrm = soup->normals, *uv = soup->uvs;
    uint32_t *off = soup->face_offsets, *idx = soup->face_indices;
    /* even (old) vertices */
    for (size_t v = 0; v < nv; ++v) {
        const double *p = m->positions + 3 * v;
        double *q = pos + 3 * v;
        memcpy(q, p, 3 * sizeof(double));
        if (nrm)
            memcpy(nrm + 3 * v, m->normals + 3 * v, 3 * sizeof(double));
        if (uv)
            memcpy(uv + 2 * v, m->uvs + 2 * v, 2 * sizeof(double));
        uint32_t h0 = m->v_halfedge[v];
        if (!loop || m->v_deleted[v] || h0 == SK_INVALID)
            continue;
        if (m->h_face[h0] == SK_INVALID) { /* boundary: 3/4 v + 1/8 (b0 + b1) */
            const double *b0 = m->positions + 3 * (size_t)m->h_vertex[h0];
            const double *b1 = m->positions + 3 * (size_t)sk_from(m, m->h_prev[h0]);
            for (int k = 0; k < 3; ++k)
                q[k] = 0.75 * p[k] + 0.125 * (b0[k] + b1[k]);
        } else {
            size_t n = 0;
            double s[3] = {0, 0, 0};
            uint32_t h = h0;
            do {
                sk__add3(s, s, m->positions + 3 * (size_t)m->h_vertex[h]);
                ++n;
                h = sk_cw_out(m, h);
            } while (h != h0);
            double beta = loop_beta(n);
            for (int k = 0; k < 3; ++k)
                q[k] = (1.0 - (double)n * beta) * p[k] + beta * s[k];
        }
    }
    /* odd (edge) vertices */
    for (size_t e = 0; e < ne; ++e) {
        double *q = pos + 3 * (nv + e);
        if (m->e_deleted[e]) {
            q[0] = q[1] = q[2] = 0.0;
            continue;
        }
        uint32_t h = (uint32_t)(2 * e);
        uint32_t a = m->h_vertex[h], b = m->h_vertex[h ^ 1u];
        const double *pa = m->positions + 3 * (size_t)a, *pb = m->positions + 3 * (size_t)b;
        if (!loop || sk_is_boundary_e(m, (uint32_t)e)) {
            lerp_attr(q, pa, pb, 3);
        } else {
            const double *pc = m->positions + 3 * (size_t)m->h_vertex[m->h_next[h]];
            const double *pd = m->positions + 3 * (size_t)m->h_vertex[m->h_next[h ^ 1u]];
            for (int k = 0; k < 3; ++k)
                q[k] = 0.375 * (pa[k] + pb[k]) + 0.125 * (pc[k] + pd[k]);
        }
        if (nrm) {
            lerp_attr(nrm + 3 * (nv + e), m->normals + 3 * (size_t)a, m->normals + 3 * (size_t)b, 3);
            sk__normalize3(nrm + 3 * (nv + e));
        }
        if (uv)
            lerp_attr(uv + 2 * (nv + e), m->uvs + 2 * (size_t)a, m->uvs + 2 * (size_t)b, 2);
    }
    /* four triangles per face: corner triangles then the middle one */
    size_t k = 0, nf2 = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h0 = m->f_halfedge[f], h1 = m->h_next[h0], h2 = m->h_next[h1];
        uint32_t v0 = sk_from(m, h0), v1 = sk_from(m, h1), v2 = sk_from(m, h2);
        uint32_t e0 = (uint32_t)nv + (h0 >> 1), e1 = (uint32_t)nv + (h1 >> 1),
                 e2 = (uint32_t)nv + (h2 >> 1);
        uint32_t t[12] = {v0, e0, e2, v1, e1, e0, v2, e2, e1, e0, e1, e2};
        memcpy(idx + k, t, sizeof t);
        for (int i = 0; i < 4; ++i)
            off[nf2 + (size_t)i] = (uint32_t)(k + 3 * (size_t)i);
        k += 12;
        nf2 += 4;
    }
    off[nf2] = (uint32_t)k;
    soup->num_vertices = nv2;
    soup->num_faces = nf2;
    if ((st = sk_mesh_from_soup(soup, &r, err)))
        goto done;
    /* carry deletion of vertices and edges that were already deleted */
    for (size_t v = 0; v < nv; ++v)
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            r->v_deleted[v] = 1, r->num_deleted_vertices++;
    for (size_t e = 0; e < ne; ++e)
        if (m->e_deleted[e])
            r->v_deleted[nv + e] = 1, r->num_deleted_vertices++;
    if (r->num_deleted_vertices)
        st = sk_mesh_compact(r, NULL, NULL, err);
done:
    sk_soup_destroy(&soup);
    if (st)
        sk_mesh_destroy(&r);
    *out = r;
    return st;
}

sk_status sk_mesh_subdivide(const sk_mesh *mesh, const sk_subdiv_opts *opts, sk_mesh **out,
                            sk_error *err)
{
    sk_subdiv_opts o = {0};
    if (opts)
        o = *opts;
    unsigned n = o.iterations ? o.iterations : 1;
    bool loop = o.scheme == SK_SUBDIV_LOOP;
    if (o.scheme != SK_SUBDIV_LOOP && o.scheme != SK_SUBDIV_MIDPOINT)
        return sk__fail(err, SK_ERR_ARG, "unknown subdivision scheme %d", (int)o.scheme);
    *out = NULL;
    sk_mesh *cur = NULL;
    const sk_mesh *src = mesh;
    for (unsigned i = 0; i < n; ++i) {
        sk_status st = sk__progress(o.progress, o.progress_user, (double)i / n, err);
        sk_mesh *next = NULL;
        if (st == SK_OK)
            st = subdivide_once(src, loop, &next, err);
        sk_mesh_destroy(&cur);
        if (st)
            return st;
        cur = next;
        src = cur;
    }
    *out = cur;
    return sk__progress(o.progress, o.progress_user, 1.0, err) == SK_OK ? SK_OK
                                                                         : (sk_mesh_destroy(out), SK_ERR_CANCELLED);
}
