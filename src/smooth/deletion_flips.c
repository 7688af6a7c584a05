/* Edge flips chosen for the edge deletion of the VC1 construction (after the deletion, before the
 * patches; vc1.c, deletion_flips, runs the deletion again on the flipped base and keeps a pass
 * only when it deletes fewer edges at a lower deleted / bound).
 *
 * The deleted set D is a T-join of the even interior vertices T (Cottin & van Damme, section 3:
 * a vertex is fixed when an odd number of its edges is deleted), with at most one deleted edge per
 * triangle. The flip of the kept edge ab between the triangles abc and bad to cd changes the
 * valence, and so the parity, of a, b (one face less) and c, d (one more): T becomes
 * T xor {a, b, c, d}, and D xor J is a deletion of the flipped mesh for any J whose odd vertices
 * are a, b, c, d; the smallest such J among the sides of the quad acbd are two opposite sides,
 * {ac, bd} or {ad, bc}. Two kinds of flip:
 *   - both opposite sides deleted (a gain): D xor J has two edges fewer. The new triangles adc,
 *     bcd hold no deleted edge (ad, bc shared a triangle with ac or bd, so they were kept), so
 *     every face stays a triangle or a quad and no quad changes shape (the quad-corner limit of
 *     edge_deletion.c still holds). The bound ceil(|T| / 2) moves by (odd - even) / 2 over
 *     a, b, c, d: taken when deleted / bound drops (not when all four are even);
 *   - one side of the quad deleted (a move): D xor J has as many edges; taken when the even
 *     vertices do not get fewer (the bound does not drop), one per quad. It changes which
 *     vertices are even next to a path of D, and the deletion run again (from nothing, or from
 *     D with the quad sides of the moves taken out) may pair them more cheaply: on the shared
 *     meshes a move with a side deleted gained, moves at any vertex of D, or moves that make
 *     two even vertices odd, lost more than they gained (measured in session 35).
 * A flip keeps the quality of the flip pass (sk__deletion_flip_ok, edge_flips.c): no sliver
 * (the smallest angle keeps 0.8 of what it was), no crease (the new edge bends at most 10
 * degrees), no face that agrees worse with its corner normals, valence at most 12, nothing next
 * to a crease vertex or on the boundary. Every vertex is kept, so every vertex and normal is
 * still interpolated. Edges are tried in id order, once per call: deterministic. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"

#include <string.h>

sk_status sk__deletion_flips(sk_mesh *m, const double *normals, const uint8_t *keep,
                             const uint32_t *deleted, size_t ndel, size_t even, uint32_t **flips,
                             size_t *flipped, uint32_t **hint, size_t *nhint, sk_error *err)
{
    if (hint)
        *hint = NULL;
    size_t ne = sk_num_edges(m), nv = m->num_vertices, count = 0;
    *flipped = 0;
    *flips = NULL;
    uint8_t *dflag = sk__calloc_array(ne + 1, 1), *noparity = sk__malloc_array(nv + 1, 1);
    uint8_t *crease_v = sk__calloc_array(nv + 1, 1);
    uint32_t *log = sk__malloc_array(ne + 1, sizeof *log);
    if (!dflag || !noparity || !crease_v || !log) {
        sk__free(log);
        sk__free(dflag);
        sk__free(noparity);
        sk__free(crease_v);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the deletion flips");
    }
    for (size_t i = 0; i < ndel; ++i) {
        uint32_t h = sk__find_halfedge(m, deleted[2 * i], deleted[2 * i + 1]);
        if (h != SK_INVALID)
            dflag[sk_edge(h)] = 1;
    }
    /* as the parity pass (edge_flips.c): boundary and crease vertices, and the crease vertices'
     * neighbours, are left alone */
    sk__flip_noparity(m, keep, noparity, crease_v);
    size_t nd = ndel, nt = even;
    for (uint32_t e = 0; e < ne; ++e) {
        if (m->e_deleted[e] || dflag[e] || sk_is_boundary_e(m, e) || (keep && keep[e]))
            continue;
        uint32_t h = 2 * e, o = h + 1;
        /* h: a -> b in abc (next b -> c, prev c -> a); o: b -> a in bad (next a -> d, prev
         * d -> b) */
        uint32_t ca = sk_edge(m->h_prev[h]), bc = sk_edge(m->h_next[h]);
        uint32_t ad = sk_edge(m->h_next[o]), db = sk_edge(m->h_prev[o]);
        uint32_t j1, j2;
        bool neutral = false;
        if (dflag[ca] && dflag[db])
            j1 = ca, j2 = db;
        else if (dflag[bc] && dflag[ad])
            j1 = bc, j2 = ad;
        else if (dflag[ca] || dflag[db] || dflag[bc] || dflag[ad])
            neutral = true, j1 = j2 = 0;
        else
            continue;
        uint32_t q[4] = {sk_from(m, h), sk_to(m, h), sk_to(m, m->h_next[h]),
                         sk_to(m, m->h_next[o])};
        if (noparity[q[0]] || noparity[q[1]] || noparity[q[2]] || noparity[q[3]])
            continue;
        long dt = 0; /* change of |T|: an odd vertex becomes even, an even one odd */
        for (int i = 0; i < 4; ++i)
            dt += (sk_mesh_valence(m, q[i]) & 1u) ? 1 : -1;
        size_t nt2 = (size_t)((long)nt + dt);
        size_t b = (nt + 1) / 2, b2 = (nt2 + 1) / 2;
        if (neutral) {
            if (dt < 0 || !sk__deletion_flip_ok(m, normals, noparity, h))
                continue;
            sk__flip_edge(m, h);
            log[count++] = h;
            dflag[ca] = dflag[db] = dflag[bc] = dflag[ad] = 0;
            for (int i = 0; i < 4; ++i)
                noparity[q[i]] = 1; /* one neutral flip per quad */
            nt = nt2;
            continue;
        }
        /* (nd - 2) / b2 < nd / b, the deleted count drops by 2 */
        if (b2 == 0 || !((double)(nd - 2) * (double)b < (double)nd * (double)b2) ||
            !sk__deletion_flip_ok(m, normals, noparity, h))
            continue;
        sk__flip_edge(m, h);
        log[count++] = h;
        dflag[j1] = dflag[j2] = 0;
        nd -= 2;
        nt = nt2;
    }
    sk_status st = SK_OK;
    if (hint && count && !(*hint = sk__malloc_array(2 * ndel + 1, sizeof **hint)))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in the deletion flips");
    if (hint && *hint) {
        size_t k = 0;
        for (uint32_t e = 0; e < ne; ++e) {
            if (!dflag[e])
                continue;
            (*hint)[2 * k] = sk_from(m, 2 * e);
            (*hint)[2 * k + 1] = sk_to(m, 2 * e);
            ++k;
        }
        *nhint = k;
    }
    *flipped = count;
    *flips = log;
    sk__free(dflag);
    sk__free(noparity);
    sk__free(crease_v);
    if (st == SK_OK)
        sk__ok(err);
    return st;
}
