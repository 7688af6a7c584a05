/* A better triangulation of the same vertices before the edge deletion of the VC1 construction:
 * edge flips that remove slivers and near-folds while keeping the shape.
 *
 * The VC1 surface interpolates the vertices and normals; it need not keep the input's
 * triangulation. Slivers (a tiny corner angle) make the ratios nu of eq. (6) extreme and the
 * corner fans of the vertex systems (8) nearly degenerate, near-folds (two faces folded onto each
 * other) put a patch across a crease of the polyhedron: both give singular or overshooting
 * patches. The pass is an extrinsic Delaunay-style flip: the edge ab between the triangles abc
 * and bad is replaced by cd when
 *   - the quadrilateral acbd is not Delaunay (the angles opposite ab sum to more than pi, 3D
 *     angles) and the smallest angle of the two triangles grows (max-min angle, strictly, so the
 *     pass cannot cycle on a plane), or ab is a near-fold (dihedral angle above
 *     SK_FLIP_FOLD_DEG) that the flip unfolds;
 *   - the new edge cd is not a crease: the dihedral angle of the new triangles adc, bcd at cd is
 *     at most SK_FLIP_MAX_DIHEDRAL_DEG (the shape is kept: the four points are nearly coplanar);
 *   - the new triangles agree with the vertex normals at their corners at least as well as the
 *     old ones (the smallest cosine between a face normal and a corner normal does not drop), cd
 *     is not an edge yet, a and b keep at least three faces (interior) or two (boundary).
 * The limits were chosen on the shared meshes (tests/unit/test_smooth_shape.c prints the table):
 * a dihedral limit of 10 degrees left fewer singular patches than 15, 20, 30 or 45 on cow,
 * three_peaks and lion-head, and the normal-agreement rule removed the regressions that a plain
 * max-min angle criterion had (three_peaks 2 -> 13 singular patches).
 * A bad face (a corner normal more than SK_FLIP_BAD_DEG off the face normal: the input folds
 * against its own normals, as at the cow's tail tip and hooves) is a bad base for a patch: its
 * edge is flipped to the other diagonal when that raises the smallest face/corner-normal cosine of
 * the two faces by SK_FLIP_BAD_GAIN and the new edge's dihedral angle is at most
 * SK_FLIP_BAD_DIHEDRAL_DEG (no Delaunay test then; the smaller agreement of the two faces grows with
 * every such flip and never drops with the others; the cap bounds the work). Measured (singular patches cow / pig / armadillo / mech-holes-shark, with
 * the repair's pair round): 45 and 30 degrees 6 / 0 / 0 / 4; 45 and 45: 7 / 1 / 0 / 4; 60 and
 * 45: 8 / 0 / 1 / 3; 40 and 40: 11 / 1 / 0 / 4 and a spike (overshoot 1.97) on the cow; without
 * the rule 10 / 2 / 1 / 3. A bad-face limit of 30 degrees made lion-head 0 -> 8 (before the
 * pair round).
 * Every flip is local and keeps the vertices, so every input vertex and normal is still
 * interpolated. Edges are processed from a work stack (the four edges around a flip are pushed
 * again), with a cap on the flips that bounds the work on any input. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

/* dihedral angle (degrees, between the face normals) that a new edge may have at most */
#define SK_FLIP_MAX_DIHEDRAL_DEG 10.0
/* an edge whose face normals differ by more than this (degrees) is a near-fold */
#define SK_FLIP_FOLD_DEG 120.0
/* the smallest angle must grow by at least this (radians) for a Delaunay flip */
#define SK_FLIP_ANGLE_GAIN 1e-6
/* a face is bad when a corner normal is more than this (degrees) off its normal */
#define SK_FLIP_BAD_DEG 45.0
/* a bad face's edge is flipped when the smallest cosine between a face normal and its corner
 * normals grows by at least this, and the new edge's dihedral angle is at most
 * SK_FLIP_BAD_DIHEDRAL_DEG */
#define SK_FLIP_BAD_GAIN 0.05
#define SK_FLIP_BAD_DIHEDRAL_DEG 30.0
/* the parity pass (sk__parity_flips): the smallest angle of the two faces may drop to this share
 * of what it was (measured on the 12 shared meshes of bench/smooth.sh: at 0.5 lion-head got 2
 * singular patches and three_peaks, knot1 and bunny00 twice their worst fairness; at 0.8 no mesh
 * got a singular patch), and the opposite vertices may reach this valence at most */
#define SK_FLIP_PARITY_ANGLE 0.8
#define SK_FLIP_PARITY_MAX_VALENCE 12
/* flips at most this many times the number of edges */
#define SK_FLIP_CAP 4

static double corner_angle(const double *a, const double *b, const double *c)
{
    /* angle at a of the triangle abc */
    double u[3], v[3], x[3];
    sk__sub3(u, b, a);
    sk__sub3(v, c, a);
    sk__cross3(x, u, v);
    return atan2(sk__norm3(x), sk__dot3(u, v));
}

static double min_angle(const double *a, const double *b, const double *c)
{
    double x = corner_angle(a, b, c), y = corner_angle(b, c, a);
    return fmin(fmin(x, y), M_PI - x - y);
}

/* unit normal of the triangle abc (zero vector for a degenerate one); returns twice its area */
static double tri_normal(const double *a, const double *b, const double *c, double n[3])
{
    double u[3], v[3];
    sk__sub3(u, b, a);
    sk__sub3(v, c, a);
    sk__cross3(n, u, v);
    return sk__normalize3(n);
}

/* the smallest cosine between the normal of abc and the vertex normals of its corners */
static double normal_agreement(const double *N, uint32_t ia, uint32_t ib, uint32_t ic,
                               const double n[3])
{
    double x = sk__dot3(n, N + 3 * (size_t)ia), y = sk__dot3(n, N + 3 * (size_t)ib);
    double z = sk__dot3(n, N + 3 * (size_t)ic);
    return fmin(fmin(x, y), z);
}

static bool has_edge(const sk_mesh *m, uint32_t c, uint32_t d)
{
    uint32_t h0 = m->v_halfedge[c], h = h0;
    do {
        if (sk_to(m, h) == d)
            return true;
        h = sk_cw_out(m, h);
    } while (h != h0);
    return false;
}

/* v keeps at least three faces (interior) or two (boundary) after losing one */
static bool enough_faces(const sk_mesh *m, uint32_t v)
{
    bool boundary = sk_is_boundary_v(m, v);
    return sk_mesh_valence(m, v) - boundary > (boundary ? 2u : 3u);
}

/* The flip of the edge of half-edge h (a -> b in face abc, b -> a in face bad): the vertices
 * a, b, c, d, their positions, and the unit normals n (twice the areas s) of the old faces abc,
 * bad and the new faces adc, bcd */
typedef struct flip_quad {
    uint32_t a, b, c, d;
    const double *A, *B, *C, *D;
    double n1[3], n2[3], n3[3], n4[3], s1, s2, s3, s4;
} flip_quad;

static void flip_quad_of(const sk_mesh *m, uint32_t h, flip_quad *q)
{
    q->a = sk_from(m, h), q->b = sk_to(m, h);
    q->c = sk_to(m, m->h_next[h]), q->d = sk_to(m, m->h_next[sk_opp(h)]);
    q->A = m->positions + 3 * (size_t)q->a, q->B = m->positions + 3 * (size_t)q->b;
    q->C = m->positions + 3 * (size_t)q->c, q->D = m->positions + 3 * (size_t)q->d;
    q->s1 = tri_normal(q->A, q->B, q->C, q->n1), q->s2 = tri_normal(q->B, q->A, q->D, q->n2);
    q->s3 = tri_normal(q->A, q->D, q->C, q->n3), q->s4 = tri_normal(q->B, q->C, q->D, q->n4);
}

/* The flip of q is possible: the new edge joins two vertices, its ends keep enough faces, the new
 * triangles are not degenerate (whether cd is an edge yet, the dearest test, comes last: see
 * want_flip) */
static bool flip_possible(const sk_mesh *m, const flip_quad *q)
{
    return q->c != q->d && enough_faces(m, q->a) && enough_faces(m, q->b) && q->s3 > 0.0 &&
           q->s4 > 0.0;
}

/* Should the interior edge of half-edge h be flipped? */
static bool want_flip(const sk_mesh *m, const double *N, uint32_t h)
{
    flip_quad q;
    flip_quad_of(m, h, &q);
    uint32_t a = q.a, b = q.b, c = q.c, d = q.d;
    if (!flip_possible(m, &q))
        return false;
    const double *A = q.A, *B = q.B, *C = q.C, *D = q.D;
    const double *n1 = q.n1, *n2 = q.n2, *n3 = q.n3, *n4 = q.n4;
    double s1 = q.s1, s2 = q.s2;
    double old_agree = fmin(normal_agreement(N, a, b, c, n1), normal_agreement(N, b, a, d, n2));
    double new_agree = fmin(normal_agreement(N, a, d, c, n3), normal_agreement(N, b, c, d, n4));
    bool old_ok = s1 > 0.0 && s2 > 0.0;
    /* a bad face: its normal is far from a corner normal; the diagonal whose two faces agree
     * better with the vertex normals is taken when the new edge is not too sharp */
    bool bad = old_ok && old_agree < cos(SK_FLIP_BAD_DEG * M_PI / 180.0) &&
               new_agree > old_agree + SK_FLIP_BAD_GAIN &&
               sk__dot3(n3, n4) >= cos(SK_FLIP_BAD_DIHEDRAL_DEG * M_PI / 180.0);
    /* the shape is kept: the new edge is no crease */
    if (!bad && sk__dot3(n3, n4) < cos(SK_FLIP_MAX_DIHEDRAL_DEG * M_PI / 180.0))
        return false;
    /* no new face agrees worse with its corner normals than the old ones did (measured: flips
     * that trade normal agreement for angles made more singular patches on three_peaks, pig) */
    if (new_agree <= 0.0 || (old_ok && !(new_agree >= old_agree)))
        return false;
    bool fold = !old_ok || bad || sk__dot3(n1, n2) < cos(SK_FLIP_FOLD_DEG * M_PI / 180.0);
    if (!fold) {
        /* Delaunay: the angles opposite ab sum to more than pi */
        if (corner_angle(C, A, B) + corner_angle(D, B, A) <= M_PI + SK_FLIP_ANGLE_GAIN)
            return false;
        double before = fmin(min_angle(A, B, C), min_angle(B, A, D));
        double after = fmin(min_angle(A, D, C), min_angle(B, C, D));
        if (!(after > before + SK_FLIP_ANGLE_GAIN))
            return false;
    }
    return !has_edge(m, c, d);
}

/* Flips the edge of half-edge h (a -> b in face abc, its opposite b -> a in face bad): h becomes
 * d -> c in face (d, c, a), its opposite c -> d in face (c, d, b). */
static void flip(sk_mesh *m, uint32_t h)
{
    uint32_t o = sk_opp(h);
    uint32_t h1 = m->h_next[h], h2 = m->h_next[h1], o1 = m->h_next[o], o2 = m->h_next[o1];
    uint32_t f = m->h_face[h], g = m->h_face[o];
    uint32_t a = sk_from(m, h), b = sk_to(m, h), c = sk_to(m, h1), d = sk_to(m, o1);
    if (m->v_halfedge[a] == h)
        m->v_halfedge[a] = o1;
    if (m->v_halfedge[b] == o)
        m->v_halfedge[b] = h1;
    m->h_vertex[h] = c;
    m->h_vertex[o] = d;
    /* f: h (d -> c), h2 (c -> a), o1 (a -> d); g: o (c -> d), o2 (d -> b), h1 (b -> c) */
    m->h_next[h] = h2, m->h_next[h2] = o1, m->h_next[o1] = h;
    m->h_prev[h] = o1, m->h_prev[o1] = h2, m->h_prev[h2] = h;
    m->h_next[o] = o2, m->h_next[o2] = h1, m->h_next[h1] = o;
    m->h_prev[o] = h1, m->h_prev[h1] = o2, m->h_prev[o2] = o;
    m->h_face[o1] = f;
    m->h_face[h1] = g;
    m->f_halfedge[f] = h;
    m->f_halfedge[g] = o;
}

sk_status sk__improve_triangulation(sk_mesh *m, const double *normals, size_t *flipped,
                                    sk_error *err)
{
    return sk__improve_triangulation_keep(m, normals, NULL, flipped, err);
}

sk_status sk__improve_triangulation_keep(sk_mesh *m, const double *normals, const uint8_t *keep,
                                         size_t *flipped, sk_error *err)
{
    size_t ne = sk_num_edges(m), count = 0;
    *flipped = 0;
    uint32_t *stack = sk__malloc_array(ne + 1, sizeof *stack);
    uint8_t *queued = sk__calloc_array(ne + 1, 1), *want = sk__malloc_array(ne + 1, 1);
    uint8_t *moved = sk__calloc_array(m->num_vertices + 1, 1);
    if (!stack || !queued || !want || !moved) {
        sk__free(stack);
        sk__free(queued);
        sk__free(want);
        sk__free(moved);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory improving the triangulation");
    }
    /* per-corner uvs and normals do not survive a flip (the VC1 construction reads the corner
     * normals before, through the creases): dropped */
    sk_mesh_set_wedge_uvs(m, 0, NULL, NULL, NULL);
    sk_mesh_set_wedge_normals(m, 0, NULL, NULL, NULL);
    size_t top = 0;
    for (size_t e = ne; e-- > 0;) {
        if (!m->e_deleted[e] && !sk_is_boundary_e(m, (uint32_t)e)) {
            stack[top++] = (uint32_t)e;
            queued[e] = 1;
        }
    }
    /* want_flip of every edge on the input, in parallel: it reads the quad a, b, c, d of the edge,
     * the stars of a and b (their valence) and of c (whether cd is an edge), which a flip changes
     * only for the four vertices of its own quad (moved). So while none of an edge's a, b, c, d
     * has moved, the answer stands (a, b unmoved: its two faces and so c, d are those of the
     * input); the ordered pass below evaluates the others again: the same flips in the same
     * order as evaluating every edge there. */
    long nel = (long)ne;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 4096) if (nel > 100000)
#endif
    for (long el = 0; el < nel; ++el)
        want[el] = queued[el] && !(keep && keep[el]) && want_flip(m, normals, 2 * (uint32_t)el);
    size_t cap = SK_FLIP_CAP * ne;
    while (top && count < cap) {
        uint32_t e = stack[--top];
        queued[e] = 0;
        uint32_t h = 2 * e, o = h + 1;
        uint32_t q[4] = {sk_from(m, h), sk_to(m, h), sk_to(m, m->h_next[h]),
                         sk_to(m, m->h_next[o])};
        bool fresh = !moved[q[0]] && !moved[q[1]] && !moved[q[2]] && !moved[q[3]];
        if ((keep && keep[e]) || !(fresh ? want[e] : want_flip(m, normals, h)))
            continue;
        flip(m, h);
        ++count;
        for (int i = 0; i < 4; ++i)
            moved[q[i]] = 1;
        /* the four edges around the new one */
        uint32_t around[4] = {m->h_next[h], m->h_prev[h], m->h_next[sk_opp(h)],
                              m->h_prev[sk_opp(h)]};
        for (int i = 0; i < 4; ++i) {
            uint32_t x = sk_edge(around[i]);
            if (!queued[x] && !sk_is_boundary_e(m, x)) {
                queued[x] = 1;
                stack[top++] = x;
            }
        }
    }
    *flipped = count;
    sk__free(stack);
    sk__free(queued);
    sk__free(want);
    sk__free(moved);
    sk__ok(err);
    return SK_OK;
}

/* change in the number of even vertices when the edge of h is flipped: its ends lose a face, the
 * two opposite vertices gain one, and each of the four changes parity (the caller has made sure
 * that all four have a parity: interior, on no crease) */
static int parity_change(const sk_mesh *m, uint32_t h)
{
    uint32_t v[4] = {sk_from(m, h), sk_to(m, h), sk_to(m, m->h_next[h]),
                     sk_to(m, m->h_next[sk_opp(h)])};
    int d = 0;
    for (int i = 0; i < 4; ++i)
        d += (sk_mesh_valence(m, v[i]) & 1u) ? 1 : -1;
    return d;
}

/* The bounds shared by the parity flips and the flips chosen for the deletion: the quad's four
 * vertices all have a parity and are no neighbour of a crease vertex (noparity), the new edge
 * bends at most SK_FLIP_MAX_DIHEDRAL_DEG, each new face agrees with its corner normals at least
 * as well as the better (than_better; else the worse) of the two old faces did, the smallest
 * angle stays above SK_FLIP_PARITY_ANGLE of what it was, and no vertex gets more than
 * SK_FLIP_PARITY_MAX_VALENCE faces. */
static bool flip_within_bounds(const sk_mesh *m, const double *N, const uint8_t *noparity,
                               const flip_quad *q, bool than_better)
{
    if (q->c == q->d || noparity[q->a] || noparity[q->b] || noparity[q->c] || noparity[q->d] ||
        !enough_faces(m, q->a) || !enough_faces(m, q->b) ||
        sk_mesh_valence(m, q->c) >= SK_FLIP_PARITY_MAX_VALENCE ||
        sk_mesh_valence(m, q->d) >= SK_FLIP_PARITY_MAX_VALENCE)
        return false;
    if (!(q->s1 > 0.0 && q->s2 > 0.0 && q->s3 > 0.0 && q->s4 > 0.0) ||
        sk__dot3(q->n3, q->n4) < cos(SK_FLIP_MAX_DIHEDRAL_DEG * M_PI / 180.0))
        return false;
    double old1 = normal_agreement(N, q->a, q->b, q->c, q->n1);
    double old2 = normal_agreement(N, q->b, q->a, q->d, q->n2);
    double old_agree = than_better ? fmax(old1, old2) : fmin(old1, old2);
    double new_agree = fmin(normal_agreement(N, q->a, q->d, q->c, q->n3),
                            normal_agreement(N, q->b, q->c, q->d, q->n4));
    if (!(new_agree > 0.0 && new_agree >= old_agree))
        return false;
    double before = fmin(min_angle(q->A, q->B, q->C), min_angle(q->B, q->A, q->D));
    double after = fmin(min_angle(q->A, q->D, q->C), min_angle(q->B, q->C, q->D));
    return after >= SK_FLIP_PARITY_ANGLE * before && !has_edge(m, q->c, q->d);
}

/* Should the edge of h be flipped to lower the number of even vertices by at least -need,
 * within flip_within_bounds (agreement with the normals no worse than the better old face's)? */
static bool want_parity_flip(const sk_mesh *m, const double *N, const uint8_t *noparity,
                             uint32_t h, int need)
{
    flip_quad q;
    flip_quad_of(m, h, &q);
    return parity_change(m, h) <= need && flip_within_bounds(m, N, noparity, &q, true);
}

void sk__flip_noparity(const sk_mesh *m, const uint8_t *keep, uint8_t *noparity,
                       uint8_t *crease_v)
{
    size_t ne = sk_num_edges(m), nv = m->num_vertices;
    memset(crease_v, 0, nv);
    for (uint32_t v = 0; v < nv; ++v)
        noparity[v] = m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID || sk_is_boundary_v(m, v);
    /* crease vertices and their neighbours (as the fold refit, vc1.c: a crease vertex's sectors
     * build on its neighbours' edges; with flips next to fandisk's crease vertices a sector at
     * vertex 3243 failed and the construction dropped 697 of its 706 G0 edges) */
    for (uint32_t e = 0; keep && e < ne; ++e)
        if (keep[e] && !m->e_deleted[e])
            crease_v[sk_from(m, 2 * e)] = crease_v[sk_to(m, 2 * e)] = 1;
    for (uint32_t e = 0; keep && e < ne; ++e)
        if (!m->e_deleted[e] && (crease_v[sk_from(m, 2 * e)] || crease_v[sk_to(m, 2 * e)]))
            noparity[sk_from(m, 2 * e)] = noparity[sk_to(m, 2 * e)] = 1;
}

sk_status sk__parity_flips(sk_mesh *m, const double *normals, const uint8_t *keep,
                           size_t *flipped, sk_error *err)
{
    size_t ne = sk_num_edges(m), nv = m->num_vertices, count = 0;
    *flipped = 0;
    uint8_t *noparity = sk__malloc_array(nv + 1, 1), *crease_v = sk__malloc_array(nv + 1, 1);
    if (!noparity || !crease_v) {
        sk__free(noparity);
        sk__free(crease_v);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the parity flips");
    }
    sk__flip_noparity(m, keep, noparity, crease_v);
    /* one sweep for the flips that make four even vertices odd, one for three of four (each
     * flip lowers the count by 4 or 2) */
    for (int need = -4; need <= -2; need += 2)
        for (uint32_t e = 0; e < ne; ++e) {
            if (m->e_deleted[e] || sk_is_boundary_e(m, e) || (keep && keep[e]) ||
                !want_parity_flip(m, normals, noparity, 2 * e, need))
                continue;
            flip(m, 2 * e);
            ++count;
        }
    *flipped = count;
    sk__free(noparity);
    sk__free(crease_v);
    sk__ok(err);
    return SK_OK;
}

/* The quality test of a flip chosen for the edge deletion (deletion_flips.c): the bounds of the
 * parity pass without its parity condition, each new face agreeing with its corner normals at
 * least as well as the worse old face did (the quality pass's rule). */
bool sk__deletion_flip_ok(const sk_mesh *m, const double *N, const uint8_t *noparity, uint32_t h)
{
    flip_quad q;
    flip_quad_of(m, h, &q);
    return flip_within_bounds(m, N, noparity, &q, false);
}

void sk__flip_edge(sk_mesh *m, uint32_t h)
{
    flip(m, h);
}

bool sk__flip_edge_if_valid(sk_mesh *m, uint32_t h, const uint8_t *keep)
{
    uint32_t e = sk_edge(h);
    if (sk_is_boundary_e(m, e) || (keep && keep[e]))
        return false;
    flip_quad q;
    flip_quad_of(m, h, &q);
    if (!flip_possible(m, &q) || has_edge(m, q.c, q.d))
        return false;
    flip(m, h);
    return true;
}
