/* The field map: a surface shaded by its interpolated vertex normals and coloured per pixel by a
 * scalar field at the surface point the pixel shows (a deferred pass: the rasterizer records the
 * point and the shade of the nearest surface at each pixel, the field is evaluated once per
 * covered pixel afterwards). */
#include "render/render_internal.h"
#include "core/internal.h"
#include "core/vec.h"
#include "mesh/fan.h"

#include <math.h>
#include <stdlib.h>

enum { LEGEND_W = 200 };

typedef struct gbuffer {
    const sk_soup *soup;
    const uint32_t *tri; /* 3 per fan triangle */
    const double *normal;
    double light[3];
    int w;
    double *point; /* 3 per pixel */
    float *shade;  /* per pixel; negative where no surface */
} gbuffer;

static void record(void *user, uint32_t id, const double b[3], int px, int py, double rgb[3])
{
    gbuffer *g = user;
    const uint32_t *t = g->tri + 3 * (size_t)id;
    double n[3] = {0, 0, 0}, p[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        sk__axpy3(n, n, b[k], g->normal + 3 * (size_t)t[k]);
        sk__axpy3(p, p, b[k], g->soup->positions + 3 * (size_t)t[k]);
    }
    sk__normalize3(n);
    size_t i = (size_t)py * (size_t)g->w + (size_t)px;
    for (int k = 0; k < 3; ++k)
        g->point[3 * i + k] = p[k];
    g->shade[i] = (float)(0.3 + 0.7 * fabs(sk__dot3(n, g->light)));
    rgb[0] = rgb[1] = rgb[2] = 0.5; /* replaced in the colour pass */
}

/* Fan triangles and area-weighted vertex normals of the soup. */
static sk_status prepare(const sk_soup *s, uint32_t **tri_out, size_t *nt_out, double **nrm_out,
                         sk_error *err)
{
    size_t nt = 0;
    for (size_t f = 0; f < s->num_faces; ++f)
        for (size_t c = 0, m = sk_soup_face_size(s, f); c < m; ++c)
            if (s->face_indices[s->face_offsets[f] + c] >= s->num_vertices)
                return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has an index out of range", f);
    uint32_t *tri = NULL;
    sk_status st = sk__soup_fan_triangles(s, &tri, NULL, &nt, err);
    if (st)
        return st;
    double *nrm = sk__calloc_array(3 * s->num_vertices + 3, sizeof *nrm);
    if (!nrm) {
        sk__free(tri);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *v = tri + 3 * t;
        double e1[3], e2[3], n[3];
        sk__sub3(e1, s->positions + 3 * (size_t)v[1], s->positions + 3 * (size_t)v[0]);
        sk__sub3(e2, s->positions + 3 * (size_t)v[2], s->positions + 3 * (size_t)v[0]);
        sk__cross3(n, e1, e2);
        for (int k = 0; k < 3; ++k)
            sk__add3(nrm + 3 * (size_t)v[k], nrm + 3 * (size_t)v[k], n);
    }
    *tri_out = tri;
    *nt_out = nt;
    *nrm_out = nrm;
    return SK_OK;
}

static void draw_legend(cairo_t *cr, int x0, int top, int h, double scale, bool beyond,
                        const char *label, const char *title)
{
    double lx = x0 + 30, ly = top + 10, lh = h * 0.6;
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 12);
    sk__ramp_bar(cr, lx, ly, lh);
    for (int i = 0; i <= 4; ++i) {
        char buf[40];
        snprintf(buf, sizeof buf, "%.3g", scale * i / 4.0);
        cairo_move_to(cr, lx + 26, ly + lh * (1.0 - i / 4.0) + 4);
        cairo_show_text(cr, buf);
    }
    cairo_move_to(cr, lx - 20, ly + lh + 22);
    cairo_show_text(cr, label ? label : "value");
    if (beyond) {
        cairo_set_source_rgb(cr, 1, 0, 1);
        cairo_rectangle(cr, lx, ly + lh + 36, 22, 14);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, lx + 26, ly + lh + 48);
        cairo_show_text(cr, "beyond the scale");
    }
    if (title) {
        cairo_set_font_size(cr, 15);
        cairo_move_to(cr, 12, 22);
        cairo_show_text(cr, title);
    }
}

/* Evaluates the field at every covered pixel (values into g->point's first slot reused as a
 * separate array) and returns the largest value. */
static double evaluate(const gbuffer *g, size_t npix, sk_field_fn field, void *user, double *val)
{
    double top = 0;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 2048) reduction(max : top)
#endif
    for (ptrdiff_t i = 0; i < (ptrdiff_t)npix; ++i) {
        val[i] = g->shade[i] < 0 ? 0 : field(user, g->point + 3 * (size_t)i);
        if (g->shade[i] >= 0 && val[i] > top)
            top = val[i];
    }
    return top;
}

static void colour(sk__raster *r, const gbuffer *g, const double *val, double scale, int w)
{
    for (int j = 0; j < r->h; ++j) {
        uint32_t *row = (uint32_t *)(r->data + (size_t)j * r->stride);
        for (int i = 0; i < w; ++i) {
            size_t k = (size_t)j * (size_t)w + (size_t)i;
            if (g->shade[k] < 0)
                continue;
            double rgb[3], sh = g->shade[k];
            if (!(val[k] <= scale * (1 + 1e-9)))
                rgb[0] = 1, rgb[1] = 0, rgb[2] = 1;
            else
                sk__ramp(val[k] / scale, rgb);
            uint32_t R = (uint32_t)(255 * rgb[0] * sh), G = (uint32_t)(255 * rgb[1] * sh),
                     B = (uint32_t)(255 * rgb[2] * sh);
            row[i] = (R << 16) | (G << 8) | B;
        }
    }
}

sk_status sk_render_field(const sk_soup *soup, sk_field_fn field, void *user, double scale,
                          const char *label, const char *path, const sk_render_opts *opts,
                          sk_error *err)
{
    sk_render_opts o = {0};
    if (opts)
        o = *opts;
    int W = o.width > 0 ? o.width : 1024;
    uint32_t *tri = NULL;
    double *nrm = NULL, *val = NULL;
    size_t nt = 0, npix = (size_t)W * (size_t)W;
    gbuffer g = {0};
    sk__raster r = {0};
    sk_status st = prepare(soup, &tri, &nt, &nrm, err);
    if (st)
        return st;
    g.point = sk__malloc_array(3 * npix, sizeof *g.point);
    g.shade = sk__malloc_array(npix, sizeof *g.shade);
    val = sk__malloc_array(npix, sizeof *val);
    if (!g.point || !g.shade || !val) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for a %d x %d picture", W, W);
        goto done;
    }
    st = sk__raster_create(&r, W, W, err);
    if (st)
        goto done;
    sk__view view;
    const double fallback[3] = {0, 0, -1};
    sk__view_fit(&view, o.view, fallback, soup->positions, soup->num_vertices, W, W, 0.92);
    g.soup = soup, g.tri = tri, g.normal = nrm, g.w = W;
    for (int k = 0; k < 3; ++k) /* a light from the viewer, a little from the upper left */
        g.light[k] = view.d[k] - 0.4 * view.y[k] + 0.3 * view.x[k];
    sk__normalize3(g.light);
    for (size_t i = 0; i < npix; ++i)
        g.shade[i] = -1;
    for (size_t t = 0; t < nt; ++t) {
        double s[3][3];
        for (int k = 0; k < 3; ++k)
            sk__view_project(&view, soup->positions + 3 * (size_t)tri[3 * t + k], s[k]);
        sk__raster_triangle(&r, s, (uint32_t)t, record, &g);
    }
    double top = evaluate(&g, npix, field, user, val);
    bool beyond = scale > 0 && top > scale * (1 + 1e-9);
    if (!(scale > 0))
        scale = top > 0 ? top : 1;
    sk__raster_destroy(&r); /* a wider picture with room for the legend */
    st = sk__raster_create(&r, W + LEGEND_W, W, err);
    if (st)
        goto done;
    colour(&r, &g, val, scale, W);
    cairo_surface_mark_dirty(r.surf);
    cairo_t *cr = cairo_create(r.surf);
    draw_legend(cr, W, o.title ? 40 : 16, W, scale, beyond, label, o.title);
    cairo_destroy(cr);
    st = sk__write_png(r.surf, path, err);
    r.surf = NULL; /* destroyed by the writer */
done:
    sk__raster_destroy(&r);
    sk__free(g.point);
    sk__free(g.shade);
    sk__free(val);
    sk__free(tri);
    sk__free(nrm);
    return st;
}
