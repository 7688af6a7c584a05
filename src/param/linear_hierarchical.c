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
#include "solve/amg.h"
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
/* AMG's coarse corrections times this (over-correction for the piecewise-constant
 * prolongation's low energy; lion head Loop x2, iterations at scale 1 / 1.5: Floater 27 / 21,
 * mean value 21 / 18, Tutte 21 / 19, LSCM 148 / 144) */
#define SK_AMG_CORRECTION 1.5

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

/* The state of one hierarchical solve: per hierarchy level the unknowns, the prolongation, and
 * for the selected levels (coarsest first) the prolongations between them and the coarse
 * operators. */
typedef struct hsolve {
    size_t L, U;      /* hierarchy levels, selected levels */
    uint32_t **lidx;  /* per level: vertex -> unknown or SK_INVALID; the finest is borrowed */
    size_t *nun;      /* per level: unknowns */
    size_t *sel;      /* the selected levels, coarsest first */
    sk__csr *p;       /* per level k: the prolongation from k to k + 1 */
    sk__csr *sp;      /* per selected level i: the prolongation from sel[i] to sel[i + 1] */
    sk__csr *ops;     /* per selected level: a rediscretized operator (harmonic) */
} hsolve;

static void hsolve_free(hsolve *hs)
{
    for (size_t k = 0; k < hs->L; ++k) {
        if (hs->lidx && k + 1 < hs->L)
            sk__free(hs->lidx[k]);
        if (hs->p)
            sk__csr_free(&hs->p[k]);
        if (hs->sp)
            sk__csr_free(&hs->sp[k]);
        if (hs->ops)
            sk__csr_free(&hs->ops[k]);
    }
    sk__free(hs->lidx);
    sk__free(hs->nun);
    sk__free(hs->sel);
    sk__free(hs->p);
    sk__free(hs->sp);
    sk__free(hs->ops);
    memset(hs, 0, sizeof *hs);
}

/* The unknowns of every level: a coarse vertex is free when the fine vertex it is kept from is
 * free and no fixed fine vertex was collapsed onto it (so a removed LSCM pin pins the vertex it
 * went to; the boundary of the fixed-boundary methods only collapses onto itself). */
static sk_status level_unknowns(const sk_hierarchy *h, const uint32_t *idx, size_t nverts,
                                hsolve *hs, sk_error *err)
{
    size_t L = hs->L;
    hs->nun[L - 1] = nverts;
    for (size_t k = L - 1; k-- > 0;) {
        size_t nc = sk_hierarchy_level_info(h, k).vertices;
        size_t nf = sk_hierarchy_level_info(h, k + 1).vertices;
        const uint32_t *fidx = k + 1 == L - 1 ? idx : hs->lidx[k + 1];
        const uint32_t *map = sk_hierarchy_vertex_map(h, k);
        size_t ns = 0;
        const sk_vertex_split *spl = sk_hierarchy_splits(h, k, &ns);
        uint32_t *ci = hs->lidx[k] = sk__malloc_array(nc ? nc : 1, sizeof(uint32_t));
        if (!ci)
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
        for (size_t c = 0; c < nc; ++c)
            ci[c] = SK_INVALID;
        for (size_t f = 0; f < nf; ++f)
            if (map[f] != SK_INVALID && fidx[f] != SK_INVALID)
                ci[map[f]] = 0;
        for (size_t j = 0; j < ns; ++j)
            if (fidx[spl[j].v] == SK_INVALID)
                ci[spl[j].w0] = SK_INVALID;
        size_t n = 0;
        for (size_t c = 0; c < nc; ++c)
            if (ci[c] != SK_INVALID)
                ci[c] = (uint32_t)n++;
        hs->nun[k] = n;
    }
    hs->lidx[L - 1] = (uint32_t *)idx; /* borrowed: not freed */
    return SK_OK;
}

/* Levels of the hierarchy used: every SK_HLINEAR_STRIDE-th from the input down. */
#define SK_HLINEAR_STRIDE 2

/* The selected levels (the input and every SK_HLINEAR_STRIDE-th below it, down to the finest
 * with at most coarse_max unknowns; the hierarchy may stop above the target when collapses run
 * out) and the prolongations between them: products of the level ones. */
static sk_status select_levels(const sk_hierarchy *h, unsigned dim, size_t coarse_max,
                               hsolve *hs, sk_error *err)
{
    size_t L = hs->L, first = 0;
    while (first + 1 < L - 1 && hs->nun[first + 1] <= coarse_max)
        first++;
    sk_status st = SK_OK;
    for (size_t k = first; k + 1 < L; ++k)
        if ((st = build_prolongation(h, k, hs->lidx[k + 1], hs->nun[k + 1], hs->lidx[k],
                                     hs->nun[k], dim, &hs->p[k], err)))
            return st;
    size_t tmp[64], nt = 0;
    for (size_t k = L - 1;; k = k >= first + SK_HLINEAR_STRIDE ? k - SK_HLINEAR_STRIDE : first) {
        tmp[nt++] = k;
        if (k == first || nt == 64)
            break;
    }
    hs->U = nt;
    for (size_t i = 0; i < nt; ++i)
        hs->sel[i] = tmp[nt - 1 - i];
    for (size_t i = 0; i + 1 < hs->U; ++i) {
        sk__csr acc = hs->p[hs->sel[i]];
        memset(&hs->p[hs->sel[i]], 0, sizeof acc);
        for (size_t k = hs->sel[i] + 1; k < hs->sel[i + 1]; ++k) {
            sk__csr prod;
            st = sk__csr_product(&hs->p[k], &acc, &prod, err);
            sk__csr_free(&acc);
            if (st)
                return st;
            acc = prod;
        }
        hs->sp[i] = acc;
    }
    return SK_OK;
}

/* The harmonic method's own matrix on each selected coarse level mesh (the cotangent matrix is
 * the finite element stiffness matrix, which the Galerkin product of a nested linear space
 * reproduces: this rediscretization is close to Galerkin at a quarter of its entries); the
 * level meshes come from the coarsest by the vertex splits. */
static sk_status rediscretize(const sk_hierarchy *h, sk_param_method method, hsolve *hs,
                              sk_error *err)
{
    sk_mesh *lm = NULL;
    sk_status st = sk_mesh_copy(sk_hierarchy_coarsest(h), &lm, err);
    for (size_t k = 0, i = 0; st == SK_OK && i + 1 < hs->U; ++k) {
        if (k == hs->sel[i]) {
            if ((st = level_operator(lm, method, hs->lidx[k], hs->nun[k], &hs->ops[i], err)))
                break;
            if (++i + 1 == hs->U)
                break;
        }
        st = sk_hierarchy_split(h, k, lm, err);
    }
    sk_mesh_destroy(&lm);
    return st;
}

/* The nested Krylov solve over a built multilevel object; stats (t[0] start, t[1] end of the
 * analysis: the hierarchy or the matrix conversion). */
static sk_status krylov_run(sk__multilevel *mg, const sk_sparse *a, bool symmetric, size_t nrhs,
                            const double *rhs, double *x, const sk_param_opts *o, const double t[2],
                            sk_param_stats *stats, sk_error *err)
{
    double t2 = sk_seconds();
    sk__krylov_opts ko;
    ko.tolerance = o->tolerance > 0 ? o->tolerance : SK_HLINEAR_TOLERANCE;
    ko.max_iterations = o->max_iterations ? o->max_iterations : 500;
    ko.level_iterations = SK_HLINEAR_LEVEL_ITERATIONS;
    ko.pair_always = false; /* u, v on two threads where two are free (krylov.c) */
    sk__krylov_result kr;
    sk_status st = sk__multilevel_solve(mg, nrhs, rhs, x, &ko, &kr, err);
    if (st)
        return st;
    double t3 = sk_seconds();
    if (!kr.converged)
        st = sk__fail(err, SK_ERR_NUMERIC, "the %s solve stopped at relative residual "
                      "%.3g after %zu iterations (tolerance %.3g)",
                      o->solver == SK_LINEAR_AMG ? "algebraic multigrid" : "hierarchical",
                      kr.residual, kr.iterations, ko.tolerance);
    if (stats) {
        sk__multilevel_stats ms;
        sk__multilevel_stats_get(mg, &ms);
        stats->solver = o->solver;
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
        stats->solve.analyse_seconds = t[1] - t[0]; /* the hierarchy */
        stats->solve.factor_seconds = t2 - t[1];    /* prolongations, operators, coarse factor */
        stats->solve.solve_seconds = t3 - t2;       /* nested Krylov iterations */
    }
    return st;
}

/* The multilevel hierarchy over the selected levels and its nested Krylov solve; stats. */
static sk_status multilevel_run(const sk_sparse *a, bool symmetric, hsolve *hs, bool redisc,
                                size_t nrhs, const double *rhs, double *x, const sk_param_opts *o,
                                const double t[2], sk_param_stats *stats, sk_error *err)
{
    sk__csr fine = {0};
    sk__multilevel *mg = NULL;
    sk_status st = sk__csr_from_sparse(a, &fine, err);
    /* the multilevel object takes the prolongations and operators over (and zeroes them) */
    if (st == SK_OK)
        st = sk__multilevel_create(&fine, hs->sp, redisc ? hs->ops : NULL, hs->U, symmetric, &mg,
                                   err);
    if (st == SK_OK)
        st = krylov_run(mg, a, symmetric, nrhs, rhs, x, o, t, stats, err);
    sk__multilevel_destroy(&mg);
    sk__csr_free(&fine);
    return st;
}

sk_status sk__param_solve_amg(const sk_sparse *a, bool symmetric, unsigned dim, size_t nrhs,
                              const double *rhs, double *x, const sk_param_opts *o,
                              sk_param_stats *stats, sk_error *err)
{
    double t[2] = {sk_seconds(), 0};
    sk__csr fine = {0};
    sk__multilevel *mg = NULL;
    sk__amg_opts ao = {0};
    ao.coarse_max = dim * o->coarse_vertices;
    ao.dim = dim;
    sk_status st = sk__csr_from_sparse(a, &fine, err);
    t[1] = sk_seconds();
    if (st == SK_OK)
        st = sk__amg_create(&fine, &ao, symmetric, &mg, err);
    /* Tutte / harmonic: the K-cycle (CG 42 iterations where the V-cycle took 81, harmonic at 1M
     * triangles); otherwise the W-cycle: BiCGStab needs a linear preconditioner (Floater at 1M:
     * 33 iterations, V-cycle 65), and on LSCM the K-cycle took 497 CG iterations where the
     * W-cycle took 149 (lion head Loop x2: its low modes are similarities, which piecewise
     * constants do not carry) */
    bool k = symmetric && dim == 1;
    if (st == SK_OK)
        sk__multilevel_set_cycle(mg, SK_AMG_CORRECTION, k ? 1 : 2, k);
    if (st == SK_OK)
        st = krylov_run(mg, a, symmetric, nrhs, rhs, x, o, t, stats, err);
    sk__multilevel_destroy(&mg);
    sk__csr_free(&fine);
    return st;
}

sk_status sk__param_solve_hierarchical(const sk_mesh *m, sk_param_method method,
                                       const sk_sparse *a, bool symmetric, const uint32_t *idx,
                                       unsigned dim, size_t nrhs, const double *rhs, double *x,
                                       const sk_param_opts *o, sk_param_stats *stats,
                                       sk_error *err)
{
    sk_status st = SK_OK;
    sk_hierarchy *h = NULL;
    hsolve hs = {0};
    double t[2] = {sk_seconds(), 0};
    size_t nverts = a->n / dim;
    size_t coarse_max = o->coarse_vertices ? o->coarse_vertices : SK_HLINEAR_COARSE_VERTICES;
    if (m->num_deleted_vertices > 0 || nverts <= 2 * coarse_max) {
        /* small (or not compacted): the hierarchy has nothing to win */
        if (stats)
            stats->levels = 1;
        return sk__param_solve_direct(m, a, symmetric, idx, dim, nrhs, rhs, x, o, stats, err);
    }
    sk_hierarchy_opts ho = {0};
    ho.seed = 1;
    ho.target_faces = 2 * coarse_max;
    if ((st = sk_hierarchy_build(m, &ho, &h, err)))
        goto done;
    t[1] = sk_seconds();
    size_t L = hs.L = sk_hierarchy_num_levels(h);
    hs.lidx = sk__calloc_array(L, sizeof *hs.lidx);
    hs.nun = sk__calloc_array(L, sizeof *hs.nun);
    hs.sel = sk__calloc_array(L, sizeof *hs.sel);
    hs.p = sk__calloc_array(L, sizeof *hs.p);
    hs.sp = sk__calloc_array(L, sizeof *hs.sp);
    hs.ops = sk__calloc_array(L, sizeof *hs.ops);
    if (!hs.lidx || !hs.nun || !hs.sel || !hs.p || !hs.sp || !hs.ops) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if ((st = level_unknowns(h, idx, nverts, &hs, err)) ||
        (st = select_levels(h, dim, coarse_max, &hs, err)))
        goto done;
    /* coarse operators: rediscretized for the harmonic method; for the others the Galerkin
     * products (Tutte's graph Laplacian and the normalised Floater / mean value rows of a
     * coarse mesh are poor stand-ins for them: 2-3x the iterations measured on a 1M-triangle
     * disk) */
    bool redisc = method == SK_PARAM_HARMONIC && dim == 1;
    if (redisc && (st = rediscretize(h, method, &hs, err)))
        goto done;
    sk_hierarchy_destroy(&h);
    st = multilevel_run(a, symmetric, &hs, redisc, nrhs, rhs, x, o, t, stats, err);
done:
    hsolve_free(&hs);
    sk_hierarchy_destroy(&h);
    return st;
}
