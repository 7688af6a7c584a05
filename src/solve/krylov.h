/* Internal: row-compressed matrices, a multilevel hierarchy over given prolongations, and
 * Krylov solvers preconditioned by its V-cycle (preconditioned conjugate gradients for symmetric
 * positive definite systems, right-preconditioned BiCGStab for the others).
 *
 * The multilevel operator of level k is A_k = P_k^T A_{k+1} P_k (Galerkin) or one the caller
 * gives (a rediscretization), P_k the prolongation from level k to k + 1 (n_{k+1} x n_k);
 * level 0, the coarsest, is factored directly (CHOLMOD or UMFPACK). The V-cycle smooths with Gauss-Seidel, forward before the
 * coarse correction and backward after it, so that for a symmetric A it is a symmetric positive
 * definite preconditioner and CG applies. */
#ifndef SK_SOLVE_KRYLOV_H
#define SK_SOLVE_KRYLOV_H

#include "surfkit/solve.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* rows x cols, entries of row i at ptr[i] .. ptr[i+1]-1, columns sorted, no duplicates. */
typedef struct sk__csr {
    size_t rows, cols;
    size_t *ptr;  /* rows + 1 */
    uint32_t *col;
    double *val;
} sk__csr;

void sk__csr_free(sk__csr *a);
/* a with rows + 1 zeroed row pointers and room for nnz entries (NULL arrays on failure). */
sk_status sk__csr_alloc(sk__csr *a, size_t rows, size_t cols, size_t nnz, sk_error *err);
/* The full matrix of a (a lower-stored matrix is mirrored) in rows. */
sk_status sk__csr_from_sparse(const sk_sparse *a, sk__csr *out, sk_error *err);
/* out = a^T */
sk_status sk__csr_transpose(const sk__csr *a, sk__csr *out, sk_error *err);
/* out = a b */
sk_status sk__csr_product(const sk__csr *a, const sk__csr *b, sk__csr *out, sk_error *err);
/* out = r a p with r = p^T given (a square n_f x n_f, p n_f x n_c, r n_c x n_f). */
sk_status sk__csr_galerkin(const sk__csr *r, const sk__csr *a, const sk__csr *p, sk__csr *out,
                           sk_error *err);
/* out = P^T a P for the piecewise-constant P whose row i is one entry 1 in column map[i] (nc
 * columns): the entries and bits of sk__csr_galerkin(P^T, a, P) (the same additions in the same
 * order) in one pass over a, blocks of coarse rows in parallel. */
sk_status sk__csr_galerkin_map(const sk__csr *a, const uint32_t *map, size_t nc, sk__csr *out,
                               sk_error *err);
/* y = a x */
void sk__csr_multiply(const sk__csr *a, const double *x, double *y);

typedef struct sk__multilevel sk__multilevel;

typedef struct sk__multilevel_stats {
    size_t levels;
    size_t unknowns[2];   /* coarsest, finest */
    size_t operator_nnz;  /* sum over all levels (operator complexity = this / finest nnz) */
    size_t finest_nnz;
    size_t coarse_factor_nnz;
    double setup_seconds; /* Galerkin products, coarse analyse and factor */
} sk__multilevel_stats;

/* Takes ownership of *fine and of the num_levels - 1 prolongations p[0..] (p[k] from level k to
 * k + 1, level num_levels - 1 being fine), and of the coarse operators coarse_ops[0..L-2] when
 * given (a rediscretization; NULL = Galerkin products); all are freed by sk__multilevel_destroy,
 * also on failure. symmetric: fine is symmetric positive definite (Cholesky at the coarsest level, CG);
 * otherwise LU and BiCGStab. */
sk_status sk__multilevel_create(sk__csr *fine, sk__csr *p, sk__csr *coarse_ops,
                                size_t num_levels, bool symmetric, sk__multilevel **out,
                                sk_error *err);
void sk__multilevel_destroy(sk__multilevel **mg);
void sk__multilevel_stats_get(const sk__multilevel *mg, sk__multilevel_stats *s);
/* The cycle: each coarse correction times scale (default 1), gamma corrections per level
 * (default 1, a V-cycle; 2 is a W-cycle). Over-correction (1 < scale < 2) and the W-cycle make up
 * for the low energy of piecewise-constant prolongations; the cycle stays symmetric, so CG still
 * applies. kcycle (symmetric only): every coarse level but the coarsest solved by two flexible
 * CG steps preconditioned by its own cycle (Notay and Vassilevski's K-cycle), the finest CG
 * made flexible. */
void sk__multilevel_set_cycle(sk__multilevel *mg, double scale, unsigned gamma, bool kcycle);
/* The coarse operators given to sk__multilevel_create are the Galerkin products R A P of the
 * level above (as the aggregation AMG builds them; without coarse_ops this holds already): a
 * W-cycle then forms its later coarse corrections' residuals on the coarse level. */
void sk__multilevel_set_galerkin(sk__multilevel *mg);

typedef struct sk__krylov_opts {
    double tolerance;      /* stop at ||b - A x|| <= tolerance ||b|| (2-norm) */
    size_t max_iterations; /* per right-hand side, finest level */
    size_t level_iterations; /* nested iteration: Krylov steps on each intermediate level */
    bool pair_always; /* two right-hand sides in one pass even where two threads are free */
} sk__krylov_opts;

typedef struct sk__krylov_result {
    size_t iterations;     /* finest-level Krylov iterations, largest over the right-hand sides */
    double residual;       /* largest final ||b - A x|| / ||b|| */
    bool converged;
} sk__krylov_result;

/* Solves A x = b on the finest level for nrhs right-hand sides (column after column, n doubles
 * each; two right-hand sides, u and v, run together through one pass over the matrices with
 * interleaved vectors, the same to the bit as one at a time, unless two threads are free (then, and
 * for other counts, one column per thread; opts->pair_always: one pass anyway)) by
 * nested iteration: the right-hand side restricted to
 * every level (b_k = P_k^T b_{k+1}), the coarsest solved directly, prolonged, a few Krylov steps
 * on each finer level, and on the finest Krylov iterations until the tolerance. */
sk_status sk__multilevel_solve(sk__multilevel *mg, size_t nrhs, const double *b, double *x,
                               const sk__krylov_opts *opts, sk__krylov_result *res,
                               sk_error *err);

#endif
