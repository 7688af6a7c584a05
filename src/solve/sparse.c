/* Triplets -> compressed sparse columns, duplicates summed (the CSparse cs_compress/cs_dupl
 * scheme, done as two stable bucket passes so that rows come out sorted in every column). */
#include "surfkit/solve.h"
#include "core/internal.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>


sk_status sk_triplets_reserve(sk_triplets *t, size_t capacity, sk_error *err)
{
    if (capacity <= t->capacity)
        return SK_OK;
    uint32_t *r = sk__realloc_array(t->rows, capacity, sizeof *r);
    if (r)
        t->rows = r;
    uint32_t *c = sk__realloc_array(t->cols, capacity, sizeof *c);
    if (c)
        t->cols = c;
    double *v = sk__realloc_array(t->values, capacity, sizeof *v);
    if (v)
        t->values = v;
    if (!r || !c || !v)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for %zu matrix entries", capacity);
    t->capacity = capacity;
    return SK_OK;
}

sk_status sk_triplets_add(sk_triplets *t, uint32_t row, uint32_t col, double value)
{
    if (t->count == t->capacity) {
        sk_status st = sk_triplets_reserve(t, t->capacity < 16 ? 32 : 2 * t->capacity, NULL);
        if (st)
            return st;
    }
    t->rows[t->count] = row;
    t->cols[t->count] = col;
    t->values[t->count] = value;
    t->count++;
    return SK_OK;
}

void sk_triplets_clear(sk_triplets *t)
{
    t->count = 0;
}

void sk_triplets_free(sk_triplets *t)
{
    sk__free(t->rows);
    sk__free(t->cols);
    sk__free(t->values);
    memset(t, 0, sizeof *t);
}

void sk_sparse_destroy(sk_sparse **a)
{
    if (!a || !*a)
        return;
    sk__free((*a)->colptr);
    sk__free((*a)->rowind);
    sk__free((*a)->values);
    sk__free((*a)->map);
    sk__free(*a);
    *a = NULL;
}

sk_status sk_sparse_from_triplets(size_t n, const sk_triplets *t, sk_sparse_storage storage,
                                  sk_sparse **out, sk_error *err)
{
    *out = NULL;
    if (n == 0 || n >= (size_t)INT_MAX || t->count >= (size_t)INT_MAX)
        return sk__fail(err, SK_ERR_ARG, "matrix size %zu with %zu entries is out of range", n,
                        t->count);
    sk_status st = SK_OK;
    size_t nt = t->count;
    size_t *rowcount = NULL, *colcount = NULL;
    uint32_t *byrow = NULL, *bycol = NULL;
    sk_sparse *a = sk__calloc_array(1, sizeof *a);
    rowcount = sk__calloc_array(n + 1, sizeof *rowcount);
    colcount = sk__calloc_array(n + 1, sizeof *colcount);
    byrow = sk__malloc_array(nt, sizeof *byrow);
    bycol = sk__malloc_array(nt, sizeof *bycol);
    if (a) {
        a->colptr = sk__calloc_array(n + 1, sizeof(int));
        a->map = sk__malloc_array(nt, sizeof(size_t));
    }
    if (!a || !rowcount || !colcount || !byrow || !bycol || !a->colptr || !a->map) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory assembling a %zu x %zu matrix", n, n);
        goto done;
    }
    a->n = n;
    a->storage = storage;
    a->num_map = nt;
    /* pass 1: bucket by row (stable) */
    size_t kept = 0;
    for (size_t k = 0; k < nt; ++k) {
        uint32_t r = t->rows[k], c = t->cols[k];
        if (r >= n || c >= n) {
            st = sk__fail(err, SK_ERR_ARG, "matrix entry %zu at (%u, %u) is outside %zu x %zu", k,
                          r, c, n, n);
            goto done;
        }
        a->map[k] = SIZE_MAX;
        if (storage == SK_SPARSE_LOWER && r < c)
            continue;
        rowcount[r + 1]++;
        colcount[c + 1]++;
        kept++;
    }
    for (size_t i = 0; i < n; ++i) {
        rowcount[i + 1] += rowcount[i];
        colcount[i + 1] += colcount[i];
    }
    for (size_t k = 0; k < nt; ++k) {
        if (storage == SK_SPARSE_LOWER && t->rows[k] < t->cols[k])
            continue;
        byrow[rowcount[t->rows[k]]++] = (uint32_t)k;
    }
    /* pass 2: walk rows in order, bucket by column: rows ascend within each column */
    for (size_t i = 0; i < kept; ++i) {
        uint32_t k = byrow[i];
        bycol[colcount[t->cols[k]]++] = k;
    }
    /* colcount[c] is now the end of column c; merge duplicates */
    a->rowind = sk__malloc_array(kept ? kept : 1, sizeof(int));
    a->values = sk__malloc_array(kept ? kept : 1, sizeof(double));
    if (!a->rowind || !a->values) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory assembling a %zu x %zu matrix", n, n);
        goto done;
    }
    size_t nz = 0, begin = 0;
    for (size_t c = 0; c < n; ++c) {
        a->colptr[c] = (int)nz;
        size_t end = colcount[c];
        size_t col_start = nz;
        for (size_t i = begin; i < end; ++i) {
            uint32_t k = bycol[i];
            int r = (int)t->rows[k];
            if (nz > col_start && a->rowind[nz - 1] == r) {
                a->values[nz - 1] += t->values[k];
            } else {
                a->rowind[nz] = r;
                a->values[nz] = t->values[k];
                nz++;
            }
            a->map[k] = nz - 1;
        }
        begin = end;
    }
    a->colptr[n] = (int)nz;
    a->nnz = nz;
done:
    sk__free(rowcount);
    sk__free(colcount);
    sk__free(byrow);
    sk__free(bycol);
    if (st)
        sk_sparse_destroy(&a);
    *out = a;
    return st;
}

sk_status sk_sparse_update_values(sk_sparse *a, const sk_triplets *t, sk_error *err)
{
    if (t->count != a->num_map)
        return sk__fail(err, SK_ERR_ARG, "%zu new entries for a matrix built from %zu", t->count,
                        a->num_map);
    memset(a->values, 0, a->nnz * sizeof(double));
    for (size_t k = 0; k < t->count; ++k)
        if (a->map[k] != SIZE_MAX)
            a->values[a->map[k]] += t->values[k];
    return SK_OK;
}

void sk_sparse_multiply(const sk_sparse *a, const double *x, double *y)
{
    memset(y, 0, a->n * sizeof(double));
    for (size_t c = 0; c < a->n; ++c) {
        for (int p = a->colptr[c]; p < a->colptr[c + 1]; ++p) {
            size_t r = (size_t)a->rowind[p];
            y[r] += a->values[p] * x[c];
            if (a->storage == SK_SPARSE_LOWER && r != c)
                y[c] += a->values[p] * x[r];
        }
    }
}
