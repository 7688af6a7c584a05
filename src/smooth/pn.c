/* PN triangles (Vlachos, Peters, Boyd, Mitchell 2001): one cubic triangle per mesh triangle from its
 * corner positions and normals. Only C0 across edges: the baseline that shows what the VC1
 * construction buys. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>
#include <string.h>

/* b_ij = (2 P_i + P_j - w_ij N_i) / 3 with w_ij = (P_j - P_i) . N_i */
static void pn_edge_point(const double *pi, const double *pj, const double *ni, double out[3])
{
    double d[3];
    sk__sub3(d, pj, pi);
    double w = sk__dot3(d, ni);
    for (int x = 0; x < 3; ++x)
        out[x] = (2.0 * pi[x] + pj[x] - w * ni[x]) / 3.0;
}

sk_status sk__pn_build(sk_smooth *s, sk_error *err)
{
    const sk_mesh *m = s->config;
    size_t nf = m->num_faces;
    s->num_patches = nf;
    s->num_points = 10 * nf;
    s->patches = sk__malloc_array(nf + 1, sizeof(sk_smooth_patch));
    s->points = sk__malloc_array(10 * nf + 1, 3 * sizeof(double));
    if (!s->patches || !s->points)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory building PN triangles");
    for (uint32_t f = 0; f < nf; ++f) {
        sk_smooth_patch *pa = s->patches + f;
        uint32_t h = m->f_halfedge[f];
        uint32_t c[3] = {sk_from(m, h), sk_to(m, h), sk_to(m, m->h_next[h])};
        pa->kind = SK_SMOOTH_TRIANGLE;
        pa->degree = 3;
        pa->first = 10 * f;
        pa->corners[0] = c[0], pa->corners[1] = c[1], pa->corners[2] = c[2];
        pa->corners[3] = SK_INVALID;
        double *b = s->points + 3 * (size_t)pa->first;
        const double *P[3], *N[3];
        for (int i = 0; i < 3; ++i) {
            P[i] = m->positions + 3 * (size_t)c[i];
            N[i] = s->normals + 3 * (size_t)c[i];
        }
        /* index (j, k) of b_{3-j-k, j, k} */
        memcpy(b + 3 * sk__tri_index(3, 0, 0), P[0], 3 * sizeof(double));
        memcpy(b + 3 * sk__tri_index(3, 3, 0), P[1], 3 * sizeof(double));
        memcpy(b + 3 * sk__tri_index(3, 0, 3), P[2], 3 * sizeof(double));
        pn_edge_point(P[0], P[1], N[0], b + 3 * sk__tri_index(3, 1, 0)); /* b210 */
        pn_edge_point(P[1], P[0], N[1], b + 3 * sk__tri_index(3, 2, 0)); /* b120 */
        pn_edge_point(P[1], P[2], N[1], b + 3 * sk__tri_index(3, 2, 1)); /* b021 */
        pn_edge_point(P[2], P[1], N[2], b + 3 * sk__tri_index(3, 1, 2)); /* b012 */
        pn_edge_point(P[2], P[0], N[2], b + 3 * sk__tri_index(3, 0, 2)); /* b102 */
        pn_edge_point(P[0], P[2], N[0], b + 3 * sk__tri_index(3, 0, 1)); /* b201 */
        double E[3] = {0, 0, 0}, V[3];
        size_t ids[6] = {sk__tri_index(3, 1, 0), sk__tri_index(3, 2, 0), sk__tri_index(3, 2, 1),
                         sk__tri_index(3, 1, 2), sk__tri_index(3, 0, 2), sk__tri_index(3, 0, 1)};
        for (int i = 0; i < 6; ++i)
            sk__add3(E, E, b + 3 * ids[i]);
        sk__scale3(E, E, 1.0 / 6.0);
        for (int x = 0; x < 3; ++x)
            V[x] = (P[0][x] + P[1][x] + P[2][x]) / 3.0;
        double *b111 = b + 3 * sk__tri_index(3, 1, 1);
        for (int x = 0; x < 3; ++x)
            b111[x] = E[x] + (E[x] - V[x]) / 2.0;
    }
    sk__ok(err);
    return SK_OK;
}
