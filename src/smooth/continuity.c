/* Continuity report of a patch network: gaps and normal jumps sampled densely along every interior
 * edge, interpolation errors at the vertices, and the regularity of every patch (normal-cone test of
 * Ginkel, Peters, Umlauf, then sampling). Tolerances: Albat & Mueller's industrial values, G1 within
 * 0.5 degrees and gaps under 0.005 mm. */
#include "smooth/smooth_internal.h"
#include "surfkit/intersect.h"
#include "analysis/intersect_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int side_of(const sk_mesh *m, uint32_t f, uint32_t h)
{
    uint32_t g = m->f_halfedge[f];
    int i = 0;
    while (g != h) {
        g = m->h_next[g];
        ++i;
    }
    return i;
}

static void corner_param(int kind, unsigned i, double *u, double *v)
{
    static const double tu[4] = {0, 1, 1, 0}, tv[4] = {0, 0, 1, 1};
    if (kind == SK_PATCH_TRIANGLE) {
        *u = i == 1 ? 1.0 : 0.0;
        *v = i == 2 ? 1.0 : 0.0;
    } else {
        *u = tu[i];
        *v = tv[i];
    }
}

#define RAD2DEG (180.0 / M_PI)

/* Work is split into fixed blocks whose partial results are combined in block order, so the report
 * is the same for any number of threads: BLOCK edges (their sums depend on the blocks), PBLOCK
 * patches (maxima and counts only: any blocks give the same, small ones balance the threads). */
#define BLOCK 4096
#define PBLOCK 256

typedef struct edge_block {
    double max_gap, sum_gap, max_jump, sum_jump;
    long worst;
    size_t nint, nsamp;
    size_t ncrease;
    double max_crease_gap, max_crease_jump, min_crease_jump;
} edge_block;

typedef struct patch_block {
    double max_verr, max_nerr;
    size_t uncert;
} patch_block;

/* The data of one side of a patch that the samples along it need: the boundary row of control
 * points (degree n, from the side's first corner to its second) and the next row inwards (triangle:
 * n points, b_{.,.,1} of the net relabelled so that the side is side 0; quad: 4 points). A cyclic
 * relabelling of the corners keeps their counter-clockwise order, so du x dv of the relabelled
 * patch has the direction of the original normal. */
typedef struct side_rows {
    int kind, n;
    double row0[5][3], row1[5][3];
} side_rows;

/* the net indices of side_rows_of for the three sides of a quartic triangle, made once per
 * block of edges by its own index arithmetic (tri_side_index_init) */
typedef struct tri_side_index {
    unsigned row0[3][5], row1[3][4];
} tri_side_index;

static void tri_rows_index(int n, int side, unsigned *i0, unsigned *i1)
{
    for (int t = 0; t <= n; ++t) {
        /* barycentric multi-index (i, j, k) of the boundary point t and of the inner point */
        int I0[3], I1[3];
        I0[0] = n - t, I0[1] = t, I0[2] = 0;       /* relabelled: side 0 from corner 0 to 1 */
        I1[0] = n - 1 - t, I1[1] = t, I1[2] = 1;   /* next row toward corner 2 */
        /* relabelled corner c is the original corner (c + side) mod 3 */
        int J0[3], J1[3];
        for (int c = 0; c < 3; ++c) {
            J0[(c + side) % 3] = I0[c];
            J1[(c + side) % 3] = I1[c];
        }
        i0[t] = sk_tri_index((unsigned)n, (unsigned)J0[1], (unsigned)J0[2]);
        if (t < n)
            i1[t] = sk_tri_index((unsigned)n, (unsigned)J1[1], (unsigned)J1[2]);
    }
}

static void tri_side_index_init(tri_side_index *x)
{
    for (int side = 0; side < 3; ++side)
        tri_rows_index(4, side, x->row0[side], x->row1[side]);
}

static void side_rows_of(const sk_smooth *s, const tri_side_index *x4, uint32_t f, int side,
                         side_rows *r)
{
    const sk_patch *pa = &s->surface.patches[f];
    const double *b = sk_patch_cp(&s->surface, f);
    r->kind = pa->kind;
    if (pa->kind == SK_PATCH_TRIANGLE) {
        int n = pa->degree;
        unsigned i0[SK_PATCH_MAX_DEGREE + 1], i1[SK_PATCH_MAX_DEGREE + 1];
        const unsigned *row0 = i0, *row1 = i1;
        if (n == 4)
            row0 = x4->row0[side], row1 = x4->row1[side];
        else
            tri_rows_index(n, side, i0, i1);
        r->n = n;
        for (int t = 0; t <= n; ++t) {
            memcpy(r->row0[t], b + 3 * row0[t], 3 * sizeof(double));
            if (t < n)
                memcpy(r->row1[t], b + 3 * row1[t], 3 * sizeof(double));
        }
    } else {
        r->n = 3;
        for (int t = 0; t <= 3; ++t) {
            unsigned i0, j0, i1, j1; /* (i, j) of the net on the side and one row inwards */
            unsigned u = (unsigned)t;
            switch (side) {
            case 0: i0 = u, j0 = 0, i1 = u, j1 = 1; break;
            case 1: i0 = 3, j0 = u, i1 = 2, j1 = u; break;
            case 2: i0 = 3 - u, j0 = 3, i1 = 3 - u, j1 = 2; break;
            default: i0 = 0, j0 = 3 - u, i1 = 1, j1 = 3 - u; break;
            }
            memcpy(r->row0[t], b + 3 * sk_tensor_index(3, i0, j0), 3 * sizeof(double));
            memcpy(r->row1[t], b + 3 * sk_tensor_index(3, i1, j1), 3 * sizeof(double));
        }
    }
}

/* The differences of the rows that the tangents along and across the side sum (row0[j + 1] -
 * row0[j], row1[j] - row0[j]): constants of the side, formed once per side instead of once per
 * sample (the same subtractions, so the same tangents to the bit). */
typedef struct side_diffs {
    double along[5][3], across[5][3];
} side_diffs;

static void side_diffs_of(const side_rows *r, side_diffs *d)
{
    int n = r->n, nx = r->kind == SK_PATCH_TRIANGLE ? n : n + 1;
    for (int j = 0; j < n; ++j)
        for (int c = 0; c < 3; ++c)
            d->along[j][c] = r->row0[j + 1][c] - r->row0[j][c];
    for (int j = 0; j < nx; ++j)
        for (int c = 0; c < 3; ++c)
            d->across[j][c] = r->row1[j][c] - r->row0[j][c];
}

/* Bernstein values of degrees n and n - 1 at the K + 1 samples t_i = i / K of an edge and at
 * 1 - t_i (the other side runs the edge backwards), for n = 3 and 4 (the degrees of VC1's sides),
 * made once per block of edges by the same sk__bernstein_n calls as per sample before. */
#define TAB_MAX_K 64
typedef struct bern_tab {
    unsigned K;
    double B[2][2][TAB_MAX_K + 1][5], B1[2][2][TAB_MAX_K + 1][5]; /* [n - 3][reversed][i][j] */
} bern_tab;

static void bern_tab_init(bern_tab *tb, unsigned K)
{
    tb->K = K;
    if (K > TAB_MAX_K)
        return;
    for (unsigned n = 3; n <= 4; ++n)
        for (unsigned i = 0; i <= K; ++i) {
            double t = (double)i / K, ts[2] = {t, 1.0 - t};
            for (int rev = 0; rev < 2; ++rev) {
                sk__bernstein_n(n, ts[rev], tb->B[n - 3][rev][i], NULL);
                sk__bernstein_n(n - 1, ts[rev], tb->B1[n - 3][rev][i], NULL);
            }
        }
}

/* position and unit normal (zero where du x dv vanishes) on the side with Bernstein values B
 * (degree n) and B1 (degree n - 1); inlined with the constant degrees of VC1 (quartic triangles,
 * bicubic quads: same results) */
static inline __attribute__((always_inline)) void side_eval_b(const side_rows *r,
                                                              const side_diffs *d, const int n,
                                                              const double *B, const double *B1,
                                                              double x[3], double nrm[3])
{
    double T[3] = {0, 0, 0}, X[3] = {0, 0, 0};
    x[0] = x[1] = x[2] = 0.0;
    for (int j = 0; j <= n; ++j)
        for (int c = 0; c < 3; ++c)
            x[c] += B[j] * r->row0[j][c];
    for (int j = 0; j < n; ++j)
        for (int c = 0; c < 3; ++c)
            T[c] += B1[j] * d->along[j][c];
    if (r->kind == SK_PATCH_TRIANGLE) {
        for (int j = 0; j < n; ++j)
            for (int c = 0; c < 3; ++c)
                X[c] += B1[j] * d->across[j][c];
    } else {
        for (int j = 0; j <= n; ++j)
            for (int c = 0; c < 3; ++c)
                X[c] += B[j] * d->across[j][c];
    }
    sk__cross3(nrm, T, X);
    double len = sk__norm3(nrm);
    if (len > 0.0)
        sk__scale3(nrm, nrm, 1.0 / len);
    else
        nrm[0] = nrm[1] = nrm[2] = 0.0;
}

/* the side at sample i of the edge (at 1 - t_i when rev) */
static void side_eval(const side_rows *r, const side_diffs *d, const bern_tab *tb, unsigned i,
                      int rev, double x[3], double nrm[3])
{
    int n = r->n;
    if (tb->K <= TAB_MAX_K && n == 4) {
        side_eval_b(r, d, 4, tb->B[1][rev][i], tb->B1[1][rev][i], x, nrm);
    } else if (tb->K <= TAB_MAX_K && n == 3) {
        side_eval_b(r, d, 3, tb->B[0][rev][i], tb->B1[0][rev][i], x, nrm);
    } else {
        double t = (double)i / tb->K, B[6], B1[6];
        t = rev ? 1.0 - t : t;
        sk__bernstein_n((unsigned)n, t, B, NULL);
        sk__bernstein_n((unsigned)(n - 1), t, B1, NULL);
        side_eval_b(r, d, n, B, B1, x, nrm);
    }
}

/* Two samples i0, i1 of a side at once, one in each lane of a vector: side_eval_b's sums,
 * cross product, length and scaling in each lane, in their order, so the same values to the bit
 * (the tabled degrees 3 and 4 only). */
typedef double v2d __attribute__((vector_size(16)));

static inline __attribute__((always_inline)) void side_eval_2b(
    const side_rows *r, const side_diffs *d, const int n, const double *Ba, const double *B1a,
    const double *Bb, const double *B1b, v2d x[3], v2d nrm[3])
{
    v2d zero = {0.0, 0.0}, T[3] = {zero, zero, zero}, X[3] = {zero, zero, zero};
    x[0] = x[1] = x[2] = zero;
    for (int j = 0; j <= n; ++j) {
        v2d Bj = {Ba[j], Bb[j]};
        for (int c = 0; c < 3; ++c)
            x[c] += Bj * (v2d){r->row0[j][c], r->row0[j][c]};
    }
    for (int j = 0; j < n; ++j) {
        v2d Bj = {B1a[j], B1b[j]};
        for (int c = 0; c < 3; ++c)
            T[c] += Bj * (v2d){d->along[j][c], d->along[j][c]};
    }
    if (r->kind == SK_PATCH_TRIANGLE) {
        for (int j = 0; j < n; ++j) {
            v2d Bj = {B1a[j], B1b[j]};
            for (int c = 0; c < 3; ++c)
                X[c] += Bj * (v2d){d->across[j][c], d->across[j][c]};
        }
    } else {
        for (int j = 0; j <= n; ++j) {
            v2d Bj = {Ba[j], Bb[j]};
            for (int c = 0; c < 3; ++c)
                X[c] += Bj * (v2d){d->across[j][c], d->across[j][c]};
        }
    }
    v2d c0 = T[1] * X[2] - T[2] * X[1], c1 = T[2] * X[0] - T[0] * X[2],
        c2 = T[0] * X[1] - T[1] * X[0];
    v2d q = c0 * c0 + c1 * c1 + c2 * c2, len = {sqrt(q[0]), sqrt(q[1])};
    v2d inv = (v2d){1.0, 1.0} / len, s0 = c0 * inv, s1 = c1 * inv, s2 = c2 * inv;
    nrm[0] = (v2d){len[0] > 0.0 ? s0[0] : 0.0, len[1] > 0.0 ? s0[1] : 0.0};
    nrm[1] = (v2d){len[0] > 0.0 ? s1[0] : 0.0, len[1] > 0.0 ? s1[1] : 0.0};
    nrm[2] = (v2d){len[0] > 0.0 ? s2[0] : 0.0, len[1] > 0.0 ? s2[1] : 0.0};
}

/* samples i and i + 1 of the side (at 1 - t when rev) in the lanes; false where not tabled */
static bool side_eval2(const side_rows *r, const side_diffs *d, const bern_tab *tb, unsigned i,
                       int rev, v2d x[3], v2d nrm[3])
{
    if (tb->K > TAB_MAX_K || (r->n != 3 && r->n != 4))
        return false;
    if (r->n == 4)
        side_eval_2b(r, d, 4, tb->B[1][rev][i], tb->B1[1][rev][i], tb->B[1][rev][i + 1],
                     tb->B1[1][rev][i + 1], x, nrm);
    else
        side_eval_2b(r, d, 3, tb->B[0][rev][i], tb->B1[0][rev][i], tb->B[0][rev][i + 1],
                     tb->B1[0][rev][i + 1], x, nrm);
    return true;
}

/* |n| == 0 for n a unit vector or zero (a unit vector's largest component is over 0.5, so its
 * squares do not underflow): no square root */
static bool is_zero3(const double n[3])
{
    return n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0;
}

static void edge_range(const sk_smooth *s, unsigned K, long e0, long e1, edge_block *b)
{
    const sk_mesh *m = s->config;
    memset(b, 0, sizeof *b);
    b->worst = -1;
    b->max_jump = -1.0;
    b->min_crease_jump = 180.0;
    bern_tab tb;
    bern_tab_init(&tb, K);
    tri_side_index x4;
    tri_side_index_init(&x4);
    for (long e = e0; e < e1; ++e) {
        uint32_t h = (uint32_t)(2 * e), o = h + 1;
        uint32_t f = m->h_face[h], g = m->h_face[o];
        if (f == SK_INVALID || g == SK_INVALID)
            continue;
        bool crease = s->crease_edge && s->crease_edge[e];
        if (!crease)
            ++b->nint;
        else
            ++b->ncrease;
        side_rows rf, rg;
        side_diffs df, dg;
        side_rows_of(s, &x4, f, side_of(m, f, h), &rf);
        side_rows_of(s, &x4, g, side_of(m, g, o), &rg);
        side_diffs_of(&rf, &df);
        side_diffs_of(&rg, &dg);
        double local_max = 0.0;
        /* samples i and i + 1 in the lanes: the gap and the jump's cross and dot products as
         * sk__dist3 and sk__angle3 form them in each lane (the same values to the bit) */
        v2d N1[3], N2[3], G, Y, XD;
        bool two = false;
        for (unsigned i = 0; i <= K; ++i) {
            double n1[3], n2[3], gap, y, xd;
            if (i % 2 == 0) {
                v2d X1[3], X2[3], dd[3], cc[3];
                two = i + 1 <= K && side_eval2(&rf, &df, &tb, i, 0, X1, N1) &&
                      side_eval2(&rg, &dg, &tb, i, 1, X2, N2);
                if (two) {
                    for (int c = 0; c < 3; ++c)
                        dd[c] = X1[c] - X2[c];
                    v2d q = dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2];
                    G = (v2d){sqrt(q[0]), sqrt(q[1])};
                    cc[0] = N1[1] * N2[2] - N1[2] * N2[1];
                    cc[1] = N1[2] * N2[0] - N1[0] * N2[2];
                    cc[2] = N1[0] * N2[1] - N1[1] * N2[0];
                    q = cc[0] * cc[0] + cc[1] * cc[1] + cc[2] * cc[2];
                    Y = (v2d){sqrt(q[0]), sqrt(q[1])};
                    XD = N1[0] * N2[0] + N1[1] * N2[1] + N1[2] * N2[2];
                }
            }
            if (two) {
                int l = (int)(i % 2);
                for (int c = 0; c < 3; ++c)
                    n1[c] = N1[c][l], n2[c] = N2[c][l];
                gap = G[l], y = Y[l], xd = XD[l];
            } else {
                double x1[3], x2[3], cc[3];
                side_eval(&rf, &df, &tb, i, 0, x1, n1);
                side_eval(&rg, &dg, &tb, i, 1, x2, n2);
                gap = sk__dist3(x1, x2);
                sk__cross3(cc, n1, n2);
                y = sk__norm3(cc), xd = sk__dot3(n1, n2);
            }
            /* a vanishing normal on an edge counts as a full jump */
            double jump = is_zero3(n1) || is_zero3(n2) ? 180.0 : atan2(y, xd) * RAD2DEG;
            b->max_gap = b->max_gap > gap ? b->max_gap : gap;
            if (crease) {
                /* G0 by design: the gap counts, the normal jump only in the crease figures */
                b->max_crease_gap = fmax(b->max_crease_gap, gap);
                b->max_crease_jump = fmax(b->max_crease_jump, jump);
                b->min_crease_jump = fmin(b->min_crease_jump, jump);
                continue;
            }
            b->sum_gap += gap;
            b->sum_jump += jump;
            local_max = local_max > jump ? local_max : jump;
            ++b->nsamp;
        }
        if (local_max > b->max_jump) {
            b->max_jump = local_max;
            b->worst = e;
        }
    }
}

/* Point and unit normal of a triangle of degree n >= 1 at its corner c, as sk_patch_eval gives
 * them: at a corner de Casteljau's weights are 1, 0, 0, so every step copies one point of the net
 * (x + 0 y = x: the same values, a zero's sign aside), and the last step's three points are the
 * control points next to the corner; the derivatives, cross product, length and scaling are then
 * sk_bezier_eval's operations. A zero's sign changes neither the distance nor the angle the
 * corner checks take. */
static void tri_corner_eval(const double *cp, unsigned n, unsigned c, double x[3], double nrm[3])
{
    unsigned i100, i010, i001; /* the last step's points b_{100}, b_{010}, b_{001} */
    if (c == 0)
        i100 = sk_tri_index(n, 0, 0), i010 = sk_tri_index(n, 1, 0), i001 = sk_tri_index(n, 0, 1);
    else if (c == 1)
        i100 = sk_tri_index(n, n - 1, 0), i010 = sk_tri_index(n, n, 0),
        i001 = sk_tri_index(n, n - 1, 1);
    else
        i100 = sk_tri_index(n, 0, n - 1), i010 = sk_tri_index(n, 1, n - 1),
        i001 = sk_tri_index(n, 0, n);
    const double *b100 = cp + 3 * i100, *b010 = cp + 3 * i010, *b001 = cp + 3 * i001;
    const double *corner = c == 0 ? b100 : c == 1 ? b010 : b001;
    double D1[3], D2[3], N[3];
    for (int q = 0; q < 3; ++q) {
        x[q] = corner[q];
        D1[q] = (double)n * (b010[q] - b100[q]);
        D2[q] = (double)n * (b001[q] - b100[q]);
    }
    sk__cross3(N, D1, D2);
    double len = sk__norm3(N);
    if (len > 0.0)
        sk__scale3(nrm, N, 1.0 / len);
    else
        nrm[0] = nrm[1] = nrm[2] = 0.0;
}

/* Interpolation errors at the corners of patch p and its regularity (sk__patch_regularity). */
static void patch_check(const sk_smooth *s, size_t p, patch_block *b, uint8_t *singular_out,
                        const sk__shape_ctx *shape, double *overshoot, double *fairness)
{
    sk__patch_shape(shape, p, overshoot + p, fairness + p);
    const sk_mesh *m = s->config;
    const sk_patch *pa = &s->surface.patches[p];
    for (unsigned i = 0; i < sk_patch_num_corners(pa); ++i) {
        double u, v, x[3], n[3];
        if (pa->kind == SK_PATCH_TRIANGLE && pa->degree >= 1) {
            tri_corner_eval(sk_patch_cp(&s->surface, p), pa->degree, i, x, n);
        } else {
            corner_param(pa->kind, i, &u, &v);
            sk_patch_eval(&s->surface, p, u, v, x, NULL, NULL, n);
        }
        const double *V = m->positions + 3 * (size_t)pa->corner_ids[i];
        const double *N = sk__corner_normal(s, p, i); /* its sector's at a crease */
        b->max_verr = fmax(b->max_verr, sk__dist3(x, V));
        b->max_nerr = fmax(b->max_nerr, sk__norm3(n) == 0.0 ? 180.0 : sk__angle3(n, N) * RAD2DEG);
    }
    bool cone;
    *singular_out = sk__patch_singular(s, p, &cone);
    b->uncert += !cone;
}

/* Crossing patch pairs, on a tessellation of n segments per side of the patches that can cross
 * another (sk__patch_box_pairs, or sk__patch_box_candidates where the grid gives no pairs; the
 * others' pairs cannot cross): the tessellator emits the faces patch by patch (n^2 per triangle,
 * 2 n^2 per tensor patch), and candidate g's corner ids make face g of the groups soup, so
 * patches sharing a corner are neighbours. With the pairs only their triangles are tested against
 * each other (sk__self_intersections_pairs: the same crossing pairs as testing every candidate
 * against every other, a crossing pair having overlapping boxes), else all the candidates'
 * (sk_self_intersections). The reported patches are mapped back to the whole set's indices (in
 * the same order: the candidates keep theirs). */
static sk_status intersections(const sk_patch_set *set, unsigned n, sk_continuity_report *rep,
                               sk_error *err)
{
    sk_soup *tess = NULL, *groups = NULL;
    sk_patch_set sub = {0};
    uint64_t *pairs = NULL;
    size_t npairs = 0;
    uint32_t *face_patch = NULL, *orig = sk__malloc_array(set->count + 1, sizeof *orig);
    uint32_t *sub_of = sk__malloc_array(set->count + 1, sizeof *sub_of);
    uint8_t *cand = sk__malloc_array(set->count + 1, 1);
    sk_status st = orig && cand && sub_of ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (!st)
        st = sk__patch_box_pairs(set, &pairs, &npairs, err);
    if (!st && pairs) {
        memset(cand, 0, set->count);
        for (size_t k = 0; k < npairs; ++k)
            cand[pairs[k] >> 32] = cand[(uint32_t)pairs[k]] = 1;
    } else if (!st) {
        st = sk__patch_box_candidates(set, cand, err);
    }
    size_t nc = 0;
    for (size_t p = 0; !st && p < set->count; ++p) {
        const sk_patch *pp = &set->patches[p];
        if (!cand[p])
            continue;
        sub_of[p] = (uint32_t)nc;
        orig[nc++] = (uint32_t)p;
        st = sk_patch_set_add(&sub, (sk_patch_kind)pp->kind, pp->degree, pp->degree_v,
                              sk_patch_cp(set, p), pp->corner_ids, NULL, err);
    }
    rep->intersecting_pairs = rep->intersecting_patches = 0;
    if (st || nc == 0)
        goto done;
    st = sk_patch_set_tessellate(&sub, n, &tess, err);
    if (!st)
        st = sk_soup_create(0, nc, 4 * nc, false, false, &groups, err);
    if (!st && !(face_patch = sk__malloc_array(tess->num_faces + 1, sizeof *face_patch)))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    size_t f = 0;
    for (size_t p = 0; !st && p < nc; ++p) {
        const sk_patch *pp = &sub.patches[p];
        size_t nf = (size_t)n * n * (pp->kind == SK_PATCH_TRIANGLE ? 1 : 2);
        for (size_t k = 0; k < nf && f < tess->num_faces; ++k)
            face_patch[f++] = (uint32_t)p;
        if (sk_soup_push_face(groups, pp->corner_ids, sk_patch_num_corners(pp)))
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    if (!st && f != tess->num_faces)
        st = sk__fail(err, SK_ERR_NUMERIC, "the tessellation has %zu faces, expected %zu",
                      tess->num_faces, f);
    sk_intersection_report x;
    bool fallback = !pairs;
    if (!st && pairs) {
        for (size_t k = 0; k < npairs; ++k) /* to the candidates' indices (the order kept) */
            pairs[k] = (uint64_t)sub_of[pairs[k] >> 32] << 32 | sub_of[(uint32_t)pairs[k]];
        st = sk__self_intersections_pairs(tess, face_patch, nc, pairs, npairs, &x, &fallback, err);
    }
    if (!st && fallback)
        st = sk_self_intersections(tess, face_patch, groups, &x, err);
    if (!st) {
        rep->intersecting_pairs = x.pairs;
        rep->intersecting_patches = x.groups;
        for (size_t i = 0; i < x.num_examples && i < SK_CONTINUITY_EXAMPLES; ++i) {
            rep->intersection_examples[2 * i] = orig[x.examples[2 * i]];
            rep->intersection_examples[2 * i + 1] = orig[x.examples[2 * i + 1]];
            rep->num_intersection_examples = i + 1;
        }
    }
done:
    sk__free(face_patch);
    sk__free(pairs);
    sk__free(sub_of);
    sk__free(orig);
    sk__free(cand);
    sk_patch_set_free(&sub);
    sk_soup_destroy(&groups);
    sk_soup_destroy(&tess);
    return st;
}

/* Worst and mean overshoot and fairness, the worst patches (first index among equals) and the
 * patches over 0.5 (worst first), independent of the number of threads. */
static void shape_summary(const double *over, const double *fair, size_t np,
                          sk_continuity_report *rep)
{
    double so = 0.0, sf = 0.0;
    rep->max_overshoot_patch = rep->max_fairness_patch = SK_INVALID;
    for (size_t p = 0; p < np; ++p) {
        so += over[p];
        sf += fair[p];
        if (rep->max_overshoot_patch == SK_INVALID || over[p] > rep->max_overshoot) {
            rep->max_overshoot = over[p];
            rep->max_overshoot_patch = (uint32_t)p;
        }
        if (rep->max_fairness_patch == SK_INVALID || fair[p] > rep->max_fairness_deg) {
            rep->max_fairness_deg = fair[p];
            rep->max_fairness_patch = (uint32_t)p;
        }
        if (!(over[p] > 0.5))
            continue;
        rep->overshoot_patches++;
        size_t n = rep->num_overshoot_examples, i = n < SK_CONTINUITY_EXAMPLES ? n : n - 1;
        if (n == SK_CONTINUITY_EXAMPLES && !(over[p] > over[rep->overshoot_examples[i]]))
            continue;
        while (i > 0 && over[p] > over[rep->overshoot_examples[i - 1]]) {
            rep->overshoot_examples[i] = rep->overshoot_examples[i - 1];
            --i;
        }
        rep->overshoot_examples[i] = (uint32_t)p;
        if (n < SK_CONTINUITY_EXAMPLES)
            rep->num_overshoot_examples++;
    }
    rep->mean_overshoot = np ? so / (double)np : 0.0;
    rep->mean_fairness_deg = np ? sf / (double)np : 0.0;
}

sk_status sk_smooth_continuity(const sk_smooth *s, const sk_continuity_opts *opts,
                               sk_continuity_report *rep, sk_error *err)
{
    if (!s || !rep)
        return sk__fail(err, SK_ERR_ARG, "sk_smooth_continuity: NULL argument");
    unsigned K = opts && opts->samples ? opts->samples : 32;
    double tol_deg = opts && opts->max_angle_deg > 0 ? opts->max_angle_deg : 0.5;
    double tol_gap = opts && opts->max_gap > 0 ? opts->max_gap : 0.005;
    const sk_mesh *m = s->config;
    memset(rep, 0, sizeof *rep);
    long ne = (long)sk_num_edges(m), np = (long)s->surface.count;
    long neb = (ne + BLOCK - 1) / BLOCK, npb = (np + PBLOCK - 1) / PBLOCK;
    edge_block *eb = sk__malloc_array((size_t)neb + 1, sizeof *eb);
    patch_block *pb = sk__malloc_array((size_t)npb + 1, sizeof *pb);
    uint8_t *singular = sk__malloc_array((size_t)np + 1, 1);
    double *shape_v = sk__malloc_array(2 * (size_t)np + 1, sizeof *shape_v);
    sk__shape_ctx shape;
    sk_status shape_st = sk__shape_ctx_init(&shape, s, opts ? opts->shape_samples : 0, err);
    if (!eb || !pb || !singular || !shape_v || shape_st) {
        sk__free(eb);
        sk__free(pb);
        sk__free(singular);
        sk__free(shape_v);
        sk__shape_ctx_free(&shape);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the continuity report");
    }
    /* the crossing patches (serial but for their triangle tests, which then run in this thread
     * alone: the same result) go beside the edges' and patches' blocks */
    unsigned tess = opts && opts->intersection_tess ? opts->intersection_tess : 6;
    sk_continuity_report xrep = {0};
    sk_error xerr = {0};
    sk_status xst = SK_OK;
    xrep.intersecting_pairs = xrep.intersecting_patches = SIZE_MAX;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel
#endif
    {
#ifdef SK_HAVE_OPENMP
#pragma omp single nowait
#endif
        if (tess != (unsigned)-1)
            xst = intersections(&s->surface, tess, &xrep, &xerr);
#ifdef SK_HAVE_OPENMP
#pragma omp for schedule(dynamic, 1) nowait
#endif
        for (long k = 0; k < neb; ++k)
            edge_range(s, K, k * BLOCK, k + 1 < neb ? (k + 1) * BLOCK : ne, eb + k);
#ifdef SK_HAVE_OPENMP
#pragma omp for schedule(dynamic, 1)
#endif
        for (long k = 0; k < npb; ++k) {
            memset(pb + k, 0, sizeof pb[k]);
            long p1 = k + 1 < npb ? (k + 1) * PBLOCK : np;
            for (long p = k * PBLOCK; p < p1; ++p)
                patch_check(s, (size_t)p, pb + k, singular + p, &shape, shape_v, shape_v + np);
        }
    }
    double max_gap = 0.0, sum_gap = 0.0, max_jump = 0.0, sum_jump = 0.0;
    size_t nint = 0, nsamp = 0;
    long worst = -1;
    rep->min_crease_jump_deg = 180.0;
    for (long k = 0; k < neb; ++k) {
        rep->crease_edges += eb[k].ncrease;
        rep->max_crease_gap = fmax(rep->max_crease_gap, eb[k].max_crease_gap);
        rep->max_crease_jump_deg = fmax(rep->max_crease_jump_deg, eb[k].max_crease_jump);
        rep->min_crease_jump_deg = fmin(rep->min_crease_jump_deg, eb[k].min_crease_jump);
        max_gap = fmax(max_gap, eb[k].max_gap);
        sum_gap += eb[k].sum_gap;
        sum_jump += eb[k].sum_jump;
        nint += eb[k].nint;
        nsamp += eb[k].nsamp;
        if (eb[k].worst >= 0 && eb[k].max_jump > max_jump) {
            max_jump = eb[k].max_jump;
            worst = eb[k].worst;
        }
    }
    if (rep->crease_edges == 0)
        rep->min_crease_jump_deg = 0.0;
    rep->interior_edges = nint;
    rep->samples = nsamp;
    rep->max_gap = max_gap;
    rep->mean_gap = nsamp ? sum_gap / (double)nsamp : 0.0;
    rep->max_normal_jump_deg = max_jump;
    rep->mean_normal_jump_deg = nsamp ? sum_jump / (double)nsamp : 0.0;
    rep->worst_edge_vertices[0] = rep->worst_edge_vertices[1] = SK_INVALID;
    if (worst >= 0) {
        rep->worst_edge_vertices[0] = sk_from(m, (uint32_t)(2 * worst));
        rep->worst_edge_vertices[1] = sk_to(m, (uint32_t)(2 * worst));
    }
    double max_verr = 0.0, max_nerr = 0.0;
    size_t uncert = 0;
    for (long k = 0; k < npb; ++k) {
        max_verr = fmax(max_verr, pb[k].max_verr);
        max_nerr = fmax(max_nerr, pb[k].max_nerr);
        uncert += pb[k].uncert;
    }
    for (long p = 0; p < np; ++p) {
        if (!singular[p])
            continue;
        if (rep->num_singular_examples < SK_CONTINUITY_EXAMPLES)
            rep->singular_examples[rep->num_singular_examples++] = (uint32_t)p;
        rep->singular_patches++;
    }
    shape_summary(shape_v, shape_v + np, (size_t)np, rep);
    sk__free(eb);
    sk__free(pb);
    sk__free(singular);
    sk__free(shape_v);
    sk__shape_ctx_free(&shape);
    rep->max_vertex_error = max_verr;
    rep->max_normal_error_deg = max_nerr;
    rep->uncertified_patches = uncert;
    rep->pass_g1 = rep->max_normal_jump_deg <= tol_deg;
    rep->pass_gap = rep->max_gap <= tol_gap;
    if (xst) {
        if (err)
            *err = xerr;
        return xst;
    }
    rep->intersecting_pairs = xrep.intersecting_pairs;
    rep->intersecting_patches = xrep.intersecting_patches;
    rep->num_intersection_examples = xrep.num_intersection_examples;
    memcpy(rep->intersection_examples, xrep.intersection_examples,
           sizeof rep->intersection_examples);
    rep->pass_intersections = rep->intersecting_pairs == 0 || rep->intersecting_pairs == SIZE_MAX;
    sk__ok(err);
    return SK_OK;
}
