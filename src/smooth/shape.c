/* Shape measures of the patches of a smooth surface (smooth.h, sk_smooth_patch_shapes):
 *
 *  - overshoot: the largest distance of a patch from the flat triangle(s) of the mesh face it
 *    replaces, over a grid of samples, divided by the longest edge of those triangles (a quad
 *    replaces the two input triangles on either side of its deleted edge; that edge counts as
 *    one of its edges). 0 for a patch lying in its face; a spike is > 1.
 *  - fairness: the largest angle between the patch normal and the normal interpolated from the
 *    vertex normals at its corners (linearly over a triangle, bilinearly over a quad, then
 *    normalized: the Phong normal), over the same grid; 180 where the patch normal vanishes.
 *    The patches interpolate those normals at the corners, so the angle is 0 there; in between it
 *    grows with every ripple, bulge, spike or fold (a fold turns the normal over: above 90). It
 *    is scale invariant, 0 on a flat face with equal normals, and small (second order in the edge
 *    length) on a densely sampled smooth shape such as the sphere.
 * Both are the largest over the grid of samples, each computed by sk_patch_eval's operations. The
 * grids of quartic triangles and bicubic quads are screened first (tri4_screen, bicubic_screen):
 * every sample from a table of Bernstein values (four samples per vector, with fused
 * multiply-adds where the processor has them), within a proven bound of the full values, and only
 * the samples that could still raise the largest angle or distance are evaluated in full (about 2
 * a patch on the scans): the figures are those of the full grid to the bit. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RAD2DEG (180.0 / M_PI)

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

static int key_cmp(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The screen's table (tri4_screen): at the samples (a, b) = (i / N, j / N), i + j <= N, of the
 * triangle grid in the order of its loops, the quartic Bernstein values B^4_{ijk}(U, V, W) at
 * (1 - a - b, a, b) (rows 0..14, index sk_tri_index(4, j, k)), the cubic ones (rows 15..24,
 * sk_tri_index(3, j, k)), a and b (rows 25, 26); the samples in fours, each row of a four
 * holding its samples in turn (the last sample repeated to fill the last four). Without it (no memory, or a
 * grid above 512 samples) the grid is evaluated in full. */
#define SCREEN_ROWS 27
#define SCREEN_MAX_NS 512

static void screen_table_init(sk__shape_ctx *c)
{
    unsigned N = c->n, ns = (N + 1) * (N + 2) / 2, nsp = (ns + 3) / 4 * 4;
    if (N > 200 || ns > SCREEN_MAX_NS)
        return;
    c->tab = sk__malloc_array((size_t)SCREEN_ROWS * nsp, sizeof *c->tab);
    if (!c->tab)
        return;
    c->tab_ns = ns;
    static const double fact[5] = {1, 1, 2, 6, 24};
    unsigned q = 0;
    for (unsigned i = 0; i <= N; ++i)
        for (unsigned j = 0; j <= N - i; ++j, ++q) {
            double a = (double)i / N, b = (double)j / N, U = 1.0 - a - b;
            for (unsigned rep = q; rep < nsp && (rep == q || q + 1 == ns); ++rep) {
                double *t = c->tab + (size_t)(rep / 4) * 4 * SCREEN_ROWS + rep % 4;
                for (unsigned n = 3; n <= 4; ++n)
                    for (unsigned k = 0; k <= n; ++k)
                        for (unsigned jj = 0; jj + k <= n; ++jj) {
                            unsigned ii = n - jj - k;
                            double v = fact[n] / (fact[ii] * fact[jj] * fact[k]);
                            v *= pow(U, ii) * pow(a, jj) * pow(b, k);
                            t[4 * ((n == 4 ? 0 : 15) + sk_tri_index(n, jj, k))] = v;
                        }
                t[4 * 25] = a;
                t[4 * 26] = b;
            }
        }
}

sk_status sk__shape_ctx_init(sk__shape_ctx *c, const sk_smooth *s, unsigned samples,
                             sk_error *err)
{
    memset(c, 0, sizeof *c);
    c->s = s;
    c->n = samples ? samples : 12;
    screen_table_init(c);
    if (!s->num_deleted)
        return SK_OK;
    c->keys = sk__malloc_array(s->num_deleted, sizeof *c->keys);
    if (!c->keys)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory for the shape measures");
    for (size_t i = 0; i < s->num_deleted; ++i)
        c->keys[i] = edge_key(s->deleted[2 * i], s->deleted[2 * i + 1]);
    qsort(c->keys, s->num_deleted, sizeof *c->keys, key_cmp);
    c->nkeys = s->num_deleted;
    return SK_OK;
}

void sk__shape_ctx_free(sk__shape_ctx *c)
{
    sk__free(c->tab);
    c->tab = NULL;
    sk__free(c->keys);
    c->keys = NULL;
    c->nkeys = 0;
}

static bool is_deleted(const sk__shape_ctx *c, uint32_t a, uint32_t b)
{
    uint64_t k = edge_key(a, b);
    return c->nkeys && bsearch(&k, c->keys, c->nkeys, sizeof k, key_cmp) != NULL;
}

static double seg_dist2(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], q[3];
    sk__sub3(ab, b, a);
    sk__sub3(ap, p, a);
    double ll = sk__dot3(ab, ab), t = ll > 0 ? sk__dot3(ap, ab) / ll : 0.0;
    t = fmin(fmax(t, 0.0), 1.0);
    for (int k = 0; k < 3; ++k)
        q[k] = a[k] + t * ab[k] - p[k];
    return sk__dot3(q, q);
}

/* a flat triangle abc of the face and what the distances to it need of it alone (computed once
 * per patch, not per sample) */
typedef struct flat_tri {
    const double *a, *b, *c;
    double e1[3], e2[3], n[3], nn, len;
} flat_tri;

static void flat_tri_init(flat_tri *t, const double *a, const double *b, const double *c)
{
    t->a = a, t->b = b, t->c = c;
    sk__sub3(t->e1, b, a);
    sk__sub3(t->e2, c, a);
    sk__cross3(t->n, t->e1, t->e2);
    t->nn = sk__dot3(t->n, t->n);
    t->len = sqrt(t->nn);
}

/* The distance from p to the triangle (a segment or a point when it is degenerate), or true
 * without it where it is proven at most dmax: its value could then not raise the largest so far.
 * The proof compares before the division or the square root: with u the unit roundoff, fl(dmax
 * len) (1 - 1e-15) rounded is below dmax len (the factor outweighs the two roundings, 2u =
 * 2.2e-16), so h at most that gives h / len < dmax, and the rounded quotient, rounding being
 * monotone, is at most dmax (the same for sqrt(m2) against dmax^2). Where the proof does not hold
 * *d is computed by the same operations as always; outside the triangle's prism (v < 0) w is not
 * needed. */
/* The same for the nearest of the sides ab, bc, ca, tried from side `first` on (the one across
 * which p lies outside the triangle): the first within the bound proves the minimum within it,
 * and the minimum of all three, when needed, does not depend on their order. */
static bool seg_dist_within(const double p[3], const flat_tri *T, int first, double dmax,
                            double *d)
{
    const double *end[4] = {T->a, T->b, T->c, T->a}, bound = dmax * dmax * (1.0 - 1e-15);
    double d2[3];
    for (int k = 0; k < 3; ++k) {
        int e = (first + k) % 3;
        d2[e] = seg_dist2(p, end[e], end[e + 1]);
        if (d2[e] <= bound)
            return true;
    }
    *d = sqrt(fmin(d2[0], fmin(d2[1], d2[2])));
    return false;
}

static bool tri_dist_within(const double p[3], const flat_tri *T, double dmax, double *d)
{
    double ap[3], t[3];
    sk__sub3(ap, p, T->a);
    int first = 0;
    if (T->nn > 0) {
        sk__cross3(t, ap, T->e2);
        double v = sk__dot3(t, T->n) / T->nn;
        first = 2; /* v < 0: outside across ca */
        if (v >= 0) {
            sk__cross3(t, T->e1, ap);
            double w = sk__dot3(t, T->n) / T->nn;
            if (w >= 0 && v + w <= 1) {
                double h = fabs(sk__dot3(ap, T->n));
                if (h <= dmax * T->len * (1.0 - 1e-15))
                    return true;
                *d = h / T->len;
                return false;
            }
            first = w >= 0 ? 1 : 0;
        }
    }
    return seg_dist_within(p, T, first, dmax, d);
}

/* The largest angle and distance over the samples, with the work that cannot change them
 * skipped (the results are those of computing every sample in full): an angle atan2(y, x)
 * (y >= 0) is computed only when (x, y) is not clearly clockwise of the largest so far (ym, xm)
 * (the 2D cross product, with a margin far above its rounding), and the distance to the
 * triangles of a quad stops at the first within the largest distance so far (the minimum can
 * then no longer raise it). */
typedef struct shape_max {
    double amax, ym, xm, dmax;
    bool any_angle;
} shape_max;

static void max_angle_yx(shape_max *M, double y, double x)
{
    if (M->any_angle &&
        y * M->xm - x * M->ym < -1e-9 * (fabs(y * M->xm) + fabs(x * M->ym)))
        return;
    double ang = atan2(y, x) * RAD2DEG;
    if (!M->any_angle || ang > M->amax) {
        M->amax = ang;
        M->ym = y;
        M->xm = x;
    }
    M->any_angle = true;
}

static void max_angle(shape_max *M, const double nrm[3], const double phong[3])
{
    double c[3];
    sk__cross3(c, nrm, phong);
    max_angle_yx(M, sk__norm3(c), sk__dot3(nrm, phong));
}

static void max_distance(shape_max *M, const double x[3], const flat_tri *tris, int ntri)
{
    double d = INFINITY;
    for (int t = 0; t < ntri; ++t) {
        double dt;
        if (tri_dist_within(x, tris + t, M->dmax, &dt))
            return;
        d = fmin(d, dt);
        if (d <= M->dmax)
            return;
    }
    M->dmax = d;
}

/* Evaluation of a patch on the rows of the sample grid, giving what sk_patch_eval gives (point,
 * unit normal, |du x dv|) to the bit, for less: two samples of a row at once in the de Casteljau
 * steps of a quartic triangle (two lanes of a vector, each lane the same operations in the same
 * order as the scalar code of src/bezier/eval.c), and the rows of a bicubic patch's net summed
 * in s once per grid row (a = i / N is the row's), not once per sample. Other degrees go through
 * sk_patch_eval. */
typedef double v2d __attribute__((vector_size(16)));

typedef struct row_eval {
    const sk_patch_set *set;
    size_t p;
    const double *cp;
    int mode; /* 0: sk_patch_eval, 2: bicubic (quartic triangles: tri4_grid) */
    double a, r[4][3], dr[4][3];
} row_eval;

static void row_eval_start(row_eval *R, const sk_patch_set *set, size_t p, double a)
{
    const sk_patch *pa = &set->patches[p];
    R->set = set, R->p = p, R->a = a, R->cp = sk_patch_cp(set, p);
    R->mode = 0;
    if (pa->kind != SK_PATCH_TRIANGLE && pa->degree == 3 && pa->degree_v == 3)
        R->mode = 2;
    if (R->mode != 2)
        return;
    double Bs[4], dBs[4];
    sk__bernstein_n(3, a, Bs, dBs);
    for (unsigned j = 0; j <= 3; ++j) {
        const double *row = R->cp + 3 * sk_tensor_index(3, 0, j);
        double r[3] = {0, 0, 0}, dr[3] = {0, 0, 0};
        for (unsigned i = 0; i <= 3; ++i)
            for (int x = 0; x < 3; ++x) {
                r[x] += Bs[i] * row[3 * i + x];
                dr[x] += dBs[i] * row[3 * i + x];
            }
        memcpy(R->r[j], r, sizeof r);
        memcpy(R->dr[j], dr, sizeof dr);
    }
}

/* sk_bezier_eval's normal and length from the point's derivatives */
static double finish(const double D1[3], const double D2[3], double normal[3])
{
    double n[3];
    sk__cross3(n, D1, D2);
    double len = sk__norm3(n);
    if (len > 0.0)
        sk__scale3(normal, n, 1.0 / len);
    else
        normal[0] = normal[1] = normal[2] = 0.0;
    return len;
}

/* de Casteljau of the quartic triangle at (V[0], W[0]) and (V[1], W[1]) (tri_eval_n of eval.c),
 * from its control points cpv each in both lanes, point and derivatives as two lanes per
 * coordinate */
static void tri4_eval2v(const v2d *cpv, v2d V, v2d W, v2d pt[3], v2d d1[3], v2d d2[3])
{
    const unsigned n = 4;
    v2d one = {1.0, 1.0}, U = one - V - W;
    v2d net[3 * 10], tmp[3 * 10];
    for (unsigned k = 0; k < n; ++k) { /* degree 4 -> 3 from the control points */
        unsigned row = sk_tri_index(n, 0, k), up = sk_tri_index(n, 0, k + 1);
        unsigned orow = sk_tri_index(n - 1, 0, k);
        for (unsigned j = 0; j + k < n; ++j) {
            const v2d *a = cpv + 3 * (row + j), *b = a + 3, *c = cpv + 3 * (up + j);
            v2d *o = net + 3 * (orow + j);
            for (int x = 0; x < 3; ++x)
                o[x] = U * a[x] + V * b[x] + W * c[x];
        }
    }
    v2d *src = net, *dst = tmp;
    for (unsigned r = n - 1; r > 1; --r) {
        for (unsigned k = 0; k < r; ++k) {
            unsigned row = sk_tri_index(r, 0, k), up = sk_tri_index(r, 0, k + 1);
            unsigned orow = sk_tri_index(r - 1, 0, k);
            for (unsigned j = 0; j + k < r; ++j) {
                const v2d *a = src + 3 * (row + j), *b = a + 3, *c = src + 3 * (up + j);
                v2d *o = dst + 3 * (orow + j);
                for (int x = 0; x < 3; ++x)
                    o[x] = U * a[x] + V * b[x] + W * c[x];
            }
        }
        v2d *t = src;
        src = dst, dst = t;
    }
    const v2d *b100 = src, *b010 = src + 3 * sk_tri_index(1, 1, 0),
              *b001 = src + 3 * sk_tri_index(1, 0, 1);
    v2d N = {(double)n, (double)n};
    for (int x = 0; x < 3; ++x) {
        pt[x] = U * b100[x] + V * b010[x] + W * b001[x];
        d1[x] = N * (b010[x] - b100[x]);
        d2[x] = N * (b001[x] - b100[x]);
    }
}

/* cross product and dot product of two-lane vectors (sk__cross3, sk__dot3 in each lane) */
static void cross2v(v2d r[3], const v2d a[3], const v2d b[3])
{
    v2d x = a[1] * b[2] - a[2] * b[1];
    v2d y = a[2] * b[0] - a[0] * b[2];
    v2d z = a[0] * b[1] - a[1] * b[0];
    r[0] = x, r[1] = y, r[2] = z;
}

static v2d dot2v(const v2d a[3], const v2d b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static v2d sqrt2v(v2d q)
{
    v2d r = {sqrt(q[0]), sqrt(q[1])};
    return r;
}

/* max_distance of the points P (lane 0, and lane 1 when nl is 2) in turn, the first triangle's
 * barycentric coordinates v, w and plane distance formed in the two lanes by tri_dist_within's
 * operations (the same values to the bit), its decisions then taken lane by lane in order. */
static void max_distance2(shape_max *M, const v2d P[3], int nl, const flat_tri *tris, int ntri)
{
    const flat_tri *T = tris;
    v2d ap[3], t1[3], t2[3], E1[3], E2[3], Nn[3], nn = {T->nn, T->nn};
    for (int x = 0; x < 3; ++x) {
        ap[x] = P[x] - (v2d){T->a[x], T->a[x]};
        E1[x] = (v2d){T->e1[x], T->e1[x]};
        E2[x] = (v2d){T->e2[x], T->e2[x]};
        Nn[x] = (v2d){T->n[x], T->n[x]};
    }
    cross2v(t1, ap, E2);
    cross2v(t2, E1, ap);
    v2d v = dot2v(t1, Nn) / nn, w = dot2v(t2, Nn) / nn, h = dot2v(ap, Nn);
    for (int l = 0; l < nl; ++l) {
        double x[3] = {P[0][l], P[1][l], P[2][l]}, d, dt;
        if (T->nn > 0 && v[l] >= 0 && w[l] >= 0 && v[l] + w[l] <= 1) {
            double hl = fabs(h[l]);
            if (hl <= M->dmax * T->len * (1.0 - 1e-15))
                continue;
            d = fmin(INFINITY, hl / T->len); /* max_distance's fmin (a NaN gives inf) */
        } else if (seg_dist_within(x, T, !(v[l] >= 0) ? 2 : w[l] >= 0 ? 1 : 0, M->dmax, &dt)) {
            continue;
        } else {
            d = fmin(INFINITY, dt);
        }
        if (d <= M->dmax)
            continue;
        int t = 1;
        for (; t < ntri; ++t) {
            if (tri_dist_within(x, tris + t, M->dmax, &dt))
                break;
            d = fmin(d, dt);
            if (d <= M->dmax)
                break;
        }
        if (t == ntri)
            M->dmax = d;
    }
}

/* Two samples (A[l], B[l]) of the shape grid (only lane 0 when nl is 1) from their points P and
 * derivatives D1, D2, up to the largest angle and distance in the two lanes of a vector: each
 * lane the operations of the scalar code (finish, the Phong normal, max_angle's cross and dot
 * products) in their order, so the same values to the bit. */
static void grid_lanes(const v2d A, const v2d B, int nl, const v2d P[3], const v2d D1[3],
                       const v2d D2[3], const double *const Nv[4], unsigned nc,
                       const flat_tri *tris, int ntri, shape_max *M, bool *flat_normal)
{
    v2d one = {1.0, 1.0}, zero = {0.0, 0.0}, n[3], nrm[3], ph[3], c[3], w[4];
    cross2v(n, D1, D2); /* finish */
    v2d len = sqrt2v(dot2v(n, n)), inv = one / len;
    for (int x = 0; x < 3; ++x) {
        v2d s = n[x] * inv, r = {len[0] > 0.0 ? s[0] : 0.0, len[1] > 0.0 ? s[1] : 0.0};
        nrm[x] = r;
    }
    if (nc == 3) /* the Phong normal: linear over a triangle, bilinear over a quad */
        w[0] = one - A - B, w[1] = A, w[2] = B;
    else
        w[0] = (one - A) * (one - B), w[1] = A * (one - B), w[2] = A * B, w[3] = (one - A) * B;
    for (int q = 0; q < 3; ++q) {
        ph[q] = zero;
        for (unsigned k = 0; k < nc; ++k) {
            v2d Nk = {Nv[k][q], Nv[k][q]};
            ph[q] += w[k] * Nk;
        }
    }
    v2d pp = dot2v(ph, ph);
    cross2v(c, nrm, ph);
    v2d y = sqrt2v(dot2v(c, c)), xd = dot2v(nrm, ph);
    for (int l = 0; l < nl; ++l) {
        if (len[l] > 0 && pp[l] > 0)
            max_angle_yx(M, y[l], xd[l]);
        else
            *flat_normal = true;
    }
    max_distance2(M, P, nl, tris, ntri);
}

/* The shape grid of a quartic triangle, its samples (i / N, j / N), i + j <= N, in the order of
 * sk__patch_shape's loops, taken two at a time (across rows too); the largest angle and distance
 * do not depend on the order of the samples. */
static void tri4_grid(const double *cp, unsigned N, const double *const Nv[4],
                      const flat_tri *tris, int ntri, shape_max *M, bool *flat_normal)
{
    unsigned total = (N + 1) * (N + 2) / 2, k = 0, i = 0, j = 0;
    v2d cpv[3 * 15]; /* the net in both lanes, once per patch */
    for (int q = 0; q < 3 * 15; ++q)
        cpv[q] = (v2d){cp[q], cp[q]};
    while (k < total) {
        double a2[2], b2[2];
        int nl = k + 1 < total ? 2 : 1;
        for (int l = 0; l < 2; ++l) {
            if (l < nl) {
                a2[l] = (double)i / N, b2[l] = (double)j / N;
                if (++j > N - i)
                    j = 0, ++i;
            } else {
                a2[l] = a2[0], b2[l] = b2[0];
            }
        }
        k += (unsigned)nl;
        v2d A = {a2[0], a2[1]}, B = {b2[0], b2[1]}, P[3], D1[3], D2[3];
        tri4_eval2v(cpv, A, B, P, D1, D2);
        grid_lanes(A, B, nl, P, D1, D2, Nv, 3, tris, ntri, M, flat_normal);
    }
}

/* The plain distance from p to the flat triangle (for the screen: no skips) */
static double tri_dist_plain(const double p[3], const flat_tri *T)
{
    double ap[3], t[3];
    sk__sub3(ap, p, T->a);
    if (T->nn > 0) {
        sk__cross3(t, ap, T->e2);
        double v = sk__dot3(t, T->n) / T->nn;
        if (v >= 0) {
            sk__cross3(t, T->e1, ap);
            double w = sk__dot3(t, T->n) / T->nn;
            if (w >= 0 && v + w <= 1)
                return fabs(sk__dot3(ap, T->n)) / T->len;
        }
    }
    const double *end[4] = {T->a, T->b, T->c, T->a};
    double d2 = INFINITY;
    for (int e = 0; e < 3; ++e)
        d2 = fmin(d2, seg_dist2(p, end[e], end[e + 1]));
    return sqrt(d2);
}

/* An upper bound of the distance from p to the flat triangle outside its prism: the distance to
 * the side p lies across (vv, ww: the barycentric coordinates v, w times |n|^2), the first that
 * tri_dist_within tries; the plain distance where the triangle is degenerate. */
static double tri_dist_ub(const double p[3], const flat_tri *T, double vv, double ww)
{
    if (!(T->nn > 0))
        return tri_dist_plain(p, T);
    const double *end[4] = {T->a, T->b, T->c, T->a};
    int e = !(vv >= 0) ? 2 : ww >= 0 ? 1 : 0;
    return sqrt(seg_dist2(p, end[e], end[e + 1]));
}

/* The shape grid of a quartic triangle, screened: every sample is first evaluated from the
 * context's Bernstein table (sums over the net instead of de Casteljau's steps, no rounding
 * guarantees beyond a bound), and only the samples whose screened angle or distance could reach
 * the largest found so far are evaluated in full (tri4_eval2v and grid_lanes: the same values to
 * the bit as sk_patch_eval), the screen's largest of each first. The reported figures are the
 * largest of the full values, so they are those of the full grid whenever the skipped samples'
 * full values are at most those: proven by these bounds, with C the largest coordinate of the net
 * and the flat triangle and u = 2^-53:
 *  - points: both the de Casteljau point and the table's are within about 20 u C of the exact
 *    value (convex combinations of the net, 4 steps or 15 terms, weights summing to 1 up to
 *    rounding), so the full distance (1-Lipschitz in the point, rounded relatively by a few u) is
 *    within dm = 1e-12 C of the screened one;
 *  - derivatives: both within about 200 u C of the exact (differences of the net times 4), taken
 *    as dD = 1e-12 C; with Dmax the largest length of the derivative net (a bound on both
 *    derivatives by the convex hull), the normals' cross products differ by at most E = 2 dD
 *    (Dmax + dD) + dD^2 + 1e-14 (Dmax + dD)^2, so the directions by at most 1.6 E / |N~| radians
 *    (asin(x) <= 1.6 x, x <= 1); with the roundings of the cross and dot products and atan2 well
 *    under 1e-13, a sample is skipped when the 2D cross product of its (x, y) with the largest
 *    angle's (xm, ym) shows it at least (1.6 E + 2e-13 |N~|) |ph| |(xm, ym)| clockwise of it.
 * A sample with a vanishing Phong normal, a NaN or no full angle yet is always evaluated in full.
 * The bounds are 10 to 50 times the rounding analysis; test_smooth_shape checks every patch of
 * three meshes against a plain full grid to the bit. */
/* The screen's pass over the samples, four at a time in the lanes of a vector (compiled also
 * for processors with FMA, chosen at run time: its values need only the bounds of tri4_screen,
 * not the bits of the full evaluation, which stays outside this function): per sample the
 * distance to the flat triangle T, the angle's (x, y) = (N~ . ph, |N~ x ph|) and whether the
 * Phong normal vanishes (pp0); returns the samples of the largest distance and angle. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define SCREEN_CLONES __attribute__((target_clones("fma", "default")))
#else
#define SCREEN_CLONES
#endif
typedef double v4d __attribute__((vector_size(32)));
typedef double v4du __attribute__((vector_size(32), aligned(8))); /* the table's rows */

SCREEN_CLONES
static void screen_pass(const double *tab, unsigned ns, const double *cp, const double *dv,
                        const double *dw, const double *const Nv[4], const flat_tri *T,
                        double *dist, double *ys, double *xs, bool *pp0, double *ta, double *tb,
                        unsigned *best)
{
    v4d cv[15][3], dvv[10][3], dwv[10][3], Nvv[3][3], zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
    for (int k = 0; k < 15; ++k)
        for (int q = 0; q < 3; ++q)
            cv[k][q] = zero + cp[3 * k + q];
    for (int k = 0; k < 10; ++k)
        for (int q = 0; q < 3; ++q)
            dvv[k][q] = zero + dv[3 * k + q], dwv[k][q] = zero + dw[3 * k + q];
    for (int k = 0; k < 3; ++k)
        for (int q = 0; q < 3; ++q)
            Nvv[k][q] = zero + Nv[k][q];
    v4d Ta[3], E1[3], E2[3], Tn[3];
    for (int q = 0; q < 3; ++q) {
        Ta[q] = zero + T->a[q];
        E1[q] = zero + T->e1[q];
        E2[q] = zero + T->e2[q];
        Tn[q] = zero + T->n[q];
    }
    double inv_len = T->len > 0 ? 1.0 / T->len : 0.0;
    unsigned best_d = 0, best_a = 0;
    for (unsigned i = 0; i < ns; i += 4) {
        const v4du *t = (const v4du *)(tab + (size_t)(i / 4) * 4 * SCREEN_ROWS);
        v4d P[3] = {zero, zero, zero}, D1[3] = {zero, zero, zero}, D2[3] = {zero, zero, zero};
        for (int k = 0; k < 15; ++k)
            for (int q = 0; q < 3; ++q)
                P[q] += t[k] * cv[k][q];
        for (int k = 0; k < 10; ++k)
            for (int q = 0; q < 3; ++q) {
                D1[q] += t[15 + k] * dvv[k][q];
                D2[q] += t[15 + k] * dwv[k][q];
            }
        v4d A = t[25], B = t[26], n[3], ph[3], c[3], ap[3], t1[3], t2[3];
        n[0] = D1[1] * D2[2] - D1[2] * D2[1];
        n[1] = D1[2] * D2[0] - D1[0] * D2[2];
        n[2] = D1[0] * D2[1] - D1[1] * D2[0];
        v4d w0 = one - A - B;
        for (int q = 0; q < 3; ++q)
            ph[q] = w0 * Nvv[0][q] + A * Nvv[1][q] + B * Nvv[2][q];
        v4d pp = ph[0] * ph[0] + ph[1] * ph[1] + ph[2] * ph[2];
        c[0] = n[1] * ph[2] - n[2] * ph[1];
        c[1] = n[2] * ph[0] - n[0] * ph[2];
        c[2] = n[0] * ph[1] - n[1] * ph[0];
        v4d y2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        v4d x = n[0] * ph[0] + n[1] * ph[1] + n[2] * ph[2];
        for (int q = 0; q < 3; ++q)
            ap[q] = P[q] - Ta[q];
        t1[0] = ap[1] * E2[2] - ap[2] * E2[1];
        t1[1] = ap[2] * E2[0] - ap[0] * E2[2];
        t1[2] = ap[0] * E2[1] - ap[1] * E2[0];
        t2[0] = E1[1] * ap[2] - E1[2] * ap[1];
        t2[1] = E1[2] * ap[0] - E1[0] * ap[2];
        t2[2] = E1[0] * ap[1] - E1[1] * ap[0];
        v4d vv = t1[0] * Tn[0] + t1[1] * Tn[1] + t1[2] * Tn[2];
        v4d ww = t2[0] * Tn[0] + t2[1] * Tn[1] + t2[2] * Tn[2];
        v4d h = (ap[0] * Tn[0] + ap[1] * Tn[1] + ap[2] * Tn[2]) * inv_len;
        for (int l = 0; l < 4 && i + (unsigned)l < ns; ++l) {
            unsigned k = i + (unsigned)l;
            ta[k] = A[l], tb[k] = B[l], ys[k] = sqrt(y2[l]), xs[k] = x[l];
            pp0[k] = !(pp[l] > 0);
            if (T->nn > 0 && vv[l] >= 0 && ww[l] >= 0 && vv[l] + ww[l] <= T->nn) {
                dist[k] = fabs(h[l]);
            } else {
                double px[3] = {P[0][l], P[1][l], P[2][l]};
                dist[k] = tri_dist_ub(px, T, vv[l], ww[l]);
            }
            if (dist[k] > dist[best_d])
                best_d = k;
            if (ys[k] * xs[best_a] - xs[k] * ys[best_a] > 0)
                best_a = k;
        }
    }
    best[0] = best_d, best[1] = best_a;
}

/* The shape grid of a quartic triangle, screened: every sample is first evaluated from the
 * context's Bernstein table (sums over the net instead of de Casteljau's steps, within a bound of
 * the exact values), and only the samples whose screened angle or distance could reach the
 * largest found so far are evaluated in full (tri4_eval2v and grid_lanes: the same values to the
 * bit as sk_patch_eval), the screen's largest of each first. The reported figures are the largest
 * of the full values, so they are those of the full grid when the skipped samples' full values
 * are at most those: proven by these bounds, with C the largest coordinate of the net and the
 * flat triangle and u = 2^-53:
 *  - points: both the de Casteljau point and the table's (with or without fused multiply-adds)
 *    are within about 20 u C of the exact value (convex combinations of the net: 4 steps or 15
 *    terms, weights summing to 1 up to rounding), so the full distance (1-Lipschitz in the point,
 *    rounded relatively by a few u) is within dm = 1e-12 C of the screened one;
 *  - derivatives: both within about 200 u C of the exact (differences of the net times 4), taken
 *    as dD = 1e-12 C; with Dmax a bound on both derivatives' lengths (the longest of the
 *    derivative net, by the convex hull, plus dD), the normals' cross products differ by at most
 *    E = 2 dD Dmax + dD^2 + 1e-14 Dmax^2, so their directions by at most 1.6 E / |N~| radians
 *    (asin(x) <= 1.6 x for x <= 1); with the roundings of the cross and dot products and of
 *    atan2 (under 2e-13 of the angle's scale), a sample is skipped when the 2D cross product of
 *    its (x, y) with the largest full angle's (xm, ym) shows it clockwise by more than
 *    (1.6 E + 2e-13 |N~|) |ph| |(xm, ym)|, bounded by LIM |(xm, ym)| with LIM = (1.6 E + 2e-13
 *    Dmax^2) (1 + 1e-12) max |N_k| (the Phong normal being a convex combination of the N_k).
 * A sample with a vanishing Phong normal, a NaN or no full angle yet is always evaluated in full.
 * The bounds are 10 to 50 times the rounding analysis; test_smooth_shape checks every patch of
 * three meshes against a plain full grid to the bit. */
static void tri4_screen(const sk__shape_ctx *ctx, const double *cp, const double *const Nv[4],
                        const double *const X[4], const flat_tri *tris, shape_max *M,
                        bool *flat_normal)
{
    const unsigned ns = ctx->tab_ns;
    double C = 0.0, dv[10][3], dw[10][3], D2max = 0.0, Nmax = 0.0;
    for (int q = 0; q < 45; ++q)
        C = fmax(C, fabs(cp[q]));
    for (int i = 0; i < 3; ++i) {
        for (int q = 0; q < 3; ++q)
            C = fmax(C, fabs(X[i][q]));
        Nmax = fmax(Nmax, sk__norm3(Nv[i]));
    }
    for (unsigned k = 0; k <= 3; ++k)
        for (unsigned j = 0; j + k <= 3; ++j) {
            unsigned o = sk_tri_index(3, j, k);
            const double *b0 = cp + 3 * sk_tri_index(4, j, k);
            const double *bv = cp + 3 * sk_tri_index(4, j + 1, k);
            const double *bw = cp + 3 * sk_tri_index(4, j, k + 1);
            for (int q = 0; q < 3; ++q) {
                dv[o][q] = 4.0 * (bv[q] - b0[q]);
                dw[o][q] = 4.0 * (bw[q] - b0[q]);
            }
            D2max = fmax(D2max, fmax(sk__dot3(dv[o], dv[o]), sk__dot3(dw[o], dw[o])));
        }
    double dm = 1e-12 * C, dD = 1e-12 * C, Dmax = sqrt(D2max) * (1.0 + 1e-12) + dD;
    double E = 2.0 * dD * Dmax + dD * dD + 1e-14 * Dmax * Dmax;
    double LIM = (1.6 * E + 2e-13 * Dmax * Dmax) * (1.0 + 1e-12) * Nmax;
    double dist[SCREEN_MAX_NS], ys[SCREEN_MAX_NS], xs[SCREEN_MAX_NS], ta[SCREEN_MAX_NS],
        tb[SCREEN_MAX_NS];
    bool pp0[SCREEN_MAX_NS];
    unsigned best[2];
    screen_pass(ctx->tab, ns, cp, dv[0], dw[0], Nv, tris, dist, ys, xs, pp0, ta, tb, best);
    /* full evaluations: the screen's largest first, then every sample the screen cannot skip,
     * two at a time */
    v2d cpv[3 * 15];
    for (int q = 0; q < 3 * 15; ++q)
        cpv[q] = (v2d){cp[q], cp[q]};
    unsigned pend[2], np = 0;
    pend[np++] = best[0];
    if (best[1] != best[0])
        pend[np++] = best[1];
    for (unsigned i = 0;; ++i) {
        if (np == 2 || (i == ns && np > 0)) {
            int nl = (int)np;
            v2d A = {ta[pend[0]], ta[pend[nl - 1]]}, B = {tb[pend[0]], tb[pend[nl - 1]]};
            v2d Pf[3], F1[3], F2[3];
            tri4_eval2v(cpv, A, B, Pf, F1, F2);
            grid_lanes(A, B, nl, Pf, F1, F2, Nv, 3, tris, 1, M, flat_normal);
            np = 0;
        }
        if (i == ns)
            break;
        if (i == best[0] || i == best[1])
            continue;
        bool skip_d = dist[i] + dm <= M->dmax;
        double vm = sqrt(M->xm * M->xm + M->ym * M->ym);
        bool skip_a = M->any_angle && !pp0[i] && -(ys[i] * M->xm - xs[i] * M->ym) > LIM * vm;
        if (!(skip_d && skip_a))
            pend[np++] = i;
    }
}

/* The shape grid of a bicubic patch, row a = i / N at a time (its net summed in s once, by
 * row_eval_start), two samples of the row at once: the sums of row_eval2 in the lanes. */
static void bicubic_grid(const sk_patch_set *set, size_t p, unsigned N, const double *const Nv[4],
                         const flat_tri *tris, int ntri, shape_max *M, bool *flat_normal)
{
    for (unsigned i = 0; i <= N; ++i) {
        row_eval R;
        row_eval_start(&R, set, p, (double)i / N);
        for (unsigned j = 0; j <= N; j += 2) {
            int nl = j + 1 <= N ? 2 : 1;
            double b2[2] = {(double)j / N, (double)(nl == 2 ? j + 1 : j) / N};
            double Bt[2][4], dBt[2][4];
            for (int l = 0; l < 2; ++l)
                sk__bernstein_n(3, b2[l], Bt[l], dBt[l]);
            v2d zero = {0.0, 0.0}, A = {R.a, R.a}, B = {b2[0], b2[1]};
            v2d P[3] = {zero, zero, zero}, S[3] = {zero, zero, zero}, T[3] = {zero, zero, zero};
            for (unsigned q = 0; q <= 3; ++q) {
                v2d Bq = {Bt[0][q], Bt[1][q]}, dBq = {dBt[0][q], dBt[1][q]};
                for (int x = 0; x < 3; ++x) {
                    v2d r = {R.r[q][x], R.r[q][x]}, dr = {R.dr[q][x], R.dr[q][x]};
                    P[x] += Bq * r;
                    S[x] += Bq * dr;
                    T[x] += dBq * r;
                }
            }
            grid_lanes(A, B, nl, P, S, T, Nv, 4, tris, ntri, M, flat_normal);
        }
    }
}

/* The screen of a bicubic patch (bicubic_screen): per sample (i / N, j / N), in the order of
 * the rows, the distance bound (the least plane distance over the flat triangles whose prism holds
 * the point, else the least of tri_dist_ub over them), the angle's (x, y) and the vanishing Phong normal,
 * four samples of a row at a time; the rows' sums r, dr and the columns' Bernstein values given.
 * Returns the samples of the largest distance bound and angle. */
#define BIC_MAX_N 32
SCREEN_CLONES
static void bicubic_screen_pass(unsigned N, const double (*r)[4][3], const double (*dr)[4][3],
                                const double (*Bt)[4], const double (*dBt)[4],
                                const double *const Nv[4], const flat_tri *tris, int ntri,
                                double *dist, double *ys, double *xs, bool *pp0, unsigned *best)
{
    v4d zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
    unsigned nj = (N + 4) / 4 * 4, best_d = 0, best_a = 0, k = 0;
    for (unsigned i = 0; i <= N; ++i) {
        v4d A = zero + (double)i / N;
        for (unsigned j = 0; j < nj; j += 4) {
            v4d B, P[3] = {zero, zero, zero}, S[3] = {zero, zero, zero}, T[3] = {zero, zero, zero};
            unsigned jl[4];
            for (int l = 0; l < 4; ++l)
                jl[l] = j + (unsigned)l <= N ? j + (unsigned)l : N;
            for (int l = 0; l < 4; ++l)
                B[l] = (double)jl[l] / N;
            for (unsigned q = 0; q <= 3; ++q) {
                v4d Bq = {Bt[jl[0]][q], Bt[jl[1]][q], Bt[jl[2]][q], Bt[jl[3]][q]};
                v4d dBq = {dBt[jl[0]][q], dBt[jl[1]][q], dBt[jl[2]][q], dBt[jl[3]][q]};
                for (int x = 0; x < 3; ++x) {
                    P[x] += Bq * r[i][q][x];
                    S[x] += Bq * dr[i][q][x];
                    T[x] += dBq * r[i][q][x];
                }
            }
            v4d n[3], ph[3], c[3], w[4];
            n[0] = S[1] * T[2] - S[2] * T[1];
            n[1] = S[2] * T[0] - S[0] * T[2];
            n[2] = S[0] * T[1] - S[1] * T[0];
            w[0] = (one - A) * (one - B), w[1] = A * (one - B), w[2] = A * B, w[3] = (one - A) * B;
            for (int q = 0; q < 3; ++q)
                ph[q] = w[0] * Nv[0][q] + w[1] * Nv[1][q] + w[2] * Nv[2][q] + w[3] * Nv[3][q];
            v4d pp = ph[0] * ph[0] + ph[1] * ph[1] + ph[2] * ph[2];
            c[0] = n[1] * ph[2] - n[2] * ph[1];
            c[1] = n[2] * ph[0] - n[0] * ph[2];
            c[2] = n[0] * ph[1] - n[1] * ph[0];
            v4d y2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
            v4d x = n[0] * ph[0] + n[1] * ph[1] + n[2] * ph[2];
            v4d ub = zero + INFINITY, vt[4], wt[4];
            for (int t = 0; t < ntri; ++t) {
                const flat_tri *F = tris + t;
                v4d ap[3], t1[3], t2[3];
                for (int q = 0; q < 3; ++q)
                    ap[q] = P[q] - F->a[q];
                t1[0] = ap[1] * F->e2[2] - ap[2] * F->e2[1];
                t1[1] = ap[2] * F->e2[0] - ap[0] * F->e2[2];
                t1[2] = ap[0] * F->e2[1] - ap[1] * F->e2[0];
                t2[0] = F->e1[1] * ap[2] - F->e1[2] * ap[1];
                t2[1] = F->e1[2] * ap[0] - F->e1[0] * ap[2];
                t2[2] = F->e1[0] * ap[1] - F->e1[1] * ap[0];
                v4d vv = t1[0] * F->n[0] + t1[1] * F->n[1] + t1[2] * F->n[2];
                v4d ww = t2[0] * F->n[0] + t2[1] * F->n[1] + t2[2] * F->n[2];
                v4d h = (ap[0] * F->n[0] + ap[1] * F->n[1] + ap[2] * F->n[2]) *
                        (F->len > 0 ? 1.0 / F->len : 0.0);
                for (int l = 0; l < 4; ++l)
                    if (F->nn > 0 && vv[l] >= 0 && ww[l] >= 0 && vv[l] + ww[l] <= F->nn)
                        ub[l] = fmin(ub[l], fabs(h[l]));
                vt[t] = vv, wt[t] = ww;
            }
            for (int l = 0; l < 4 && j + (unsigned)l <= N; ++l, ++k) {
                ys[k] = sqrt(y2[l]), xs[k] = x[l];
                pp0[k] = !(pp[l] > 0);
                dist[k] = ub[l];
                if (!(ub[l] < INFINITY)) {
                    double px[3] = {P[0][l], P[1][l], P[2][l]}, d = INFINITY;
                    for (int t = 0; t < ntri; ++t)
                        d = fmin(d, tri_dist_ub(px, tris + t, vt[t][l], wt[t][l]));
                    dist[k] = d;
                }
                if (dist[k] > dist[best_d])
                    best_d = k;
                if (ys[k] * xs[best_a] - xs[k] * ys[best_a] > 0)
                    best_a = k;
            }
        }
    }
    best[0] = best_d, best[1] = best_a;
}

/* The shape grid of a bicubic patch, screened as tri4_screen's (the same bounds, with the
 * derivatives' bound 3 times the longest difference of the net along s or t and Nmax over the
 * four corners: the bilinear Phong weights are convex); the full evaluations are bicubic_grid's
 * sums in the lanes, each lane its sample's row. */
static void bicubic_screen(const sk_patch_set *set, size_t p, unsigned N,
                           const double *const Nv[4], const double *const X[4],
                           const flat_tri *tris, int ntri, shape_max *M, bool *flat_normal)
{
    const double *cp = sk_patch_cp(set, p);
    double C = 0.0, D2max = 0.0, Nmax = 0.0;
    for (int q = 0; q < 48; ++q)
        C = fmax(C, fabs(cp[q]));
    for (int i = 0; i < 4; ++i) {
        for (int q = 0; q < 3; ++q)
            C = fmax(C, fabs(X[i][q]));
        Nmax = fmax(Nmax, sk__norm3(Nv[i]));
    }
    for (unsigned j = 0; j <= 3; ++j)
        for (unsigned i = 0; i <= 3; ++i) {
            const double *b = cp + 3 * sk_tensor_index(3, i, j);
            double d[3];
            if (i < 3) {
                sk__sub3(d, cp + 3 * sk_tensor_index(3, i + 1, j), b);
                D2max = fmax(D2max, 9.0 * sk__dot3(d, d));
            }
            if (j < 3) {
                sk__sub3(d, cp + 3 * sk_tensor_index(3, i, j + 1), b);
                D2max = fmax(D2max, 9.0 * sk__dot3(d, d));
            }
        }
    double dm = 1e-12 * C, dD = 1e-12 * C, Dmax = sqrt(D2max) * (1.0 + 1e-12) + dD;
    double E = 2.0 * dD * Dmax + dD * dD + 1e-14 * Dmax * Dmax;
    double LIM = (1.6 * E + 2e-13 * Dmax * Dmax) * (1.0 + 1e-12) * Nmax;
    double r[BIC_MAX_N + 1][4][3], dr[BIC_MAX_N + 1][4][3], Bt[BIC_MAX_N + 1][4],
        dBt[BIC_MAX_N + 1][4];
    for (unsigned i = 0; i <= N; ++i) {
        row_eval R;
        row_eval_start(&R, set, p, (double)i / N);
        memcpy(r[i], R.r, sizeof R.r);
        memcpy(dr[i], R.dr, sizeof R.dr);
        sk__bernstein_n(3, (double)i / N, Bt[i], dBt[i]);
    }
    enum { NS = (BIC_MAX_N + 1) * (BIC_MAX_N + 1) };
    double dist[NS], ys[NS], xs[NS];
    bool pp0[NS];
    unsigned best[2], ns = (N + 1) * (N + 1);
    bicubic_screen_pass(N, (const double (*)[4][3])r, (const double (*)[4][3])dr,
                        (const double (*)[4])Bt, (const double (*)[4])dBt, Nv, tris, ntri, dist,
                        ys, xs, pp0, best);
    unsigned pend[2], np = 0;
    pend[np++] = best[0];
    if (best[1] != best[0])
        pend[np++] = best[1];
    for (unsigned k = 0;; ++k) {
        if (np == 2 || (k == ns && np > 0)) {
            int nl = (int)np;
            v2d zero = {0.0, 0.0}, A, B;
            v2d P[3] = {zero, zero, zero}, S[3] = {zero, zero, zero}, T[3] = {zero, zero, zero};
            unsigned il[2], jl[2];
            for (int l = 0; l < 2; ++l) {
                unsigned q = pend[l < nl ? l : 0];
                il[l] = q / (N + 1), jl[l] = q % (N + 1);
                A[l] = (double)il[l] / N, B[l] = (double)jl[l] / N;
            }
            for (unsigned q = 0; q <= 3; ++q) { /* bicubic_grid's sums, lane by lane */
                v2d Bq = {Bt[jl[0]][q], Bt[jl[1]][q]}, dBq = {dBt[jl[0]][q], dBt[jl[1]][q]};
                for (int x = 0; x < 3; ++x) {
                    v2d rr = {r[il[0]][q][x], r[il[1]][q][x]};
                    v2d dd = {dr[il[0]][q][x], dr[il[1]][q][x]};
                    P[x] += Bq * rr;
                    S[x] += Bq * dd;
                    T[x] += dBq * rr;
                }
            }
            grid_lanes(A, B, nl, P, S, T, Nv, 4, tris, ntri, M, flat_normal);
            np = 0;
        }
        if (k == ns)
            break;
        if (k == best[0] || k == best[1])
            continue;
        bool skip_d = dist[k] + dm <= M->dmax;
        double vm = sqrt(M->xm * M->xm + M->ym * M->ym);
        bool skip_a = M->any_angle && !pp0[k] && -(ys[k] * M->xm - xs[k] * M->ym) > LIM * vm;
        if (!(skip_d && skip_a))
            pend[np++] = k;
    }
}

/* samples (a, b[0]) and, when two, (a, b[1]) of the row: point, unit normal, |du x dv| */
static void row_eval2(const row_eval *R, const double b[2], int two, double x[2][3],
                      double nrm[2][3], double len[2])
{
    for (int l = 0; l < 1 + two; ++l) {
        if (R->mode == 0) {
            len[l] = sk_patch_eval(R->set, R->p, R->a, b[l], x[l], NULL, NULL, nrm[l]);
            continue;
        }
        double Bt[4], dBt[4], P[3] = {0, 0, 0}, S[3] = {0, 0, 0}, T[3] = {0, 0, 0};
        sk__bernstein_n(3, b[l], Bt, dBt);
        for (unsigned j = 0; j <= 3; ++j)
            for (int q = 0; q < 3; ++q) {
                P[q] += Bt[j] * R->r[j][q];
                S[q] += Bt[j] * R->dr[j][q];
                T[q] += dBt[j] * R->r[j][q];
            }
        memcpy(x[l], P, sizeof P);
        len[l] = finish(S, T, nrm[l]);
    }
}

void sk__patch_shape(const sk__shape_ctx *c, size_t p, double *overshoot, double *fairness_deg)
{
    const sk_smooth *s = c->s;
    const sk_patch *pa = &s->surface.patches[p];
    unsigned nc = sk_patch_num_corners(pa), N = c->n;
    const double *X[4], *Nv[4];
    for (unsigned i = 0; i < nc; ++i) {
        X[i] = s->config->positions + 3 * (size_t)pa->corner_ids[i];
        Nv[i] = sk__corner_normal(s, p, i); /* its sector's normal at a crease */
    }
    /* the flat triangles the patch replaces, as corner triples */
    int tri[4][3] = {{0, 1, 2}}, ntri = 1;
    double longest = 0.0;
    for (unsigned i = 0; i < nc; ++i)
        longest = fmax(longest, sk__dist3(X[i], X[(i + 1) % nc]));
    if (nc == 4) {
        bool d02 = is_deleted(c, pa->corner_ids[0], pa->corner_ids[2]);
        bool d13 = is_deleted(c, pa->corner_ids[1], pa->corner_ids[3]);
        static const int split02[2][3] = {{0, 1, 2}, {0, 2, 3}}, split13[2][3] = {{0, 1, 3}, {1, 2, 3}};
        ntri = 0;
        if (d02 || !d13) { /* unknown diagonal: both splits (the nearer one counts) */
            memcpy(tri[ntri], split02, sizeof split02);
            ntri += 2;
            longest = fmax(longest, sk__dist3(X[0], X[2]));
        }
        if (d13 || !d02) {
            memcpy(tri[ntri], split13, sizeof split13);
            ntri += 2;
            longest = fmax(longest, sk__dist3(X[1], X[3]));
        }
    }
    flat_tri tris[4];
    for (int t = 0; t < ntri; ++t)
        flat_tri_init(tris + t, X[tri[t][0]], X[tri[t][1]], X[tri[t][2]]);
    shape_max M = {0};
    bool flat_normal = false; /* 180: a vanishing normal somewhere */
    bool tri4 = pa->kind == SK_PATCH_TRIANGLE && pa->degree == 4;
    bool bicubic = pa->kind != SK_PATCH_TRIANGLE && pa->degree == 3 && pa->degree_v == 3;
    if (tri4 && c->tab)
        tri4_screen(c, sk_patch_cp(&s->surface, p), Nv, X, tris, &M, &flat_normal);
    else if (tri4)
        tri4_grid(sk_patch_cp(&s->surface, p), N, Nv, tris, ntri, &M, &flat_normal);
    else if (bicubic && N <= BIC_MAX_N)
        bicubic_screen(&s->surface, p, N, Nv, X, tris, ntri, &M, &flat_normal);
    else if (bicubic)
        bicubic_grid(&s->surface, p, N, Nv, tris, ntri, &M, &flat_normal);
    for (unsigned i = 0; !tri4 && !bicubic && i <= N; ++i) {
        double a = (double)i / N, b2[2], x2[2][3], nrm2[2][3], len2[2];
        unsigned nj = pa->kind == SK_PATCH_TRIANGLE ? N - i + 1 : N + 1;
        row_eval R;
        row_eval_start(&R, &s->surface, p, a);
        for (unsigned j = 0; j < nj; ++j) {
            if (j % 2 == 0) {
                int two = j + 1 < nj;
                b2[0] = (double)j / N;
                b2[1] = two ? (double)(j + 1) / N : b2[0];
                row_eval2(&R, b2, two, x2, nrm2, len2);
            }
            double b = b2[j % 2], *x = x2[j % 2], *nrm = nrm2[j % 2], len = len2[j % 2], w[4];
            if (pa->kind == SK_PATCH_TRIANGLE)
                w[0] = 1.0 - a - b, w[1] = a, w[2] = b;
            else
                w[0] = (1 - a) * (1 - b), w[1] = a * (1 - b), w[2] = a * b, w[3] = (1 - a) * b;
            double phong[3] = {0, 0, 0};
            for (unsigned k = 0; k < nc; ++k)
                for (int q = 0; q < 3; ++q)
                    phong[q] += w[k] * Nv[k][q];
            if (len > 0 && sk__dot3(phong, phong) > 0) /* |phong| > 0 without the root */
                max_angle(&M, nrm, phong);
            else
                flat_normal = true;
            max_distance(&M, x, tris, ntri);
        }
    }
    double dmax = M.dmax, amax = fmax(M.amax, flat_normal ? 180.0 : 0.0);
    *overshoot = longest > 0 ? dmax / longest : (dmax > 0 ? INFINITY : 0.0);
    *fairness_deg = amax;
}

sk_status sk_smooth_patch_shapes(const sk_smooth *s, unsigned samples, sk_patch_shape *out,
                                 sk_error *err)
{
    if (!s || (!out && s->surface.count))
        return sk__fail(err, SK_ERR_ARG, "sk_smooth_patch_shapes: NULL argument");
    sk__shape_ctx c;
    sk_status st = sk__shape_ctx_init(&c, s, samples, err);
    if (st)
        return st;
    long np = (long)s->surface.count;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 256)
#endif
    for (long p = 0; p < np; ++p) {
        sk__patch_shape(&c, (size_t)p, &out[p].overshoot, &out[p].fairness_deg);
        out[p].singular = sk__patch_singular(s, (size_t)p, NULL);
    }
    sk__shape_ctx_free(&c);
    sk__ok(err);
    return SK_OK;
}
