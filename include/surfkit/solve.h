/* Sparse linear systems for mesh processing (Botsch, Bommes, Kobbelt, "Efficient Linear System
 * Solvers for Mesh Processing"): assemble from triplets into compressed columns, then a direct
 * solver with the analyse / factorize / solve split:
 *
 *   - symmetric positive definite matrices: CHOLMOD (fill-reducing ordering chosen once by the
 *     analysis, supernodal Cholesky, refactorization with new values and the same pattern,
 *     several right-hand sides in one call);
 *   - general square matrices: UMFPACK (symbolic analysis once, numeric LU, solve).
 *
 * Matrices are square, indices are 0-based, compressed sparse column (CSC) with int indices
 * (what the SuiteSparse "di" interfaces take). For the Cholesky path only the lower triangle
 * (row >= col) is stored: assemble with SK_SPARSE_LOWER. */
#ifndef SURFKIT_SOLVE_H
#define SURFKIT_SOLVE_H

#include "surfkit/core.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Growing list of (row, col, value) entries; duplicates are summed by sk_sparse_from_triplets. */
typedef struct sk_triplets {
    size_t count, capacity;
    uint32_t *rows;
    uint32_t *cols;
    double *values;
} sk_triplets;

SK_API sk_status sk_triplets_reserve(sk_triplets *t, size_t capacity, sk_error *err);
/* Appends one entry (grows as needed); SK_ERR_NOMEM on failure. */
SK_API sk_status sk_triplets_add(sk_triplets *t, uint32_t row, uint32_t col, double value);
SK_API void sk_triplets_clear(sk_triplets *t); /* count = 0, keeps the memory */
SK_API void sk_triplets_free(sk_triplets *t);

typedef enum {
    SK_SPARSE_FULL = 0, /* keep every entry */
    SK_SPARSE_LOWER = 1 /* keep only row >= col (entries above the diagonal are dropped) */
} sk_sparse_storage;

/* Square n x n matrix in compressed sparse columns; rows sorted within each column, no
 * duplicates. */
typedef struct sk_sparse {
    size_t n;
    size_t nnz;
    sk_sparse_storage storage;
    int *colptr;    /* n + 1 */
    int *rowind;    /* nnz */
    double *values; /* nnz */
    /* triplet index -> position in values (SIZE_MAX for dropped entries), kept so that new
     * values with the same pattern can be scattered quickly (sk_sparse_update_values) */
    size_t num_map;
    size_t *map;
} sk_sparse;

/* Builds the matrix; duplicates summed, out-of-range indices rejected with SK_ERR_ARG. */
SK_API sk_status sk_sparse_from_triplets(size_t n, const sk_triplets *t, sk_sparse_storage storage,
                                         sk_sparse **out, sk_error *err);
/* Refills values from triplets with the same (row, col) sequence as the build; only the values
 * may differ. */
SK_API sk_status sk_sparse_update_values(sk_sparse *a, const sk_triplets *t, sk_error *err);
/* y = A x (a lower-stored matrix acts as the full symmetric one). */
SK_API void sk_sparse_multiply(const sk_sparse *a, const double *x, double *y);
SK_API void sk_sparse_destroy(sk_sparse **a);

typedef enum {
    SK_SOLVER_CHOLESKY = 0, /* CHOLMOD; the matrix must be SK_SPARSE_LOWER and positive definite */
    SK_SOLVER_LU = 1        /* UMFPACK; the matrix must be SK_SPARSE_FULL */
} sk_solver_kind;

/* Timings and sizes, cumulative over the solver's life (factor_seconds adds up refactorizations). */
typedef struct sk_solve_stats {
    sk_solver_kind kind;
    size_t n;
    size_t nnz;        /* stored entries of A */
    size_t factor_nnz; /* entries of L (Cholesky) or L + U (LU) */
    size_t factorizations, solves, rhs;
    double analyse_seconds, factor_seconds, solve_seconds;
} sk_solve_stats;

typedef struct sk_solver sk_solver;

/* Fill-reducing orderings (bench/solve.sh measures them on the parametrization systems). */
typedef enum {
    SK_ORDERING_DEFAULT = 0, /* surfkit's pick for mesh systems (see solver.c) */
    SK_ORDERING_AUTO,        /* the library's own default: CHOLMOD tries AMD, then METIS when
                                the fill is high; UMFPACK uses AMD */
    SK_ORDERING_AMD,         /* approximate minimum degree */
    SK_ORDERING_METIS,       /* METIS nested dissection */
    SK_ORDERING_NESDIS,      /* CHOLMOD's nested dissection (Cholesky only; LU: UMFPACK_ORDERING_CHOLMOD) */
    SK_ORDERING_BEST,        /* try several and keep the sparsest factor */
    SK_ORDERING_GIVEN,       /* sk_solver_opts.perm (e.g. from sk_sparse_point_ordering) */
    SK_ORDERING_GEOMETRIC    /* sk_sparse_point_ordering only: nested dissection from the points */
} sk_ordering;

typedef struct sk_solver_opts {
    sk_ordering ordering;
    bool simplicial; /* Cholesky: simplicial (no BLAS) instead of supernodal; for small factors
                        solved many times from several threads (the multilevel coarsest level) */
    const int *perm; /* SK_ORDERING_GIVEN: the fill-reducing permutation, n entries (unknown
                        perm[k] is eliminated k-th); copied by sk_solver_create_opts */
} sk_solver_opts;

/* A fill-reducing ordering of a (square, symmetric pattern; lower or full storage) whose unknowns
 * are dim per point (unknown dim * i + c belongs to point i), computed on the point graph and
 * expanded so that a point's unknowns stay together (for LSCM's interleaved u, v: half the
 * graph, wider supernodes). method: SK_ORDERING_METIS, SK_ORDERING_AMD, or
 * SK_ORDERING_GEOMETRIC: nested dissection with plane / breadth-first separators of the points
 * xyz (3 coordinates per point; planes across the part's principal or a coordinate axis, placed
 * where they cut fewest edges for their balance; separators last), the
 * order within each part and separator by constrained minimum degree (CAMD). perm gets a->n
 * entries, for SK_ORDERING_GIVEN. xyz may be NULL unless geometric. */
SK_API sk_status sk_sparse_point_ordering(const sk_sparse *a, unsigned dim, const double *xyz,
                                          sk_ordering method, int *perm, sk_error *err);

/* Analyses the pattern of a (fill-reducing ordering, symbolic factorization). */
SK_API sk_status sk_solver_create(const sk_sparse *a, sk_solver_kind kind, sk_solver **out,
                                  sk_error *err);
/* The same with options (NULL = defaults). */
SK_API sk_status sk_solver_create_opts(const sk_sparse *a, sk_solver_kind kind,
                                       const sk_solver_opts *opts, sk_solver **out, sk_error *err);
/* Numeric factorization of a; may be called again with new values on the same pattern.
 * Fails with SK_ERR_NUMERIC when the matrix is not positive definite (Cholesky) or singular. */
SK_API sk_status sk_solver_factorize(sk_solver *s, const sk_sparse *a, sk_error *err);
/* Solves A X = B for nrhs right-hand sides stored column after column (n * nrhs doubles each);
 * x and b may not alias. */
SK_API sk_status sk_solver_solve(sk_solver *s, size_t nrhs, const double *b, double *x, sk_error *err);
SK_API void sk_solver_stats(const sk_solver *s, sk_solve_stats *stats);
SK_API void sk_solver_destroy(sk_solver **s);

/* Convenience: create + factorize + solve, stats filled (may be NULL). */
SK_API sk_status sk_sparse_solve(const sk_sparse *a, sk_solver_kind kind, size_t nrhs, const double *b,
                                 double *x, sk_solve_stats *stats, sk_error *err);



#ifdef __cplusplus
}
#endif
#endif
