/* The regularity test of the continuity report: a patch is singular where its normal vanishes or
 * turns away from its corner normals; the control-net certificates of src/bezier/regularity.c
 * (Ginkel, Peters, Umlauf) decide most patches without sampling. */
#include "smooth/smooth_internal.h"
#include "core/vec.h"
#include "core/internal.h"

#define SING_GRID 8

/* sample k (in the order i = 0 .. G, j = 0 .. G, triangles only i + j <= G) of patch p fails:
 * the normal vanishes or turns away from ref */
static bool sample_fails(const sk_smooth *s, size_t p, unsigned i, unsigned j, const double ref[3],
                         double scale)
{
    double du[3], dv[3], c[3];
    sk_patch_eval(&s->surface, p, (double)i / SING_GRID, (double)j / SING_GRID, NULL, du, dv,
                  NULL);
    sk__cross3(c, du, dv);
    double len = sk__norm3(c);
    return !(len > 1e-10 * scale) || sk__dot3(c, ref) <= 0.0;
}

/* the grid point (i, j) of sample k in the order of sample_fails; false past the last sample */
static bool sample_at(bool tri, unsigned k, unsigned *i, unsigned *j)
{
    unsigned row = SING_GRID + 1; /* samples in row i: G + 1, or G + 1 - i on a triangle */
    for (*i = 0; *i <= SING_GRID; ++*i) {
        if (k < row) {
            *j = k;
            return true;
        }
        k -= row;
        row -= tri;
    }
    return false;
}

bool sk__patch_singular(const sk_smooth *s, size_t p, bool *cone_regular)
{
    uint8_t first = 0;
    return sk__patch_singular_from(s, p, cone_regular, &first);
}

/* The samples are tried from *first on (the one that failed last time: a patch tried again with
 * nearby control points, as the repair does, usually fails there again), then the others in
 * order; the answer is the same in any order. */
bool sk__patch_singular_from(const sk_smooth *s, size_t p, bool *cone_regular, uint8_t *first)
{
    const unsigned G = SING_GRID;
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
    bool tri = pa->kind == SK_PATCH_TRIANGLE;
    unsigned k0 = *first, i0, j0, k = 0;
    if (sample_at(tri, k0, &i0, &j0) && sample_fails(s, p, i0, j0, ref, scale))
        return true;
    for (unsigned i = 0; i <= G; ++i)
        for (unsigned j = 0; j <= G; ++j) {
            if (tri && i + j > G)
                continue;
            if (k++ != k0 && sample_fails(s, p, i, j, ref, scale)) {
                *first = (uint8_t)(k - 1);
                return true;
            }
        }
    return false;
}
