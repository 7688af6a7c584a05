/* Boundary maps: the boundary loop onto a circle or a square, by chord length or uniformly. */
#include "surfkit/param.h"
#include "param/param_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sk_status sk__param_ccw_loop(const sk_mesh *m, uint32_t **verts, size_t *count, sk_error *err)
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

sk_status sk__param_check_corners(const uint32_t *loop, size_t nb, const uint32_t c[4],
                                  sk_error *err)
{
    size_t pos[4];
    for (int i = 0; i < 4; ++i) {
        for (pos[i] = 0; pos[i] < nb && loop[pos[i]] != c[i]; ++pos[i])
            ;
        if (pos[i] == nb)
            return sk__fail(err, SK_ERR_ARG, "corner %u is not a boundary vertex", c[i]);
    }
    /* counter-clockwise: the positions increase cyclically from the first corner */
    for (int i = 1; i < 4; ++i)
        if ((pos[i] + nb - pos[0]) % nb <= (pos[i - 1] + nb - pos[0]) % nb)
            return sk__fail(err, SK_ERR_ARG,
                            "the corners are not four distinct boundary vertices in "
                            "counter-clockwise order");
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
    sk_status st = sk__param_ccw_loop(m, &loop, &nb, err);
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

/* ---------------------------------------------------------------------------------------------
 * Square corners at the sharpest turns, and dividing edges split
 * ------------------------------------------------------------------------------------------- */

/* Sum of the face angles at boundary vertex v (pi on a straight stretch, pi/2 at a square
 * corner). */
static double interior_angle(const sk_mesh *m, uint32_t v)
{
    double sum = 0;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        if (!sk_is_boundary_h(m, h)) {
            uint32_t a = sk_to(m, h), b = sk_from(m, sk_prev(m, h));
            double e1[3], e2[3];
            sk__sub3(e1, m->positions + 3 * (size_t)a, m->positions + 3 * (size_t)v);
            sk__sub3(e2, m->positions + 3 * (size_t)b, m->positions + 3 * (size_t)v);
            sum += sk__angle3(e1, e2);
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    return sum;
}

sk_status sk_param_square_corners(const sk_mesh *m, uint32_t corners[4], sk_error *err)
{
    uint32_t *loop = NULL, *rot = NULL;
    size_t nb = 0;
    sk_status st = sk__param_ccw_loop(m, &loop, &nb, err);
    if (st)
        return st;
    double *arc = sk__malloc_array(nb + 1, sizeof *arc), *ang = sk__malloc_array(nb, sizeof *ang);
    rot = sk__malloc_array(nb, sizeof *rot);
    if (!arc || !ang || !rot) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    arc[0] = 0;
    for (size_t k = 0; k < nb; ++k) {
        arc[k + 1] = arc[k] + sk__dist3(m->positions + 3 * (size_t)loop[k],
                                        m->positions + 3 * (size_t)loop[(k + 1) % nb]);
        ang[k] = interior_angle(m, loop[k]);
    }
    /* smallest interior angle first, each at least sep of arc length (cyclically) from those
     * picked, sep = a sixth of the boundary, halved while four cannot be found */
    double L = arc[nb];
    size_t pos[4], got = 0;
    for (double sep = L / 6; got < 4 && sep > L / 64; sep /= 2) {
        got = 0;
        for (int pick = 0; pick < 4; ++pick) {
            size_t best = SIZE_MAX;
            for (size_t k = 0; k < nb; ++k) {
                bool ok = true;
                for (size_t q = 0; q < got && ok; ++q) {
                    double d = fabs(arc[k] - arc[pos[q]]);
                    ok = fmin(d, L - d) >= sep;
                }
                if (ok && (best == SIZE_MAX || ang[k] < ang[best]))
                    best = k;
            }
            if (best == SIZE_MAX)
                break;
            pos[got++] = best;
        }
    }
    if (got < 4) {
        st = sk__fail(err, SK_ERR_TOPOLOGY, "the boundary has %zu vertices: too few for four "
                      "square corners", nb);
        goto done;
    }
    for (int i = 0; i < 4; ++i) /* into loop order */
        for (int j = i + 1; j < 4; ++j)
            if (pos[j] < pos[i]) {
                size_t t = pos[i];
                pos[i] = pos[j];
                pos[j] = t;
            }
    /* the loop from the first corner on; then move corners into the spans of dividing edges
     * where that removes them (the rest sk_param_split_side_edges splits) */
    for (size_t k = 0; k < nb; ++k)
        rot[k] = loop[(pos[0] + k) % nb];
    size_t c[5] = {0, pos[1] - pos[0], pos[2] - pos[0], pos[3] - pos[0], nb};
    if ((st = repair_corners(m, rot, nb, c, err)))
        goto done;
    for (int i = 0; i < 4; ++i)
        corners[i] = rot[c[i]];
done:
    sk__free(loop);
    sk__free(rot);
    sk__free(arc);
    sk__free(ang);
    return st;
}

/* Loop positions of the corners (c[0] = 0 after rotating the loop to start there, c[4] = nb)
 * and every vertex's position (SIZE_MAX inside). */
static sk_status side_positions(const sk_mesh *m, const uint32_t corners[4], size_t **pos_out,
                                size_t c[5], sk_error *err)
{
    uint32_t *loop = NULL;
    size_t nb = 0;
    sk_status st = sk__param_ccw_loop(m, &loop, &nb, err);
    if (st)
        return st;
    size_t *pos = sk__malloc_array(m->num_vertices, sizeof *pos);
    if (!pos) {
        sk__free(loop);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    size_t s0 = 0;
    while (s0 < nb && loop[s0] != corners[0])
        ++s0;
    for (size_t v = 0; v < m->num_vertices; ++v)
        pos[v] = SIZE_MAX;
    for (size_t k = 0; k < nb; ++k)
        pos[loop[(s0 + k) % nb]] = k;
    c[0] = 0, c[4] = nb;
    for (int i = 0; i < 4 && !st; ++i) {
        if (corners[i] >= m->num_vertices || pos[corners[i]] == SIZE_MAX ||
            (i > 0 && pos[corners[i]] <= c[i - 1]))
            st = sk__fail(err, SK_ERR_ARG, "square corner %u is not on the boundary or the "
                          "corners are not in counter-clockwise boundary order", corners[i]);
        else
            c[i] = pos[corners[i]];
    }
    sk__free(loop);
    if (st) {
        sk__free(pos);
        return st;
    }
    *pos_out = pos;
    return SK_OK;
}

/* True when loop positions a and b lie on one side of the square (position 0 is also nb). */
static bool same_side(const size_t c[5], size_t a, size_t b)
{
    for (int s = 0; s < 4; ++s) {
        bool ina = (a >= c[s] && a <= c[s + 1]) || (s == 3 && a == 0);
        bool inb = (b >= c[s] && b <= c[s + 1]) || (s == 3 && b == 0);
        if (ina && inb)
            return true;
    }
    return false;
}

sk_status sk_param_split_side_edges(const sk_mesh *m, const uint32_t corners[4], sk_mesh **out,
                                    size_t *splits, sk_error *err)
{
    *out = NULL;
    if (splits)
        *splits = 0;
    size_t c[5], *pos = NULL, nv = m->num_vertices, ne = m->num_halfedges / 2, nsplit = 0;
    sk_status st = side_positions(m, corners, &pos, c, err);
    if (st)
        return st;
    uint32_t *mid = sk__malloc_array(ne ? ne : 1, sizeof *mid), *off = NULL, *idx = NULL;
    double *xyz = NULL;
    if (!mid) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t e = 0; e < ne; ++e) {
        uint32_t h = (uint32_t)(2 * e), a = sk_from(m, h), b = sk_to(m, h);
        mid[e] = SK_INVALID;
        if (a < nv && b < nv && !sk_is_boundary_e(m, (uint32_t)e) && pos[a] != SIZE_MAX &&
            pos[b] != SIZE_MAX && same_side(c, pos[a], pos[b]))
            mid[e] = (uint32_t)(nv + nsplit++);
    }
    /* each face becomes 1 + (its split edges) triangles, 4 at most */
    size_t nf = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f];
        size_t k = (mid[sk_edge(h)] != SK_INVALID) + (mid[sk_edge(sk_next(m, h))] != SK_INVALID) +
                   (mid[sk_edge(sk_prev(m, h))] != SK_INVALID);
        nf += 1 + k;
    }
    xyz = sk__malloc_array(3 * (nv + nsplit), sizeof *xyz);
    off = sk__malloc_array(nf + 1, sizeof *off);
    idx = sk__malloc_array(3 * nf, sizeof *idx);
    if (!xyz || !off || !idx) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    memcpy(xyz, m->positions, 3 * nv * sizeof *xyz);
    for (size_t e = 0; e < ne; ++e)
        if (mid[e] != SK_INVALID) {
            uint32_t a = sk_from(m, (uint32_t)(2 * e)), b = sk_to(m, (uint32_t)(2 * e));
            for (int k = 0; k < 3; ++k)
                xyz[3 * (size_t)mid[e] + (size_t)k] =
                    0.5 * (m->positions[3 * (size_t)a + (size_t)k] + m->positions[3 * (size_t)b + (size_t)k]);
        }
    size_t t = 0;
#define SK_TRI(x, y, z) (idx[3 * t] = (x), idx[3 * t + 1] = (y), idx[3 * t + 2] = (z), ++t)
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f];
        /* rotate (a, b, c) so that the split edges come first: ab, then bc */
        for (int r = 0; r < 3; ++r) {
            bool ab = mid[sk_edge(h)] != SK_INVALID, ca = mid[sk_edge(sk_prev(m, h))] != SK_INVALID;
            if ((ab && !ca) || (!ab && !ca && mid[sk_edge(sk_next(m, h))] == SK_INVALID) ||
                (ab && ca && mid[sk_edge(sk_next(m, h))] != SK_INVALID))
                break;
            h = sk_next(m, h);
        }
        uint32_t a = sk_from(m, h), b = sk_to(m, h), cc = sk_to(m, sk_next(m, h));
        uint32_t m1 = mid[sk_edge(h)], m2 = mid[sk_edge(sk_next(m, h))], m3 = mid[sk_edge(sk_prev(m, h))];
        if (m1 == SK_INVALID) {
            SK_TRI(a, b, cc);
        } else if (m2 == SK_INVALID) { /* ab split */
            SK_TRI(a, m1, cc);
            SK_TRI(m1, b, cc);
        } else if (m3 == SK_INVALID) { /* ab and bc split */
            SK_TRI(a, m1, m2);
            SK_TRI(m1, b, m2);
            SK_TRI(a, m2, cc);
        } else { /* all three */
            SK_TRI(a, m1, m3);
            SK_TRI(m1, b, m2);
            SK_TRI(m3, m2, cc);
            SK_TRI(m1, m2, m3);
        }
    }
#undef SK_TRI
    for (size_t i = 0; i <= nf; ++i)
        off[i] = (uint32_t)(3 * i);
    st = sk_mesh_from_faces(nv + nsplit, xyz, nf, off, idx, out, err);
    if (!st && splits)
        *splits = nsplit;
done:
    sk__free(pos);
    sk__free(mid);
    sk__free(xyz);
    sk__free(off);
    sk__free(idx);
    return st;
}
