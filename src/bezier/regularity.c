/* Regularity certificates of a Bezier patch from its control net: the normal-cone test of
 * Ginkel, Peters, Umlauf (Lemma 3) and a bound that proves a sampled test cannot fail. */
#include "bezier/bezier_internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

/* Differences along the two parameter directions of patch i's control net (at most
 * SK__PATCH_MAX_POINTS each); returns their weight W: du x dv = W sum_k beta_k g_k with
 * beta_k >= 0, sum beta_k = 1 (products of Bernstein polynomials). */
static double net_differences(const sk_patch_set *set, size_t pi, double (*du)[3], double (*dv)[3],
                              unsigned *ndu, unsigned *ndv)
{
    const sk_patch *p = &set->patches[pi];
    const double *b = sk_patch_cp(set, pi);
    unsigned nu = 0, nv = 0, n = p->degree;
    double W;
    if (p->kind == SK_PATCH_TENSOR) {
        unsigned m = p->degree_v;
        for (unsigned j = 0; j <= m; ++j)
            for (unsigned i = 0; i < n; ++i)
                sk__sub3(du[nu++], b + 3 * sk_tensor_index(n, i + 1, j),
                         b + 3 * sk_tensor_index(n, i, j));
        for (unsigned j = 0; j < m; ++j)
            for (unsigned i = 0; i <= n; ++i)
                sk__sub3(dv[nv++], b + 3 * sk_tensor_index(n, i, j + 1),
                         b + 3 * sk_tensor_index(n, i, j));
        W = (double)n * m;
    } else {
        for (unsigned k = 0; k < n; ++k)
            for (unsigned j = 0; j < n - k; ++j) {
                const double *p0 = b + 3 * sk_tri_index(n, j, k);
                sk__sub3(du[nu++], b + 3 * sk_tri_index(n, j + 1, k), p0);
                sk__sub3(dv[nv++], b + 3 * sk_tri_index(n, j, k + 1), p0);
            }
        W = (double)n * n;
    }
    *ndu = nu;
    *ndv = nv;
    return W;
}

void sk__patch_certify(const sk_patch_set *set, size_t pi, const double ref[3], double scale,
                       bool *cone_regular, bool *sampling_certified)
{
    double du[SK__PATCH_MAX_POINTS][3], dv[SK__PATCH_MAX_POINTS][3], axis[3] = {0, 0, 0};
    unsigned nu, nv;
    double W = net_differences(set, pi, du, dv, &nu, &nv);
    /* the generators g = du_i x dv_j; axis: their sum (Lemma 3: the normal lies in their cone).
     * Kept for the second pass when they fit (VC1's quartic triangles 10 x 10, bicubic quads
     * 12 x 12), so each cross product is formed once: the same values to the bit. */
    enum { GEN_MAX = 12 * 12 };
    double gen[GEN_MAX][3];
    bool keep = (size_t)nu * nv <= GEN_MAX;
    for (unsigned i = 0; i < nu; ++i)
        for (unsigned j = 0; j < nv; ++j) {
            double g[3];
            sk__cross3(g, du[i], dv[j]);
            sk__add3(axis, axis, g);
            if (keep)
                memcpy(gen[i * nv + j], g, sizeof g);
        }
    bool cone = sk__normalize3(axis) != 0.0;
    /* the cone excludes 0 if every generator that is not zero lies strictly on the axis side
     * (zero generators, e.g. collapsed differences, add nothing to the cone) */
    double refn[3] = {ref[0], ref[1], ref[2]};
    bool sample = sk__normalize3(refn) != 0.0 && scale > 0.0;
    double min_ref = 1e300, max_len2 = 0.0;
    for (unsigned i = 0; i < nu; ++i)
        for (unsigned j = 0; j < nv; ++j) {
            double g[3];
            if (keep)
                memcpy(g, gen[i * nv + j], sizeof g);
            else
                sk__cross3(g, du[i], dv[j]);
            double len2 = sk__dot3(g, g);
            max_len2 = max_len2 > len2 ? max_len2 : len2;
            if (len2 == 0.0) {
                sample = false; /* a zero generator may carry all the weight at a corner */
                continue;
            }
            double d = sk__dot3(g, axis); /* d > 1e-12 |g| without the square root */
            if (cone && !(d > 0.0 && d * d > 1e-24 * len2))
                cone = false;
            double dr = sk__dot3(g, refn);
            min_ref = min_ref < dr ? min_ref : dr;
        }
    /* so (du x dv) . ref >= W min_k g_k . ref: the sampled test (|du x dv| > 1e-10 scale,
     * (du x dv) . ref > 0) cannot fail anywhere when that bound clears it with a margin against
     * rounding */
    if (sample)
        sample = min_ref > 1e-9 * sqrt(max_len2) && W * min_ref > 2e-10 * scale;
    *cone_regular = cone;
    *sampling_certified = sample;
}
