/* Boundary maps: the boundary loop onto a circle or a square, by chord length or uniformly. */
#include "surfkit/param.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>

/* Boundary loop as a vertex cycle, counter-clockwise around the surface (the loop of boundary
 * half-edges runs clockwise, so we walk it backwards). */
static sk_status ccw_loop(const sk_mesh *m, uint32_t **verts, size_t *count, sk_error *err)
{
    sk_loops loops = {0};
    sk_status st = sk_mesh_boundary_loops(m, &loops, err);
    if (st)
        return st;
    if (loops.count != 1) {
        sk_loops_free(&loops);
        return sk__fail(err, SK_ERR_TOPOLOGY, "the mesh has %zu boundary loops, a disk has one",
                        loops.count);
    }
    size_t nb = loops.offsets[1] - loops.offsets[0];
    uint32_t *v = sk__malloc_array(nb, sizeof *v);
    if (!v) {
        sk_loops_free(&loops);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t k = 0; k < nb; ++k) /* boundary half-edge h runs from(h) -> to(h), clockwise */
        v[k] = sk_to(m, loops.halfedges[loops.offsets[0] + (nb - 1 - k)]);
    sk_loops_free(&loops);
    *verts = v;
    *count = nb;
    return SK_OK;
}

/* An interior edge with both ends on one straight side of the square makes the triangles between
 * it and the side degenerate (every "ear" triangle is such a case), and Floater's bijectivity
 * theorem excludes it. Move corners (never the first) into such edges' spans until none is left
 * (a few passes; the meshes have a handful of these edges at most). c[0..4] are loop positions
 * with c[0] = 0 and c[4] = nb. */
static sk_status repair_corners(const sk_mesh *m, const uint32_t *rot, size_t nb, size_t c[5],
                                sk_error *err)
{
    size_t *pos = sk__malloc_array(m->num_vertices, sizeof *pos);
    if (!pos)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t v = 0; v < m->num_vertices; ++v)
        pos[v] = SIZE_MAX;
    for (size_t k = 0; k < nb; ++k)
        pos[rot[k]] = k;
    for (int pass = 0; pass < 32; ++pass) {
        bool changed = false;
        for (size_t k = 0; k < nb && !changed; ++k) {
            uint32_t v = rot[k], h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t j = sk_to(m, h);
                size_t pj = pos[j];
                if (pj != SIZE_MAX && pj > k && !sk_is_boundary_e(m, sk_edge(h))) {
                    /* the span (a, b) of the edge: (k, pj), or (pj, nb) when k is position 0 */
                    for (int rep = 0; rep < 2 && !changed; ++rep) {
                        size_t a = rep == 0 ? k : pj, b = rep == 0 ? pj : nb;
                        if (rep == 1 && k != 0)
                            break;
                        for (int s = 0; s < 4; ++s) {
                            if (!(c[s] <= a && b <= c[s + 1]) || b - a < 2)
                                continue;
                            size_t mid = (a + b) / 2;
                            int move = s == 0 ? 1 : s == 3 ? 3 : (a - c[s] < c[s + 1] - b ? s : s + 1);
                            c[move] = mid;
                            changed = true;
                            break;
                        }
                    }
                }
                h = sk_cw_out(m, h);
            } while (h != h0 && !changed);
        }
        if (!changed)
            break;
    }
    sk__free(pos);
    return SK_OK;
}

sk_status sk_param_boundary(const sk_mesh *m, const sk_boundary_opts *opts, double *uv,
                            sk_error *err)
{
    sk_boundary_opts o = {0};
    if (opts)
        o = *opts;
    if (o.shape == SK_BOUNDARY_GIVEN)
        return SK_OK;
    if (o.shape == SK_BOUNDARY_DEFAULT)
        o.shape = SK_BOUNDARY_CIRCLE;
    if (o.shape == SK_BOUNDARY_FREE)
        return sk__fail(err, SK_ERR_ARG, "a free boundary has no boundary map");
    uint32_t *loop = NULL;
    size_t nb = 0;
    sk_status st = ccw_loop(m, &loop, &nb, err);
    if (st)
        return st;
    double *t = sk__malloc_array(nb + 1, sizeof *t);
    uint32_t *rot = sk__malloc_array(nb, sizeof *rot);
    if (!t || !rot) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    /* rotate so that the start vertex comes first */
    size_t s0 = 0;
    if (o.has_start) {
        for (s0 = 0; s0 < nb && loop[s0] != o.start; ++s0)
            ;
        if (s0 == nb) {
            st = sk__fail(err, SK_ERR_ARG, "start vertex %u is not on the boundary", o.start);
            goto done;
        }
    }
    if (o.shape == SK_BOUNDARY_SQUARE && o.has_corners && !o.has_start) {
        for (s0 = 0; s0 < nb && loop[s0] != o.corners[0]; ++s0)
            ;
    }
    for (size_t k = 0; k < nb; ++k)
        rot[k] = loop[(s0 + k) % nb];
    /* cumulative parameter along the loop, t[0] = 0, t[nb] = total */
    t[0] = 0;
    for (size_t k = 0; k < nb; ++k) {
        double step = 1.0;
        if (o.spacing == SK_SPACING_CHORD)
            step = sk__dist3(m->positions + 3 * (size_t)rot[k],
                             m->positions + 3 * (size_t)rot[(k + 1) % nb]);
        t[k + 1] = t[k] + step;
    }
    double total = t[nb];
    if (!(total > 0)) {
        st = sk__fail(err, SK_ERR_TOPOLOGY, "the boundary loop has zero length");
        goto done;
    }
    if (o.shape == SK_BOUNDARY_CIRCLE) {
        for (size_t k = 0; k < nb; ++k) {
            double a = 2.0 * M_PI * t[k] / total;
            uv[2 * (size_t)rot[k]] = cos(a);
            uv[2 * (size_t)rot[k] + 1] = sin(a);
        }
    } else if (o.shape == SK_BOUNDARY_SQUARE) {
        if (nb < 4) {
            st = sk__fail(err, SK_ERR_TOPOLOGY, "a square boundary needs at least 4 boundary "
                          "vertices, the mesh has %zu", nb);
            goto done;
        }
        size_t c[5]; /* corner positions in rot, c[4] = nb */
        if (o.has_corners) {
            for (int i = 0; i < 4; ++i) {
                for (c[i] = 0; c[i] < nb && rot[c[i]] != o.corners[i]; ++c[i])
                    ;
                if (c[i] == nb || (i > 0 && c[i] <= c[i - 1])) {
                    st = sk__fail(err, SK_ERR_ARG, "square corner %u is not on the boundary or "
                                  "the corners are not in counter-clockwise boundary order",
                                  o.corners[i]);
                    goto done;
                }
            }
        } else {
            /* the vertex closest to quarter arc length, kept strictly increasing */
            c[0] = 0;
            for (int i = 1; i < 4; ++i) {
                double target = total * i / 4.0;
                size_t best = c[i - 1] + 1;
                for (size_t k = best; k < nb; ++k)
                    if (fabs(t[k] - target) < fabs(t[best] - target))
                        best = k;
                size_t limit = nb - (size_t)(4 - i); /* leave room for the remaining corners */
                c[i] = best > limit ? limit : best;
            }
        }
        c[4] = nb;
        if (!o.has_corners && (st = repair_corners(m, rot, nb, c, err)))
            goto done;
        static const double corner[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
        for (int i = 0; i < 4; ++i) {
            double t0 = t[c[i]], len = t[c[i + 1]] - t0;
            for (size_t k = c[i]; k < c[i + 1]; ++k) {
                double s = len > 0 ? (t[k] - t0) / len : 0;
                uv[2 * (size_t)rot[k]] = (1 - s) * corner[i][0] + s * corner[i + 1][0];
                uv[2 * (size_t)rot[k] + 1] = (1 - s) * corner[i][1] + s * corner[i + 1][1];
            }
        }
    } else {
        st = sk__fail(err, SK_ERR_ARG, "unknown boundary shape %d", (int)o.shape);
    }
done:
    sk__free(loop);
    sk__free(t);
    sk__free(rot);
    return st;
}
