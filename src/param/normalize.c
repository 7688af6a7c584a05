/* Normalization of a parametrization to the unit square (uniform scale and translation). */
#include "surfkit/param.h"
#include "core/internal.h"

#include <math.h>

sk_status sk_param_normalize(const sk_mesh *mesh, double *uv, sk_error *err)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    size_t used = 0;
    for (size_t f = 0; f < mesh->num_faces; ++f) {
        if (mesh->f_deleted[f])
            continue;
        uint32_t h0 = mesh->f_halfedge[f], h = h0;
        do {
            const double *q = uv + 2 * (size_t)mesh->h_vertex[h];
            if (!isfinite(q[0]) || !isfinite(q[1]))
                return sk__fail(err, SK_ERR_NUMERIC, "vertex %u has a non-finite uv",
                                mesh->h_vertex[h]);
            for (int k = 0; k < 2; ++k) {
                lo[k] = fmin(lo[k], q[k]);
                hi[k] = fmax(hi[k], q[k]);
            }
            used++;
            h = mesh->h_next[h];
        } while (h != h0);
    }
    if (!used)
        return SK_OK;
    double ext = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(ext > 0.0) || !isfinite(ext))
        return sk__fail(err, SK_ERR_NUMERIC, "the uv of every vertex is the same point");
    /* (u - lo) / ext: the division keeps the result in [0, 1] exactly (monotone rounding, and
     * ext / ext = 1) */
    for (size_t v = 0; v < mesh->num_vertices; ++v) {
        if (mesh->v_deleted[v] || mesh->v_halfedge[v] == SK_INVALID)
            continue;
        for (int k = 0; k < 2; ++k)
            uv[2 * v + (size_t)k] = (uv[2 * v + (size_t)k] - lo[k]) / ext;
    }
    return SK_OK;
}
