/* Internal: the direct solve of a pair of systems that share their matrix and are coupled only
 * through a few border unknowns (LSCM in the form E_D(u) + E_D(v) - A(u, v): the same cotangent
 * matrix for u and v, coupled by the signed area along the boundary alone). */
#ifndef SK_SOLVE_BORDERED_H
#define SK_SOLVE_BORDERED_H

#include "surfkit/solve.h"

/* Solves the 2n x 2n symmetric positive definite system
 *
 *     [ A        E C E^T ] [x]   [f]
 *     [ E C^T E^T    A   ] [y] = [g]
 *
 * A n x n, lower-stored, symmetric positive definite; E the last k columns of the n x n
 * identity (the border unknowns are n - k .. n - 1); C k x k dense, column-major (C[r + k c]
 * couples row n - k + r of the x block with unknown n - k + c of the y block). b = (f, g) and
 * x = (x, y), 2n each. One Cholesky factor of A (the leading n - k unknowns ordered by
 * `ordering`, SK_ORDERING_METIS or SK_ORDERING_AMD on their graph, the border last) serves
 * both halves; the border is solved densely through the Schur complement (src/solve/bordered.c).
 * SK_ERR_ARG when the factorization could not keep the border last
 * (the caller then solves the whole system another way). stats gets the factor's figures,
 * residual the relative 2-norm residual of the 2n system. */
sk_status sk__solve_bordered_pair(const sk_sparse *a, size_t k, const double *c, sk_ordering ordering,
                                  const double *b, double *x, sk_solve_stats *stats,
                                  double *ordering_seconds, double *residual, sk_error *err);

#endif
