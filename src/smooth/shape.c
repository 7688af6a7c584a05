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
 *    length) on a densely sampled smooth shape such as the sphere. */
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

sk_status sk__shape_ctx_init(sk__shape_ctx *c, const sk_smooth *s, unsigned samples,
                             sk_error *err)
{
    memset(c, 0, sizeof *c);
    c->s = s;
    c->n = samples ? samples : 12;
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

/* distance from p to the triangle (a segment or a point when it is degenerate) */
static double tri_dist(const double p[3], const flat_tri *T)
{
    double ap[3], t[3];
    sk__sub3(ap, p, T->a);
    if (T->nn > 0) {
        sk__cross3(t, ap, T->e2);
        double v = sk__dot3(t, T->n) / T->nn;
        sk__cross3(t, T->e1, ap);
        double w = sk__dot3(t, T->n) / T->nn;
        if (v >= 0 && w >= 0 && v + w <= 1)
            return fabs(sk__dot3(ap, T->n)) / T->len;
    }
    return sqrt(fmin(seg_dist2(p, T->a, T->b),
                     fmin(seg_dist2(p, T->b, T->c), seg_dist2(p, T->c, T->a))));
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

static void max_angle(shape_max *M, const double nrm[3], const double phong[3])
{
    double c[3];
    sk__cross3(c, nrm, phong);
    double y = sk__norm3(c), x = sk__dot3(nrm, phong);
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

static void max_distance(shape_max *M, const double x[3], const flat_tri *tris, int ntri)
{
    double d = INFINITY;
    for (int t = 0; t < ntri; ++t) {
        d = fmin(d, tri_dist(x, tris + t));
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
    int mode; /* 0: sk_patch_eval, 1: quartic triangle, 2: bicubic */
    double a, r[4][3], dr[4][3];
} row_eval;

static void row_eval_start(row_eval *R, const sk_patch_set *set, size_t p, double a)
{
    const sk_patch *pa = &set->patches[p];
    R->set = set, R->p = p, R->a = a, R->cp = sk_patch_cp(set, p);
    R->mode = 0;
    if (pa->kind == SK_PATCH_TRIANGLE && pa->degree == 4)
        R->mode = 1;
    else if (pa->kind != SK_PATCH_TRIANGLE && pa->degree == 3 && pa->degree_v == 3)
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

/* de Casteljau of the quartic triangle at (v, w[0]) and (v, w[1]) (tri_eval_n of eval.c) */
static void tri4_eval2(const double *cp, double v, const double w[2], double pt[2][3],
                       double d1[2][3], double d2[2][3])
{
    const unsigned n = 4;
    v2d U = {1.0 - v - w[0], 1.0 - v - w[1]}, V = {v, v}, W = {w[0], w[1]};
    v2d net[3 * 10], tmp[3 * 10];
    for (unsigned k = 0; k < n; ++k) { /* degree 4 -> 3 from the control points */
        unsigned row = sk_tri_index(n, 0, k), up = sk_tri_index(n, 0, k + 1);
        unsigned orow = sk_tri_index(n - 1, 0, k);
        for (unsigned j = 0; j + k < n; ++j) {
            const double *a = cp + 3 * (row + j), *b = a + 3, *c = cp + 3 * (up + j);
            v2d *o = net + 3 * (orow + j);
            for (int x = 0; x < 3; ++x) {
                v2d A = {a[x], a[x]}, B = {b[x], b[x]}, C = {c[x], c[x]};
                o[x] = U * A + V * B + W * C;
            }
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
        v2d P = U * b100[x] + V * b010[x] + W * b001[x];
        v2d E1 = N * (b010[x] - b100[x]), E2 = N * (b001[x] - b100[x]);
        for (int l = 0; l < 2; ++l)
            pt[l][x] = P[l], d1[l][x] = E1[l], d2[l][x] = E2[l];
    }
}

/* samples (a, b[0]) and, when two, (a, b[1]) of the row: point, unit normal, |du x dv| */
static void row_eval2(const row_eval *R, const double b[2], int two, double x[2][3],
                      double nrm[2][3], double len[2])
{
    if (R->mode == 1) {
        double D1[2][3], D2[2][3];
        tri4_eval2(R->cp, R->a, b, x, D1, D2);
        for (int l = 0; l < 1 + two; ++l)
            len[l] = finish(D1[l], D2[l], nrm[l]);
        return;
    }
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
    for (unsigned i = 0; i <= N; ++i) {
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
