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

/* The cubic triangle of face f (corners c, control points into b). */
static void pn_patch(const sk_smooth *s, const uint32_t c[3], double *b)
{
    const sk_mesh *m = s->config;
    const double *P[3], *N[3];
    for (int i = 0; i < 3; ++i) {
        P[i] = m->positions + 3 * (size_t)c[i];
        N[i] = s->normals + 3 * (size_t)c[i];
    }
    /* index (j, k) of b_{3-j-k, j, k} */
    memcpy(b + 3 * sk_tri_index(3, 0, 0), P[0], 3 * sizeof(double));
    memcpy(b + 3 * sk_tri_index(3, 3, 0), P[1], 3 * sizeof(double));
    memcpy(b + 3 * sk_tri_index(3, 0, 3), P[2], 3 * sizeof(double));
    pn_edge_point(P[0], P[1], N[0], b + 3 * sk_tri_index(3, 1, 0)); /* b210 */
    pn_edge_point(P[1], P[0], N[1], b + 3 * sk_tri_index(3, 2, 0)); /* b120 */
    pn_edge_point(P[1], P[2], N[1], b + 3 * sk_tri_index(3, 2, 1)); /* b021 */
    pn_edge_point(P[2], P[1], N[2], b + 3 * sk_tri_index(3, 1, 2)); /* b012 */
    pn_edge_point(P[2], P[0], N[2], b + 3 * sk_tri_index(3, 0, 2)); /* b102 */
    pn_edge_point(P[0], P[2], N[0], b + 3 * sk_tri_index(3, 0, 1)); /* b201 */
    double E[3] = {0, 0, 0}, V[3];
    const unsigned ids[6] = {sk_tri_index(3, 1, 0), sk_tri_index(3, 2, 0), sk_tri_index(3, 2, 1),
                             sk_tri_index(3, 1, 2), sk_tri_index(3, 0, 2), sk_tri_index(3, 0, 1)};
    for (int i = 0; i < 6; ++i)
        sk__add3(E, E, b + 3 * ids[i]);
    sk__scale3(E, E, 1.0 / 6.0);
    for (int x = 0; x < 3; ++x)
        V[x] = (P[0][x] + P[1][x] + P[2][x]) / 3.0;
    double *b111 = b + 3 * sk_tri_index(3, 1, 1);
    for (int x = 0; x < 3; ++x)
        b111[x] = E[x] + (E[x] - V[x]) / 2.0;
}

sk_status sk__pn_build(sk_smooth *s, sk_error *err)
{
    const sk_mesh *m = s->config;
    size_t nf = m->num_faces;
    sk_status st = sk_patch_set_reserve(&s->surface, nf, 10 * nf, err);
    for (uint32_t f = 0; f < nf && st == SK_OK; ++f) {
        uint32_t h = m->f_halfedge[f];
        uint32_t c[3] = {sk_from(m, h), sk_to(m, h), sk_to(m, m->h_next[h])};
        if ((st = sk__patch_set_add_tagged(&s->surface, SK_PATCH_TRIANGLE, 3, 0, NULL, c, f,
                                           err)) != SK_OK)
            break;
        pn_patch(s, c, sk_patch_cp(&s->surface, f));
    }
    if (st == SK_OK)
        sk__ok(err);
    return st;
}
