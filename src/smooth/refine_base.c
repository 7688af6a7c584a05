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
#include "surfkit/subdivide.h"

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

sk_status sk__refine_base_midpoint(const sk_mesh *base, const double *normals,
                                   const uint32_t *creases, size_t ncreases, sk_mesh **out,
                                   double **out_normals, uint32_t **out_creases, size_t *out_ncreases,
                                   sk_error *err)
{
    *out = NULL;
    *out_normals = NULL;
    *out_creases = NULL;
    *out_ncreases = 0;
    size_t nv = base->num_vertices, ne = sk_num_edges(base);
    for (size_t v = 0; v < nv; ++v)
        if (base->v_deleted[v])
            return sk__fail(err, SK_ERR_ARG, "refine_base: the base has deleted vertices");
    for (size_t e = 0; e < ne; ++e)
        if (base->e_deleted[e])
            return sk__fail(err, SK_ERR_ARG, "refine_base: the base has deleted edges");
    sk_subdiv_opts so = {.scheme = SK_SUBDIV_MIDPOINT, .iterations = 1};
    sk_mesh *r = NULL;
    sk_status st = sk_mesh_subdivide(base, &so, &r, err);
    if (st)
        return st;
    double *n2 = sk__malloc_array(nv + ne + 1, 3 * sizeof(double));
    uint32_t *c2 = sk__malloc_array(4 * ncreases + 1, sizeof(uint32_t));
    if (!n2 || !c2 || r->num_vertices != nv + ne) {
        sk__free(n2);
        sk__free(c2);
        sk_mesh_destroy(&r);
        return r ? sk__fail(err, SK_ERR_NOMEM, "out of memory refining the base")
                 : sk__fail(err, SK_ERR_NUMERIC, "refine_base: unexpected vertex count");
    }
    memcpy(n2, normals, nv * 3 * sizeof(double));
    for (size_t e = 0; e < ne; ++e) { /* vertex nv + e sits on edge e (subdivide.c) */
        double *n = n2 + 3 * (nv + e), fn[3];
        n[0] = n[1] = n[2] = 0.0;
        for (uint32_t k = 0; k < 2; ++k) {
            uint32_t f = base->h_face[2 * e + k];
            if (f == SK_INVALID)
                continue;
            face_unit_normal(base, f, fn);
            sk__add3(n, n, fn);
        }
        if (sk__normalize3(n) == 0.0) { /* a fold of 180 degrees: the ends' normals */
            sk__add3(n, normals + 3 * (size_t)sk_from(base, (uint32_t)(2 * e)),
                     normals + 3 * (size_t)sk_to(base, (uint32_t)(2 * e)));
            if (sk__normalize3(n) == 0.0) {
                sk__free(n2);
                sk__free(c2);
                sk_mesh_destroy(&r);
                return sk__fail(err, SK_ERR_NUMERIC,
                                "refine_base: edge (%u, %u) has no normal for its midpoint",
                                sk_from(base, (uint32_t)(2 * e)), sk_to(base, (uint32_t)(2 * e)));
            }
        }
    }
    size_t nc = 0;
    for (size_t i = 0; i < ncreases; ++i) {
        uint32_t a = creases[2 * i], b = creases[2 * i + 1], h = sk__find_halfedge(base, a, b);
        if (h == SK_INVALID)
            continue; /* not an edge of the base (sk__crease_flags skips it too) */
        uint32_t mid = (uint32_t)(nv + sk_edge(h));
        c2[2 * nc] = a;
        c2[2 * nc + 1] = mid;
        c2[2 * nc + 2] = mid;
        c2[2 * nc + 3] = b;
        nc += 2;
    }
    *out = r;
    *out_normals = n2;
    *out_creases = c2;
    *out_ncreases = nc;
    return SK_OK;
}
