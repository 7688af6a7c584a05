/* Floater's shape-preserving weights (Floater 1997, reference [7] of Hormann, Greiner, Campagna).
 *
 * For each interior vertex V with neighbours W_1..W_d in order, the local exponential map of
 * section 1 of the hierarchical paper puts w_k at distance |W_k - V| from v = 0 and scales the
 * angles Gamma_k between consecutive edges to sum 2 pi:
 *     |w_k - v| = |W_k - V|,   gamma_k = 2 pi Gamma_k / sum_j Gamma_j.
 * For each l, the ray from w_l through v leaves the ring through a segment [w_r, w_r+1]; the
 * barycentric coordinates (mu_l, mu_r, mu_r+1) of v in the triangle (w_l, w_r, w_r+1) are
 * non-negative. Floater's weights are their average over l: lambda_k = (1/d) sum_l mu_k,l. */
#include "param_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>

sk_status sk__weights_floater(const sk_mesh *m, double *w, sk_error *err)
{
    size_t maxd = 0;
    for (size_t v = 0; v < m->num_vertices; ++v)
        if (!m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID) {
            size_t d = sk_mesh_valence(m, (uint32_t)v);
            if (d > maxd)
                maxd = d;
        }
    int fail = 0;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel reduction(| : fail)
#endif
    {
        /* per thread: q (2 per neighbour), lambda, half-edges */
        double *q = sk__malloc_array(3 * maxd + 1, sizeof(double));
        uint32_t *hs = sk__malloc_array(maxd + 1, sizeof(uint32_t));
        if (!q || !hs)
            fail = 1;
#if defined(SK_HAVE_OPENMP)
#pragma omp for schedule(dynamic, 4096)
#endif
        for (long vi = 0; vi < (long)m->num_vertices; ++vi) {
            uint32_t v = (uint32_t)vi;
            if (fail || m->v_deleted[v] || sk_is_boundary_v(m, v))
                continue;
            double *lambda = q + 2 * maxd;
            const double *pv = m->positions + 3 * (size_t)v;
            size_t d = 0;
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do {
                hs[d++] = h;
                h = sk_ccw_out(m, h);
            } while (h != h0);
            /* exponential map: lengths kept, angles scaled to 2 pi */
            double total = 0;
            for (size_t k = 0; k < d; ++k) {
                double a[3], b[3];
                sk__sub3(a, m->positions + 3 * (size_t)sk_to(m, hs[k]), pv);
                sk__sub3(b, m->positions + 3 * (size_t)sk_to(m, hs[(k + 1) % d]), pv);
                q[2 * k] = sk__angle3(a, b); /* Gamma_k, temporarily */
                total += q[2 * k];
            }
            double phi = 0;
            for (size_t k = 0; k < d; ++k) {
                double gamma = q[2 * k] * 2.0 * M_PI / total;
                double len = sk__dist3(m->positions + 3 * (size_t)sk_to(m, hs[k]), pv);
                q[2 * k] = len * cos(phi);
                q[2 * k + 1] = len * sin(phi);
                phi += gamma;
            }
            for (size_t k = 0; k < d; ++k)
                lambda[k] = 0;
            for (size_t l = 0; l < d; ++l) {
                /* the triangle (w_l, w_r, w_r+1) containing the origin: the one whose smallest
                 * barycentric coordinate of 0 is largest (>= 0 up to rounding) */
                double best = -INFINITY, bl = 0, br = 0, bs = 0;
                size_t brk = 0;
                const double *a = q + 2 * l;
                for (size_t r = 0; r < d; ++r) {
                    size_t s = (r + 1) % d;
                    if (r == l || s == l)
                        continue;
                    const double *b = q + 2 * r, *c = q + 2 * s;
                    double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                    if (!(area > 0))
                        continue;
                    double cl = sk__cross2(b, c), cr = sk__cross2(c, a), cs = sk__cross2(a, b);
                    /* the smallest coordinate with one division: x -> x / area (area > 0) is
                     * monotone, and so is its rounding, so min(x / area) = min(x) / area */
                    double mn = fmin(cl, fmin(cr, cs)) / area;
                    if (mn > best) {
                        best = mn;
                        bl = cl / area;
                        br = cr / area;
                        bs = cs / area;
                        brk = r;
                    }
                }
                if (best == -INFINITY) { /* cannot happen for a valid ring; fall back to uniform */
                    for (size_t k = 0; k < d; ++k)
                        lambda[k] += 1.0 / (double)d;
                    continue;
                }
                /* clamp rounding-level negatives and renormalise */
                bl = fmax(bl, 0);
                br = fmax(br, 0);
                bs = fmax(bs, 0);
                double sum = bl + br + bs;
                lambda[l] += bl / sum;
                lambda[brk] += br / sum;
                lambda[(brk + 1) % d] += bs / sum;
            }
            for (size_t k = 0; k < d; ++k)
                w[hs[k]] = lambda[k] / (double)d;
        }
        sk__free(q);
        sk__free(hs);
    }
    if (fail)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    return SK_OK;
}
