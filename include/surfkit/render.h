/* Pictures with cairo: UV layouts coloured by distortion, and a checkerboard textured view of
 * the 3D mesh. PNG or SVG chosen by the file extension (.png, .svg); files are written
 * atomically. Every call takes (what to draw..., path, opts, err); opts may be NULL (defaults). */
#ifndef SURFKIT_RENDER_H
#define SURFKIT_RENDER_H

#include "surfkit/mesh.h"
#include "surfkit/smooth.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_render_opts {
    int width;             /* picture width in pixels (points for SVG); 0 = 1024 (patch pictures:
                              900) */
    int height;            /* patch pictures only; 0 = 900 */
    int edges;             /* 0 = draw edges when the mesh has at most 100k faces, 1 = always,
                              -1 = never */
    double conformal_max;  /* top of the colour scale for sigma1/sigma2 (log scale from 1); 0 = 4 */
    const char *title;     /* a line of text at the top, or NULL */
    /* checkerboard and patch pictures */
    double view[3];        /* direction the camera looks along; zero = (0, 0, -1) for the
                              checkerboard, (-0.4, -0.5, -1) for the patch pictures */
    int checks;            /* squares across the uv bounding box; 0 = 16 */
} sk_render_opts;

/* The UV layout: triangles coloured by conformal distortion (legend on the right), flipped
 * triangles filled in magenta with a thick outline, edges in thin grey, boundary in black. */
SK_API sk_status sk_render_uv(const sk_mesh *mesh, const double *uv, const char *path,
                              const sk_render_opts *opts, sk_error *err);

/* The 3D mesh seen along opts->view (orthographic, z-buffered), textured with a checkerboard
 * in uv and shaded by the angle to the view (PNG only). */
SK_API sk_status sk_render_checker(const sk_mesh *mesh, const double *uv, const char *path,
                                   const sk_render_opts *opts, sk_error *err);

/* Pictures of the smooth surface (cairo, PNG, orthographic flat shading) */
/* The triangle/quad configuration: triangles grey, quads blue, deleted edges red, problem
 * vertices marked. */
SK_API sk_status sk_render_patch_layout(const sk_smooth *s, const char *png_path,
                                        const sk_render_opts *opts, sk_error *err);
/* A flat-shaded picture of a triangle soup (e.g. the tessellated surface). */
SK_API sk_status sk_render_shaded(const sk_soup *soup, const char *png_path, const sk_render_opts *opts,
                                  sk_error *err);

/* Pictures of the smooth surface itself, shaded per pixel with the exact patch normals (no
 * facets), seen along opts->view (zero: (-0.4, -0.5, -1)), orthographic, width x height (0: 900 x
 * 900), PNG written atomically; the back side (through a hole or a fold) is drawn in orange:
 *  - SK_SURFACE_SHADED: diffuse light and a little specular;
 *  - SK_SURFACE_ZEBRA: reflection lines (zebra stripes): the view direction reflected in the
 *    surface against a fixed direction; a kink in the stripes is a kink in the surface, stripes
 *    that bend smoothly across patch boundaries show tangent-plane continuity;
 *  - SK_SURFACE_PATCH_MAP: the patches (triangles grey, quads blue) with their boundaries,
 *    patches with overshoot > 0.5 in orange, with a singular point in magenta, with both in
 *    dark red
 *    (sk_smooth_patch_shapes), a legend with the counts. */
typedef enum {
    SK_SURFACE_SHADED = 0,
    SK_SURFACE_ZEBRA = 1,
    SK_SURFACE_PATCH_MAP = 2
} sk_surface_picture;
SK_API sk_status sk_render_surface(const sk_smooth *s, sk_surface_picture kind,
                                   const char *png_path, const sk_render_opts *opts,
                                   sk_error *err);

/* A scalar field over a surface (e.g. the distance to another surface, sk_bvh_distance). */
typedef double (*sk_field_fn)(void *user, const double p[3]);

/* The field map: soup seen along opts->view (zero: (0, 0, -1)), shaded by its interpolated vertex
 * normals, each pixel coloured by field at the surface point it shows, from blue at 0 to red at
 * scale, magenta beyond it; scale <= 0 uses the largest value drawn. A legend shows the scale
 * under `label` (e.g. "distance to the surface"). PNG, written atomically. SK_ERR_TOPOLOGY when a
 * face index is out of range. */
SK_API sk_status sk_render_field(const sk_soup *soup, sk_field_fn field, void *user, double scale,
                                 const char *label, const char *path, const sk_render_opts *opts,
                                 sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
