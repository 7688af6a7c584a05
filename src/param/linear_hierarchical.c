/* Hierarchical solve of the linear parametrization systems over the progressive mesh
 * (Hormann, Greiner, Campagna, sections 2-3, used as a multigrid hierarchy): level k + 1's
 * unknowns are prolonged from level k's through the vertex map (kept vertices) and the
 * barycentric coordinates of the inserted ones in their parent triangles (section 3), the
 * coarse operators are Galerkin products P^T A P of the input system (so every level solves the
 * same problem and the finest level is exactly the direct solver's system), the coarsest level
 * is factored directly, and the finer levels are solved by Krylov iterations preconditioned by
 * the V-cycle (src/solve/krylov.c) starting from the prolonged coarser solution. */
#include "param_internal.h"
#include "core/internal.h"
#include "solve/krylov.h"
#include "surfkit/hierarchy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Vertices of the coarsest level used (its system is factored directly): small enough that its
 * factor costs a few milliseconds per triangular solve, large enough that the hierarchy build
 * stops early. */
#define SK_HLINEAR_COARSE_VERTICES 20000
/* Krylov steps on each intermediate level of the nested iteration. */
#define SK_HLINEAR_LEVEL_ITERATIONS 2
/* Default tolerance: relative residual ||b - A x|| / ||b|| (a direct solve reaches ~1e-15). */
#define SK_HLINEAR_TOLERANCE 1e-12

/* The prolongation from level k (unknowns cidx) to level k + 1 (unknowns fidx), dim components
 * per vertex (unknown dim * idx + c). */
static sk_status build_prolongation(const sk_hierarchy *h, size_t k, const uint32_t *fidx,
                                    size_t nfu, const uint32_t *cidx, size_t ncu, unsigned dim,
                                    sk__csr *p, sk_error *err)
{
    const uint32_t *map = sk_hierarchy_vertex_map(h, k);
    size_t nsplit = 0;
    const sk_vertex_split *sp = sk_hierarchy_splits(h, k, &nsplit);
    size_t nf = sk_hierarchy_level_info(h, k + 1).vertices;
    memset(p, 0, sizeof *p);
    sk_status st = SK_OK;
    uint32_t *split_of = sk__malloc_array(nf ? nf : 1, sizeof *split_of);
    p->rows = dim * nfu;
    p->cols = dim * ncu;
    p->ptr = sk__calloc_array(p->rows + 1, sizeof *p->ptr);
    p->col = sk__malloc_array(3 * p->rows + 1, sizeof *p->col);
    p->val = sk__malloc_array(3 * p->rows + 1, sizeof *p->val);
    if (!split_of || !p->ptr || !p->col || !p->val) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for a prolongation");
        goto done;
    }
    for (size_t f = 0; f < nf; ++f)
        split_of[f] = SK_INVALID;
    for (size_t j = 0; j < nsplit; ++j)
        split_of[sp[j].v] = (uint32_t)j;
    size_t q = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (fidx[f] == SK_INVALID)
            continue;
        uint32_t cols[3];
        double vals[3];
        int len = 0;
        if (map[f] != SK_INVALID) {
            if (cidx[map[f]] != SK_INVALID) {
                cols[0] = cidx[map[f]];
                vals[0] = 1;
                len = 1;
            }
        } else if (split_of[f] != SK_INVALID) {
            const sk_vertex_split *s = &sp[split_of[f]];
            for (int t = 0; t < 3; ++t) {
                uint32_t c = cidx[s->parent[t]];
                if (c == SK_INVALID || s->bary[t] == 0)
                    continue; /* a fixed parent: the correction is zero there */
                int u = len++;
                for (; u > 0 && cols[u - 1] > c; --u) {
                    cols[u] = cols[u - 1];
                    vals[u] = vals[u - 1];
                }
                cols[u] = c;
                vals[u] = s->bary[t];
            }
        } else {
            st = sk__fail(err, SK_ERR_ARG, "vertex %zu of level %zu is neither kept nor split", f,
                          k + 1);
            goto done;
        }
        for (unsigned c = 0; c < dim; ++c) {
            size_t row = dim * (size_t)fidx[f] + c;
            p->ptr[row] = q; /* rows are visited in increasing order: fidx follows f */
            for (int t = 0; t < len; ++t) {
                p->col[q] = dim * cols[t] + c;
                p->val[q++] = vals[t];
            }
            p->ptr[row + 1] = q;
        }
    }
done:
    sk__free(split_of);
    if (st)
        sk__csr_free(p);
    return st;
}

/* The method's matrix on a level mesh, rows and columns the free vertices (idx), in rows. */
static sk_status level_operator(const sk_mesh *lm, sk_param_method method, const uint32_t *idx,
                                size_t n, sk__csr *out, sk_error *err)
{
    memset(out, 0, sizeof *out);
    sk_status st = SK_OK;
    double *w = sk__malloc_array(lm->num_halfedges ? lm->num_halfedges : 1, sizeof *w);
    if (!w)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if ((st = sk_param_weights(lm, method, w, err)))
        goto done;
    size_t nnz = 0;
    for (size_t v = 0; v < lm->num_vertices; ++v)
        if (idx[v] != SK_INVALID)
            nnz += 1 + sk_mesh_valence(lm, (uint32_t)v);
    out->rows = out->cols = n;
    out->ptr = sk__calloc_array(n + 1, sizeof *out->ptr);
    out->col = sk__malloc_array(nnz ? nnz : 1, sizeof *out->col);
    out->val = sk__malloc_array(nnz ? nnz : 1, sizeof *out->val);
    if (!out->ptr || !out->col || !out->val) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    size_t q = 0;
    for (size_t v = 0; v < lm->num_vertices; ++v) {
        uint32_t i = idx[v];
        if (i == SK_INVALID)
            continue;
        size_t start = q;
        double diag = 0;
        uint32_t h0 = lm->v_halfedge[v], h = h0;
        do {
            uint32_t j = idx[sk_to(lm, h)];
            diag += w[h];
            if (j != SK_INVALID) {
                size_t u = q++;
                for (; u > start && out->col[u - 1] > j; --u) {
                    out->col[u] = out->col[u - 1];
                    out->val[u] = out->val[u - 1];
                }
                out->col[u] = j;
                out->val[u] = -w[h];
            }
            h = sk_cw_out(lm, h);
        } while (h != h0);
        size_t u = q++;
        for (; u > start && out->col[u - 1] > i; --u) {
            out->col[u] = out->col[u - 1];
            out->val[u] = out->val[u - 1];
        }
        out->col[u] = i;
        out->val[u] = diag;
        if (!isfinite(diag)) {
            st = sk__fail(err, SK_ERR_NUMERIC, "non-finite weights on a coarse level");
            goto done;
        }
        out->ptr[i + 1] = q; /* free vertices are numbered in vertex order */
    }
done:
    sk__free(w);
    if (st)
        sk__csr_free(out);
    return st;
}

/* Levels of the hierarchy used: every SK_HLINEAR_STRIDE-th from the input down. */
#define SK_HLINEAR_STRIDE 2

sk_status sk__param_solve_hierarchical(const sk_mesh *m, sk_param_method method,
                                       const sk_sparse *a, bool symmetric, const uint32_t *idx,
                                       unsigned dim, size_t nrhs, const double *rhs, double *x,
                                       const sk_param_opts *o, sk_param_stats *stats,
                                       sk_error *err)
{
    sk_status st = SK_OK;
    sk_hierarchy *h = NULL;
    sk_mesh *lm = NULL;
    uint32_t **lidx = NULL;
    size_t *nun = NULL, *sel = NULL;
    sk__csr *p = NULL, *sp = NULL, *ops = NULL, fine = {0};
    sk__multilevel *mg = NULL;
    size_t L = 0, U = 0;
    double t0 = sk_seconds();
    size_t nverts = a->n / dim;
    size_t coarse_max = o->coarse_vertices ? o->coarse_vertices : SK_HLINEAR_COARSE_VERTICES;
    if (m->num_deleted_vertices > 0 || nverts <= 2 * coarse_max) {
        /* small (or not compacted): the hierarchy has nothing to win */
        if (stats)
            stats->levels = 1;
        st = sk__param_solve_direct(m, a, symmetric, idx, dim, nrhs, rhs, x, o, stats, err);
        goto done;
    }
    sk_hierarchy_opts ho = {0};
    ho.seed = 1;
    ho.target_faces = 2 * coarse_max;
    if ((st = sk_hierarchy_build(m, &ho, &h, err)))
        goto done;
    double t1 = sk_seconds();
    L = sk_hierarchy_num_levels(h);
    lidx = sk__calloc_array(L, sizeof *lidx);
    nun = sk__calloc_array(L, sizeof *nun);
    sel = sk__calloc_array(L, sizeof *sel);
    p = sk__calloc_array(L, sizeof *p);
    sp = sk__calloc_array(L, sizeof *sp);
    ops = sk__calloc_array(L, sizeof *ops);
    if (!lidx || !nun || !sel || !p || !sp || !ops) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    /* unknowns of every level: a coarse vertex is free when the fine vertex it is kept from is
     * free and no fixed fine vertex was collapsed onto it (so a removed LSCM pin pins the vertex
     * it went to; the boundary of the fixed-boundary methods only collapses onto itself) */
    nun[L - 1] = nverts;
    for (size_t k = L - 1; k-- > 0;) {
        size_t nc = sk_hierarchy_level_info(h, k).vertices, nf = sk_hierarchy_level_info(h, k + 1).vertices;
        const uint32_t *fidx = k + 1 == L - 1 ? idx : lidx[k + 1];
        const uint32_t *map = sk_hierarchy_vertex_map(h, k);
        size_t ns = 0;
        const sk_vertex_split *spl = sk_hierarchy_splits(h, k, &ns);
        lidx[k] = sk__malloc_array(nc ? nc : 1, sizeof(uint32_t));
        if (!lidx[k]) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        for (size_t c = 0; c < nc; ++c)
            lidx[k][c] = SK_INVALID;
        for (size_t f = 0; f < nf; ++f)
            if (map[f] != SK_INVALID && fidx[f] != SK_INVALID)
                lidx[k][map[f]] = 0;
        for (size_t j = 0; j < ns; ++j)
            if (fidx[spl[j].v] == SK_INVALID)
                lidx[k][spl[j].w0] = SK_INVALID;
        size_t n = 0;
        for (size_t c = 0; c < nc; ++c)
            if (lidx[k][c] != SK_INVALID)
                lidx[k][c] = (uint32_t)n++;
        nun[k] = n;
    }
    lidx[L - 1] = (uint32_t *)idx; /* borrowed: not freed */
    /* the coarsest level used: the finest one that is small enough (the hierarchy may stop
     * above the target when collapses run out) */
    size_t first = 0;
    while (first + 1 < L - 1 && nun[first + 1] <= coarse_max)
        first++;
    for (size_t k = first; k + 1 < L; ++k)
        if ((st = build_prolongation(h, k, lidx[k + 1], nun[k + 1], lidx[k], nun[k], dim, &p[k],
                                     err)))
            goto done;
    size_t stride = SK_HLINEAR_STRIDE;
    /* selected levels, coarsest first; the coarsest used is always `first` */
    size_t tmp[64], nt = 0;
    for (size_t k = L - 1;; k = k >= first + stride ? k - stride : first) {
        tmp[nt++] = k;
        if (k == first || nt == 64)
            break;
    }
    U = nt;
    for (size_t i = 0; i < U; ++i)
        sel[i] = tmp[U - 1 - i];
    /* prolongations between selected levels: products of the level ones */
    for (size_t i = 0; i + 1 < U; ++i) {
        sk__csr acc = p[sel[i]];
        memset(&p[sel[i]], 0, sizeof acc);
        for (size_t k = sel[i] + 1; k < sel[i + 1]; ++k) {
            sk__csr prod;
            st = sk__csr_product(&p[k], &acc, &prod, err);
            sk__csr_free(&acc);
            if (st)
                goto done;
            acc = prod;
        }
        sp[i] = acc;
    }
    /* coarse operators: for the harmonic method its own matrix on each level mesh (the
     * cotangent matrix is the finite element stiffness matrix, which the Galerkin product of a
     * nested linear space reproduces: this rediscretization is close to Galerkin at a quarter of
     * its entries); for the others the Galerkin products (Tutte's graph Laplacian and the
     * normalised Floater / mean value rows of a coarse mesh are poor stand-ins for them: 2-3x
     * the iterations measured on a 1M-triangle disk) */
    bool redisc = method == SK_PARAM_HARMONIC && dim == 1;
    if (redisc) {
        if ((st = sk_mesh_copy(sk_hierarchy_coarsest(h), &lm, err)))
            goto done;
        for (size_t k = 0, i = 0; i + 1 < U; ++k) {
            if (k == sel[i]) {
                if ((st = level_operator(lm, method, lidx[k], nun[k], &ops[i], err)))
                    goto done;
                i++;
                if (i + 1 == U)
                    break;
            }
            if ((st = sk_hierarchy_split(h, k, lm, err)))
                goto done;
        }
        sk_mesh_destroy(&lm);
    }
    sk_hierarchy_destroy(&h);
    if ((st = sk__csr_from_sparse(a, &fine, err)))
        goto done;
    st = sk__multilevel_create(&fine, sp, redisc ? ops : NULL, U, symmetric, &mg, err);
    if (st)
        goto done;
    double t2 = sk_seconds();
    sk__krylov_opts ko;
    ko.tolerance = o->tolerance > 0 ? o->tolerance : SK_HLINEAR_TOLERANCE;
    ko.max_iterations = o->max_iterations ? o->max_iterations : 500;
    ko.level_iterations = SK_HLINEAR_LEVEL_ITERATIONS;
    sk__krylov_result kr;
    if ((st = sk__multilevel_solve(mg, nrhs, rhs, x, &ko, &kr, err)))
        goto done;
    double t3 = sk_seconds();
    if (!kr.converged)
        st = sk__fail(err, SK_ERR_NUMERIC, "the hierarchical solve stopped at relative residual "
                      "%.3g after %zu iterations (tolerance %.3g)", kr.residual, kr.iterations,
                      ko.tolerance);
    if (stats) {
        sk__multilevel_stats ms;
        sk__multilevel_stats_get(mg, &ms);
        stats->levels = ms.levels;
        stats->iterations = kr.iterations;
        stats->residual = kr.residual;
        stats->solve.kind = symmetric ? SK_SOLVER_CHOLESKY : SK_SOLVER_LU;
        stats->solve.n = a->n;
        stats->solve.nnz = a->nnz;
        stats->solve.factor_nnz = ms.coarse_factor_nnz;
        stats->solve.factorizations = 1;
        stats->solve.solves = 1;
        stats->solve.rhs = nrhs;
        stats->solve.analyse_seconds = t1 - t0; /* the hierarchy */
        stats->solve.factor_seconds = t2 - t1;  /* prolongations, operators, coarse factor */
        stats->solve.solve_seconds = t3 - t2;   /* nested Krylov iterations */
    }
done:
    sk__multilevel_destroy(&mg);
    sk__csr_free(&fine);
    sk_mesh_destroy(&lm);
    for (size_t k = 0; k < L; ++k) {
        if (lidx && k + 1 < L)
            sk__free(lidx[k]);
        if (p)
            sk__csr_free(&p[k]);
        if (sp)
            sk__csr_free(&sp[k]);
        if (ops)
            sk__csr_free(&ops[k]);
    }
    sk__free(lidx);
    sk__free(nun);
    sk__free(sel);
    sk__free(p);
    sk__free(sp);
    sk__free(ops);
    sk_hierarchy_destroy(&h);
    return st;
}
