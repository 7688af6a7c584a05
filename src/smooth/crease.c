/* Crease edges: sharp edges of a triangle mesh, the G0 boundaries a VC1 surface with creases
 * needs (design in docs/creases.md; the construction itself is not built yet).
 *
 * A plain dihedral threshold is fooled by scans: a sliver's normal is unreliable and a noisy or
 * coarse mesh has many single sharp edges. After Belyaev & Anoshkina (Mathematics of Surfaces XI,
 * "Detection of surface creases in range data": smooth the normals first, then keep the crease
 * points that form lines), adapted to a mesh:
 *   1. the dihedral angle of the two face normals must reach the crease angle A;
 *   2. so must the angle between the two side normals, each the area-weighted normal of a face
 *      and its neighbours across its two other edges (one smoothing step per side, not across
 *      the edge tested): a sliver weighs by its area, so its own normal hardly counts;
 *   3. crease edges must form lines (the paper's hysteresis, simplified): the edges of steps 1-2
 *      are joined into chains through the vertices with exactly two of them; a chain of fewer
 *      than SK_CREASE_MIN_CHAIN edges is dropped, unless both its ends are corners (three or
 *      more such edges meet there: the cube's feature lines are single edges). */
#include "surfkit/smooth.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <string.h>

/* twice the area vector of face f (a triangle: the cross product of two sides; a larger face:
 * the sum over a fan) */
static void face_area_vector(const sk_mesh *m, uint32_t f, double out[3])
{
    uint32_t h0 = m->f_halfedge[f], h = m->h_next[h0];
    const double *p0 = m->positions + 3 * (size_t)sk_from(m, h0);
    out[0] = out[1] = out[2] = 0.0;
    while (m->h_next[h] != h0) {
        const double *p1 = m->positions + 3 * (size_t)sk_from(m, h);
        const double *p2 = m->positions + 3 * (size_t)sk_to(m, h);
        double x[3], y[3], c[3];
        sk__sub3(x, p1, p0);
        sk__sub3(y, p2, p0);
        sk__cross3(c, x, y);
        sk__add3(out, out, c);
        h = m->h_next[h];
    }
}

static double angle_deg(const double *a, const double *b)
{
    double c[3];
    sk__cross3(c, a, b);
    return atan2(sqrt(sk__dot3(c, c)), sk__dot3(a, b)) * (180.0 / 3.14159265358979323846);
}

/* side normal of face(h) away from edge(h): the face and its neighbours across its other edges */
static void side_normal(const sk_mesh *m, const double *fa, uint32_t h, double out[3])
{
    uint32_t f = m->h_face[h];
    memcpy(out, fa + 3 * (size_t)f, 3 * sizeof(double));
    for (uint32_t g = m->h_next[h]; g != h; g = m->h_next[g]) {
        uint32_t nb = m->h_face[sk_opp(g)];
        if (nb != SK_INVALID)
            sk__add3(out, out, fa + 3 * (size_t)nb);
    }
}

/* shortest line of crease edges kept (step 3) */
#define SK_CREASE_MIN_CHAIN 3

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

sk_status sk_mesh_crease_edges(const sk_mesh *mesh, const sk_crease_opts *opts, uint8_t *crease,
                               size_t *count, sk_error *err)
{
    if (!mesh || !crease)
        return sk__fail(err, SK_ERR_ARG, "sk_mesh_crease_edges: NULL argument");
    double A = opts && opts->angle_deg != 0.0 ? opts->angle_deg : SK_CREASE_ANGLE_DEFAULT;
    if (!(A > 0.0 && A < 180.0))
        return sk__fail(err, SK_ERR_ARG, "crease angle %g is not between 0 and 180 degrees", A);
    const sk_mesh *m = mesh;
    size_t ne = sk_num_edges(m), nv = m->num_vertices, nf = m->num_faces, n = 0;
    double *fa = sk__malloc_array(nf + 1, 3 * sizeof(double));
    uint32_t *deg = sk__calloc_array(nv + 1, sizeof(uint32_t));
    uint32_t *first = sk__malloc_array(nv + 1, sizeof(uint32_t)); /* a crease edge at v */
    uint32_t *parent = sk__malloc_array(ne + 1, sizeof(uint32_t)); /* chains (union-find) */
    uint32_t *size = sk__calloc_array(ne + 1, sizeof(uint32_t));
    sk_status st = SK_OK;
    memset(crease, 0, ne);
    if (!fa || !deg || !first || !parent || !size) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory detecting creases");
        goto done;
    }
    for (uint32_t f = 0; f < nf; ++f)
        if (!m->f_deleted[f])
            face_area_vector(m, f, fa + 3 * (size_t)f);
    for (uint32_t e = 0; e < ne; ++e) {
        uint32_t h = 2 * e, o = h + 1;
        if (m->e_deleted[e] || m->h_face[h] == SK_INVALID || m->h_face[o] == SK_INVALID)
            continue;
        if (angle_deg(fa + 3 * (size_t)m->h_face[h], fa + 3 * (size_t)m->h_face[o]) < A)
            continue;
        double sh[3], so[3];
        side_normal(m, fa, h, sh);
        side_normal(m, fa, o, so);
        if (angle_deg(sh, so) < A)
            continue;
        crease[e] = 1;
        deg[sk_from(m, h)]++;
        deg[sk_to(m, h)]++;
    }
    /* chains: the two crease edges of a vertex with exactly two are one line */
    for (uint32_t e = 0; e < ne; ++e)
        parent[e] = e;
    for (uint32_t v = 0; v < nv; ++v)
        first[v] = SK_INVALID;
    for (uint32_t e = 0; e < ne; ++e) {
        if (!crease[e])
            continue;
        uint32_t ends[2] = {sk_from(m, 2 * e), sk_to(m, 2 * e)};
        for (int k = 0; k < 2; ++k) {
            uint32_t v = ends[k];
            if (deg[v] != 2)
                continue;
            if (first[v] == SK_INVALID)
                first[v] = e;
            else
                parent[uf_find(parent, e)] = uf_find(parent, first[v]);
        }
    }
    for (uint32_t e = 0; e < ne; ++e)
        if (crease[e])
            size[uf_find(parent, e)]++;
    for (uint32_t e = 0; e < ne; ++e) {
        if (!crease[e])
            continue;
        bool corners = deg[sk_from(m, 2 * e)] >= 3 && deg[sk_to(m, 2 * e)] >= 3;
        if (size[uf_find(parent, e)] < SK_CREASE_MIN_CHAIN && !corners)
            crease[e] = 0; /* a short piece, not a line */
        else
            n++;
    }
    if (count)
        *count = n;
    sk__ok(err);
done:
    sk__free(fa);
    sk__free(deg);
    sk__free(first);
    sk__free(parent);
    sk__free(size);
    return st;
}
