/* B-spline fitting of a disk (fit.h): corners, square parametrization, least squares with a
 * thin-plate term, hierarchical knot refinement. */
#include "surfkit/fit.h"
#include "fit/bspline_internal.h"
#include "surfkit/deviation.h"
#include "surfkit/mips.h"
#include "surfkit/param.h"
#include "surfkit/parametrize.h"
#include "surfkit/solve.h"
#include "param/param_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_DEG = 5, MAX_CTRL_1D = 1024, CORRECTIONS = 3 };
/* The share of the spans above the tolerance that a round splits (the worst ones, per
 * direction, at least one): 1 bisects all of them (the grid about doubles where the error is),
 * a tenth adds knots only along the worst rows and columns and lets the next fit show whether
 * the others still need one (paraboloid-patch at 1e-3 of the diagonal: 575 control points with
 * 1, 378 with 1/2, 288 with 1/4, 225 with 1/10; more rounds, each a few small solves). */
#define REFINE_SHARE 0.1

/* ---------------------------------------------------------------------------------------------
 * Least squares with the thin-plate energy
 * ------------------------------------------------------------------------------------------- */

/* Gram matrices of one direction: G[r][i * n + k] = int_0^1 N_i^(r) N_k^(r), r = 0, 1, 2, by
 * 6-point Gauss-Legendre per knot span (exact for the degree 2p <= 10 products). */
static sk_status gram(const double *U, size_t n, int p, double *G[3], sk_error *err)
{
    static const double gx[6] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                 0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
    static const double gw[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                 0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
    for (int r = 0; r < 3; ++r) {
        G[r] = sk__calloc_array(n * n, sizeof *G[r]);
        if (!G[r])
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t s = (size_t)p; s < n; ++s) {
        double a = U[s], b = U[s + 1];
        if (!(b > a))
            continue;
        for (int g = 0; g < 6; ++g) {
            double t = 0.5 * (a + b) + 0.5 * (b - a) * gx[g], w = 0.5 * (b - a) * gw[g];
            double d[3 * (MAX_DEG + 1)];
            sk_bspline_basis(U, s, p, t, 2, d);
            for (int r = 0; r < 3; ++r)
                for (int x = 0; x <= p; ++x)
                    for (int y = 0; y <= p; ++y)
                        G[r][(s - (size_t)p + (size_t)x) * n + (s - (size_t)p + (size_t)y)] +=
                            w * d[r * (p + 1) + x] * d[r * (p + 1) + y];
        }
    }
    return SK_OK;
}

typedef struct samples {
    size_t n;
    double *pos;    /* 3 per sample: points of the mesh */
    double *uv;     /* 2 per sample */
    uint8_t *fixed; /* bit 0: u stays (on the sides u = 0, 1), bit 1: v stays */
} samples;

static void samples_free(samples *x)
{
    sk__free(x->pos);
    sk__free(x->uv);
    sk__free(x->fixed);
    memset(x, 0, sizeof *x);
}

/* Samples per edge of face f: its uv area should hold about two samples per knot cell of the
 * cells around its centroid. */
static unsigned face_density(const sk_mesh *m, uint32_t f, const double *uv,
                             const sk_bspline_surface *s)
{
    uint32_t h = m->f_halfedge[f], a = sk_from(m, h), b = sk_to(m, h), c = sk_to(m, sk_next(m, h));
    const double *A = uv + 2 * (size_t)a, *B = uv + 2 * (size_t)b, *C = uv + 2 * (size_t)c;
    double area = 0.5 * fabs((B[0] - A[0]) * (C[1] - A[1]) - (C[0] - A[0]) * (B[1] - A[1]));
    double cu = (A[0] + B[0] + C[0]) / 3, cv = (A[1] + B[1] + C[1]) / 3;
    size_t su = sk_bspline_span(s->knots_u, s->nu, s->degree_u, cu);
    size_t sv = sk_bspline_span(s->knots_v, s->nv, s->degree_v, cv);
    double cell = (s->knots_u[su + 1] - s->knots_u[su]) * (s->knots_v[sv + 1] - s->knots_v[sv]);
    double n = cell > 0 ? ceil(sqrt(2.0 * area / cell)) : 1;
    return n < 1 ? 1 : n > 16 ? 16 : (unsigned)n;
}

/* The data of a round: every vertex (boundary ones keep their side of the square), and in every
 * triangle the centroids of its n x n sub-triangles (face_density): points of the mesh where the
 * parametrization spreads few vertices over many knot cells, so that no cell is without data. */
static sk_status build_samples(const sk_mesh *m, const double *uv, const sk_bspline_surface *s,
                               samples *x, sk_error *err)
{
    samples_free(x);
    size_t n = m->num_vertices;
    for (size_t f = 0; f < m->num_faces; ++f) {
        unsigned d = face_density(m, (uint32_t)f, uv, s);
        n += (size_t)d * d;
    }
    x->pos = sk__malloc_array(3 * n, sizeof *x->pos);
    x->uv = sk__malloc_array(2 * n, sizeof *x->uv);
    x->fixed = sk__calloc_array(n, 1);
    if (!x->pos || !x->uv || !x->fixed) {
        samples_free(x);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memcpy(x->pos, m->positions, 3 * m->num_vertices * sizeof *x->pos);
    memcpy(x->uv, uv, 2 * m->num_vertices * sizeof *x->uv);
    for (size_t v = 0; v < m->num_vertices; ++v) /* the square map puts the sides at exact 0, 1 */
        x->fixed[v] = (uint8_t)((uv[2 * v] == 0 || uv[2 * v] == 1) |
                                ((uv[2 * v + 1] == 0 || uv[2 * v + 1] == 1) << 1));
    size_t k = m->num_vertices;
    for (size_t f = 0; f < m->num_faces; ++f) {
        unsigned d = face_density(m, (uint32_t)f, uv, s);
        uint32_t h = m->f_halfedge[f], c[3] = {sk_from(m, h), sk_to(m, h), sk_to(m, sk_next(m, h))};
        for (unsigned i = 0; i < d; ++i)
            for (unsigned j = 0; i + j < d; ++j)
                for (int up = 0; up < 2; ++up) {
                    if (up && i + j + 1 >= d)
                        continue;
                    double b1 = (i + (up ? 2.0 : 1.0) / 3.0) / d, b2 = (j + (up ? 2.0 : 1.0) / 3.0) / d;
                    double w[3] = {1 - b1 - b2, b1, b2};
                    for (int q = 0; q < 3; ++q) {
                        x->pos[3 * k + (size_t)q] = 0;
                        if (q < 2)
                            x->uv[2 * k + (size_t)q] = 0;
                        for (int t = 0; t < 3; ++t) {
                            x->pos[3 * k + (size_t)q] += w[t] * m->positions[3 * (size_t)c[t] + (size_t)q];
                            if (q < 2)
                                x->uv[2 * k + (size_t)q] += w[t] * uv[2 * (size_t)c[t] + (size_t)q];
                        }
                    }
                    ++k;
                }
    }
    x->n = k;
    return SK_OK;
}

/* Fits the control points of s (its knots set) to the samples: (A^T A + lambda K) P = A^T X. */
static sk_status solve_points(sk_bspline_surface *s, const samples *x, double smoothing,
                              sk_error *err)
{
    int p = s->degree_u, q = s->degree_v;
    size_t nu = s->nu, nv = s->nv, N = nu * nv, per = (size_t)(p + 1) * (size_t)(q + 1);
    sk_triplets t = {0};
    double *rhs = sk__calloc_array(3 * N, sizeof *rhs), *Gu[3] = {0}, *Gv[3] = {0};
    sk_sparse *A = NULL;
    sk_status st = rhs ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (!st)
        st = sk_triplets_reserve(&t, x->n * per * (per + 1) / 2 + N * per * per, err);
    double tr_data = 0, tr_k = 0;
    for (size_t k = 0; !st && k < x->n; ++k) {
        double u = x->uv[2 * k], v = x->uv[2 * k + 1], Nu[MAX_DEG + 1], Nv[MAX_DEG + 1];
        size_t su = sk_bspline_span(s->knots_u, nu, p, u), sv = sk_bspline_span(s->knots_v, nv, q, v);
        sk_bspline_basis(s->knots_u, su, p, u, 0, Nu);
        sk_bspline_basis(s->knots_v, sv, q, v, 0, Nv);
        uint32_t idx[(MAX_DEG + 1) * (MAX_DEG + 1)];
        double w[(MAX_DEG + 1) * (MAX_DEG + 1)];
        for (int b = 0, c = 0; b <= q; ++b)
            for (int a = 0; a <= p; ++a, ++c) {
                idx[c] = (uint32_t)((su - (size_t)p + (size_t)a) + nu * (sv - (size_t)q + (size_t)b));
                w[c] = Nu[a] * Nv[b];
            }
        for (size_t i = 0; i < per; ++i) {
            for (int d = 0; d < 3; ++d)
                rhs[(size_t)d * N + idx[i]] += w[i] * x->pos[3 * k + (size_t)d];
            tr_data += w[i] * w[i];
            for (size_t j = 0; j < per && !st; ++j)
                if (idx[i] >= idx[j] && (st = sk_triplets_add(&t, idx[i], idx[j], w[i] * w[j])))
                    sk__fail(err, st, "out of memory");
        }
    }
    if (!st)
        st = gram(s->knots_u, nu, p, Gu, err);
    if (!st)
        st = gram(s->knots_v, nv, q, Gv, err);
    /* thin plate: K = G2u (x) G0v + 2 G1u (x) G1v + G0u (x) G2v, banded (|i - k| <= p, ...) */
    for (size_t i = 0; !st && i < N; ++i) {
        size_t iu = i % nu, iv = i / nu;
        tr_k += Gu[2][iu * nu + iu] * Gv[0][iv * nv + iv] + 2 * Gu[1][iu * nu + iu] * Gv[1][iv * nv + iv] +
                Gu[0][iu * nu + iu] * Gv[2][iv * nv + iv];
    }
    double lambda = tr_k > 0 ? (smoothing * tr_data / tr_k) : 0, ridge = 1e-12 * tr_data / (double)N;
    for (size_t i = 0; !st && i < N; ++i) {
        size_t iu = i % nu, iv = i / nu;
        for (size_t jv = iv >= (size_t)q ? iv - (size_t)q : 0; jv <= iv + (size_t)q && jv < nv; ++jv)
            for (size_t ju = iu >= (size_t)p ? iu - (size_t)p : 0; ju <= iu + (size_t)p && ju < nu; ++ju) {
                size_t j = ju + nu * jv;
                if (j > i)
                    continue;
                double k = Gu[2][iu * nu + ju] * Gv[0][iv * nv + jv] +
                           2 * Gu[1][iu * nu + ju] * Gv[1][iv * nv + jv] +
                           Gu[0][iu * nu + ju] * Gv[2][iv * nv + jv];
                double val = lambda * k + (i == j ? ridge : 0);
                if (val != 0 && (st = sk_triplets_add(&t, (uint32_t)i, (uint32_t)j, val)))
                    sk__fail(err, st, "out of memory");
            }
    }
    if (!st)
        st = sk_sparse_from_triplets(N, &t, SK_SPARSE_LOWER, &A, err);
    double *sol = st ? NULL : sk__malloc_array(3 * N, sizeof *sol);
    if (!st && !sol)
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (!st)
        st = sk_sparse_solve(A, SK_SOLVER_CHOLESKY, 3, rhs, sol, NULL, err);
    for (size_t i = 0; !st && i < N; ++i)
        for (int d = 0; d < 3; ++d)
            s->points[3 * i + (size_t)d] = sol[(size_t)d * N + i];
    sk__free(sol);
    sk_sparse_destroy(&A);
    sk_triplets_free(&t);
    sk__free(rhs);
    for (int r = 0; r < 3; ++r) {
        sk__free(Gu[r]);
        sk__free(Gv[r]);
    }
    return st;
}

/* Parameter correction (foot points, Hoschek): moves each sample's (u, v) towards the surface
 * point nearest to it by two Gauss-Newton steps on |S(u, v) - p|^2, inside [0, 1]^2, the
 * coordinates of boundary samples that lie on a side of the square kept. After it the fit's
 * residuals are (close to) orthogonal distances, so a parametrization that is only roughly
 * smooth (Floater's) no longer limits the fit. */
static void correct_params(const sk_bspline_surface *s, samples *x)
{
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) if (x->n > 20000)
#endif
    for (ptrdiff_t k = 0; k < (ptrdiff_t)x->n; ++k) {
        double *t = x->uv + 2 * k;
        for (int it = 0; it < 2; ++it) {
            double p[3], su[3], sv[3], r[3];
            sk_bspline_eval(s, t[0], t[1], p, su, sv);
            sk__sub3(r, x->pos + 3 * k, p);
            double a = sk__dot3(su, su), b = sk__dot3(su, sv), c = sk__dot3(sv, sv);
            double g0 = sk__dot3(su, r), g1 = sk__dot3(sv, r), du = 0, dv = 0;
            bool fu = x->fixed[k] & 1, fv = x->fixed[k] & 2;
            if (!fu && !fv) {
                double det = a * c - b * b;
                if (!(det > 1e-300))
                    break;
                du = (c * g0 - b * g1) / det;
                dv = (a * g1 - b * g0) / det;
            } else if (!fu && a > 0) {
                du = g0 / a;
            } else if (!fv && c > 0) {
                dv = g1 / c;
            }
            t[0] = fmin(fmax(t[0] + du, 0.0), 1.0);
            t[1] = fmin(fmax(t[1] + dv, 0.0), 1.0);
        }
    }
}

/* ---------------------------------------------------------------------------------------------
 * Refinement
 * ------------------------------------------------------------------------------------------- */

/* Records e at parameter t in the score of its span (the largest error above tol there). */
static void score_at(const double *U, size_t n, int p, double t, double e, double *score)
{
    size_t s = sk_bspline_span(U, n, p, t);
    score[s] = fmax(score[s], e);
}

/* Errors |S(u_k, v_k) - p_k|; scores (in score_u / score_v, one per span) the spans of the
 * samples above tol with their largest error. Returns max, fills rms. */
static double residuals(const sk_bspline_surface *s, const samples *x, double tol, double *score_u,
                        double *score_v, double *rms)
{
    double mx = 0, sum2 = 0;
    for (size_t k = 0; k < x->n; ++k) {
        double u = x->uv[2 * k], v = x->uv[2 * k + 1], p[3];
        sk_bspline_eval(s, u, v, p, NULL, NULL);
        double e = sk__dist3(p, x->pos + 3 * k);
        mx = fmax(mx, e);
        sum2 += e * e;
        if (e > tol) {
            score_at(s->knots_u, s->nu, s->degree_u, u, e, score_u);
            score_at(s->knots_v, s->nv, s->degree_v, v, e, score_v);
        }
    }
    *rms = x->n ? sqrt(sum2 / (double)x->n) : 0;
    return mx;
}

/* Lines per side of the check that confirms a fit within T at most: the knot-adaptive grid of
 * the CLI's tessellation (sk_fit_tessellate), whose chord bound is T / 20 where it is reached,
 * so that a wiggle between the coarse grid's points (near a corner, or where the map crowds
 * the data into small knot cells) is found where the report would show it. */
#define DENSE_SIDE 1024

/* The distance of S(u, v) to the mesh; scores the spans of (u, v) when it is beyond tol. */
static double stray_at(const sk_bspline_surface *s, const sk_bvh *mesh, double u, double v,
                       double tol, double *score_u, double *score_v)
{
    double p[3];
    sk_bspline_eval(s, u, v, p, NULL, NULL);
    sk_closest c;
    sk_bvh_closest(mesh, p, &c);
    if (c.distance > tol) {
        score_at(s->knots_u, s->nu, s->degree_u, u, c.distance, score_u);
        score_at(s->knots_v, s->nv, s->degree_v, v, c.distance, score_v);
    }
    return c.distance;
}

/* The other direction: the largest distance from a grid of surface points (4 per knot span and
 * direction, at most 512; the knot-adaptive lines when dense) to the mesh; scores the spans of
 * the points farther than tol, where the surface strays from the mesh between the samples. */
static sk_status stray(const sk_bspline_surface *s, const sk_bvh *mesh, double tol, bool dense,
                       double *score_u, double *score_v, double *out, sk_error *err)
{
    sk__fit_lines l = {0};
    sk_status st = dense ? sk__fit_lines_make(s, tol, DENSE_SIDE, &l, err) : SK_OK;
    size_t gu = 4 * (s->nu - (size_t)s->degree_u), gv = 4 * (s->nv - (size_t)s->degree_v);
    gu = dense ? l.nu : gu > 512 ? 512 : gu;
    gv = dense ? l.nv : gv > 512 ? 512 : gv;
    double mx = 0;
    for (size_t j = 0; !st && j <= gv; ++j)
        for (size_t i = 0; i <= gu; ++i)
            mx = fmax(mx, stray_at(s, mesh, dense ? l.u[i] : (double)i / (double)gu,
                                   dense ? l.v[j] : (double)j / (double)gv, tol, score_u, score_v));
    sk__fit_lines_free(&l);
    *out = mx;
    return st;
}

static int cmp_desc(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x < y) - (x > y);
}

/* New knot vector with the midpoints of the worst spans inserted: of the spans scored above
 * zero, the share `fraction` (at least one) with the largest scores; *n becomes the new number
 * of control points. Returns NULL when out of memory. */
static double *refine_knots(const double *U, size_t *n, int p, const double *score,
                            double fraction)
{
    size_t m = *n + (size_t)p + 1, marked = 0;
    double *sorted = sk__malloc_array(*n + 1, sizeof *sorted);
    if (!sorted)
        return NULL;
    for (size_t s = (size_t)p; s < *n; ++s)
        if (score[s] > 0 && U[s + 1] > U[s])
            sorted[marked++] = score[s];
    qsort(sorted, marked, sizeof *sorted, cmp_desc);
    size_t keep = (size_t)ceil(fraction * (double)marked);
    keep = keep < 1 ? 1 : keep > marked ? marked : keep;
    double cut = marked ? sorted[keep - 1] : INFINITY;
    sk__free(sorted);
    double *V = sk__malloc_array(m + keep, sizeof *V);
    if (!V)
        return NULL;
    size_t j = 0, add = 0;
    for (size_t i = 0; i < m; ++i) {
        V[j++] = U[i];
        if (i >= (size_t)p && i < *n && score[i] >= cut && score[i] > 0 && U[i + 1] > U[i] &&
            add < keep) {
            V[j++] = 0.5 * (U[i] + U[i + 1]);
            ++add;
        }
    }
    *n += add;
    return V;
}

/* The smoothing weights tried in each round (o->smoothing alone when given): the smallest
 * keeps the fit closest to the data; the larger ones hold the surface where a knot span has
 * few samples (near the sides of the square, where a shape-preserving map crowds them) and
 * would otherwise stray from the mesh between them. (lion-head at 1e-2 of the diagonal, theta
 * 0.5, share 1/4, meets T only with the weight fixed at 1e-2, --smoothing; adding 1e-2 here
 * changes which maps win on the cut cone, and is left for a measured change.) */
static const double smoothing_tried[] = {1e-6, 1e-3};

/* One fit of s's points (its knots set) with the weight w: samples of the map, the least
 * squares, the parameter corrections; the errors in fs, the span scores in su, sv (zeroed). */
static sk_status fit_weight(const sk_mesh *disk, const double *uv, const sk_bvh *bvh, double w,
                            sk_bspline_surface *s, samples *x, sk_fit_stats *fs, double *su,
                            double *sv, sk_error *err)
{
    sk_status st = build_samples(disk, uv, s, x, err);
    if (!st)
        st = solve_points(s, x, w, err);
    for (int c = 0; c < CORRECTIONS && !st; ++c) {
        correct_params(s, x);
        st = solve_points(s, x, w, err);
    }
    if (st)
        return st;
    memset(su, 0, (s->nu + 1) * sizeof *su);
    memset(sv, 0, (s->nv + 1) * sizeof *sv);
    fs->samples = x->n;
    fs->max_error = residuals(s, x, fs->tolerance, su, sv, &fs->rms_error);
    return stray(s, bvh, fs->tolerance, false, su, sv, &fs->surface_to_mesh, err);
}

/* A round: s fitted with each smoothing weight tried, the one with the smallest deviation
 * (the larger of max_error and surface_to_mesh; the first on a tie) kept with its scores. */
static sk_status fit_round(const sk_mesh *disk, const double *uv, const sk_bvh *bvh,
                           const sk_fit_opts *o, sk_bspline_surface *s, samples *x,
                           sk_fit_stats *fs, double **score_u, double **score_v, sk_error *err)
{
    size_t nw = o->smoothing > 0 ? 1 : sizeof smoothing_tried / sizeof *smoothing_tried;
    size_t np = 3 * s->nu * s->nv;
    double *su = sk__calloc_array(s->nu + 1, sizeof *su), *sv = sk__calloc_array(s->nv + 1, sizeof *sv);
    double *pts = sk__malloc_array(np, sizeof *pts), best = INFINITY;
    sk_status st = su && sv && pts ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    sk__free(*score_u);
    sk__free(*score_v);
    *score_u = sk__calloc_array(s->nu + 1, sizeof **score_u);
    *score_v = sk__calloc_array(s->nv + 1, sizeof **score_v);
    if (!st && (!*score_u || !*score_v))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t k = 0; !st && k < nw; ++k) {
        sk_fit_stats trial = *fs;
        st = fit_weight(disk, uv, bvh, nw == 1 ? o->smoothing : smoothing_tried[k], s, x, &trial,
                        su, sv, err);
        double dev = fmax(trial.max_error, trial.surface_to_mesh);
        if (!st && dev < best) {
            best = dev;
            *fs = trial;
            memcpy(pts, s->points, np * sizeof *pts);
            memcpy(*score_u, su, (s->nu + 1) * sizeof *su);
            memcpy(*score_v, sv, (s->nv + 1) * sizeof *sv);
        }
    }
    if (!st)
        memcpy(s->points, pts, np * sizeof *pts);
    sk__free(su);
    sk__free(sv);
    sk__free(pts);
    return st;
}

/* A copy of s (same degrees, knots and points), or NULL when out of memory. */
static sk_bspline_surface *bspline_copy(const sk_bspline_surface *s)
{
    sk_bspline_surface *c = NULL;
    if (sk_bspline_create(s->degree_u, s->degree_v, s->nu, s->nv, &c, NULL))
        return NULL;
    memcpy(c->knots_u, s->knots_u, (s->nu + (size_t)s->degree_u + 1) * sizeof *c->knots_u);
    memcpy(c->knots_v, s->knots_v, (s->nv + (size_t)s->degree_v + 1) * sizeof *c->knots_v);
    memcpy(c->points, s->points, 3 * s->nu * s->nv * sizeof *c->points);
    return c;
}

static double mesh_diagonal(const sk_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, d[3];
    for (size_t v = 0; v < m->num_vertices; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], m->positions[3 * v + k]);
            hi[k] = fmax(hi[k], m->positions[3 * v + k]);
        }
    sk__sub3(d, hi, lo);
    return sk__norm3(d);
}

/* The square parametrization with the corners (Floater's map, or another method of
 * sk_parametrize with the square boundary fixed). */
static sk_status square_map(const sk_mesh *disk, sk_param_method method, const uint32_t c[4],
                            double *uv, sk_error *err)
{
    sk_parametrize_opts po = {0};
    po.method = method ? method : SK_PARAM_FLOATER;
    po.boundary.shape = SK_BOUNDARY_SQUARE;
    po.boundary.has_corners = true;
    memcpy(po.boundary.corners, c, 4 * sizeof *c);
    po.raw = true; /* the unit square itself: the sides at exact 0 and 1 */
    sk_parametrize_stats ps;
    sk_status st = sk_parametrize(disk, &po, uv, &ps, err);
    if (st == SK_WARN_FLIPS)
        st = SK_OK; /* counted by balance(); the fit still works on a folded map, less well */
    sk_parametrize_stats_release(&ps);
    return st;
}

/* The map of one try: uv as the square map gave it (theta 0), or balanced by MIPS with the area
 * term, the square's sides kept, so that the knot grid (uniform in uv at the start) covers the
 * surface evenly instead of crowding the parts a conformal or shape-preserving map shrinks;
 * and its flip count. */
static sk_status balance(const sk_mesh *disk, double theta, double *uv, size_t *flipped,
                         sk_error *err)
{
    sk_status st = SK_OK;
    if (theta > 0) {
        sk_mips_opts mo = {.boundary = SK_BOUNDARY_GIVEN, .area_theta = theta};
        st = sk_param_mips(disk, &mo, uv, NULL, err);
        if (st == SK_WARN_FLIPS)
            st = SK_OK;
    }
    sk_param_metrics pm;
    if (!st)
        st = sk_param_metrics_compute(disk, uv, &pm, err);
    if (!st)
        *flipped = pm.flipped;
    return st;
}

static double deviation_of(const sk_fit_stats *fs)
{
    return fmax(fs->max_error, fs->surface_to_mesh);
}

/* The knots of s refined where the scores say (refine_knots), its points reset; *grown false
 * (and s unchanged) when the grid would pass cap control points or MAX_CTRL_1D a side. */
static sk_status grow_grid(sk_bspline_surface *s, const double *score_u, const double *score_v,
                           double share, size_t cap, bool *grown, sk_error *err)
{
    size_t nu = s->nu, nv = s->nv;
    double *ku = refine_knots(s->knots_u, &nu, s->degree_u, score_u, share);
    double *kv = refine_knots(s->knots_v, &nv, s->degree_v, score_v, share);
    *grown = ku && kv && nu * nv <= cap && nu <= MAX_CTRL_1D && nv <= MAX_CTRL_1D;
    double *pts = *grown ? sk__calloc_array(3 * nu * nv, sizeof *pts) : NULL;
    if (!ku || !kv || (*grown && !pts)) {
        sk__free(ku);
        sk__free(kv);
        *grown = false;
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    if (!*grown) {
        sk__free(ku);
        sk__free(kv);
        return SK_OK;
    }
    sk__free(s->knots_u);
    sk__free(s->knots_v);
    sk__free(s->points);
    s->knots_u = ku, s->knots_v = kv, s->points = pts, s->nu = nu, s->nv = nv;
    return SK_OK;
}

/* The hierarchical refinement over one map: rounds of fit_round, knots inserted in the worst
 * spans, until T holds on the dense check, the rounds run out or the grid would pass cap control
 * points (sk_fit_opts.max_control_points, by default twice the mesh's vertices: a tensor grid
 * pays a whole row or column for each local knot; or fewer than an earlier map's fit within
 * T). *out is the fit within T, else the round nearest to T. fs comes in with the
 * tolerance and the map's figures; progress runs from p0 to p1. */
static sk_status fit_map(const sk_mesh *disk, const double *uv, const sk_bvh *bvh,
                         const sk_fit_opts *o, int deg, size_t cap, double p0, double p1,
                         sk_bspline_surface **out, sk_fit_stats *fs, bool *capped, sk_error *err)
{
    size_t spans = o->initial_spans ? o->initial_spans : 4;
    unsigned rounds = o->max_rounds ? o->max_rounds : 40;
    double share = o->refine_share > 0 ? o->refine_share : REFINE_SHARE;
    sk_bspline_surface *s = NULL, *best = NULL;
    sk_fit_stats best_fs = *fs;
    best_fs.max_error = INFINITY;
    double *score_u = NULL, *score_v = NULL;
    samples x = {0};
    *capped = false;
    sk_status st = sk_bspline_create(deg, deg, spans + (size_t)deg, spans + (size_t)deg, &s, err);
    for (unsigned r = 1; !st && r <= rounds; ++r) {
        fs->rounds = r;
        if ((st = fit_round(disk, uv, bvh, o, s, &x, fs, &score_u, &score_v, err)))
            break;
        fs->control_points = s->nu * s->nv;
        fs->met = fs->max_error <= fs->tolerance && fs->surface_to_mesh <= fs->tolerance;
        if (fs->met) { /* confirmed on the dense grid, or refined where that finds a stray */
            memset(score_u, 0, (s->nu + 1) * sizeof *score_u);
            memset(score_v, 0, (s->nv + 1) * sizeof *score_v);
            if ((st = stray(s, bvh, fs->tolerance, true, score_u, score_v, &fs->surface_to_mesh,
                            err)))
                break;
            fs->met = fs->surface_to_mesh <= fs->tolerance;
        }
        if (fs->met || r == rounds)
            break;
        /* the round nearest to T so far, handed out if T is never met: on a noisy disk later
         * rounds can stray further (mask_cone at 1e-3: 0.0145 of the diagonal after 40
         * rounds against 0.0035 at round 5) */
        if (deviation_of(fs) < deviation_of(&best_fs)) {
            sk_bspline_destroy(&best);
            if (!(best = bspline_copy(s))) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                break;
            }
            best_fs = *fs;
        }
        if ((st = sk__progress(o->progress, o->progress_user, p0 + (p1 - p0) * r / rounds, err)))
            break;
        bool grown = false;
        if ((st = grow_grid(s, score_u, score_v, share, cap, &grown, err)) || !grown) {
            *capped = !st;
            break; /* more control points than allowed: keep the last fit */
        }
    }
    if (!st && !fs->met && best && deviation_of(&best_fs) < deviation_of(fs)) {
        sk_bspline_surface *t = s;
        s = best;
        best = t;
        size_t r = fs->rounds;
        *fs = best_fs;
        fs->rounds = r; /* rounds run, the kept one being an earlier one */
    }
    if (!st) {
        *out = s;
        s = NULL;
    }
    sk_bspline_destroy(&s);
    sk_bspline_destroy(&best);
    sk__free(score_u);
    sk__free(score_v);
    samples_free(&x);
    return st;
}

/* a better than b: within T against not, then fewer control points (the smaller deviation on a
 * tie), or when neither is within T the smaller deviation */
static bool better_fit(const sk_fit_stats *a, const sk_fit_stats *b)
{
    if (a->met != b->met)
        return a->met;
    if (a->met && a->control_points != b->control_points)
        return a->control_points < b->control_points;
    return deviation_of(a) < deviation_of(b);
}

/* The automatic choice's maps, the balanced ones first: they mostly need fewer control points
 * (the cut cone at 1e-2 of the diagonal: 289 with theta 1, 812 without), so the refinement of
 * the later ones stops early at their count. */
static const double auto_thetas[SK_FIT_AUTO_THETAS] = {1, 0.5, 0};

/* The fits over the maps to try (one when o->area_theta is set, else auto_thetas), the best
 * (better_fit) into *out and fs; base_uv is the square map, fs comes in with the tolerance. */
static sk_status fit_maps(const sk_mesh *disk, const double *base_uv, const sk_bvh *bvh,
                          const sk_fit_opts *o, int deg, size_t n_input,
                          sk_bspline_surface **out, sk_fit_stats *fs, sk_error *err)
{
    double one = o->area_theta > 0 ? o->area_theta : 0;
    const double *thetas = o->area_theta == 0 ? auto_thetas : &one;
    size_t n = o->area_theta == 0 ? SK_FIT_AUTO_THETAS : 1, nv = disk->num_vertices;
    double *uv = sk__malloc_array(2 * nv, sizeof *uv), tp = 0;
    sk_fit_stats in = *fs;
    sk_status st = uv ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t k = 0; !st && k < n; ++k) {
        double t0 = sk_seconds();
        sk_fit_stats f = in;
        sk_bspline_surface *s = NULL;
        bool capped = false;
        size_t first = (size_t)(o->initial_spans ? o->initial_spans : 4) + (size_t)deg;
        if (*out && fs->met && fs->control_points <= first * first)
            break; /* met on the first grid: no map can do with fewer */
        memcpy(uv, base_uv, 2 * nv * sizeof *uv);
        if ((st = balance(disk, thetas[k], uv, &f.flipped, err)))
            break;
        tp += sk_seconds() - t0;
        /* a later map is of use only with fewer control points than a fit within T */
        size_t cap = *out && fs->met ? fs->control_points - 1 : n_input;
        if ((st = fit_map(disk, uv, bvh, o, deg, cap, (double)k / n, (double)(k + 1) / n, &s, &f,
                          &capped, err)))
            break;
        f.area_theta = thetas[k];
        fs->tried[k] = (sk_fit_try){thetas[k], f.control_points, deviation_of(&f), f.met,
                                    capped && cap < n_input, sk_seconds() - t0};
        if (!*out || better_fit(&f, fs)) {
            sk_bspline_destroy(out);
            *out = s;
            sk_fit_try tried[SK_FIT_AUTO_THETAS];
            memcpy(tried, fs->tried, sizeof tried);
            *fs = f;
            memcpy(fs->tried, tried, sizeof tried);
        } else {
            sk_bspline_destroy(&s);
        }
        fs->tries = k + 1;
    }
    fs->seconds_param += tp;
    if (st)
        sk_bspline_destroy(out);
    sk__free(uv);
    return st;
}

sk_status sk_fit_bspline(const sk_mesh *disk, const sk_fit_opts *opts, sk_bspline_surface **out,
                         sk_fit_stats *stats, sk_error *err)
{
    *out = NULL;
    sk_fit_opts o = {0};
    if (opts)
        o = *opts;
    sk_fit_stats fs = {0};
    int deg = o.degree ? o.degree : 3;
    if (deg < 2 || deg > MAX_DEG || o.tolerance < 0 || o.smoothing < 0 || isnan(o.area_theta) ||
        o.initial_spans > 256 || !(o.refine_share >= 0 && o.refine_share <= 1))
        return sk__fail(err, SK_ERR_ARG, "fit options out of range (degree 2..%d, spans <= 256, "
                        "refine share 0..1)",
                        MAX_DEG);
    double t0 = sk_seconds();
    sk_status st = sk_param_check_disk(disk, err);
    if (st)
        return st;
    size_t n_input = o.max_control_points ? o.max_control_points : 2 * disk->num_vertices;
    uint32_t *loop = NULL;
    size_t nb = 0;
    double *uv = sk__malloc_array(2 * disk->num_vertices, sizeof *uv);
    sk_soup *soup = NULL;
    sk_bvh *bvh = NULL;
    sk_mesh *split = NULL;
    if (!uv) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    st = sk__param_ccw_loop(disk, &loop, &nb, err);
    if (!st && o.has_corners)
        st = sk__param_check_corners(loop, nb, o.corners, err);
    if (!st && !o.has_corners)
        st = sk_param_square_corners(disk, o.corners, err);
    /* no triangle with its three vertices on one side of the square: split dividing edges */
    if (!st)
        st = sk_param_split_side_edges(disk, o.corners, &split, &fs.split_edges, err);
    if (!st) {
        disk = split;
        double *grown = sk__realloc_array(uv, 2 * disk->num_vertices, sizeof *uv);
        if (!grown)
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        else
            uv = grown;
    }
    if (!st)
        st = square_map(disk, o.method, o.corners, uv, err);
    if (st)
        goto done;
    memcpy(fs.corners, o.corners, sizeof fs.corners);
    if ((st = sk_mesh_to_soup(disk, &soup, err)) || (st = sk_bvh_build(soup, &bvh, err)))
        goto done;
    fs.seconds_param = sk_seconds() - t0;
    fs.tolerance = o.tolerance > 0 ? o.tolerance
                                   : (o.tolerance_rel > 0 ? o.tolerance_rel : 1e-3) * mesh_diagonal(disk);
    st = fit_maps(disk, uv, bvh, &o, deg, n_input, out, &fs, err);
    fs.seconds_fit = sk_seconds() - t0 - fs.seconds_param;
done:
    if (stats)
        *stats = fs;
    sk__free(loop);
    sk__free(uv);
    sk_bvh_destroy(&bvh);
    sk_soup_destroy(&soup);
    sk_mesh_destroy(&split);
    return st;
}
