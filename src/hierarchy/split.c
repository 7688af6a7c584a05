/* Vertex split (the inverse of the half-edge collapse, Hormann et al. section 2, Fig. 2), level
 * storage and the walk from the coarsest level up ("Triangle Insertion", section 3).
 *
 * Storage (OpenSubdiv-like, O(n) memory): the coarsest mesh, and per pair of consecutive levels
 * the fine -> coarse vertex map and one sk_vertex_split record per removed vertex. A split finds
 * the half-edges (w0 -> first) and (w0 -> last), gives the fan of faces between them to the new
 * vertex and recreates the one or two triangles of the collapsed edge; the half-edge that took
 * another one's place during the collapse gives it back. Splits of one level touch disjoint faces
 * (the removed vertices are pairwise non-adjacent), so their order does not matter; they are
 * stored sorted by w0 (locality) and applied in reverse order. The renumbering at the end gives
 * every vertex its level i+1 number, so the result equals level i+1 face for face (half-edge and
 * face ids may differ). */
#include "hierarchy/hierarchy_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>
#include <string.h>

uint32_t sk__vertex_split(sk_mesh *m, const sk_vertex_split *s)
{
    uint32_t v1 = s->w0;
    if (v1 >= m->num_vertices || m->v_deleted[v1] || m->v_halfedge[v1] == SK_INVALID)
        return SK_INVALID;
    /* the half-edges w0 -> first and w0 -> last */
    uint32_t h0 = m->v_halfedge[v1], z = h0, x = SK_INVALID, y = SK_INVALID;
    size_t val = 0;
    do {
        if (m->h_vertex[z] == s->first)
            x = z;
        if (m->h_vertex[z] == s->last)
            y = z;
        ++val;
        z = sk_cw_out(m, z);
    } while (z != h0 && val <= m->num_halfedges);
    if (x == SK_INVALID || y == SK_INVALID || x == y)
        return SK_INVALID;
    if (s->left_face && m->h_face[x] == SK_INVALID)
        return SK_INVALID;

    uint32_t v0 = sk_mesh_new_vertex(m, s->position);
    uint32_t h = sk_mesh_new_edge(m), o = h ^ 1u;
    uint32_t a = s->left_face ? sk_mesh_new_edge(m) : SK_INVALID;
    uint32_t d = s->right_face ? sk_mesh_new_edge(m) : SK_INVALID;
    uint32_t fl = s->left_face ? sk_mesh_new_face(m) : SK_INVALID;
    uint32_t fr = s->right_face ? sk_mesh_new_face(m) : SK_INVALID;
    if (v0 == SK_INVALID || h == SK_INVALID || (s->left_face && (a == SK_INVALID || fl == SK_INVALID)) ||
        (s->right_face && (d == SK_INVALID || fr == SK_INVALID)))
        return SK_INVALID; /* out of memory (the caller reserves, so this does not happen) */
    uint32_t *hv = m->h_vertex, *hn = m->h_next, *hp = m->h_prev, *hf = m->h_face;
    uint32_t *vh = m->v_halfedge, *fh = m->f_halfedge;

    /* the fan from x counter-clockwise to y goes to v0 */
    z = x;
    for (size_t k = 0; k <= val; ++k) {
        hv[z ^ 1u] = v0;
        if (z == y)
            break;
        z = hp[z] ^ 1u;
    }
    hv[h] = v1;
    hv[o] = v0;

    if (s->left_face) {
        /* triangle (v0, v1, first): a1 = first->v1 takes back the place of b = first->v0 */
        uint32_t a1 = a ^ 1u, b = x ^ 1u;
        hv[a] = s->first;
        hv[a1] = v1;
        sk__halfedge_take_place(m, a1, b);
        if (vh[s->first] == b)
            vh[s->first] = a1;
        hn[h] = a, hn[a] = b, hn[b] = h;
        hp[h] = b, hp[b] = a, hp[a] = h;
        hf[h] = hf[a] = hf[b] = fl;
        fh[fl] = h;
    } else {
        /* boundary: ... -> first->v0 -> v0->v1 -> (v1's boundary half-edge) */
        uint32_t p = x ^ 1u, g = hn[p];
        hn[p] = h;
        hp[h] = p;
        hn[h] = g;
        hp[g] = h;
        hf[h] = SK_INVALID;
    }
    if (s->right_face) {
        /* triangle (v1, v0, last): d1 = v1->last takes back the place of c = y = v0->last */
        uint32_t d1 = d ^ 1u, c = y;
        hv[d] = v1;
        hv[d1] = s->last;
        sk__halfedge_take_place(m, d1, c);
        if (vh[v1] == c)
            vh[v1] = d1;
        hn[o] = c, hn[c] = d, hn[d] = o;
        hp[o] = d, hp[d] = c, hp[c] = o;
        hf[o] = hf[c] = hf[d] = fr;
        fh[fr] = o;
    } else {
        /* boundary: (into v1) -> v1->v0 -> v0->last */
        uint32_t q = hp[y];
        hn[q] = o;
        hp[o] = q;
        hn[o] = y;
        hp[y] = o;
        hf[o] = SK_INVALID;
    }
    vh[v0] = !s->left_face ? h : (!s->right_face ? y : h);
    if (!s->right_face || hv[vh[v1] ^ 1u] != v1)
        vh[v1] = o;

    /* attributes of the new vertex from the parent triangle (section 3) */
    const double *l = s->bary;
    if (m->uvs) {
        double *uv = m->uvs;
        for (int k = 0; k < 2; ++k)
            uv[2 * (size_t)v0 + k] = l[0] * uv[2 * (size_t)s->parent[0] + k] +
                                     l[1] * uv[2 * (size_t)s->parent[1] + k] +
                                     l[2] * uv[2 * (size_t)s->parent[2] + k];
    }
    if (m->normals) {
        double *nr = m->normals, nv[3];
        for (int k = 0; k < 3; ++k)
            nv[k] = l[0] * nr[3 * (size_t)s->parent[0] + k] + l[1] * nr[3 * (size_t)s->parent[1] + k] +
                    l[2] * nr[3 * (size_t)s->parent[2] + k];
        sk__normalize3(nv);
        memcpy(nr + 3 * (size_t)v0, nv, sizeof nv);
    }
    return v0;
}

sk_status sk__permute_vertices(sk_mesh *m, const uint32_t *newid, sk_error *err)
{
    size_t nv = m->num_vertices;
    double *pos = sk__alloc_huge(nv, 3 * sizeof(double));
    double *nrm = m->normals ? sk__alloc_huge(nv, 3 * sizeof(double)) : NULL;
    double *uv = m->uvs ? sk__alloc_huge(nv, 2 * sizeof(double)) : NULL;
    uint32_t *vh = sk__alloc_huge(nv, sizeof(uint32_t));
    if (!pos || !vh || (m->normals && !nrm) || (m->uvs && !uv)) {
        sk__free(pos);
        sk__free(nrm);
        sk__free(uv);
        sk__free(vh);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory renumbering a level");
    }
    for (size_t k = 0; k < nv; ++k) {
        size_t t = newid[k];
        memcpy(pos + 3 * t, m->positions + 3 * k, 3 * sizeof(double));
        if (nrm)
            memcpy(nrm + 3 * t, m->normals + 3 * k, 3 * sizeof(double));
        if (uv)
            memcpy(uv + 2 * t, m->uvs + 2 * k, 2 * sizeof(double));
        vh[t] = m->v_halfedge[k];
    }
    memcpy(m->positions, pos, nv * 3 * sizeof(double));
    if (nrm)
        memcpy(m->normals, nrm, nv * 3 * sizeof(double));
    if (uv)
        memcpy(m->uvs, uv, nv * 2 * sizeof(double));
    memcpy(m->v_halfedge, vh, nv * sizeof(uint32_t));
    memset(m->v_deleted, 0, nv);
    for (size_t h = 0; h < m->num_halfedges; ++h)
        m->h_vertex[h] = newid[m->h_vertex[h]];
    sk__free(pos);
    sk__free(nrm);
    sk__free(uv);
    sk__free(vh);
    return SK_OK;
}

size_t sk_hierarchy_num_levels(const sk_hierarchy *h)
{
    return h ? h->num_levels : 0;
}

sk_level_info sk_hierarchy_level_info(const sk_hierarchy *h, size_t level)
{
    sk_level_info info = {0, 0, 0.0};
    if (h && level < h->num_levels) {
        info.vertices = h->levels[level].vertices;
        info.faces = h->levels[level].faces;
        info.seconds = h->levels[level].seconds;
    }
    return info;
}

const sk_mesh *sk_hierarchy_coarsest(const sk_hierarchy *h)
{
    return h ? h->coarsest : NULL;
}

const sk_vertex_split *sk_hierarchy_splits(const sk_hierarchy *h, size_t level, size_t *count)
{
    if (!h || level + 1 >= h->num_levels) {
        if (count)
            *count = 0;
        return NULL;
    }
    if (count)
        *count = h->levels[level].num_splits;
    return h->levels[level].splits;
}

const uint32_t *sk_hierarchy_vertex_map(const sk_hierarchy *h, size_t level)
{
    if (!h || level + 1 >= h->num_levels)
        return NULL;
    return h->levels[level].fine_to_coarse;
}

sk_status sk_hierarchy_split(const sk_hierarchy *h, size_t level, sk_mesh *m, sk_error *err)
{
    if (!h || !m || level + 1 >= h->num_levels)
        return sk__fail(err, SK_ERR_ARG, "no level %zu to split from", level);
    const sk__level *L = &h->levels[level];
    size_t nc = L->vertices, nf = h->levels[level + 1].vertices, ns = L->num_splits;
    if (m->num_vertices != nc || m->num_deleted_vertices || m->num_faces != L->faces ||
        m->num_deleted_faces)
        return sk__fail(err, SK_ERR_ARG, "the mesh is not level %zu (%zu vertices, %zu faces; the "
                        "level has %zu and %zu)", level, m->num_vertices, m->num_faces, nc, L->faces);
    /* room for the finest level at once: one reallocation for the whole walk up (pages that are
       never touched cost nothing) */
    const sk__level *F = &h->levels[h->num_levels - 1];
    size_t need_v = nc + ns, need_h = m->num_halfedges + 6 * ns, need_f = m->num_faces + 2 * ns;
    sk_status st = SK_OK;
    if (m->cap_vertices < need_v || m->cap_halfedges < need_h || m->cap_faces < need_f) {
        st = sk_mesh_reserve(m, need_v > F->vertices ? need_v : F->vertices,
                             need_h > F->halfedges ? need_h : F->halfedges,
                             need_f > F->faces ? need_f : F->faces, err);
        if (st)
            return st;
        sk__mesh_huge_hint(m); /* the grown, untouched tails */
    }
    for (size_t j = ns; j-- > 0;)
        if (sk__vertex_split(m, &L->splits[j]) == SK_INVALID)
            return sk__fail(err, SK_ERR_TOPOLOGY, "vertex split %zu of level %zu does not fit the "
                            "mesh", j, level);
    uint32_t *newid = sk__alloc_huge(nf, sizeof(uint32_t));
    if (!newid)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t f = 0; f < nf; ++f)
        if (L->fine_to_coarse[f] != SK_INVALID)
            newid[L->fine_to_coarse[f]] = (uint32_t)f;
    for (size_t t = 0; t < ns; ++t) /* appended in reverse record order */
        newid[nc + t] = L->splits[ns - 1 - t].v;
    st = sk__permute_vertices(m, newid, err);
    sk__free(newid);
    return st;
}

sk_status sk_hierarchy_level_mesh(const sk_hierarchy *h, size_t level, sk_mesh **out,
                                  sk_error *err)
{
    *out = NULL;
    if (!h || level >= h->num_levels)
        return sk__fail(err, SK_ERR_ARG, "no level %zu", level);
    sk_mesh *m = NULL;
    sk_status st = sk_mesh_copy(h->coarsest, &m, err);
    for (size_t i = 0; st == SK_OK && i < level; ++i)
        st = sk_hierarchy_split(h, i, m, err);
    if (st)
        sk_mesh_destroy(&m);
    *out = m;
    return st;
}

sk_status sk_hierarchy_prolong(const sk_hierarchy *h, size_t level, const double *coarse,
                               size_t dim, double *fine, sk_error *err)
{
    if (!h || level + 1 >= h->num_levels || !coarse || !fine || dim == 0)
        return sk__fail(err, SK_ERR_ARG, "bad arguments to sk_hierarchy_prolong (level %zu)", level);
    const sk__level *L = &h->levels[level];
    size_t nf = h->levels[level + 1].vertices;
    for (size_t f = 0; f < nf; ++f) {
        uint32_t c = L->fine_to_coarse[f];
        if (c != SK_INVALID)
            memcpy(fine + dim * f, coarse + dim * (size_t)c, dim * sizeof(double));
    }
    for (size_t j = 0; j < L->num_splits; ++j) {
        const sk_vertex_split *s = &L->splits[j];
        const double *a = coarse + dim * (size_t)s->parent[0], *b = coarse + dim * (size_t)s->parent[1],
                     *c = coarse + dim * (size_t)s->parent[2];
        double *t = fine + dim * (size_t)s->v;
        for (size_t k = 0; k < dim; ++k) /* section 3: p = rho p0 + sigma p_i + tau p_i+1 */
            t[k] = s->bary[0] * a[k] + s->bary[1] * b[k] + s->bary[2] * c[k];
    }
    return SK_OK;
}
