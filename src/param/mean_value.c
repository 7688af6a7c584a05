/* Mean value coordinates (Floater 2003): w_ij = (tan(gamma_1 / 2) + tan(gamma_2 / 2)) / |p_j - p_i|,
 * gamma_1, gamma_2 the angles at p_i of the two triangles beside edge ij, normalised to sum 1. */
#include "param_internal.h"
#include "core/vec.h"

/* tan(gamma / 2) for the angle gamma between a and b: |a x b| / (|a||b| + a.b). */
static double tan_half(const double a[3], const double b[3])
{
    double x[3];
    sk__cross3(x, a, b);
    return sk__norm3(x) / (sk__norm3(a) * sk__norm3(b) + sk__dot3(a, b));
}

void sk__weights_mean_value(const sk_mesh *m, double *w)
{
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 4096)
#endif
    for (long vi = 0; vi < (long)m->num_vertices; ++vi) {
        uint32_t v = (uint32_t)vi;
        if (m->v_deleted[v] || sk_is_boundary_v(m, v))
            continue;
        const double *pi = m->positions + 3 * (size_t)v;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        double sum = 0;
        do {
            double e[3], a[3], b[3];
            sk__sub3(e, m->positions + 3 * (size_t)sk_to(m, h), pi);
            /* face of h: i -> j -> k; face of opp(h): j -> i -> l */
            sk__sub3(a, m->positions + 3 * (size_t)sk_to(m, sk_next(m, h)), pi);
            sk__sub3(b, m->positions + 3 * (size_t)sk_to(m, sk_next(m, sk_opp(h))), pi);
            double wij = (tan_half(e, a) + tan_half(e, b)) / sk__norm3(e);
            w[h] = wij;
            sum += wij;
            h = sk_cw_out(m, h);
        } while (h != h0);
        do {
            w[h] /= sum;
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
}
