/* The viewer page (view.h): the template viewer/viewer.html with the data (base64 arrays in a
 * JSON block), the app viewer/viewer.js and three.js filled in. The assets are compiled in from
 * a file generated at build time (viewer/embed.c); without them the library has no viewer. */
#include "surfkit/view.h"
#include "surfkit/deviation.h"
#include "core/internal.h"
#include "mesh/fan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(SK_HAVE_VIEWER)
extern const char sk__asset_template[], sk__asset_app[], sk__asset_three_core[],
    sk__asset_three_module[];
extern const size_t sk__asset_template_size, sk__asset_app_size, sk__asset_three_core_size,
    sk__asset_three_module_size;
#endif

bool sk_view_available(void)
{
#if defined(SK_HAVE_VIEWER)
    return true;
#else
    return false;
#endif
}

#if defined(SK_HAVE_VIEWER)
/* Base64 of n bytes, straight to fp. */
static void put_base64(FILE *fp, const void *data, size_t n)
{
    static const char A[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const unsigned char *p = data;
    char buf[4096];
    size_t k = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)p[i] << 16;
        if (i + 1 < n)
            v |= (unsigned)p[i + 1] << 8;
        if (i + 2 < n)
            v |= p[i + 2];
        buf[k++] = A[(v >> 18) & 63];
        buf[k++] = A[(v >> 12) & 63];
        buf[k++] = i + 1 < n ? A[(v >> 6) & 63] : '=';
        buf[k++] = i + 2 < n ? A[v & 63] : '=';
        if (k + 4 > sizeof buf) {
            fwrite(buf, 1, k, fp);
            k = 0;
        }
    }
    fwrite(buf, 1, k, fp);
}

/* A JSON string; '<' is escaped so that no "</script" can end the data block. */
static void put_json_string(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (; s && *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(fp, "\\%c", c);
        else if (c < 32 || c == '<' || c == '>' || c == '&')
            fprintf(fp, "\\u%04x", c);
        else
            fputc(c, fp);
    }
    fputc('"', fp);
}

static void put_floats(FILE *fp, const char *key, const float *v, size_t n)
{
    fprintf(fp, "\"%s\":\"", key);
    put_base64(fp, v, n * sizeof *v);
    fputs("\"", fp);
}

/* Arrays of one surface: float positions (and normals) and uint32 triangles (fans). */
typedef struct arrays {
    float *pos, *nrm, *uv, *dist, *lines;
    uint32_t *tri;
    size_t nv, nt, nlines;
} arrays;

static void arrays_free(arrays *a)
{
    sk__free(a->pos);
    sk__free(a->nrm);
    sk__free(a->uv);
    sk__free(a->dist);
    sk__free(a->lines);
    sk__free(a->tri);
}

static sk_status from_mesh(const sk_mesh *m, const double *uv, arrays *a, sk_error *err)
{
    a->nv = m->num_vertices;
    sk_status st = sk__mesh_fan_triangles(m, &a->tri, NULL, &a->nt, err);
    if (st)
        return st;
    a->pos = sk__malloc_array(3 * a->nv + 1, sizeof *a->pos);
    a->uv = uv ? sk__malloc_array(2 * a->nv + 1, sizeof *a->uv) : NULL;
    if (!a->pos || (uv && !a->uv))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < 3 * a->nv; ++i)
        a->pos[i] = (float)m->positions[i];
    for (size_t i = 0; uv && i < 2 * a->nv; ++i)
        a->uv[i] = (float)uv[i];
    return SK_OK;
}

/* The tessellated smooth surface, its distance to the mesh, and its patch boundary curves. */
static sk_status from_smooth(const sk_smooth *s, const sk_mesh *mesh, unsigned n, arrays *a,
                             double *top, sk_error *err)
{
    sk_soup *soup = NULL, *ms = NULL;
    sk_bvh *bvh = NULL;
    const sk_patch_set *set = &s->surface;
    sk_status st = sk_patch_set_tessellate(set, n, &soup, err);
    if (!st)
        st = sk_mesh_to_soup(mesh, &ms, err);
    if (!st)
        st = sk_bvh_build(ms, &bvh, err);
    if (st)
        goto done;
    a->nv = soup->num_vertices;
    a->nt = soup->num_faces;
    size_t nseg = 0;
    for (size_t p = 0; p < set->count; ++p)
        nseg += (size_t)sk_patch_num_corners(&set->patches[p]) * 2 * n;
    a->pos = sk__malloc_array(3 * a->nv + 1, sizeof *a->pos);
    a->nrm = sk__malloc_array(3 * a->nv + 1, sizeof *a->nrm);
    a->dist = sk__malloc_array(a->nv + 1, sizeof *a->dist);
    a->tri = sk__malloc_array(3 * a->nt + 1, sizeof *a->tri);
    a->lines = sk__malloc_array(6 * nseg + 1, sizeof *a->lines);
    if (!a->pos || !a->nrm || !a->dist || !a->tri || !a->lines) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    *top = 0;
    for (size_t v = 0; v < a->nv; ++v) {
        sk_closest c;
        sk_bvh_closest(bvh, soup->positions + 3 * v, &c);
        a->dist[v] = (float)c.distance;
        *top = fmax(*top, c.distance);
        for (int k = 0; k < 3; ++k) {
            a->pos[3 * v + k] = (float)soup->positions[3 * v + k];
            a->nrm[3 * v + k] = (float)soup->normals[3 * v + k];
        }
    }
    for (size_t t = 0; t < a->nt; ++t) /* the tessellation is all triangles */
        for (int k = 0; k < 3; ++k)
            a->tri[3 * t + k] = soup->face_indices[soup->face_offsets[t] + (size_t)k];
    /* patch edges as 2n segments each */
    for (size_t p = 0; p < set->count; ++p)
        for (unsigned e = 0; e < sk_patch_num_corners(&set->patches[p]); ++e)
            for (unsigned i = 0; i < 2 * n; ++i, ++a->nlines)
                for (unsigned end = 0; end < 2; ++end) {
                    double q[3];
                    sk_patch_edge_point(set, p, e, (double)(i + end) / (2.0 * n), q);
                    for (int k = 0; k < 3; ++k)
                        a->lines[6 * a->nlines + 3 * end + (size_t)k] = (float)q[k];
                }
done:
    sk_bvh_destroy(&bvh);
    sk_soup_destroy(&soup);
    sk_soup_destroy(&ms);
    return st;
}

static void put_data(FILE *fp, const arrays *m, const arrays *s, double scale,
                     const sk_view_opts *o)
{
    fputs("{\"title\":", fp);
    put_json_string(fp, o->title ? o->title : "surfkit view");
    fputs(",\"info\":", fp);
    put_json_string(fp, o->info ? o->info : "");
    fputs(",\"mesh\":{", fp);
    put_floats(fp, "positions", m->pos, 3 * m->nv);
    fputs(",\"triangles\":\"", fp);
    put_base64(fp, m->tri, 3 * m->nt * sizeof *m->tri);
    fputs("\"", fp);
    if (m->uv) {
        fputs(",", fp);
        put_floats(fp, "uv", m->uv, 2 * m->nv);
    }
    fputs("}", fp);
    if (s->pos) {
        fputs(",\"surface\":{", fp);
        put_floats(fp, "positions", s->pos, 3 * s->nv);
        fputs(",", fp);
        put_floats(fp, "normals", s->nrm, 3 * s->nv);
        fputs(",\"triangles\":\"", fp);
        put_base64(fp, s->tri, 3 * s->nt * sizeof *s->tri);
        fputs("\",", fp);
        put_floats(fp, "distance", s->dist, s->nv);
        fprintf(fp, ",\"distance_scale\":%.9g,", scale > 0 ? scale : 1.0);
        put_floats(fp, "boundaries", s->lines, 6 * s->nlines);
        fputs("}", fp);
    }
    fputs("}", fp);
}

/* Writes the template with its markers @DATA@, @THREE_CORE@, @THREE_MODULE@, @APP@ filled. */
static void put_page(FILE *fp, const arrays *m, const arrays *s, double scale,
                     const sk_view_opts *o)
{
    const char *t = sk__asset_template, *end = t + sk__asset_template_size;
    while (t < end) {
        const char *at = memchr(t, '@', (size_t)(end - t));
        if (!at) {
            fwrite(t, 1, (size_t)(end - t), fp);
            break;
        }
        fwrite(t, 1, (size_t)(at - t), fp);
        size_t left = (size_t)(end - at);
#define MARK(s) (left >= sizeof(s) - 1 && !memcmp(at, s, sizeof(s) - 1) && (t = at + sizeof(s) - 1))
        if (MARK("@DATA@"))
            put_data(fp, m, s, scale, o);
        else if (MARK("@THREE_CORE@"))
            fwrite(sk__asset_three_core, 1, sk__asset_three_core_size, fp);
        else if (MARK("@THREE_MODULE@"))
            fwrite(sk__asset_three_module, 1, sk__asset_three_module_size, fp);
        else if (MARK("@APP@"))
            fwrite(sk__asset_app, 1, sk__asset_app_size, fp);
        else {
            fputc('@', fp);
            t = at + 1;
        }
#undef MARK
    }
}

sk_status sk_view_write(const sk_mesh *mesh, const double *uv, const sk_smooth *smooth,
                        const sk_view_opts *opts, const char *path, sk_error *err)
{
    sk_view_opts o = {0};
    if (opts)
        o = *opts;
    unsigned n = o.tess ? o.tess : 8;
    arrays m = {0}, s = {0};
    double top = 0;
    sk_status st = from_mesh(mesh, uv, &m, err);
    if (!st && smooth)
        st = from_smooth(smooth, mesh, n, &s, &top, err);
    sk__atomic_file af;
    if (!st)
        st = sk__atomic_open(&af, path, err);
    if (!st) {
        put_page(af.fp, &m, &s, o.deviation_scale > 0 ? o.deviation_scale : top, &o);
        st = sk__atomic_commit(&af, err);
    }
    arrays_free(&m);
    arrays_free(&s);
    return st;
}
#else
sk_status sk_view_write(const sk_mesh *mesh, const double *uv, const sk_smooth *smooth,
                        const sk_view_opts *opts, const char *path, sk_error *err)
{
    (void)mesh, (void)uv, (void)smooth, (void)opts, (void)path;
    return sk__fail(err, SK_ERR_ARG,
                    "this surfkit was built without the viewer (three.js was not found; "
                    "scripts/setup.sh fetches it)");
}
#endif
