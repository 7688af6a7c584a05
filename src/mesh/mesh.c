/* Half-edge mesh storage: allocation, growth, copying, compaction, invariant checks. */
#include "surfkit/mesh.h"
#include "core/internal.h"
#include "mesh/mesh_internal.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* The arrays of a mesh sized by its capacities, one row each: sk_mesh_reserve grows them,
 * sk_mesh_copy copies the required ones, sk_mesh_destroy frees them all. An optional array
 * (normals, uvs, corner wedges) is grown only when the mesh has it. */
typedef enum { PER_VERTEX, PER_HALFEDGE, PER_EDGE, PER_FACE } per_element;

typedef struct mesh_array {
    size_t offset; /* of the array's pointer in sk_mesh */
    size_t size;   /* bytes per element */
    per_element per;
    bool optional;
} mesh_array;

#define ARRAY(field, size, per, optional) {offsetof(sk_mesh, field), size, per, optional}
static const mesh_array mesh_arrays[] = {
    ARRAY(positions, 3 * sizeof(double), PER_VERTEX, false),
    ARRAY(normals, 3 * sizeof(double), PER_VERTEX, true),
    ARRAY(uvs, 2 * sizeof(double), PER_VERTEX, true),
    ARRAY(v_halfedge, sizeof(uint32_t), PER_VERTEX, false),
    ARRAY(v_deleted, 1, PER_VERTEX, false),
    ARRAY(h_vertex, sizeof(uint32_t), PER_HALFEDGE, false),
    ARRAY(h_next, sizeof(uint32_t), PER_HALFEDGE, false),
    ARRAY(h_prev, sizeof(uint32_t), PER_HALFEDGE, false),
    ARRAY(h_face, sizeof(uint32_t), PER_HALFEDGE, false),
    ARRAY(h_wedge_uv, sizeof(uint32_t), PER_HALFEDGE, true),
    ARRAY(h_wedge_normal, sizeof(uint32_t), PER_HALFEDGE, true),
    ARRAY(e_deleted, 1, PER_EDGE, false),
    ARRAY(f_halfedge, sizeof(uint32_t), PER_FACE, false),
    ARRAY(f_deleted, 1, PER_FACE, false),
};
#undef ARRAY
#define NUM_MESH_ARRAYS (sizeof mesh_arrays / sizeof mesh_arrays[0])

static void **array_ptr(sk_mesh *m, const mesh_array *a)
{
    return (void **)((char *)m + a->offset);
}

static const void *array_of(const sk_mesh *m, const mesh_array *a)
{
    const void *p;
    memcpy(&p, (const char *)m + a->offset, sizeof p);
    return p;
}

/* Elements of an array of this kind for these vertex, half-edge and face counts. */
static size_t array_len(per_element per, size_t nv, size_t nh, size_t nf)
{
    return per == PER_VERTEX ? nv : per == PER_FACE ? nf : per == PER_EDGE ? nh / 2 : nh;
}

sk_status sk_mesh_reserve(sk_mesh *m, size_t nv, size_t nh, size_t nf, sk_error *err)
{
    nh += nh & 1u;
    if (nv > UINT32_MAX - 1 || nh > UINT32_MAX - 1 || nf > UINT32_MAX - 1)
        return sk__fail(err, SK_ERR_ARG, "mesh too large for 32-bit indices");
    /* each capacity that is too small grows by half, or to what is needed */
    size_t cv = m->cap_vertices, ch = m->cap_halfedges, cf = m->cap_faces;
    if (nv > cv)
        cv = cv * 3 / 2 > nv ? cv * 3 / 2 : nv;
    if (nh > ch) {
        ch = ch * 3 / 2 > nh ? ch * 3 / 2 : nh;
        ch += ch & 1u;
    }
    if (nf > cf)
        cf = cf * 3 / 2 > nf ? cf * 3 / 2 : nf;
    for (size_t k = 0; k < NUM_MESH_ARRAYS; ++k) {
        const mesh_array *a = &mesh_arrays[k];
        void **p = array_ptr(m, a);
        size_t len = array_len(a->per, cv, ch, cf);
        if ((a->optional && !*p) ||
            len == array_len(a->per, m->cap_vertices, m->cap_halfedges, m->cap_faces))
            continue;
        void *q = sk__realloc_array(*p, len, a->size);
        if (!q) /* the arrays grown so far keep their room; the capacities stay */
            return sk__fail(err, SK_ERR_NOMEM, "out of memory growing the mesh");
        *p = q;
    }
    m->cap_vertices = cv;
    m->cap_halfedges = ch;
    m->cap_faces = cf;
    return SK_OK;
}

sk_mesh *sk__mesh_alloc(size_t nv, size_t nh, size_t nf, sk_error *err)
{
    sk_mesh *m = sk__calloc_array(1, sizeof *m);
    if (!m) {
        sk__fail(err, SK_ERR_NOMEM, "out of memory");
        return NULL;
    }
    if (sk_mesh_reserve(m, nv ? nv : 1, nh ? nh : 2, nf ? nf : 1, err) != SK_OK) {
        sk_mesh_destroy(&m);
        return NULL;
    }
    return m;
}

void sk_mesh_destroy(sk_mesh **mesh)
{
    if (!mesh || !*mesh)
        return;
    sk_mesh *m = *mesh;
    for (size_t k = 0; k < NUM_MESH_ARRAYS; ++k)
        sk__free(*array_ptr(m, &mesh_arrays[k]));
    sk__free(m->wedge_uvs);
    sk__free(m->wedge_normals);
    sk__free(m);
    *mesh = NULL;
}

sk_status sk_mesh_add_normals(sk_mesh *m, sk_error *err)
{
    if (m->normals)
        return SK_OK;
    m->normals = sk__calloc_array(m->cap_vertices, 3 * sizeof(double));
    return m->normals ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
}

sk_status sk_mesh_add_uvs(sk_mesh *m, sk_error *err)
{
    if (m->uvs)
        return SK_OK;
    m->uvs = sk__calloc_array(m->cap_vertices, 2 * sizeof(double));
    return m->uvs ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
}

sk_status sk__mesh_set_attributes(sk_mesh *m, const double *normals, const double *uvs,
                                  sk_error *err)
{
    sk_status st = SK_OK;
    if ((normals && (st = sk_mesh_add_normals(m, err))) || (uvs && (st = sk_mesh_add_uvs(m, err))))
        return st;
    if (normals)
        memcpy(m->normals, normals, m->num_vertices * 3 * sizeof(double));
    if (uvs)
        memcpy(m->uvs, uvs, m->num_vertices * 2 * sizeof(double));
    return SK_OK;
}

uint32_t sk_mesh_new_vertex(sk_mesh *m, const double pos[3])
{
    if (sk_mesh_reserve(m, m->num_vertices + 1, m->num_halfedges, m->num_faces, NULL) != SK_OK)
        return SK_INVALID;
    uint32_t v = (uint32_t)m->num_vertices++;
    memcpy(m->positions + 3 * (size_t)v, pos, 3 * sizeof(double));
    if (m->normals)
        memset(m->normals + 3 * (size_t)v, 0, 3 * sizeof(double));
    if (m->uvs)
        memset(m->uvs + 2 * (size_t)v, 0, 2 * sizeof(double));
    m->v_halfedge[v] = SK_INVALID;
    m->v_deleted[v] = 0;
    return v;
}

uint32_t sk_mesh_new_edge(sk_mesh *m)
{
    if (sk_mesh_reserve(m, m->num_vertices, m->num_halfedges + 2, m->num_faces, NULL) != SK_OK)
        return SK_INVALID;
    uint32_t h = (uint32_t)m->num_halfedges;
    m->num_halfedges += 2;
    for (uint32_t i = h; i < h + 2; ++i) {
        m->h_vertex[i] = m->h_next[i] = m->h_prev[i] = m->h_face[i] = SK_INVALID;
        if (m->h_wedge_uv)
            m->h_wedge_uv[i] = SK_INVALID;
        if (m->h_wedge_normal)
            m->h_wedge_normal[i] = SK_INVALID;
    }
    m->e_deleted[h / 2] = 0;
    return h;
}

uint32_t sk_mesh_new_face(sk_mesh *m)
{
    if (sk_mesh_reserve(m, m->num_vertices, m->num_halfedges, m->num_faces + 1, NULL) != SK_OK)
        return SK_INVALID;
    uint32_t f = (uint32_t)m->num_faces++;
    m->f_halfedge[f] = SK_INVALID;
    m->f_deleted[f] = 0;
    return f;
}

sk_status sk_mesh_copy(const sk_mesh *src, sk_mesh **out, sk_error *err)
{
    *out = NULL;
    sk_mesh *m = sk__mesh_alloc(src->num_vertices, src->num_halfedges, src->num_faces, err);
    if (!m)
        return SK_ERR_NOMEM;
    size_t nv = src->num_vertices, nh = src->num_halfedges, nf = src->num_faces;
    m->num_vertices = nv;
    m->num_halfedges = nh;
    m->num_faces = nf;
    if (sk__mesh_set_attributes(m, src->normals, src->uvs, err)) {
        sk_mesh_destroy(&m);
        return SK_ERR_NOMEM;
    }
    for (size_t k = 0; k < NUM_MESH_ARRAYS; ++k) {
        const mesh_array *a = &mesh_arrays[k];
        if (!a->optional)
            memcpy(*array_ptr(m, a), array_of(src, a), array_len(a->per, nv, nh, nf) * a->size);
    }
    m->num_deleted_vertices = src->num_deleted_vertices;
    m->num_deleted_edges = src->num_deleted_edges;
    m->num_deleted_faces = src->num_deleted_faces;
    if ((src->h_wedge_uv &&
         sk_mesh_set_wedge_uvs(m, src->num_wedge_uvs, src->wedge_uvs, src->h_wedge_uv, err)) ||
        (src->h_wedge_normal &&
         sk_mesh_set_wedge_normals(m, src->num_wedge_normals, src->wedge_normals,
                                   src->h_wedge_normal, err))) {
        sk_mesh_destroy(&m);
        return SK_ERR_NOMEM;
    }
    *out = m;
    return SK_OK;
}

/* per-corner values of dim doubles (uvs, normals) into *num, *vals, *idx */
static sk_status set_wedges(sk_mesh *m, size_t dim, size_t n, const double *values,
                            const uint32_t *h_wedge, size_t *num, double **vals, uint32_t **idx,
                            sk_error *err)
{
    if (!values || !h_wedge) {
        sk__free(*vals);
        sk__free(*idx);
        *vals = NULL;
        *idx = NULL;
        *num = 0;
        return SK_OK;
    }
    for (size_t h = 0; h < m->num_halfedges; ++h)
        if (h_wedge[h] != SK_INVALID && h_wedge[h] >= n)
            return sk__fail(err, SK_ERR_ARG, "half-edge %zu has wedge %u of %zu", h,
                            (unsigned)h_wedge[h], n);
    double *v = sk__malloc_array(n ? n : 1, dim * sizeof(double));
    uint32_t *i = sk__malloc_array(m->cap_halfedges ? m->cap_halfedges : 1, sizeof(uint32_t));
    if (!v || !i) {
        sk__free(v);
        sk__free(i);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memcpy(v, values, dim * n * sizeof(double));
    memcpy(i, h_wedge, m->num_halfedges * sizeof(uint32_t));
    sk__free(*vals);
    sk__free(*idx);
    *vals = v;
    *idx = i;
    *num = n;
    return SK_OK;
}

sk_status sk_mesh_set_wedge_uvs(sk_mesh *m, size_t n, const double *values,
                                const uint32_t *h_wedge, sk_error *err)
{
    return set_wedges(m, 2, n, values, h_wedge, &m->num_wedge_uvs, &m->wedge_uvs, &m->h_wedge_uv,
                      err);
}

sk_status sk_mesh_set_wedge_normals(sk_mesh *m, size_t n, const double *values,
                                    const uint32_t *h_wedge, sk_error *err)
{
    return set_wedges(m, 3, n, values, h_wedge, &m->num_wedge_normals, &m->wedge_normals,
                      &m->h_wedge_normal, err);
}

size_t sk_mesh_valence(const sk_mesh *m, uint32_t v)
{
    uint32_t h0 = m->v_halfedge[v], h = h0;
    size_t n = 0;
    if (h0 == SK_INVALID)
        return 0;
    do {
        ++n;
        h = sk_cw_out(m, h);
    } while (h != h0);
    return n;
}

size_t sk_mesh_face_size(const sk_mesh *m, uint32_t f)
{
    uint32_t h0 = m->f_halfedge[f], h = h0;
    size_t n = 0;
    do {
        ++n;
        h = m->h_next[h];
    } while (h != h0);
    return n;
}

static uint32_t remap(const uint32_t *map, uint32_t i)
{
    return i == SK_INVALID ? SK_INVALID : map[i];
}

sk_status sk_mesh_compact(sk_mesh *m, uint32_t *vmap_out, uint32_t *fmap_out, sk_error *err)
{
    size_t nv = m->num_vertices, nh = m->num_halfedges, nf = m->num_faces;
    uint32_t *vmap = sk__malloc_array(nv, sizeof(uint32_t));
    uint32_t *hmap = sk__malloc_array(nh, sizeof(uint32_t));
    uint32_t *fmap = sk__malloc_array(nf, sizeof(uint32_t));
    if (!vmap || !hmap || !fmap) {
        sk__free(vmap);
        sk__free(hmap);
        sk__free(fmap);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory compacting the mesh");
    }
    uint32_t k = 0;
    for (size_t v = 0; v < nv; ++v)
        vmap[v] = m->v_deleted[v] ? SK_INVALID : k++;
    size_t nv2 = k;
    k = 0;
    for (size_t e = 0; e < nh / 2; ++e) {
        if (m->e_deleted[e]) {
            hmap[2 * e] = hmap[2 * e + 1] = SK_INVALID;
        } else {
            hmap[2 * e] = k;
            hmap[2 * e + 1] = k + 1;
            k += 2;
        }
    }
    size_t nh2 = k;
    k = 0;
    for (size_t f = 0; f < nf; ++f)
        fmap[f] = m->f_deleted[f] ? SK_INVALID : k++;
    size_t nf2 = k;

    for (size_t v = 0; v < nv; ++v) {
        uint32_t t = vmap[v];
        if (t == SK_INVALID)
            continue;
        memmove(m->positions + 3 * (size_t)t, m->positions + 3 * v, 3 * sizeof(double));
        if (m->normals)
            memmove(m->normals + 3 * (size_t)t, m->normals + 3 * v, 3 * sizeof(double));
        if (m->uvs)
            memmove(m->uvs + 2 * (size_t)t, m->uvs + 2 * v, 2 * sizeof(double));
        m->v_halfedge[t] = remap(hmap, m->v_halfedge[v]);
        m->v_deleted[t] = 0;
    }
    for (size_t h = 0; h < nh; ++h) {
        uint32_t t = hmap[h];
        if (t == SK_INVALID)
            continue;
        m->h_vertex[t] = remap(vmap, m->h_vertex[h]);
        m->h_next[t] = remap(hmap, m->h_next[h]);
        m->h_prev[t] = remap(hmap, m->h_prev[h]);
        m->h_face[t] = remap(fmap, m->h_face[h]);
        if (m->h_wedge_uv)
            m->h_wedge_uv[t] = m->h_wedge_uv[h];
        if (m->h_wedge_normal)
            m->h_wedge_normal[t] = m->h_wedge_normal[h];
        m->e_deleted[t / 2] = 0;
    }
    for (size_t f = 0; f < nf; ++f) {
        uint32_t t = fmap[f];
        if (t == SK_INVALID)
            continue;
        m->f_halfedge[t] = remap(hmap, m->f_halfedge[f]);
        m->f_deleted[t] = 0;
    }
    m->num_vertices = nv2;
    m->num_halfedges = nh2;
    m->num_faces = nf2;
    m->num_deleted_vertices = m->num_deleted_edges = m->num_deleted_faces = 0;
    if (vmap_out)
        memcpy(vmap_out, vmap, nv * sizeof(uint32_t));
    if (fmap_out)
        memcpy(fmap_out, fmap, nf * sizeof(uint32_t));
    sk__free(vmap);
    sk__free(hmap);
    sk__free(fmap);
    return SK_OK;
}

sk_status sk_mesh_check(const sk_mesh *m, sk_error *err)
{
    size_t nv = m->num_vertices, nh = m->num_halfedges, nf = m->num_faces;
    if (nh & 1u)
        return sk__fail(err, SK_ERR_TOPOLOGY, "odd number of half-edges");
    for (size_t h = 0; h < nh; ++h) {
        if (m->e_deleted[h / 2])
            continue;
        uint32_t n = m->h_next[h], p = m->h_prev[h], v = m->h_vertex[h], f = m->h_face[h];
        if (n >= nh || p >= nh || v >= nv)
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu has an invalid link", h);
        if (m->e_deleted[n / 2] || m->e_deleted[p / 2] || m->v_deleted[v])
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu links a deleted element", h);
        if (m->h_prev[n] != h || m->h_next[p] != h)
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu: next/prev are not inverse", h);
        if (m->h_face[n] != f)
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu: next has another face", h);
        if (m->h_vertex[h ^ 1u] == v)
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu is a loop at vertex %u", h, v);
        if (sk_from(m, n) != v)
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu: next does not start at its end", h);
        if (f != SK_INVALID && (f >= nf || m->f_deleted[f]))
            return sk__fail(err, SK_ERR_TOPOLOGY, "half-edge %zu has an invalid face", h);
        if (f == SK_INVALID && m->h_face[h ^ 1u] == SK_INVALID)
            return sk__fail(err, SK_ERR_TOPOLOGY, "edge %zu has no face on either side", h / 2);
    }
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h0 = m->f_halfedge[f], h = h0;
        size_t n = 0;
        if (h0 >= nh || m->h_face[h0] != f)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has an invalid half-edge", f);
        do {
            if (++n > nh)
                return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu does not close", f);
            h = m->h_next[h];
        } while (h != h0);
        if (n < 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has %zu sides", f, n);
    }
    /* each vertex: one fan; its half-edge is a boundary one when it has any */
    size_t *deg = sk__calloc_array(nv, sizeof(size_t));
    if (!deg)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    sk_status st = SK_OK;
    for (size_t h = 0; h < nh; ++h)
        if (!m->e_deleted[h / 2])
            deg[sk_from(m, (uint32_t)h)]++;
    for (size_t v = 0; v < nv && st == SK_OK; ++v) {
        if (m->v_deleted[v])
            continue;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        if (h0 == SK_INVALID) {
            if (deg[v])
                st = sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu has edges but no half-edge", v);
            continue;
        }
        if (h0 >= nh || m->e_deleted[h0 / 2] || sk_from(m, h0) != v) {
            st = sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu has an invalid half-edge", v);
            break;
        }
        size_t n = 0, nb = 0;
        do {
            ++n;
            nb += m->h_face[h] == SK_INVALID;
            h = sk_cw_out(m, h);
        } while (h != h0 && n <= deg[v]);
        if (n != deg[v])
            st = sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu is non-manifold (%zu of %zu edges in "
                          "its fan)", v, n, deg[v]);
        else if (nb > 1 || (nb == 1 && m->h_face[h0] != SK_INVALID))
            st = sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu: bad boundary half-edge", v);
    }
    sk__free(deg);
    return st;
}

sk_status sk_mesh_to_soup(const sk_mesh *m, sk_soup **out, sk_error *err)
{
    *out = NULL;
    size_t nv = m->num_vertices - m->num_deleted_vertices;
    size_t nf = m->num_faces - m->num_deleted_faces;
    sk_soup *s = NULL;
    sk_status st = sk_soup_create(nv, nf, 3 * nf + 1, m->normals != NULL, m->uvs != NULL, &s, err);
    if (st)
        return st;
    uint32_t *vmap = sk__malloc_array(m->num_vertices, sizeof(uint32_t));
    uint32_t buf[64];
    uint32_t *idx = buf, *cw = NULL;
    size_t cap = 64;
    if (!vmap) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    uint32_t k = 0;
    for (size_t v = 0; v < m->num_vertices; ++v) {
        if (m->v_deleted[v]) {
            vmap[v] = SK_INVALID;
            continue;
        }
        vmap[v] = k++;
        if ((st = sk_soup_push_vertex(s, m->positions + 3 * v, m->normals ? m->normals + 3 * v : NULL,
                                      m->uvs ? m->uvs + 2 * v : NULL))) {
            st = sk__fail(err, st, "out of memory");
            goto done;
        }
    }
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        size_t n = sk_mesh_face_size(m, (uint32_t)f);
        if (n > cap) {
            uint32_t *p = sk__malloc_array(n, sizeof(uint32_t));
            if (!p) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                goto done;
            }
            if (idx != buf)
                sk__free(idx);
            idx = p;
            cap = n;
        }
        uint32_t h = m->f_halfedge[f];
        for (size_t i = 0; i < n; ++i) {
            idx[i] = vmap[sk_from(m, h)];
            h = m->h_next[h];
        }
        if ((st = sk_soup_push_face(s, idx, n))) {
            st = sk__fail(err, st, "out of memory");
            goto done;
        }
    }
    if (m->h_wedge_uv) {
        /* corners in the order just pushed: alive faces, half-edges from f_halfedge */
        size_t nc = s->face_offsets[s->num_faces];
        cw = sk__malloc_array(nc ? nc : 1, sizeof(uint32_t));
        if (!cw) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        size_t c = 0;
        for (size_t f = 0; f < m->num_faces; ++f) {
            if (m->f_deleted[f])
                continue;
            uint32_t h0 = m->f_halfedge[f], h = h0;
            do {
                cw[c++] = m->h_wedge_uv[h];
                h = m->h_next[h];
            } while (h != h0);
        }
        if ((st = sk_soup_set_corner_uvs(s, m->num_wedge_uvs, m->wedge_uvs, cw))) {
            st = sk__fail(err, st, "per-corner uvs: %s", st == SK_ERR_NOMEM ? "out of memory"
                                                                            : "index out of range");
            goto done;
        }
    }
    if (m->h_wedge_normal) {
        size_t nc = s->face_offsets[s->num_faces], c = 0;
        sk__free(cw);
        cw = sk__malloc_array(nc ? nc : 1, sizeof(uint32_t));
        if (!cw) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        for (size_t f = 0; f < m->num_faces; ++f) {
            if (m->f_deleted[f])
                continue;
            uint32_t h0 = m->f_halfedge[f], h = h0;
            do {
                cw[c++] = m->h_wedge_normal[h];
                h = m->h_next[h];
            } while (h != h0);
        }
        if ((st = sk_soup_set_corner_normals(s, m->num_wedge_normals, m->wedge_normals, cw))) {
            st = sk__fail(err, st, "per-corner normals: %s",
                          st == SK_ERR_NOMEM ? "out of memory" : "index out of range");
            goto done;
        }
    }
done:
    if (idx != buf)
        sk__free(idx);
    sk__free(cw);
    sk__free(vmap);
    if (st)
        sk_soup_destroy(&s);
    *out = s;
    return st;
}
