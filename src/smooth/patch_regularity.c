/* The regularity test of the continuity report: a patch is singular where its normal vanishes or
 * turns away from its corner normals; the control-net certificates of src/bezier/regularity.c
 * (Ginkel, Peters, Umlauf) decide most patches without sampling. */
#include "smooth/smooth_internal.h"
#include "core/vec.h"
#include "core/internal.h"

bool sk__patch_singular(const sk_smooth *s, size_t p, bool *cone_regular)
{
    const unsigned G = 8;
    const sk_patch *pa = &s->surface.patches[p];
    unsigned nc = sk_patch_num_corners(pa);
    double ref[3] = {0, 0, 0};
    for (unsigned i = 0; i < nc; ++i)
        sk__add3(ref, ref, sk__corner_normal(s, p, i));
    double du[3], dv[3];
    sk_patch_eval(&s->surface, p, 1.0 / 3.0, 1.0 / 3.0, NULL, du, dv, NULL);
    double scale = sk__norm3(du) * sk__norm3(dv);
    bool cone, certified;
    sk__patch_certify(&s->surface, p, ref, scale, &cone, &certified);
    if (cone_regular)
        *cone_regular = cone;
    if (certified)
        return false;
    for (unsigned i = 0; i <= G; ++i)
        for (unsigned j = 0; j <= G; ++j) {
            if (pa->kind == SK_PATCH_TRIANGLE && i + j > G)
                continue;
            double c[3];
            sk_patch_eval(&s->surface, p, (double)i / G, (double)j / G, NULL, du, dv, NULL);
            sk__cross3(c, du, dv);
            double len = sk__norm3(c);
            if (!(len > 1e-10 * scale) || sk__dot3(c, ref) <= 0.0)
                return true;
        }
    return false;
}
