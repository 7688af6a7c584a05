/* VC1 surfaces within a tolerance over a coarse level of the progressive mesh (issue 13).
 *
 *   fine normals -> progressive mesh (hierarchy.h) -> search over the levels for the coarsest
 *   whose VC1 surface is within T of the fine mesh -> local refinement: from a level below it,
 *   split back only the collapses whose removed vertices lie where the surface is farther than T
 *   from the mesh (or the mesh from the surface), rebuild, repeat
 *
 * Every surface is the VC1 interpolant (sk_smooth_build) of a mesh whose vertices are vertices of
 * the input, with the normals estimated once on the input (the coarse vertices keep their fine
 * normals). The deviation is measured both ways on the samples sk_deviation uses: every input
 * vertex and n x n points per input triangle against the surface, and every vertex and n x n
 * points per triangle of the surface's tessellation against the input. */
#ifndef SURFKIT_TOLERANCE_H
#define SURFKIT_TOLERANCE_H

#include "surfkit/core.h"
#include "surfkit/deviation.h"
#include "surfkit/hierarchy.h"
#include "surfkit/mesh.h"
#include "surfkit/smooth.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_tolerance_opts {
    double tolerance;        /* largest two-sided distance, model units; 0 = tolerance_rel times
                                the bounding-box diagonal of the mesh */
    double tolerance_rel;    /* used when tolerance is 0; 0 = 1e-3 */
    sk_smooth_opts smooth;   /* for every VC1 build (scheme must be VC1; the progress fields are
                                not used) and the normals: mesh->normals when present and not
                                smooth.estimate_normals, else estimated with smooth.normals */
    int face_samples;        /* samples per triangle edge on both sides (0 = 2: 4 per triangle) */
    unsigned tess;           /* tessellation of each patch for the surface side (0 = 4: the
                                grid `surfkit smooth -o OUT.obj` writes by default) */
    unsigned refine_levels;  /* the refinement starts this many levels below the coarsest level
                                that meets the tolerance (0 = 6: on bunny00 at 1e-3 of the
                                diagonal 9,723 patches, against 15,406 with 4 and 27,674 with
                                2; the levels' deviations are not monotone, and a coarse level
                                is often out of T at a few places only) */
    unsigned max_rounds;     /* refinement rounds (0 = 32); each splits back the coarsest
                                missing collapses around the offending vertices and the
                                corners of singular patches; a round within T with singular
                                patches goes on while their number falls */
    unsigned stall_rounds;   /* the refinement stops (stats.stalled) after this many rounds in
                                a row without progress: neither fewer offending vertices nor a
                                smaller max deviation than every earlier round (0 = 4; on
                                fandisk at 3e-3 of the diagonal, where no level meets T, the
                                rounds then stop at 14 instead of 32; the converging runs
                                measured went at most 3 rounds without progress) */
    bool no_estimate;        /* search the levels by bisection alone (the old search), without
                                starting from the level estimate (the coarsest level whose own
                                triangles are within T) */
    bool full_search;        /* search the levels with VC1 builds until the coarsest level
                                within T is bracketed (the old route). The default builds the
                                level PROBE_BELOW (3) under the estimate only: missed there,
                                the estimate is taken as the coarsest level within T and the
                                refinement starts refine_levels below it (on scans the
                                estimate is that level, so the result is the same without the
                                two largest builds); met there, or the estimate is the input
                                itself, or the refinement ends without a surface within T and
                                without singular patches: the full search follows (and its
                                refinement when its base differs) */
    bool full_checks;        /* every refinement round measures all distances again (the
                                reference for the default, incremental checks: a round keeps a
                                bound within T that the displacement of the patches since the
                                last round cannot have pushed beyond T, and measures the rest;
                                both flag the same places beyond T) */
    uint64_t seed;           /* hierarchy seed (0 = 1, as surfkit simplify) */
    sk_collapse_opts collapse; /* the hierarchy's collapses: 0 = a face normal turns by at most
                                15 degrees, interior valence at least 4 */
    sk_progress_fn progress; /* called between surfaces; non-zero cancels */
    void *progress_user;
} sk_tolerance_opts;

enum { SK_TOLERANCE_MAX_TRIED = 48 };

/* One surface built on the way: a full level of the hierarchy (refined = false) or a round of the
 * local refinement. */
typedef struct sk_tolerance_try {
    uint32_t level;          /* level of the hierarchy (0 = coarsest); for a round: its base */
    bool refined;            /* a refinement round */
    sk_status status;        /* SK_OK, or why VC1 could not be built there (then skipped) */
    size_t vertices, patches;
    double max_deviation;    /* two-sided, over the samples; NaN when not built. Exact when
                                beyond T; within T an upper bound (at most T: the check stops
                                each closest-point walk at the first triangle within T). A level
                                the search finds beyond T (either side): the largest distance
                                found before it stopped (beyond T) */
    size_t singular;         /* singular patches (sk_smooth_patch_shapes; the refinement splits
                                around them too) */
    size_t offending;        /* a refinement round: the input vertices it flagged (beyond T, on
                                a face beyond T, or around a singular patch); 0 for a level */
    size_t paired;           /* a round with an incremental check (see full_checks): its patches
                                over the same corners, kind and degrees as one of the last
                                round's (0 otherwise) */
    size_t unmoved;          /* ... of them, with the same control points to the bit */
    size_t moved_far;        /* ... of them, with a control point moved by a tenth of T or more
                                (how far a rebuild of the cut changes the surface away from the
                                round's splits: on armadillo after two Loop subdivisions at 1e-3
                                of the diagonal, with an edge deletion from nothing in every
                                round 4,000 to 5,000 of about 20,000 patches in the rounds that
                                split 44 to 80 vertices; with the rounds' warm start, 1,946 in
                                the round that splits 20) */
    bool met;                /* within T */
} sk_tolerance_try;

typedef struct sk_tolerance_stats {
    double tolerance;        /* model units, as used */
    double diagonal;         /* bounding-box diagonal of the input */
    size_t levels;           /* levels of the hierarchy (input included) */
    size_t num_tried;        /* surfaces built (the first SK_TOLERANCE_MAX_TRIED listed) */
    sk_tolerance_try tried[SK_TOLERANCE_MAX_TRIED];
    size_t estimate_level;   /* the coarsest level whose piecewise linear surface (its own
                                triangles) is within T both ways: where the search starts */
    size_t linear_tried;     /* levels whose linear surface was checked for the estimate */
    size_t levels_tried;     /* full levels tried by the search (VC1 surfaces built) */
    size_t failed_levels;    /* of them, where VC1 could not be built (skipped to a finer one) */
    size_t singular_levels;  /* of them, whose surface has singular patches */
    size_t coarsest_met;     /* the coarsest full level found to meet T (levels - 1 when none) */
    bool level_met;          /* some full level meets T */
    bool level_assumed;      /* the search took the estimate as the coarsest level within T
                                (see full_search): coarsest_met is the estimate, level_met
                                false, and no full level met T was built */
    size_t base_level;       /* the level the refinement started from */
    size_t rounds;           /* refinement rounds (surfaces built from the base level) */
    size_t failed_rounds;    /* rounds where VC1 could not be built (the region was widened) */
    size_t stalled;          /* refinements stopped for no progress (opts.stall_rounds) */
    size_t parity_splits;    /* extra splits to give each closed component an even vertex count */
    bool refined;            /* the result is a refined mesh (else a full level) */
    size_t vertices;         /* vertices of the result (all of them input vertices) */
    size_t patches;
    size_t input_faces;
    bool met;                /* deviation.hausdorff <= tolerance */
    sk_deviation_report deviation; /* the result against the input (sk_deviation, both ways) */
    double seconds_normals, seconds_hierarchy, seconds_search, seconds_refine, seconds_deviation;
    double seconds_estimate; /* of the search: the level estimate */
    double seconds_vc1, seconds_check; /* of search and refinement: VC1 builds, distance checks */
    size_t checked_patches;  /* patches of the refinement rounds' incremental checks ... */
    size_t reused_patches;   /* ... of them, the ones paired with a patch of the last round
                                (same corners, kind and degrees: their bounds may be kept) */
} sk_tolerance_stats;

/* Builds a VC1 surface of the manifold triangle mesh within the tolerance with few patches.
 * *out receives the surface (its config mesh has the result's vertices, numbered from 0; fine_ids,
 * when not NULL, gets an array of config vertex -> input vertex, freed with the allocator's free: free() by
 * default). Returns SK_OK
 * when the tolerance is met, SK_WARN_TOLERANCE with the closest surface found (still in *out)
 * when no surface meets it (not even the one over the input mesh itself, or the refinement ran
 * out of rounds), or an error: SK_ERR_TOPOLOGY (not triangles), SK_ERR_ARG (bad options), the
 * error of the VC1 build of the input itself when no level can be built, SK_ERR_NOMEM,
 * SK_ERR_CANCELLED. */
SK_API sk_status sk_smooth_tolerance(const sk_mesh *mesh, const sk_tolerance_opts *opts,
                                     sk_smooth **out, uint32_t **fine_ids,
                                     sk_tolerance_stats *stats, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
