/* Fan triangulation of soup and mesh faces (mesh/fan.h). */
#include "mesh/fan.h"
#include "core/internal.h"

#include <stdint.h>

/* Allocates room for nt triangles (and their faces when wanted). */
static sk_status fan_alloc(size_t nt, uint32_t **tri, uint32_t **face, sk_error *err)
{
    *tri = NULL;
    if (face)
        *face = NULL;
    if (nt >= UINT32_MAX / 2)
        return sk__fail(err, SK_ERR_ARG, "too many triangles (%zu)", nt);
    *tri = sk__malloc_array(3 * nt + 3, sizeof **tri);
    if (face)
        *face = sk__malloc_array(nt + 1, sizeof **face);
    if (!*tri || (face && !*face)) {
        sk__free(*tri);
        *tri = NULL;
        if (face) {
            sk__free(*face);
            *face = NULL;
        }
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    return SK_OK;
}

sk_status sk__soup_fan_triangles(const sk_soup *s, uint32_t **tri, uint32_t **face, size_t *nt,
                                 sk_error *err)
{
    size_t n = 0;
    for (size_t f = 0; f < s->num_faces; ++f) {
        size_t m = sk_soup_face_size(s, f);
        n += m >= 3 ? m - 2 : 0;
    }
    sk_status st = fan_alloc(n, tri, face, err);
    if (st)
        return st;
    size_t t = 0;
    for (size_t f = 0; f < s->num_faces; ++f) {
        const uint32_t *idx = s->face_indices + s->face_offsets[f];
        size_t m = sk_soup_face_size(s, f);
        for (size_t c = 1; c + 1 < m; ++c, ++t) {
            (*tri)[3 * t] = idx[0];
            (*tri)[3 * t + 1] = idx[c];
            (*tri)[3 * t + 2] = idx[c + 1];
            if (face)
                (*face)[t] = (uint32_t)f;
        }
    }
    *nt = n;
    return SK_OK;
}

sk_status sk__mesh_fan_triangles(const sk_mesh *m, uint32_t **tri, uint32_t **face, size_t *nt,
                                 sk_error *err)
{
    size_t n = 0;
    for (size_t f = 0; f < m->num_faces; ++f)
        if (!m->f_deleted[f])
            n += sk_mesh_face_size(m, (uint32_t)f) - 2;
    sk_status st = fan_alloc(n, tri, face, err);
    if (st)
        return st;
    size_t t = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h0 = m->f_halfedge[f], h = m->h_next[h0], v0 = sk_from(m, h0);
        for (; m->h_next[h] != h0; h = m->h_next[h], ++t) {
            (*tri)[3 * t] = v0;
            (*tri)[3 * t + 1] = sk_from(m, h);
            (*tri)[3 * t + 2] = sk_to(m, h);
            if (face)
                (*face)[t] = (uint32_t)f;
        }
    }
    *nt = n;
    return SK_OK;
}
