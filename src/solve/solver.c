/* Direct solvers: CHOLMOD for symmetric positive definite matrices, UMFPACK for general ones,
 * both with the analyse once / factorize (again) / solve split that Botsch, Bommes and Kobbelt
 * recommend for mesh systems. The library never prints: CHOLMOD's printing is switched off and
 * every failure comes back as an sk_status with a message. */
#include "surfkit/solve.h"
#include "core/internal.h"
#include "solve/solver_internal.h"

#include <cholmod.h>
#include <limits.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <umfpack.h>
#if defined(SK_HAVE_OPENMP)
#include <omp.h>
#endif

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
    return sk_solver_create_opts(a, kind, NULL, out, err);
}

/* SK_ORDERING_DEFAULT, from bench/solve.sh on the systems of a 1M-triangle disk (docs/linear.md):
 *   Cholesky: CHOLMOD's own choice (AMD there; METIS when AMD fills badly). METIS has 34% fewer
 *     factor entries, but its analysis costs about 2.3 s more CPU than the factorization saves
 *     for the single factorization of a linear method.
 *   LU: METIS. 36% fewer factor entries than UMFPACK's default AMD and 15% less peak memory
 *     (Floater / mean value at 1M triangles under 1 GB), CPU time the same within the noise. */
static sk_ordering default_ordering(sk_solver_kind kind)
{
    return kind == SK_SOLVER_CHOLESKY ? SK_ORDERING_AUTO : SK_ORDERING_METIS;
}

static void cholmod_ordering(cholmod_common *cc, sk_ordering o)
{
    switch (o) {
    case SK_ORDERING_DEFAULT:
    case SK_ORDERING_AUTO: break; /* nmethods = 0: AMD, METIS if AMD fills badly */
    case SK_ORDERING_AMD:
        cc->nmethods = 1;
        cc->method[0].ordering = CHOLMOD_AMD;
        break;
    case SK_ORDERING_METIS:
        cc->nmethods = 1;
        cc->method[0].ordering = CHOLMOD_METIS;
        break;
    case SK_ORDERING_NESDIS:
        cc->nmethods = 1;
        cc->method[0].ordering = CHOLMOD_NESDIS;
        break;
    case SK_ORDERING_BEST:
        cc->nmethods = 9; /* every ordering CHOLMOD has, the best kept */
        break;
    case SK_ORDERING_GIVEN:
    case SK_ORDERING_GEOMETRIC: /* refused by sk_solver_create_opts */
        cc->nmethods = 1;
        cc->method[0].ordering = CHOLMOD_GIVEN;
        break;
    }
}

/* METIS is not reentrant here: two METIS_NodeND calls at once (charts of the atlas ordered on the
 * threads of its parallel loop) give orderings that change from run to run, hence other factors
 * and other rounding in the solutions (bunny00's two largest LSCM charts: different uv bits on
 * every run with 2 threads, the same with 1 or with the calls serialized; the state of METIS's
 * random generator is process-wide). So every call that may run METIS (cholmod_metis,
 * CHOLMOD's analysis with its own choice or METIS / NESDIS, UMFPACK's METIS-based orderings)
 * holds one process-wide mutex (a plain pthread mutex, so that it also serializes threads of the
 * caller's own and builds without OpenMP); AMD, CAMD and given orderings run unlocked. */
static pthread_mutex_t metis_mutex = PTHREAD_MUTEX_INITIALIZER;

void sk__metis_lock(void)
{
    pthread_mutex_lock(&metis_mutex);
}

void sk__metis_unlock(void)
{
    pthread_mutex_unlock(&metis_mutex);
}

static bool may_run_metis(sk_solver_kind kind, sk_ordering o)
{
    switch (o) {
    case SK_ORDERING_AUTO: return kind == SK_SOLVER_CHOLESKY; /* CHOLMOD: METIS if AMD fills badly */
    case SK_ORDERING_METIS:
    case SK_ORDERING_NESDIS:
    case SK_ORDERING_BEST: return true;
    case SK_ORDERING_DEFAULT:
    case SK_ORDERING_AMD:
    case SK_ORDERING_GIVEN:
    case SK_ORDERING_GEOMETRIC: break;
    }
    return false;
}

static double umfpack_ordering(sk_ordering o)
{
    switch (o) {
    case SK_ORDERING_METIS: return UMFPACK_ORDERING_METIS;
    case SK_ORDERING_NESDIS: return UMFPACK_ORDERING_CHOLMOD;
    case SK_ORDERING_BEST: return UMFPACK_ORDERING_BEST;
    case SK_ORDERING_GIVEN:
    case SK_ORDERING_GEOMETRIC: return UMFPACK_ORDERING_GIVEN;
    case SK_ORDERING_AMD:
    case SK_ORDERING_AUTO:
    case SK_ORDERING_DEFAULT: break;
    }
    return UMFPACK_ORDERING_AMD;
}

sk_status sk_solver_create_opts(const sk_sparse *a, sk_solver_kind kind,
                                const sk_solver_opts *opts, sk_solver **out, sk_error *err)
{
    sk_ordering ord = opts ? opts->ordering : SK_ORDERING_DEFAULT;
    if (ord == SK_ORDERING_DEFAULT)
        ord = default_ordering(kind);
    *out = NULL;
    int *perm = NULL; /* a copy: CHOLMOD and UMFPACK take non-const pointers */
    if (ord == SK_ORDERING_GIVEN && (!opts->perm || a->n > (size_t)INT_MAX))
        return sk__fail(err, SK_ERR_ARG, "SK_ORDERING_GIVEN without a permutation");
    if (ord == SK_ORDERING_GEOMETRIC)
        return sk__fail(err, SK_ERR_ARG, "the geometric ordering needs the points: compute it "
                        "with sk_sparse_point_ordering and pass it as SK_ORDERING_GIVEN");
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
    if (ord == SK_ORDERING_GIVEN) {
        perm = sk__malloc_array(a->n ? a->n : 1, sizeof *perm);
        uint8_t *seen = sk__calloc_array(a->n ? a->n : 1, 1);
        bool valid = perm && seen;
        for (size_t k = 0; valid && k < a->n; ++k) {
            int p = opts->perm[k];
            valid = p >= 0 && (size_t)p < a->n && !seen[p];
            if (valid)
                seen[p] = 1;
            perm[k] = p;
        }
        bool nomem = !perm || !seen;
        sk__free(seen);
        if (!valid) {
            st = nomem ? sk__fail(err, SK_ERR_NOMEM, "out of memory")
                       : sk__fail(err, SK_ERR_ARG, "the given ordering is not a permutation of "
                                  "0..%zu", a->n - 1);
            goto done;
        }
    }
    if (kind == SK_SOLVER_CHOLESKY) {
        cholmod_start(&s->cc);
        s->cc_started = true;
        s->cc.print = 0;
        s->cc.error_handler = NULL;
        cholmod_ordering(&s->cc, ord);
        if (opts && opts->simplicial)
            s->cc.supernodal = CHOLMOD_SIMPLICIAL;
        cholmod_sparse A = cholmod_view(a);
        bool lock = may_run_metis(kind, ord);
        if (lock)
            sk__metis_lock();
        s->L = perm ? cholmod_analyze_p(&A, perm, NULL, 0, &s->cc) : cholmod_analyze(&A, &s->cc);
        if (lock)
            sk__metis_unlock();
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
        s->control[UMFPACK_ORDERING] = umfpack_ordering(ord);
        if (perm) /* the given order is symmetric (of A + A^T): rows follow the columns */
            s->control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;
        double info[UMFPACK_INFO];
        bool lock = may_run_metis(kind, ord);
        if (lock)
            sk__metis_lock();
        int r = perm ? umfpack_di_qsymbolic((int)a->n, (int)a->n, s->ap, s->ai, s->ax, perm,
                                            &s->symbolic, s->control, info)
                     : umfpack_di_symbolic((int)a->n, (int)a->n, s->ap, s->ai, s->ax,
                                           &s->symbolic, s->control, info);
        if (lock)
            sk__metis_unlock();
        if (r != UMFPACK_OK) {
            st = sk__fail(err, r == UMFPACK_ERROR_out_of_memory ? SK_ERR_NOMEM : SK_ERR_NUMERIC,
                          "UMFPACK analysis of a %zu x %zu matrix failed (status %d)", a->n, a->n,
                          r);
            goto done;
        }
    }
done:
    sk__free(perm);
    s->stats.analyse_seconds = sk_seconds() - t0;
    if (st)
        sk_solver_destroy(&s);
    *out = s;
    return st;
}

static sk_status factorize(sk_solver *s, const sk_sparse *a, sk_error *err)
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

static sk_status solve(sk_solver *s, size_t nrhs, const double *b, double *x, sk_error *err)
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

/* The factor and the solves run with one BLAS thread: on this project's 2-core machine, the 1M
 * lion-head (Loop x3) costs the same wall time with one as with the default two (LSCM 9.86 against
 * 9.80 s, Floater 8.06 / 8.13, Tutte 4.53 / 4.64, at load 1) and 2.5 s less CPU, the second
 * thread spinning in sched_yield between CHOLMOD's supernode calls; at load 10-20 one is faster
 * (docs/linear.md). */
/* CHOLMOD's supernodal factorization opens OpenMP teams of CHOLMOD_OMP_NUM_THREADS threads (4,
 * fixed when the library was built) for its scatter loops, whatever OMP_NUM_THREADS says; inside
 * a parallel loop (the atlas's charts on two threads) they are nested and run on one thread, but
 * outside one (every solve with OMP_NUM_THREADS=1, where the chart loop's team of one is not
 * active) three more threads spin between supernodes: the atlas of lion-head Loop x1 took 10.4 s
 * of CPU on one thread, 2.9 s with OMP_THREAD_LIMIT=1 and 3.4 s on two. So the factorization runs
 * with no further active level, and restores the caller's setting; the loops' results do not
 * depend on their threads (disjoint writes). Returns the setting to restore, -1 for none. */
static int cholmod_teams_off(void)
{
#if defined(SK_HAVE_OPENMP)
    if (omp_in_parallel())
        return -1; /* nested: single already, and the setting is not ours to change from here */
    int saved = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
    return saved;
#else
    return -1;
#endif
}

static void cholmod_teams_restore(int saved)
{
#if defined(SK_HAVE_OPENMP)
    if (saved >= 0)
        omp_set_max_active_levels(saved);
#else
    (void)saved;
#endif
}

sk_status sk_solver_factorize(sk_solver *s, const sk_sparse *a, sk_error *err)
{
    int blas = sk__blas_serial_begin();
    int teams = s->kind == SK_SOLVER_CHOLESKY ? cholmod_teams_off() : -1;
    sk_status st = factorize(s, a, err);
    cholmod_teams_restore(teams);
    sk__blas_serial_end(blas);
    return st;
}

sk_status sk_solver_solve(sk_solver *s, size_t nrhs, const double *b, double *x, sk_error *err)
{
    int blas = sk__blas_serial_begin();
    sk_status st = solve(s, nrhs, b, x, err);
    sk__blas_serial_end(blas);
    return st;
}

cholmod_factor *sk__solver_cholmod(sk_solver *s, cholmod_common **cc)
{
    if (s->kind != SK_SOLVER_CHOLESKY || !s->factored)
        return NULL;
    *cc = &s->cc;
    return s->L;
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
