/* Indexed-face soup: growable arrays filled by the readers. */
#include "surfkit/mesh.h"
#include "core/internal.h"

#include <stdlib.h>
#include <string.h>

sk_status sk_soup_create(size_t reserve_vertices, size_t reserve_faces, size_t reserve_indices,
                         bool has_normals, bool has_uvs, sk_soup **out, sk_error *err)
{
    *out = NULL;
    sk_soup *s = sk__calloc_array(1, sizeof *s);
    if (!s)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    s->cap_vertices = reserve_vertices ? reserve_vertices : 16;
    s->cap_faces = reserve_faces ? reserve_faces : 16;
    s->cap_indices = reserve_indices ? reserve_indices : 3 * s->cap_faces;
    s->positions = sk__malloc_array(s->cap_vertices, 3 * sizeof(double));
    s->face_offsets = sk__malloc_array(s->cap_faces + 1, sizeof(uint32_t));
    s->face_indices = sk__malloc_array(s->cap_indices, sizeof(uint32_t));
    if (has_normals)
        s->normals = sk__malloc_array(s->cap_vertices, 3 * sizeof(double));
    if (has_uvs)
        s->uvs = sk__malloc_array(s->cap_vertices, 2 * sizeof(double));
    if (!s->positions || !s->face_offsets || !s->face_indices || (has_normals && !s->normals) ||
        (has_uvs && !s->uvs)) {
        sk_soup_destroy(&s);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory reserving %zu vertices and %zu faces",
                        reserve_vertices, reserve_faces);
    }
    s->face_offsets[0] = 0;
    *out = s;
    return SK_OK;
}

void sk_soup_destroy(sk_soup **soup)
{
    if (!soup || !*soup)
        return;
    sk_soup *s = *soup;
    sk__free(s->positions);
    sk__free(s->normals);
    sk__free(s->uvs);
    sk__free(s->face_offsets);
    sk__free(s->face_indices);
    sk__free(s->wedge_uvs);
    sk__free(s->wedge_normals);
    sk__free(s->corner_uv);
    sk__free(s->corner_normal);
    sk__free(s);
    *soup = NULL;
}

static sk_status grow_vertices(sk_soup *s, size_t need)
{
    if (need <= s->cap_vertices)
        return SK_OK;
    size_t cap = s->cap_vertices * 2 > need ? s->cap_vertices * 2 : need;
    double *p = sk__realloc_array(s->positions, cap, 3 * sizeof(double));
    if (!p)
        return SK_ERR_NOMEM;
    s->positions = p;
    if (s->normals) {
        double *n = sk__realloc_array(s->normals, cap, 3 * sizeof(double));
        if (!n)
            return SK_ERR_NOMEM;
        s->normals = n;
    }
    if (s->uvs) {
        double *t = sk__realloc_array(s->uvs, cap, 2 * sizeof(double));
        if (!t)
            return SK_ERR_NOMEM;
        s->uvs = t;
    }
    s->cap_vertices = cap;
    return SK_OK;
}

sk_status sk_soup_push_vertex(sk_soup *s, const double pos[3], const double normal[3],
                              const double uv[2])
{
    if (s->num_vertices >= UINT32_MAX - 1)
        return SK_ERR_ARG;
    sk_status st = grow_vertices(s, s->num_vertices + 1);
    if (st)
        return st;
    size_t v = s->num_vertices++;
    memcpy(s->positions + 3 * v, pos, 3 * sizeof(double));
    if (s->normals) {
        if (normal)
            memcpy(s->normals + 3 * v, normal, 3 * sizeof(double));
        else
            memset(s->normals + 3 * v, 0, 3 * sizeof(double));
    }
    if (s->uvs) {
        if (uv)
            memcpy(s->uvs + 2 * v, uv, 2 * sizeof(double));
        else
            memset(s->uvs + 2 * v, 0, 2 * sizeof(double));
    }
    return SK_OK;
}

sk_status sk_soup_push_face(sk_soup *s, const uint32_t *indices, size_t n)
{
    size_t used = s->face_offsets[s->num_faces];
    if (n > UINT32_MAX - used || s->num_faces >= UINT32_MAX - 1)
        return SK_ERR_ARG;
    if (s->num_faces + 1 > s->cap_faces) {
        size_t cap = s->cap_faces * 2;
        uint32_t *o = sk__realloc_array(s->face_offsets, cap + 1, sizeof(uint32_t));
        if (!o)
            return SK_ERR_NOMEM;
        s->face_offsets = o;
        s->cap_faces = cap;
    }
    if (used + n > s->cap_indices) {
        size_t cap = s->cap_indices * 2 > used + n ? s->cap_indices * 2 : used + n;
        uint32_t *ix = sk__realloc_array(s->face_indices, cap, sizeof(uint32_t));
        if (!ix)
            return SK_ERR_NOMEM;
        s->face_indices = ix;
        s->cap_indices = cap;
    }
    if (n)
        memcpy(s->face_indices + used, indices, n * sizeof(uint32_t));
    s->face_offsets[++s->num_faces] = (uint32_t)(used + n);
    return SK_OK;
}

sk_status sk_soup_add_normals(sk_soup *s)
{
    if (s->normals)
        return SK_OK;
    s->normals = sk__calloc_array(s->cap_vertices, 3 * sizeof(double));
    return s->normals ? SK_OK : SK_ERR_NOMEM;
}

sk_status sk_soup_add_uvs(sk_soup *s)
{
    if (s->uvs)
        return SK_OK;
    s->uvs = sk__calloc_array(s->cap_vertices, 2 * sizeof(double));
    return s->uvs ? SK_OK : SK_ERR_NOMEM;
}

static sk_status set_corner(sk_soup *s, size_t dim, size_t n, const double *values,
                            const uint32_t *corner, size_t *num, double **vals, uint32_t **idx)
{
    size_t nc = s->face_offsets[s->num_faces];
    if (!values || !corner) {
        sk__free(*vals);
        sk__free(*idx);
        *vals = NULL;
        *idx = NULL;
        *num = 0;
        return SK_OK;
    }
    for (size_t c = 0; c < nc; ++c)
        if (corner[c] != SK_INVALID && corner[c] >= n)
            return SK_ERR_ARG;
    double *v = sk__malloc_array(n ? n : 1, dim * sizeof(double));
    uint32_t *i = sk__malloc_array(nc ? nc : 1, sizeof(uint32_t));
    if (!v || !i) {
        sk__free(v);
        sk__free(i);
        return SK_ERR_NOMEM;
    }
    memcpy(v, values, n * dim * sizeof(double));
    memcpy(i, corner, nc * sizeof(uint32_t));
    sk__free(*vals);
    sk__free(*idx);
    *vals = v;
    *idx = i;
    *num = n;
    return SK_OK;
}

sk_status sk_soup_set_corner_uvs(sk_soup *s, size_t n, const double *values,
                                 const uint32_t *corner)
{
    return set_corner(s, 2, n, values, corner, &s->num_wedge_uvs, &s->wedge_uvs, &s->corner_uv);
}

sk_status sk_soup_set_corner_normals(sk_soup *s, size_t n, const double *values,
                                     const uint32_t *corner)
{
    return set_corner(s, 3, n, values, corner, &s->num_wedge_normals, &s->wedge_normals,
                      &s->corner_normal);
}
