/* The shared picture pieces: view fitting, a z-buffered rasterizer, the colour ramp, PNG output
 * (render_internal.h). */
#include "render/render_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>

void sk__view_fit(sk__view *v, const double dir[3], const double fallback[3], const double *pos,
                  size_t n, int w, int h, double fill)
{
    double d[3] = {dir[0], dir[1], dir[2]};
    if (!(sk__normalize3(d) > 0)) {
        d[0] = fallback[0], d[1] = fallback[1], d[2] = fallback[2];
        sk__normalize3(d);
    }
    double up[3] = {0, 1, 0};
    if (fabs(d[1]) > 0.9)
        up[1] = 0, up[2] = 1;
    for (int k = 0; k < 3; ++k)
        v->d[k] = d[k];
    sk__cross3(v->x, d, up);
    sk__normalize3(v->x);
    sk__cross3(v->y, v->x, d);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < n; ++i) {
        double px = sk__dot3(pos + 3 * i, v->x), py = sk__dot3(pos + 3 * i, v->y);
        lo[0] = fmin(lo[0], px), hi[0] = fmax(hi[0], px);
        lo[1] = fmin(lo[1], py), hi[1] = fmax(hi[1], py);
    }
    double sx = hi[0] > lo[0] ? fill * w / (hi[0] - lo[0]) : 1.0;
    double sy = hi[1] > lo[1] ? fill * h / (hi[1] - lo[1]) : 1.0;
    v->scale = fmin(sx, sy);
    v->w = w, v->h = h;
    v->ox = 0.5 * w - v->scale * 0.5 * (lo[0] + hi[0]);
    v->oy = 0.5 * h + v->scale * 0.5 * (lo[1] + hi[1]);
}

void sk__view_project(const sk__view *v, const double p[3], double s[3])
{
    s[0] = v->ox + v->scale * sk__dot3(p, v->x);
    s[1] = v->oy - v->scale * sk__dot3(p, v->y);
    s[2] = sk__dot3(p, v->d);
}

sk_status sk__raster_create(sk__raster *r, int w, int h, sk_error *err)
{
    r->w = w, r->h = h;
    r->surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    r->z = sk__malloc_array((size_t)w * (size_t)h, sizeof *r->z);
    if (cairo_surface_status(r->surf) != CAIRO_STATUS_SUCCESS || !r->z) {
        sk__raster_destroy(r);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %d x %d picture", w, h);
    }
    cairo_surface_flush(r->surf);
    r->data = cairo_image_surface_get_data(r->surf);
    r->stride = cairo_image_surface_get_stride(r->surf);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            ((uint32_t *)(r->data + (size_t)j * r->stride))[i] = 0xffffffu;
            r->z[(size_t)j * w + i] = INFINITY;
        }
    return SK_OK;
}

void sk__raster_destroy(sk__raster *r)
{
    if (r->surf)
        cairo_surface_destroy(r->surf);
    sk__free(r->z);
    r->surf = NULL;
    r->z = NULL;
    r->data = NULL;
}

void sk__raster_triangle(sk__raster *r, double s[3][3], uint32_t id, sk__shade_fn fn,
                         void *user)
{
    double area = (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[2][0] - s[0][0]) * (s[1][1] - s[0][1]);
    if (!(fabs(area) > 1e-12))
        return;
    double xmin = fmin(s[0][0], fmin(s[1][0], s[2][0])), xmax = fmax(s[0][0], fmax(s[1][0], s[2][0]));
    double ymin = fmin(s[0][1], fmin(s[1][1], s[2][1])), ymax = fmax(s[0][1], fmax(s[1][1], s[2][1]));
    if (xmax < 0 || ymax < 0 || xmin > r->w || ymin > r->h)
        return;
    int i0 = (int)fmax(0, floor(xmin)), i1 = (int)fmin(r->w - 1, ceil(xmax));
    int j0 = (int)fmax(0, floor(ymin)), j1 = (int)fmin(r->h - 1, ceil(ymax));
    for (int j = j0; j <= j1; ++j) {
        uint32_t *row = (uint32_t *)(r->data + (size_t)j * r->stride);
        for (int i = i0; i <= i1; ++i) {
            double px = i + 0.5, py = j + 0.5, b[3];
            b[0] = ((s[1][0] - px) * (s[2][1] - py) - (s[2][0] - px) * (s[1][1] - py)) / area;
            b[1] = ((s[2][0] - px) * (s[0][1] - py) - (s[0][0] - px) * (s[2][1] - py)) / area;
            b[2] = 1 - b[0] - b[1];
            if (b[0] < 0 || b[1] < 0 || b[2] < 0)
                continue;
            float z = (float)(b[0] * s[0][2] + b[1] * s[1][2] + b[2] * s[2][2]);
            if (z >= r->z[(size_t)j * r->w + i])
                continue;
            r->z[(size_t)j * r->w + i] = z;
            double rgb[3];
            fn(user, id, b, i, j, rgb);
            uint32_t R = (uint32_t)(255 * fmin(fmax(rgb[0], 0), 1)),
                     G = (uint32_t)(255 * fmin(fmax(rgb[1], 0), 1)),
                     B = (uint32_t)(255 * fmin(fmax(rgb[2], 0), 1));
            row[i] = (R << 16) | (G << 8) | B;
        }
    }
}

void sk__ramp(double t, double rgb[3])
{
    static const double stops[5][3] = {
        {0.23, 0.30, 0.75}, {0.35, 0.70, 0.90}, {0.55, 0.80, 0.40}, {0.98, 0.80, 0.20},
        {0.80, 0.10, 0.10}};
    t = fmin(fmax(t, 0.0), 1.0) * 4.0;
    int i = (int)t;
    if (i > 3)
        i = 3;
    double s = t - i;
    for (int c = 0; c < 3; ++c)
        rgb[c] = (1 - s) * stops[i][c] + s * stops[i + 1][c];
}

void sk__ramp_bar(cairo_t *cr, double x, double y, double h)
{
    for (int i = 0; i < 100; ++i) {
        double rgb[3];
        sk__ramp(1.0 - (i + 0.5) / 100.0, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        cairo_rectangle(cr, x, y + h * i / 100.0, 22, h / 100.0 + 0.6);
        cairo_fill(cr);
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, x, y, 22, h);
    cairo_stroke(cr);
}

cairo_status_t sk__cairo_write_fp(void *closure, const unsigned char *data, unsigned int length)
{
    return fwrite(data, 1, length, (FILE *)closure) == length ? CAIRO_STATUS_SUCCESS
                                                              : CAIRO_STATUS_WRITE_ERROR;
}

sk_status sk__write_png(cairo_surface_t *surf, const char *path, sk_error *err)
{
    sk__atomic_file af;
    sk_status st = sk__atomic_open(&af, path, err);
    if (st) {
        cairo_surface_destroy(surf);
        return st;
    }
    cairo_status_t cs = cairo_surface_write_to_png_stream(surf, sk__cairo_write_fp, af.fp);
    cairo_surface_destroy(surf);
    if (cs != CAIRO_STATUS_SUCCESS) {
        sk__atomic_abort(&af);
        return sk__fail(err, SK_ERR_IO, "%s: cairo could not write the picture: %s",
                        sk__basename(path), cairo_status_to_string(cs));
    }
    return sk__atomic_commit(&af, err);
}
