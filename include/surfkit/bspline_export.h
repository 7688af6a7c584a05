/* CAD export of one tensor-product B-spline surface (bspline.h), e.g. the fit of a disk (fit.h):
 *
 *   STEP AP214: one B_SPLINE_SURFACE_WITH_KNOTS carried by an ADVANCED_FACE bounded by its four
 *   boundary curves (B_SPLINE_CURVE_WITH_KNOTS, the boundary rows of the control grid), the face
 *   in an OPEN_SHELL of a SHELL_BASED_SURFACE_MODEL, so that CAD systems open it as a face;
 *   IGES 5.3: one entity 128 (polynomial: all weights 1), independent.
 *
 * The parameter domain is [0, 1]^2 as in sk_bspline_eval; u is STEP's first (outer) control
 * point index and IGES's first (fastest) one. opts as in export.h (units, name, timestamp; the
 * patch-set flags are ignored); stats->faces is 1, edges 4 (STEP) or 0 (IGES), vertices 4 or 0. */
#ifndef SURFKIT_BSPLINE_EXPORT_H
#define SURFKIT_BSPLINE_EXPORT_H

#include "surfkit/bspline.h"
#include "surfkit/export.h"

#ifdef __cplusplus
extern "C" {
#endif

SK_API sk_status sk_export_bspline_step(const char *path, const sk_bspline_surface *surface,
                                        const sk_export_opts *opts, sk_export_stats *stats,
                                        sk_error *err);
SK_API sk_status sk_export_bspline_iges(const char *path, const sk_bspline_surface *surface,
                                        const sk_export_opts *opts, sk_export_stats *stats,
                                        sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
