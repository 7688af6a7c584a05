/* Surface fitting: one tensor-product B-spline over a triangulated disk, within a tolerance.
 *
 * The disk is parametrized over the unit square (Floater's shape-preserving map, corners on four
 * boundary vertices: given, or the four sharpest turns of the boundary), then a cubic B-spline is
 * fitted to the vertices by least squares with a thin-plate smoothing term, and knots are
 * inserted in the spans where a vertex is farther than the tolerance from its surface point,
 * hierarchically (each round halves the worst quarter of the offending spans per direction),
 * as in the hierarchical B-spline fitting the hierarchical parametrization paper names as its
 * first use (its reference [8]). */
#ifndef SURFKIT_FIT_H
#define SURFKIT_FIT_H

#include "surfkit/bspline.h"
#include "surfkit/core.h"
#include "surfkit/mesh.h"
#include "surfkit/param.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_fit_opts {
    double tolerance;        /* largest distance of a vertex from the surface, model units;
                                0 = tolerance_rel times the bounding-box diagonal */
    double tolerance_rel;    /* used when tolerance is 0; 0 = 1e-3 */
    int degree;              /* 0 = 3 (bicubic) */
    double smoothing;        /* weight of the thin-plate energy relative to the data term
                                (scale free: both are normalized by their traces); 0 = each
                                round tries 1e-6 and 1e-3 and keeps the closer fit */
    unsigned initial_spans;  /* knot spans per direction to start from; 0 = 4 */
    unsigned max_rounds;     /* refinement rounds; 0 = 40 */
    double refine_share;     /* share of the knot spans above the tolerance split per round and
                                direction, the worst first (at least one): 0 = 1/10; 1 = all of
                                them (about doubling the grid where the error is) */
    sk_param_method method;  /* the square map: 0 = Floater (shape preserving, linear);
                                SK_PARAM_MIPS = hierarchical MIPS with the square boundary fixed
                                (the same corners and spacing); others as sk_parametrize */
    double area_theta;       /* > 0: the square map is balanced by MIPS with the area term
                                (sk_mips_opts.area_theta), the sides kept; negative: no balance
                                (the method's map alone); 0 = automatic: the disk is fitted over
                                SK_FIT_AUTO_THETAS maps (theta 1, 0.5, and none), and the fit kept
                                is the one with the fewest control points among those meeting the
                                tolerance, or the closest one when none does (stats->tried) */
    size_t max_control_points; /* the refinement stops before the grid passes this many control
                                  points; 0 = twice the disk's vertex count (a tensor grid
                                  adds a whole row or column per knot, so a local feature can
                                  need more control points than the mesh has vertices:
                                  patch-01 at 5e-3 of the diagonal, 1156 for 735) */
    bool has_corners;        /* corners: four boundary vertices, counter-clockwise around the */
    uint32_t corners[4];     /* surface, mapped to (0,0), (1,0), (1,1), (0,1) */
    sk_progress_fn progress;
    void *progress_user;
} sk_fit_opts;

/* The maps the automatic choice tries (sk_fit_opts.area_theta 0), in this order: a later map's
 * refinement stops below the control points of an earlier one that met the tolerance. */
#define SK_FIT_AUTO_THETAS 3

/* One square map tried and the fit over it (sk_fit_stats.tried). */
typedef struct sk_fit_try {
    double area_theta;     /* 0: the method's map without balance */
    size_t control_points; /* of the fit kept for this map */
    double deviation;      /* max(max_error, surface_to_mesh) of that fit */
    bool met;
    bool capped;           /* its refinement stopped at an earlier map's count (it could only
                              lose) */
    double seconds;        /* balance and fit of this map */
} sk_fit_try;

typedef struct sk_fit_stats {
    uint32_t corners[4];       /* the corners used */
    size_t samples;            /* points fitted in the last round (vertices and face samples) */
    size_t rounds;             /* refinement rounds done (the first fit is round 1); when T is
                                * not met, the surface handed out is the round nearest to T */
    size_t control_points;     /* nu * nv of the result */
    double tolerance;          /* the tolerance used (model units) */
    double max_error, rms_error; /* |S(u_k, v_k) - p_k| over the samples (vertices and points of
                                    the faces) after the foot-point correction: their distance
                                    to the surface, to within the correction's convergence */
    double surface_to_mesh;    /* largest distance of a grid of surface points to the mesh */
    bool met;                  /* max_error and surface_to_mesh <= tolerance */
    size_t split_edges;        /* dividing edges split (sk_param_split_side_edges) before the
                                  square map */
    size_t flipped;            /* flipped triangles of the square parametrization (of the split
                                  mesh) */
    double area_theta;         /* the map of the result (0: no balance) */
    size_t tries;              /* maps fitted: 1, or up to SK_FIT_AUTO_THETAS when automatic */
    sk_fit_try tried[SK_FIT_AUTO_THETAS];
    double seconds_param, seconds_fit; /* all maps tried: the square map and balances, fits */
} sk_fit_stats;

/* Fits a B-spline to a triangulated disk (sk_param_check_disk's conditions: SK_ERR_TOPOLOGY with
 * its message otherwise, e.g. for closed meshes). When the tolerance is not met after the last
 * round (or the control grid would exceed the number of mesh vertices), the best surface is returned with
 * stats->met false and status SK_OK: the caller decides. SK_ERR_ARG for bad options (corners
 * not on the boundary or not in order), SK_ERR_NUMERIC when the normal equations are singular. */
SK_API sk_status sk_fit_bspline(const sk_mesh *disk, const sk_fit_opts *opts, sk_bspline_surface **out,
                                sk_fit_stats *stats, sk_error *err);

/* A knot-adaptive tessellation of a fitted surface (sk_fit_tessellate). */
typedef struct sk_fit_tessellation {
    size_t nu, nv; /* cells along u and v: (nu + 1) (nv + 1) vertices, 2 nu nv triangles */
    double chord;  /* bound on the distance between the surface and the triangles */
} sk_fit_tessellation;

/* Triangles of s whose chord error stays below tol / 20 by a bound per knot cell (the largest
 * second- and mixed-derivative control points over the cell): each knot span split evenly,
 * as finely as the worst cell of its row or column needs, at least 4 per span and 64 per side,
 * at most max_side (2..4096) per side (info->chord then gives the bound reached). Vertex
 * (i, j) is S(u_i, v_j) with its unit normal and (u_i, v_j) as its uv, in rows of constant v.
 * info may be NULL. */
SK_API sk_status sk_fit_tessellate(const sk_bspline_surface *s, double tol, size_t max_side,
                                   sk_soup **out, sk_fit_tessellation *info, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
