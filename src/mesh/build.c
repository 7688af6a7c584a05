/* Building a half-edge mesh from indexed faces.
 *
 * Corners (face, position) are keyed by their undirected edge (lo, hi) and sorted by it: a
 * counting sort by lo, then each vertex's few corners by hi; each group of one or two corners
 * becomes an edge with half-edges 2e and 2e+1. Groups of three or more (non-manifold edges), two
 * corners in the same direction (orientation conflict), a vertex with two boundary gaps or two
 * separate fans (non-manifold vertex) stop the build with an error naming the elements.
 * sk_soup_validate gives the full report of such input. */
#include "surfkit/mesh.h"
#include "core/internal.h"
#include "mesh/mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static sk_status check_faces(size_t nv, const double *pos, size_t nf, const uint32_t *off,
                             const uint32_t *idx, sk_error *err)
{
    for (size_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(pos[3 * v + k]))
                return sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu has a non-finite coordinate", v);
    for (size_t f = 0; f < nf; ++f) {
        size_t n = off[f + 1] - off[f];
        const uint32_t *c = idx + off[f];
        if (n < 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has %zu vertices (at least 3 needed)",
                            f, n);
        for (size_t i = 0; i < n; ++i) {
            if (c[i] >= nv)
                return sk__fail(err, SK_ERR_TOPOLOGY,
                                "face %zu has index %u but there are %zu vertices", f, c[i], nv);
            for (size_t j = 0; j < i; ++j)
                if (c[i] == c[j])
                    return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu uses vertex %u twice", f, c[i]);
        }
    }
    return SK_OK;
}

/* Corner c of a face runs from idx[c] to the face's next corner's vertex. */
static inline uint32_t corner_head(const uint32_t *off, const uint32_t *idx, size_t f, uint32_t c)
{
    return idx[c + 1 < off[f + 1] ? c + 1 : off[f]];
}

/* Sorts the n pairs (hi, corner) by hi, stably: the corners of one edge stay in their order. */
static sk_status sort_bucket(uint64_t *hi, uint32_t *corner, size_t n)
{
    if (n > 32)
        return sk__sort_u64_u32(hi, corner, n);
    for (size_t i = 1; i < n; ++i) {
        uint64_t k = hi[i];
        uint32_t c = corner[i];
        size_t j = i;
        for (; j > 0 && hi[j - 1] > k; --j) {
            hi[j] = hi[j - 1];
            corner[j] = corner[j - 1];
        }
        hi[j] = k;
        corner[j] = c;
    }
    return SK_OK;
}

/* keys[i] = lo << 32 | hi of the undirected edge of corner[i], ascending, corners of one edge in
 * increasing order: the order of a stable sort of all corners by that key, made as a counting
 * sort by lo and a sort of each lo's corners by hi (a vertex has few). */
static sk_status sort_corners_by_edge(size_t nv, size_t nf, const uint32_t *off,
                                      const uint32_t *idx, uint64_t *keys, uint32_t *corner)
{
    uint32_t *start = sk__calloc_array(nv + 1, sizeof *start);
    if (!start)
        return SK_ERR_NOMEM;
    for (size_t f = 0; f < nf; ++f)
        for (uint32_t c = off[f]; c < off[f + 1]; ++c) {
            uint32_t a = idx[c], b = corner_head(off, idx, f, c);
            start[(a < b ? a : b) + 1]++;
        }
    for (size_t v = 0; v < nv; ++v)
        start[v + 1] += start[v];
    for (size_t f = 0; f < nf; ++f) /* keys holds hi until the buckets are sorted */
        for (uint32_t c = off[f]; c < off[f + 1]; ++c) {
            uint32_t a = idx[c], b = corner_head(off, idx, f, c);
            uint32_t slot = start[a < b ? a : b]++;
            keys[slot] = a < b ? b : a;
            corner[slot] = c;
        }
    sk_status st = SK_OK;
    for (size_t v = nv, end = off[nf]; v-- > 0 && !st;) { /* bucket v ends at start[v] now */
        size_t b = v ? start[v - 1] : 0;
        st = sort_bucket(keys + b, corner + b, end - b);
        for (size_t i = b; i < end; ++i)
            keys[i] |= (uint64_t)v << 32;
        end = b;
    }
    sk__free(start);
    return st;
}

sk_status sk_mesh_from_faces(size_t nv, const double *pos, size_t nf, const uint32_t *off,
                             const uint32_t *idx, sk_mesh **out, sk_error *err)
{
    *out = NULL;
    sk_status st = check_faces(nv, pos, nf, off, idx, err);
    if (st)
        return st;
    size_t nc = off[nf]; /* corners */
    if (nc > UINT32_MAX / 2 - 1 || nv >= UINT32_MAX)
        return sk__fail(err, SK_ERR_ARG, "mesh too large for 32-bit indices");

    uint64_t *keys = sk__malloc_array(nc, sizeof(uint64_t));
    uint32_t *corner = sk__malloc_array(nc, sizeof(uint32_t));
    uint32_t *cface = sk__malloc_array(nc, sizeof(uint32_t));
    uint32_t *ch = sk__malloc_array(nc, sizeof(uint32_t));     /* corner -> half-edge */
    uint32_t *bout = sk__malloc_array(nv, sizeof(uint32_t));   /* outgoing boundary half-edge */
    sk_mesh *m = NULL;
    if (!keys || !corner || !cface || !ch || !bout) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the mesh");
        goto done;
    }
    for (size_t f = 0; f < nf; ++f)
        for (uint32_t c = off[f]; c < off[f + 1]; ++c)
            cface[c] = (uint32_t)f;
    if (sort_corners_by_edge(nv, nf, off, idx, keys, corner)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the mesh");
        goto done;
    }
    /* count edges */
    size_t ne = 0;
    for (size_t i = 0; i < nc;) {
        size_t j = i + 1;
        while (j < nc && keys[j] == keys[i])
            ++j;
        if (j - i > 2) {
            st = sk__fail(err, SK_ERR_TOPOLOGY,
                          "edge (%u, %u) is non-manifold: %zu faces share it (faces %u, %u, %u)",
                          (uint32_t)(keys[i] >> 32), (uint32_t)keys[i], j - i, cface[corner[i]],
                          cface[corner[i + 1]], cface[corner[i + 2]]);
            goto done;
        }
        if (j - i == 2 && idx[corner[i]] == idx[corner[i + 1]]) {
            st = sk__fail(err, SK_ERR_TOPOLOGY,
                          "faces %u and %u use edge (%u, %u) in the same direction "
                          "(inconsistent orientation)",
                          cface[corner[i]], cface[corner[i + 1]], (uint32_t)(keys[i] >> 32),
                          (uint32_t)keys[i]);
            goto done;
        }
        ++ne;
        i = j;
    }
    m = sk__mesh_alloc(nv, 2 * ne, nf, err);
    if (!m) {
        st = SK_ERR_NOMEM;
        goto done;
    }
    m->num_vertices = nv;
    m->num_halfedges = 2 * ne;
    m->num_faces = nf;
    memcpy(m->positions, pos, nv * 3 * sizeof(double));
    memset(m->v_deleted, 0, nv);
    memset(m->e_deleted, 0, ne);
    memset(m->f_deleted, 0, nf);
    for (size_t v = 0; v < nv; ++v)
        m->v_halfedge[v] = bout[v] = SK_INVALID;

    uint32_t e = 0;
    for (size_t i = 0; i < nc; ++e) {
        size_t j = i + 1;
        while (j < nc && keys[j] == keys[i])
            ++j;
        for (size_t k = i; k < j; ++k) {
            uint32_t c = corner[k], f = cface[c];
            uint32_t h = 2 * e + (uint32_t)(k - i);
            uint32_t cn = c + 1 < off[f + 1] ? c + 1 : off[f];
            ch[c] = h;
            m->h_vertex[h] = idx[cn];
            m->h_face[h] = f;
        }
        if (j - i == 1) { /* boundary half-edge: opposite direction, no face */
            uint32_t c = corner[i];
            uint32_t h = 2 * e + 1;
            m->h_vertex[h] = idx[c];
            m->h_face[h] = SK_INVALID;
            uint32_t from = m->h_vertex[h ^ 1u];
            if (bout[from] != SK_INVALID) {
                st = sk__fail(err, SK_ERR_TOPOLOGY,
                              "vertex %u is non-manifold: two boundary gaps meet there", from);
                goto done;
            }
            bout[from] = h;
        }
        i = j;
    }
    for (size_t f = 0; f < nf; ++f) {
        uint32_t b = off[f], n = off[f + 1] - b;
        m->f_halfedge[f] = ch[b];
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t h = ch[b + i], hn = ch[b + (i + 1) % n];
            m->h_next[h] = hn;
            m->h_prev[hn] = h;
            m->v_halfedge[idx[b + i]] = h; /* some outgoing half-edge */
        }
    }
    for (size_t v = 0; v < nv; ++v) {
        uint32_t h = bout[v];
        if (h == SK_INVALID)
            continue;
        m->v_halfedge[v] = h;
        uint32_t hn = bout[m->h_vertex[h]];
        m->h_next[h] = hn;
        m->h_prev[hn] = h;
    }
    /* two fans at one vertex: the fan walk from v_halfedge misses edges */
    sk_error cerr;
    sk_status cst = sk_mesh_check(m, &cerr);
    if (cst != SK_OK) { /* out of memory stays out of memory */
        st = sk__fail(err, cst == SK_ERR_NOMEM ? SK_ERR_NOMEM : SK_ERR_TOPOLOGY, "%s", cerr.message);
        goto done;
    }
done:
    sk__free(keys);
    sk__free(corner);
    sk__free(cface);
    sk__free(ch);
    sk__free(bout);
    if (st)
        sk_mesh_destroy(&m);
    *out = m;
    return st;
}

/* The soup's per-corner wedge indices (of uvs, or of normals) as the mesh's per-half-edge ones:
 * soup corner c of face f is the half-edge leaving face_indices[c] (build order). */
static sk_status corner_wedges(sk_mesh *m, const sk_soup *s, const uint32_t *corner, bool normals,
                               sk_error *err)
{
    uint32_t *hw = sk__malloc_array(m->num_halfedges ? m->num_halfedges : 1, sizeof(uint32_t));
    if (!hw)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t h = 0; h < m->num_halfedges; ++h)
        hw[h] = SK_INVALID;
    for (size_t f = 0; f < s->num_faces; ++f) {
        uint32_t h = m->f_halfedge[f];
        for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; ++c) {
            hw[h] = corner[c];
            h = m->h_next[h];
        }
    }
    sk_status st = normals
                       ? sk_mesh_set_wedge_normals(m, s->num_wedge_normals, s->wedge_normals, hw, err)
                       : sk_mesh_set_wedge_uvs(m, s->num_wedge_uvs, s->wedge_uvs, hw, err);
    sk__free(hw);
    return st;
}

sk_status sk_mesh_from_soup(const sk_soup *s, sk_mesh **out, sk_error *err)
{
    sk_status st = sk_mesh_from_faces(s->num_vertices, s->positions, s->num_faces, s->face_offsets,
                                      s->face_indices, out, err);
    if (st)
        return st;
    sk_mesh *m = *out;
    if (sk__mesh_set_attributes(m, s->normals, s->uvs, err)) {
        sk_mesh_destroy(out);
        return SK_ERR_NOMEM;
    }
    sk_status st2 = SK_OK;
    if (s->corner_uv)
        st2 = corner_wedges(m, s, s->corner_uv, false, err);
    if (!st2 && s->corner_normal)
        st2 = corner_wedges(m, s, s->corner_normal, true, err);
    if (st2)
        sk_mesh_destroy(out);
    return st2;
}
