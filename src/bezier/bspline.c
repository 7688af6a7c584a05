/* Tensor-product B-spline surfaces (bspline.h): the Cox-de Boor recurrence for the basis and its
 * derivatives, evaluation and a grid tessellation. */
#include "surfkit/bspline.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_DEGREE = 7 };

static void uniform_clamped(double *k, size_t n, int p)
{
    size_t m = n + (size_t)p + 1, spans = n - (size_t)p;
    for (size_t i = 0; i < m; ++i) {
        if (i <= (size_t)p)
            k[i] = 0;
        else if (i >= n)
            k[i] = 1;
        else
            k[i] = (double)(i - (size_t)p) / (double)spans;
    }
}

sk_status sk_bspline_create(int degree_u, int degree_v, size_t nu, size_t nv,
                            sk_bspline_surface **out, sk_error *err)
{
    *out = NULL;
    if (degree_u < 1 || degree_u > MAX_DEGREE || degree_v < 1 || degree_v > MAX_DEGREE)
        return sk__fail(err, SK_ERR_ARG, "B-spline degrees must be 1 to %d", MAX_DEGREE);
    if (nu <= (size_t)degree_u || nv <= (size_t)degree_v || nu > 100000 || nv > 100000)
        return sk__fail(err, SK_ERR_ARG, "%zu x %zu control points for degrees %d x %d", nu, nv,
                        degree_u, degree_v);
    sk_bspline_surface *s = sk__calloc_array(1, sizeof *s);
    if (!s)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    s->degree_u = degree_u, s->degree_v = degree_v, s->nu = nu, s->nv = nv;
    s->knots_u = sk__malloc_array(nu + (size_t)degree_u + 1, sizeof *s->knots_u);
    s->knots_v = sk__malloc_array(nv + (size_t)degree_v + 1, sizeof *s->knots_v);
    s->points = sk__calloc_array(3 * nu * nv, sizeof *s->points);
    if (!s->knots_u || !s->knots_v || !s->points) {
        sk_bspline_destroy(&s);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    uniform_clamped(s->knots_u, nu, degree_u);
    uniform_clamped(s->knots_v, nv, degree_v);
    *out = s;
    return SK_OK;
}

void sk_bspline_destroy(sk_bspline_surface **s)
{
    if (!s || !*s)
        return;
    sk__free((*s)->knots_u);
    sk__free((*s)->knots_v);
    sk__free((*s)->points);
    sk__free(*s);
    *s = NULL;
}

size_t sk_bspline_span(const double *k, size_t n, int p, double t)
{
    if (t >= k[n])
        return n - 1;
    if (t <= k[p])
        return (size_t)p;
    size_t lo = (size_t)p, hi = n; /* k[lo] <= t < k[hi] */
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (t < k[mid])
            hi = mid;
        else
            lo = mid;
    }
    return lo;
}

static double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

/* B[q][k] = N_{span - q + k, q}(t), q = 0..p, k = 0..q (the triangle of the recurrence). */
static void basis_table(const double *U, size_t span, int p, double t,
                        double B[MAX_DEGREE + 1][MAX_DEGREE + 1])
{
    B[0][0] = 1;
    for (int q = 1; q <= p; ++q)
        for (int k = 0; k <= q; ++k) {
            size_t i = span - (size_t)q + (size_t)k;
            double left = k > 0 ? B[q - 1][k - 1] : 0, right = k < q ? B[q - 1][k] : 0;
            B[q][k] = ratio(t - U[i], U[i + (size_t)q] - U[i]) * left +
                      ratio(U[i + (size_t)q + 1] - t, U[i + (size_t)q + 1] - U[i + 1]) * right;
        }
}

/* d-th derivative of N_{i,q} (i = span - q + k) from the table:
 * N'_{i,q} = q (N_{i,q-1} / (U_{i+q} - U_i) - N_{i+1,q-1} / (U_{i+q+1} - U_{i+1})). */
static double deriv(const double *U, size_t span, int q, int k, int d,
                    double B[MAX_DEGREE + 1][MAX_DEGREE + 1])
{
    if (k < 0 || k > q)
        return 0;
    if (d == 0)
        return B[q][k];
    if (q == 0)
        return 0;
    size_t i = span - (size_t)q + (size_t)k;
    return q * (ratio(deriv(U, span, q - 1, k - 1, d - 1, B), U[i + (size_t)q] - U[i]) -
                ratio(deriv(U, span, q - 1, k, d - 1, B), U[i + (size_t)q + 1] - U[i + 1]));
}

void sk_bspline_basis(const double *knots, size_t span, int p, double t, int nd, double *ders)
{
    double B[MAX_DEGREE + 1][MAX_DEGREE + 1];
    basis_table(knots, span, p, t, B);
    for (int d = 0; d <= nd; ++d)
        for (int k = 0; k <= p; ++k)
            ders[d * (p + 1) + k] = deriv(knots, span, p, k, d, B);
}

void sk_bspline_eval(const sk_bspline_surface *s, double u, double v, double pos[3],
                     double du[3], double dv[3])
{
    u = fmin(fmax(u, 0.0), 1.0);
    v = fmin(fmax(v, 0.0), 1.0);
    int p = s->degree_u, q = s->degree_v;
    size_t su = sk_bspline_span(s->knots_u, s->nu, p, u), sv = sk_bspline_span(s->knots_v, s->nv, q, v);
    double Nu[2 * (MAX_DEGREE + 1)], Nv[2 * (MAX_DEGREE + 1)];
    sk_bspline_basis(s->knots_u, su, p, u, 1, Nu);
    sk_bspline_basis(s->knots_v, sv, q, v, 1, Nv);
    double P[3] = {0, 0, 0}, Du[3] = {0, 0, 0}, Dv[3] = {0, 0, 0};
    for (int b = 0; b <= q; ++b)
        for (int a = 0; a <= p; ++a) {
            const double *c = s->points + 3 * ((su - (size_t)p + (size_t)a) +
                                               s->nu * (sv - (size_t)q + (size_t)b));
            double w = Nu[a] * Nv[b], wu = Nu[p + 1 + a] * Nv[b], wv = Nu[a] * Nv[q + 1 + b];
            for (int k = 0; k < 3; ++k) {
                P[k] += w * c[k];
                Du[k] += wu * c[k];
                Dv[k] += wv * c[k];
            }
        }
    if (pos)
        memcpy(pos, P, sizeof P);
    if (du)
        memcpy(du, Du, sizeof Du);
    if (dv)
        memcpy(dv, Dv, sizeof Dv);
}

sk_status sk_bspline_tessellate(const sk_bspline_surface *s, unsigned n, sk_soup **out,
                                sk_error *err)
{
    *out = NULL;
    if (n < 1 || n > 4096)
        return sk__fail(err, SK_ERR_ARG, "tessellation %u out of 1..4096", n);
    size_t nv = (size_t)(n + 1) * (n + 1);
    sk_soup *soup = NULL;
    sk_status st = sk_soup_create(nv, 2 * (size_t)n * n, 6 * (size_t)n * n, true, false, &soup, err);
    for (unsigned j = 0; !st && j <= n; ++j)
        for (unsigned i = 0; !st && i <= n; ++i) {
            double p[3], du[3], dv[3], nrm[3];
            sk_bspline_eval(s, (double)i / n, (double)j / n, p, du, dv);
            sk__cross3(nrm, du, dv);
            if (!(sk__normalize3(nrm) > 0))
                nrm[0] = nrm[1] = 0, nrm[2] = 1; /* a degenerate point (collapsed edge) */
            if (sk_soup_push_vertex(soup, p, nrm, NULL))
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        }
    for (unsigned j = 0; !st && j < n; ++j)
        for (unsigned i = 0; !st && i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            const uint32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
            if (sk_soup_push_face(soup, t1, 3) || sk_soup_push_face(soup, t2, 3))
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        }
    if (st) {
        sk_soup_destroy(&soup);
        return st;
    }
    *out = soup;
    return SK_OK;
}

/* a bound on the second derivatives of s from its control net: second differences over the
 * smallest knot spans */
static double second_derivative_bound(const sk_bspline_surface *s)
{
    double hu = 1, hv = 1;
    for (size_t k = 0; k + 1 < s->nu + (size_t)s->degree_u + 1; ++k)
        if (s->knots_u[k + 1] > s->knots_u[k])
            hu = fmin(hu, s->knots_u[k + 1] - s->knots_u[k]);
    for (size_t k = 0; k + 1 < s->nv + (size_t)s->degree_v + 1; ++k)
        if (s->knots_v[k + 1] > s->knots_v[k])
            hv = fmin(hv, s->knots_v[k + 1] - s->knots_v[k]);
    double duu = 0, dvv = 0, duv = 0;
    const double *P = s->points;
    size_t nu = s->nu;
    for (size_t j = 0; j < s->nv; ++j)
        for (size_t i = 0; i < nu; ++i) {
            double a = 0, b = 0, c = 0;
            for (int k = 0; k < 3; ++k) {
                const double *p = P + 3 * (i + nu * j) + k;
                if (i > 0 && i + 1 < nu)
                    a += (p[3] - 2 * p[0] + p[-3]) * (p[3] - 2 * p[0] + p[-3]);
                if (j > 0 && j + 1 < s->nv)
                    b += (p[3 * nu] - 2 * p[0] + p[-3 * (ptrdiff_t)nu]) *
                         (p[3 * nu] - 2 * p[0] + p[-3 * (ptrdiff_t)nu]);
                if (i + 1 < nu && j + 1 < s->nv)
                    c += (p[3 * nu + 3] - p[3 * nu] - p[3] + p[0]) *
                         (p[3 * nu + 3] - p[3 * nu] - p[3] + p[0]);
            }
            duu = fmax(duu, sqrt(a)), dvv = fmax(dvv, sqrt(b)), duv = fmax(duv, sqrt(c));
        }
    return duu / (hu * hu) + 2 * duv / (hu * hv) + dvv / (hv * hv);
}

/* Tessellation grid for the deviation and mesh output: fine enough that the chord error of its
 * triangles (at most |S_dd| / (8 N^2) along a diagonal of a grid cell) stays below 1/20 of the
 * tolerance, at least 8 per knot span, 64 to 512 (the deviation's cost). *chord gets that error bound. */
unsigned sk_bspline_tessellation_grid(const sk_bspline_surface *s, double tol, double *chord)
{
    size_t spans = s->nu - (size_t)s->degree_u;
    if (s->nv - (size_t)s->degree_v > spans)
        spans = s->nv - (size_t)s->degree_v;
    double k = second_derivative_bound(s);
    double n = fmax(8.0 * (double)spans, tol > 0 ? ceil(sqrt(k / (8 * tol / 20))) : 0);
    n = fmin(fmax(n, 64), 512);
    if (chord)
        *chord = k / (8 * n * n);
    return (unsigned)n;
}
