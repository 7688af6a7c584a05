/* Pictures of smooth surfaces (cairo, PNG): the triangle/quad configuration after edge deletion and
 * flat-shaded views of triangle soups. Orthographic projection along a fixed view direction,
 * back faces culled, faces painted far to near. */
#include "render/render_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <cairo.h>
#include <stdlib.h>

typedef struct view {
    double f[3], r[3], u[3];
    double scale, ox, oy, cx, cy;
    int w, h;
} view;

static void view_setup(view *v, const sk_render_opts *o, const double *pos, size_t n)
{
    v->w = o && o->width ? (int)o->width : 900;
    v->h = o && o->height ? (int)o->height : 900;
    double d[3] = {-0.4, -0.5, -1.0};
    if (o && (o->view[0] != 0 || o->view[1] != 0 || o->view[2] != 0))
        d[0] = o->view[0], d[1] = o->view[1], d[2] = o->view[2];
    sk__normalize3(d);
    v->f[0] = d[0], v->f[1] = d[1], v->f[2] = d[2];
    double up[3] = {0, 1, 0};
    if (fabs(d[1]) > 0.9)
        up[1] = 0, up[2] = 1;
    sk__cross3(v->r, v->f, up);
    sk__normalize3(v->r);
    sk__cross3(v->u, v->r, v->f);
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (size_t i = 0; i < n; ++i) {
        double x = sk__dot3(pos + 3 * i, v->r), y = sk__dot3(pos + 3 * i, v->u);
        lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
        lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
    }
    double sx = (hi[0] - lo[0]) > 0 ? (v->w * 0.9) / (hi[0] - lo[0]) : 1.0;
    double sy = (hi[1] - lo[1]) > 0 ? (v->h * 0.9) / (hi[1] - lo[1]) : 1.0;
    v->scale = fmin(sx, sy);
    v->cx = 0.5 * (lo[0] + hi[0]);
    v->cy = 0.5 * (lo[1] + hi[1]);
}

static void project(const view *v, const double p[3], double *x, double *y)
{
    *x = v->w * 0.5 + (sk__dot3(p, v->r) - v->cx) * v->scale;
    *y = v->h * 0.5 - (sk__dot3(p, v->u) - v->cy) * v->scale;
}

typedef struct item {
    double depth;
    uint32_t id;
} item;

static int item_cmp(const void *a, const void *b)
{
    const item *x = a, *y = b;
    return (x->depth < y->depth) - (x->depth > y->depth); /* far (large depth) first */
}

/* through the atomic writer, as render.h promises (cairo_surface_write_to_png wrote in place) */
static sk_status finish(cairo_surface_t *surf, cairo_t *cr, const char *path, sk_error *err)
{
    cairo_destroy(cr);
    return sk__write_png(surf, path, err);
}

sk_status sk_render_patch_layout(const sk_smooth *s, const char *png_path,
                                 const sk_render_opts *opts, sk_error *err)
{
    const sk_mesh *m = s->config;
    view v;
    view_setup(&v, opts, m->positions, m->num_vertices);
    item *items = sk__malloc_array(m->num_faces + 1, sizeof *items);
    if (!items)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t ni = 0;
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        double n[3];
        sk_mesh_face_normal(m, f, n);
        if (sk__dot3(n, v.f) >= 0.0)
            continue;
        const double *p = m->positions + 3 * (size_t)sk_from(m, m->f_halfedge[f]);
        items[ni++] = (item){sk__dot3(p, v.f), f};
    }
    qsort(items, ni, sizeof *items, item_cmp);
    cairo_surface_t *surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, v.w, v.h);
    cairo_t *cr = cairo_create(surf);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_set_line_width(cr, m->num_faces > 20000 ? 0.2 : 0.6);
    for (size_t i = 0; i < ni; ++i) {
        uint32_t f = items[i].id, h0 = m->f_halfedge[f], h = h0;
        double n[3];
        sk_mesh_face_normal(m, f, n);
        double shade = 0.35 + 0.65 * fmax(0.0, -sk__dot3(n, v.f));
        int quad = sk_mesh_face_size(m, f) == 4;
        do {
            double x, y;
            project(&v, m->positions + 3 * (size_t)sk_from(m, h), &x, &y);
            if (h == h0)
                cairo_move_to(cr, x, y);
            else
                cairo_line_to(cr, x, y);
            h = m->h_next[h];
        } while (h != h0);
        cairo_close_path(cr);
        if (quad)
            cairo_set_source_rgb(cr, 0.45 * shade, 0.65 * shade, 1.0 * shade);
        else
            cairo_set_source_rgb(cr, 0.85 * shade, 0.85 * shade, 0.85 * shade);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
        cairo_stroke(cr);
    }
    /* deleted edges (red), drawn when both end points face the viewer */
    cairo_set_source_rgb(cr, 0.85, 0.05, 0.05);
    cairo_set_line_width(cr, m->num_faces > 20000 ? 0.4 : 1.2);
    for (size_t i = 0; i < s->num_deleted; ++i) {
        const double *a = m->positions + 3 * (size_t)s->deleted[2 * i];
        const double *b = m->positions + 3 * (size_t)s->deleted[2 * i + 1];
        const double *na = s->normals + 3 * (size_t)s->deleted[2 * i];
        if (sk__dot3(na, v.f) >= 0.0)
            continue;
        double x0, y0, x1, y1;
        project(&v, a, &x0, &y0);
        project(&v, b, &x1, &y1);
        cairo_move_to(cr, x0, y0);
        cairo_line_to(cr, x1, y1);
        cairo_stroke(cr);
    }
    /* problem vertices */
    cairo_set_source_rgb(cr, 1.0, 0.5, 0.0);
    for (size_t i = 0; i < s->num_problems; ++i) {
        double x, y;
        project(&v, m->positions + 3 * (size_t)s->problems[i], &x, &y);
        cairo_arc(cr, x, y, 4.0, 0, 2 * M_PI);
        cairo_fill(cr);
    }
    sk__free(items);
    return finish(surf, cr, png_path, err);
}

sk_status sk_render_shaded(const sk_soup *soup, const char *png_path, const sk_render_opts *opts,
                           sk_error *err)
{
    view v;
    view_setup(&v, opts, soup->positions, soup->num_vertices);
    item *items = sk__malloc_array(soup->num_faces + 1, sizeof *items);
    if (!items)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t ni = 0;
    for (uint32_t f = 0; f < soup->num_faces; ++f) {
        if (sk_soup_face_size(soup, f) != 3)
            continue;
        const uint32_t *t = soup->face_indices + soup->face_offsets[f];
        const double *a = soup->positions + 3 * (size_t)t[0], *b = soup->positions + 3 * (size_t)t[1],
                     *c = soup->positions + 3 * (size_t)t[2];
        double e1[3], e2[3], n[3];
        sk__sub3(e1, b, a);
        sk__sub3(e2, c, a);
        sk__cross3(n, e1, e2);
        if (sk__dot3(n, v.f) >= 0.0)
            continue;
        items[ni++] = (item){(sk__dot3(a, v.f) + sk__dot3(b, v.f) + sk__dot3(c, v.f)) / 3.0, f};
    }
    qsort(items, ni, sizeof *items, item_cmp);
    cairo_surface_t *surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, v.w, v.h);
    cairo_t *cr = cairo_create(surf);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
    /* light travelling from the upper left of the viewer into the scene */
    double light[3];
    for (int k = 0; k < 3; ++k)
        light[k] = v.f[k] - 0.5 * v.u[k] + 0.3 * v.r[k];
    sk__normalize3(light);
    for (size_t i = 0; i < ni; ++i) {
        const uint32_t *t = soup->face_indices + soup->face_offsets[items[i].id];
        double n[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            double x, y;
            project(&v, soup->positions + 3 * (size_t)t[k], &x, &y);
            if (k == 0)
                cairo_move_to(cr, x, y);
            else
                cairo_line_to(cr, x, y);
            if (soup->normals)
                sk__add3(n, n, soup->normals + 3 * (size_t)t[k]);
        }
        cairo_close_path(cr);
        sk__normalize3(n);
        /* headlight-ish diffuse + a little specular, from the (smooth) vertex normals */
        double l = fmax(0.0, -sk__dot3(n, light));
        double sh = 0.12 + 0.78 * l + 0.25 * pow(l, 40.0);
        sh = fmin(sh, 1.0);
        cairo_set_source_rgb(cr, 0.75 * sh, 0.8 * sh, 0.95 * sh);
        cairo_fill_preserve(cr);
        cairo_set_line_width(cr, 0.5);
        cairo_stroke(cr);
    }
    sk__free(items);
    return finish(surf, cr, png_path, err);
}
