/* Refinement of the VC1 base beyond the input: 1-to-4 midpoint splits of the triangulation the
 * edge deletion runs on (after the flips, the normal refits and the crease detection on the
 * input), so that the VC1 surface can come closer to the input's flat facets than the surface
 * over the input's own vertices does (issue 13: at 1e-3 of the diagonal that surface misses on
 * cow, pig, lion-head and armadillo).
 *
 * The new vertices lie on the base's edges, so the mesh being interpolated is still the base
 * surface; their normals come from the facets (the normalised sum of the two unit face normals
 * of the edge, the face's on a boundary edge); the old vertices keep theirs. The structure the
 * construction derives from the triangulation is inherited, not derived again on the refined
 * mesh: both halves of a crease edge are crease edges, no new edge is one, and the refined mesh
 * is not flipped. Deriving it again is what broke VC1 over a midpoint-refined cow
 * (`surfkit subdivide --scheme midpoint` then `smooth`): the crease detection works in rings of
 * faces, so on the refined mesh its smooth side regions (3 rings) shrink to half their size and
 * it finds 543 crease edges instead of 13 (2822 after two refinements, where two crease-sector
 * systems fail to converge), the Delaunay flips act on coplanar pairs of sub-triangles, and the
 * fold refits and bad-face flips that make the input's folds (hooves, tail tip) buildable cannot
 * act on the halved edges. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

/* the unit normal of triangle f of m (zero for a degenerate one) */
static void face_unit_normal(const sk_mesh *m, uint32_t f, double n[3])
{
    uint32_t h = m->f_halfedge[f];
    const double *a = m->positions + 3 * (size_t)sk_from(m, h);
    const double *b = m->positions + 3 * (size_t)sk_to(m, h);
    const double *c = m->positions + 3 * (size_t)sk_to(m, m->h_next[h]);
    double u[3], v[3];
    sk__sub3(u, b, a);
    sk__sub3(v, c, a);
    sk__cross3(n, u, v);
    if (sk__normalize3(n) == 0.0)
        n[0] = n[1] = n[2] = 0.0;
}

/* the squared distance between vertices a and b of the soup */
static double dist2(const double *pos, uint32_t a, uint32_t b)
{
    double d[3];
    sk__sub3(d, pos + 3 * (size_t)a, pos + 3 * (size_t)b);
    return sk__dot3(d, d);
}

/* Triangle (t[0], t[1], t[2]) of the base with its edges' midpoints mid[0..2] (mid[i] on edge
 * t[i] t[i+1], SK_INVALID when that edge is not split) as 1 to 4 triangles of the soup: all three
 * split, the four of the midpoint rule; two, the corner triangle at their common vertex and the
 * quad left split along its shorter diagonal; one, two triangles through the opposite vertex. */
static sk_status split_triangle(sk_soup *soup, const uint32_t t[3], const uint32_t mid[3])
{
    int n = (mid[0] != SK_INVALID) + (mid[1] != SK_INVALID) + (mid[2] != SK_INVALID), r = 0;
    if (n == 3) {
        uint32_t f[4][3] = {{t[0], mid[0], mid[2]}, {t[1], mid[1], mid[0]},
                            {t[2], mid[2], mid[1]}, {mid[0], mid[1], mid[2]}};
        for (int i = 0; i < 4; ++i) {
            sk_status st = sk_soup_push_face(soup, f[i], 3);
            if (st)
                return st;
        }
        return SK_OK;
    }
    if (n == 0)
        return sk_soup_push_face(soup, t, 3);
    if (n == 2) { /* rotate the edge left whole to t[r] t[r+1] */
        while (mid[r] != SK_INVALID)
            ++r;
    } else {      /* rotate the split edge to t[r] t[r+1] */
        while (mid[r] == SK_INVALID)
            ++r;
    }
    uint32_t a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
    uint32_t f[3][3];
    int nf = 0;
    if (n == 2) {
        uint32_t m1 = mid[(r + 1) % 3], m2 = mid[(r + 2) % 3]; /* on b c and on c a */
        f[nf][0] = c, f[nf][1] = m2, f[nf][2] = m1, ++nf;
        if (dist2(soup->positions, a, m1) <= dist2(soup->positions, b, m2)) {
            f[nf][0] = a, f[nf][1] = b, f[nf][2] = m1, ++nf;
            f[nf][0] = a, f[nf][1] = m1, f[nf][2] = m2, ++nf;
        } else {
            f[nf][0] = a, f[nf][1] = b, f[nf][2] = m2, ++nf;
            f[nf][0] = b, f[nf][1] = m1, f[nf][2] = m2, ++nf;
        }
    } else {
        uint32_t m0 = mid[r];
        f[nf][0] = a, f[nf][1] = m0, f[nf][2] = c, ++nf;
        f[nf][0] = m0, f[nf][1] = b, f[nf][2] = c, ++nf;
    }
    for (int i = 0; i < nf; ++i) {
        sk_status st = sk_soup_push_face(soup, f[i], 3);
        if (st)
            return st;
    }
    return SK_OK;
}

sk_status sk__refine_base_split(const sk_mesh *base, const double *normals, const uint8_t *split,
                                const uint32_t *creases, size_t ncreases, sk_mesh **out,
                                double **out_normals, uint32_t **out_creases, size_t *out_ncreases,
                                size_t *out_split, sk_error *err)
{
    *out = NULL;
    *out_normals = NULL;
    *out_creases = NULL;
    *out_ncreases = 0;
    *out_split = 0;
    size_t nv = base->num_vertices, ne = sk_num_edges(base), nf = base->num_faces;
    for (size_t v = 0; v < nv; ++v)
        if (base->v_deleted[v])
            return sk__fail(err, SK_ERR_ARG, "refine_base: the base has deleted vertices");
    for (size_t f = 0; f < nf; ++f)
        if (base->f_deleted[f] || sk_mesh_face_size(base, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_ARG, "refine_base: the base must be a triangle mesh");
    uint32_t *mid = sk__malloc_array(ne + 1, sizeof(uint32_t));
    double *n2 = NULL;
    uint32_t *c2 = sk__malloc_array(4 * ncreases + 1, sizeof(uint32_t));
    sk_soup *soup = NULL;
    sk_mesh *r = NULL;
    sk_status st =
        mid && c2 ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory refining the base");
    size_t nnew = 0;
    for (size_t e = 0; st == SK_OK && e < ne; ++e)
        mid[e] = split[e] && !base->e_deleted[e] ? (uint32_t)(nv + nnew++) : SK_INVALID;
    if (st == SK_OK && nv + nnew >= UINT32_MAX)
        st = sk__fail(err, SK_ERR_ARG, "refined base too large for 32-bit indices");
    if (st == SK_OK && !(n2 = sk__malloc_array(nv + nnew + 1, 3 * sizeof(double))))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory refining the base");
    if (st == SK_OK)
        st = sk_soup_create(nv + nnew, nf + 3 * nnew, 3 * (nf + 3 * nnew), false, false, &soup,
                            err);
    for (size_t v = 0; st == SK_OK && v < nv; ++v)
        st = sk_soup_push_vertex(soup, base->positions + 3 * v, NULL, NULL);
    if (st == SK_OK)
        memcpy(n2, normals, nv * 3 * sizeof(double));
    for (size_t e = 0; st == SK_OK && e < ne; ++e) {
        if (mid[e] == SK_INVALID)
            continue;
        uint32_t a = sk_from(base, (uint32_t)(2 * e)), b = sk_to(base, (uint32_t)(2 * e));
        const double *pa = base->positions + 3 * (size_t)a, *pb = base->positions + 3 * (size_t)b;
        double p[3] = {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])};
        double *n = n2 + 3 * (size_t)mid[e], fn[3];
        n[0] = n[1] = n[2] = 0.0;
        for (uint32_t k = 0; k < 2; ++k) {
            uint32_t f = base->h_face[2 * e + k];
            if (f == SK_INVALID)
                continue;
            face_unit_normal(base, f, fn);
            sk__add3(n, n, fn);
        }
        if (sk__normalize3(n) == 0.0) /* the facets cancel: the ends' normals */
            sk__add3(n, normals + 3 * (size_t)a, normals + 3 * (size_t)b);
        if (sk__normalize3(n) == 0.0)
            st = sk__fail(err, SK_ERR_NUMERIC,
                          "refine_base: edge (%u, %u) has no normal for its midpoint", a, b);
        else
            st = sk_soup_push_vertex(soup, p, NULL, NULL);
    }
    for (size_t f = 0; st == SK_OK && f < nf; ++f) {
        uint32_t h0 = base->f_halfedge[f], h1 = base->h_next[h0], h2 = base->h_next[h1];
        uint32_t t[3] = {sk_from(base, h0), sk_from(base, h1), sk_from(base, h2)};
        uint32_t m3[3] = {mid[sk_edge(h0)], mid[sk_edge(h1)], mid[sk_edge(h2)]};
        st = split_triangle(soup, t, m3);
    }
    if (st == SK_OK)
        st = sk_mesh_from_soup(soup, &r, err);
    if (st == SK_OK && r->num_vertices != nv + nnew)
        st = sk__fail(err, SK_ERR_NUMERIC, "refine_base: unexpected vertex count");
    size_t nc = 0;
    for (size_t i = 0; st == SK_OK && i < ncreases; ++i) {
        uint32_t a = creases[2 * i], b = creases[2 * i + 1], h = sk__find_halfedge(base, a, b);
        if (h == SK_INVALID)
            continue; /* not an edge of the base (sk__crease_flags skips it too) */
        uint32_t m = mid[sk_edge(h)];
        c2[2 * nc] = a;
        c2[2 * nc + 1] = m == SK_INVALID ? b : m;
        ++nc;
        if (m != SK_INVALID) {
            c2[2 * nc] = m;
            c2[2 * nc + 1] = b;
            ++nc;
        }
    }
    sk_soup_destroy(&soup);
    sk__free(mid);
    if (st != SK_OK) {
        sk_mesh_destroy(&r);
        sk__free(n2);
        sk__free(c2);
        return st;
    }
    *out = r;
    *out_normals = n2;
    *out_creases = c2;
    *out_ncreases = nc;
    *out_split = nnew;
    return SK_OK;
}

/* the root of v in the union-find forest parent (path halving) */
static uint32_t find_root(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

sk_status sk__refine_base_flags(const sk_mesh *base, double fold_deg, uint8_t *split,
                                size_t *count, sk_error *err)
{
    size_t ne = sk_num_edges(base), nv = base->num_vertices, n = 0;
    double lim = cos(fold_deg * (M_PI / 180.0));
    double *cosine = sk__malloc_array(ne + 1, sizeof(double));
    uint32_t *parent = sk__malloc_array(nv + 1, sizeof(uint32_t));
    uint32_t *best = sk__malloc_array(nv + 1, sizeof(uint32_t));
    uint8_t *odd = sk__calloc_array(nv + 1, 1), *open = sk__calloc_array(nv + 1, 1);
    if (!cosine || !parent || !best || !odd || !open) {
        sk__free(cosine);
        sk__free(parent);
        sk__free(best);
        sk__free(odd);
        sk__free(open);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory refining the base");
    }
    for (uint32_t v = 0; v < nv; ++v) {
        parent[v] = v;
        best[v] = SK_INVALID;
    }
    for (size_t e = 0; e < ne; ++e) {
        uint32_t f = base->h_face[2 * e], g = base->h_face[2 * e + 1];
        double a[3], b[3];
        split[e] = !base->e_deleted[e];
        cosine[e] = 1.0;
        if (!split[e])
            continue;
        uint32_t ra = find_root(parent, sk_from(base, (uint32_t)(2 * e)));
        uint32_t rb = find_root(parent, sk_to(base, (uint32_t)(2 * e)));
        parent[ra] = rb;
        if (f != SK_INVALID && g != SK_INVALID) {
            face_unit_normal(base, f, a);
            face_unit_normal(base, g, b);
            cosine[e] = sk__dot3(a, b);
            split[e] = !(cosine[e] < lim); /* a near-fold stays whole */
        }
    }
    /* a closed component must keep an even vertex count (edge deletion needs it: the refinement
     * of all its edges does, V + E = 4 V - 6): where the near-folds left whole make the count of
     * its new vertices odd, the flattest of them is split after all */
    for (size_t e = 0; e < ne; ++e) {
        if (base->e_deleted[e])
            continue;
        uint32_t r = find_root(parent, sk_from(base, (uint32_t)(2 * e)));
        if (base->h_face[2 * e] == SK_INVALID || base->h_face[2 * e + 1] == SK_INVALID)
            open[r] = 1;
        odd[r] ^= split[e];
        if (!split[e] && (best[r] == SK_INVALID || cosine[e] > cosine[best[r]]))
            best[r] = (uint32_t)e;
    }
    for (uint32_t v = 0; v < nv; ++v)
        if (parent[v] == v && odd[v] && !open[v] && best[v] != SK_INVALID)
            split[best[v]] = 1;
    for (size_t e = 0; e < ne; ++e)
        n += split[e];
    *count = n;
    sk__free(cosine);
    sk__free(parent);
    sk__free(best);
    sk__free(odd);
    sk__free(open);
    return SK_OK;
}
