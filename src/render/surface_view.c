/* Pictures of a smooth surface from its exact normals (render.h, sk_render_surface): each patch is
 * tessellated finely enough for its silhouette (a few pixels per triangle) and z-buffered; every
 * pixel maps back to the patch parameter it shows, where the patch normal is evaluated, so the
 * shading has no facets. Shaded: diffuse + a little specular. Zebra: reflection lines, stripes
 * of the view direction reflected in the surface against a fixed direction, so a kink of the
 * normal shows as a kink (or a jump) of the stripes. Patch map: patches coloured by kind, those
 * with overshoot > 0.5 or a singular point highlighted, boundaries drawn, with a legend. */
#include "render/render_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TESS 32

typedef struct ctx {
    const sk_smooth *s;
    sk_surface_picture kind;
    const sk__view *view;
    double light[3], stripe_dir[3];
    double par[3][2];       /* the parameters of the corners of the triangle being drawn */
    double edge_eps;        /* patch map: parameter distance of a boundary pixel */
    const uint8_t *cls;     /* patch map: class per patch */
} ctx;

enum { CLS_TRI, CLS_QUAD, CLS_OVERSHOOT, CLS_SINGULAR, CLS_BOTH, NCLS };

static const double cls_rgb[NCLS][3] = {{0.86, 0.86, 0.86}, {0.55, 0.72, 1.0}, {0.95, 0.45, 0.1},
                                        {0.85, 0.1, 0.85}, {0.5, 0.0, 0.15}};
static const char *const cls_name[NCLS] = {"triangle patch", "quad patch", "overshoot > 0.5",
                                           "singular point", "both"};

static void shade(void *user, uint32_t id, const double b[3], int px, int py, double rgb[3])
{
    (void)px, (void)py;
    const ctx *c = user;
    double a = b[0] * c->par[0][0] + b[1] * c->par[1][0] + b[2] * c->par[2][0];
    double t = b[0] * c->par[0][1] + b[1] * c->par[1][1] + b[2] * c->par[2][1];
    double n[3];
    double len = sk_patch_eval(&c->s->surface, id, a, t, NULL, NULL, NULL, n);
    if (!(len > 0)) { /* no tangent plane: a singular point */
        rgb[0] = 1, rgb[1] = 0, rgb[2] = 1;
        return;
    }
    const double *d = c->view->d;
    bool back = sk__dot3(n, d) > 0; /* the back side, seen through a hole or a fold */
    if (back)
        sk__scale3(n, n, -1.0);
    double l = fmax(0.0, -sk__dot3(n, c->light));
    double base[3] = {0.75, 0.8, 0.95};
    if (back)
        base[0] = 0.95, base[1] = 0.7, base[2] = 0.45;
    if (c->kind == SK_SURFACE_ZEBRA) {
        double r[3], dn = sk__dot3(d, n);
        for (int k = 0; k < 3; ++k)
            r[k] = d[k] - 2.0 * dn * n[k];
        double phi = acos(fmin(1.0, fmax(-1.0, sk__dot3(r, c->stripe_dir))));
        double f = phi * 10.0 / M_PI; /* 10 stripe pairs over the half turn */
        bool white = f - floor(f) < 0.5;
        double v = white ? 0.55 + 0.45 * l : 0.05 + 0.1 * l;
        rgb[0] = rgb[1] = rgb[2] = v;
        if (back)
            rgb[2] *= 0.6;
        return;
    }
    double sh = fmin(1.0, 0.12 + 0.78 * l), spec = 0.25 * pow(l, 40.0);
    if (c->kind == SK_SURFACE_PATCH_MAP) {
        const sk_patch *pa = &c->s->surface.patches[id];
        for (int k = 0; k < 3; ++k)
            base[k] = cls_rgb[c->cls[id]][k];
        double m = pa->kind == SK_PATCH_TRIANGLE ? fmin(fmin(a, t), 1.0 - a - t)
                                                 : fmin(fmin(a, 1.0 - a), fmin(t, 1.0 - t));
        if (m < c->edge_eps) {
            rgb[0] = rgb[1] = rgb[2] = 0.2;
            return;
        }
        spec = 0.0;
        sh = 0.45 + 0.55 * l; /* the colours stay readable */
    }
    for (int k = 0; k < 3; ++k)
        rgb[k] = fmin(1.0, base[k] * sh + spec);
}

/* Tessellates patch p (n steps per side) and rasterizes it. */
static void draw_patch(sk__raster *r, ctx *c, size_t p, unsigned n, double (*scr)[3])
{
    const sk_patch *pa = &c->s->surface.patches[p];
    bool tri = pa->kind == SK_PATCH_TRIANGLE;
    for (unsigned j = 0; j <= n; ++j)
        for (unsigned i = 0; i <= n; ++i) {
            if (tri && i + j > n)
                continue;
            double x[3];
            sk_patch_eval(&c->s->surface, p, (double)i / n, (double)j / n, x, NULL, NULL, NULL);
            sk__view_project(c->view, x, scr[j * (n + 1) + i]);
        }
    for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i) {
            /* the cell's two triangles (a triangle patch: only those inside the domain) */
            unsigned q[2][3][2] = {{{i, j}, {i + 1, j}, {i, j + 1}},
                                   {{i + 1, j}, {i + 1, j + 1}, {i, j + 1}}};
            for (int h = 0; h < 2; ++h) {
                if (tri && (h == 0 ? i + j + 1 > n : i + j + 2 > n))
                    continue;
                double s[3][3];
                for (int k = 0; k < 3; ++k) {
                    unsigned ii = q[h][k][0], jj = q[h][k][1];
                    memcpy(s[k], scr[jj * (n + 1) + ii], sizeof s[k]);
                    c->par[k][0] = (double)ii / n;
                    c->par[k][1] = (double)jj / n;
                }
                /* half a pixel wider: neighbouring patches tessellated with other step counts
                 * leave no crack at their T-junctions */
                double cx = (s[0][0] + s[1][0] + s[2][0]) / 3, cy = (s[0][1] + s[1][1] + s[2][1]) / 3;
                for (int k = 0; k < 3; ++k) {
                    double dx = s[k][0] - cx, dy = s[k][1] - cy, l = hypot(dx, dy);
                    if (l > 0)
                        s[k][0] += 0.5 * dx / l, s[k][1] += 0.5 * dy / l;
                }
                sk__raster_triangle(r, s, (uint32_t)p, shade, c);
            }
        }
}

static void legend(cairo_t *cr, const size_t count[NCLS], bool title)
{
    double y = title ? 44 : 18;
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 13);
    for (int k = 0; k < NCLS; ++k, y += 20) {
        cairo_set_source_rgb(cr, cls_rgb[k][0], cls_rgb[k][1], cls_rgb[k][2]);
        cairo_rectangle(cr, 12, y - 11, 16, 14);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_set_line_width(cr, 1);
        cairo_stroke(cr);
        char line[64];
        snprintf(line, sizeof line, "%s (%zu)", cls_name[k], count[k]);
        cairo_move_to(cr, 34, y);
        cairo_show_text(cr, line);
    }
}

sk_status sk_render_surface(const sk_smooth *s, sk_surface_picture kind, const char *png_path,
                            const sk_render_opts *opts, sk_error *err)
{
    if (!s || !png_path || kind > SK_SURFACE_PATCH_MAP)
        return sk__fail(err, SK_ERR_ARG, "sk_render_surface: bad argument");
    sk_render_opts o = {0};
    if (opts)
        o = *opts;
    int W = o.width > 0 ? o.width : 900, H = o.height > 0 ? o.height : 900;
    size_t np = s->surface.count;
    sk__raster r = {0};
    sk_patch_shape *shapes = NULL;
    uint8_t *cls = NULL;
    double(*scr)[3] = sk__malloc_array((MAX_TESS + 1) * (MAX_TESS + 1), sizeof *scr);
    size_t count[NCLS] = {0};
    sk_status st = SK_OK;
    if (!scr) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (kind == SK_SURFACE_PATCH_MAP) {
        shapes = sk__malloc_array(np + 1, sizeof *shapes);
        cls = sk__malloc_array(np + 1, sizeof *cls);
        if (!shapes || !cls) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        if ((st = sk_smooth_patch_shapes(s, 0, shapes, err)))
            goto done;
        for (size_t p = 0; p < np; ++p) {
            bool over = shapes[p].overshoot > 0.5;
            cls[p] = shapes[p].singular && over    ? CLS_BOTH
                     : shapes[p].singular          ? CLS_SINGULAR
                     : over                        ? CLS_OVERSHOOT
                     : s->surface.patches[p].kind == SK_PATCH_TRIANGLE ? CLS_TRI
                                                                       : CLS_QUAD;
            count[cls[p]]++;
        }
    }
    if ((st = sk__raster_create(&r, W, H, err)))
        goto done;
    sk__view view;
    const double fallback[3] = {-0.4, -0.5, -1.0};
    sk__view_fit(&view, o.view, fallback, s->config->positions, s->config->num_vertices, W, H,
                 0.9);
    ctx c = {.s = s, .kind = kind, .view = &view, .cls = cls};
    for (int k = 0; k < 3; ++k) { /* light from the upper left of the viewer into the scene */
        c.light[k] = view.d[k] - 0.5 * view.y[k] + 0.3 * view.x[k];
        c.stripe_dir[k] = view.y[k] + 0.35 * view.x[k]; /* tubes across the picture, tilted */
    }
    sk__normalize3(c.light);
    sk__normalize3(c.stripe_dir);
    for (size_t p = 0; p < np; ++p) {
        const sk_patch *pa = &s->surface.patches[p];
        const double *cp = sk_patch_cp(&s->surface, p);
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (unsigned i = 0; i < sk_patch_num_points(pa); ++i) {
            double q[3];
            sk__view_project(&view, cp + 3 * i, q);
            lo[0] = fmin(lo[0], q[0]), hi[0] = fmax(hi[0], q[0]);
            lo[1] = fmin(lo[1], q[1]), hi[1] = fmax(hi[1], q[1]);
        }
        if (hi[0] < 0 || hi[1] < 0 || lo[0] > W || lo[1] > H || !(hi[0] >= lo[0]))
            continue; /* off the picture (or not finite) */
        double ext = fmax(hi[0] - lo[0], hi[1] - lo[1]);
        unsigned n = (unsigned)fmin(MAX_TESS, fmax(2.0, ceil(ext / 4.0)));
        c.edge_eps = ext > 0 ? 0.8 / ext : 0.0;
        draw_patch(&r, &c, p, n, scr);
    }
    cairo_surface_mark_dirty(r.surf);
    cairo_t *cr = cairo_create(r.surf);
    if (o.title) {
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(cr, 15);
        cairo_move_to(cr, 12, 22);
        cairo_show_text(cr, o.title);
    }
    if (kind == SK_SURFACE_PATCH_MAP)
        legend(cr, count, o.title != NULL);
    cairo_destroy(cr);
    st = sk__write_png(r.surf, png_path, err);
    r.surf = NULL; /* destroyed by the writer */
done:
    sk__raster_destroy(&r);
    sk__free(scr);
    sk__free(shapes);
    sk__free(cls);
    return st;
}
