/* Direct solvers: CHOLMOD for symmetric positive definite matrices, UMFPACK for general ones,
 * both with the analyse once / factorize (again) / solve split that Botsch, Bommes and Kobbelt
 * recommend for mesh systems. The library never prints: CHOLMOD's printing is switched off and
 * every failure comes back as an sk_status with a message. */
#include "surfkit/solve.h"
#include "core/internal.h"

#include <cholmod.h>
#include <stdlib.h>
#include <string.h>
#include <umfpack.h>

struct sk_solver {
    sk_solver_kind kind;
    size_t n;
    sk_solve_stats stats;
    /* Cholesky */
    cholmod_common cc;
    bool cc_started;
    cholmod_factor *L;
    bool factored;
    /* LU: UMFPACK keeps pointers to the pattern, so we keep a copy of the matrix */
    void *symbolic, *numeric;
    int *ap, *ai;
    double *ax;
    double control[UMFPACK_CONTROL];
};

/* A CHOLMOD view of our lower-stored CSC matrix (no copy). */
static cholmod_sparse cholmod_view(const sk_sparse *a)
{
    cholmod_sparse A;
    memset(&A, 0, sizeof A);
    A.nrow = a->n;
    A.ncol = a->n;
    A.nzmax = a->nnz;
    A.p = a->colptr;
    A.i = a->rowind;
    A.x = a->values;
    A.stype = -1; /* symmetric, lower triangle stored */
    A.itype = CHOLMOD_INT;
    A.xtype = CHOLMOD_REAL;
    A.dtype = CHOLMOD_DOUBLE;
    A.sorted = 1;
    A.packed = 1;
    return A;
}

static const char *cholmod_status_text(int status)
{
    switch (status) {
    case CHOLMOD_OUT_OF_MEMORY: return "out of memory";
    case CHOLMOD_TOO_LARGE: return "problem too large";
    case CHOLMOD_INVALID: return "invalid input";
    case CHOLMOD_NOT_POSDEF: return "matrix not positive definite";
    case CHOLMOD_DSMALL: return "tiny diagonal entry";
    default: return "failure";
    }
}

void sk_solver_destroy(sk_solver **sp)
{
    if (!sp || !*sp)
        return;
    sk_solver *s = *sp;
    if (s->cc_started) {
        if (s->L)
            cholmod_free_factor(&s->L, &s->cc);
        cholmod_finish(&s->cc);
    }
    if (s->numeric)
        umfpack_di_free_numeric(&s->numeric);
    if (s->symbolic)
        umfpack_di_free_symbolic(&s->symbolic);
    sk__free(s->ap);
    sk__free(s->ai);
    sk__free(s->ax);
    sk__free(s);
    *sp = NULL;
}

sk_status sk_solver_create(const sk_sparse *a, sk_solver_kind kind, sk_solver **out,
                           sk_error *err)
{
    *out = NULL;
    if (kind == SK_SOLVER_CHOLESKY && a->storage != SK_SPARSE_LOWER)
        return sk__fail(err, SK_ERR_ARG, "the Cholesky solver needs a lower-stored matrix");
    if (kind == SK_SOLVER_LU && a->storage != SK_SPARSE_FULL)
        return sk__fail(err, SK_ERR_ARG, "the LU solver needs a fully stored matrix");
    sk_solver *s = sk__calloc_array(1, sizeof *s);
    if (!s)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    s->kind = kind;
    s->n = a->n;
    s->stats.kind = kind;
    s->stats.n = a->n;
    s->stats.nnz = a->nnz;
    double t0 = sk_seconds();
    sk_status st = SK_OK;
    if (kind == SK_SOLVER_CHOLESKY) {
        cholmod_start(&s->cc);
        s->cc_started = true;
        s->cc.print = 0;
        s->cc.error_handler = NULL;
        cholmod_sparse A = cholmod_view(a);
        s->L = cholmod_analyze(&A, &s->cc);
        if (!s->L || s->cc.status < 0) {
            st = sk__fail(err, s->cc.status == CHOLMOD_OUT_OF_MEMORY ? SK_ERR_NOMEM : SK_ERR_NUMERIC,
                          "CHOLMOD analysis of a %zu x %zu matrix failed: %s", a->n, a->n,
                          cholmod_status_text(s->cc.status));
            goto done;
        }
        s->stats.factor_nnz = (size_t)s->cc.lnz;
    } else {
        size_t nnz = a->nnz;
        s->ap = sk__malloc_array(a->n + 1, sizeof(int));
        s->ai = sk__malloc_array(nnz ? nnz : 1, sizeof(int));
        s->ax = sk__malloc_array(nnz ? nnz : 1, sizeof(double));
        if (!s->ap || !s->ai || !s->ax) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        memcpy(s->ap, a->colptr, (a->n + 1) * sizeof(int));
        memcpy(s->ai, a->rowind, nnz * sizeof(int));
        memcpy(s->ax, a->values, nnz * sizeof(double));
        umfpack_di_defaults(s->control);
        s->control[UMFPACK_PRL] = 0;
        double info[UMFPACK_INFO];
        int r = umfpack_di_symbolic((int)a->n, (int)a->n, s->ap, s->ai, s->ax, &s->symbolic,
                                    s->control, info);
        if (r != UMFPACK_OK) {
            st = sk__fail(err, r == UMFPACK_ERROR_out_of_memory ? SK_ERR_NOMEM : SK_ERR_NUMERIC,
                          "UMFPACK analysis of a %zu x %zu matrix failed (status %d)", a->n, a->n,
                          r);
            goto done;
        }
    }
done:
    s->stats.analyse_seconds = sk_seconds() - t0;
    if (st)
        sk_solver_destroy(&s);
    *out = s;
    return st;
}

sk_status sk_solver_factorize(sk_solver *s, const sk_sparse *a, sk_error *err)
{
    if (a->n != s->n)
        return sk__fail(err, SK_ERR_ARG, "matrix size %zu differs from the analysed %zu", a->n, s->n);
    double t0 = sk_seconds();
    sk_status st = SK_OK;
    if (s->kind == SK_SOLVER_CHOLESKY) {
        cholmod_sparse A = cholmod_view(a);
        s->factored = false;
        int ok = cholmod_factorize(&A, s->L, &s->cc);
        if (!ok || s->cc.status != CHOLMOD_OK) {
            if (s->cc.status == CHOLMOD_NOT_POSDEF)
                st = sk__fail(err, SK_ERR_NUMERIC, "the %zu x %zu matrix is not positive definite "
                              "(Cholesky failed at column %zu)", a->n, a->n, (size_t)s->L->minor);
            else
                st = sk__fail(err, s->cc.status == CHOLMOD_OUT_OF_MEMORY ? SK_ERR_NOMEM : SK_ERR_NUMERIC,
                              "CHOLMOD factorization failed: %s", cholmod_status_text(s->cc.status));
        } else {
            s->factored = true;
            s->stats.factor_nnz = s->L->is_super ? s->L->xsize : s->L->nzmax;
        }
    } else {
        if (a->nnz != (size_t)s->ap[s->n] ||
            memcmp(a->colptr, s->ap, (s->n + 1) * sizeof(int)) ||
            memcmp(a->rowind, s->ai, a->nnz * sizeof(int)))
            return sk__fail(err, SK_ERR_ARG, "the matrix pattern differs from the analysed one");
        memcpy(s->ax, a->values, a->nnz * sizeof(double));
        if (s->numeric)
            umfpack_di_free_numeric(&s->numeric);
        double info[UMFPACK_INFO];
        int r = umfpack_di_numeric(s->ap, s->ai, s->ax, s->symbolic, &s->numeric, s->control, info);
        if (r == UMFPACK_WARNING_singular_matrix) {
            st = sk__fail(err, SK_ERR_NUMERIC, "the %zu x %zu matrix is singular", s->n, s->n);
        } else if (r != UMFPACK_OK) {
            st = sk__fail(err, r == UMFPACK_ERROR_out_of_memory ? SK_ERR_NOMEM : SK_ERR_NUMERIC,
                          "UMFPACK factorization failed (status %d)", r);
        } else {
            s->stats.factor_nnz = (size_t)(info[UMFPACK_LNZ] + info[UMFPACK_UNZ]);
        }
        if (st && s->numeric)
            umfpack_di_free_numeric(&s->numeric);
    }
    s->stats.factor_seconds += sk_seconds() - t0;
    s->stats.factorizations++;
    return st;
}

sk_status sk_solver_solve(sk_solver *s, size_t nrhs, const double *b, double *x, sk_error *err)
{
    if (nrhs == 0)
        return SK_OK;
    double t0 = sk_seconds();
    sk_status st = SK_OK;
    size_t n = s->n;
    if (s->kind == SK_SOLVER_CHOLESKY) {
        if (!s->factored)
            return sk__fail(err, SK_ERR_ARG, "solve before a successful factorization");
        cholmod_dense B;
        memset(&B, 0, sizeof B);
        B.nrow = n;
        B.ncol = nrhs;
        B.nzmax = n * nrhs;
        B.d = n;
        B.x = (void *)b;
        B.xtype = CHOLMOD_REAL;
        B.dtype = CHOLMOD_DOUBLE;
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, s->L, &B, &s->cc);
        if (!X) {
            st = sk__fail(err, SK_ERR_NUMERIC, "CHOLMOD solve failed: %s",
                          cholmod_status_text(s->cc.status));
        } else {
            memcpy(x, X->x, n * nrhs * sizeof(double));
            cholmod_free_dense(&X, &s->cc);
        }
    } else {
        if (!s->numeric)
            return sk__fail(err, SK_ERR_ARG, "solve before a successful factorization");
        int fail = 0;
        /* the numeric object is read-only during solves, so right-hand sides run in parallel */
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(| : fail) if (nrhs > 1 && n > 20000)
#endif
        for (long k = 0; k < (long)nrhs; ++k) {
            double info[UMFPACK_INFO];
            int r = umfpack_di_solve(UMFPACK_A, s->ap, s->ai, s->ax, x + (size_t)k * n,
                                     b + (size_t)k * n, s->numeric, s->control, info);
            if (r != UMFPACK_OK)
                fail |= 1;
        }
        if (fail)
            st = sk__fail(err, SK_ERR_NUMERIC, "UMFPACK solve failed");
    }
    s->stats.solve_seconds += sk_seconds() - t0;
    s->stats.solves++;
    s->stats.rhs += nrhs;
    return st;
}

void sk_solver_stats(const sk_solver *s, sk_solve_stats *stats)
{
    *stats = s->stats;
}

sk_status sk_sparse_solve(const sk_sparse *a, sk_solver_kind kind, size_t nrhs, const double *b,
                          double *x, sk_solve_stats *stats, sk_error *err)
{
    sk_solver *s = NULL;
    sk_status st = sk_solver_create(a, kind, &s, err);
    if (st == SK_OK)
        st = sk_solver_factorize(s, a, err);
    if (st == SK_OK)
        st = sk_solver_solve(s, nrhs, b, x, err);
    if (stats) {
        if (s)
            sk_solver_stats(s, stats);
        else
            memset(stats, 0, sizeof *stats);
    }
    sk_solver_destroy(&s);
    return st;
}
