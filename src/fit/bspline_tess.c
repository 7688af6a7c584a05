/* Knot-adaptive tessellation of a fitted B-spline (fit.h): parameter lines per knot span from
 * bounds on the second derivatives over that span, so that the chord error is bounded cell by
 * cell instead of by the worst span of the whole surface. */
#include "fit/bspline_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <string.h>

/* Norm of the second-derivative control point along u of point (i, j): the B-spline of degree
 * p - 2 whose control points these are is S_uu, so their largest norm over a span bounds
 * |S_uu| there (convex hull). stride 1 for u, nu for v (the knots of that direction in U). */
static double second_point(const double *P, const double *U, int p, size_t i, size_t stride)
{
    double d0 = U[i + (size_t)p + 1] - U[i + 1], d1 = U[i + (size_t)p + 2] - U[i + 2];
    double d2 = U[i + (size_t)p + 1] - U[i + 2];
    if (!(d0 > 0 && d1 > 0 && d2 > 0))
        return 0;
    double r = 0;
    for (int k = 0; k < 3; ++k) {
        const double *a = P + 3 * i * stride + k, *b = a + 3 * stride, *c = b + 3 * stride;
        double e = (double)p * (double)(p - 1) / d2 * ((*c - *b) / d1 - (*b - *a) / d0);
        r += e * e;
    }
    return sqrt(r);
}

/* Norm of the mixed-derivative control point of (i, j) (S_uv, degrees p - 1, q - 1). */
static double mixed_point(const sk_bspline_surface *s, size_t i, size_t j)
{
    int p = s->degree_u, q = s->degree_v;
    double du = s->knots_u[i + (size_t)p + 1] - s->knots_u[i + 1];
    double dv = s->knots_v[j + (size_t)q + 1] - s->knots_v[j + 1];
    if (!(du > 0 && dv > 0))
        return 0;
    const double *a = s->points + 3 * (i + s->nu * j), *b = a + 3 * s->nu;
    double r = 0;
    for (int k = 0; k < 3; ++k) {
        double e = (double)(p * q) * (b[3 + k] - b[k] - a[3 + k] + a[k]) / (du * dv);
        r += e * e;
    }
    return sqrt(r);
}

/* The bounds of cell (su, sv) (knot spans of u and v): |S_uu|, |S_uv|, |S_vv| <= m[0..2]. */
static void cell_bounds(const sk_bspline_surface *s, size_t su, size_t sv, double m[3])
{
    int p = s->degree_u, q = s->degree_v;
    m[0] = m[1] = m[2] = 0;
    for (size_t j = sv - (size_t)q; j <= sv; ++j)
        for (size_t i = su - (size_t)p; i <= su; ++i) {
            if (i + 2 <= su)
                m[0] = fmax(m[0], second_point(s->points + 3 * s->nu * j, s->knots_u, p, i, 1));
            if (i < su && j < sv)
                m[1] = fmax(m[1], mixed_point(s, i, j));
            if (j + 2 <= sv)
                m[2] = fmax(m[2], second_point(s->points + 3 * i, s->knots_v, q, j, s->nu));
        }
}

/* Chord bound of a du x dv cell split along a diagonal, its second derivatives bounded by m:
 * the linear interpolant on a triangle errs by at most R^2 / 2 times the largest second
 * derivative (R the circumradius), here in coordinates scaled to the unit right triangle
 * (R^2 = 1/2) whose Hessian norm is at most max(A, B) + X by Gershgorin. */
static double cell_chord(const double m[3], double du, double dv)
{
    return 0.25 * (fmax(m[0] * du * du, m[2] * dv * dv) + m[1] * du * dv);
}

/* Subdivisions per span of one direction from the largest bounds over its column of cells
 * (worst[s]: along the direction, mixed), so that each factor of cell_chord is <= e; at
 * least `least` per non-empty span; scaled down to at most `cap` in all. Returns the count. */
static size_t span_counts(const double *U, size_t n, int p, const double *worst, double e,
                          unsigned least, size_t cap, unsigned *cnt)
{
    size_t total = 0;
    for (size_t s = (size_t)p; s < n; ++s) {
        double h = U[s + 1] - U[s], lim = INFINITY;
        cnt[s] = 0;
        if (!(h > 0))
            continue;
        for (int k = 0; k < 2; ++k)
            if (worst[2 * s + (size_t)k] > 0)
                lim = fmin(lim, sqrt(e / worst[2 * s + (size_t)k]));
        double c = ceil(h / lim);
        cnt[s] = (unsigned)(c > (double)cap ? (double)cap : c < least ? least : c);
        total += cnt[s];
    }
    if (total > cap) { /* too fine: fewer everywhere, in proportion */
        double f = (double)cap / (double)total;
        total = 0;
        for (size_t s = (size_t)p; s < n; ++s) {
            unsigned c = (unsigned)floor(cnt[s] * f);
            cnt[s] = cnt[s] && c < 1 ? 1 : c;
            total += cnt[s];
        }
    }
    return total;
}

/* The lines of one direction from the counts: total + 1 values from 0 to 1. */
static void fill_lines(const double *U, size_t n, int p, const unsigned *cnt, double *t)
{
    size_t k = 0;
    for (size_t s = (size_t)p; s < n; ++s)
        for (unsigned i = 0; i < cnt[s]; ++i)
            t[k++] = U[s] + (U[s + 1] - U[s]) * i / cnt[s];
    t[k] = 1;
}

static void lines_free(sk__fit_lines *l)
{
    sk__free(l->u);
    sk__free(l->v);
    memset(l, 0, sizeof *l);
}

/* The worst bounds per span of each direction (2 per span: along it, mixed). */
static void direction_worst(const sk_bspline_surface *s, double *wu, double *wv)
{
    for (size_t sv = (size_t)s->degree_v; sv < s->nv; ++sv)
        for (size_t su = (size_t)s->degree_u; su < s->nu; ++su) {
            double m[3];
            cell_bounds(s, su, sv, m);
            wu[2 * su] = fmax(wu[2 * su], m[0]);
            wu[2 * su + 1] = fmax(wu[2 * su + 1], m[1]);
            wv[2 * sv] = fmax(wv[2 * sv], m[2]);
            wv[2 * sv + 1] = fmax(wv[2 * sv + 1], m[1]);
        }
}

/* The largest cell_chord over the cells with the subdivisions chosen. */
static double lines_chord(const sk_bspline_surface *s, const unsigned *cu, const unsigned *cv)
{
    double chord = 0;
    for (size_t sv = (size_t)s->degree_v; sv < s->nv; ++sv)
        for (size_t su = (size_t)s->degree_u; su < s->nu; ++su) {
            if (!cu[su] || !cv[sv])
                continue;
            double m[3];
            cell_bounds(s, su, sv, m);
            chord = fmax(chord, cell_chord(m, (s->knots_u[su + 1] - s->knots_u[su]) / cu[su],
                                           (s->knots_v[sv + 1] - s->knots_v[sv]) / cv[sv]));
        }
    return chord;
}

sk_status sk__fit_lines_make(const sk_bspline_surface *s, double tol, size_t max_side,
                             sk__fit_lines *out, sk_error *err)
{
    memset(out, 0, sizeof *out);
    double *wu = sk__calloc_array(2 * (s->nu + 1), sizeof *wu);
    double *wv = sk__calloc_array(2 * (s->nv + 1), sizeof *wv);
    unsigned *cu = sk__calloc_array(s->nu + 1, sizeof *cu), *cv = sk__calloc_array(s->nv + 1, sizeof *cv);
    sk_status st = wu && wv && cu && cv ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (!st) {
        direction_worst(s, wu, wv);
        /* cell_chord <= (e + e) / 4 = tol / 20 when each factor is <= e */
        double e = tol > 0 ? tol / 10 : INFINITY;
        size_t least_u = 64 / (s->nu - (size_t)s->degree_u) + 1, least_v = 64 / (s->nv - (size_t)s->degree_v) + 1;
        out->nu = span_counts(s->knots_u, s->nu, s->degree_u, wu, e, (unsigned)(least_u < 4 ? 4 : least_u),
                              max_side, cu);
        out->nv = span_counts(s->knots_v, s->nv, s->degree_v, wv, e, (unsigned)(least_v < 4 ? 4 : least_v),
                              max_side, cv);
        out->u = sk__malloc_array(out->nu + 1, sizeof *out->u);
        out->v = sk__malloc_array(out->nv + 1, sizeof *out->v);
        if (!out->u || !out->v)
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    if (!st) {
        fill_lines(s->knots_u, s->nu, s->degree_u, cu, out->u);
        fill_lines(s->knots_v, s->nv, s->degree_v, cv, out->v);
        out->chord = lines_chord(s, cu, cv);
    } else {
        lines_free(out);
    }
    sk__free(wu);
    sk__free(wv);
    sk__free(cu);
    sk__free(cv);
    return st;
}

void sk__fit_lines_free(sk__fit_lines *l)
{
    lines_free(l);
}

/* The soup of the lines: vertex (i, j) = S(u_i, v_j) with its unit normal. */
static sk_status lines_soup(const sk_bspline_surface *s, const sk__fit_lines *l, sk_soup **out,
                            sk_error *err)
{
    size_t w = l->nu + 1, cells = l->nu * l->nv;
    sk_status st = sk_soup_create(w * (l->nv + 1), 2 * cells, 6 * cells, true, true, out, err);
    for (size_t k = 0; !st && k < w * (l->nv + 1); ++k) {
        double pos[3], su[3], sv[3], n[3], uv[2] = {l->u[k % w], l->v[k / w]};
        sk_bspline_eval(s, uv[0], uv[1], pos, su, sv);
        sk__cross3(n, su, sv);
        if (!(sk__normalize3(n) > 0)) /* a collapsed side */
            n[0] = n[1] = 0, n[2] = 1;
        st = sk_soup_push_vertex(*out, pos, n, uv);
    }
    for (size_t c = 0; !st && c < cells; ++c) {
        uint32_t a = (uint32_t)(c / l->nu * w + c % l->nu);
        const uint32_t lo[3] = {a, a + 1, a + (uint32_t)w + 1}, hi[3] = {a, a + (uint32_t)w + 1, a + (uint32_t)w};
        st = sk_soup_push_face(*out, lo, 3);
        if (!st)
            st = sk_soup_push_face(*out, hi, 3);
    }
    if (st) {
        sk_soup_destroy(out);
        return sk__fail(err, st, "out of memory");
    }
    return SK_OK;
}

sk_status sk_fit_tessellate(const sk_bspline_surface *s, double tol, size_t max_side,
                            sk_soup **out, sk_fit_tessellation *info, sk_error *err)
{
    *out = NULL;
    if (!s || !(tol >= 0) || max_side < 2 || max_side > 4096)
        return sk__fail(err, SK_ERR_ARG, "tessellation: tolerance >= 0 and 2..4096 lines a side");
    sk__fit_lines l;
    sk_status st = sk__fit_lines_make(s, tol, max_side, &l, err);
    if (!st)
        st = lines_soup(s, &l, out, err);
    if (!st && info)
        *info = (sk_fit_tessellation){l.nu, l.nv, l.chord};
    sk__fit_lines_free(&l);
    return st;
}
