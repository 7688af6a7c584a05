/* The parametrize pipeline: one options struct and one call for every method (the linear methods
 * of param.h, hierarchical and flat MIPS of hierarchical.h), with the defaults and the legality
 * checks per method, the corners and edge splits of the square boundary, the normalization of
 * the result to the unit square and a count of flipped triangles. This is what `surfkit param`
 * calls. */
#ifndef SURFKIT_PARAMETRIZE_H
#define SURFKIT_PARAMETRIZE_H

#include "surfkit/hierarchical.h"
#include "surfkit/mips.h"
#include "surfkit/param.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Options of sk_parametrize; zero-initialized means every default (Floater, circle boundary,
 * chord spacing, uv normalized to the unit square). */
typedef struct sk_parametrize_opts {
    sk_param_method method;    /* 0 = Floater; SK_PARAM_MIPS = hierarchical MIPS (or flat) */
    /* shape 0 = the method's default: the circle for Tutte, Floater, mean value and harmonic;
     * free for LSCM and MIPS. Legal: the fixed-boundary methods take circle, square or given
     * (boundary uv read from the uv array); LSCM only free; MIPS circle, square or free. Spacing
     * as in sk_param_boundary. Square: the corners given (has_corners), or else at the four
     * sharpest boundary turns (sk_param_square_corners; sk_param_boundary alone takes quarter
     * arc lengths), and every dividing edge split at its midpoint (sk_param_split_side_edges)
     * so that no triangle lies on one side: the split mesh comes back in the stats. */
    sk_boundary_opts boundary;
    bool flat;                 /* MIPS: the conventional flat optimization, not hierarchical */
    size_t max_steps;          /* MIPS: budget of local steps (vertex moves); 0 = no budget */
    uint64_t seed;             /* MIPS: hierarchy and sweep order; 0 = 1 (0 and 1 are the same) */
    bool raw;                  /* keep the method's own scale (unit circle, unit square, LSCM's
                                  pins, MIPS's power of two); default: the uv of the faces'
                                  vertices fill [0, 1]^2 along the larger side (sk_param_normalize) */
    /* Fine tuning of the hierarchical MIPS (sweep schedule, global steps, hierarchy); NULL =
     * defaults; only with the MIPS method. Its boundary, max_steps, seed and progress are
     * replaced by the fields above. */
    const sk_hparam_opts *hierarchical;
    /* Fine tuning of the linear methods (solver, tolerance, pins); NULL = defaults; not with
     * the MIPS method. Its method, boundary and progress are replaced by the fields above. */
    const sk_param_opts *linear;
    sk_progress_fn progress;   /* may be NULL; non-zero return cancels (SK_ERR_CANCELLED) */
    void *progress_user;
} sk_parametrize_opts;

/* What sk_parametrize did. The hierarchical stats hold an allocated level table: release with
 * sk_parametrize_stats_release. */
typedef struct sk_parametrize_stats {
    sk_param_method method;      /* the method run (never SK_PARAM_DEFAULT) */
    sk_boundary_shape boundary;  /* the boundary used (never SK_BOUNDARY_DEFAULT) */
    bool hierarchical;           /* MIPS: hierarchical (else flat) */
    const char *name;            /* "floater", ..., "lscm", "mips-hierarchical", "mips-flat";
                                    static storage */
    sk_param_stats linear;       /* linear methods and LSCM */
    sk_hparam_stats hparam;      /* hierarchical MIPS (holds the allocated level table) */
    sk_mips_stats mips;          /* flat MIPS */
    size_t flipped;              /* triangles with clockwise or zero-area uv (sk_orient2d) */
    size_t split_edges;          /* square boundary: dividing edges split at their midpoints */
    /* When split_edges > 0: the mesh parametrized, the input's vertices first (same ids) and
     * then split_edges new interior ones, with the whole uv in split_mesh->uvs. Owned by the
     * stats (sk_parametrize_stats_release destroys it; set the field to NULL to keep it). NULL
     * when the input itself was parametrized. */
    sk_mesh *split_mesh;
    double seconds;              /* the whole call */
} sk_parametrize_stats;

/* Checks opts alone (no mesh): SK_ERR_ARG with a message saying which combination is not
 * allowed (e.g. "lscm has a free boundary", "flat and max_steps go with the MIPS method").
 * opts may be NULL (the defaults are legal). */
SK_API sk_status sk_parametrize_check(const sk_parametrize_opts *opts, sk_error *err);

/* Parametrizes a triangulated disk (one component, one boundary loop, Euler characteristic 1,
 * no degenerate triangle, no deleted element) into uv: 2 * mesh->num_vertices doubles, written
 * (read first for a given boundary). A square boundary may split edges (opts->boundary): then
 * the map is of stats->split_mesh and uv gets its input vertices' part. opts may be NULL
 * (defaults); stats may be NULL, else it is overwritten (not freed first) and must be released
 * with sk_parametrize_stats_release, also after a failure. Returns SK_OK; SK_WARN_FLIPS when the
 * result has flipped triangles (harmonic and LSCM can flip; the uv is complete and
 * stats->flipped says how many); SK_ERR_ARG for options sk_parametrize_check refuses or square
 * corners that are not boundary vertices in counter-clockwise order; SK_ERR_TOPOLOGY when the
 * mesh is not a disk; others from the solvers. */
SK_API sk_status sk_parametrize(const sk_mesh *mesh, const sk_parametrize_opts *opts, double *uv,
                                sk_parametrize_stats *stats, sk_error *err);

/* Frees what stats holds (the hierarchical level table, the split mesh) and zeroes it.
 * NULL-safe. */
SK_API void sk_parametrize_stats_release(sk_parametrize_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
