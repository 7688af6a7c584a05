/* Sparse assembly and the CHOLMOD / UMFPACK wrappers. */
#include "testutil.h"

#include "surfkit/solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* given triplets with duplicates, when assembled, then duplicates are summed and rows sorted */
static void test_triplets_to_csc(void **state)
{
    (void)state;
    sk_triplets t = {0};
    assert_int_equal(sk_triplets_add(&t, 2, 0, 1.0), SK_OK);
    assert_int_equal(sk_triplets_add(&t, 0, 0, 4.0), SK_OK);
    assert_int_equal(sk_triplets_add(&t, 2, 0, 2.5), SK_OK);
    assert_int_equal(sk_triplets_add(&t, 1, 1, 3.0), SK_OK);
    assert_int_equal(sk_triplets_add(&t, 0, 2, 7.0), SK_OK);
    assert_int_equal(sk_triplets_add(&t, 0, 0, 1.0), SK_OK);
    sk_sparse *a = NULL;
    assert_int_equal(sk_sparse_from_triplets(3, &t, SK_SPARSE_FULL, &a, NULL), SK_OK);
    assert_int_equal(a->nnz, 4);
    int cp[4] = {0, 2, 3, 4}, ri[4] = {0, 2, 1, 0};
    double vals[4] = {5.0, 3.5, 3.0, 7.0};
    for (int k = 0; k < 4; ++k) {
        assert_int_equal(a->colptr[k], cp[k]);
        assert_int_equal(a->rowind[k], ri[k]);
        assert_true(a->values[k] == vals[k]);
    }
    /* same pattern, new values */
    for (size_t k = 0; k < t.count; ++k)
        t.values[k] *= 2;
    assert_int_equal(sk_sparse_update_values(a, &t, NULL), SK_OK);
    assert_true(a->values[0] == 10.0 && a->values[1] == 7.0);
    sk_sparse_destroy(&a);
    /* lower storage drops the (0, 2) entry */
    assert_int_equal(sk_sparse_from_triplets(3, &t, SK_SPARSE_LOWER, &a, NULL), SK_OK);
    assert_int_equal(a->nnz, 3);
    sk_sparse_destroy(&a);
    /* out of range */
    sk_error err;
    assert_int_equal(sk_triplets_add(&t, 5, 0, 1.0), SK_OK);
    assert_int_equal(sk_sparse_from_triplets(3, &t, SK_SPARSE_FULL, &a, &err), SK_ERR_ARG);
    assert_null(a);
    assert_non_null(strstr(err.message, "outside"));
    sk_triplets_free(&t);
}

/* 1D Laplacian with Dirichlet ends: tridiag(-1, 2, -1), SPD */
static sk_sparse *laplacian_1d(size_t n, double diag, sk_sparse_storage storage, sk_triplets *t)
{
    sk_triplets_clear(t);
    for (uint32_t i = 0; i < n; ++i) {
        sk_triplets_add(t, i, i, diag);
        if (i > 0)
            sk_triplets_add(t, i, i - 1, -1.0);
        if (i + 1 < n)
            sk_triplets_add(t, i, i + 1, -1.0);
    }
    sk_sparse *a = NULL;
    assert_int_equal(sk_sparse_from_triplets(n, t, storage, &a, NULL), SK_OK);
    return a;
}

static double max_residual(const sk_sparse *a, const double *x, const double *b)
{
    double *y = malloc(a->n * sizeof *y), r = 0;
    sk_sparse_multiply(a, x, y);
    for (size_t i = 0; i < a->n; ++i)
        r = fmax(r, fabs(y[i] - b[i]));
    free(y);
    return r;
}

/* given an SPD matrix, when analysed once and factorized twice, then both solves with two
 * right-hand sides are accurate and the stats add up */
static void test_cholesky_refactor(void **state)
{
    (void)state;
    size_t n = 500;
    sk_triplets t = {0};
    sk_sparse *a = laplacian_1d(n, 2.0, SK_SPARSE_LOWER, &t);
    double *b = malloc(2 * n * sizeof *b), *x = malloc(2 * n * sizeof *x);
    for (size_t i = 0; i < n; ++i) {
        b[i] = 1.0;
        b[n + i] = sin((double)i);
    }
    sk_solver *s = NULL;
    assert_int_equal(sk_solver_create(a, SK_SOLVER_CHOLESKY, &s, NULL), SK_OK);
    assert_int_equal(sk_solver_factorize(s, a, NULL), SK_OK);
    assert_int_equal(sk_solver_solve(s, 2, b, x, NULL), SK_OK);
    assert_true(max_residual(a, x, b) < 1e-9);
    assert_true(max_residual(a, x + n, b + n) < 1e-9);
    /* x_i = i (n + 1 - i) / 2 - ... : check the known solution of the first column */
    for (size_t i = 0; i < n; ++i)
        assert_true(fabs(x[i] - 0.5 * (double)(i + 1) * (double)(n - i)) < 1e-6 * n * n);
    /* new values, same pattern */
    for (size_t k = 0; k < t.count; ++k)
        if (t.rows[k] == t.cols[k])
            t.values[k] = 3.0;
    assert_int_equal(sk_sparse_update_values(a, &t, NULL), SK_OK);
    assert_int_equal(sk_solver_factorize(s, a, NULL), SK_OK);
    assert_int_equal(sk_solver_solve(s, 2, b, x, NULL), SK_OK);
    assert_true(max_residual(a, x, b) < 1e-12 * n);
    sk_solve_stats st;
    sk_solver_stats(s, &st);
    assert_int_equal(st.n, n);
    assert_int_equal(st.nnz, 2 * n - 1);
    assert_true(st.factor_nnz >= 2 * n - 1);
    assert_int_equal(st.factorizations, 2);
    assert_int_equal(st.rhs, 4);
    assert_true(st.analyse_seconds >= 0 && st.factor_seconds >= 0 && st.solve_seconds >= 0);
    sk_solver_destroy(&s);
    assert_null(s);
    sk_sparse_destroy(&a);
    /* indefinite: diag 1 gives negative eigenvalues */
    a = laplacian_1d(50, 1.0, SK_SPARSE_LOWER, &t);
    sk_error err;
    assert_int_equal(sk_sparse_solve(a, SK_SOLVER_CHOLESKY, 1, b, x, NULL, &err), SK_ERR_NUMERIC);
    assert_non_null(strstr(err.message, "not positive definite"));
    sk_sparse_destroy(&a);
    sk_triplets_free(&t);
    free(b);
    free(x);
}

/* given a non-symmetric matrix, when solved by LU, then the residual is tiny; a singular one
 * is reported */
static void test_lu(void **state)
{
    (void)state;
    size_t n = 300;
    sk_triplets t = {0};
    for (uint32_t i = 0; i < n; ++i) {
        sk_triplets_add(&t, i, i, 4.0);
        if (i > 0)
            sk_triplets_add(&t, i, i - 1, -1.5);
        if (i + 1 < n)
            sk_triplets_add(&t, i, i + 1, -0.5);
        sk_triplets_add(&t, i, (i * 7) % (uint32_t)n, 0.25);
    }
    sk_sparse *a = NULL;
    assert_int_equal(sk_sparse_from_triplets(n, &t, SK_SPARSE_FULL, &a, NULL), SK_OK);
    double *b = malloc(2 * n * sizeof *b), *x = malloc(2 * n * sizeof *x);
    for (size_t i = 0; i < 2 * n; ++i)
        b[i] = cos((double)i);
    sk_solve_stats st;
    assert_int_equal(sk_sparse_solve(a, SK_SOLVER_LU, 2, b, x, &st, NULL), SK_OK);
    assert_true(max_residual(a, x, b) < 1e-12);
    assert_true(max_residual(a, x + n, b + n) < 1e-12);
    assert_int_equal(st.kind, SK_SOLVER_LU);
    assert_true(st.factor_nnz >= n);
    sk_sparse_destroy(&a);
    /* wrong storage for the solver */
    assert_int_equal(sk_sparse_from_triplets(n, &t, SK_SPARSE_LOWER, &a, NULL), SK_OK);
    sk_solver *s = NULL;
    assert_int_equal(sk_solver_create(a, SK_SOLVER_LU, &s, NULL), SK_ERR_ARG);
    sk_sparse_destroy(&a);
    /* singular: a zero column */
    sk_triplets_clear(&t);
    sk_triplets_add(&t, 0, 0, 1.0);
    sk_triplets_add(&t, 1, 0, 1.0);
    sk_triplets_add(&t, 2, 2, 1.0);
    assert_int_equal(sk_sparse_from_triplets(3, &t, SK_SPARSE_FULL, &a, NULL), SK_OK);
    sk_error err;
    assert_int_equal(sk_sparse_solve(a, SK_SOLVER_LU, 1, b, x, NULL, &err), SK_ERR_NUMERIC);
    assert_non_null(strstr(err.message, "singular"));
    sk_sparse_destroy(&a);
    sk_triplets_free(&t);
    free(b);
    free(x);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_triplets_to_csc),
        cmocka_unit_test(test_cholesky_refactor),
        cmocka_unit_test(test_lu),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
