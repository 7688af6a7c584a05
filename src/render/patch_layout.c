/* Pictures of smooth surfaces (cairo, PNG): the triangle/quad configuration after edge deletion and
 * flat-shaded views of triangle soups. Orthographic projection along a fixed view direction,
 * back faces culled, faces painted far to near. */
#include "render/render_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <cairo.h>
#include <stdlib.h>

/* The one camera of the pictures (sk__view_fit, raster.c), 900 x 900 unless opts say otherwise. */
static void view_setup(sk__view *v, const sk_render_opts *o, const double *pos, size_t n)
{
    const double zero[3] = {0, 0, 0}, fallback[3] = {-0.4, -0.5, -1.0};
    int w = o && o->width ? (int)o->width : 900, h = o && o->height ? (int)o->height : 900;
    sk__view_fit(v, o ? o->view : zero, fallback, pos, n, w, h, 0.9);
}

static void project(const sk__view *v, const double p[3], double *x, double *y)
{
    double s[3];
    sk__view_project(v, p, s);
    *x = s[0];
    *y = s[1];
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
    sk__view v;
    view_setup(&v, opts, m->positions, m->num_vertices);
    item *items = sk__malloc_array(m->num_faces + 1, sizeof *items);
    if (!items)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t ni = 0;
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        double n[3];
        sk_mesh_face_normal(m, f, n);
        if (sk__dot3(n, v.d) >= 0.0)
            continue;
        const double *p = m->positions + 3 * (size_t)sk_from(m, m->f_halfedge[f]);
        items[ni++] = (item){sk__dot3(p, v.d), f};
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
        double shade = 0.35 + 0.65 * fmax(0.0, -sk__dot3(n, v.d));
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
        if (sk__dot3(na, v.d) >= 0.0)
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
    sk__view v;
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
        if (sk__dot3(n, v.d) >= 0.0)
            continue;
        items[ni++] = (item){(sk__dot3(a, v.d) + sk__dot3(b, v.d) + sk__dot3(c, v.d)) / 3.0, f};
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
        light[k] = v.d[k] - 0.5 * v.y[k] + 0.3 * v.x[k];
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
