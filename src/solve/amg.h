/* Internal: algebraic multigrid by aggregation. The prolongations come from the matrix graph
 * alone (no mesh): each level groups its unknowns into aggregates by pairwise heavy-edge matching
 * applied twice (about four unknowns per aggregate), prolongs piecewise constantly over them
 * (optionally smoothed by one damped Jacobi step), and takes the Galerkin product P^T A P as the
 * next operator, until at most coarse_max unknowns are left; the multilevel object of krylov.h
 * (Gauss-Seidel V-cycle, coarsest level factored directly, CG or BiCGStab) does the rest. */
#ifndef SK_SOLVE_AMG_H
#define SK_SOLVE_AMG_H

#include "solve/krylov.h"

/* Aggregates of the unknowns of the square matrix a, dim unknowns per block (block b owns
 * unknowns dim * b .. dim * b + dim - 1, a->rows a multiple of dim): the blocks are matched over
 * the strength (below) summed over the dim same-component couplings, twice (the second time over
 * the graph of the first pass's pairs); a block with no unmatched neighbour joins its strongest
 * neighbour's aggregate, one with no neighbour at all stays alone. agg[b] (a->rows / dim
 * entries) is block b's aggregate in 0 .. *count - 1, every aggregate non-empty. The strength of
 * a coupling is -a_ij where a_ij < 0 and 0 otherwise (a positive off-diagonal, as an obtuse
 * triangle gives the cotangent weights, is weak: 37 -> 36 CG iterations, harmonic on a 266k-
 * triangle disk). */
sk_status sk__amg_aggregate(const sk__csr *a, unsigned dim, uint32_t *agg, size_t *count,
                            sk_error *err);

/* The prolongation (a->rows x dim * count) over the aggregates: unknown dim * b + c takes the
 * value of coarse unknown dim * agg[b] + c; smoothed: (I - omega D^-1 a) times that, omega 2/3
 * (rows with a zero diagonal stay unsmoothed). */
sk_status sk__amg_prolongation(const sk__csr *a, unsigned dim, const uint32_t *agg, size_t count,
                               bool smooth, sk__csr *p, sk_error *err);

typedef struct sk__amg_opts {
    size_t coarse_max; /* stop coarsening at this many unknowns or fewer; 0 = 3000 */
    unsigned dim;      /* unknowns per block; 0 = 1 */
    bool smooth;       /* smoothed aggregation (denser coarse operators) */
} sk__amg_opts;

/* Builds the aggregation hierarchy of *fine and the multilevel object over it; takes ownership
 * of *fine as sk__multilevel_create does (freed on failure too). */
sk_status sk__amg_create(sk__csr *fine, const sk__amg_opts *opts, bool symmetric,
                         sk__multilevel **out, sk_error *err);

#endif
