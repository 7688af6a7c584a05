/* Least squares conformal maps (Levy, Petitjean, Ray, Maillot 2002), in the form of Desbrun,
 * Meyer, Alliez: the conformal energy
 *
 *     E_C(u, v) = E_D(u) + E_D(v) - A(u, v),
 *
 * E_D the Dirichlet energy (1/2 u^T L u with the cotangent matrix L_ij = -(cot a + cot b) / 2)
 * and A(u, v) = 1/2 sum over the counter-clockwise boundary edges (a, b) of u_a v_b - u_b v_a the
 * signed area of the image. E_C >= 0 with equality exactly for conformal maps; with two vertices
 * pinned it is a positive definite quadratic form in the remaining 2 (n - 2) unknowns, solved by
 * Cholesky with the pinned values moved to the right-hand side.
 *
 * u and v share the cotangent matrix and are coupled by A(u, v) alone, i.e. between boundary
 * vertices only. So the direct route (from SK_LSCM_BORDERED_MIN free vertices, the default
 * ordering) numbers the interior vertices first and the free boundary last and hands the
 * (n - 2) x (n - 2) cotangent matrix and the boundary coupling to sk__solve_bordered_pair: one
 * factor of the cotangent matrix for both halves and a dense system on the boundary
 * (src/solve/bordered.c), instead of the 2 (n - 2) x 2 (n - 2) interleaved factor. The other
 * routes (hierarchical, AMG, a given ordering) solve the interleaved system. */
#include "param_internal.h"
#include "core/internal.h"
#include "core/vec.h"
#include "solve/bordered.h"

#include <assert.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* The two boundary vertices farthest apart (two sweeps of "farthest from"). */
static void farthest_pair(const sk_mesh *m, uint32_t pins[2])
{
    uint32_t first = SK_INVALID;
    for (size_t v = 0; v < m->num_vertices && first == SK_INVALID; ++v)
        if (!m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID && sk_is_boundary_v(m, (uint32_t)v))
            first = (uint32_t)v;
    uint32_t a = first, b = first;
    for (int pass = 0; pass < 2; ++pass) {
        double best = -1;
        uint32_t from = pass == 0 ? first : a;
        for (size_t v = 0; v < m->num_vertices; ++v) {
            if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID || !sk_is_boundary_v(m, (uint32_t)v))
                continue;
            double d = sk__dist3(m->positions + 3 * (size_t)from, m->positions + 3 * v);
            if (d > best) {
                best = d;
                if (pass == 0)
                    a = (uint32_t)v;
                else
                    b = (uint32_t)v;
            }
        }
    }
    pins[0] = a;
    pins[1] = b;
}

/* The two pinned vertices (given or the farthest boundary pair) and their uv: (0, 0) and
 * (|P1 - P0|, 0), so that the result has about the surface's size; every other uv is zeroed. */
static sk_status place_pins(const sk_mesh *m, const sk_param_opts *o, uint32_t pins[2], double *uv,
                            sk_error *err)
{
    size_t nv = m->num_vertices;
    if (o->has_pins) {
        pins[0] = o->pins[0];
        pins[1] = o->pins[1];
        for (int k = 0; k < 2; ++k)
            if (pins[k] >= nv || m->v_deleted[pins[k]] || m->v_halfedge[pins[k]] == SK_INVALID)
                return sk__fail(err, SK_ERR_ARG, "pinned vertex %u is not a vertex of the mesh",
                                pins[k]);
        if (pins[0] == pins[1])
            return sk__fail(err, SK_ERR_ARG, "LSCM needs two different pinned vertices");
    } else {
        farthest_pair(m, pins);
    }
    for (size_t v = 0; v < 2 * nv; ++v)
        uv[v] = 0;
    double dist = sk__dist3(m->positions + 3 * (size_t)pins[0], m->positions + 3 * (size_t)pins[1]);
    uv[2 * (size_t)pins[1]] = dist;
    return SK_OK;
}

/* The lower triangle of the 2n x 2n conformal energy matrix over the free vertices idx
 * (unknown 2i is u_i, 2i + 1 is v_i) into t, the pinned columns moved to rhs (2n, zeroed). */
static sk_status assemble(const sk_mesh *m, const uint32_t *idx, const double *uv, sk_triplets *t,
                          double *rhs, sk_error *err)
{
    if (sk_triplets_reserve(t, 12 * (m->num_faces + 1), err))
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    bool add_failed = false; /* a dropped entry would give wrong UVs, not an error */
/* adds Q[(va, ca)][(vb, cb)] += q (ca, cb: 0 for u, 1 for v); pinned columns go to the rhs */
#define ADD(va, ca, vb, cb, q)                                                                     \
    do {                                                                                           \
        uint32_t ia_ = idx[va], ib_ = idx[vb];                                                     \
        if (ia_ != SK_INVALID) {                                                                   \
            uint32_t r_ = 2 * ia_ + (ca);                                                          \
            if (ib_ == SK_INVALID)                                                                 \
                rhs[r_] -= (q) * uv[2 * (size_t)(vb) + (cb)];                                      \
            else if (2 * ib_ + (cb) <= r_ && sk_triplets_add(t, r_, 2 * ib_ + (cb), (q)))          \
                add_failed = true;                                                                 \
        }                                                                                          \
    } while (0)
    /* Dirichlet part, per triangle and edge: c/2 (x_i - x_j)^2 for u and for v */
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f];
        for (int k = 0; k < 3; ++k, h = sk_next(m, h)) {
            uint32_t i = sk_from(m, h), j = sk_to(m, h), l = sk_to(m, sk_next(m, h));
            double c = 0.5 * sk__cot3(m->positions + 3 * (size_t)i, m->positions + 3 * (size_t)j,
                                      m->positions + 3 * (size_t)l);
            for (int comp = 0; comp < 2; ++comp) {
                ADD(i, comp, i, comp, c);
                ADD(j, comp, j, comp, c);
                ADD(i, comp, j, comp, -c);
                ADD(j, comp, i, comp, -c);
            }
        }
    }
    /* area part: -1/2 (u_a v_b - u_b v_a) per ccw boundary edge a -> b (the interior half-edge
     * opposite a boundary half-edge); as 1/2 x^T Q x: Q[u_a][v_b] = Q[v_b][u_a] = -1/2,
     * Q[u_b][v_a] = Q[v_a][u_b] = +1/2 */
    for (size_t hb = 0; hb < m->num_halfedges; ++hb) {
        if (m->e_deleted[hb >> 1] || !sk_is_boundary_h(m, (uint32_t)hb))
            continue;
        uint32_t h = (uint32_t)hb ^ 1u;
        uint32_t va = sk_from(m, h), vb = sk_to(m, h);
        ADD(va, 0, vb, 1, -0.5);
        ADD(vb, 1, va, 0, -0.5);
        ADD(vb, 0, va, 1, 0.5);
        ADD(va, 1, vb, 0, 0.5);
    }
#undef ADD
    return add_failed ? sk__fail(err, SK_ERR_NOMEM, "out of memory") : SK_OK;
}

/* The bordered route from this many free vertices (smaller systems, the atlas's charts among
 * them, keep the interleaved factor) and up to this many free boundary vertices: the dense border
 * system is 2k x 2k, (2k)^3 / 3 flops for its Cholesky (0.5 Gflop at k = 576, the boundary of a
 * 4M-triangle lion head; the 1M one has 288). */
#define SK_LSCM_BORDERED_MIN 5000
#define SK_LSCM_BORDER_MAX 1024

/* Whether o's route for n free vertices is the direct solve with the default ordering. */
static bool bordered_route(const sk_param_opts *o, size_t n, size_t k)
{
    bool direct = o->solver == SK_LINEAR_DIRECT;
    if (o->solver == SK_LINEAR_AUTO)
        direct = n < (o->auto_vertices ? o->auto_vertices : SK_AUTO_VERTICES_LSCM);
    return direct && o->ordering == SK_ORDERING_DEFAULT && n >= SK_LSCM_BORDERED_MIN &&
           k <= SK_LSCM_BORDER_MAX;
}

/* The boundary coupling of the bordered route: C (k x k, column-major; row: u of free boundary
 * vertex m + r, column: v of m + c) and the right-hand sides (u then v, n each). */
typedef struct {
    const uint32_t *idx;
    const double *uv;
    size_t n, m, k;
    double *c, *rhs;
} bordered_coupling;

/* Q[(va, ca)][(vb, cb)] += q for a u-v entry of A(u, v) (ca != cb) as assemble() adds it: into C
 * when both vertices are free (a v-u entry is C^T's, implied), into the right-hand side of the
 * row when vb is pinned. */
static void area_add(bordered_coupling *b, uint32_t va, int ca, uint32_t vb, int cb, double q)
{
    uint32_t ia = b->idx[va], ib = b->idx[vb];
    if (ia == SK_INVALID)
        return;
    if (ib == SK_INVALID) {
        b->rhs[(size_t)ca * b->n + ia] -= q * b->uv[2 * (size_t)vb + (size_t)cb];
    } else if (ca == 0) {
        assert(ia >= b->m && ib >= b->m); /* boundary vertices, numbered last */
        b->c[(ia - b->m) + b->k * (ib - b->m)] += q;
    }
}

/* Half of the cotangent weight of the edge of half-edge h: cot of the angle opposite it in its
 * face, halved (0 for a boundary half-edge); the edge's weight is the sum over its two halves,
 * as assemble() sums it per triangle. */
static double half_weight(const sk_mesh *m, uint32_t h)
{
    if (sk_is_boundary_h(m, h))
        return 0;
    return 0.5 * sk__cot3(m->positions + 3 * (size_t)sk_from(m, h),
                          m->positions + 3 * (size_t)sk_to(m, h),
                          m->positions + 3 * (size_t)sk_to(m, sk_next(m, h)));
}

/* The cotangent matrix over the free vertices straight into compressed columns (lower, rows
 * sorted), column by column over each free vertex's one-ring; pinned neighbours move to both
 * right-hand sides (rhs: u then v, n each, zeroed). */
static sk_status cotangent_columns(const sk_mesh *m, const uint32_t *idx, size_t n,
                                   const double *uv, double *rhs, sk_sparse **out, sk_error *err)
{
    sk_status st = SK_OK;
    uint32_t *vert = sk__malloc_array(n, sizeof *vert);
    sk_sparse *a = sk__calloc_array(1, sizeof *a);
    if (!vert || !a || !(a->colptr = sk__malloc_array(n + 1, sizeof *a->colptr))) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    a->n = n;
    a->storage = SK_SPARSE_LOWER;
    for (size_t v = 0; v < m->num_vertices; ++v)
        if (idx[v] != SK_INVALID)
            vert[idx[v]] = (uint32_t)v;
    size_t nnz = 0;
    a->colptr[0] = 0;
    for (size_t c = 0; c < n; ++c) {
        uint32_t h0 = m->v_halfedge[vert[c]], h = h0;
        nnz++; /* the diagonal */
        do {
            uint32_t j = idx[sk_to(m, h)];
            nnz += j != SK_INVALID && j > c;
            h = sk_cw_out(m, h);
        } while (h != h0);
        if (nnz >= (size_t)INT_MAX) {
            st = sk__fail(err, SK_ERR_ARG, "the LSCM matrix is too large");
            goto done;
        }
        a->colptr[c + 1] = (int)nnz;
    }
    a->nnz = nnz;
    a->rowind = sk__malloc_array(nnz, sizeof *a->rowind);
    a->values = sk__malloc_array(nnz, sizeof *a->values);
    if (!a->rowind || !a->values) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    int *ri = a->rowind;
    double *va = a->values;
    /* each column writes its own entries and right-hand side rows: any thread count, same bytes */
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) if (n > 50000)
#endif
    for (long cl = 0; cl < (long)n; ++cl) {
        size_t c = (size_t)cl;
        uint32_t h0 = m->v_halfedge[vert[c]], h = h0;
        int p = a->colptr[c], q = p + 1;
        double diag = 0;
        do {
            uint32_t vj = sk_to(m, h), j = idx[vj];
            double w = half_weight(m, h) + half_weight(m, h ^ 1u);
            diag += w;
            if (j == SK_INVALID) {
                rhs[c] += w * uv[2 * (size_t)vj];
                rhs[n + c] += w * uv[2 * (size_t)vj + 1];
            } else if (j > c) { /* insert, rows kept increasing */
                int r = q++;
                for (; r > p + 1 && ri[r - 1] > (int)j; --r) {
                    ri[r] = ri[r - 1];
                    va[r] = va[r - 1];
                }
                ri[r] = (int)j;
                va[r] = -w;
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
        ri[p] = (int)c;
        va[p] = diag;
    }
done:
    sk__free(vert);
    if (st)
        sk_sparse_destroy(&a);
    *out = a;
    return st;
}

/* The bordered direct solve; idx numbers the interior free vertices 0 .. m - 1 and the free
 * boundary m .. n - 1. */
static sk_status solve_bordered(const sk_mesh *m, const uint32_t *idx, size_t n, size_t k,
                                double *uv, const sk_param_opts *o, sk_param_stats *s,
                                sk_error *err)
{
    double t0 = sk_seconds();
    sk_status st = SK_OK;
    sk_sparse *a = NULL;
    double *c = sk__calloc_array(k ? k * k : 1, sizeof *c);
    double *rhs = sk__calloc_array(2 * n, sizeof *rhs);
    double *x = sk__malloc_array(2 * n, sizeof *x);
    if (!c || !rhs || !x) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    bordered_coupling b = {idx, uv, n, n - k, k, c, rhs};
    if ((st = cotangent_columns(m, idx, n, uv, rhs, &a, err)))
        goto done;
    /* area part, as in assemble() */
    for (size_t hb = 0; hb < m->num_halfedges; ++hb) {
        if (m->e_deleted[hb >> 1] || !sk_is_boundary_h(m, (uint32_t)hb))
            continue;
        uint32_t h = (uint32_t)hb ^ 1u;
        uint32_t va = sk_from(m, h), vb = sk_to(m, h);
        area_add(&b, va, 0, vb, 1, -0.5);
        area_add(&b, vb, 1, va, 0, -0.5);
        area_add(&b, vb, 0, va, 1, 0.5);
        area_add(&b, va, 1, vb, 0, 0.5);
    }
    double t1 = sk_seconds();
    s->weights_seconds = t1 - t0;
    if ((st = sk__progress(o->progress, o->progress_user, 0.4, err)))
        goto done;
    /* AMD on the interior's graph: at 1M triangles 2.0 s less CPU than METIS for a factor
     * half as large again (docs/linear.md, "The bordered LSCM solve") */
    st = sk__solve_bordered_pair(a, k, c, SK_ORDERING_AMD, rhs, x, &s->solve,
                                 &s->ordering_seconds, &s->residual, err);
    if (st)
        goto done;
    s->solve.analyse_seconds += s->ordering_seconds; /* the ordering is analysis */
    s->solver = SK_LINEAR_DIRECT;
    for (size_t v = 0; v < m->num_vertices; ++v)
        if (idx[v] != SK_INVALID) {
            uv[2 * v] = x[idx[v]];
            uv[2 * v + 1] = x[n + idx[v]];
        }
done:
    sk_sparse_destroy(&a);
    sk__free(c);
    sk__free(rhs);
    sk__free(x);
    return st;
}

sk_status sk_param_lscm(const sk_mesh *m, const sk_param_opts *opts, double *uv,
                        sk_param_stats *stats, sk_error *err)
{
    sk_param_opts o = {0};
    if (opts)
        o = *opts;
    sk_param_stats s;
    memset(&s, 0, sizeof s);
    double t0 = sk_seconds();
    size_t nv = m->num_vertices;
    uint32_t *idx = NULL;
    double *rhs = NULL, *x = NULL;
    sk_triplets t = {0};
    sk_sparse *a = NULL;
    uint32_t pins[2];
    sk_status st = sk_param_check_disk(m, err);
    if (st)
        goto done;
    s.vertices = nv;
    s.faces = m->num_faces - m->num_deleted_faces;
    double t1 = sk_seconds();
    s.check_seconds = t1 - t0;
    if ((st = place_pins(m, &o, pins, uv, err)))
        goto done;
    double t2 = sk_seconds();
    s.boundary_seconds = t2 - t1;
    idx = sk__malloc_array(nv, sizeof *idx);
    size_t n = 0;
    if (!idx) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t v = 0; v < nv; ++v) {
        idx[v] = SK_INVALID;
        if (!m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID && v != pins[0] && v != pins[1])
            idx[v] = (uint32_t)n++;
    }
    s.interior = n;
    s.boundary = 2;
    size_t k = 0; /* free boundary vertices */
    for (size_t v = 0; v < nv; ++v)
        if (idx[v] != SK_INVALID && sk_is_boundary_v(m, (uint32_t)v))
            ++k;
    if (n > 0 && bordered_route(&o, n, k)) {
        size_t in = 0, bn = n - k; /* interior first, the boundary last */
        for (size_t v = 0; v < nv; ++v)
            if (idx[v] != SK_INVALID)
                idx[v] = (uint32_t)(sk_is_boundary_v(m, (uint32_t)v) ? bn++ : in++);
        st = solve_bordered(m, idx, n, k, uv, &o, &s, err);
        if (st != SK_ERR_ARG) { /* ARG: the factor could not keep the boundary last */
            s.solve_seconds = sk_seconds() - t2 - s.weights_seconds;
            if (st == SK_OK)
                st = sk__progress(o.progress, o.progress_user, 1.0, err);
            goto done;
        }
        sk__ok(err);
        st = SK_OK;
        memset(&s.solve, 0, sizeof s.solve);
        s.ordering_seconds = 0;
    }
    size_t N = 2 * n; /* unknown 2i is u_i, 2i + 1 is v_i */
    rhs = sk__calloc_array(N ? N : 1, sizeof *rhs);
    x = sk__malloc_array(N ? N : 1, sizeof *x);
    if (!rhs || !x) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (n == 0)
        goto done;
    if ((st = assemble(m, idx, uv, &t, rhs, err)) ||
        (st = sk_sparse_from_triplets(N, &t, SK_SPARSE_LOWER, &a, err)))
        goto done;
    sk_triplets_free(&t);
    double t3 = sk_seconds();
    s.weights_seconds = t3 - t2;
    if ((st = sk__progress(o.progress, o.progress_user, 0.4, err)))
        goto done;
    if (o.solver == SK_LINEAR_GAUSS_SEIDEL)
        o.solver = SK_LINEAR_DIRECT;
    st = sk__param_solve_route(m, SK_PARAM_LSCM, a, true, idx, 2, 1, rhs, x, &o, &s, err);
    s.solve_seconds = sk_seconds() - t3;
    if (st)
        goto done;
    for (size_t v = 0; v < nv; ++v)
        if (idx[v] != SK_INVALID) {
            uv[2 * v] = x[2 * (size_t)idx[v]];
            uv[2 * v + 1] = x[2 * (size_t)idx[v] + 1];
        }
    st = sk__progress(o.progress, o.progress_user, 1.0, err);
done:
    sk_sparse_destroy(&a);
    sk_triplets_free(&t);
    sk__free(idx);
    sk__free(rhs);
    sk__free(x);
    s.total_seconds = sk_seconds() - t0;
    if (stats)
        *stats = s;
    return st;
}
