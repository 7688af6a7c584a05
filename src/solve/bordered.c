/* A pair of systems with one matrix, coupled only through a border (solve/bordered.h).
 *
 * Order the unknowns interior (I) first, border (B) last, and factor the shared matrix once,
 * A = L L^T with
 *
 *     L = [ L_I      0  ]       S_0 = L_B L_B^T = A_BB - A_BI A_II^-1 A_IB,
 *         [ L_BI    L_B ],
 *
 * S_0 the Schur complement of the interior (the dense discrete Dirichlet-to-Neumann map of the
 * border). Eliminating x_I and y_I from the 2n x 2n system leaves the 2k x 2k one
 *
 *     G [x_B; y_B] = [h_f; h_g],   G = [ S_0   C  ]     h_f = f_B - A_BI A_II^-1 f_I = L_B z_B,
 *                                      [ C^T  S_0 ],
 *
 * where z = L^-1 f (the forward solve; likewise for g). G is symmetric positive definite (a
 * Schur complement of the positive definite 2n x 2n matrix), solved by dense Cholesky
 * (LAPACK). The interior then follows from one backward solve per half: with z_B replaced by
 * L_B^T x_B, L^T x = z gives the border x_B back and x_I = L_I^-T (z_I - L_BI^T x_B). So the
 * cost is one sparse factorization of the n x n matrix (instead of a 2n x 2n one with its
 * u-v couplings at the border spread through the fill), two forward and two backward solves,
 * and O(k^3) dense work on the border. */
#include "solve/bordered.h"
#include "core/internal.h"
#include "solve/solver_internal.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The leading m x m block of the lower-stored a (rows sorted, so each column's rows >= m end
 * it), for the ordering of the interior. */
static sk_status leading_block(const sk_sparse *a, size_t m, sk_sparse **out, sk_error *err)
{
    sk_sparse *b = sk__calloc_array(1, sizeof *b);
    if (!b)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    b->n = m;
    b->storage = a->storage;
    b->colptr = sk__malloc_array(m + 1, sizeof *b->colptr);
    size_t nnz = (size_t)a->colptr[m];
    b->rowind = sk__malloc_array(nnz ? nnz : 1, sizeof *b->rowind);
    b->values = sk__malloc_array(nnz ? nnz : 1, sizeof *b->values);
    if (!b->colptr || !b->rowind || !b->values) {
        sk_sparse_destroy(&b);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    size_t q = 0;
    b->colptr[0] = 0;
    for (size_t j = 0; j < m; ++j) {
        for (int p = a->colptr[j]; p < a->colptr[j + 1] && (size_t)a->rowind[p] < m; ++p) {
            b->rowind[q] = a->rowind[p];
            b->values[q++] = a->values[p];
        }
        b->colptr[j + 1] = (int)q;
    }
    b->nnz = q;
    *out = b;
    return SK_OK;
}

/* The border block L_B of the factor (the last k of its n columns), k x k column-major lower,
 * from a supernodal or a simplicial LL^T factor. */
static void border_block(const cholmod_factor *L, size_t n, size_t k, double *lb)
{
    size_t m = n - k;
    memset(lb, 0, k * k * sizeof *lb);
    const double *lx = L->x;
    if (L->is_super) {
        const int *super = L->super, *pi = L->pi, *px = L->px, *ls = L->s;
        for (size_t s = L->nsuper; s-- > 0 && (size_t)super[s + 1] > m;) {
            size_t nsrow = (size_t)(pi[s + 1] - pi[s]);
            for (size_t col = (size_t)super[s]; col < (size_t)super[s + 1]; ++col) {
                if (col < m)
                    continue;
                const double *xc = lx + px[s] + (col - (size_t)super[s]) * nsrow;
                for (size_t r = 0; r < nsrow; ++r) {
                    size_t row = (size_t)ls[pi[s] + r];
                    if (row >= col)
                        lb[(row - m) + k * (col - m)] = xc[r];
                }
            }
        }
    } else {
        const int *lp = L->p, *li = L->i, *lnz = L->nz;
        for (size_t col = m; col < n; ++col)
            for (int p = lp[col]; p < lp[col] + lnz[col]; ++p)
                if ((size_t)li[p] >= col)
                    lb[((size_t)li[p] - m) + k * (col - m)] = lx[p];
    }
}

sk_status sk__solve_bordered_pair(const sk_sparse *a, size_t k, const double *c, sk_ordering ordering,
                                  const double *b, double *x, sk_solve_stats *stats,
                                  double *ordering_seconds, double *residual, sk_error *err)
{
    size_t n = a->n;
    if (a->storage != SK_SPARSE_LOWER || k > n || n == 0)
        return sk__fail(err, SK_ERR_ARG, "a bordered pair needs a lower-stored matrix with at most "
                        "n border unknowns");
    if (ordering != SK_ORDERING_METIS && ordering != SK_ORDERING_AMD)
        return sk__fail(err, SK_ERR_ARG, "the interior of a bordered pair is ordered by METIS or AMD");
    size_t m = n - k;
    sk_status st = SK_OK;
    sk_sparse *ai = NULL;
    sk_solver *solver = NULL;
    int *perm = sk__malloc_array(n, sizeof *perm);
    double *lb = sk__malloc_array(k ? k * k : 1, sizeof *lb);
    double *g = sk__malloc_array(k ? 4 * k * k : 1, sizeof *g);
    double *h = sk__malloc_array(k ? 2 * k : 1, sizeof *h);
    int *gamma = sk__malloc_array(k ? k : 1, sizeof *gamma);
    double *ax = sk__malloc_array(n, sizeof *ax);
    cholmod_dense *y = NULL, *z = NULL, *w = NULL, *xs = NULL;
    cholmod_common *cc = NULL;
    int blas = -1;
    bool blas_serial = false;
    if (!perm || !lb || !g || !h || !gamma || !ax) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    /* the interior ordered on its own graph, the border after it */
    double t0 = sk_seconds();
    if (m > 0) {
        if ((st = leading_block(a, m, &ai, err)) ||
            (st = sk_sparse_point_ordering(ai, 1, NULL, ordering, perm, err)))
            goto done;
        sk_sparse_destroy(&ai);
    }
    for (size_t i = m; i < n; ++i)
        perm[i] = (int)i;
    if (ordering_seconds)
        *ordering_seconds = sk_seconds() - t0;
    sk_solver_opts so = {.ordering = SK_ORDERING_GIVEN, .perm = perm};
    if ((st = sk_solver_create_opts(a, SK_SOLVER_CHOLESKY, &so, &solver, err)) ||
        (st = sk_solver_factorize(solver, a, err)))
        goto done;
    cholmod_factor *L = sk__solver_cholmod(solver, &cc);
    if (!L) {
        st = sk__fail(err, SK_ERR_NUMERIC, "no Cholesky factor");
        goto done;
    }
    /* CHOLMOD's postorder of the elimination tree may move interior columns between border
     * ones (an interior part attached to the border alone); then there is no border block */
    const int *lperm = L->Perm;
    for (size_t p = m; p < n; ++p) {
        if ((size_t)lperm[p] < m) {
            st = sk__fail(err, SK_ERR_ARG, "the factorization did not keep the border last");
            goto done;
        }
        gamma[p - m] = lperm[p] - (int)m;
    }
    blas = sk__blas_serial_begin();
    blas_serial = true;
    if (!L->is_super && !L->is_ll &&
        !cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, L, cc)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory converting the factor");
        goto done;
    }
    double t1 = sk_seconds();
    /* G = [S_0 C'; C'^T S_0], C' the coupling in the factor's border order; lower triangle */
    if (k > 0) {
        border_block(L, n, k, lb);
        size_t k2 = 2 * k;
        /* S_0 = L_B L_B^T into the leading block (lower triangle), copied to the trailing one */
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, (blasint)k, (blasint)k, 1.0, lb,
                    (blasint)k, 0.0, g, (blasint)k2);
        for (size_t j = 0; j < k; ++j)
            for (size_t i = j; i < k; ++i)
                g[(k + i) + k2 * (k + j)] = g[i + k2 * j];
        for (size_t j = 0; j < k; ++j)     /* rows of the y block, columns of the x block: C'^T */
            for (size_t i = 0; i < k; ++i) /* (y_i, x_j) = C'(j, i) = C(gamma_j, gamma_i) */
                g[(k + i) + k2 * j] = c[(size_t)gamma[j] + k * (size_t)gamma[i]];
        lapack_int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', (lapack_int)k2, g, (lapack_int)k2);
        if (info != 0) {
            st = sk__fail(err, info > 0 ? SK_ERR_NUMERIC : SK_ERR_ARG,
                          "the %zu x %zu border system is not positive definite (%d)", k2, k2,
                          (int)info);
            goto done;
        }
    }
    /* forward: z = L^-1 P (f, g) */
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = n;
    B.ncol = 2;
    B.nzmax = 2 * n;
    B.d = n;
    B.x = (void *)b;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (!(y = cholmod_solve(CHOLMOD_P, L, &B, cc)) || !(z = cholmod_solve(CHOLMOD_L, L, y, cc))) {
        st = sk__fail(err, SK_ERR_NOMEM, "CHOLMOD solve failed");
        goto done;
    }
    if (k > 0) {
        double *zx = z->x;
        size_t d = z->d;
        for (size_t half = 0; half < 2; ++half) /* h = L_B z_B */
            for (size_t i = 0; i < k; ++i) {
                double s = 0;
                for (size_t l = 0; l <= i; ++l)
                    s += lb[i + k * l] * zx[m + l + d * half];
                h[i + k * half] = s;
            }
        lapack_int info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', (lapack_int)(2 * k), 1, g,
                                         (lapack_int)(2 * k), h, (lapack_int)(2 * k));
        if (info != 0) {
            st = sk__fail(err, SK_ERR_ARG, "border solve failed (%d)", (int)info);
            goto done;
        }
        for (size_t half = 0; half < 2; ++half) /* z_B = L_B^T (x_B or y_B) */
            for (size_t i = 0; i < k; ++i) {
                double s = 0;
                for (size_t l = i; l < k; ++l)
                    s += lb[l + k * i] * h[l + k * half];
                zx[m + i + d * half] = s;
            }
    }
    /* backward: x = P^T L^-T z */
    if (!(w = cholmod_solve(CHOLMOD_Lt, L, z, cc)) || !(xs = cholmod_solve(CHOLMOD_Pt, L, w, cc))) {
        st = sk__fail(err, SK_ERR_NOMEM, "CHOLMOD solve failed");
        goto done;
    }
    for (size_t half = 0; half < 2; ++half)
        memcpy(x + half * n, (const double *)xs->x + half * xs->d, n * sizeof *x);
    double t2 = sk_seconds();
    sk__blas_serial_end(blas);
    blas_serial = false;
    if (stats) {
        sk_solver_stats(solver, stats);
        stats->n = 2 * n;
        stats->solve_seconds += t2 - t1;
        stats->solves++;
        stats->rhs += 1;
    }
    /* the residual of the 2n x 2n system */
    if (residual) {
        double rr = 0, bb = 0;
        for (size_t half = 0; half < 2; ++half) {
            sk_sparse_multiply(a, x + half * n, ax);
            const double *other = x + (1 - half) * n + m;
            for (size_t i = 0; i < k; ++i) { /* x block: + C y_B; y block: + C^T x_B */
                double s = 0;
                for (size_t j = 0; j < k; ++j)
                    s += (half == 0 ? c[i + k * j] : c[j + k * i]) * other[j];
                ax[m + i] += s;
            }
            for (size_t i = 0; i < n; ++i) {
                double r = b[half * n + i] - ax[i];
                rr += r * r;
                bb += b[half * n + i] * b[half * n + i];
            }
        }
        *residual = bb > 0 ? sqrt(rr / bb) : 0;
    }
done:
    if (blas_serial)
        sk__blas_serial_end(blas);
    if (cc) {
        cholmod_free_dense(&y, cc);
        cholmod_free_dense(&z, cc);
        cholmod_free_dense(&w, cc);
        cholmod_free_dense(&xs, cc);
    }
    sk_solver_destroy(&solver);
    sk_sparse_destroy(&ai);
    sk__free(perm);
    sk__free(lb);
    sk__free(g);
    sk__free(h);
    sk__free(gamma);
    sk__free(ax);
    return st;
}
