/* Linear parametrizations of disk-topology triangle meshes, and their distortion metrics.
 *
 * A parametrization is a per-vertex array uv of 2 * mesh->num_vertices doubles (u, v of vertex i
 * at uv[2i], uv[2i+1]); deleted and isolated vertices get (0, 0). Copy it into mesh->uvs to write
 * an OBJ with vt or a PLY with s t. Each method leaves uv at its own scale (the unit circle, the
 * unit square, LSCM's pins); sk_param_normalize maps it into the unit square.
 *
 * Fixed-boundary methods (the boundary is mapped to a convex polygon, then every interior vertex
 * is an affine combination of its neighbours: sum_j w_ij (u_i - u_j) = 0, eq. (1) of Hormann,
 * Greiner, Campagna):
 *   SK_PARAM_TUTTE       uniform weights w_ij = 1 (symmetric: Cholesky)
 *   SK_PARAM_FLOATER     Floater's shape-preserving weights: local exponential map of each one
 *                        ring, averaged barycentric coordinates (non-symmetric: LU)
 *   SK_PARAM_MEAN_VALUE  Floater's mean value coordinates (non-symmetric: LU)
 *   SK_PARAM_HARMONIC    cotangent weights (symmetric: Cholesky). The weights can be negative
 *                        (obtuse triangles), and then triangles CAN flip: only Tutte, Floater and
 *                        mean value have the guarantee of Tutte's / Floater's theorem.
 * Free boundary:
 *   SK_PARAM_LSCM        least squares conformal maps (Levy et al.) with two pinned boundary
 *                        vertices (the two farthest apart, or opts->pins), Cholesky.
 * With a convex boundary, Tutte, Floater and mean value give a bijection (no flipped triangle).
 * MIPS (non-linear, hierarchical or flat) is in mips.h and hierarchical.h; one call for every
 * method, with the defaults and legality checks, is sk_parametrize in parametrize.h.
 */
#ifndef SURFKIT_PARAM_H
#define SURFKIT_PARAM_H

#include "surfkit/mesh.h"
#include "surfkit/solve.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SK_PARAM_DEFAULT = 0, /* Floater (sk_param_linear, sk_param_weights, sk_parametrize) */
    SK_PARAM_TUTTE,
    SK_PARAM_FLOATER,
    SK_PARAM_MEAN_VALUE,
    SK_PARAM_HARMONIC,
    SK_PARAM_LSCM,
    SK_PARAM_MIPS         /* hierarchical (or flat) MIPS: sk_parametrize only (parametrize.h) */
} sk_param_method;

/* "tutte", "floater", "mvc", "harmonic", "lscm", "mips" ("floater" for SK_PARAM_DEFAULT,
 * "unknown" else); static storage, never NULL. */
SK_API const char *sk_param_method_name(sk_param_method m);
/* Parses those names (and "barycentric", "shape-preserving", "mean-value", "cotangent"); name
 * may be NULL; returns false (and leaves *m) when unknown. */
SK_API bool sk_param_method_parse(const char *name, sk_param_method *m);

/* One boundary vocabulary for every parametrizer. Which shapes a call accepts is said at the
 * call; SK_ERR_ARG for the others. */
typedef enum {
    SK_BOUNDARY_DEFAULT = 0, /* the method's own: the circle for the fixed-boundary methods
                                (Tutte, Floater, mean value, harmonic), free for LSCM and MIPS */
    SK_BOUNDARY_CIRCLE,      /* fixed on the unit circle, counter-clockwise */
    SK_BOUNDARY_SQUARE,      /* fixed on the unit square [0,1]^2, corners on four boundary vertices */
    SK_BOUNDARY_FREE,        /* natural boundary (LSCM, MIPS) */
    SK_BOUNDARY_GIVEN        /* fixed where the uv array already has it */
} sk_boundary_shape;

/* "default", "circle", "square", "free", "given" ("unknown" else); static storage. */
SK_API const char *sk_boundary_shape_name(sk_boundary_shape shape);
/* Parses "circle", "square", "free", "given"; name may be NULL; false when unknown. */
SK_API bool sk_boundary_shape_parse(const char *name, sk_boundary_shape *shape);

typedef enum {
    SK_SPACING_CHORD = 0, /* by chord length along the boundary loop */
    SK_SPACING_UNIFORM    /* equal steps */
} sk_boundary_spacing;

typedef struct sk_boundary_opts {
    sk_boundary_shape shape;     /* 0 = the method's default (above) */
    sk_boundary_spacing spacing;
    /* Square: the four corner vertices in boundary order (counter-clockwise in uv); when
     * has_corners is false they are the boundary vertices closest to quarter arc length. */
    bool has_corners;
    uint32_t corners[4];
    /* Circle / square: the boundary vertex mapped to (1, 0) / (0, 0); SK_INVALID or 0 with
     * has_start false = the first vertex of the loop. */
    bool has_start;
    uint32_t start;
} sk_boundary_opts;

typedef enum {
    SK_LINEAR_DIRECT = 0,  /* sparse Cholesky / LU (default) */
    SK_LINEAR_GAUSS_SEIDEL, /* iterative, starting from the interior uv given (a warm start, e.g.
                              a coarser level's solution); stops at `tolerance` or the budget */
    SK_LINEAR_HIERARCHICAL, /* multilevel over the progressive mesh: the coarsest level solved
                               directly, prolonged through the barycentric coordinates, Krylov
                               iterations (CG for Tutte / harmonic / LSCM, BiCGStab for Floater /
                               mean value) preconditioned by a V-cycle on each finer level until
                               the relative residual reaches `tolerance`; the same system as
                               direct (see coarse_vertices for small meshes). */
    SK_LINEAR_AMG,          /* algebraic multigrid: aggregates of the matrix graph (pairwise
                               heavy-edge matching twice per level), piecewise-constant
                               prolongation, Galerkin operators down to a few thousand unknowns
                               factored directly, the same V-cycle and Krylov methods as
                               hierarchical; no progressive mesh to build */
    SK_LINEAR_AUTO          /* AMG for systems of at least `auto_vertices` free vertices (the
                               crossover measured per method, docs/linear.md), direct below; an
                               AMG solve that does not converge is redone directly. The stats
                               say which ran. */
} sk_linear_solver;

/* "direct", "gauss-seidel", "hierarchical", "amg", "auto" ("unknown" else); static storage. */
SK_API const char *sk_linear_solver_name(sk_linear_solver solver);

/* Options of the linear methods; zero-initialized means every default. */
typedef struct sk_param_opts {
    sk_param_method method;    /* 0 = Floater; SK_PARAM_MIPS is refused (SK_ERR_ARG) */
    sk_boundary_opts boundary; /* circle (default), square or given; ignored by LSCM */
    sk_linear_solver solver;   /* LSCM: direct, hierarchical, AMG or auto (Gauss-Seidel means
                                  direct) */
    double tolerance;          /* Gauss-Seidel: largest update relative to the uv extent; 0 = 1e-10.
                                  Hierarchical, AMG: relative residual ||b - Ax|| / ||b||; 0 = 1e-12 */
    size_t max_iterations;     /* Gauss-Seidel sweeps; 0 = 10000. Hierarchical: finest-level
                                  Krylov iterations; 0 = 500 */
    size_t coarse_vertices;    /* hierarchical: the coarsest level solved directly has at most
                                  this many vertices, and meshes with fewer than twice as many are
                                  solved directly; 0 = 20000. AMG: the coarsest level has at
                                  most this many vertices' unknowns; 0 = 3000 unknowns */
    size_t auto_vertices;      /* auto: AMG from this many free vertices up, direct below;
                                  0 = the method's measured crossover (SIZE_MAX: never AMG) */
    bool has_pins;             /* LSCM: pin these two vertices (else the farthest boundary pair) */
    uint32_t pins[2];
    sk_ordering ordering;      /* direct: fill-reducing ordering. AMD, METIS, GEOMETRIC: on the
                                  vertex graph (sk_sparse_point_ordering); AUTO, NESDIS, BEST:
                                  the solver's own; 0 = surfkit's pick per system (src/param/
                                  linear.c, docs/linear.md) */
    sk_progress_fn progress;   /* may be NULL; non-zero return cancels (SK_ERR_CANCELLED) */
    void *progress_user;
} sk_param_opts;

/* What a linear method did (plain values; times in seconds). */
typedef struct sk_param_stats {
    size_t vertices, interior, boundary, faces;
    sk_solve_stats solve;   /* direct solver details (n, nnz, factor nnz, phase seconds);
                               hierarchical: analyse = hierarchy build, factor = prolongations,
                               Galerkin operators and the coarsest factor (factor_nnz), solve =
                               the Krylov iterations */
    sk_linear_solver solver; /* the solver that ran: direct, Gauss-Seidel, hierarchical or AMG
                                (never auto; hierarchical on a small mesh runs direct) */
    size_t iterations;      /* Gauss-Seidel sweeps, finest-level Krylov iterations (0 for direct) */
    size_t levels;          /* hierarchical: levels used (1 = solved directly) */
    double residual;        /* final relative residual ||b - Ax|| / ||b|| (2-norm, largest over
                               the right-hand sides); direct too (0 for Gauss-Seidel) */
    double check_seconds;   /* input check */
    double boundary_seconds;
    double weights_seconds; /* weights + matrix assembly */
    double ordering_seconds; /* direct: a vertex-graph ordering (part of solve.analyse_seconds) */
    double solve_seconds;   /* analyse + factor + solve (or the iterations) */
    double total_seconds;
} sk_param_stats;

/* Checks that the mesh is a triangulated disk: triangles only, one component, one boundary loop,
 * Euler characteristic 1, no degenerate (zero-area) triangle. Otherwise SK_ERR_TOPOLOGY with a
 * message saying what the mesh is ("closed surface of genus 2: cut it to a disk first"). */
SK_API sk_status sk_param_check_disk(const sk_mesh *mesh, sk_error *err);

/* Writes uv of the boundary vertices (only) for the circle (also SK_BOUNDARY_DEFAULT) or square
 * map; SK_BOUNDARY_GIVEN leaves uv as it is; SK_BOUNDARY_FREE is SK_ERR_ARG (no map). opts may be
 * NULL (circle, chord spacing). */
SK_API sk_status sk_param_boundary(const sk_mesh *mesh, const sk_boundary_opts *opts, double *uv,
                                   sk_error *err);

/* Corners for the square boundary map of a disk: four boundary vertices, counter-clockwise
 * around the surface, at the four sharpest turns of the boundary (smallest sums of face angles),
 * each at least a sixth of the boundary length from the others (less when that leaves fewer than
 * four), then moved into the span of an interior edge whose two ends would lie on one side where
 * that removes it. SK_ERR_TOPOLOGY when the mesh has not one boundary loop or it has fewer than
 * four vertices. */
SK_API sk_status sk_param_square_corners(const sk_mesh *disk, uint32_t corners[4], sk_error *err);

/* A copy of the disk in which every dividing edge of the square map with these corners (an
 * interior edge whose two ends lie on one side of the square, e.g. the inner edge of an "ear"
 * triangle at a ragged boundary) is split at its midpoint: the new vertex is interior, so no
 * triangle has all its vertices on one side and Tutte, Floater and mean value keep their
 * no-flip guarantee (Floater 2003). The surface is the same (the midpoints lie on the edges);
 * vertices keep their ids, the new ones follow (*splits of them, may be NULL). Corners as in
 * sk_boundary_opts; SK_ERR_ARG when they are not boundary vertices in counter-clockwise order. */
SK_API sk_status sk_param_split_side_edges(const sk_mesh *disk, const uint32_t corners[4],
                                           sk_mesh **out, size_t *splits, sk_error *err);

/* Per half-edge weights w[h] = w_ij for i = from(h), j = to(h), over mesh->num_halfedges
 * entries; defined for half-edges leaving interior vertices (others 0). Floater and mean value
 * are normalised to sum 1 per vertex; Tutte is 1, harmonic (cot alpha + cot beta) / 2. */
SK_API sk_status sk_param_weights(const sk_mesh *mesh, sk_param_method method, double *w, sk_error *err);

/* Solves sum_j w_ij (u_i - u_j) = 0 for every free vertex, the others (fixed[i] != 0; NULL means
 * the boundary vertices) keeping their uv. `symmetric` says w_ij = w_ji (then the fixed
 * vertices are eliminated into the right-hand side and the matrix is symmetric positive
 * definite: Cholesky), else LU. u and v are solved together (two right-hand sides). With
 * opts->solver == SK_LINEAR_GAUSS_SEIDEL the free uv given are the starting guess. */
SK_API sk_status sk_param_solve_weights(const sk_mesh *mesh, const double *w, bool symmetric,
                                        const uint8_t *fixed, const sk_param_opts *opts, double *uv,
                                        sk_param_stats *stats, sk_error *err);

/* The whole method: check, boundary map, weights, solve. uv has 2 * num_vertices doubles (with
 * SK_BOUNDARY_GIVEN its boundary entries are inputs), at the method's own scale. opts may be NULL
 * (Floater, circle); stats may be NULL. SK_ERR_ARG for SK_PARAM_MIPS or a free boundary with a
 * fixed-boundary method. */
SK_API sk_status sk_param_linear(const sk_mesh *mesh, const sk_param_opts *opts, double *uv,
                                 sk_param_stats *stats, sk_error *err);

/* LSCM alone (also reached through sk_param_linear with SK_PARAM_LSCM); opts and stats may be
 * NULL. uv at the scale the two pins set (see sk_param_normalize). */
SK_API sk_status sk_param_lscm(const sk_mesh *mesh, const sk_param_opts *opts, double *uv,
                               sk_param_stats *stats, sk_error *err);

/* Maps uv (2 * mesh->num_vertices doubles, changed in place) into the unit square by one
 * uniform scale and a translation (the aspect ratio is kept): the bounding box of the vertices
 * of the alive faces gets its lower-left corner at (0, 0) and its larger side 1, so every such
 * uv lies in [0, 1]^2 (exactly: no rounding outside). Deleted and isolated vertices keep their
 * value. Every metric below is invariant under this map. SK_ERR_NUMERIC when a uv is not
 * finite or all of them are one point; a mesh without faces is left as it is. */
SK_API sk_status sk_param_normalize(const sk_mesh *mesh, double *uv, sk_error *err);

/* ---------------------------------------------------------------------------------------------
 * Metrics
 * ------------------------------------------------------------------------------------------- */

/* Sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear, exact
 * for all finite doubles (error-bounded filter, then exact expansion arithmetic). */
SK_API int sk_orient2d(const double a[2], const double b[2], const double c[2]);

/* Distortion of a parametrization; every value is invariant under a similarity of uv. */
typedef struct sk_param_metrics {
    size_t faces;
    size_t flipped;        /* triangles with clockwise or zero-area uv (exact orientation test) */
    size_t degenerate;     /* of those, the zero-area ones */
    double mips_sum;       /* sum over triangles of sigma1/sigma2 + sigma2/sigma1 (papers README);
                              flipped triangles add their value too, zero-area ones make it inf */
    double mips_mean;      /* mips_sum / faces (2 is the minimum) */
    double conformal_mean; /* 3D-area-weighted mean of sigma1 / sigma2 (1 is conformal) */
    double conformal_max;
    double area_log_mean;  /* mean over triangles of |log((A_uv / sum A_uv) / (A / sum A))| */
    double stretch_max;    /* max over triangles of max(sigma1, 1 / sigma2) with uv scaled to the
                              3D area: the worst lengthening or shortening of any direction */
    size_t boundary_self_intersections; /* crossing pairs of non-adjacent boundary edges in uv */
    double area_uv;        /* signed uv area (sum over triangles) */
} sk_param_metrics;

/* Fills *m (not NULL) for uv (2 * num_vertices doubles) over the alive triangles of mesh. */
SK_API sk_status sk_param_metrics_compute(const sk_mesh *mesh, const double *uv, sk_param_metrics *m,
                                          sk_error *err);

/* Per face (num_faces entries; deleted / non-triangle faces get 0): conformal distortion
 * sigma1/sigma2 (inf for zero uv area) and orientation (+1, -1, 0 from sk_orient2d). Either
 * output may be NULL. */
SK_API sk_status sk_param_face_distortion(const sk_mesh *mesh, const double *uv, double *conformal,
                                          int8_t *orientation, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
