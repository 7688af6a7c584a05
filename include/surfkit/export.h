/* CAD export of patch sets (include/surfkit/bezier.h): IGES 5.3 (a B-rep of entity 128 faces:
 * 186/514/510/508/504/502, or free 128 surfaces), STEP AP214 (B-spline surfaces in advanced faces
 * of one shell whose faces share their edges and vertices), OBJ free-form. The writers know
 * patches only, nothing of how they were made.
 *
 * In STEP and the IGES B-rep a triangular patch becomes one tensor patch with a collapsed side
 * (the face is bounded by the triangle's three sides; sk_patch_triangle_to_degenerate_tensor), or
 * with split_triangles three tensor patches (sk_patch_split_triangle: exact, no singular point,
 * about three times the size). OBJ free-form and the IGES free-surface layout split triangles
 * unless degenerate_triangles. STEP needs corner_ids (mesh vertex ids) on every patch to share
 * vertices and edges: two patches sharing corner ids a, b along a side share that edge. */
#ifndef SURFKIT_EXPORT_H
#define SURFKIT_EXPORT_H

#include "surfkit/bezier.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_export_opts {
    const char *units;         /* "mm" (default), "cm", "m", "in", "ft", "um" */
    bool split_triangles;      /* STEP, IGES B-rep: three regular faces per triangle instead of
                                  one with a collapsed side */
    bool degenerate_triangles; /* IGES: free surfaces (as iges_free_surfaces), one biquartic with
                                  a collapsed side per triangle */
    bool closed;               /* STEP: CLOSED_SHELL (every edge shared by two faces) */
    bool iges_free_surfaces;   /* IGES: only the surfaces (entity 128, in one 402 group), no
                                  B-rep; implied by degenerate_triangles */
    bool iges_pcurves;         /* IGES B-rep with one face per triangle: write the loops'
                                  parameter-space curves (110 lines; about 0.7 KB more per
                                  triangle, faster to import); the split layout always has them */
    const char *name;          /* product / model name; default "surfkit" */
    const char *timestamp;     /* ISO 8601 date for the file headers; NULL = now (tests pass a
                                  fixed one for reproducible files) */
    sk_progress_fn progress;   /* STEP, IGES: called with the fraction of patches written (0 to
                                  1, increasing, 1 last); non-zero return cancels
                                  (SK_ERR_CANCELLED, no file) */
    void *progress_user;
} sk_export_opts;

typedef struct sk_export_stats {
    size_t faces;      /* surfaces / faces written */
    size_t edges;      /* distinct edge curves (IGES: 0 in the free-surface layout) */
    size_t vertices;   /* distinct vertex points */
    size_t bytes;
    bool solid;        /* a closed shell, written as a solid (STEP MANIFOLD_SOLID_BREP, IGES 186) */
} sk_export_stats;

/* Unit flag / name pairs of IGES and the SI prefix of STEP; false for an unknown name. */
SK_API bool sk_export_units_known(const char *units);

SK_API sk_status sk_export_iges(const char *path, const sk_patch_set *patches,
                                const sk_export_opts *opts, sk_export_stats *stats, sk_error *err);
SK_API sk_status sk_export_step(const char *path, const sk_patch_set *patches,
                                const sk_export_opts *opts, sk_export_stats *stats, sk_error *err);
SK_API sk_status sk_export_obj_freeform(const char *path, const sk_patch_set *patches,
                                        const sk_export_opts *opts, sk_export_stats *stats,
                                        sk_error *err);

/* The tensor patches the STEP and IGES writers emit for the given patches (triangles degenerate
 * unless opts->split_triangles, or opts->iges_free_surfaces without degenerate_triangles), in
 * output order, appended to *out (free it with sk_patch_set_free). Tests compare these
 * with what a CAD kernel reads back. */
SK_API sk_status sk_export_tensor_patches(const sk_patch_set *patches, const sk_export_opts *opts,
                                          sk_patch_set *out, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
