/* Quartic / cubic triangular and bicubic Bezier patches: evaluation, first derivatives and
 * normals by de Casteljau; the normal-cone regularity test of Ginkel, Peters, Umlauf. */
#include "smooth/smooth_internal.h"
#include "core/vec.h"
#include "core/internal.h"

#include <string.h>

/* The control nets use the layout of sk_patch (include/surfkit/bezier.h), so evaluation is the
 * shared de Casteljau of src/smooth/bezier.c. */
void sk_smooth_eval(const sk_smooth *s, size_t p, double u, double v, double pos[3], double du[3],
                    double dv[3], double normal[3])
{
    const sk_smooth_patch *pa = s->patches + p;
    bool quad = pa->kind == SK_SMOOTH_QUAD;
    sk_bezier_eval(quad ? SK_PATCH_TENSOR : SK_PATCH_TRIANGLE, pa->degree, quad ? 3 : 0,
                   s->points + 3 * (size_t)pa->first, u, v, pos, du, dv, normal);
}

sk_status sk_smooth_to_patches(const sk_smooth *s, sk_patch **out, size_t *count, sk_error *err)
{
    sk_patch *ps = sk__malloc_array(s->num_patches ? s->num_patches : 1, sizeof *ps);
    if (!ps)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t p = 0; p < s->num_patches; ++p) {
        const sk_smooth_patch *pa = s->patches + p;
        bool quad = pa->kind == SK_SMOOTH_QUAD;
        memset(&ps[p], 0, sizeof ps[p]);
        ps[p].kind = quad ? SK_PATCH_TENSOR : SK_PATCH_TRIANGLE;
        ps[p].degree = pa->degree;
        ps[p].degree_v = quad ? 3 : 0;
        memcpy(ps[p].cp, s->points + 3 * (size_t)pa->first,
               3 * sk__patch_points(pa->kind, pa->degree) * sizeof(double));
        /* quads: corners[0..3] sit at (0,0), (1,0), (1,1), (0,1) of the net, as in sk_patch */
        memcpy(ps[p].corner_ids, pa->corners, sizeof pa->corners);
    }
    *out = ps;
    *count = s->num_patches;
    return SK_OK;
}

/* u- and v-differences of the control net (directions corners[0]->[1] and [0]->[2] or [0]->[3]) */
static int net_differences(const sk_smooth_patch *pa, const double *b, double du[][3], double dv[][3],
                           int *ndu, int *ndv)
{
    int nu = 0, nv = 0;
    if (pa->kind == SK_SMOOTH_QUAD) {
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 3; ++i)
                sk__sub3(du[nu++], b + 3 * (i + 1 + 4 * j), b + 3 * (i + 4 * j));
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i)
                sk__sub3(dv[nv++], b + 3 * (i + 4 * (j + 1)), b + 3 * (i + 4 * j));
    } else {
        int n = pa->degree;
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n - k; ++j) {
                const double *p0 = b + 3 * sk__tri_index(n, j, k);
                sk__sub3(du[nu++], b + 3 * sk__tri_index(n, j + 1, k), p0);
                sk__sub3(dv[nv++], b + 3 * sk__tri_index(n, j, k + 1), p0);
            }
    }
    *ndu = nu;
    *ndv = nv;
    return 0;
}

void sk__patch_certify(const sk_smooth *s, size_t p, const double ref[3], double scale,
                       bool *cone_regular, bool *sampling_certified)
{
    const sk_smooth_patch *pa = s->patches + p;
    const double *b = s->points + 3 * (size_t)pa->first;
    double du[12][3], dv[12][3], g[144][3], axis[3] = {0, 0, 0};
    int nu, nv;
    net_differences(pa, b, du, dv, &nu, &nv);
    /* the generators g = du_i x dv_j; axis: their sum (Lemma 3: the normal lies in their cone) */
    int ng = 0;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            sk__cross3(g[ng], du[i], dv[j]);
            sk__add3(axis, axis, g[ng]);
            ++ng;
        }
    bool cone = sk__normalize3(axis) != 0.0;
    /* the cone excludes 0 if every generator that is not zero lies strictly on the axis side
     * (zero generators, e.g. collapsed differences, add nothing to the cone) */
    double refn[3] = {ref[0], ref[1], ref[2]};
    bool sample = sk__normalize3(refn) != 0.0 && scale > 0.0;
    double min_ref = 1e300, max_len2 = 0.0;
    for (int k = 0; k < ng; ++k) {
        double len2 = sk__dot3(g[k], g[k]);
        max_len2 = max_len2 > len2 ? max_len2 : len2;
        if (len2 == 0.0) {
            sample = false; /* a zero generator may carry all the weight at a corner */
            continue;
        }
        double d = sk__dot3(g[k], axis); /* d > 1e-12 |g| without the square root */
        if (cone && !(d > 0.0 && d * d > 1e-24 * len2))
            cone = false;
        double dr = sk__dot3(g[k], refn);
        min_ref = min_ref < dr ? min_ref : dr;
    }
    /* du x dv = W sum_k beta_k g_k with beta_k >= 0, sum beta_k = 1 (products of Bernstein
     * polynomials), W = 9 for bicubics, n^2 for triangles of degree n; so (du x dv) . ref >=
     * W min_k g_k . ref: the sampled test (|du x dv| > 1e-10 scale, (du x dv) . ref > 0) cannot fail
     * anywhere when that bound clears it with a margin against rounding */
    double W = pa->kind == SK_SMOOTH_QUAD ? 9.0 : (double)pa->degree * pa->degree;
    if (sample)
        sample = min_ref > 1e-9 * sqrt(max_len2) && W * min_ref > 2e-10 * scale;
    *cone_regular = cone;
    *sampling_certified = sample;
}

bool sk__patch_singular(const sk_smooth *s, size_t p, bool *cone_regular)
{
    const unsigned G = 8;
    const sk_smooth_patch *pa = s->patches + p;
    double ref[3] = {0, 0, 0};
    for (int i = 0; i < pa->kind; ++i)
        sk__add3(ref, ref, s->normals + 3 * (size_t)pa->corners[i]);
    double du[3], dv[3];
    sk_smooth_eval(s, p, 1.0 / 3.0, 1.0 / 3.0, NULL, du, dv, NULL);
    double scale = sk__norm3(du) * sk__norm3(dv);
    bool cone, certified;
    sk__patch_certify(s, p, ref, scale, &cone, &certified);
    if (cone_regular)
        *cone_regular = cone;
    if (certified)
        return false;
    for (unsigned i = 0; i <= G; ++i)
        for (unsigned j = 0; j <= G; ++j) {
            if (pa->kind == SK_SMOOTH_TRIANGLE && i + j > G)
                continue;
            double c[3];
            sk_smooth_eval(s, p, (double)i / G, (double)j / G, NULL, du, dv, NULL);
            sk__cross3(c, du, dv);
            double len = sk__norm3(c);
            if (!(len > 1e-10 * scale) || sk__dot3(c, ref) <= 0.0)
                return true;
        }
    return false;
}
