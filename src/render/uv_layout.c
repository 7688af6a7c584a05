/* UV layout pictures with cairo. */
#include "render/render_internal.h"
#include "surfkit/param.h"
#include "core/internal.h"
#include "core/vec.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const double FLIP_RGB[3] = {1.0, 0.0, 1.0}; /* magenta */


/* the uv -> pixel map of the plot: x = ox + s u, y = oy - s v (v up) */
typedef struct uv_frame {
    double ox, oy, s;
} uv_frame;

static double px(const uv_frame *fr, const double *q) { return fr->ox + fr->s * q[0]; }
static double py(const uv_frame *fr, const double *q) { return fr->oy - fr->s * q[1]; }

/* bounding box of the live faces' uv, their count and the flipped ones among them */
static void layout_bounds(const sk_mesh *m, const double *uv, const int8_t *orient, double lo[2],
                          double hi[2], size_t *nalive, size_t *nflip)
{
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    *nalive = *nflip = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        ++*nalive;
        if (orient[f] <= 0)
            ++*nflip;
        uint32_t h = m->f_halfedge[f];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            const double *q = uv + 2 * (size_t)sk_from(m, h);
            for (int c = 0; c < 2; ++c) {
                lo[c] = fmin(lo[c], q[c]);
                hi[c] = fmax(hi[c], q[c]);
            }
        }
    }
}

/* the triangles coloured by sigma1/sigma2 (log scale up to exp(logmax)); flipped ones last, on
 * top, in the flip colour with a ring so that even a sliver is seen */
static void draw_triangles(cairo_t *cr, const sk_mesh *m, const double *uv, const double *conf,
                           const int8_t *orient, const uv_frame *fr, bool draw_edges,
                           double logmax)
{
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t f = 0; f < m->num_faces; ++f) {
            if (m->f_deleted[f] || (pass == 0) != (orient[f] > 0))
                continue;
            uint32_t h = m->f_halfedge[f];
            const double *q[3];
            for (int k = 0; k < 3; ++k, h = m->h_next[h])
                q[k] = uv + 2 * (size_t)sk_from(m, h);
            cairo_move_to(cr, px(fr, q[0]), py(fr, q[0]));
            cairo_line_to(cr, px(fr, q[1]), py(fr, q[1]));
            cairo_line_to(cr, px(fr, q[2]), py(fr, q[2]));
            cairo_close_path(cr);
            if (pass == 0) {
                double rgb[3];
                sk__ramp(log(fmax(conf[f], 1.0)) / logmax, rgb);
                cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
                cairo_fill_preserve(cr);
                if (draw_edges) {
                    cairo_set_source_rgba(cr, 0.15, 0.15, 0.15, 0.6);
                    cairo_set_line_width(cr, 0.35);
                } else { /* a hairline of the fill colour closes the antialiasing seams */
                    cairo_set_line_width(cr, 0.5);
                }
                cairo_stroke(cr);
                continue;
            }
            cairo_set_source_rgb(cr, FLIP_RGB[0], FLIP_RGB[1], FLIP_RGB[2]);
            cairo_fill_preserve(cr);
            cairo_set_line_width(cr, 3.0);
            cairo_stroke(cr);
            double cx = (px(fr, q[0]) + px(fr, q[1]) + px(fr, q[2])) / 3,
                   cy = (py(fr, q[0]) + py(fr, q[1]) + py(fr, q[2])) / 3;
            cairo_new_path(cr);
            cairo_arc(cr, cx, cy, 8.0, 0, 2 * M_PI);
            cairo_set_line_width(cr, 2.0);
            cairo_stroke(cr);
        }
    }
}

static void draw_boundary(cairo_t *cr, const sk_mesh *m, const double *uv, const uv_frame *fr)
{
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.2);
    for (size_t h = 0; h < m->num_halfedges; ++h) {
        if (m->e_deleted[h >> 1] || !sk_is_boundary_h(m, (uint32_t)h))
            continue;
        const double *a = uv + 2 * (size_t)sk_from(m, (uint32_t)h),
                     *b = uv + 2 * (size_t)sk_to(m, (uint32_t)h);
        cairo_move_to(cr, px(fr, a), py(fr, a));
        cairo_line_to(cr, px(fr, b), py(fr, b));
    }
    cairo_stroke(cr);
}

/* the colour bar of sigma1/sigma2 at (lx, ly), lh high, and the flipped count below it */
static void draw_legend(cairo_t *cr, double lx, double ly, double lh, double logmax,
                        size_t nflip)
{
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 12);
    sk__ramp_bar(cr, lx, ly, lh);
    for (int i = 0; i <= 4; ++i) {
        double val = exp(logmax * i / 4.0);
        double y = ly + lh * (1.0 - i / 4.0);
        char buf[32];
        snprintf(buf, sizeof buf, i == 4 ? ">= %.2f" : "%.2f", val);
        cairo_move_to(cr, lx + 26, y + 4);
        cairo_show_text(cr, buf);
    }
    cairo_move_to(cr, lx - 14, ly + lh + 22);
    cairo_show_text(cr, "sigma1 / sigma2");
    cairo_set_source_rgb(cr, FLIP_RGB[0], FLIP_RGB[1], FLIP_RGB[2]);
    cairo_rectangle(cr, lx, ly + lh + 36, 22, 14);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    char fb[48];
    snprintf(fb, sizeof fb, "flipped: %zu", nflip);
    cairo_move_to(cr, lx + 26, ly + lh + 48);
    cairo_show_text(cr, fb);
}

sk_status sk_render_uv(const sk_mesh *m, const double *uv, const char *path,
                       const sk_render_opts *opts, sk_error *err)
{
    sk_render_opts o = {0};
    if (opts)
        o = *opts;
    int width = o.width > 0 ? o.width : 1024;
    double cmax = o.conformal_max > 1 ? o.conformal_max : 4.0;
    bool svg = sk_path_has_ext(path, ".svg");
    if (!svg && !sk_path_has_ext(path, ".png"))
        return sk__fail(err, SK_ERR_ARG, "%s: pictures are .png or .svg", sk__basename(path));
    size_t nf = m->num_faces;
    double *conf = sk__malloc_array(nf ? nf : 1, sizeof *conf);
    int8_t *orient = sk__malloc_array(nf ? nf : 1, 1);
    if (!conf || !orient) {
        sk__free(conf);
        sk__free(orient);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    sk_param_face_distortion(m, uv, conf, orient, NULL);
    double lo[2], hi[2];
    size_t nflip, nalive;
    layout_bounds(m, uv, orient, lo, hi, &nalive, &nflip);
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(span > 0) || !isfinite(span))
        span = 1;
    int legend_w = 150, top = o.title ? 40 : 16, margin = 16;
    int plot = width - legend_w - 2 * margin;
    if (plot < 64)
        plot = 64;
    int height = top + plot + margin;
    int total_w = plot + legend_w + 2 * margin;
    uv_frame fr;
    fr.s = plot / span;
    fr.ox = margin + 0.5 * (plot - fr.s * (hi[0] - lo[0])) - fr.s * lo[0];
    fr.oy = top + plot - 0.5 * (plot - fr.s * (hi[1] - lo[1])) + fr.s * lo[1];
    sk__atomic_file af;
    sk_status st = sk__atomic_open(&af, path, err);
    if (st) {
        sk__free(conf);
        sk__free(orient);
        return st;
    }
    cairo_surface_t *surf = svg ? cairo_svg_surface_create_for_stream(sk__cairo_write_fp, af.fp, total_w, height)
                                : cairo_image_surface_create(CAIRO_FORMAT_ARGB32, total_w, height);
    cairo_t *cr = cairo_create(surf);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    bool draw_edges = o.edges > 0 || (o.edges == 0 && nalive <= 100000);
    double logmax = log(cmax);
    draw_triangles(cr, m, uv, conf, orient, &fr, draw_edges, logmax);
    draw_boundary(cr, m, uv, &fr);
    draw_legend(cr, margin + plot + 30, top + 10, plot * 0.6, logmax, nflip);
    if (o.title) {
        cairo_set_font_size(cr, 15);
        cairo_move_to(cr, margin, 26);
        cairo_show_text(cr, o.title);
    }
    cairo_destroy(cr);
    cairo_status_t cs;
    if (svg) {
        cairo_surface_finish(surf);
        cs = cairo_surface_status(surf);
    } else {
        cs = cairo_surface_write_to_png_stream(surf, sk__cairo_write_fp, af.fp);
    }
    cairo_surface_destroy(surf);
    sk__free(conf);
    sk__free(orient);
    if (cs != CAIRO_STATUS_SUCCESS) {
        sk__atomic_abort(&af);
        return sk__fail(err, SK_ERR_IO, "%s: cairo could not write the picture: %s",
                        sk__basename(path), cairo_status_to_string(cs));
    }
    return sk__atomic_commit(&af, err);
}
