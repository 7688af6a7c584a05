/* Fixed-boundary linear parametrization: minimise eq. (1) of Hormann, Greiner, Campagna,
 * E = 1/2 sum c_ij |p_i - p_j|^2, i.e. solve sum_j w_ij (p_i - p_j) = 0 for the free vertices
 * with the fixed ones moved to the right-hand side (which keeps a symmetric matrix symmetric,
 * as Botsch et al. advise). u and v share the matrix: one factorization, two right-hand sides. */
#include "param_internal.h"
#include "core/internal.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool vertex_alive(const sk_mesh *m, size_t v)
{
    return !m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID;
}

/* Gauss-Seidel sweeps p_i <- sum_j w_ij p_j / sum_j w_ij from the given uv (warm start). */
static sk_status gauss_seidel(const sk_mesh *m, const double *w, const uint8_t *is_fixed,
                              const sk_param_opts *o, double *uv, sk_param_stats *stats,
                              sk_error *err)
{
    double tol = o->tolerance > 0 ? o->tolerance : 1e-10;
    size_t maxit = o->max_iterations ? o->max_iterations : 10000;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t v = 0; v < m->num_vertices; ++v)
        if (vertex_alive(m, v) && is_fixed[v])
            for (int c = 0; c < 2; ++c) {
                lo[c] = fmin(lo[c], uv[2 * v + c]);
                hi[c] = fmax(hi[c], uv[2 * v + c]);
            }
    double extent = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(extent > 0))
        extent = 1;
    size_t it = 0;
    for (; it < maxit; ++it) {
        double change = 0;
        for (size_t v = 0; v < m->num_vertices; ++v) {
            if (!vertex_alive(m, v) || is_fixed[v])
                continue;
            uint32_t h0 = m->v_halfedge[v], h = h0;
            double s = 0, a = 0, b = 0;
            do {
                uint32_t j = sk_to(m, h);
                s += w[h];
                a += w[h] * uv[2 * (size_t)j];
                b += w[h] * uv[2 * (size_t)j + 1];
                h = sk_cw_out(m, h);
            } while (h != h0);
            if (s == 0)
                continue;
            a /= s;
            b /= s;
            change = fmax(change, fmax(fabs(a - uv[2 * v]), fabs(b - uv[2 * v + 1])));
            uv[2 * v] = a;
            uv[2 * v + 1] = b;
        }
        if (it % 16 == 0 && o->progress) {
            sk_status st = sk__progress(o->progress, o->progress_user,
                                        0.5 + 0.5 * (double)it / (double)maxit, err);
            if (st)
                return st;
        }
        if (change <= tol * extent) {
            ++it;
            break;
        }
    }
    if (stats)
        stats->iterations = it;
    return SK_OK;
}

/* Systems smaller than this use the solver's own ordering (AMD is quick and fills little there). */
#define SK_POINT_ORDERING_MIN 5000

/* The ordering for the direct solve of a parametrization system (measured in docs/linear.md). */
static sk_ordering default_ordering(bool symmetric, unsigned dim, size_t n)
{
    if (n < SK_POINT_ORDERING_MIN)
        return SK_ORDERING_DEFAULT;
    /* METIS on the vertex graph: for LU (Floater, mean value) the factor UMFPACK's own METIS
     * gives with a quicker analysis; for LSCM half the graph CHOLMOD orders, u and v together.
     * Tutte and harmonic keep CHOLMOD's choice (AMD): least CPU time measured. */
    if (dim > 1 || !symmetric)
        return SK_ORDERING_METIS;
    return SK_ORDERING_DEFAULT;
}

/* The largest over the nrhs columns of ||b - a x|| / ||b|| (2-norm; 0 for b = 0). */
static sk_status residual(const sk_sparse *a, size_t nrhs, const double *b, const double *x,
                          double *res, sk_error *err)
{
    double *ax = sk__malloc_array(a->n ? a->n : 1, sizeof *ax);
    if (!ax)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    *res = 0;
    for (size_t c = 0; c < nrhs; ++c) {
        const double *bc = b + c * a->n;
        sk_sparse_multiply(a, x + c * a->n, ax);
        double rr = 0, bb = 0;
        for (size_t i = 0; i < a->n; ++i) {
            double d = bc[i] - ax[i];
            rr += d * d;
            bb += bc[i] * bc[i];
        }
        if (bb > 0)
            *res = fmax(*res, sqrt(rr / bb));
    }
    sk__free(ax);
    return SK_OK;
}

sk_status sk__param_solve_direct(const sk_mesh *m, const sk_sparse *a, bool symmetric,
                                 const uint32_t *idx, unsigned dim, size_t nrhs, const double *rhs,
                                 double *x, const sk_param_opts *o, sk_param_stats *stats,
                                 sk_error *err)
{
    sk_solver_opts so = {0};
    so.ordering = o ? o->ordering : SK_ORDERING_DEFAULT;
    if (so.ordering == SK_ORDERING_DEFAULT)
        so.ordering = default_ordering(symmetric, dim, a->n);
    sk_status st = SK_OK;
    double *xyz = NULL;
    int *perm = NULL;
    sk_solver *solver = NULL;
    /* geometric, METIS and AMD on the vertex graph; the others are the solver's own */
    if (so.ordering == SK_ORDERING_GEOMETRIC || so.ordering == SK_ORDERING_METIS ||
        so.ordering == SK_ORDERING_AMD) {
        double t0 = sk_seconds();
        size_t np = a->n / dim;
        perm = sk__malloc_array(a->n ? a->n : 1, sizeof *perm);
        if (so.ordering == SK_ORDERING_GEOMETRIC)
            xyz = sk__malloc_array(np ? 3 * np : 1, sizeof *xyz);
        if (!perm || (so.ordering == SK_ORDERING_GEOMETRIC && !xyz)) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        for (size_t v = 0; xyz && v < m->num_vertices; ++v)
            if (idx[v] != SK_INVALID)
                memcpy(xyz + 3 * (size_t)idx[v], m->positions + 3 * v, 3 * sizeof *xyz);
        if ((st = sk_sparse_point_ordering(a, dim, xyz, so.ordering, perm, err)))
            goto done;
        so.ordering = SK_ORDERING_GIVEN;
        so.perm = perm;
        if (stats)
            stats->ordering_seconds = sk_seconds() - t0;
    }
    st = sk_solver_create_opts(a, symmetric ? SK_SOLVER_CHOLESKY : SK_SOLVER_LU, &so, &solver, err);
    if (st == SK_OK)
        st = sk_solver_factorize(solver, a, err);
    if (st == SK_OK)
        st = sk_solver_solve(solver, nrhs, rhs, x, err);
    if (solver && stats) {
        sk_solver_stats(solver, &stats->solve);
        stats->solve.analyse_seconds += stats->ordering_seconds; /* the ordering is analysis */
        stats->solver = SK_LINEAR_DIRECT;
        if (st == SK_OK)
            st = residual(a, nrhs, rhs, x, &stats->residual, err);
    }
done:
    sk_solver_destroy(&solver);
    sk__free(xyz);
    sk__free(perm);
    return st;
}

/* SK_LINEAR_AUTO: free vertices from which AMG beats the direct solve (whole solve stage,
 * interleaved runs on lion-head Loop x1..x3, docs/linear.md); SIZE_MAX: never. */
static size_t auto_vertices(sk_param_method method)
{
    switch (method) {
    case SK_PARAM_LSCM:
        return SK_AUTO_VERTICES_LSCM;
    case SK_PARAM_TUTTE:
    case SK_PARAM_HARMONIC:
        return SK_AUTO_VERTICES_SYMMETRIC;
    default:
        return SK_AUTO_VERTICES_LU;
    }
}

static const char *const solver_names[] = {"direct", "gauss-seidel", "hierarchical", "amg",
                                           "auto"};

const char *sk_linear_solver_name(sk_linear_solver solver)
{
    return (unsigned)solver < sizeof solver_names / sizeof solver_names[0] ? solver_names[solver]
                                                                          : "unknown";
}

sk_status sk__param_solve_route(const sk_mesh *m, sk_param_method method, const sk_sparse *a,
                                bool symmetric, const uint32_t *idx, unsigned dim, size_t nrhs,
                                const double *rhs, double *x, const sk_param_opts *o,
                                sk_param_stats *stats, sk_error *err)
{
    sk_param_opts ro = *o;
    if (ro.solver == SK_LINEAR_AUTO) {
        size_t from = o->auto_vertices ? o->auto_vertices : auto_vertices(method);
        ro.solver = a->n / dim >= from ? SK_LINEAR_AMG : SK_LINEAR_DIRECT;
        if (!(ro.tolerance > 0))
            ro.tolerance = SK_AUTO_TOLERANCE;
    }
    sk_status st;
    if (ro.solver == SK_LINEAR_HIERARCHICAL)
        return sk__param_solve_hierarchical(m, method, a, symmetric, idx, dim, nrhs, rhs, x, &ro,
                                            stats, err);
    if (ro.solver != SK_LINEAR_AMG)
        return sk__param_solve_direct(m, a, symmetric, idx, dim, nrhs, rhs, x, &ro, stats, err);
    st = sk__param_solve_amg(a, symmetric, dim, nrhs, rhs, x, &ro, stats, err);
    if (st == SK_ERR_NUMERIC && o->solver == SK_LINEAR_AUTO) { /* not converged: the sure way */
        st = sk__param_solve_direct(m, a, symmetric, idx, dim, nrhs, rhs, x, &ro, stats, err);
        if (st == SK_OK)
            sk__ok(err); /* the AMG's message is not the caller's: the solve succeeded */
    }
    return st;
}

/* Free vertices from which the system is assembled straight into compressed columns, in
 * parallel (below: through triplets). */
#define SK_ASSEMBLE_PARALLEL 50000

/* The system of sk_param_solve_weights straight into compressed columns: column c (free vertex
 * u, idx[u] = c) holds the diagonal of row c and, for each free neighbour v (row idx[v], in the
 * lower triangle only when symmetric), -w of the half-edge v -> u, which is what row idx[v]
 * adds as its triplet; rows sorted. The diagonals and right-hand sides are summed over each
 * row's one-ring in the order of the triplet loop, so the matrix and rhs are those of the
 * triplets to the bit. *out NULL (SK_OK) when two edges join the same pair of vertices (the
 * triplets then sum the duplicates). */
static sk_status assemble_columns(const sk_mesh *m, const double *w, bool symmetric,
                                  const uint32_t *idx, const uint32_t *vert, size_t n,
                                  const double *uv, double *rhs, sk_sparse **out, sk_error *err)
{
    *out = NULL;
    sk_sparse *a = sk__calloc_array(1, sizeof *a);
    if (a)
        a->colptr = sk__malloc_array(n + 1, sizeof(int));
    if (!a || !a->colptr) {
        sk_sparse_destroy(&a);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu system", n, n);
    }
    a->n = n;
    a->storage = symmetric ? SK_SPARSE_LOWER : SK_SPARSE_FULL;
    size_t total = 0;
    for (size_t c = 0; c < n; ++c) {
        uint32_t u = vert[c], h0 = m->v_halfedge[u], h = h0;
        size_t len = 1;
        do {
            uint32_t i = idx[sk_to(m, h)];
            len += i != SK_INVALID && (!symmetric || i > c);
            h = sk_cw_out(m, h);
        } while (h != h0);
        a->colptr[c] = (int)total;
        total += len;
        if (total >= (size_t)INT_MAX) {
            sk_sparse_destroy(&a);
            return sk__fail(err, SK_ERR_ARG, "a %zu x %zu system with %zu entries is out of range",
                            n, n, total);
        }
    }
    a->colptr[n] = (int)total;
    a->nnz = total;
    a->rowind = sk__malloc_array(total ? total : 1, sizeof(int));
    a->values = sk__malloc_array(total ? total : 1, sizeof(double));
    if (!a->rowind || !a->values) {
        sk_sparse_destroy(&a);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu system", n, n);
    }
    int dup = 0;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 4096) reduction(| : dup) if (n > SK_ASSEMBLE_PARALLEL)
#endif
    for (long cl = 0; cl < (long)n; ++cl) {
        size_t c = (size_t)cl;
        uint32_t u = vert[c], h0 = m->v_halfedge[u], h = h0;
        /* row c: the diagonal and the right-hand side, in the triplet loop's order */
        double diag = 0, r0 = 0, r1 = 0;
        do {
            uint32_t j = sk_to(m, h);
            double wij = w[h];
            diag += wij;
            if (idx[j] == SK_INVALID) {
                r0 += wij * uv[2 * (size_t)j];
                r1 += wij * uv[2 * (size_t)j + 1];
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
        rhs[c] = r0;
        rhs[n + c] = r1;
        /* column c */
        int *ri = a->rowind + a->colptr[c];
        double *va = a->values + a->colptr[c];
        size_t len = 0;
        ri[len] = (int)c;
        va[len++] = diag;
        do {
            uint32_t i = idx[sk_to(m, h)];
            if (i != SK_INVALID && (!symmetric || i > c)) {
                ri[len] = (int)i;
                va[len++] = -w[h ^ 1u]; /* the half-edge from row i's vertex to u */
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
        for (size_t s = 1; s < len; ++s) { /* rows ascending (short: insertion sort) */
            int key = ri[s];
            double kv = va[s];
            size_t t = s;
            for (; t > 0 && ri[t - 1] > key; --t) {
                ri[t] = ri[t - 1];
                va[t] = va[t - 1];
            }
            ri[t] = key;
            va[t] = kv;
        }
        for (size_t s = 1; s < len; ++s)
            dup |= ri[s] == ri[s - 1];
    }
    if (dup) {
        sk_sparse_destroy(&a);
        return SK_OK;
    }
    *out = a;
    return SK_OK;
}

sk_status sk_param_solve_weights(const sk_mesh *m, const double *w, bool symmetric,
                                 const uint8_t *fixed, const sk_param_opts *opts, double *uv,
                                 sk_param_stats *stats, sk_error *err)
{
    sk_param_opts o = {0};
    if (opts)
        o = *opts;
    double t0 = sk_seconds();
    size_t nv = m->num_vertices;
    sk_status st = SK_OK;
    uint32_t *idx = sk__malloc_array(nv ? nv : 1, sizeof *idx);
    uint8_t *is_fixed = sk__malloc_array(nv ? nv : 1, 1);
    double *rhs = NULL, *x = NULL;
    uint32_t *vert = NULL; /* unknown -> vertex */
    sk_triplets t = {0};
    sk_sparse *a = NULL;
    if (!idx || !is_fixed) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    size_t n = 0, nfixed = 0;
    for (size_t v = 0; v < nv; ++v) {
        idx[v] = SK_INVALID;
        if (!vertex_alive(m, v)) {
            is_fixed[v] = 1;
            uv[2 * v] = uv[2 * v + 1] = 0;
            continue;
        }
        is_fixed[v] = fixed ? (fixed[v] != 0) : sk_is_boundary_v(m, (uint32_t)v);
        if (is_fixed[v])
            nfixed++;
        else
            idx[v] = (uint32_t)n++;
    }
    if (stats) {
        stats->interior = n;
        stats->boundary = nfixed;
    }
    if (n == 0)
        goto done; /* nothing to solve (e.g. a single triangle) */
    if (nfixed == 0) {
        st = sk__fail(err, SK_ERR_ARG, "no fixed vertex: the linear system would be singular");
        goto done;
    }
    if (o.solver == SK_LINEAR_GAUSS_SEIDEL) {
        double ts = sk_seconds();
        st = gauss_seidel(m, w, is_fixed, &o, uv, stats, err);
        if (stats) {
            stats->solve_seconds = sk_seconds() - ts;
            stats->solver = SK_LINEAR_GAUSS_SEIDEL;
        }
        goto done;
    }
    /* assembly: row i = sum_j w_ij p_i - sum_{j free} w_ij p_j = sum_{j fixed} w_ij p_j */
    rhs = sk__calloc_array(2 * n, sizeof *rhs);
    x = sk__malloc_array(2 * n, sizeof *x);
    vert = sk__malloc_array(n, sizeof *vert);
    if (!rhs || !x || !vert) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu system", n, n);
        goto done;
    }
    for (size_t v = 0; v < nv; ++v)
        if (idx[v] != SK_INVALID)
            vert[idx[v]] = (uint32_t)v;
    if (n > SK_ASSEMBLE_PARALLEL &&
        (st = assemble_columns(m, w, symmetric, idx, vert, n, uv, rhs, &a, err)))
        goto done;
    if (!a) { /* small, or edges joining the same two vertices: through triplets */
        size_t guess = 0;
        for (size_t v = 0; v < nv; ++v)
            if (idx[v] != SK_INVALID)
                guess += 1 + sk_mesh_valence(m, (uint32_t)v);
        memset(rhs, 0, 2 * n * sizeof *rhs);
        if (sk_triplets_reserve(&t, guess, err)) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory for a %zu x %zu system", n, n);
            goto done;
        }
        for (size_t v = 0; v < nv; ++v) {
            uint32_t i = idx[v];
            if (i == SK_INVALID)
                continue;
            uint32_t h0 = m->v_halfedge[v], h = h0;
            double diag = 0;
            do {
                uint32_t j = sk_to(m, h);
                double wij = w[h];
                diag += wij;
                if (idx[j] == SK_INVALID) {
                    rhs[i] += wij * uv[2 * (size_t)j];
                    rhs[n + i] += wij * uv[2 * (size_t)j + 1];
                } else if (!symmetric || idx[j] < i) {
                    sk_triplets_add(&t, i, idx[j], -wij);
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
            sk_triplets_add(&t, i, i, diag);
        }
        st = sk_sparse_from_triplets(n, &t, symmetric ? SK_SPARSE_LOWER : SK_SPARSE_FULL, &a,
                                     err);
        sk_triplets_free(&t);
        if (st)
            goto done;
    }
    if (!(isfinite(rhs[0]))) {
        st = sk__fail(err, SK_ERR_NUMERIC, "non-finite weights (degenerate triangles?)");
        goto done;
    }
    double t1 = sk_seconds();
    if (stats)
        stats->weights_seconds += t1 - t0;
    if ((st = sk__progress(o.progress, o.progress_user, 0.4, err)))
        goto done;
    st = sk__param_solve_route(m, o.method, a, symmetric, idx, 1, 2, rhs, x, &o, stats, err);
    if (stats)
        stats->solve_seconds = sk_seconds() - t1;
    if (st)
        goto done;
    for (size_t v = 0; v < nv; ++v) {
        uint32_t i = idx[v];
        if (i == SK_INVALID)
            continue;
        uv[2 * v] = x[i];
        uv[2 * v + 1] = x[n + i];
        if (!isfinite(x[i]) || !isfinite(x[n + i])) {
            st = sk__fail(err, SK_ERR_NUMERIC, "the solution is not finite at vertex %zu", v);
            goto done;
        }
    }
done:
    sk_sparse_destroy(&a);
    sk_triplets_free(&t);
    sk__free(idx);
    sk__free(is_fixed);
    sk__free(rhs);
    sk__free(x);
    sk__free(vert);
    return st;
}

sk_status sk_param_linear(const sk_mesh *m, const sk_param_opts *opts, double *uv,
                          sk_param_stats *stats, sk_error *err)
{
    sk_param_opts o = {0};
    if (opts)
        o = *opts;
    sk_param_stats s;
    memset(&s, 0, sizeof s);
    if (o.method == SK_PARAM_DEFAULT)
        o.method = SK_PARAM_FLOATER;
    if (o.method == SK_PARAM_LSCM) {
        sk_status st = sk_param_lscm(m, &o, uv, stats, err);
        return st;
    }
    if (o.method == SK_PARAM_MIPS)
        return sk__fail(err, SK_ERR_ARG, "MIPS is not a linear method: use sk_parametrize or "
                        "sk_param_hierarchical");
    if (o.boundary.shape == SK_BOUNDARY_FREE)
        return sk__fail(err, SK_ERR_ARG, "%s has a fixed boundary: a free boundary needs LSCM "
                        "or MIPS", sk_param_method_name(o.method));
    double t0 = sk_seconds();
    double *w = NULL;
    sk_status st = sk_param_check_disk(m, err);
    if (st)
        goto done;
    double t1 = sk_seconds();
    s.check_seconds = t1 - t0;
    s.vertices = m->num_vertices;
    s.faces = m->num_faces - m->num_deleted_faces;
    if (o.boundary.shape != SK_BOUNDARY_GIVEN)
        for (size_t v = 0; v < 2 * m->num_vertices; ++v)
            uv[v] = 0;
    if ((st = sk_param_boundary(m, &o.boundary, uv, err)))
        goto done;
    double t2 = sk_seconds();
    s.boundary_seconds = t2 - t1;
    if (o.solver == SK_LINEAR_GAUSS_SEIDEL && o.boundary.shape != SK_BOUNDARY_GIVEN) {
        /* no warm start to keep: start the interior at the boundary's centroid */
        double c[2] = {0, 0};
        size_t nb = 0;
        for (size_t v = 0; v < m->num_vertices; ++v)
            if (!m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID && sk_is_boundary_v(m, (uint32_t)v)) {
                c[0] += uv[2 * v];
                c[1] += uv[2 * v + 1];
                nb++;
            }
        for (size_t v = 0; nb && v < m->num_vertices; ++v)
            if (!m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID && !sk_is_boundary_v(m, (uint32_t)v)) {
                uv[2 * v] = c[0] / (double)nb;
                uv[2 * v + 1] = c[1] / (double)nb;
            }
    }
    w = sk__malloc_array(m->num_halfedges ? m->num_halfedges : 1, sizeof *w);
    if (!w) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if ((st = sk_param_weights(m, o.method, w, err)))
        goto done;
    s.weights_seconds = sk_seconds() - t2;
    if ((st = sk__progress(o.progress, o.progress_user, 0.2, err)))
        goto done;
    bool symmetric = o.method == SK_PARAM_TUTTE || o.method == SK_PARAM_HARMONIC;
    st = sk_param_solve_weights(m, w, symmetric, NULL, &o, uv, &s, err);
    if (st == SK_OK)
        st = sk__progress(o.progress, o.progress_user, 1.0, err);
done:
    sk__free(w);
    s.total_seconds = sk_seconds() - t0;
    if (stats)
        *stats = s;
    return st;
}
