/* Regularity repair of the VC1 construction. */
#include "smooth/vc1_internal.h"
#include "core/internal.h"

#include <stdlib.h>
#include <string.h>

/* Every solution of the vertex systems (8) with the interior points of (4)
 * gives a VC1 surface, so the free choices (here: the targets a vertex system is fitted to) can
 * be spent on patch quality. For every corner vertex of a patch that the report's regularity test
 * finds singular, the vertex system is re-solved with varied targets (directions blended towards
 * an even spread, lengths scaled); the variant with the fewest singular patches among the faces
 * whose control points it moves (the faces around the vertex and its neighbours) is kept if it
 * has fewer than the plain construction. Sequential in vertex order: deterministic. */

static const double repair_variants[][2] = {
    /* blend, length scale */
    {0.25, 1.0}, {0.5, 1.0}, {1.0, 1.0}, {0.0, 0.75}, {0.0, 1.3}, {0.5, 0.75}, {0.5, 1.3},
    {0.0, 0.55}, {0.0, 1.7}, {1.0, 0.7},
    /* six more (measured: mushroom 2 -> 0 singular patches, armadillo 19 -> 14, cow 44 -> 41;
     * a third round gained nothing) */
    {0.25, 0.75}, {0.25, 1.3}, {1.0, 1.3}, {0.0, 0.4}, {0.5, 0.55}, {0.0, 2.2},
};
#define N_VARIANTS (sizeof repair_variants / sizeof repair_variants[0])

/* faces around v and around its neighbours, deduplicated with the marks array (cleared after) */
static size_t local_faces(const sk_mesh *m, uint32_t v, uint8_t *mark, uint32_t *faces,
                          size_t cap, uint32_t *verts, size_t *nverts)
{
    size_t nf = 0, nvv = 0;
    verts[nvv++] = v;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        verts[nvv++] = sk_to(m, h);
        h = sk_cw_out(m, h);
    } while (h != h0 && nvv < SK_VSYS_MAX + 1);
    for (size_t i = 0; i < nvv; ++i) {
        uint32_t g0 = m->v_halfedge[verts[i]], g = g0;
        do {
            uint32_t f = m->h_face[g];
            if (f != SK_INVALID && !mark[f] && nf < cap) {
                mark[f] = 1;
                faces[nf++] = f;
            }
            g = sk_cw_out(m, g);
        } while (g != g0);
    }
    for (size_t i = 0; i < nf; ++i)
        mark[faces[i]] = 0;
    *nverts = nvv;
    return nf;
}

/* Rebuilds the patches of faces after new vertex solutions at verts and counts the singular
 * ones, stopping once the count reaches limit (the variant cannot win then; the patches are all
 * assembled either way). faces lists the ones singular before first, so a losing variant is
 * usually found out after a few tests. */
static size_t rebuild_local(sk_smooth *s, sk__vc1_work *W, const uint32_t *verts, size_t nverts,
                            const uint32_t *faces, size_t nf, size_t limit)
{
    for (size_t i = 0; i < nverts; ++i)
        sk__vc1_interior_points(W, verts[i]);
    for (size_t i = 0; i < nf; ++i)
        sk__vc1_assemble_patch(W, faces[i], sk_patch_cp(&s->surface, faces[i]));
    size_t bad = 0;
    for (size_t i = 0; i < nf && bad < limit; ++i)
        bad += sk__patch_singular(s, faces[i], NULL);
    return bad;
}

#define LOCAL_FACES 4096

sk_status sk__vc1_repair_regularity(sk_smooth *s, sk__vc1_work *W, uint8_t *status,
                                    const uint8_t *known, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t np = s->surface.count, nv = m->num_vertices;
    uint8_t *sing = sk__malloc_array(np + 1, 1), *cand = sk__calloc_array(nv + 1, 1), *mark = sk__calloc_array(np + 1, 1);
    uint32_t *faces = sk__malloc_array(LOCAL_FACES, sizeof *faces);
    if (!sing || !cand || !mark || !faces) {
        sk__free(sing);
        sk__free(cand);
        sk__free(mark);
        sk__free(faces);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the regularity repair");
    }
    long npl = (long)np;
    size_t nsing = 0;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : nsing)
#endif
    for (long p = 0; p < npl; ++p) {
        sing[p] = known && known[p] != SK_SING_UNKNOWN ? known[p]
                                                       : sk__patch_singular(s, (size_t)p, NULL);
        nsing += sing[p];
    }
    s->stats.singular_before_repair = nsing;
    for (size_t p = 0; p < np && nsing; ++p)
        if (sing[p])
            for (unsigned i = 0; i < sk_patch_num_corners(&s->surface.patches[p]); ++i)
                cand[s->surface.patches[p].corner_ids[i]] = 1;
    size_t repaired = 0;
    for (int round = 0; round < 2 && nsing; ++round) {
    if (round == 1) {
        /* second round: the corners of the patches still singular and their neighbours */
        memset(cand, 0, nv);
        for (size_t p = 0; p < np; ++p)
            if (sing[p])
                for (unsigned i = 0; i < sk_patch_num_corners(&s->surface.patches[p]); ++i) {
                    uint32_t c = s->surface.patches[p].corner_ids[i], h0 = m->v_halfedge[c];
                    uint32_t h = h0;
                    cand[c] = 1;
                    do {
                        cand[sk_to(m, h)] = 1;
                        h = sk_cw_out(m, h);
                    } while (h != h0);
                }
    }
    for (uint32_t v = 0; v < nv && nsing; ++v) {
        if (!cand[v] || status[v] == 3)
            continue;
        uint32_t verts[SK_VSYS_MAX + 1];
        size_t nverts;
        size_t nf = local_faces(m, v, mark, faces, LOCAL_FACES, verts, &nverts);
        size_t before = 0;
        for (size_t i = 0; i < nf; ++i)
            if (sing[faces[i]]) { /* the singular faces first (see rebuild_local) */
                uint32_t t = faces[before];
                faces[before++] = faces[i];
                faces[i] = t;
            }
        if (before == 0)
            continue;
        /* the plain solution of v, to restore */
        uint32_t E[SK_VSYS_MAX];
        int closed, n = sk__vc1_ordered_edges(m, v, E, &closed);
        double P0[3 * SK_VSYS_MAX], w0[SK_VSYS_MAX];
        for (int k = 0; k < n; ++k) {
            memcpy(P0 + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
            w0[k] = W->w1[E[k]];
        }
        size_t best = before;
        int best_variant = -1, best_code = status[v];
        sk__vsys sys;
        for (int t = 0; t < (int)N_VARIANTS; ++t) {
            int code = sk__vc1_solve_vertex(W, v, &sys, repair_variants[t][0],
                                            repair_variants[t][1]);
            if (code > status[v] || code >= 2)
                continue; /* never trade regularity for an angle violation or a failed system */
            size_t after = rebuild_local(s, W, verts, nverts, faces, nf, best);
            if (after < best) {
                best = after;
                best_variant = t;
                best_code = code;
            }
            if (best == 0)
                break; /* nothing left to gain: the later variants cannot do better */
        }
        if (best_variant >= 0) {
            sk__vc1_solve_vertex(W, v, &sys, repair_variants[best_variant][0],
                                 repair_variants[best_variant][1]);
            status[v] = (uint8_t)best_code;
            ++repaired;
        } else {
            for (int k = 0; k < n; ++k) {
                memcpy(W->P + 3 * (size_t)E[k], P0 + 3 * k, 3 * sizeof(double));
                W->w1[E[k]] = w0[k];
            }
        }
        rebuild_local(s, W, verts, nverts, faces, nf, 0);
        /* restored: the same solution gives the same patches, their flags stand */
        for (size_t i = 0; i < nf && best_variant >= 0; ++i) {
            uint8_t now = sk__patch_singular(s, faces[i], NULL);
            nsing = nsing - sing[faces[i]] + now;
            sing[faces[i]] = now;
        }
    }
    }
    s->stats.repaired_vertices = repaired;
    sk__free(sing);
    sk__free(cand);
    sk__free(mark);
    sk__free(faces);
    return SK_OK;
}
