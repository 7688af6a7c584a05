/* Repair after an insertion (Hormann, Greiner, Campagna, section 3): a vertex inserted at its
 * barycentric coordinates can leave triangles of its one ring inverted; it is moved to the
 * centroid of the kernel of its one ring, the region where every triangle around it is
 * counter-clockwise. */
#include "core/internal.h"
#include "param/mips_internal.h"

#include <limits.h>
#include <math.h>
#include <string.h>

/* True when every triangle around v is counter-clockwise with the MIPS margin at v. */
static bool ring_ok(const sk_mesh *m, const double *uv, uint32_t v, const double x[2])
{
    uint32_t h0 = m->v_halfedge[v], h = h0;
    if (h0 == SK_INVALID)
        return true;
    do {
        if (m->h_face[h] != SK_INVALID) {
            uint32_t a = m->h_vertex[h], b = m->h_vertex[m->h_next[h]];
            if (!sk__mips_corner_ok(x, uv + 2 * (size_t)a, uv + 2 * (size_t)b))
                return false;
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    return true;
}

/* Moves v to the centroid of the kernel of its one ring: the convex polygon where every triangle
 * (v, a, b) around v is counter-clockwise, i.e. the intersection of the half-planes left of each
 * opposite edge a -> b, found by clipping a large box (Sutherland-Hodgman). Returns false when the
 * kernel is empty (or too thin for the margin). */
static bool move_into_kernel(const sk_mesh *m, double *uv, uint32_t v)
{
    enum { CAP = 256 };
    double poly[2][CAP][2];
    int n = 0, cur = 0;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        const double *q = uv + 2 * (size_t)m->h_vertex[h];
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], q[k]);
            hi[k] = fmax(hi[k], q[k]);
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    double pad = (hi[0] - lo[0]) + (hi[1] - lo[1]) + 1e-300;
    double box[4][2] = {{lo[0] - pad, lo[1] - pad}, {hi[0] + pad, lo[1] - pad},
                        {hi[0] + pad, hi[1] + pad}, {lo[0] - pad, hi[1] + pad}};
    for (n = 0; n < 4; ++n)
        memcpy(poly[0][n], box[n], sizeof box[n]);
    h = h0;
    do {
        if (m->h_face[h] != SK_INVALID) {
            const double *a = uv + 2 * (size_t)m->h_vertex[h];
            const double *b = uv + 2 * (size_t)m->h_vertex[m->h_next[h]];
            double e[2] = {b[0] - a[0], b[1] - a[1]};
            int nn = 0;
            for (int i = 0; i < n && nn < CAP - 1; ++i) {
                const double *p = poly[cur][i], *q = poly[cur][(i + 1) % n];
                double sp = e[0] * (p[1] - a[1]) - e[1] * (p[0] - a[0]);
                double sq = e[0] * (q[1] - a[1]) - e[1] * (q[0] - a[0]);
                if (sp > 0)
                    memcpy(poly[1 - cur][nn++], p, 2 * sizeof(double));
                if ((sp > 0) != (sq > 0) && sp != sq) {
                    double t = sp / (sp - sq);
                    poly[1 - cur][nn][0] = p[0] + t * (q[0] - p[0]);
                    poly[1 - cur][nn][1] = p[1] + t * (q[1] - p[1]);
                    nn++;
                }
            }
            n = nn;
            cur = 1 - cur;
            if (n < 3)
                return false;
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    double area = 0.0, c[2] = {0.0, 0.0};
    for (int i = 0; i < n; ++i) {
        const double *p = poly[cur][i], *q = poly[cur][(i + 1) % n];
        double w = p[0] * q[1] - q[0] * p[1];
        area += w;
        c[0] += (p[0] + q[0]) * w;
        c[1] += (p[1] + q[1]) * w;
    }
    if (!(area > 0.0))
        return false;
    c[0] /= 3.0 * area;
    c[1] /= 3.0 * area;
    if (!ring_ok(m, uv, v, c))
        return false;
    memcpy(uv + 2 * (size_t)v, c, sizeof c);
    return true;
}

/* Faces per block of the parallel search for failing faces. */
#define REPAIR_BLOCK 2048

/* True when face f (alive) fails the margin at one of its corners. */
static bool face_bad(const sk_mesh *m, const double *uv, uint32_t f, uint32_t w[3])
{
    uint32_t h = m->f_halfedge[f], hb = m->h_next[h], hc = m->h_next[hb];
    w[0] = sk_from(m, h);
    w[1] = sk_from(m, hb);
    w[2] = sk_from(m, hc);
    const double *q[3] = {uv + 2 * (size_t)w[0], uv + 2 * (size_t)w[1], uv + 2 * (size_t)w[2]};
    return !(sk__mips_corner_ok(q[0], q[1], q[2]) && sk__mips_corner_ok(q[1], q[2], q[0]) &&
             sk__mips_corner_ok(q[2], q[0], q[1]));
}

/* Makes every triangle flip-free by moving the vertices of inverted triangles into the kernels of
 * their one rings, a few rounds; returns the number of moves, or -1 when some remain inverted. */
long sk__mips_repair(const sk_mesh *m, double *uv)
{
    long moved = -1, done = 0;
    size_t nf = m->num_faces, nb = (nf + REPAIR_BLOCK - 1) / REPAIR_BLOCK;
    uint8_t *flag = sk__malloc_array(nb ? nb : 1, 1); /* (NULL: every block scanned) */
    for (int round = 0; round < 8; ++round) {
        /* the blocks holding a face that fails the margin, found in parallel (read only). A
         * move makes every triangle around its vertex pass and changes no other, so the faces
         * that fail later in the scan below are among those failing now: visiting only the
         * flagged blocks does what a scan over all faces does */
        bool any = flag == NULL;
        if (flag) {
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(| : any) if (nf > 50000)
#endif
            for (long b = 0; b < (long)nb; ++b) {
                size_t f0 = (size_t)b * REPAIR_BLOCK, end = f0 + REPAIR_BLOCK < nf ? f0 + REPAIR_BLOCK : nf;
                uint8_t fb = 0;
                for (size_t f = f0; f < end && !fb; ++f) {
                    uint32_t w[3];
                    fb = !m->f_deleted[f] && face_bad(m, uv, (uint32_t)f, w);
                }
                flag[b] = fb;
                any = any || fb;
            }
        }
        size_t bad = 0;
        /* a scan over the faces (sequential memory); only the vertices of a face that fails the
         * margin somewhere get the one-ring test and, if needed, the move */
        for (size_t b = 0; b < nb && any; ++b) {
            if (flag && !flag[b])
                continue;
            size_t f0 = b * REPAIR_BLOCK, end = f0 + REPAIR_BLOCK < nf ? f0 + REPAIR_BLOCK : nf;
            for (size_t f = f0; f < end; ++f) {
                uint32_t w[3];
                if (m->f_deleted[f] || !face_bad(m, uv, (uint32_t)f, w))
                    continue;
                for (int k = 0; k < 3; ++k) {
                    if (ring_ok(m, uv, w[k], uv + 2 * (size_t)w[k]))
                        continue;
                    bad++;
                    done += move_into_kernel(m, uv, w[k]);
                }
            }
        }
        if (!bad) {
            moved = done;
            break;
        }
    }
    sk__free(flag);
    return moved;
}
