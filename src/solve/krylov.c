/* Multilevel-preconditioned Krylov solvers (see krylov.h): Galerkin coarse operators over given
 * prolongations, a Gauss-Seidel V-cycle with a direct solve on the coarsest level, conjugate
 * gradients (Hestenes & Stiefel) for symmetric positive definite systems and BiCGStab (van der
 * Vorst 1992) with right preconditioning for the others, and nested iteration from the coarsest
 * level up (the "cascadic" start: every level begins from the prolonged solution below it). */
#include "solve/krylov.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#if defined(SK_HAVE_OPENMP)
#include <omp.h>
#endif

/* Gauss-Seidel sweeps before and after the coarse correction. */
#define SK_MG_SWEEPS 1

void sk__csr_free(sk__csr *a)
{
    if (!a)
        return;
    sk__free(a->ptr);
    sk__free(a->col);
    sk__free(a->val);
    memset(a, 0, sizeof *a);
}

sk_status sk__csr_alloc(sk__csr *a, size_t rows, size_t cols, size_t nnz, sk_error *err)
{
    memset(a, 0, sizeof *a);
    a->rows = rows;
    a->cols = cols;
    a->ptr = sk__calloc_array(rows + 1, sizeof *a->ptr);
    a->col = sk__malloc_array(nnz ? nnz : 1, sizeof *a->col);
    a->val = sk__malloc_array(nnz ? nnz : 1, sizeof *a->val);
    if (!a->ptr || !a->col || !a->val) {
        sk__csr_free(a);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu matrix with %zu entries",
                        rows, cols, nnz);
    }
    return SK_OK;
}

sk_status sk__csr_from_sparse(const sk_sparse *a, sk__csr *out, sk_error *err)
{
    size_t n = a->n;
    bool lower = a->storage == SK_SPARSE_LOWER;
    size_t nnz = 0;
    for (size_t c = 0; c < n; ++c)
        for (int k = a->colptr[c]; k < a->colptr[c + 1]; ++k)
            nnz += (lower && (size_t)a->rowind[k] != c) ? 2 : 1;
    sk_status st = sk__csr_alloc(out, n, n, nnz, err);
    if (st)
        return st;
    size_t *next = out->ptr + 1; /* counts, then insertion positions shifted by one */
    for (size_t c = 0; c < n; ++c)
        for (int k = a->colptr[c]; k < a->colptr[c + 1]; ++k) {
            size_t r = (size_t)a->rowind[k];
            next[r]++;
            if (lower && r != c)
                next[c]++;
        }
    for (size_t i = 0; i < n; ++i)
        out->ptr[i + 1] += out->ptr[i];
    size_t *pos = sk__malloc_array(n ? n : 1, sizeof *pos);
    if (!pos) {
        sk__csr_free(out);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memcpy(pos, out->ptr, n * sizeof *pos);
    /* columns in increasing order: every row receives its columns sorted (for a lower-stored
     * matrix row c gets its mirrored entries, all right of the diagonal, while column c is
     * visited, after everything left of it and before anything later) */
    for (size_t c = 0; c < n; ++c)
        for (int k = a->colptr[c]; k < a->colptr[c + 1]; ++k) {
            size_t r = (size_t)a->rowind[k];
            double v = a->values[k];
            out->col[pos[r]] = (uint32_t)c;
            out->val[pos[r]++] = v;
            if (lower && r != c) {
                out->col[pos[c]] = (uint32_t)r;
                out->val[pos[c]++] = v;
            }
        }
    sk__free(pos);
    return SK_OK;
}

sk_status sk__csr_transpose(const sk__csr *a, sk__csr *out, sk_error *err)
{
    size_t nnz = a->ptr[a->rows];
    sk_status st = sk__csr_alloc(out, a->cols, a->rows, nnz, err);
    if (st)
        return st;
    for (size_t k = 0; k < nnz; ++k)
        out->ptr[a->col[k] + 1]++;
    for (size_t j = 0; j < a->cols; ++j)
        out->ptr[j + 1] += out->ptr[j];
    size_t *pos = sk__malloc_array(a->cols ? a->cols : 1, sizeof *pos);
    if (!pos) {
        sk__csr_free(out);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memcpy(pos, out->ptr, a->cols * sizeof *pos);
    for (size_t i = 0; i < a->rows; ++i)
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            size_t p = pos[a->col[k]]++;
            out->col[p] = (uint32_t)i;
            out->val[p] = a->val[k];
        }
    sk__free(pos);
    return SK_OK;
}

/* Row `row` of a * b (Gustavson) with the dense accumulator acc / mark over the columns of b:
 * its columns into list, sorted (the values in acc by column); returns their count. */
static size_t product_row(const sk__csr *a, const sk__csr *b, size_t row, double *acc,
                          size_t *mark, uint32_t *list)
{
    size_t len = 0;
    for (size_t ka = a->ptr[row]; ka < a->ptr[row + 1]; ++ka) {
        size_t i = a->col[ka];
        double av = a->val[ka];
        for (size_t kb = b->ptr[i]; kb < b->ptr[i + 1]; ++kb) {
            uint32_t q = b->col[kb];
            if (mark[q] != row) {
                mark[q] = row;
                acc[q] = 0;
                list[len++] = q;
            }
            acc[q] += av * b->val[kb];
        }
    }
    /* sort the columns of the row (short lists: insertion sort) */
    for (size_t s = 1; s < len; ++s) {
        uint32_t key = list[s];
        size_t t = s;
        for (; t > 0 && list[t - 1] > key; --t)
            list[t] = list[t - 1];
        list[t] = key;
    }
    return len;
}

/* The rows of a product taken by one block: its entries, in row order. */
typedef struct product_block {
    uint32_t *col;
    double *val;
    size_t len, cap;
} product_block;

/* The row with columns list[0..len) and values acc[list[s]] appended to blk; false: out of
 * memory (blk keeps what it had). */
static bool block_append(product_block *blk, const uint32_t *list, const double *acc, size_t len)
{
    if (blk->len + len > blk->cap) {
        size_t ncap = 2 * blk->cap + len + 1024;
        uint32_t *c2 = sk__realloc_array(blk->col, ncap, sizeof *c2);
        if (c2)
            blk->col = c2;
        double *v2 = c2 ? sk__realloc_array(blk->val, ncap, sizeof *v2) : NULL;
        if (v2)
            blk->val = v2;
        if (!c2 || !v2)
            return false;
        blk->cap = ncap;
    }
    for (size_t s = 0; s < len; ++s) {
        blk->col[blk->len + s] = list[s];
        blk->val[blk->len + s] = acc[list[s]];
    }
    blk->len += len;
    return true;
}

/* Rows [r0, r1) of a * b appended to blk, their lengths into rowlen[row]; false: out of memory. */
static bool product_rows(const sk__csr *a, const sk__csr *b, size_t r0, size_t r1, double *acc,
                         size_t *mark, uint32_t *list, product_block *blk, size_t *rowlen)
{
    for (size_t row = r0; row < r1; ++row) {
        size_t len = product_row(a, b, row, acc, mark, list);
        if (!block_append(blk, list, acc, len))
            return false;
        rowlen[row] = len;
    }
    return true;
}

/* Blocks of rows of a product computed in parallel (a fixed count: the result does not depend
 * on the threads), from this many rows on. */
#define SK_PRODUCT_BLOCKS 16
#define SK_PRODUCT_PARALLEL_ROWS 20000

/* Row-by-row product (Gustavson): blocks of rows in parallel, each into its own buffer, then
 * joined in row order. */
/* The row blocks blk[0..nb) concatenated into out's columns and values (freed here; out->ptr
 * holds the row lengths, summed into offsets); false when fail is set or memory runs out (out is
 * freed then). */
static bool gather_blocks(product_block *blk, size_t nb, bool fail, sk__csr *out)
{
    size_t nnz = 0;
    for (size_t k = 0; k < nb; ++k)
        nnz += blk[k].len;
    if (!fail) {
        out->col = sk__malloc_array(nnz ? nnz : 1, sizeof *out->col);
        out->val = sk__malloc_array(nnz ? nnz : 1, sizeof *out->val);
        fail = !out->col || !out->val;
    }
    for (size_t k = 0, at = 0; !fail && k < nb; at += blk[k++].len) {
        if (blk[k].len) {
            memcpy(out->col + at, blk[k].col, blk[k].len * sizeof *out->col);
            memcpy(out->val + at, blk[k].val, blk[k].len * sizeof *out->val);
        }
    }
    for (size_t k = 0; k < nb; ++k) {
        sk__free(blk[k].col);
        sk__free(blk[k].val);
    }
    if (fail) {
        sk__csr_free(out);
        return false;
    }
    for (size_t row = 0; row < out->rows; ++row)
        out->ptr[row + 1] += out->ptr[row];
    return true;
}

sk_status sk__csr_product(const sk__csr *a, const sk__csr *b, sk__csr *out, sk_error *err)
{
    size_t nr = a->rows, nc = b->cols;
    memset(out, 0, sizeof *out);
    if (a->cols != b->rows)
        return sk__fail(err, SK_ERR_ARG, "matrix product of %zu x %zu and %zu x %zu", a->rows,
                        a->cols, b->rows, b->cols);
    size_t nb = nr >= SK_PRODUCT_PARALLEL_ROWS ? SK_PRODUCT_BLOCKS : 1;
    product_block blk[SK_PRODUCT_BLOCKS];
    memset(blk, 0, sizeof blk);
    out->rows = nr;
    out->cols = nc;
    out->ptr = sk__calloc_array(nr + 1, sizeof *out->ptr);
    int fail = !out->ptr;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel reduction(| : fail) if (nb > 1)
#endif
    {
        double *acc = sk__malloc_array(nc ? nc : 1, sizeof *acc);
        size_t *mark = sk__malloc_array(nc ? nc : 1, sizeof *mark);
        uint32_t *list = sk__malloc_array(nc ? nc : 1, sizeof *list);
        int bad = !acc || !mark || !list;
        for (size_t q = 0; !bad && q < nc; ++q)
            mark[q] = SIZE_MAX;
#if defined(SK_HAVE_OPENMP)
#pragma omp for schedule(dynamic, 1)
#endif
        for (long k = 0; k < (long)nb; ++k)
            if (!bad && out->ptr)
                bad = !product_rows(a, b, (size_t)k * nr / nb, (size_t)(k + 1) * nr / nb, acc,
                                    mark, list, &blk[k], out->ptr + 1);
        fail |= bad;
        sk__free(acc);
        sk__free(mark);
        sk__free(list);
    }
    if (!gather_blocks(blk, nb, fail, out))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu matrix product", nr, nc);
    return SK_OK;
}

sk_status sk__csr_galerkin(const sk__csr *r, const sk__csr *a, const sk__csr *p, sk__csr *out,
                           sk_error *err)
{
    sk__csr ap = {0};
    sk_status st = sk__csr_product(a, p, &ap, err);
    if (st == SK_OK)
        st = sk__csr_product(r, &ap, out, err);
    sk__csr_free(&ap);
    return st;
}

/* Scratch of one thread of sk__csr_galerkin_map: per coarse column an accumulator, a mark and
 * a list, for the product row A P (inner) and the row of P^T (A P) (outer). */
typedef struct galerkin_scratch {
    double *iacc, *oacc;
    size_t *imark, *omark;
    uint32_t *ilist, *olist;
} galerkin_scratch;

/* Coarse rows [r0, r1) of P^T A P into blk (see sk__csr_galerkin_map); false: out of memory. */
static bool galerkin_rows(const sk__csr *a, const uint32_t *map, const size_t *start,
                          const uint32_t *members, size_t r0, size_t r1, galerkin_scratch *g,
                          product_block *blk, size_t *rowlen)
{
    for (size_t row = r0; row < r1; ++row) {
        size_t olen = 0;
        for (size_t m = start[row]; m < start[row + 1]; ++m) {
            uint32_t i = members[m];
            size_t ilen = 0;
            /* row i of A P: the entries of row i of A summed by the aggregate of their column, in
             * column order (product_row with P's one entry 1 per row) */
            for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
                uint32_t q = map[a->col[k]];
                if (g->imark[q] != i) {
                    g->imark[q] = i;
                    g->iacc[q] = 0;
                    g->ilist[ilen++] = q;
                }
                g->iacc[q] += a->val[k] * 1.0;
            }
            /* added into the coarse row (R's entry 1 times it), the members in increasing order
             * as R = P^T lists them */
            for (size_t s = 0; s < ilen; ++s) {
                uint32_t q = g->ilist[s];
                if (g->omark[q] != row) {
                    g->omark[q] = row;
                    g->oacc[q] = 0;
                    g->olist[olen++] = q;
                }
                g->oacc[q] += 1.0 * g->iacc[q];
            }
        }
        for (size_t s = 1; s < olen; ++s) { /* sorted columns (insertion sort, as product_row) */
            uint32_t key = g->olist[s];
            size_t t = s;
            for (; t > 0 && g->olist[t - 1] > key; --t)
                g->olist[t] = g->olist[t - 1];
            g->olist[t] = key;
        }
        if (!block_append(blk, g->olist, g->oacc, olen))
            return false;
        rowlen[row] = olen;
    }
    return true;
}

sk_status sk__csr_galerkin_map(const sk__csr *a, const uint32_t *map, size_t nc, sk__csr *out,
                               sk_error *err)
{
    size_t n = a->rows;
    memset(out, 0, sizeof *out);
    size_t *start = sk__calloc_array(nc + 1, sizeof *start);
    uint32_t *members = sk__malloc_array(n ? n : 1, sizeof *members);
    out->rows = out->cols = nc;
    out->ptr = sk__calloc_array(nc + 1, sizeof *out->ptr);
    int fail = !start || !members || !out->ptr;
    size_t nb = nc >= SK_PRODUCT_PARALLEL_ROWS / 4 ? SK_PRODUCT_BLOCKS : 1;
    product_block blk[SK_PRODUCT_BLOCKS];
    memset(blk, 0, sizeof blk);
    if (!fail) { /* the fine rows of each aggregate, in increasing order (R's rows) */
        for (size_t i = 0; i < n; ++i)
            start[map[i] + 1]++;
        for (size_t c = 0; c < nc; ++c)
            start[c + 1] += start[c];
        for (size_t i = 0; i < n; ++i)
            members[start[map[i]]++] = (uint32_t)i;
        for (size_t c = nc; c > 0; --c)
            start[c] = start[c - 1];
        start[0] = 0;
    }
    const int ready = !fail; /* fail is the reduction's private 0 inside the region */
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel reduction(| : fail) if (nb > 1 && ready)
#endif
    {
        galerkin_scratch g;
        size_t m = nc ? nc : 1;
        g.iacc = sk__malloc_array(m, sizeof *g.iacc);
        g.oacc = sk__malloc_array(m, sizeof *g.oacc);
        g.imark = sk__malloc_array(m, sizeof *g.imark);
        g.omark = sk__malloc_array(m, sizeof *g.omark);
        g.ilist = sk__malloc_array(m, sizeof *g.ilist);
        g.olist = sk__malloc_array(m, sizeof *g.olist);
        int bad = !ready || !g.iacc || !g.oacc || !g.imark || !g.omark || !g.ilist || !g.olist;
        for (size_t q = 0; !bad && q < nc; ++q)
            g.imark[q] = g.omark[q] = SIZE_MAX;
#if defined(SK_HAVE_OPENMP)
#pragma omp for schedule(dynamic, 1)
#endif
        for (long k = 0; k < (long)nb; ++k)
            if (!bad)
                bad = !galerkin_rows(a, map, start, members, (size_t)k * nc / nb,
                                     (size_t)(k + 1) * nc / nb, &g, &blk[k], out->ptr + 1);
        fail |= bad;
        sk__free(g.iacc);
        sk__free(g.oacc);
        sk__free(g.imark);
        sk__free(g.omark);
        sk__free(g.ilist);
        sk__free(g.olist);
    }
    sk__free(start);
    sk__free(members);
    if (!gather_blocks(blk, nb, fail, out))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu Galerkin product", nc,
                        nc);
    return SK_OK;
}

void sk__csr_multiply(const sk__csr *a, const double *x, double *y)
{
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 4096) if (a->rows > 100000)
#endif
    for (long i = 0; i < (long)a->rows; ++i) {
        double s = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            s += a->val[k] * x[a->col[k]];
        y[i] = s;
    }
}

/* ---------------------------------------------------------------------------------------------
 * Hierarchy
 * ------------------------------------------------------------------------------------------- */

struct sk__multilevel {
    size_t L;
    bool symmetric;
    sk__csr *A;    /* L operators, A[L-1] the finest */
    sk__csr *P;    /* L-1 prolongations */
    sk__csr *R;    /* L-1 restrictions R[k] = P[k]^T (freed where pmap[k] is set) */
    double **dinv; /* 1 / diagonal per level (0 for a zero diagonal: that unknown is not smoothed) */
    size_t **upper; /* per level and row: the first entry right of the diagonal */
    float **fval;   /* per level above the coarsest: the values over fscale in single
                     * precision, which the cycle's sweeps and residuals read (a third less memory
                     * traffic; the Krylov iterations keep the double values) */
    double *fscale; /* per level: a power of two near the largest value (no float overflow) */
    uint32_t **pmap; /* per prolongation: when every row of P[k] is one entry 1 (piecewise
                      * constant, the aggregation AMG's), row i's column; else NULL. The cycle
                      * then restricts and prolongs through the map alone (the same sums as
                      * through R and P, a third of their memory traffic) */
    sk_sparse *coarse;
    sk_solver *solver;
    double scale;   /* of the coarse correction (1 = the plain V-cycle) */
    unsigned gamma; /* coarse corrections per level (1 = V-cycle, 2 = W-cycle) */
    bool kcycle;    /* symmetric: each coarse level solved by two flexible CG steps */
    bool galerkin;  /* every coarse operator is R A P of the level above (in exact arithmetic):
                     * the restricted residual after a coarse correction e is then r_c - A_c e,
                     * formed on the coarse level (W-cycle) */
    sk__multilevel_stats stats;
};

void sk__multilevel_destroy(sk__multilevel **mgp)
{
    if (!mgp || !*mgp)
        return;
    sk__multilevel *mg = *mgp;
    for (size_t k = 0; k < mg->L; ++k) {
        if (mg->A)
            sk__csr_free(&mg->A[k]);
        if (mg->dinv)
            sk__free(mg->dinv[k]);
        if (mg->upper)
            sk__free(mg->upper[k]);
        if (mg->fval)
            sk__free(mg->fval[k]);
        if (k + 1 < mg->L) {
            if (mg->pmap)
                sk__free(mg->pmap[k]);
            if (mg->P)
                sk__csr_free(&mg->P[k]);
            if (mg->R)
                sk__csr_free(&mg->R[k]);
        }
    }
    sk__free(mg->A);
    sk__free(mg->P);
    sk__free(mg->R);
    sk__free(mg->dinv);
    sk__free(mg->upper);
    sk__free(mg->fval);
    sk__free(mg->fscale);
    sk__free(mg->pmap);
    sk_solver_destroy(&mg->solver);
    sk_sparse_destroy(&mg->coarse);
    sk__free(mg);
    *mgp = NULL;
}

void sk__multilevel_stats_get(const sk__multilevel *mg, sk__multilevel_stats *s)
{
    *s = mg->stats;
}

void sk__multilevel_set_galerkin(sk__multilevel *mg)
{
    mg->galerkin = true;
}

void sk__multilevel_set_cycle(sk__multilevel *mg, double scale, unsigned gamma, bool kcycle)
{
    mg->scale = scale;
    mg->gamma = gamma ? gamma : 1;
    mg->kcycle = kcycle && mg->symmetric;
}

/* The coarsest operator as an sk_sparse for the direct solvers: the lower triangle in columns
 * (symmetric: row j of the CSR holds column j) or the full matrix in columns (the transpose). */
static sk_status coarse_sparse(const sk__csr *a, bool symmetric, sk_sparse **out, sk_error *err)
{
    *out = NULL;
    sk__csr t = {0};
    const sk__csr *src = a;
    sk_status st = SK_OK;
    if (!symmetric) {
        if ((st = sk__csr_transpose(a, &t, err)))
            return st;
        src = &t;
    }
    size_t n = a->rows, nnz = 0;
    for (size_t i = 0; i < n; ++i)
        for (size_t k = src->ptr[i]; k < src->ptr[i + 1]; ++k)
            if (!symmetric || src->col[k] >= i)
                nnz++;
    sk_sparse *s = sk__calloc_array(1, sizeof *s);
    if (s) {
        s->colptr = sk__malloc_array(n + 1, sizeof(int));
        s->rowind = sk__malloc_array(nnz ? nnz : 1, sizeof(int));
        s->values = sk__malloc_array(nnz ? nnz : 1, sizeof(double));
    }
    if (!s || !s->colptr || !s->rowind || !s->values) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    s->n = n;
    s->nnz = nnz;
    s->storage = symmetric ? SK_SPARSE_LOWER : SK_SPARSE_FULL;
    size_t q = 0;
    for (size_t i = 0; i < n; ++i) {
        s->colptr[i] = (int)q;
        for (size_t k = src->ptr[i]; k < src->ptr[i + 1]; ++k)
            if (!symmetric || src->col[k] >= i) {
                s->rowind[q] = (int)src->col[k];
                s->values[q++] = src->val[k];
            }
    }
    s->colptr[n] = (int)q;
done:
    sk__csr_free(&t);
    if (st)
        sk_sparse_destroy(&s);
    *out = s;
    return st;
}

/* Level k's smoother data: 1 / diagonal, the first entry right of the diagonal per row, and
 * above the coarsest level the single-precision values over a power of two near the largest. */
static sk_status smoother_setup(sk__multilevel *mg, size_t k, sk_error *err)
{
    const sk__csr *a = &mg->A[k];
    size_t nnz = a->ptr[a->rows];
    mg->dinv[k] = sk__calloc_array(a->rows ? a->rows : 1, sizeof(double));
    mg->upper[k] = sk__malloc_array(a->rows ? a->rows : 1, sizeof(size_t));
    if (k > 0)
        mg->fval[k] = sk__malloc_array(nnz ? nnz : 1, sizeof(float));
    if (!mg->dinv[k] || !mg->upper[k] || (k > 0 && !mg->fval[k]))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    double big = 0;
    for (size_t q = 0; q < nnz; ++q)
        big = fmax(big, fabs(a->val[q]));
    int e = 0;
    if (isfinite(big) && big > 0)
        frexp(big, &e);
    double sc = mg->fscale[k] = ldexp(1, e);
    for (size_t q = 0; k > 0 && q < nnz; ++q)
        mg->fval[k][q] = (float)(a->val[q] / sc);
    for (size_t i = 0; i < a->rows; ++i) {
        size_t q = a->ptr[i];
        for (; q < a->ptr[i + 1] && a->col[q] <= i; ++q)
            if (a->col[q] == i && a->val[q] != 0) /* the sweeps' own (single) diagonal */
                mg->dinv[k][i] = k == 0 ? 1.0 / a->val[q]
                               : mg->fval[k][q] != 0 ? 1.0 / (sc * (double)mg->fval[k][q])
                                                     : 0;
        mg->upper[k][i] = q;
    }
    return SK_OK;
}

/* *map = the column of each row of p when every row is one entry equal to 1, else NULL. */
static sk_status piecewise_constant_map(const sk__csr *p, uint32_t **map, sk_error *err)
{
    *map = NULL;
    for (size_t i = 0; i < p->rows; ++i)
        if (p->ptr[i + 1] != p->ptr[i] + 1 || p->val[p->ptr[i]] != 1)
            return SK_OK;
    if (!(*map = sk__malloc_array(p->rows ? p->rows : 1, sizeof **map)))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < p->rows; ++i)
        (*map)[i] = p->col[p->ptr[i]];
    return SK_OK;
}

sk_status sk__multilevel_create(sk__csr *fine, sk__csr *p, sk__csr *coarse_ops, size_t L,
                                bool symmetric, sk__multilevel **out, sk_error *err)
{
    *out = NULL;
    double t0 = sk_seconds();
    sk_status st = SK_OK;
    sk__multilevel *mg = sk__calloc_array(1, sizeof *mg);
    if (mg) {
        mg->L = L;
        mg->symmetric = symmetric;
        mg->scale = 1;
        mg->gamma = 1;
        mg->A = sk__calloc_array(L, sizeof *mg->A);
        mg->P = sk__calloc_array(L, sizeof *mg->P);
        mg->R = sk__calloc_array(L, sizeof *mg->R);
        mg->dinv = sk__calloc_array(L, sizeof *mg->dinv);
        mg->upper = sk__calloc_array(L, sizeof *mg->upper);
        mg->fval = sk__calloc_array(L, sizeof *mg->fval);
        mg->fscale = sk__calloc_array(L, sizeof *mg->fscale);
        mg->pmap = sk__calloc_array(L, sizeof *mg->pmap);
    }
    if (!mg || !mg->A || !mg->P || !mg->R || !mg->dinv || !mg->upper || !mg->fval ||
        !mg->fscale || !mg->pmap) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        if (mg) /* keep the ownership promise */
            mg->L = 0;
        sk__csr_free(fine);
        for (size_t k = 0; k + 1 < L; ++k) {
            sk__csr_free(&p[k]);
            if (coarse_ops)
                sk__csr_free(&coarse_ops[k]);
        }
        goto done;
    }
    mg->A[L - 1] = *fine;
    memset(fine, 0, sizeof *fine);
    mg->galerkin = !coarse_ops;
    for (size_t k = 0; k + 1 < L; ++k) {
        mg->P[k] = p[k];
        memset(&p[k], 0, sizeof p[k]);
        if (coarse_ops) {
            mg->A[k] = coarse_ops[k];
            memset(&coarse_ops[k], 0, sizeof coarse_ops[k]);
        }
    }
    for (size_t k = L - 1; k-- > 0;) {
        if (mg->P[k].rows != mg->A[k + 1].rows) {
            st = sk__fail(err, SK_ERR_ARG, "prolongation %zu has %zu rows for %zu unknowns", k,
                          mg->P[k].rows, mg->A[k + 1].rows);
            goto done;
        }
        if ((st = sk__csr_transpose(&mg->P[k], &mg->R[k], err)))
            goto done;
        if (coarse_ops) {
            if (mg->A[k].rows != mg->P[k].cols) {
                st = sk__fail(err, SK_ERR_ARG, "operator %zu has %zu rows for %zu unknowns", k,
                              mg->A[k].rows, mg->P[k].cols);
                goto done;
            }
        } else if ((st = sk__csr_galerkin(&mg->R[k], &mg->A[k + 1], &mg->P[k], &mg->A[k], err))) {
            goto done;
        }
    }
    for (size_t k = 0; k + 1 < L; ++k) {
        if ((st = piecewise_constant_map(&mg->P[k], &mg->pmap[k], err)))
            goto done;
        if (mg->pmap[k]) /* the map restricts: R is not read again */
            sk__csr_free(&mg->R[k]);
    }
    for (size_t k = 0; k < L; ++k) {
        if ((st = smoother_setup(mg, k, err)))
            goto done;
        mg->stats.operator_nnz += mg->A[k].ptr[mg->A[k].rows];
    }
    mg->stats.levels = L;
    mg->stats.unknowns[0] = mg->A[0].rows;
    mg->stats.unknowns[1] = mg->A[L - 1].rows;
    mg->stats.finest_nnz = mg->A[L - 1].ptr[mg->A[L - 1].rows];
    /* simplicial: the coarsest factor is small and solved once per V-cycle from the threads of
     * the right-hand sides, where BLAS threads of a supernodal solve only compete with them */
    sk_solver_opts so = {SK_ORDERING_DEFAULT, true, NULL};
    if ((st = coarse_sparse(&mg->A[0], symmetric, &mg->coarse, err)) ||
        (st = sk_solver_create_opts(mg->coarse, symmetric ? SK_SOLVER_CHOLESKY : SK_SOLVER_LU,
                                    &so, &mg->solver, err)) ||
        (st = sk_solver_factorize(mg->solver, mg->coarse, err)))
        goto done;
    sk_solve_stats ss;
    sk_solver_stats(mg->solver, &ss);
    mg->stats.coarse_factor_nnz = ss.factor_nnz;
done:
    if (mg)
        mg->stats.setup_seconds = sk_seconds() - t0;
    if (st)
        sk__multilevel_destroy(&mg);
    *out = mg;
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * V-cycle and Krylov iterations
 * ------------------------------------------------------------------------------------------- */

typedef struct workspace {
    double **b, **x, **r, **z, **t; /* per level */
    double **e;                     /* per level: a W-cycle's later coarse corrections */
    double **kc[5];                 /* K-cycle vectors per level */
    double *kv[8];                  /* Krylov vectors, finest size */
    double *cb;                     /* two right-hand sides: the coarsest level's columns */
    int fail;
} workspace;

static void ws_free(workspace *w, size_t L)
{
    for (size_t k = 0; k < L; ++k) {
        if (w->b)
            sk__free(w->b[k]);
        if (w->x)
            sk__free(w->x[k]);
        if (w->r)
            sk__free(w->r[k]);
        if (w->z)
            sk__free(w->z[k]);
        if (w->t)
            sk__free(w->t[k]);
        if (w->e)
            sk__free(w->e[k]);
    }
    sk__free(w->b);
    sk__free(w->x);
    sk__free(w->r);
    sk__free(w->z);
    sk__free(w->t);
    sk__free(w->e);
    for (int i = 0; i < 5; ++i) {
        for (size_t k = 0; w->kc[i] && k < L; ++k)
            sk__free(w->kc[i][k]);
        sk__free(w->kc[i]);
    }
    for (int i = 0; i < 8; ++i)
        sk__free(w->kv[i]);
    sk__free(w->cb);
    memset(w, 0, sizeof *w);
}

/* width: vectors of one right-hand side (1) or of two interleaved (2). */
static bool ws_alloc(workspace *w, const sk__multilevel *mg, size_t width)
{
    memset(w, 0, sizeof *w);
    size_t L = mg->L;
    w->b = sk__calloc_array(L, sizeof *w->b);
    w->x = sk__calloc_array(L, sizeof *w->x);
    w->r = sk__calloc_array(L, sizeof *w->r);
    w->z = sk__calloc_array(L, sizeof *w->z);
    w->t = sk__calloc_array(L, sizeof *w->t);
    w->e = sk__calloc_array(L, sizeof *w->e);
    if (!w->b || !w->x || !w->r || !w->z || !w->t || !w->e)
        return false;
    for (size_t k = 0; k < L; ++k) {
        size_t n = width * (mg->A[k].rows ? mg->A[k].rows : 1);
        w->b[k] = sk__malloc_array(n, sizeof(double));
        w->x[k] = sk__malloc_array(n, sizeof(double));
        w->r[k] = sk__malloc_array(n, sizeof(double));
        w->z[k] = sk__malloc_array(n, sizeof(double));
        w->t[k] = sk__malloc_array(n, sizeof(double));
        if (!w->b[k] || !w->x[k] || !w->r[k] || !w->z[k] || !w->t[k])
            return false;
        if (mg->gamma > 1 && mg->galerkin && k + 1 < L &&
            !(w->e[k] = sk__malloc_array(n, sizeof(double))))
            return false;
    }
    for (int i = 0; mg->kcycle && i < 5; ++i) {
        if (!(w->kc[i] = sk__calloc_array(L, sizeof *w->kc[i])))
            return false;
        for (size_t k = 0; k < L; ++k)
            if (!(w->kc[i][k] = sk__malloc_array(width * (mg->A[k].rows ? mg->A[k].rows : 1),
                                                 sizeof(double))))
                return false;
    }
    size_t nf = width * (mg->A[L - 1].rows ? mg->A[L - 1].rows : 1);
    for (int i = 0; i < 8; ++i)
        if (!(w->kv[i] = sk__malloc_array(nf, sizeof(double))))
            return false;
    if (width > 1 && !(w->cb = sk__malloc_array(2 * width * (mg->A[0].rows ? mg->A[0].rows : 1),
                                                sizeof(double))))
        return false;
    return true;
}

static double dot(size_t n, const double *a, const double *b)
{
    double s = 0;
    for (size_t i = 0; i < n; ++i)
        s += a[i] * b[i];
    return s;
}

/* y = a x with the values sc val (the cycle's single-precision copy). */
static void cycle_multiply(const sk__csr *a, const float *val, double sc, const double *x,
                           double *y)
{
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 4096) if (a->rows > 100000)
#endif
    for (long i = 0; i < (long)a->rows; ++i) {
        double s = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            s += (double)val[k] * x[a->col[k]];
        y[i] = sc * s;
    }
}

/* r -= scale a x with the values sc val: the restricted residual after a coarse correction
 * scale P x, R (r_f - A_f (z + scale P x)) = R (r_f - A_f z) - scale (R A_f P) x, formed on the
 * coarse level where a = R A_f P (Galerkin) instead of on the fine level and restricted. */
static void residual_update(const sk__csr *a, const float *val, double sc, double scale,
                            const double *x, double *r)
{
    for (size_t i = 0; i < a->rows; ++i) {
        double s = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            s += (double)val[k] * x[a->col[k]];
        r[i] -= scale * (sc * s);
    }
}

static void gs_forward(const sk__csr *a, const float *val, double sc, const double *dinv,
                       const double *b, double *x)
{
    for (size_t i = 0; i < a->rows; ++i) {
        double s = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            s += (double)val[k] * x[a->col[k]];
        x[i] += (b[i] - sc * s) * dinv[i];
    }
}

/* The first forward sweep from x = 0 (only the entries left of the diagonal are read), then
 * t = b - a x from it: after row i's update b_i minus its row's sum through the diagonal is
 * zero (up to rounding) unless the row is not smoothed, so only the entries right of the
 * diagonal are read: one pass over the matrix instead of two. */
static void gs_forward_zero_residual(const sk__csr *a, const float *val, double sc,
                                     const double *dinv, const size_t *upper, const double *b,
                                     double *x, double *t, const uint32_t *map, double *y,
                                     size_t nc)
{
    for (size_t i = 0; i < a->rows; ++i) {
        double s = 0;
        size_t end = upper[i];
        if (end > a->ptr[i] && a->col[end - 1] == i)
            --end; /* the diagonal: x_i is still zero */
        for (size_t k = a->ptr[i]; k < end; ++k)
            s += (double)val[k] * x[a->col[k]];
        s = b[i] - sc * s;
        x[i] = s * dinv[i];
        t[i] = dinv[i] == 0 ? s : 0;
    }
    if (map) { /* y = R t at once: t_i added into its coarse unknown, not stored */
        memset(y, 0, nc * sizeof *y);
        for (size_t i = 0; i < a->rows; ++i) {
            double s = 0;
            for (size_t k = upper[i]; k < a->ptr[i + 1]; ++k)
                s += (double)val[k] * x[a->col[k]];
            y[map[i]] += t[i] - sc * s;
        }
        return;
    }
    for (size_t i = 0; i < a->rows; ++i) {
        double s = 0;
        for (size_t k = upper[i]; k < a->ptr[i + 1]; ++k)
            s += (double)val[k] * x[a->col[k]];
        t[i] -= sc * s;
    }
}

static void gs_backward(const sk__csr *a, const float *val, double sc, const double *dinv,
                        const double *b, double *x)
{
    for (size_t i = a->rows; i-- > 0;) {
        double s = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            s += (double)val[k] * x[a->col[k]];
        x[i] += (b[i] - sc * s) * dinv[i];
    }
}

/* y = R_j t: through the map, each fine entry added into its coarse unknown in row order, which
 * is the order of R's rows (the transpose of P), so the same sums as sk__csr_multiply. */
static void restrict_to(const sk__multilevel *mg, size_t j, const double *t, double *y)
{
    const uint32_t *map = mg->pmap[j];
    if (!map) {
        sk__csr_multiply(&mg->R[j], t, y);
        return;
    }
    memset(y, 0, mg->A[j].rows * sizeof *y);
    for (size_t i = 0; i < mg->P[j].rows; ++i)
        y[map[i]] += t[i];
}

/* y += scale P_j x; through the map 0 + x_c as the row sum over P's one entry 1. */
static void prolong_add(const sk__multilevel *mg, size_t j, double scale, const double *x,
                        double *y)
{
    const sk__csr *p = &mg->P[j];
    const uint32_t *map = mg->pmap[j];
    if (map) {
        for (size_t i = 0; i < p->rows; ++i)
            y[i] += scale * (0.0 + x[map[i]]);
        return;
    }
    for (size_t i = 0; i < p->rows; ++i) {
        double s = 0;
        for (size_t k = p->ptr[i]; k < p->ptr[i + 1]; ++k)
            s += p->val[k] * x[p->col[k]];
        y[i] += scale * s;
    }
}

static void coarse_solve(sk__multilevel *mg, const double *r, double *z, workspace *w)
{
    int bad = 0;
#if defined(SK_HAVE_OPENMP)
#pragma omp critical(sk__multilevel_coarse)
#endif
    bad = sk_solver_solve(mg->solver, 1, r, z, NULL) != SK_OK;
    if (bad) {
        w->fail = 1;
        memset(z, 0, mg->A[0].rows * sizeof *z);
    }
}

static void vcycle(sk__multilevel *mg, size_t k, const double *r, double *z, workspace *w);

/* x = about A_j^-1 r by two steps of flexible CG preconditioned by the cycle of level j, the
 * second skipped when the first reduced the residual four times (the K-cycle of Notay and
 * Vassilevski 2008). */
static void kcycle(sk__multilevel *mg, size_t j, const double *r, double *x, workspace *w)
{
    const sk__csr *a = &mg->A[j];
    size_t n = a->rows;
    double *c = w->kc[0][j], *v = w->kc[1][j], *r2 = w->kc[2][j], *d = w->kc[3][j],
           *u = w->kc[4][j];
    vcycle(mg, j, r, c, w);
    cycle_multiply(a, mg->fval[j], mg->fscale[j], c, v);
    double rho1 = dot(n, c, v), t1 = rho1 > 0 ? dot(n, c, r) / rho1 : 1;
    for (size_t i = 0; i < n; ++i)
        r2[i] = r[i] - t1 * v[i];
    double gam = 0, t2 = 0;
    if (rho1 > 0 && dot(n, r2, r2) > 0.0625 * dot(n, r, r)) {
        vcycle(mg, j, r2, d, w);
        cycle_multiply(a, mg->fval[j], mg->fscale[j], d, u);
        gam = dot(n, d, v);
        double rho2 = dot(n, d, u) - gam * gam / rho1;
        if (rho2 > 0) {
            t2 = dot(n, d, r2) / rho2;
            t1 -= gam * t2 / rho1;
        }
    }
    for (size_t i = 0; i < n; ++i)
        x[i] = t1 * c[i] + (t2 != 0 ? t2 * d[i] : 0);
}

/* z = V-cycle(k) applied to r (z and r of level k; z is overwritten). */
static void vcycle(sk__multilevel *mg, size_t k, const double *r, double *z, workspace *w)
{
    if (k == 0) {
        coarse_solve(mg, r, z, w);
        return;
    }
    const sk__csr *a = &mg->A[k];
    size_t n = a->rows;
    double *t = w->t[k];
    /* the first sweep from zero, fused with the first residual */
    const float *fv = mg->fval[k];
    double sc = mg->fscale[k];
    const uint32_t *map = SK_MG_SWEEPS == 1 ? mg->pmap[k - 1] : NULL; /* t restricted at once */
    gs_forward_zero_residual(a, fv, sc, mg->dinv[k], mg->upper[k], r, z, t, map, w->r[k - 1],
                             mg->A[k - 1].rows);
    for (int s = 1; s < SK_MG_SWEEPS; ++s)
        gs_forward(a, fv, sc, mg->dinv[k], r, z);
    /* gamma coarse corrections (a W-cycle for 2); one when the coarse level is solved exactly
     * (a second would be zero). With Galerkin operators the later ones take their restricted
     * residual from the coarse level (residual_update) and the corrections are summed there,
     * then prolonged once: no fine-level product, restriction or second prolongation. */
    unsigned cycles = k - 1 > 0 ? mg->gamma : 1;
    bool coarse_res = mg->galerkin && cycles > 1;
    double *rc = w->r[k - 1], *zc = w->z[k - 1], *e = w->e[k - 1];
    size_t nc = mg->A[k - 1].rows;
    for (unsigned c = 0; c < cycles; ++c) {
        if (coarse_res && c > 0) {
            residual_update(&mg->A[k - 1], mg->fval[k - 1], mg->fscale[k - 1], mg->scale,
                            c == 1 ? zc : e, rc);
        } else {
            if (c > 0 || SK_MG_SWEEPS > 1) {
                cycle_multiply(a, fv, sc, z, t);
                for (size_t i = 0; i < n; ++i)
                    t[i] = r[i] - t[i];
            }
            if (c > 0 || !map)
                restrict_to(mg, k - 1, t, rc);
        }
        double *out = coarse_res && c > 0 ? e : zc;
        if (mg->kcycle && k - 1 > 0)
            kcycle(mg, k - 1, rc, out, w);
        else
            vcycle(mg, k - 1, rc, out, w);
        if (!coarse_res)
            prolong_add(mg, k - 1, mg->scale, zc, z);
        else if (c > 0)
            for (size_t i = 0; i < nc; ++i)
                zc[i] += e[i];
    }
    if (coarse_res)
        prolong_add(mg, k - 1, mg->scale, zc, z);
    for (int s = 0; s < SK_MG_SWEEPS; ++s)
        gs_backward(a, fv, sc, mg->dinv[k], r, z);
}

/* Preconditioned CG on level k from the given x; returns the iterations, *relres the true
 * relative residual at the end. */
static size_t pcg(sk__multilevel *mg, size_t k, const double *b, double *x, double tol,
                  size_t maxit, workspace *w, double *relres)
{
    const sk__csr *a = &mg->A[k];
    size_t n = a->rows;
    double *r = w->kv[0], *z = w->kv[1], *p = w->kv[2], *q = w->kv[3], *rold = w->kv[4];
    double bn = sqrt(dot(n, b, b));
    if (bn == 0) {
        memset(x, 0, n * sizeof *x);
        *relres = 0;
        return 0;
    }
    sk__csr_multiply(a, x, r);
    for (size_t i = 0; i < n; ++i)
        r[i] = b[i] - r[i];
    double rn = sqrt(dot(n, r, r));
    size_t it = 0;
    if (rn > tol * bn && maxit > 0) {
        vcycle(mg, k, r, z, w);
        memcpy(p, z, n * sizeof *p);
        double rz = dot(n, r, z);
        for (; it < maxit;) {
            sk__csr_multiply(a, p, q);
            double pq = dot(n, p, q);
            if (!(pq > 0))
                break;
            double alpha = rz / pq;
            if (mg->kcycle)
                memcpy(rold, r, n * sizeof *rold);
            for (size_t i = 0; i < n; ++i) {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
            }
            ++it;
            rn = sqrt(dot(n, r, r));
            if (rn <= tol * bn)
                break;
            vcycle(mg, k, r, z, w);
            double rz2 = dot(n, r, z);
            /* flexible (Polak-Ribiere) for the K-cycle, whose preconditioner is not linear */
            double beta = (mg->kcycle ? rz2 - dot(n, rold, z) : rz2) / rz;
            rz = rz2;
            for (size_t i = 0; i < n; ++i)
                p[i] = z[i] + beta * p[i];
        }
    }
    /* the true residual (the recursive one drifts by rounding) */
    sk__csr_multiply(a, x, r);
    for (size_t i = 0; i < n; ++i)
        r[i] = b[i] - r[i];
    *relres = sqrt(dot(n, r, r)) / bn;
    return it;
}

/* y = a x and the sums (d, y) (dd non-NULL: also (y, y) into *yy and (y, d) into *dd) in the
 * same pass, each in row order as dot sums it: the same bits as the product and dot apart. */
static double multiply_dots(const sk__csr *a, const double *x, double *y, const double *d,
                            double *yy)
{
    double s1 = 0, s2 = 0;
    for (size_t i = 0; i < a->rows; ++i) {
        double s = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            s += a->val[k] * x[a->col[k]];
        y[i] = s;
        if (yy)
            s2 += s * s;
        s1 += d[i] * s;
    }
    if (yy)
        *yy = s2;
    return s1;
}

/* Right-preconditioned BiCGStab on level k. */
static size_t bicgstab(sk__multilevel *mg, size_t k, const double *b, double *x, double tol,
                       size_t maxit, workspace *w, double *relres)
{
    const sk__csr *a = &mg->A[k];
    size_t n = a->rows;
    double *r = w->kv[0], *rh = w->kv[1], *p = w->kv[2], *v = w->kv[3], *s = w->kv[4],
           *t = w->kv[5], *ph = w->kv[6], *sh = w->kv[7];
    double bn = sqrt(dot(n, b, b));
    if (bn == 0) {
        memset(x, 0, n * sizeof *x);
        *relres = 0;
        return 0;
    }
    sk__csr_multiply(a, x, r);
    for (size_t i = 0; i < n; ++i)
        r[i] = b[i] - r[i];
    memcpy(rh, r, n * sizeof *rh);
    memset(p, 0, n * sizeof *p);
    memset(v, 0, n * sizeof *v);
    double rho = 1, alpha = 1, omega = 1;
    /* each vector update carries the dot products of its result (the same sums in the same
     * order as dot: the same bits, one pass over the vectors instead of two or three) */
    double rr = dot(n, r, r), rhr = dot(n, rh, r);
    double rn = sqrt(rr);
    size_t it = 0;
    while (rn > tol * bn && it < maxit) {
        double rho2 = rhr;
        if (rho2 == 0 || omega == 0)
            break; /* breakdown: the caller sees the residual */
        double beta = (rho2 / rho) * (alpha / omega);
        rho = rho2;
        for (size_t i = 0; i < n; ++i)
            p[i] = r[i] + beta * (p[i] - omega * v[i]);
        vcycle(mg, k, p, ph, w);
        double rv = multiply_dots(a, ph, v, rh, NULL); /* v = A ph, (rh, v) */
        if (rv == 0)
            break;
        alpha = rho / rv;
        double ss = 0;
        for (size_t i = 0; i < n; ++i) {
            s[i] = r[i] - alpha * v[i];
            ss += s[i] * s[i];
        }
        ++it;
        double sn = sqrt(ss);
        if (sn <= tol * bn) {
            for (size_t i = 0; i < n; ++i)
                x[i] += alpha * ph[i];
            break;
        }
        vcycle(mg, k, s, sh, w);
        double tt = 0, ts = multiply_dots(a, sh, t, s, &tt); /* t = A sh, (t, t), (s, t) */
        omega = tt > 0 ? ts / tt : 0;
        rr = rhr = 0;
        for (size_t i = 0; i < n; ++i) {
            x[i] += alpha * ph[i] + omega * sh[i];
            r[i] = s[i] - omega * t[i];
            rr += r[i] * r[i];
            rhr += rh[i] * r[i];
        }
        rn = sqrt(rr);
    }
    sk__csr_multiply(a, x, r);
    for (size_t i = 0; i < n; ++i)
        r[i] = b[i] - r[i];
    *relres = sqrt(dot(n, r, r)) / bn;
    return it;
}

static size_t krylov(sk__multilevel *mg, size_t k, const double *b, double *x, double tol,
                     size_t maxit, workspace *w, double *relres)
{
    return mg->symmetric ? pcg(mg, k, b, x, tol, maxit, w, relres)
                         : bicgstab(mg, k, b, x, tol, maxit, w, relres);
}

/* ---------------------------------------------------------------------------------------------
 * Two right-hand sides in one pass (u and v of the fixed-boundary methods; one thread, where
 * one column per thread before streamed every matrix twice): the vectors hold
 * both interleaved, entry 2 i + c of column c, so every sweep, residual, restriction and
 * product reads the matrix once for both and carries two independent sums per row. Each column
 * goes through exactly the operations, in the same order, that the one-column functions above
 * apply to it, so the result is the same to the bit; a column that has converged (or broken
 * down) is left as it is while the other one goes on.
 * ------------------------------------------------------------------------------------------- */

static void dot2(size_t n, const double *a, const double *b, double out[2])
{
    double s0 = 0, s1 = 0;
    for (size_t i = 0; i < n; ++i) {
        s0 += a[2 * i] * b[2 * i];
        s1 += a[2 * i + 1] * b[2 * i + 1];
    }
    out[0] = s0;
    out[1] = s1;
}

/* y = a x (double values) */
static void multiply2(const sk__csr *a, const double *x, double *y)
{
    for (long i = 0; i < (long)a->rows; ++i) {
        double s0 = 0, s1 = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            s0 += a->val[k] * xc[0];
            s1 += a->val[k] * xc[1];
        }
        y[2 * i] = s0;
        y[2 * i + 1] = s1;
    }
}

/* multiply2 with the sums (d, y) per column into s1 (yy non-NULL: (y, y) too), in one pass
 * (multiply_dots for two columns) */
static void multiply2_dots(const sk__csr *a, const double *x, double *y, const double *d,
                           double s1[2], double *yy)
{
    double a0 = 0, a1 = 0, b0 = 0, b1 = 0;
    for (size_t i = 0; i < a->rows; ++i) {
        double s0 = 0, t0 = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            s0 += a->val[k] * xc[0];
            t0 += a->val[k] * xc[1];
        }
        y[2 * i] = s0;
        y[2 * i + 1] = t0;
        if (yy) {
            b0 += s0 * s0;
            b1 += t0 * t0;
        }
        a0 += d[2 * i] * s0;
        a1 += d[2 * i + 1] * t0;
    }
    s1[0] = a0;
    s1[1] = a1;
    if (yy) {
        yy[0] = b0;
        yy[1] = b1;
    }
}

/* y = a x with the values sc val (the cycle's single-precision copy) */
static void cycle_multiply2(const sk__csr *a, const float *val, double sc, const double *x,
                            double *y)
{
    for (long i = 0; i < (long)a->rows; ++i) {
        double s0 = 0, s1 = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            double v = (double)val[k];
            s0 += v * xc[0];
            s1 += v * xc[1];
        }
        y[2 * i] = sc * s0;
        y[2 * i + 1] = sc * s1;
    }
}

static void gs_forward2(const sk__csr *a, const float *val, double sc, const double *dinv,
                        const double *b, double *x)
{
    for (size_t i = 0; i < a->rows; ++i) {
        double s0 = 0, s1 = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            double v = (double)val[k];
            s0 += v * xc[0];
            s1 += v * xc[1];
        }
        x[2 * i] += (b[2 * i] - sc * s0) * dinv[i];
        x[2 * i + 1] += (b[2 * i + 1] - sc * s1) * dinv[i];
    }
}

/* residual_update for two columns */
static void residual_update2(const sk__csr *a, const float *val, double sc, double scale,
                             const double *x, double *r)
{
    for (size_t i = 0; i < a->rows; ++i) {
        double s0 = 0, s1 = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            double v = (double)val[k];
            s0 += v * xc[0];
            s1 += v * xc[1];
        }
        r[2 * i] -= scale * (sc * s0);
        r[2 * i + 1] -= scale * (sc * s1);
    }
}

/* gs_forward_zero_residual for two columns */
static void gs_forward_zero_residual2(const sk__csr *a, const float *val, double sc,
                                      const double *dinv, const size_t *upper, const double *b,
                                      double *x, double *t, const uint32_t *map, double *y,
                                      size_t nc)
{
    for (size_t i = 0; i < a->rows; ++i) {
        double s0 = 0, s1 = 0;
        size_t end = upper[i];
        if (end > a->ptr[i] && a->col[end - 1] == i)
            --end; /* the diagonal: x_i is still zero */
        for (size_t k = a->ptr[i]; k < end; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            double v = (double)val[k];
            s0 += v * xc[0];
            s1 += v * xc[1];
        }
        s0 = b[2 * i] - sc * s0;
        s1 = b[2 * i + 1] - sc * s1;
        x[2 * i] = s0 * dinv[i];
        x[2 * i + 1] = s1 * dinv[i];
        t[2 * i] = dinv[i] == 0 ? s0 : 0;
        t[2 * i + 1] = dinv[i] == 0 ? s1 : 0;
    }
    if (map)
        memset(y, 0, 2 * nc * sizeof *y);
    for (size_t i = 0; i < a->rows; ++i) {
        double s0 = 0, s1 = 0;
        for (size_t k = upper[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            double v = (double)val[k];
            s0 += v * xc[0];
            s1 += v * xc[1];
        }
        if (map) { /* y = R t at once, as gs_forward_zero_residual */
            y[2 * (size_t)map[i]] += t[2 * i] - sc * s0;
            y[2 * (size_t)map[i] + 1] += t[2 * i + 1] - sc * s1;
        } else {
            t[2 * i] -= sc * s0;
            t[2 * i + 1] -= sc * s1;
        }
    }
}

static void gs_backward2(const sk__csr *a, const float *val, double sc, const double *dinv,
                         const double *b, double *x)
{
    for (size_t i = a->rows; i-- > 0;) {
        double s0 = 0, s1 = 0;
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)a->col[k];
            double v = (double)val[k];
            s0 += v * xc[0];
            s1 += v * xc[1];
        }
        x[2 * i] += (b[2 * i] - sc * s0) * dinv[i];
        x[2 * i + 1] += (b[2 * i + 1] - sc * s1) * dinv[i];
    }
}

/* restrict_to for two columns */
static void restrict_to2(const sk__multilevel *mg, size_t j, const double *t, double *y)
{
    const uint32_t *map = mg->pmap[j];
    if (!map) {
        multiply2(&mg->R[j], t, y);
        return;
    }
    memset(y, 0, 2 * mg->A[j].rows * sizeof *y);
    for (size_t i = 0; i < mg->P[j].rows; ++i) {
        y[2 * (size_t)map[i]] += t[2 * i];
        y[2 * (size_t)map[i] + 1] += t[2 * i + 1];
    }
}

/* y += scale P_j x (prolong_add for two columns) */
static void prolong_add2(const sk__multilevel *mg, size_t j, double scale, const double *x,
                         double *y)
{
    const sk__csr *p = &mg->P[j];
    const uint32_t *map = mg->pmap[j];
    if (map) {
        for (size_t i = 0; i < p->rows; ++i) {
            y[2 * i] += scale * (0.0 + x[2 * (size_t)map[i]]);
            y[2 * i + 1] += scale * (0.0 + x[2 * (size_t)map[i] + 1]);
        }
        return;
    }
    for (size_t i = 0; i < p->rows; ++i) {
        double s0 = 0, s1 = 0;
        for (size_t k = p->ptr[i]; k < p->ptr[i + 1]; ++k) {
            const double *xc = x + 2 * (size_t)p->col[k];
            s0 += p->val[k] * xc[0];
            s1 += p->val[k] * xc[1];
        }
        y[2 * i] += scale * s0;
        y[2 * i + 1] += scale * s1;
    }
}

/* The coarsest solve of both columns (each by itself, as coarse_solve does). */
static void coarse_solve2(sk__multilevel *mg, const double *r, double *z, workspace *w)
{
    size_t n = mg->A[0].rows;
    double *in = w->cb, *out = w->cb + 2 * n;
    for (size_t i = 0; i < n; ++i) {
        in[i] = r[2 * i];
        in[n + i] = r[2 * i + 1];
    }
    for (size_t c = 0; c < 2; ++c)
        coarse_solve(mg, in + c * n, out + c * n, w);
    for (size_t i = 0; i < n; ++i) {
        z[2 * i] = out[i];
        z[2 * i + 1] = out[n + i];
    }
}

static void vcycle2(sk__multilevel *mg, size_t k, const double *r, double *z, workspace *w);

/* kcycle for two columns: the second step is taken when either column needs it, and a column
 * that does not need it keeps its one-step result. */
static void kcycle2(sk__multilevel *mg, size_t j, const double *r, double *x, workspace *w)
{
    const sk__csr *a = &mg->A[j];
    size_t n = a->rows;
    double *c = w->kc[0][j], *v = w->kc[1][j], *r2 = w->kc[2][j], *d = w->kc[3][j],
           *u = w->kc[4][j];
    double rho1[2], t1[2], gam[2] = {0, 0}, t2[2] = {0, 0}, e[2], f[2];
    bool two[2];
    vcycle2(mg, j, r, c, w);
    cycle_multiply2(a, mg->fval[j], mg->fscale[j], c, v);
    dot2(n, c, v, rho1);
    dot2(n, c, r, e);
    for (int q = 0; q < 2; ++q)
        t1[q] = rho1[q] > 0 ? e[q] / rho1[q] : 1;
    for (size_t i = 0; i < n; ++i)
        for (int q = 0; q < 2; ++q)
            r2[2 * i + q] = r[2 * i + q] - t1[q] * v[2 * i + q];
    dot2(n, r2, r2, e);
    dot2(n, r, r, f);
    for (int q = 0; q < 2; ++q)
        two[q] = rho1[q] > 0 && e[q] > 0.0625 * f[q];
    if (two[0] || two[1]) {
        vcycle2(mg, j, r2, d, w);
        cycle_multiply2(a, mg->fval[j], mg->fscale[j], d, u);
        double du[2], dr[2];
        dot2(n, d, v, gam);
        dot2(n, d, u, du);
        dot2(n, d, r2, dr);
        for (int q = 0; q < 2; ++q) {
            if (!two[q]) {
                gam[q] = 0;
                continue;
            }
            double rho2 = du[q] - gam[q] * gam[q] / rho1[q];
            if (rho2 > 0) {
                t2[q] = dr[q] / rho2;
                t1[q] -= gam[q] * t2[q] / rho1[q];
            }
        }
    }
    for (size_t i = 0; i < n; ++i)
        for (int q = 0; q < 2; ++q)
            x[2 * i + q] = t1[q] * c[2 * i + q] + (t2[q] != 0 ? t2[q] * d[2 * i + q] : 0);
}

/* vcycle for two columns. */
static void vcycle2(sk__multilevel *mg, size_t k, const double *r, double *z, workspace *w)
{
    if (k == 0) {
        coarse_solve2(mg, r, z, w);
        return;
    }
    const sk__csr *a = &mg->A[k];
    size_t n = a->rows;
    double *t = w->t[k];
    const float *fv = mg->fval[k];
    double sc = mg->fscale[k];
    const uint32_t *map = SK_MG_SWEEPS == 1 ? mg->pmap[k - 1] : NULL; /* t restricted at once */
    gs_forward_zero_residual2(a, fv, sc, mg->dinv[k], mg->upper[k], r, z, t, map, w->r[k - 1],
                              mg->A[k - 1].rows);
    for (int s = 1; s < SK_MG_SWEEPS; ++s)
        gs_forward2(a, fv, sc, mg->dinv[k], r, z);
    unsigned cycles = k - 1 > 0 ? mg->gamma : 1;
    bool coarse_res = mg->galerkin && cycles > 1; /* as vcycle */
    double *rc = w->r[k - 1], *zc = w->z[k - 1], *e = w->e[k - 1];
    size_t nc = mg->A[k - 1].rows;
    for (unsigned c = 0; c < cycles; ++c) {
        if (coarse_res && c > 0) {
            residual_update2(&mg->A[k - 1], mg->fval[k - 1], mg->fscale[k - 1], mg->scale,
                             c == 1 ? zc : e, rc);
        } else {
            if (c > 0 || SK_MG_SWEEPS > 1) {
                cycle_multiply2(a, fv, sc, z, t);
                for (size_t i = 0; i < 2 * n; ++i)
                    t[i] = r[i] - t[i];
            }
            if (c > 0 || !map)
                restrict_to2(mg, k - 1, t, rc);
        }
        double *out = coarse_res && c > 0 ? e : zc;
        if (mg->kcycle && k - 1 > 0)
            kcycle2(mg, k - 1, rc, out, w);
        else
            vcycle2(mg, k - 1, rc, out, w);
        if (!coarse_res)
            prolong_add2(mg, k - 1, mg->scale, zc, z);
        else if (c > 0)
            for (size_t i = 0; i < 2 * nc; ++i)
                zc[i] += e[i];
    }
    if (coarse_res)
        prolong_add2(mg, k - 1, mg->scale, zc, z);
    for (int s = 0; s < SK_MG_SWEEPS; ++s)
        gs_backward2(a, fv, sc, mg->dinv[k], r, z);
}

/* bicgstab for two columns: it[c] the iterations, relres[c] the true relative residual. */
static void bicgstab2(sk__multilevel *mg, size_t k, const double *b, double *x, double tol,
                      size_t maxit, workspace *w, size_t it[2], double relres[2])
{
    const sk__csr *a = &mg->A[k];
    size_t n = a->rows;
    double *r = w->kv[0], *rh = w->kv[1], *p = w->kv[2], *v = w->kv[3], *s = w->kv[4],
           *t = w->kv[5], *ph = w->kv[6], *sh = w->kv[7];
    double bn[2], rho[2] = {1, 1}, alpha[2] = {1, 1}, omega[2] = {1, 1}, rn[2], d[2], e[2];
    bool on[2]; /* still iterating */
    dot2(n, b, b, bn);
    for (int c = 0; c < 2; ++c) {
        bn[c] = sqrt(bn[c]);
        on[c] = bn[c] != 0;
        it[c] = 0;
        relres[c] = 0;
        for (size_t i = 0; !on[c] && i < n; ++i)
            x[2 * i + c] = 0;
    }
    if (!on[0] && !on[1])
        return;
    multiply2(a, x, r);
    for (size_t i = 0; i < 2 * n; ++i)
        r[i] = b[i] - r[i];
    memcpy(rh, r, 2 * n * sizeof *rh);
    memset(p, 0, 2 * n * sizeof *p);
    memset(v, 0, 2 * n * sizeof *v);
    dot2(n, r, r, rn);
    for (int c = 0; c < 2; ++c)
        rn[c] = sqrt(rn[c]);
    double rhr[2]; /* (rh, r), summed with the update of r (as bicgstab) */
    dot2(n, rh, r, rhr);
    for (;;) {
        double beta[2] = {0, 0};
        d[0] = rhr[0];
        d[1] = rhr[1];
        for (int c = 0; c < 2; ++c) {
            on[c] = on[c] && rn[c] > tol * bn[c] && it[c] < maxit;
            if (on[c] && (d[c] == 0 || omega[c] == 0))
                on[c] = false; /* breakdown: the caller sees the residual */
            if (on[c]) {
                beta[c] = (d[c] / rho[c]) * (alpha[c] / omega[c]);
                rho[c] = d[c];
            }
        }
        if (!on[0] && !on[1])
            break;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 2; ++c)
                if (on[c])
                    p[2 * i + c] = r[2 * i + c] +
                                   beta[c] * (p[2 * i + c] - omega[c] * v[2 * i + c]);
        vcycle2(mg, k, p, ph, w);
        multiply2_dots(a, ph, v, rh, d, NULL); /* v = A ph, (rh, v) */
        bool go[2] = {on[0], on[1]}; /* on to the second half of this iteration */
        for (int c = 0; c < 2; ++c) {
            if (go[c] && d[c] == 0)
                on[c] = go[c] = false;
            if (go[c])
                alpha[c] = rho[c] / d[c];
        }
        double ss0 = 0, ss1 = 0;
        for (size_t i = 0; i < n; ++i) {
            for (int c = 0; c < 2; ++c)
                if (go[c])
                    s[2 * i + c] = r[2 * i + c] - alpha[c] * v[2 * i + c];
            ss0 += s[2 * i] * s[2 * i];
            ss1 += s[2 * i + 1] * s[2 * i + 1];
        }
        d[0] = ss0;
        d[1] = ss1;
        for (int c = 0; c < 2; ++c) {
            if (!go[c])
                continue;
            ++it[c];
            if (sqrt(d[c]) <= tol * bn[c]) {
                for (size_t i = 0; i < n; ++i)
                    x[2 * i + c] += alpha[c] * ph[2 * i + c];
                on[c] = go[c] = false;
            }
        }
        if (!go[0] && !go[1])
            continue; /* the loop's head sees that nothing is left */
        vcycle2(mg, k, s, sh, w);
        multiply2_dots(a, sh, t, s, e, d); /* t = A sh, (t, t) into d, (s, t) into e */
        for (int c = 0; c < 2; ++c)
            if (go[c])
                omega[c] = d[c] > 0 ? e[c] / d[c] : 0;
        double rr0 = 0, rr1 = 0, rhr0 = 0, rhr1 = 0;
        for (size_t i = 0; i < n; ++i) {
            for (int c = 0; c < 2; ++c)
                if (go[c]) {
                    size_t q = 2 * i + c;
                    x[q] += alpha[c] * ph[q] + omega[c] * sh[q];
                    r[q] = s[q] - omega[c] * t[q];
                }
            rr0 += r[2 * i] * r[2 * i];
            rr1 += r[2 * i + 1] * r[2 * i + 1];
            rhr0 += rh[2 * i] * r[2 * i];
            rhr1 += rh[2 * i + 1] * r[2 * i + 1];
        }
        d[0] = rr0;
        d[1] = rr1;
        rhr[0] = rhr0;
        rhr[1] = rhr1;
        for (int c = 0; c < 2; ++c)
            if (go[c])
                rn[c] = sqrt(d[c]);
    }
    multiply2(a, x, r);
    for (size_t i = 0; i < 2 * n; ++i)
        r[i] = b[i] - r[i];
    dot2(n, r, r, d);
    for (int c = 0; c < 2; ++c)
        relres[c] = bn[c] != 0 ? sqrt(d[c]) / bn[c] : 0;
}

/* pcg for two columns: it[c] the iterations, relres[c] the true relative residual. */
static void pcg2(sk__multilevel *mg, size_t k, const double *b, double *x, double tol,
                 size_t maxit, workspace *w, size_t it[2], double relres[2])
{
    const sk__csr *a = &mg->A[k];
    size_t n = a->rows;
    double *r = w->kv[0], *z = w->kv[1], *p = w->kv[2], *q = w->kv[3], *rold = w->kv[4];
    double bn[2], rn[2], rz[2], d[2], e[2];
    bool on[2];
    dot2(n, b, b, bn);
    for (int c = 0; c < 2; ++c) {
        bn[c] = sqrt(bn[c]);
        it[c] = 0;
        relres[c] = 0;
        for (size_t i = 0; bn[c] == 0 && i < n; ++i)
            x[2 * i + c] = 0;
    }
    if (bn[0] == 0 && bn[1] == 0)
        return;
    multiply2(a, x, r);
    for (size_t i = 0; i < 2 * n; ++i)
        r[i] = b[i] - r[i];
    dot2(n, r, r, rn);
    for (int c = 0; c < 2; ++c) {
        rn[c] = sqrt(rn[c]);
        on[c] = bn[c] != 0 && rn[c] > tol * bn[c] && maxit > 0;
    }
    if (on[0] || on[1]) {
        vcycle2(mg, k, r, z, w);
        memcpy(p, z, 2 * n * sizeof *p);
        dot2(n, r, z, rz);
        for (;;) {
            for (int c = 0; c < 2; ++c)
                on[c] = on[c] && it[c] < maxit;
            if (!on[0] && !on[1])
                break;
            multiply2(a, p, q);
            dot2(n, p, q, d);
            double alpha[2] = {0, 0};
            for (int c = 0; c < 2; ++c) {
                if (on[c] && !(d[c] > 0))
                    on[c] = false;
                if (on[c])
                    alpha[c] = rz[c] / d[c];
            }
            if (mg->kcycle)
                memcpy(rold, r, 2 * n * sizeof *rold);
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < 2; ++c)
                    if (on[c]) {
                        x[2 * i + c] += alpha[c] * p[2 * i + c];
                        r[2 * i + c] -= alpha[c] * q[2 * i + c];
                    }
            dot2(n, r, r, d);
            for (int c = 0; c < 2; ++c)
                if (on[c]) {
                    ++it[c];
                    rn[c] = sqrt(d[c]);
                    if (rn[c] <= tol * bn[c])
                        on[c] = false;
                }
            if (!on[0] && !on[1])
                break;
            vcycle2(mg, k, r, z, w);
            dot2(n, r, z, d);
            if (mg->kcycle)
                dot2(n, rold, z, e);
            double beta[2] = {0, 0};
            for (int c = 0; c < 2; ++c)
                if (on[c]) {
                    /* flexible (Polak-Ribiere) for the K-cycle */
                    beta[c] = (mg->kcycle ? d[c] - e[c] : d[c]) / rz[c];
                    rz[c] = d[c];
                }
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < 2; ++c)
                    if (on[c])
                        p[2 * i + c] = z[2 * i + c] + beta[c] * p[2 * i + c];
        }
    }
    multiply2(a, x, r);
    for (size_t i = 0; i < 2 * n; ++i)
        r[i] = b[i] - r[i];
    dot2(n, r, r, d);
    for (int c = 0; c < 2; ++c)
        relres[c] = bn[c] != 0 ? sqrt(d[c]) / bn[c] : 0;
}

/* sk__multilevel_solve of two right-hand sides in one pass. */
static void solve2(sk__multilevel *mg, const double *b, double *x, const sk__krylov_opts *opts,
                   size_t *its, double *worst, int *nomem, int *fail)
{
    size_t L = mg->L, nf = mg->A[L - 1].rows;
    workspace w;
    if (!ws_alloc(&w, mg, 2)) {
        *nomem = 1;
        ws_free(&w, L);
        return;
    }
    double *bf = w.b[L - 1];
    for (size_t i = 0; i < nf; ++i) {
        bf[2 * i] = b[i];
        bf[2 * i + 1] = b[nf + i];
    }
    for (size_t k = L - 1; k-- > 0;)
        restrict_to2(mg, k, w.b[k + 1], w.b[k]);
    coarse_solve2(mg, w.b[0], w.x[0], &w);
    size_t it[2] = {0, 0};
    double rr[2] = {0, 0};
    for (size_t k = 1; k < L; ++k) {
        memset(w.x[k], 0, 2 * mg->A[k].rows * sizeof(double));
        prolong_add2(mg, k - 1, 1, w.x[k - 1], w.x[k]);
        double tol = k < L - 1 ? 0 : opts->tolerance;
        size_t maxit = k < L - 1 ? opts->level_iterations : opts->max_iterations;
        if (mg->symmetric)
            pcg2(mg, k, w.b[k], w.x[k], tol, maxit, &w, it, rr);
        else
            bicgstab2(mg, k, w.b[k], w.x[k], tol, maxit, &w, it, rr);
    }
    if (L == 1)
        rr[0] = rr[1] = 0;
    const double *xf = w.x[L - 1];
    for (size_t i = 0; i < nf; ++i) {
        x[i] = xf[2 * i];
        x[nf + i] = xf[2 * i + 1];
    }
    for (int c = 0; c < 2; ++c) {
        if (L > 1 && it[c] > *its)
            *its = it[c];
        if (rr[c] > *worst)
            *worst = rr[c];
    }
    *fail |= w.fail;
    ws_free(&w, L);
}

/* u and v in one pass read each matrix once (about 20% less CPU at 1M), one column per thread
 * finishes sooner on two free cores (Floater at 1M on a quiet machine: solve 1.9 s against
 * 2.6 s); both give the same bits, so the choice does not change the result. */
static bool two_threads_free(void)
{
#if defined(SK_HAVE_OPENMP)
    return !omp_in_parallel() && omp_get_max_threads() >= 2;
#else
    return false;
#endif
}

sk_status sk__multilevel_solve(sk__multilevel *mg, size_t nrhs, const double *b, double *x,
                               const sk__krylov_opts *opts, sk__krylov_result *res,
                               sk_error *err)
{
    size_t L = mg->L, nf = mg->A[L - 1].rows;
    double tol = opts->tolerance;
    size_t maxit = opts->max_iterations, lit = opts->level_iterations;
    size_t its = 0;
    double worst = 0;
    int nomem = 0, fail = 0;
    if (nrhs == 2 && (opts->pair_always || !two_threads_free())) {
        solve2(mg, b, x, opts, &its, &worst, &nomem, &fail);
        nrhs = 0; /* done */
    }
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 1) reduction(max : its, worst) reduction(| : nomem, fail) if (nrhs > 1)
#endif
    for (long c = 0; c < (long)nrhs; ++c) {
        workspace w;
        if (!ws_alloc(&w, mg, 1)) {
            nomem = 1;
            ws_free(&w, L);
            continue;
        }
        /* restrict the right-hand side to every level */
        memcpy(w.b[L - 1], b + (size_t)c * nf, nf * sizeof(double));
        for (size_t k = L - 1; k-- > 0;)
            restrict_to(mg, k, w.b[k + 1], w.b[k]);
        coarse_solve(mg, w.b[0], w.x[0], &w);
        double rr = 0;
        size_t it = 0;
        for (size_t k = 1; k < L; ++k) {
            double *xk = k == L - 1 ? x + (size_t)c * nf : w.x[k];
            memset(xk, 0, mg->A[k].rows * sizeof *xk);
            prolong_add(mg, k - 1, 1, w.x[k - 1], xk);
            if (k < L - 1)
                krylov(mg, k, w.b[k], xk, 0, lit, &w, &rr);
            else
                it = krylov(mg, k, w.b[k], xk, tol, maxit, &w, &rr);
        }
        if (L == 1) {
            memcpy(x + (size_t)c * nf, w.x[0], nf * sizeof(double));
            rr = 0;
        }
        if (it > its)
            its = it;
        if (rr > worst)
            worst = rr;
        fail |= w.fail;
        ws_free(&w, L);
    }
    if (res) {
        res->iterations = its;
        res->residual = worst;
        res->converged = worst <= tol;
    }
    if (nomem)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for the multilevel workspace");
    if (fail)
        return sk__fail(err, SK_ERR_NUMERIC, "the coarsest direct solve failed");
    return SK_OK;
}
