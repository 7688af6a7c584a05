/* VC1 (tangent-plane continuous) smooth surfaces interpolating the vertices and normals of a
 * triangle mesh, after C. Cottin and R. van Damme, "Construction of a VC1 interpolant over
 * triangles via edge deletion" (CAGD 11, 1994):
 *
 *   normals (given or estimated) -> edge deletion (triangles + quads, every interior vertex odd)
 *   -> wire frame targets -> per-vertex constrained least squares (eq. 8) -> interior control
 *   points (system 4) -> quartic triangles (15 control points) and bicubic quads (16)
 *
 * and a baseline: PN triangles (Vlachos et al. 2001, cubic, only C0 across edges).
 *
 * The surface is a patch set (include/surfkit/bezier.h): one patch per face of the configuration
 * mesh, patch f for face f (its tag), corner ids = the face's vertex ids in counter-clockwise
 * order seen from the side the normals point to, corner 0 = from(f_halfedge[f]). Triangles have
 * degree 4 (VC1) or 3 (PN), quads are bicubic tensor patches. */
#ifndef SURFKIT_SMOOTH_H
#define SURFKIT_SMOOTH_H

#include "surfkit/analysis.h"
#include "surfkit/core.h"
#include "surfkit/mesh.h"
#include "surfkit/bezier.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Edge deletion (paper section 3)
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_edge_deletion_stats {
    size_t even_vertices;     /* interior vertices with an even number of faces, before */
    size_t lower_bound;       /* ceil(even_vertices / 2): each deleted edge fixes at most 2 */
    size_t deleted_edges;
    size_t pairs;             /* pairs formed by Initialise (even-even) */
    size_t boundary_paths;    /* even vertices connected to the boundary instead of a partner */
    size_t initialise_rounds; /* distance-growing rounds of Initialise */
    size_t path_edges;        /* total length of the initial paths */
    size_t reductions;        /* Reduce Path: loops removed and triangle short cuts */
    size_t shared_edges;      /* case (2a): edges used by two paths (cancelled) */
    size_t triangle_fixes;    /* case (2b): two deleted edges in one triangle, replaced by the third */
    size_t forced_edges;      /* deleted edges making a quad corner above 160 degrees (an even
                                 vertex without another choice, or a case-(2b) replacement) */
    size_t triangles, quads;  /* faces after deletion */
    size_t adjacent_pairs;    /* pairs of neighbouring even vertices matched before Initialise
                                 (one edge each; included in pairs) */
    size_t augmenting_paths;  /* augmenting paths that enlarged that matching */
    size_t shortcuts;         /* local improvement: walks along deleted edges replaced by shorter
                                 paths of kept edges (cycle exchanges) */
    size_t shortcut_savings;  /* deleted edges those exchanges saved */
    size_t shortcut_searched; /* even vertices whose exchanges the parallel pre-pass searched (the
                                 others provably gain nothing: see docs/edge-deletion.md) */
} sk_edge_deletion_stats;

/* Deletes interior edges of a triangle mesh so that every interior vertex lies in an odd number of
 * faces and every face is a triangle or a quad (two triangles merged across a deleted edge).
 * Writes a new mesh (vertex ids unchanged) to *out; *deleted (may be NULL) receives a malloc'ed
 * array of 2 * deleted_edges vertex ids (the deleted edges' end points). Fails with
 * SK_ERR_TOPOLOGY for faces that are not triangles and for a closed component with an odd number of
 * even vertices (equivalently an odd number of vertices, by Euler's formula: no solution exists). */
SK_API sk_status sk_edge_deletion(const sk_mesh *mesh, sk_mesh **out, uint32_t **deleted,
                                  sk_edge_deletion_stats *stats, sk_error *err);

/* ---------------------------------------------------------------------------------------------
 * Crease edges (sharp features): the VC1 surface is only G0 across them, with one normal per
 * sector on each side (docs/creases.md), and G1 everywhere else
 * ------------------------------------------------------------------------------------------- */

#define SK_CREASE_ANGLE_DEFAULT 40.0 /* degrees */

typedef struct sk_crease_opts {
    double angle_deg; /* crease angle A in degrees, 0 < A < 180 (0 = SK_CREASE_ANGLE_DEFAULT) */
} sk_crease_opts;

/* Marks the sharp interior edges of mesh: crease[e] = 1 for edge e (sk_num_edges(mesh) entries,
 * written in full) when the dihedral angle of its two faces and that of their area-weighted side
 * normals (each face with its neighbours across its other edges) both reach A, its group (such
 * edges meeting at vertices) has at least 3 of 5 edges with smooth sides (the faces within 3 rings
 * of each side, across edges below A, lie within A / 2 of their mean normal, or within a third of
 * the jump), and the edge lies on a line of at least 3 such edges (chained through vertices with
 * exactly two) or joins two corners (vertices with three or more); after Belyaev & Anoshkina's
 * detection: smooth the normals, keep the lines (docs/creases.md). *count (may be NULL) receives
 * the number of crease edges. SK_ERR_ARG for an angle outside (0, 180). */
SK_API sk_status sk_mesh_crease_edges(const sk_mesh *mesh, const sk_crease_opts *opts,
                                      uint8_t *crease, size_t *count, sk_error *err);

/* ---------------------------------------------------------------------------------------------
 * The smooth surface
 * ------------------------------------------------------------------------------------------- */

typedef enum { SK_SMOOTH_VC1 = 0, SK_SMOOTH_PN = 1 } sk_smooth_scheme;

/* The free control points of the VC1 vertex systems (8): FAIR (default) fits them to the wire
 * frame targets and then moves each vertex's tangents by the linear map of its tangent plane that
 * lowers the bending energy of the patches around it (Miao et al.; src/smooth/fair_points.c);
 * LSQ keeps the least-squares fit to the targets. Both are exactly VC1. */
typedef enum { SK_FREE_POINTS_FAIR = 0, SK_FREE_POINTS_LSQ = 1 } sk_free_points;

typedef struct sk_smooth_opts {
    sk_smooth_scheme scheme;   /* 0 = VC1 */
    sk_normal_method normals;  /* estimation method when the mesh has no normals (0 = angle) */
    bool estimate_normals;     /* estimate even when the mesh carries normals */
    bool allow_split;          /* closed component with an odd vertex count: split its longest
                                  edge at the midpoint of its wire frame curve instead of failing */
    double alpha;              /* angle bound alpha < angle/pi < 1 - alpha between neighbouring
                                  tangent control points (paper section 4); 0 = 0.01 */
    double max_nu;             /* VC1: bound on the ratio |nu| of eq. (6) between neighbouring
                                  patches (r_m lowered where a sliver or a long quad makes it
                                  extreme); 0 = 16, negative = unbounded */
    bool keep_triangulation;   /* VC1: keep the input's triangulation; by default edges are first
                                  flipped (same vertices) to remove slivers and near-folds */
    bool parity_flips;         /* VC1: after those flips, flip edges that make even vertices odd
                                  where that keeps the shape and the normal agreement (fewer
                                  deleted edges; off by default, no effect with keep_triangulation) */
    bool deletion_flips;       /* VC1: edge flips chosen for the edge deletion (off by default:
                                  while deleted / bound is above 1.01, edges next to deleted ones
                                  are flipped where the flip pass's quality bounds hold, and a pass
                                  is kept when the deletion then has fewer edges and a lower
                                  deleted / bound; a build left with singular patches is done again
                                  without them; about twice the build CPU on rough scans; no effect
                                  with keep_triangulation) */
    sk_free_points free_points; /* VC1: how the free tangent control points are chosen */
    int reroute_rounds;        /* VC1: builds again with the edge deletion re-routed (and slivers
                                  flipped) near the patches still singular after the repair, at
                                  most this many times: 0 = 6 (12 with base_refinements),
                                  negative = none */
    sk_progress_fn progress;
    void *progress_user;
    double crease_angle_deg;   /* crease detection (sk_mesh_crease_edges): 0 = 40 degrees,
                                  negative = none */
    double fit_weight;         /* VC1: > 0 fits the free tangent control points to fit_mesh after
                                  the regularity repair (src/smooth/fit_data.c): sweeps over every
                                  vertex lowering the fair points' energy plus fit_weight *
                                  sum_i |S(u_i) - p_i|^2 over its vertices and 4 points per
                                  triangle (u_i: their foot points on the surface) and over 3 (9)
                                  points inside each triangle (quad) patch paired with the nearest
                                  point of fit_mesh; 3 rounds, the foot points found again each
                                  round; a patch the fit makes singular gets its corners back. The
                                  surface stays exactly VC1 and interpolating, with no more
                                  singular patches. 0 = none (the default; the measurements and
                                  why it is not on in the tolerance route: CHANGELOG.md) */
    const sk_mesh *fit_mesh;   /* the scan fitted with fit_weight (NULL = the input mesh) */
    unsigned base_refinements; /* VC1: refinements of the input before the edge deletion (after
                                  the normals, their fold refits and the crease detection on the
                                  input; no edge flips then): every edge but the near-folds (facet
                                  normals over 120 degrees apart) split at its midpoint, the new
                                  vertex on the input's facets with the facets' normal, crease
                                  halves kept as creases (src/smooth/refine_base.c); 0 = none; not
                                  with sk_smooth_tolerance. The re-routed rounds (reroute_rounds,
                                  12 by default here) may flip slivers of the refined base near
                                  singular patches (a round whose flips do not pay is tried again
                                  without them) */
} sk_smooth_opts;

typedef struct sk_smooth_stats {
    sk_edge_deletion_stats deletion;
    size_t flipped_edges;      /* edges flipped by the triangulation pass before the deletion */
    size_t parity_flipped_edges; /* of those, flipped by the parity pass (opts.parity_flips) */
    size_t deletion_flipped_edges; /* flipped for the edge deletion after it (not in
                                      flipped_edges; opts.deletion_flips) */
    size_t folded_normals;     /* estimated normals refitted at folded stars (fold_normals.c) */
    size_t split_edges;        /* 1 when --allow-split split an edge */
    size_t vertex_systems;     /* vertices whose system (8) was solved */
    size_t max_iterations;     /* Gauss-Newton iterations of the hardest vertex */
    size_t fallback_solves;    /* vertices that needed the LAPACKE dgglse fallback */
    size_t failed_vertices;    /* vertices whose system did not converge (reported in problems) */
    size_t relaxed_vertices;   /* vertices whose targets were relaxed to meet the angle bounds */
    size_t angle_violations;   /* vertices violating alpha < angle < pi (1 - alpha) even so */
    double max_residual;       /* largest |residual of (8)| relative to the vertex's scale */
    double mean_target_deviation; /* mean |P - P*| / |P* - V| */
    double seconds_normals, seconds_flips, seconds_deletion, seconds_systems, seconds_patches;
    size_t singular_before_repair; /* patches the regularity test found singular before ... */
    size_t repaired_vertices;  /* ... vertex systems were re-solved with varied targets to make
                                  their patches regular (the VC1 property is kept exactly) */
    size_t singular_after_repair; /* patches still singular after the repair (and after the
                                     rounds of re-routed deletions that try to lower them) */
    size_t rerouted_rounds;    /* builds again with the deletion re-routed at singular patches */
    double seconds_repair;
    size_t fair_steps;         /* vertex steps of the fair free points (all sweeps) */
    double seconds_fair;
    double fair_energy_before; /* bending energy (Miao et al.) of all patches before and after */
    double fair_energy_after;  /* the fair free points (after: from the model they minimise) */
    size_t fit_points;         /* points of the fit to the scan (opts.fit_weight; 0 without) */
    double seconds_fit, cpu_fit; /* the fit: foot points, sweeps, guard (after the repair) */
    size_t fit_steps;          /* vertex steps of the fit to the scan (all rounds) */
    size_t fit_undone;         /* patches the fit made singular or farther from their points,
                                  whose corners it gave back (summed over the guard's rounds) */
    /* CPU seconds (sk_cpu_seconds: all threads) of the stages timed by the seconds_ fields */
    double cpu_normals, cpu_flips, cpu_deletion, cpu_systems, cpu_patches, cpu_fair, cpu_repair;
} sk_smooth_stats;

typedef struct sk_smooth {
    sk_smooth_scheme scheme;
    sk_mesh *config;           /* the triangle/quad mesh the patches sit on (one patch per face) */
    double *normals;           /* unit normal per vertex of config */
    sk_patch_set surface;      /* patch f belongs to face f of config */
    size_t num_deleted;        /* deleted edges ... */
    uint32_t *deleted;         /* ... as 2 vertex ids each */
    size_t num_problems;       /* vertices with a failed system or violated angle bound */
    uint32_t *problems;        /* their ids */
    size_t num_creases;        /* crease edges of the input mesh ... */
    uint32_t *creases;         /* ... as 2 vertex ids each (VC1: G0 patch boundaries) */
    /* VC1 with creases (both NULL without, and for PN): crease_edge[e] = 1 for the crease edges
     * of config (sk_num_edges(config) entries); corner_normals[3 h] the unit normal at from(h)
     * of the sector holding face(h) (per half-edge of config; a vertex on a crease has one
     * normal per sector, interpolated at the corners there; elsewhere normals[from(h)]) */
    uint8_t *crease_edge;
    double *corner_normals;
    sk_smooth_stats stats;
} sk_smooth;

/* Builds the smooth surface of a manifold triangle mesh. Uses mesh->normals when present (and not
 * opts->estimate_normals), else estimates them. Errors: SK_ERR_TOPOLOGY (non-triangle faces, odd
 * closed component without allow_split), SK_ERR_NUMERIC (an edge whose normals make a cubic
 * boundary curve impossible, named in the message; a vertex whose system (8) does not converge to
 * rounding, named in the message: never a silent residual), SK_ERR_CANCELLED. Vertices whose
 * angle bounds are violated are listed in problems; the surface is still returned. */
SK_API sk_status sk_smooth_build(const sk_mesh *mesh, const sk_smooth_opts *opts, sk_smooth **out,
                                 sk_error *err);
SK_API void sk_smooth_destroy(sk_smooth **smooth);

/* ---------------------------------------------------------------------------------------------
 * Continuity report
 * ------------------------------------------------------------------------------------------- */

#define SK_CONTINUITY_EXAMPLES 16

typedef struct sk_continuity_opts {
    unsigned samples;      /* samples per edge (0 = 32) */
    double max_angle_deg;  /* G1 tolerance (0 = 0.5 degrees, Albat & Mueller) */
    double max_gap;        /* gap tolerance in model units (0 = 0.005, i.e. mm) */
    unsigned intersection_tess; /* tessellation per patch side for the self-intersection check
                                   (0 = 6); (unsigned)-1 skips the check */
    unsigned shape_samples; /* grid steps per patch side for overshoot and fairness (0 = 12) */
} sk_continuity_opts;

typedef struct sk_continuity_report {
    size_t interior_edges, samples;
    double max_gap, mean_gap;
    double max_normal_jump_deg, mean_normal_jump_deg;
    uint32_t worst_edge_vertices[2];  /* where the largest normal jump is */
    /* creases (sk_smooth.crease_edge): the G1 figures above skip them (the surface is G0 there,
     * by design); their gaps count in max_gap and here, their normal jumps only here */
    size_t crease_edges;
    double max_crease_gap;
    double max_crease_jump_deg, min_crease_jump_deg; /* over the samples of the crease edges */
    double max_vertex_error;          /* |S(corner) - V| */
    double max_normal_error_deg;      /* angle(patch normal at corner, given normal) */
    /* singular: a patch whose normal vanishes or turns over somewhere (found by sampling): it has
     * a cusp or a fold there. Uncertified: the normal cone test (Ginkel, Peters, Umlauf) cannot
     * prove the patch regular (its cone of normals contains 0); most such patches are regular,
     * the singular ones are among them. */
    size_t singular_patches;
    size_t uncertified_patches;
    size_t num_singular_examples;
    uint32_t singular_examples[SK_CONTINUITY_EXAMPLES]; /* patch ids */
    /* self-intersections: pairs of patches that share no corner but cross each other (found on
     * a tessellation, sk_self_intersections): what CAD checkers report as self-intersecting
     * faces. SIZE_MAX when the check was skipped. */
    size_t intersecting_pairs;
    size_t intersecting_patches;
    size_t num_intersection_examples;
    uint32_t intersection_examples[2 * SK_CONTINUITY_EXAMPLES]; /* patch id pairs */
    bool pass_g1, pass_gap;           /* against the tolerances */
    bool pass_intersections;          /* no crossing patch pair (or not checked) */
    /* shape (sk_patch_shape, per patch: sk_smooth_patch_shapes). Patch ids are SK_INVALID when
     * there are no patches; the examples are the patches with overshoot > 0.5, worst first. */
    double max_overshoot, mean_overshoot;
    uint32_t max_overshoot_patch;
    size_t overshoot_patches;         /* patches with overshoot > 0.5 */
    size_t num_overshoot_examples;
    uint32_t overshoot_examples[SK_CONTINUITY_EXAMPLES];
    double max_fairness_deg, mean_fairness_deg; /* worst and mean over the patches */
    uint32_t max_fairness_patch;
} sk_continuity_report;

/* Shape measures of one patch, on a grid of `samples` steps per side (0 = 12; triangles: the
 * (samples + 1)(samples + 2)/2 points of the barycentric grid, quads (samples + 1)^2):
 *  - overshoot: largest distance of the patch from the flat triangle(s) of the face it replaces
 *    (a quad: the two triangles on either side of its deleted edge), divided by the longest edge
 *    of those triangles. 0 for a patch in its face; a spike is > 1.
 *  - fairness_deg: largest angle (degrees) between the patch normal and the normal interpolated
 *    from the vertex normals at its corners (linear over triangles, bilinear over quads, then
 *    normalized); 180 where the patch normal vanishes. 0 at the corners of an interpolating
 *    patch; ripples, bulges and spikes raise it, a fold makes it exceed 90.
 *  - singular: the regularity test of the continuity report. */
typedef struct sk_patch_shape {
    double overshoot;
    double fairness_deg;
    bool singular;
} sk_patch_shape;

/* Fills out[p] (s->surface.count entries) for every patch p. */
SK_API sk_status sk_smooth_patch_shapes(const sk_smooth *s, unsigned samples, sk_patch_shape *out,
                                        sk_error *err);

SK_API sk_status sk_smooth_continuity(const sk_smooth *s, const sk_continuity_opts *opts,
                                      sk_continuity_report *rep, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
