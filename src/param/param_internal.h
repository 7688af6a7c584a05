/* Internal pieces shared by the parametrization sources. */
#ifndef SK_PARAM_INTERNAL_H
#define SK_PARAM_INTERNAL_H

#include "surfkit/param.h"

/* Weights of the half-edges leaving interior vertex / all half-edges (see sk_param_weights). */
void sk__weights_tutte(const sk_mesh *m, double *w);
void sk__weights_harmonic(const sk_mesh *m, double *w);
sk_status sk__weights_floater(const sk_mesh *m, double *w, sk_error *err);
void sk__weights_mean_value(const sk_mesh *m, double *w);

/* Cotangent of the angle at c in triangle (a, b, c) (3D). */
double sk__cot3(const double a[3], const double b[3], const double c[3]);

/* Solves a x = rhs (nrhs columns) of `method` with SK_LINEAR_HIERARCHICAL (linear_hierarchical.c): idx[v]
 * is vertex v's unknown (SK_INVALID when fixed), dim unknowns per vertex (dim * idx[v] + c).
 * Fills stats->solve, levels, iterations, residual. */
/* Direct solve of a (n x n, dim unknowns per free vertex as above) with o->ordering; the default
 * is the geometric nested dissection of the free vertices' positions. Fills stats->solve. */
sk_status sk__param_solve_direct(const sk_mesh *m, const sk_sparse *a, bool symmetric,
                                 const uint32_t *idx, unsigned dim, size_t nrhs, const double *rhs,
                                 double *x, const sk_param_opts *o, sk_param_stats *stats,
                                 sk_error *err);

sk_status sk__param_solve_hierarchical(const sk_mesh *m, sk_param_method method,
                                       const sk_sparse *a, bool symmetric, const uint32_t *idx,
                                       unsigned dim, size_t nrhs, const double *rhs, double *x,
                                       const sk_param_opts *o, sk_param_stats *stats,
                                       sk_error *err);

/* The same with SK_LINEAR_AMG (linear_hierarchical.c): aggregation multigrid over the matrix
 * graph (src/solve/amg.c), dim unknowns per vertex aggregated together; coarsest level at most
 * dim * o->coarse_vertices unknowns (0: 3000). Fills stats as the hierarchical solve does. */
sk_status sk__param_solve_amg(const sk_sparse *a, bool symmetric, unsigned dim, size_t nrhs,
                              const double *rhs, double *x, const sk_param_opts *o,
                              sk_param_stats *stats, sk_error *err);

/* SK_LINEAR_AUTO's default crossovers in free vertices (src/param/linear.c; docs/linear.md). */
#define SK_AUTO_VERTICES_SYMMETRIC 250000
#define SK_AUTO_VERTICES_LU 250000
#define SK_AUTO_VERTICES_LSCM SIZE_MAX
/* SK_LINEAR_AUTO's relative residual when AMG runs and opts->tolerance is 0: the direct uv to
 * about 2e-9 of the layout (lion head Loop x2, Floater and mean value; 1e-9 gave 2e-8), a fifth
 * fewer iterations than AMG's own 1e-12. */
#define SK_AUTO_TOLERANCE 1e-10

/* The solve of a parametrization system by o->solver (auto resolved per method and size, see
 * SK_LINEAR_AUTO), arguments as sk__param_solve_hierarchical; fills stats->solver with the solver
 * that ran. */
sk_status sk__param_solve_route(const sk_mesh *m, sk_param_method method, const sk_sparse *a,
                                bool symmetric, const uint32_t *idx, unsigned dim, size_t nrhs,
                                const double *rhs, double *x, const sk_param_opts *o,
                                sk_param_stats *stats, sk_error *err);

/* Boundary loop of a disk as a vertex cycle, counter-clockwise around the surface (the loop of
 * boundary half-edges runs clockwise, so it is walked backwards); *verts is the caller's to
 * sk__free. Fails with SK_ERR_TOPOLOGY unless the mesh has exactly one boundary loop. */
sk_status sk__param_ccw_loop(const sk_mesh *m, uint32_t **verts, size_t *count, sk_error *err);

/* Whether c[0..3] are four distinct vertices of the counter-clockwise loop (nb vertices) in
 * counter-clockwise order, starting anywhere (SK_ERR_ARG with a message otherwise). */
sk_status sk__param_check_corners(const uint32_t *loop, size_t nb, const uint32_t c[4],
                                  sk_error *err);

#endif
