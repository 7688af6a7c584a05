/* Crease edges: sharp edges of a triangle mesh, the G0 boundaries a VC1 surface with creases
 * needs (docs/creases.md; the G0 construction is src/smooth/crease_g0.c).
 *
 * A plain dihedral threshold is fooled by scans: a sliver's normal is unreliable and a noisy or
 * coarse mesh has many single sharp edges. After Belyaev & Anoshkina (Mathematics of Surfaces XI,
 * "Detection of surface creases in range data": smooth the normals first, then keep the crease
 * points that form lines), adapted to a mesh:
 *   1. the dihedral angle of the two face normals must reach the crease angle A;
 *   2. so must the angle between the two side normals, each the area-weighted normal of a face
 *      and its neighbours across its two other edges (one smoothing step per side, not across
 *      the edge tested): a sliver weighs by its area, so its own normal hardly counts;
 *   3. both sides must be smooth surface pieces, not a thin band of sharp edges: the faces
 *      reached from each side's face within SK_CREASE_RINGS rings, crossing only edges whose
 *      dihedral stays below A (never the edge tested, never the other side's face), must all lie
 *      within A / 2 of their area-weighted mean normal (or within a third of the jump across the
 *      edge: a plane meeting a coarse cylinder). This is the paper's nonlinear diffusion
 *      of the normals reduced to its two limits (weight 1 below the threshold, 0 above): a crease
 *      of a CAD model has a flat or gently curved face on each side, while on the thin parts of a
 *      coarse scan (ears, horns, hooves, mane grooves: bands a few triangles wide) the smooth
 *      neighbourhood of a sharp edge is itself bent by far more than a face of a part is. Step 3
 *      works as the paper's hysteresis: the edges of steps 1-2 meeting at vertices form groups,
 *      and a group is kept whole when 3 of 5 of its edges pass it;
 *   4. crease edges must form lines: the edges kept are joined into chains through the vertices
 *      with exactly two of them; a chain of fewer than SK_CREASE_MIN_CHAIN edges is dropped,
 *      unless both its ends are corners (three or more such edges meet there: the cube's feature
 *      lines are single edges). */
#include "surfkit/smooth.h"
#include "smooth/smooth_internal.h"
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

/* shortest line of crease edges kept (step 4) */
#define SK_CREASE_MIN_CHAIN 3
/* rings of the smooth side region of step 3 */
#define SK_CREASE_RINGS 3
/* step 3: a side bent more than A / 2 still counts when the jump is this many times its bend */
#define SK_CREASE_JUMP_PER_BEND 3.0
/* step 3's hysteresis: a group is kept when this share of its edges passes (3 of 5) */
#define SK_CREASE_GROUP_NUM 3
#define SK_CREASE_GROUP_DEN 5

/* step 3 for side face f of edge e (other = the face across e): the bend of f's smooth region,
 * the largest angle in degrees between one of its faces and the region's mean normal. mark and
 * queue hold nf entries; stamp is unique per call. */
static double side_bend(const sk_mesh *m, const double *fa, const double *dih, double A,
                        uint32_t e, uint32_t f, uint32_t other, uint32_t *mark, uint32_t *queue,
                        uint32_t stamp)
{
    size_t head = 0, tail = 0;
    double sum[3];
    mark[f] = stamp;
    if (other != SK_INVALID)
        mark[other] = stamp;
    queue[tail++] = f;
    for (int ring = 0; ring < SK_CREASE_RINGS; ++ring) {
        size_t end = tail;
        for (; head < end; ++head) {
            uint32_t h0 = m->f_halfedge[queue[head]], g = h0;
            do {
                uint32_t ge = sk_edge(g), y = m->h_face[sk_opp(g)];
                if (ge != e && dih[ge] < A && y != SK_INVALID && mark[y] != stamp) {
                    mark[y] = stamp;
                    queue[tail++] = y;
                }
                g = m->h_next[g];
            } while (g != h0);
        }
    }
    sum[0] = sum[1] = sum[2] = 0.0;
    for (size_t i = 0; i < tail; ++i)
        sk__add3(sum, sum, fa + 3 * (size_t)queue[i]);
    double bend = 0.0;
    for (size_t i = 0; i < tail; ++i)
        bend = fmax(bend, angle_deg(fa + 3 * (size_t)queue[i], sum));
    return bend;
}

/* step 3 for one side: its region bends by at most A / 2, or by less than a third of the jump
 * across the edge (a crease between a plane and a coarse cylinder or a sliver fan) */
static bool side_is_smooth(double bend, double jump, double A)
{
    return bend <= 0.5 * A || SK_CREASE_JUMP_PER_BEND * bend <= jump;
}

/* a hinge is a fold: its face normals are more than this (degrees) apart, its faces meet at an
 * acute angle */
#define SK_CREASE_FOLD_DEG 90.0
/* a flag in a chain's edge count: one of its edges is no fold hinge */
#define SK_CREASE_NOT_HINGE 0x80000000u

/* Step 3b: a face whose edges are all crease candidates is a facet sharp against every
 * neighbour (a fold-over on a scan: the cow's tail root, where three such faces sit around
 * vertex 43), not two smooth sides meeting along a line. Such a face keeps only its sharpest
 * edge, the hinge of the fold (hinge[e] = 1), and its other crease edges are dropped (every face
 * is judged before any edge is dropped, so the order does not matter; a hinge of one face that
 * another face drops is dropped). drop holds ne zero flags on entry and on return; deg is
 * updated. */
static void prune_crease_islands(const sk_mesh *m, const double *dih, uint8_t *crease,
                                 uint32_t *deg, uint32_t *drop, uint8_t *hinge)
{
    size_t ne = sk_num_edges(m);
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h0 = m->f_halfedge[f], h = h0, sharpest = SK_INVALID;
        bool all = true;
        do {
            uint32_t e = sk_edge(h);
            all = all && crease[e];
            if (sharpest == SK_INVALID || dih[e] > dih[sharpest])
                sharpest = e;
            h = m->h_next[h];
        } while (h != h0 && all);
        if (!all)
            continue;
        do {
            if (sk_edge(h) != sharpest)
                drop[sk_edge(h)] = 1;
            h = m->h_next[h];
        } while (h != h0);
        hinge[sharpest] = dih[sharpest] > SK_CREASE_FOLD_DEG;
    }
    for (uint32_t e = 0; e < ne; ++e)
        if (drop[e]) {
            crease[e] = hinge[e] = 0;
            deg[sk_from(m, 2 * e)]--;
            deg[sk_to(m, 2 * e)]--;
            drop[e] = 0;
        }
}

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
    return sk__crease_edges_hinges(mesh, opts, crease, NULL, count, err);
}

sk_status sk__crease_edges_hinges(const sk_mesh *mesh, const sk_crease_opts *opts, uint8_t *crease,
                                  uint8_t *hinges, size_t *count, sk_error *err)
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
    double *dih = sk__malloc_array(ne + 1, sizeof(double));        /* face dihedral per edge */
    uint32_t *mark = sk__calloc_array(nf + 1, sizeof(uint32_t));   /* step 3: region stamps */
    uint32_t *queue = sk__malloc_array(nf + 1, sizeof(uint32_t));  /* step 3: region faces */
    uint32_t *vpar = sk__malloc_array(nv + 1, sizeof(uint32_t));   /* step 3: groups */
    uint32_t *nall = sk__calloc_array(nv + 1, sizeof(uint32_t));
    uint32_t *nstrong = sk__calloc_array(nv + 1, sizeof(uint32_t));
    uint8_t *hinge = sk__calloc_array(ne + 1, 1); /* step 3b: the hinge of a fold */
    uint32_t stamp = 0;
    sk_status st = SK_OK;
    memset(crease, 0, ne);
    if (!fa || !deg || !first || !parent || !size || !dih || !mark || !queue || !vpar || !nall ||
        !nstrong || !hinge) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory detecting creases");
        goto done;
    }
    long nfl = (long)nf, nel = (long)ne;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl > 100000)
#endif
    for (long f = 0; f < nfl; ++f)
        if (!m->f_deleted[f])
            face_area_vector(m, (uint32_t)f, fa + 3 * (size_t)f);
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nel > 100000)
#endif
    for (long e = 0; e < nel; ++e) {
        uint32_t h = 2 * (uint32_t)e, o = h + 1;
        dih[e] = 180.0; /* a boundary edge is never crossed by a smooth region */
        if (!m->e_deleted[e] && m->h_face[h] != SK_INVALID && m->h_face[o] != SK_INVALID)
            dih[e] = angle_deg(fa + 3 * (size_t)m->h_face[h], fa + 3 * (size_t)m->h_face[o]);
    }
    for (uint32_t e = 0; e < ne; ++e) {
        uint32_t h = 2 * e, o = h + 1;
        if (m->e_deleted[e] || m->h_face[h] == SK_INVALID || m->h_face[o] == SK_INVALID)
            continue;
        if (dih[e] < A)
            continue;
        double sh[3], so[3];
        side_normal(m, fa, h, sh);
        side_normal(m, fa, o, so);
        double jump = angle_deg(sh, so);
        if (jump < A)
            continue;
        uint32_t fh = m->h_face[h], fo = m->h_face[o];
        crease[e] = 1; /* steps 1-2 */
        if (side_is_smooth(side_bend(m, fa, dih, A, e, fh, fo, mark, queue, ++stamp), jump, A) &&
            side_is_smooth(side_bend(m, fa, dih, A, e, fo, fh, mark, queue, ++stamp), jump, A))
            crease[e] = 2; /* and step 3 */
    }
    /* step 3's hysteresis: the edges of steps 1-2 that meet at vertices form groups; a group is
     * kept whole if 3 of 5 of its edges pass step 3 (a feature line, with its few edges next to
     * a gentle blend whose smooth region bends more), dropped otherwise (a band of a thin part,
     * where most sides are bent) */
    for (uint32_t v = 0; v < nv; ++v)
        vpar[v] = v;
    for (uint32_t e = 0; e < ne; ++e)
        if (crease[e])
            vpar[uf_find(vpar, sk_from(m, 2 * e))] = uf_find(vpar, sk_to(m, 2 * e));
    for (uint32_t e = 0; e < ne; ++e)
        if (crease[e]) {
            uint32_t r = uf_find(vpar, sk_from(m, 2 * e));
            nall[r]++;
            nstrong[r] += crease[e] == 2;
        }
    for (uint32_t e = 0; e < ne; ++e) {
        if (!crease[e])
            continue;
        uint32_t r = uf_find(vpar, sk_from(m, 2 * e));
        if (SK_CREASE_GROUP_DEN * (size_t)nstrong[r] < SK_CREASE_GROUP_NUM * (size_t)nall[r]) {
            crease[e] = 0;
            continue;
        }
        crease[e] = 1;
        deg[sk_from(m, 2 * e)]++;
        deg[sk_to(m, 2 * e)]++;
    }
    prune_crease_islands(m, dih, crease, deg, size, hinge);
    /* chains: the two crease edges of a vertex with exactly two are one line (unless one is a
     * fold hinge and the other not: a piece of a crease line too short to stand alone is not
     * made a line by the fold it touches; on the cow edge 492-956 next to the hinges 956-43-2384
     * made their sectors fail, and the whole line was dropped) */
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
            else if (hinge[e] == hinge[first[v]])
                parent[uf_find(parent, e)] = uf_find(parent, first[v]);
        }
    }
    /* size[root]: the chain's edge count; a chain of fold hinges (step 3b) is kept however
     * short: the surface turns back along it, and one normal per vertex cannot follow that */
    for (uint32_t e = 0; e < ne; ++e)
        if (crease[e]) {
            uint32_t r = uf_find(parent, e);
            size[r] = (size[r] + 1) | (hinge[e] ? 0u : SK_CREASE_NOT_HINGE);
        }
    for (uint32_t e = 0; e < ne; ++e) {
        if (!crease[e])
            continue;
        bool corners = deg[sk_from(m, 2 * e)] >= 3 && deg[sk_to(m, 2 * e)] >= 3;
        uint32_t sz = size[uf_find(parent, e)];
        bool fold = !(sz & SK_CREASE_NOT_HINGE);
        if ((sz & ~SK_CREASE_NOT_HINGE) < SK_CREASE_MIN_CHAIN && !corners && !fold)
            crease[e] = 0; /* a short piece, not a line */
        else
            n++;
    }
    if (hinges)
        for (uint32_t e = 0; e < ne; ++e)
            hinges[e] = crease[e] && hinge[e];
    if (count)
        *count = n;
    sk__ok(err);
done:
    sk__free(fa);
    sk__free(deg);
    sk__free(first);
    sk__free(parent);
    sk__free(size);
    sk__free(dih);
    sk__free(mark);
    sk__free(queue);
    sk__free(vpar);
    sk__free(nall);
    sk__free(nstrong);
    sk__free(hinge);
    return st;
}
