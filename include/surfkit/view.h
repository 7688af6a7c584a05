/* The interactive viewer: one self-contained HTML file (three.js inlined, no network needed) that
 * shows a mesh (plain, with its edges, a UV checkerboard and the conformal distortion of its uv),
 * and a smooth surface (shaded with its exact normals, zebra stripes / reflection lines, the
 * distance of the surface to the mesh, the patch boundaries), with orbit, pan and zoom. */
#ifndef SURFKIT_VIEW_H
#define SURFKIT_VIEW_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"
#include "surfkit/smooth.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_view_opts {
    const char *title;      /* shown at the top of the page; NULL = "surfkit view" */
    const char *info;       /* a line of text under the toggles (e.g. the report); may be NULL */
    unsigned tess;          /* tessellation of each patch edge; 0 = 8 */
    double deviation_scale; /* distance at the top of the deviation colours (model units);
                               0 = the largest distance */
} sk_view_opts;

/* True when the library was built with three.js (scripts/setup.sh fetches it from npm). */
SK_API bool sk_view_available(void);

/* Writes the viewer page of mesh (faces of any size, split into fans) to path (atomically).
 * uv (2 per vertex of mesh, may be NULL) adds the checkerboard and distortion layers; smooth (may
 * be NULL; built over the same vertices) adds the surface layers and the surface's distance to
 * the mesh. SK_ERR_ARG when the library has no viewer (sk_view_available), SK_ERR_NOMEM, SK_ERR_IO. */
SK_API sk_status sk_view_write(const sk_mesh *mesh, const double *uv, const sk_smooth *smooth,
                               const sk_view_opts *opts, const char *path, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
