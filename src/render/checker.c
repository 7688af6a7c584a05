/* Checkerboard texture on the 3D mesh: a small z-buffered rasterizer into a cairo image
 * (orthographic view along opts->view), uv interpolated per pixel; the mesh's boundary edges drawn
 * over it in red where they are not hidden. An atlas comes as its seam-split mesh
 * (sk_atlas_split_mesh), so these are its seams and the surface's own boundary. */
#include "render/render_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <cairo.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The boundary edges, 2 pixels wide, where the z-buffer shows them (a tolerance of zeps in
 * depth, so an edge on the surface is not hidden by its own faces). */
static void draw_boundary(const sk_mesh *m, const sk__view *view, const float *zbuf, int W,
                          int H, double zeps, unsigned char *data, int stride)
{
    for (uint32_t h = 0; h < m->num_halfedges; ++h) {
        if (!sk_is_boundary_h(m, h) || m->h_face[h ^ 1u] == SK_INVALID)
            continue;
        double a[3], b[3];
        sk__view_project(view, m->positions + 3 * (size_t)sk_from(m, h), a);
        sk__view_project(view, m->positions + 3 * (size_t)sk_to(m, h), b);
        int steps = (int)fmin(4 * (double)W, ceil(2 * fmax(fabs(b[0] - a[0]), fabs(b[1] - a[1]))) + 1);
        for (int k = 0; k <= steps; ++k) {
            double t = (double)k / steps, x = a[0] + t * (b[0] - a[0]), y = a[1] + t * (b[1] - a[1]);
            double z = a[2] + t * (b[2] - a[2]);
            for (int dj = 0; dj < 2; ++dj)
                for (int di = 0; di < 2; ++di) {
                    int i = (int)floor(x) + di, j = (int)floor(y) + dj;
                    if (i < 0 || j < 0 || i >= W || j >= H || z > zbuf[(size_t)j * W + i] + zeps)
                        continue;
                    ((uint32_t *)(data + (size_t)j * stride))[i] = 0xd01818u;
                }
        }
    }
}

sk_status sk_render_checker(const sk_mesh *m, const double *uv, const char *path,
                            const sk_render_opts *opts, sk_error *err)
{
    sk_render_opts o = {0};
    if (opts)
        o = *opts;
    int W = o.width > 0 ? o.width : 1024, H = W;
    int checks = o.checks > 0 ? o.checks : 16;
    /* the one camera of the pictures (sk__view_fit), fitted to the vertices in use */
    double *pos = sk__malloc_array(3 * m->num_vertices + 3, sizeof *pos);
    if (!pos)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t np = 0;
    double ulo[2] = {INFINITY, INFINITY}, uhi[2] = {-INFINITY, -INFINITY};
    for (size_t v = 0; v < m->num_vertices; ++v) {
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        memcpy(pos + 3 * np++, m->positions + 3 * v, 3 * sizeof *pos);
        for (int c = 0; c < 2; ++c) {
            ulo[c] = fmin(ulo[c], uv[2 * v + c]);
            uhi[c] = fmax(uhi[c], uv[2 * v + c]);
        }
    }
    sk__view view;
    const double fallback[3] = {0, 0, -1};
    sk__view_fit(&view, o.view, fallback, pos, np, W, H, 0.92);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t k = 0; k < np; ++k) {
        double q[3];
        sk__view_project(&view, pos + 3 * k, q);
        lo[0] = fmin(lo[0], q[0]), hi[0] = fmax(hi[0], q[0]);
        lo[1] = fmin(lo[1], q[1]), hi[1] = fmax(hi[1], q[1]);
    }
    sk__free(pos);
    const double *d = view.d;
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    double uspan = fmax(uhi[0] - ulo[0], uhi[1] - ulo[1]);
    if (!(span > 0) || !(uspan > 0) || !isfinite(span) || !isfinite(uspan))
        return sk__fail(err, SK_ERR_ARG, "nothing to draw (empty or flat mesh or uv)");
    cairo_surface_t *surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H);
    float *zbuf = sk__malloc_array((size_t)W * H, sizeof *zbuf);
    if (cairo_surface_status(surf) != CAIRO_STATUS_SUCCESS || !zbuf) {
        cairo_surface_destroy(surf);
        sk__free(zbuf);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %d x %d picture", W, H);
    }
    cairo_surface_flush(surf);
    unsigned char *data = cairo_image_surface_get_data(surf);
    int stride = cairo_image_surface_get_stride(surf);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            ((uint32_t *)(data + (size_t)j * stride))[i] = 0xffffffu;
            zbuf[(size_t)j * W + i] = INFINITY;
        }
    double cscale = checks / uspan;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f] || sk_mesh_face_size(m, (uint32_t)f) != 3)
            continue;
        double n[3];
        sk_mesh_face_normal(m, (uint32_t)f, n);
        double shade = 0.35 + 0.65 * fabs(sk__dot3(n, d));
        uint32_t h = m->f_halfedge[f], vv[3];
        double sx[3], sy[3], sz[3];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            vv[k] = sk_from(m, h);
            const double *p = m->positions + 3 * (size_t)vv[k];
            double q[3];
            sk__view_project(&view, p, q);
            sx[k] = q[0], sy[k] = q[1], sz[k] = q[2];
        }
        double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
        if (fabs(area) < 1e-12)
            continue;
        int i0 = (int)fmax(0, floor(fmin(sx[0], fmin(sx[1], sx[2])))),
            i1 = (int)fmin(W - 1, ceil(fmax(sx[0], fmax(sx[1], sx[2])))),
            j0 = (int)fmax(0, floor(fmin(sy[0], fmin(sy[1], sy[2])))),
            j1 = (int)fmin(H - 1, ceil(fmax(sy[0], fmax(sy[1], sy[2]))));
        for (int j = j0; j <= j1; ++j) {
            for (int i = i0; i <= i1; ++i) {
                double px = i + 0.5, py = j + 0.5;
                double b0 = ((sx[1] - px) * (sy[2] - py) - (sx[2] - px) * (sy[1] - py)) / area;
                double b1 = ((sx[2] - px) * (sy[0] - py) - (sx[0] - px) * (sy[2] - py)) / area;
                double b2 = 1 - b0 - b1;
                if (b0 < 0 || b1 < 0 || b2 < 0)
                    continue;
                float z = (float)(b0 * sz[0] + b1 * sz[1] + b2 * sz[2]);
                if (z >= zbuf[(size_t)j * W + i])
                    continue;
                zbuf[(size_t)j * W + i] = z;
                double u = b0 * uv[2 * (size_t)vv[0]] + b1 * uv[2 * (size_t)vv[1]] + b2 * uv[2 * (size_t)vv[2]];
                double v = b0 * uv[2 * (size_t)vv[0] + 1] + b1 * uv[2 * (size_t)vv[1] + 1] +
                           b2 * uv[2 * (size_t)vv[2] + 1];
                long cu = (long)floor((u - ulo[0]) * cscale), cv = (long)floor((v - ulo[1]) * cscale);
                bool dark = ((cu + cv) & 1) != 0;
                double r = dark ? 0.15 : 0.95, g = dark ? 0.25 : 0.95, b = dark ? 0.55 : 0.90;
                uint32_t R = (uint32_t)(255 * r * shade), G = (uint32_t)(255 * g * shade),
                         B = (uint32_t)(255 * b * shade);
                ((uint32_t *)(data + (size_t)j * stride))[i] = (R << 16) | (G << 8) | B;
            }
        }
    }
    draw_boundary(m, &view, zbuf, W, H, 0.01 * span / view.scale, data, stride);
    sk__free(zbuf);
    cairo_surface_mark_dirty(surf);
    if (o.title) {
        cairo_t *cr = cairo_create(surf);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(cr, 15);
        cairo_move_to(cr, 12, 22);
        cairo_show_text(cr, o.title);
        cairo_destroy(cr);
    }
    return sk__write_png(surf, path, err);
}
