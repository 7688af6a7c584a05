/* The conventional method of Table 1 (Hormann, Greiner, Campagna): Floater's parametrization of
 * the full mesh, then MIPS local steps in random order; and the linear start both drivers use. */
#include "surfkit/hierarchical.h"
#include "param/mips_internal.h"

#include <string.h>

sk_status sk__mips_linear_start(const sk_mesh *m, const sk_boundary_opts *boundary,
                                const double *given, double *uv, sk_error *err)
{
    sk_param_opts po = {0};
    po.method = SK_PARAM_FLOATER;
    if (boundary)
        po.boundary = *boundary;
    if (given) { /* fixed boundary from the finest level */
        po.boundary.shape = SK_BOUNDARY_GIVEN;
        memcpy(uv, given, 2 * m->num_vertices * sizeof(double));
    }
    return sk_param_linear(m, &po, uv, NULL, err);
}

sk_status sk_param_mips_flat(const sk_mesh *mesh, sk_mips_boundary boundary, size_t max_steps,
                             double tolerance, uint64_t seed, double *uv, sk_mips_stats *stats,
                             sk_error *err)
{
    sk_boundary_opts bo = {0};
    bo.shape = boundary == SK_MIPS_BOUNDARY_SQUARE ? SK_BOUNDARY_SQUARE : SK_BOUNDARY_CIRCLE;
    sk_status st = sk__mips_linear_start(mesh, &bo, NULL, uv, err);
    if (st)
        return st;
    sk_mips_opts mo = {0};
    mo.fixed_boundary = boundary != SK_MIPS_BOUNDARY_FREE;
    mo.max_steps = max_steps;
    mo.max_sweeps = max_steps ? (size_t)-1 : 0; /* a budget, or the default sweeps */
    mo.tolerance = tolerance;
    mo.seed = seed;
    return sk_param_mips(mesh, &mo, uv, stats, err);
}
