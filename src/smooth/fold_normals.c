/* Estimated vertex normals at folded stars (the VC1 construction's normals when the file gives
 * none).
 *
 * The usual estimate (a weighted mean of the face normals around the vertex) is the axis of a
 * needle and the ridge direction of a knife edge; at the tip of a flattened needle (the cow's tail
 * tip: four faces with dihedral angles of 155-174 degrees) or on a ridge of 20 degrees opening
 * (the cow's vertices 956, 2384 beside vertex 43) the mean leaves a face more than 90 degrees off
 * the normal: that face is seen from behind, its patch must turn over to meet the normal at the
 * corner, and the regularity test (the patch normal against the sum of its corner normals) finds
 * it singular however the free control points are chosen. Where that happens, and only there, the
 * normal becomes the direction that sees its faces best: the one that maximises the smallest
 * cosine to the faces' normals (the centre of the smallest spherical cap holding them). That
 * centre is fixed by one, two or three of the face normals (the cap touches them), so it is found
 * exactly among those candidates: a face normal, the bisector of two, the direction at equal
 * angles to three. It is kept when the smallest cosine grows by SK_FOLD_GAIN. Every other
 * vertex keeps its normal bit for bit, and the surface still interpolates the normals it was
 * built with (s->normals). The cow's tail tip (vertices 2328, 2334, 2340) is regular since; the
 * fold beside vertex 43 (the tail's root, edges of 113-160 degrees) since the second refit at
 * the ends of its hinge line 956-43-2384 and their neighbours (vc1.c, refit_hinge_ends). */
#include "smooth/smooth_internal.h"
#include "core/vec.h"

#include <string.h>

/* a star is folded when a face normal is more than this (degrees) off the vertex normal */
#define SK_FOLD_DEG 90.0
/* The new normal is taken when it sees every face within see_deg (SK_FOLD_SEE_DEG, 84 degrees,
 * in smooth_internal.h) and the smallest face cosine grows by at least SK_FOLD_GAIN (measured on
 * the cow with every vertex allowed, singular patches before / after the repair, 36 / 6 without
 * the refit: 84 degrees 25 / 4, 80 degrees 29 / 6, 75 degrees 30 / 6; with 90 degrees (a refit
 * that may leave a face edge-on) 39 / 9; the build leaves the crease vertices and their
 * neighbours alone (vc1.c): 84 degrees 26 / 4). At the end of a fold hinge (two faces 160
 * degrees apart on the cow: no direction sees both within 80) the build refits once more after
 * the edge flips with SK_FOLD_HINGE_SEE_DEG, 85 degrees: the cow's vertex 956 is seen within
 * 84.7 at best (vc1.c, refit_hinge_ends). */
#define SK_FOLD_GAIN 0.05
/* faces per vertex considered (the rest of a larger star is ignored: no refit there) */
#define SK_FOLD_MAX_FACES 24

static double smallest_cos(const double *F, int k, const double n[3])
{
    double lo = 2.0;
    for (int i = 0; i < k; ++i)
        lo = fmin(lo, sk__dot3(F + 3 * i, n));
    return lo;
}

/* candidate direction x (not normalised) tried: kept in best / best_cos when better */
static void try_candidate(const double *F, int k, double x[3], double best[3], double *best_cos)
{
    if (!(sk__normalize3(x) > 0.0))
        return;
    double c = smallest_cos(F, k, x);
    if (c > *best_cos) {
        *best_cos = c;
        memcpy(best, x, 3 * sizeof(double));
    }
}

/* the direction maximising the smallest cosine to the unit vectors F[0 .. k) into best; returns
 * that cosine */
static double maximin_direction(const double *F, int k, double best[3])
{
    double best_cos = -2.0;
    for (int i = 0; i < k; ++i) {
        const double *a = F + 3 * i;
        double x[3] = {a[0], a[1], a[2]};
        try_candidate(F, k, x, best, &best_cos);
        for (int j = i + 1; j < k; ++j) {
            const double *b = F + 3 * j;
            double y[3];
            sk__add3(y, a, b); /* equal angles to a and b, in their plane */
            try_candidate(F, k, y, best, &best_cos);
            for (int l = j + 1; l < k; ++l) {
                /* x . a = x . b = x . c = 1: x = (b x c + c x a + a x b) / det */
                const double *c = F + 3 * l;
                double bc[3], ca[3], ab[3], z[3];
                sk__cross3(bc, b, c);
                sk__cross3(ca, c, a);
                sk__cross3(ab, a, b);
                double det = sk__dot3(a, bc);
                if (!(fabs(det) > 1e-12))
                    continue;
                sk__add3(z, bc, ca);
                sk__add3(z, z, ab);
                sk__scale3(z, z, 1.0 / det);
                try_candidate(F, k, z, best, &best_cos);
            }
        }
    }
    return best_cos;
}

size_t sk__fold_normals(const sk_mesh *m, double *normals, const uint8_t *skip, double see_deg)
{
    size_t changed = 0;
    double lim = cos(SK_FOLD_DEG * M_PI / 180.0), see = cos(see_deg * M_PI / 180.0);
    long nvl = (long)m->num_vertices;
    /* each vertex reads the positions and writes only its own normal */
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : changed)
#endif
    for (long i = 0; i < nvl; ++i) {
        uint32_t v = (uint32_t)i, h0 = m->v_halfedge[v], h = h0;
        if (m->v_deleted[v] || h0 == SK_INVALID || (skip && skip[v]))
            continue;
        double F[3 * SK_FOLD_MAX_FACES];
        int k = 0;
        bool whole = true;
        do {
            uint32_t f = m->h_face[h];
            if (f != SK_INVALID) {
                if (k == SK_FOLD_MAX_FACES) {
                    whole = false;
                    break;
                }
                const double *a = m->positions + 3 * (size_t)v;
                const double *b = m->positions + 3 * (size_t)sk_to(m, h);
                const double *c = m->positions + 3 * (size_t)sk_to(m, m->h_next[h]);
                double u[3], w[3];
                sk__sub3(u, b, a);
                sk__sub3(w, c, a);
                sk__cross3(F + 3 * k, u, w);
                if (sk__normalize3(F + 3 * k) > 0.0)
                    ++k;
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
        double *n = normals + 3 * (size_t)v;
        double now = smallest_cos(F, k, n);
        if (!whole || k < 2 || now >= lim)
            continue;
        double best[3];
        if (maximin_direction(F, k, best) >= fmax(now + SK_FOLD_GAIN, see)) {
            memcpy(n, best, 3 * sizeof(double));
            ++changed;
        }
    }
    return changed;
}
