/* Internal pieces of the patch layer shared by the files of src/bezier and its users (smooth). */
#ifndef SK_BEZIER_INTERNAL_H
#define SK_BEZIER_INTERNAL_H

#include "surfkit/bezier.h"

/* Largest control net of any patch (a tensor patch of the largest degrees). */
#define SK__PATCH_MAX_POINTS ((SK_PATCH_MAX_DEGREE + 1) * (SK_PATCH_MAX_DEGREE + 1))

/* Bernstein basis B_i^n(t), i = 0..n, into B, and dB_i^n/dt into dB unless it is NULL. */
void sk__bernstein(unsigned n, double t, double *B, double *dB);
/* sk__bernstein inlined (the same operations): callers with a constant degree get it unrolled */
static inline __attribute__((always_inline)) void sk__bernstein_n(const unsigned n, double t,
                                                              double *B, double *dB)
{
    double s = 1.0 - t;
    B[0] = 1.0;
    for (unsigned r = 1; r <= n; ++r) {
        if (r == n && dB) { /* dB_i^n = n (B_{i-1}^{n-1} - B_i^{n-1}) */
            for (unsigned i = 0; i <= n; ++i)
                dB[i] = (double)n * ((i > 0 ? B[i - 1] : 0.0) - (i < n ? B[i] : 0.0));
        }
        double saved = 0.0;
        for (unsigned i = 0; i < r; ++i) {
            double tmp = B[i];
            B[i] = saved + s * tmp;
            saved = t * tmp;
        }
        B[r] = saved;
    }
    if (n == 0 && dB)
        dB[0] = 0.0;
}

/* de Casteljau on a curve of degree n: point and derivative (d may be NULL) at t. */
void sk__curve_eval(const double *cp, unsigned n, double t, double pt[3], double d[3]);

/* de Casteljau on a triangle net of degree n at barycentric (1 - v - w, v, w): reduce to degree 1,
 * whose three points give the point and the derivatives toward corners 1 and 2 (d1, d2 may be
 * NULL). */
void sk__tri_eval(const double *cp, unsigned n, double v, double w, double pt[3], double d1[3],
                  double d2[3]);

/* Grows the set by `patches` headers and `points` control points and leaves both unwritten: the
 * caller fills every new header (all fields, reserved = 0) and every new point before the set is
 * read (a parallel fill touches the fresh pages on the threads that use them). */
sk_status sk__patch_set_extend_unset(sk_patch_set *set, size_t patches, size_t points,
                                     sk_error *err);

/* sk_patch_set_add with a tag. */
sk_status sk__patch_set_add_tagged(sk_patch_set *set, sk_patch_kind kind, unsigned degree,
                                   unsigned degree_v, const double *cp, const uint32_t *corner_ids,
                                   uint32_t tag, sk_error *err);

/* Regularity certificates of patch i of set from the cross products g_ij = du_i x dv_j of the
 * differences of its control net along the two parameter directions (corner 0 -> 1 and
 * corner 0 -> 2 (triangle) or 0 -> 3 (tensor)):
 *  - cone_regular: the cone test of Ginkel, Peters, Umlauf (Lemma 3): the cone spanned by the g_ij
 *    excludes 0 (then the patch has no singular point and its normals stay inside the cone);
 *  - sampling_certified: every g_ij is non-zero with g_ij . ref > 0, with a margin that proves that
 *    a sampled check (|du x dv| > 1e-10 scale and (du x dv) . ref > 0) passes at every parameter,
 *    so sampling can be skipped. */
void sk__patch_certify(const sk_patch_set *set, size_t i, const double ref[3], double scale,
                       bool *cone_regular, bool *sampling_certified);

#endif
