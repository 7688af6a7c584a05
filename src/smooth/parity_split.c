/* Parity split (--allow-split): a closed component with an odd number of vertices has no edge
 * deletion (Cottin & van Damme, section 3: every vertex odd is impossible by Euler's formula); its
 * longest edge is split at the midpoint of its wire frame curve, which adds one vertex. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>
#include <string.h>

sk_status sk__split_odd_components(const sk_mesh *m, const double *normals, sk_mesh **out,
                                   double **out_normals, size_t *splits, sk_error *err)
{
    size_t nv = m->num_vertices, nh = m->num_halfedges;
    uint32_t *comp = sk__malloc_array(nv + 1, sizeof *comp);
    uint32_t *queue = sk__malloc_array(nv + 1, sizeof *queue);
    uint32_t *split_h = NULL;
    size_t nsplit = 0, cap_split = 0;
    sk_status st = SK_OK;
    *out = NULL;
    *out_normals = NULL;
    *splits = 0;
    if (!comp || !queue) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t v = 0; v < nv; ++v)
        comp[v] = SK_INVALID;
    for (uint32_t s = 0; s < nv; ++s) {
        if (comp[s] != SK_INVALID || m->v_deleted[s] || m->v_halfedge[s] == SK_INVALID)
            continue;
        size_t qh = 0, qt = 0, count = 0;
        bool boundary = false;
        uint32_t longest = SK_INVALID;
        double best = -1.0;
        comp[s] = s;
        queue[qt++] = s;
        while (qh < qt) {
            uint32_t v = queue[qh++];
            ++count;
            boundary |= sk_is_boundary_v(m, v);
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t w = sk_to(m, h);
                if (comp[w] == SK_INVALID) {
                    comp[w] = s;
                    queue[qt++] = w;
                }
                double len = sk_mesh_edge_length(m, sk_edge(h));
                if (len > best) {
                    best = len;
                    longest = h;
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
        if (!boundary && (count & 1u)) {
            if (nsplit == cap_split) {
                cap_split = cap_split ? 2 * cap_split : 8;
                uint32_t *p = sk__realloc_array(split_h, cap_split, sizeof *p);
                if (!p) {
                    st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                    goto done;
                }
                split_h = p;
            }
            split_h[nsplit++] = longest;
        }
    }
    if (nsplit == 0)
        goto done;
    {
        /* wire frame targets of the whole mesh (only the split edges are used) */
        double *target = sk__malloc_array(nh, 3 * sizeof(double));
        size_t nf = m->num_faces, nv2 = nv + nsplit;
        double *pos = sk__malloc_array(nv2, 3 * sizeof(double));
        double *nrm = sk__malloc_array(nv2, 3 * sizeof(double));
        uint32_t *off = sk__malloc_array(nf + 2 * nsplit + 1, sizeof(uint32_t));
        uint32_t *idx = sk__malloc_array(3 * (nf + 2 * nsplit), sizeof(uint32_t));
        uint32_t *fsplit = sk__malloc_array(nf + 1, sizeof(uint32_t));
        if (!target || !pos || !nrm || !off || !idx || !fsplit) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        } else if ((st = sk__wireframe_targets(m, normals, target, err)) == SK_OK) {
            memcpy(pos, m->positions, nv * 3 * sizeof(double));
            memcpy(nrm, normals, nv * 3 * sizeof(double));
            for (size_t f = 0; f < nf; ++f)
                fsplit[f] = SK_INVALID;
            for (size_t i = 0; i < nsplit; ++i) {
                uint32_t h = split_h[i], o = sk_opp(h);
                const double *a = m->positions + 3 * (size_t)sk_from(m, h);
                const double *b = m->positions + 3 * (size_t)sk_to(m, h);
                const double *pa = target + 3 * (size_t)h, *pb = target + 3 * (size_t)o;
                double *x = pos + 3 * (nv + i), *n = nrm + 3 * (nv + i), tan[3];
                for (int k = 0; k < 3; ++k) {
                    x[k] = (a[k] + 3.0 * pa[k] + 3.0 * pb[k] + b[k]) / 8.0; /* cubic at t = 1/2 */
                    tan[k] = b[k] + pb[k] - pa[k] - a[k];                   /* its tangent */
                }
                sk__add3(n, normals + 3 * (size_t)sk_from(m, h), normals + 3 * (size_t)sk_to(m, h));
                sk__normalize3(tan);
                sk__axpy3(n, n, -sk__dot3(n, tan), tan);
                sk__normalize3(n);
                fsplit[m->h_face[h]] = (uint32_t)i;
                fsplit[m->h_face[o]] = (uint32_t)i;
            }
            size_t k = 0, nfo = 0;
            off[0] = 0;
            for (uint32_t f = 0; f < nf; ++f) {
                if (m->f_deleted[f])
                    continue;
                uint32_t h = m->f_halfedge[f];
                if (fsplit[f] != SK_INVALID) {
                    uint32_t e = sk_edge(split_h[fsplit[f]]);
                    while (sk_edge(h) != e)
                        h = m->h_next[h];
                    uint32_t a = sk_from(m, h), b = sk_to(m, h), c = sk_to(m, m->h_next[h]);
                    uint32_t x = (uint32_t)(nv + fsplit[f]);
                    idx[k++] = a, idx[k++] = x, idx[k++] = c, off[++nfo] = (uint32_t)k;
                    idx[k++] = x, idx[k++] = b, idx[k++] = c, off[++nfo] = (uint32_t)k;
                } else {
                    idx[k++] = sk_from(m, h);
                    idx[k++] = sk_to(m, h);
                    idx[k++] = sk_to(m, m->h_next[h]);
                    off[++nfo] = (uint32_t)k;
                }
            }
            st = sk_mesh_from_faces(nv2, pos, nfo, off, idx, out, err);
            if (st == SK_OK) {
                *out_normals = nrm;
                nrm = NULL;
                *splits = nsplit;
            }
        }
        sk__free(target);
        sk__free(pos);
        sk__free(nrm);
        sk__free(off);
        sk__free(idx);
        sk__free(fsplit);
    }
done:
    sk__free(comp);
    sk__free(queue);
    sk__free(split_h);
    return st;
}