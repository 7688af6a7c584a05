/* The conventional method of Table 1 (Hormann, Greiner, Campagna): Floater's parametrization of
 * the full mesh, then MIPS local steps in random order; and the linear start both drivers use. */
#include "surfkit/hierarchical.h"
#include "core/internal.h"
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

sk_status sk_param_mips_flat(const sk_mesh *mesh, const sk_mips_flat_opts *opts, double *uv,
                             sk_mips_stats *stats, sk_error *err)
{
    sk_mips_flat_opts o = {0};
    if (opts)
        o = *opts;
    sk_boundary_shape shape = o.boundary.shape;
    bool fixed = shape != SK_BOUNDARY_DEFAULT && shape != SK_BOUNDARY_FREE;
    if (shape == SK_BOUNDARY_GIVEN)
        return sk__fail(err, SK_ERR_ARG, "flat MIPS maps the boundary itself: circle, square or "
                        "free, not given");
    sk_boundary_opts bo = o.boundary;
    if (!fixed)
        bo.shape = SK_BOUNDARY_CIRCLE; /* the start */
    sk_status st = sk__mips_linear_start(mesh, &bo, NULL, uv, err);
    if (st)
        return st;
    sk_mips_opts mo = {0};
    mo.boundary = fixed ? SK_BOUNDARY_GIVEN : SK_BOUNDARY_FREE;
    mo.max_steps = o.max_steps;
    mo.max_sweeps = o.max_steps ? (size_t)-1 : 0; /* a budget, or the default sweeps */
    mo.tolerance = o.tolerance;
    mo.seed = o.seed;
    mo.progress = o.progress;
    mo.progress_user = o.progress_user;
    return sk_param_mips(mesh, &mo, uv, stats, err);
}
