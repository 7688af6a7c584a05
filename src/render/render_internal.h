/* Pieces shared by the pictures: an orthographic view fitted to a point set, a z-buffered
 * triangle rasterizer into a cairo image, the colour ramp, and the atomic PNG writer. */
#ifndef SK_RENDER_INTERNAL_H
#define SK_RENDER_INTERNAL_H

#include "surfkit/render.h"

#include <cairo.h>
#include <stdint.h>

/* Orthographic camera looking along d, x right and y up on the screen. */
typedef struct sk__view {
    double d[3], x[3], y[3];
    double scale, ox, oy; /* screen = (ox + scale * (p.x), oy - scale * (p.y)) */
    int w, h;
} sk__view;

/* Fits the view (direction dir, or fallback when dir is zero) so that the n points fill the
 * fraction `fill` of a w x h picture, centred. */
void sk__view_fit(sk__view *v, const double dir[3], const double fallback[3], const double *pos,
                  size_t n, int w, int h, double fill);
/* Screen x, y and depth (along d, larger is farther) of p. */
void sk__view_project(const sk__view *v, const double p[3], double s[3]);

/* A picture being drawn: a cairo image with a depth buffer. */
typedef struct sk__raster {
    cairo_surface_t *surf;
    unsigned char *data;
    int stride, w, h;
    float *z;
} sk__raster;

/* White picture, depth infinitely far. SK_ERR_NOMEM when out of memory. */
sk_status sk__raster_create(sk__raster *r, int w, int h, sk_error *err);
void sk__raster_destroy(sk__raster *r);

/* Colour of pixel (px, py) of triangle id at barycentric coordinates b (rgb in [0, 1]). */
typedef void (*sk__shade_fn)(void *user, uint32_t id, const double b[3], int px, int py,
                             double rgb[3]);
/* Fills the pixels whose centres lie in the screen triangle s (x, y, depth per corner) and are
 * nearer than what is drawn there. Degenerate screen triangles draw nothing. */
void sk__raster_triangle(sk__raster *r, double s[3][3], uint32_t id, sk__shade_fn fn,
                         void *user);

/* Blue - green - yellow - red colour scale for t in [0, 1] (magenta is kept for flips and
 * out-of-scale values). */
void sk__ramp(double t, double rgb[3]);

/* A colour bar of the ramp (top = 1) with its frame, 22 px wide, at (x, y), h high. */
void sk__ramp_bar(cairo_t *cr, double x, double y, double h);

/* cairo write callback into a FILE * (the closure). */
cairo_status_t sk__cairo_write_fp(void *closure, const unsigned char *data, unsigned int length);

/* Writes surf as PNG to path through the atomic writer; destroys surf. */
sk_status sk__write_png(cairo_surface_t *surf, const char *path, sk_error *err);

#endif
