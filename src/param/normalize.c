/* Normalization of a parametrization to the unit square (uniform scale and translation). */
#include "surfkit/param.h"
#include "core/internal.h"

#include <limits.h>
#include <math.h>

/* Faces from which the bounding box and the scaling run in parallel (min and max do not depend
 * on the order: the same result for any thread count). */
#define SK_NORMALIZE_PARALLEL 50000

sk_status sk_param_normalize(const sk_mesh *mesh, double *uv, sk_error *err)
{
    double lo0 = INFINITY, lo1 = INFINITY, hi0 = -INFINITY, hi1 = -INFINITY;
    size_t used = 0;
    long bad = LONG_MAX; /* the first face with a non-finite uv */
    long nf = (long)mesh->num_faces;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(min : lo0, lo1, bad) \
    reduction(max : hi0, hi1) reduction(+ : used) if (nf > SK_NORMALIZE_PARALLEL)
#endif
    for (long f = 0; f < nf; ++f) {
        if (mesh->f_deleted[f])
            continue;
        uint32_t h0 = mesh->f_halfedge[f], h = h0;
        do {
            const double *q = uv + 2 * (size_t)mesh->h_vertex[h];
            if (!isfinite(q[0]) || !isfinite(q[1]))
                bad = f < bad ? f : bad;
            lo0 = fmin(lo0, q[0]);
            hi0 = fmax(hi0, q[0]);
            lo1 = fmin(lo1, q[1]);
            hi1 = fmax(hi1, q[1]);
            used++;
            h = mesh->h_next[h];
        } while (h != h0);
    }
    if (bad != LONG_MAX) { /* the first such vertex in face order, as a sequential scan */
        uint32_t h0 = mesh->f_halfedge[bad], h = h0;
        do {
            const double *q = uv + 2 * (size_t)mesh->h_vertex[h];
            if (!isfinite(q[0]) || !isfinite(q[1]))
                break;
            h = mesh->h_next[h];
        } while (h != h0);
        return sk__fail(err, SK_ERR_NUMERIC, "vertex %u has a non-finite uv", mesh->h_vertex[h]);
    }
    if (!used)
        return SK_OK;
    double lo[2] = {lo0, lo1};
    double ext = fmax(hi0 - lo0, hi1 - lo1);
    if (!(ext > 0.0) || !isfinite(ext))
        return sk__fail(err, SK_ERR_NUMERIC, "the uv of every vertex is the same point");
    /* (u - lo) / ext: the division keeps the result in [0, 1] exactly (monotone rounding, and
     * ext / ext = 1) */
    long nv = (long)mesh->num_vertices;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) if (nf > SK_NORMALIZE_PARALLEL)
#endif
    for (long v = 0; v < nv; ++v) {
        if (mesh->v_deleted[v] || mesh->v_halfedge[v] == SK_INVALID)
            continue;
        for (int k = 0; k < 2; ++k)
            uv[2 * v + k] = (uv[2 * v + k] - lo[k]) / ext;
    }
    return SK_OK;
}
