/* Wire frame targets P*_m, R*_m (Cottin & van Damme, section 4) and the ratios r_m of eq. (7).
 *
 * Construction used (the paper's "functional case" refers to a report that is not available, see
 * the papers README): for the edge from V to W with unit normals n0, n1,
 *  - the plane F through V and W that makes equal angles with both normals contains the chord
 *    d = W - V and the mean normal n0 + n1; its normal is f = d x (n0 + n1), for which
 *    |f.n0| = |f.n1| (equal angles) and the angle is the smallest of the two equal-angle planes;
 *  - the tangent line t at V is F intersected with the tangent plane at V: direction f x n0,
 *    oriented towards W;
 *  - P* = V + h t with h = |d| / (3 cos^2(phi / 2)), phi the angle between t and the chord (phi
 *    capped at 90 degrees): one third of the chord, lengthened as the Hermite cubic that best
 *    reproduces a circular arc (h = 4/3 R tan(theta / 4) for an arc of angle theta = 2 phi).
 * When the normals are opposite (n0 + n1 = 0) no plane is defined and a cubic cannot join the two
 * tangent planes with consistent orientation: the edge is an error. When the chord is parallel to
 * n0 + n1 the plane through the chord and n0 is used. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

/* relative tolerance for "opposite normals": |n0 + n1| below this (unit normals) */
#define SK_OPPOSITE_NORMALS_TOL 1e-6
/* relative tolerance for a chord parallel to the normal plane: |f| <= tol * |d| |s| */
#define SK_PARALLEL_TOL 1e-9

sk_status sk__wireframe_targets(const sk_mesh *m, const double *normals, double *target,
                                sk_error *err)
{
    return sk__wireframe_targets_cn(m, normals, NULL, NULL, target, err);
}

sk_status sk__wireframe_targets_cn(const sk_mesh *m, const double *normals, const double *cn,
                                   const uint8_t *skip, double *target, sk_error *err)
{
    long nh = (long)m->num_halfedges;
    long bad = -1;
    int bad_kind = 0;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nh > 100000)
#endif
    for (long hh = 0; hh < nh; ++hh) {
        uint32_t h = (uint32_t)hh;
        double *t = target + 3 * (size_t)h;
        if (m->e_deleted[sk_edge(h)] || (skip && skip[sk_edge(h)])) {
            t[0] = t[1] = t[2] = 0.0;
            continue;
        }
        uint32_t a = sk_from(m, h), b = sk_to(m, h);
        const double *pa = m->positions + 3 * (size_t)a, *pb = m->positions + 3 * (size_t)b;
        const double *n0 = cn ? cn + 3 * (size_t)h : normals + 3 * (size_t)a;
        const double *n1 = cn ? cn + 3 * (size_t)sk_opp(h) : normals + 3 * (size_t)b;
        double d[3], s[3], f[3], dir[3];
        sk__sub3(d, pb, pa);
        double len = sk__norm3(d);
        sk__add3(s, n0, n1);
        int kind = 0;
        if (sk__norm3(s) < SK_OPPOSITE_NORMALS_TOL) {
            kind = 1;
        } else {
            sk__cross3(f, d, s);
            if (sk__norm3(f) <= SK_PARALLEL_TOL * len * sk__norm3(s))
                sk__cross3(f, d, n0);
            sk__cross3(dir, f, n0);
            if (sk__dot3(dir, d) < 0.0)
                sk__scale3(dir, dir, -1.0);
            if (sk__normalize3(dir) == 0.0 || sk__dot3(dir, d) <= 1e-12 * len)
                kind = 2;
        }
        if (kind) {
#ifdef SK_HAVE_OPENMP
#pragma omp critical(sk_wireframe_bad)
#endif
            if (bad < 0 || hh < bad) {
                bad = hh;
                bad_kind = kind;
            }
            t[0] = pa[0], t[1] = pa[1], t[2] = pa[2];
            continue;
        }
        double phi = acos(fmin(1.0, sk__dot3(dir, d) / len));
        if (phi > M_PI / 2)
            phi = M_PI / 2;
        double c = cos(phi / 2);
        sk__axpy3(t, pa, len / (3.0 * c * c), dir);
    }
    if (bad >= 0) {
        uint32_t h = (uint32_t)bad;
        /* the input's normals make the construction impossible: bad input, not a numerical
         * failure (a sharp edge whose per-corner normals were merged into one per vertex) */
        return sk__fail(err, SK_ERR_TOPOLOGY,
                        bad_kind == 1
                            ? "edge (%u, %u): the normals at its ends are opposite, no cubic "
                              "boundary curve can join the two tangent planes (estimate the "
                              "normals instead of the file's)"
                            : "edge (%u, %u): the edge is perpendicular to the tangent plane at "
                              "its first vertex, no cubic boundary curve leaves it in that plane",
                        sk_from(m, h), sk_to(m, h));
    }
    sk__ok(err);
    return SK_OK;
}

static double tri_area(const double *a, const double *b, const double *c)
{
    double u[3], v[3], x[3];
    sk__sub3(u, b, a);
    sk__sub3(v, c, a);
    sk__cross3(x, u, v);
    return 0.5 * sk__norm3(x);
}

void sk__patch_ratios(const sk_mesh *m, const double *target, double *r)
{
    long nfl = (long)m->num_faces;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl > 100000)
#endif
    for (long fl = 0; fl < nfl; ++fl) {
        uint32_t f = (uint32_t)fl; /* each face's r from its own corners: any thread order */
        if (m->f_deleted[f]) {
            r[f] = 0.0;
            continue;
        }
        uint32_t h0 = m->f_halfedge[f], h = h0;
        size_t n = 0;
        double sum = 0.0;
        do {
            /* corner at from(h): targets on h and on the reverse of prev(h) */
            const double *v = m->positions + 3 * (size_t)sk_from(m, h);
            sum += tri_area(v, target + 3 * (size_t)h, target + 3 * (size_t)sk_opp(m->h_prev[h]));
            ++n;
            h = m->h_next[h];
        } while (h != h0);
        /* eq. (7): Delta/3 = 1/4 for triangles, Delta/4 = 1/4 for quads */
        r[f] = (n == 3 ? sk__delta(3) / 3.0 : sk__delta(4) / 4.0) * sum;
    }
}

double sk__nu(double r_up, double r_down)
{
    /* eq. (6), oriented so that it agrees with eq. (3): -nu = Delta_up A_up / (Delta_down A_down) */
    return -r_up / r_down;
}
