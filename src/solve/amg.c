/* Aggregation AMG (see amg.h): pairwise heavy-edge matching applied twice per level (Notay's
 * double pairwise aggregation, here over the negative couplings' sizes), piecewise-constant or smoothed
 * prolongation (Vanek, Mandel, Brezina), Galerkin coarse operators, handed to the multilevel
 * object of krylov.c. */
#include "solve/amg.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SK_AMG_COARSE_MAX 3000
#define SK_AMG_MAX_LEVELS 40
#define SK_AMG_OMEGA (2.0 / 3.0)

/* Graphs are sk__csr (rows = cols = nodes, no self loops, val the edge weights). */

/* The unknowns' strength graph: max(-a_ij, 0) for i != j of the same component (i = j mod dim). */
static sk_status unknown_graph(const sk__csr *a, unsigned dim, sk__csr *g, sk_error *err)
{
    size_t n = a->rows, nnz = 0;
    for (size_t i = 0; i < n; ++i)
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            nnz += a->col[k] != i && a->col[k] % dim == i % dim;
    sk_status st = sk__csr_alloc(g, n, n, nnz, err);
    if (st)
        return st;
    size_t q = 0;
    for (size_t i = 0; i < n; ++i) {
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
            if (a->col[k] != i && a->col[k] % dim == i % dim) {
                g->col[q] = a->col[k];
                g->val[q++] = a->val[k] < 0 ? -a->val[k] : 0;
            }
        g->ptr[i + 1] = q;
    }
    return SK_OK;
}

/* A sparse row accumulator: the columns of the row that starts at position row gathered in
 * cols[row .. *q), their values summed in acc by column; mark[c] is where column c was last put
 * (SIZE_MAX: never). */
static void acc_add(size_t *mark, double *acc, uint32_t *cols, size_t row, size_t *q, uint32_t c,
                    double v)
{
    if (mark[c] == SIZE_MAX || mark[c] < row) {
        mark[c] = *q;
        acc[c] = 0;
        cols[(*q)++] = c;
    }
    acc[c] += v;
}

/* vals[row .. q) from the accumulator. */
static void acc_store(const double *acc, const uint32_t *cols, double *vals, size_t row, size_t q)
{
    for (size_t k = row; k < q; ++k)
        vals[k] = acc[cols[k]];
}

/* The graph of the groups map[i] (count of them): the weights between two groups summed, the
 * couplings inside a group dropped. */
static sk_status contract(const sk__csr *g, const uint32_t *map, size_t count, sk__csr *out,
                          sk_error *err)
{
    memset(out, 0, sizeof *out);
    sk_status st = SK_OK;
    size_t *start = sk__calloc_array(count + 1, sizeof *start);
    uint32_t *members = sk__malloc_array(g->rows ? g->rows : 1, sizeof *members);
    size_t *mark = sk__malloc_array(count ? count : 1, sizeof *mark);
    double *acc = sk__malloc_array(count ? count : 1, sizeof *acc);
    if (!start || !members || !mark || !acc ||
        (st = sk__csr_alloc(out, count, count, g->ptr[g->rows], err))) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for a graph of %zu nodes", count);
        goto done;
    }
    for (size_t i = 0; i < g->rows; ++i)
        start[map[i] + 1]++;
    for (size_t c = 0; c < count; ++c)
        start[c + 1] += start[c];
    for (size_t i = 0; i < g->rows; ++i)
        members[start[map[i]]++] = (uint32_t)i;
    for (size_t c = count; c > 0; --c) /* back to the starts */
        start[c] = start[c - 1];
    start[0] = 0;
    for (size_t c = 0; c < count; ++c)
        mark[c] = SIZE_MAX;
    size_t q = 0;
    for (size_t c = 0; c < count; ++c) {
        size_t row = q;
        for (size_t s = start[c]; s < start[c + 1]; ++s) {
            uint32_t i = members[s];
            for (size_t k = g->ptr[i]; k < g->ptr[i + 1]; ++k) {
                uint32_t d = map[g->col[k]];
                if (d != c)
                    acc_add(mark, acc, out->col, row, &q, d, g->val[k]);
            }
        }
        acc_store(acc, out->col, out->val, row, q);
        out->ptr[c + 1] = q;
    }
done:
    sk__free(start);
    sk__free(members);
    sk__free(mark);
    sk__free(acc);
    if (st)
        sk__csr_free(out);
    return st;
}

/* Heavy-edge matching in node order: each unmatched node pairs with its strongest unmatched
 * neighbour; a node left without one joins its strongest neighbour's aggregate, an isolated
 * node stays alone. */
/* Node i's strongest neighbour (among the unmatched ones when unmatched_only); SK_INVALID if none. */
static uint32_t strongest(const sk__csr *g, size_t i, const uint32_t *agg, bool unmatched_only)
{
    uint32_t best = SK_INVALID;
    double bw = -1;
    for (size_t e = g->ptr[i]; e < g->ptr[i + 1]; ++e)
        if ((!unmatched_only || agg[g->col[e]] == SK_INVALID) && g->val[e] > bw) {
            bw = g->val[e];
            best = g->col[e];
        }
    return best;
}

static void match(const sk__csr *g, uint32_t *agg, size_t *count)
{
    size_t k = 0;
    for (size_t i = 0; i < g->rows; ++i)
        agg[i] = SK_INVALID;
    for (size_t i = 0; i < g->rows; ++i) {
        if (agg[i] != SK_INVALID)
            continue;
        uint32_t best = strongest(g, i, agg, true);
        if (best != SK_INVALID)
            agg[i] = agg[best] = (uint32_t)k++;
    }
    for (size_t i = 0; i < g->rows; ++i) {
        if (agg[i] != SK_INVALID)
            continue;
        /* every neighbour is matched now (an unmatched one would have been paired) */
        uint32_t best = strongest(g, i, agg, false);
        agg[i] = best != SK_INVALID ? agg[best] : (uint32_t)k++;
    }
    *count = k;
}

sk_status sk__amg_aggregate(const sk__csr *a, unsigned dim, uint32_t *agg, size_t *count,
                            sk_error *err)
{
    if (dim == 0)
        dim = 1;
    *count = 0;
    if (a->rows != a->cols || a->rows % dim)
        return sk__fail(err, SK_ERR_ARG, "aggregation of a %zu x %zu matrix in blocks of %u",
                        a->rows, a->cols, dim);
    size_t nb = a->rows / dim;
    sk__csr g0 = {0}, g = {0}, g1 = {0};
    uint32_t *map = NULL, *first = sk__malloc_array(nb ? nb : 1, sizeof *first);
    sk_status st = first ? unknown_graph(a, dim, &g0, err)
                         : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (st)
        goto done;
    if (dim > 1) {
        if (!(map = sk__malloc_array(a->rows ? a->rows : 1, sizeof *map))) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        for (size_t i = 0; i < a->rows; ++i)
            map[i] = (uint32_t)(i / dim);
        if ((st = contract(&g0, map, nb, &g, err)))
            goto done;
        sk__csr_free(&g0);
    } else {
        g = g0;
        memset(&g0, 0, sizeof g0);
    }
    size_t c1 = 0, c2 = 0;
    match(&g, first, &c1);
    if ((st = contract(&g, first, c1, &g1, err)))
        goto done;
    match(&g1, agg, &c2); /* agg as scratch for the second pass over the c1 pairs */
    for (size_t b = 0; b < nb; ++b)
        first[b] = agg[first[b]];
    memcpy(agg, first, nb * sizeof *agg);
    *count = c2;
done:
    sk__csr_free(&g0);
    sk__csr_free(&g);
    sk__csr_free(&g1);
    sk__free(map);
    sk__free(first);
    return st;
}

sk_status sk__amg_prolongation(const sk__csr *a, unsigned dim, const uint32_t *agg, size_t count,
                               bool smooth, sk__csr *p, sk_error *err)
{
    if (dim == 0)
        dim = 1;
    size_t n = a->rows, nc = dim * count;
    sk_status st = sk__csr_alloc(p, n, nc, smooth ? a->ptr[n] + n : n, err);
    if (st)
        return st;
    size_t *mark = smooth ? sk__malloc_array(nc ? nc : 1, sizeof *mark) : NULL;
    double *acc = smooth ? sk__malloc_array(nc ? nc : 1, sizeof *acc) : NULL;
    if (smooth && (!mark || !acc)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu prolongation", n, nc);
        goto done;
    }
    for (size_t c = 0; smooth && c < nc; ++c)
        mark[c] = SIZE_MAX;
    size_t q = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t own = (uint32_t)(dim * agg[i / dim] + i % dim);
        double d = 0;
        for (size_t k = a->ptr[i]; smooth && k < a->ptr[i + 1]; ++k)
            if (a->col[k] == i)
                d = a->val[k];
        size_t row = q;
        p->col[q] = own;
        if (!smooth || d == 0) {
            p->val[q++] = 1;
            p->ptr[i + 1] = q;
            continue;
        }
        double s = SK_AMG_OMEGA / d;
        acc_add(mark, acc, p->col, row, &q, own, 1);
        for (size_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) {
            uint32_t j = a->col[k];
            acc_add(mark, acc, p->col, row, &q, (uint32_t)(dim * agg[j / dim] + j % dim),
                    -s * a->val[k]);
        }
        /* sorted columns (short rows: insertion sort) */
        for (size_t u = row + 1; u < q; ++u) {
            uint32_t key = p->col[u];
            size_t t = u;
            for (; t > row && p->col[t - 1] > key; --t)
                p->col[t] = p->col[t - 1];
            p->col[t] = key;
        }
        acc_store(acc, p->col, p->val, row, q);
        p->ptr[i + 1] = q;
    }
done:
    sk__free(mark);
    sk__free(acc);
    if (st)
        sk__csr_free(p);
    return st;
}

/* One coarsening step: the aggregates of a, their prolongation and the Galerkin operator;
 * *coarsened false (nothing built) when the aggregates would keep over 90% of the unknowns. */
static sk_status coarsen(const sk__csr *a, const sk__amg_opts *o, sk__csr *p, sk__csr *ac,
                         bool *coarsened, sk_error *err)
{
    unsigned dim = o->dim ? o->dim : 1;
    *coarsened = false;
    sk__csr r = {0};
    size_t count = 0;
    uint32_t *agg = sk__malloc_array(a->rows / dim ? a->rows / dim : 1, sizeof *agg);
    sk_status st = agg ? sk__amg_aggregate(a, dim, agg, &count, err)
                       : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (st || 10 * dim * count > 9 * a->rows)
        goto done;
    /* piecewise constant: P's columns are the map of sk__csr_galerkin_map */
    if ((st = sk__amg_prolongation(a, dim, agg, count, o->smooth, p, err)) ||
        (!o->smooth && (st = sk__csr_galerkin_map(a, p->col, p->cols, ac, err))) ||
        (o->smooth && ((st = sk__csr_transpose(p, &r, err)) ||
                       (st = sk__csr_galerkin(&r, a, p, ac, err))))) {
        sk__csr_free(p);
        goto done;
    }
    *coarsened = true;
done:
    sk__csr_free(&r);
    sk__free(agg);
    return st;
}

sk_status sk__amg_create(sk__csr *fine, const sk__amg_opts *opts, bool symmetric,
                         sk__multilevel **out, sk_error *err)
{
    *out = NULL;
    sk__amg_opts o = {0};
    if (opts)
        o = *opts;
    size_t coarse_max = o.coarse_max ? o.coarse_max : SK_AMG_COARSE_MAX;
    /* fine to coarse: ps[j] prolongs from ops[j] to ops[j - 1] (ops[-1] = fine) */
    sk__csr ps[SK_AMG_MAX_LEVELS], ops[SK_AMG_MAX_LEVELS];
    sk__csr pr[SK_AMG_MAX_LEVELS], opr[SK_AMG_MAX_LEVELS];
    size_t nl = 0;
    sk_status st = SK_OK;
    const sk__csr *cur = fine;
    while (cur->rows > coarse_max && nl + 1 < SK_AMG_MAX_LEVELS) {
        bool coarsened = false;
        if ((st = coarsen(cur, &o, &ps[nl], &ops[nl], &coarsened, err)))
            break;
        if (!coarsened)
            break;
        cur = &ops[nl++];
    }
    if (st) {
        for (size_t j = 0; j < nl; ++j) {
            sk__csr_free(&ps[j]);
            sk__csr_free(&ops[j]);
        }
        sk__csr_free(fine);
        return st;
    }
    /* coarsest first for the multilevel object */
    for (size_t k = 0; k < nl; ++k) {
        pr[k] = ps[nl - 1 - k];
        opr[k] = ops[nl - 1 - k];
    }
    st = sk__multilevel_create(fine, pr, opr, nl + 1, symmetric, out, err);
    if (st == SK_OK)
        sk__multilevel_set_galerkin(*out); /* opr are the products of coarsen */
    return st;
}
