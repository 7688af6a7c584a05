/* Edge weights of the fixed-boundary linear methods: Tutte's uniform weights and the cotangent
 * (harmonic) weights; the dispatcher for all methods. */
#include "param_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

double sk__cot3(const double a[3], const double b[3], const double c[3])
{
    double u[3], v[3], x[3];
    sk__sub3(u, a, c);
    sk__sub3(v, b, c);
    sk__cross3(x, u, v);
    return sk__dot3(u, v) / sk__norm3(x);
}

void sk__weights_tutte(const sk_mesh *m, double *w)
{
    for (size_t h = 0; h < m->num_halfedges; ++h)
        w[h] = m->e_deleted[h >> 1] ? 0.0 : 1.0;
}

/* w_ij = (cot alpha_ij + cot beta_ij) / 2, alpha and beta the angles opposite edge ij (Pinkall &
 * Polthier; the Laplace-Beltrami normalisation 1/(2 A_i) of Meyer et al. -- printed "2/A" in
 * Botsch et al., see the papers README errata -- is left out: it scales each row and would make
 * the matrix non-symmetric, and it does not change the solution of L u = 0). The same value is
 * stored for both half-edges, so the matrix is exactly symmetric. */
void sk__weights_harmonic(const sk_mesh *m, double *w)
{
    for (size_t e = 0; e < sk_num_edges(m); ++e) {
        double c = 0;
        if (!m->e_deleted[e]) {
            for (uint32_t h = (uint32_t)(2 * e); h <= 2 * e + 1; ++h) {
                if (sk_is_boundary_h(m, h))
                    continue;
                uint32_t k = sk_to(m, sk_next(m, h));
                c += 0.5 * sk__cot3(m->positions + 3 * (size_t)sk_from(m, h),
                                    m->positions + 3 * (size_t)sk_to(m, h),
                                    m->positions + 3 * (size_t)k);
            }
        }
        w[2 * e] = w[2 * e + 1] = c;
    }
}

sk_status sk_param_weights(const sk_mesh *m, sk_param_method method, double *w, sk_error *err)
{
    memset(w, 0, m->num_halfedges * sizeof *w);
    switch (method) {
    case SK_PARAM_TUTTE: sk__weights_tutte(m, w); return SK_OK;
    case SK_PARAM_HARMONIC: sk__weights_harmonic(m, w); return SK_OK;
    case SK_PARAM_DEFAULT:
    case SK_PARAM_FLOATER: return sk__weights_floater(m, w, err);
    case SK_PARAM_MEAN_VALUE: sk__weights_mean_value(m, w); return SK_OK;
    case SK_PARAM_LSCM:
    case SK_PARAM_MIPS: break;
    }
    return sk__fail(err, SK_ERR_ARG, "method %s has no edge weights", sk_param_method_name(method));
}
