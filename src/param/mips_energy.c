/* MIPS energy and its local minimisation (Hormann & Greiner; Hormann, Greiner, Campagna sec. 4).
 *
 * With c_e the cotangent of the 3D angle opposite edge e of a triangle of area A and q the
 * parameter points, the Dirichlet identity gives |J|_F^2 = (1 / 2A) sum_e c_e |dq_e|^2 and
 * det J = A_uv / A, so
 *
 *     E_t = sigma1/sigma2 + sigma2/sigma1 = |J|_F^2 / det J = sum_e c_e |dq_e|^2 / (2 A_uv).   (*)
 *
 * As a function of one vertex q_i this is a convex quadratic over a positive linear function
 * (c_j + c_k = sin(theta_i) / (sin theta_j sin theta_k) > 0), hence convex on the kernel of the
 * one ring: a damped Newton step with backtracking that never leaves the kernel converges. */
#include "surfkit/mips.h"
#include "core/internal.h"
#include "core/vec.h"
#include "param/mips_internal.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void sk__mips_ctx_free(sk__mips_ctx *c)
{
    sk__free(c->tri);
    sk__free(c->cot);
    sk__free(c->vt_start);
    sk__free(c->rec);
    sk__free(c->movable);
    sk__free(c->s3);
    memset(c, 0, sizeof *c);
}

/* Triangle t of c from face f: its vertices, corner cotangents and 1 / 2A; false when it is
 * degenerate in 3D. */
static bool ctx_triangle(sk__mips_ctx *c, const sk_mesh *m, uint32_t f, size_t t)
{
    uint32_t h = m->f_halfedge[f];
    for (int k = 0; k < 3; ++k, h = m->h_next[h])
        c->tri[3 * t + k] = sk_from(m, h);
    const double *p[3];
    for (int k = 0; k < 3; ++k)
        p[k] = m->positions + 3 * (size_t)c->tri[3 * t + k];
    /* one normal per triangle: cot at corner k = (e1 . e2) / |e1 x e2| with the same
     * |e1 x e2| = 2A at every corner */
    double e[3][3], x[3]; /* e[k] = p[k+1] - p[k] */
    for (int k = 0; k < 3; ++k)
        sk__sub3(e[k], p[(k + 1) % 3], p[k]);
    sk__cross3(x, e[0], e[2]);
    double s = sk__norm3(x), lmax = 0.0;
    for (int k = 0; k < 3; ++k)
        lmax = fmax(lmax, sk__dot3(e[k], e[k]));
    if (!(s > 1e-14 * lmax + 1e-300))
        return false;
    for (int k = 0; k < 3; ++k) /* corner k: edges e[k] and -e[k+2] */
        c->cot[3 * t + k] = -sk__dot3(e[k], e[(k + 2) % 3]) / s;
    c->s3[t] = 1.0 / s;
    return true;
}

/* The corner records in face order (any vertex, also one whose triangles form several fans);
 * fill holds nv + 1 entries. */
static void by_faces(sk__mips_ctx *c, uint32_t *fill)
{
    size_t nv = c->nv, nt = c->nt;
    memset(c->vt_start, 0, (nv + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * nt; ++i)
        c->vt_start[c->tri[i] + 1]++;
    for (size_t v = 0; v < nv; ++v)
        c->vt_start[v + 1] += c->vt_start[v];
    memcpy(fill, c->vt_start, (nv + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * nt; ++i) {
        size_t t3 = i - i % 3, k = i % 3;
        sk__mips_corner r = {c->tri[t3 + (k + 1) % 3], c->tri[t3 + (k + 2) % 3], c->cot[t3 + k],
                        c->cot[t3 + (k + 1) % 3], c->cot[t3 + (k + 2) % 3], c->s3[t3 / 3]};
        c->rec[fill[c->tri[i]]++] = r;
    }
}

/* The triangles around v in ring order from v_halfedge (clockwise), written to out[i].j (when out
 * is non-NULL); returns their number. face_t maps a face to its triangle (NULL: the same index). */
static uint32_t ring_triangles(const sk_mesh *m, const uint32_t *face_t, uint32_t v,
                               sk__mips_corner *out)
{
    uint32_t h0 = m->v_halfedge[v], h = h0, n = 0;
    if (h0 == SK_INVALID || m->v_deleted[v])
        return 0;
    do {
        uint32_t f = m->h_face[h];
        if (f != SK_INVALID && !m->f_deleted[f]) {
            if (out)
                out[n].j = face_t ? face_t[f] : f;
            n++;
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    return n;
}

/* Corners ahead whose triangle data the record fill prefetches (the triangles of a ring are far
 * apart in the triangle arrays: waiting on them was most of the fill's time) */
#define SK__MIPS_FILL_AHEAD 16
#define SK__MIPS_FILL_BLOCK 4096 /* vertices per block of the fill */

/* The corner records of vertices [v0, v1), whose runs hold their triangles in .j (ring_triangles),
 * in place. */
static void fill_records(const sk__mips_ctx *c, size_t v0, size_t v1)
{
    size_t end = c->vt_start[v1];
    for (size_t v = v0; v < v1; ++v) {
        for (size_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
#if defined(__GNUC__)
            if (i + SK__MIPS_FILL_AHEAD < end) {
                size_t ta = c->rec[i + SK__MIPS_FILL_AHEAD].j;
                __builtin_prefetch(c->tri + 3 * ta);
                __builtin_prefetch(c->cot + 3 * ta);
                __builtin_prefetch(c->s3 + ta);
            }
#endif
            size_t t = c->rec[i].j, k = 0;
            const uint32_t *tv = c->tri + 3 * t;
            while (k < 2 && tv[k] != v)
                ++k;
            const double *ct = c->cot + 3 * t;
            c->rec[i] = (sk__mips_corner){tv[(k + 1) % 3], tv[(k + 2) % 3], ct[k], ct[(k + 1) % 3],
                                          ct[(k + 2) % 3], c->s3[t]};
        }
    }
}

sk_status sk__mips_ctx_init(sk__mips_ctx *c, const sk_mesh *m, bool fixed_boundary, sk_error *err)
{
    memset(c, 0, sizeof *c);
    size_t nf = m->num_faces, nv = m->num_vertices, nt = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f];
        if (m->h_next[m->h_next[m->h_next[h]]] != h)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu is not a triangle: MIPS needs a "
                            "triangle mesh", f);
        nt++;
    }
    c->nv = nv;
    c->nt = nt;
    c->tri = sk__malloc_array(3 * nt, sizeof(uint32_t));
    c->cot = sk__malloc_array(3 * nt, sizeof(double));
    c->vt_start = sk__calloc_array(nv + 1, sizeof(uint32_t));
    c->rec = sk__malloc_array(3 * nt, sizeof(sk__mips_corner));
    c->movable = sk__malloc_array(nv, 1);
    c->s3 = sk__malloc_array(nt ? nt : 1, sizeof(double));
    /* per face its triangle when some are deleted; per vertex a fill pointer in by_faces */
    uint32_t *fill = sk__malloc_array((nf > nv ? nf : nv) + 1, sizeof(uint32_t));
    if (!c->tri || !c->cot || !c->vt_start || !c->rec || !c->movable || !c->s3 || !fill) {
        sk__free(fill);
        sk__mips_ctx_free(c);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    /* the triangles in face order: in parallel when no face is deleted (triangle t = face t;
     * each writes only its own entries), else one pass; the first degenerate face is reported */
    long bad = LONG_MAX;
    if (nt == nf) {
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(min : bad) if (nf > 50000)
#endif
        for (long f = 0; f < (long)nf; ++f)
            if (!ctx_triangle(c, m, (uint32_t)f, (size_t)f) && f < bad)
                bad = f;
    } else {
        for (size_t f = 0, t = 0; f < nf && bad == LONG_MAX; ++f)
            if (!m->f_deleted[f] && !ctx_triangle(c, m, (uint32_t)f, t++))
                bad = (long)f;
    }
    if (bad != LONG_MAX) {
        sk__free(fill);
        sk__mips_ctx_free(c);
        return sk__fail(err, SK_ERR_TOPOLOGY, "face %ld is degenerate in 3D (zero area): MIPS is "
                        "undefined there; remove it first", bad);
    }
    /* the corner records per vertex, in the order of its ring (from v_halfedge, clockwise):
     * counted and filled in parallel over the vertices, each writing only its own run (the same
     * records for any thread count) */
    if (nt != nf)
        for (size_t f = 0, t = 0; f < nf; ++f)
            fill[f] = m->f_deleted[f] ? SK_INVALID : (uint32_t)t++;
    const uint32_t *face_t = nt != nf ? fill : NULL;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 4096) if (nv > 50000)
#endif
    for (long v = 0; v < (long)nv; ++v)
        c->vt_start[v + 1] = ring_triangles(m, face_t, (uint32_t)v, NULL);
    for (size_t v = 0; v < nv; ++v)
        c->vt_start[v + 1] += c->vt_start[v];
    /* the triangles of each run first, then the records from them (with the triangles' data
     * prefetched ahead), per block of vertices */
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 1) if (nv > 50000)
#endif
    for (long b = 0; b < (long)((nv + SK__MIPS_FILL_BLOCK - 1) / SK__MIPS_FILL_BLOCK); ++b) {
        size_t v0 = (size_t)b * SK__MIPS_FILL_BLOCK;
        size_t v1 = v0 + SK__MIPS_FILL_BLOCK < nv ? v0 + SK__MIPS_FILL_BLOCK : nv;
        for (size_t v = v0; v < v1; ++v)
            ring_triangles(m, face_t, (uint32_t)v, c->rec + c->vt_start[v]);
        fill_records(c, v0, v1);
    }
    if (c->vt_start[nv] != 3 * nt) /* a vertex with several fans: the records in face order */
        by_faces(c, fill);
    sk__free(fill);
    for (size_t v = 0; v < nv; ++v)
        c->movable[v] = !m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID &&
                        !(fixed_boundary && sk_is_boundary_v(m, (uint32_t)v));
    return SK_OK;
}

double sk__mips_tri_terms(const sk__mips_ctx *c, size_t t, const double *uv, double *twice)
{
    const uint32_t *v = c->tri + 3 * t;
    const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *d = uv + 2 * (size_t)v[2];
    double ab[2] = {b[0] - a[0], b[1] - a[1]}, ad[2] = {d[0] - a[0], d[1] - a[1]};
    double bd[2] = {d[0] - b[0], d[1] - b[1]};
    *twice = sk__cross2(ab, ad);
    if (!(*twice > 0.0))
        return INFINITY;
    const double *ct = c->cot + 3 * t;
    return (ct[0] * sk__dot2(bd, bd) + ct[1] * sk__dot2(ad, ad) + ct[2] * sk__dot2(ab, ab)) /
           *twice;
}

/* Energy (*) of triangle t; +inf if its parameter triangle is not positively oriented. */
static double tri_energy(const sk__mips_ctx *c, size_t t, const double *uv)
{
    if (c->area_theta > 0.0)
        return sk__mips_area_tri_energy(c, t, uv);
    double twice;
    return sk__mips_tri_terms(c, t, uv, &twice);
}

bool sk__mips_corner_terms(const sk__mips_corner *r, const double *uv, const double x[2],
                           bool derivs, double *m, double *b, double gm[2], double gb[2],
                           double hm[3])
{
    const double *qj = uv + 2 * (size_t)r->j, *qk = uv + 2 * (size_t)r->k;
    double ci = r->ci, cj = r->cj, ck = r->ck;
    double dj[2] = {x[0] - qj[0], x[1] - qj[1]}, dk[2] = {x[0] - qk[0], x[1] - qk[1]};
    double jk[2] = {qk[0] - qj[0], qk[1] - qj[1]};
    /* b = 2 A_uv = (qj - x) x (qk - x), linear in x with gradient perp(qk - qj) */
    if (!sk__mips_corner_ok(x, qj, qk))
        return false;
    *b = sk__cross2(dj, dk);
    /* a = ck |x - qj|^2 + cj |x - qk|^2 + ci |qj - qk|^2 (edge opposite each corner) */
    double a = ck * sk__dot2(dj, dj) + cj * sk__dot2(dk, dk) + ci * sk__dot2(jk, jk);
    *m = a / *b;
    if (!derivs)
        return true;
    double ga[2] = {2.0 * (ck * dj[0] + cj * dk[0]), 2.0 * (ck * dj[1] + cj * dk[1])};
    gb[0] = -jk[1];
    gb[1] = jk[0];
    double ha = 2.0 * (cj + ck);
    double ib = 1.0 / *b, ib2 = ib * ib, ib3 = ib2 * ib;
    gm[0] = ga[0] * ib - a * gb[0] * ib2;
    gm[1] = ga[1] * ib - a * gb[1] * ib2;
    /* H = Ha / b - (ga gb^T + gb ga^T) / b^2 + 2 a gb gb^T / b^3 */
    hm[0] = ha * ib - 2.0 * ga[0] * gb[0] * ib2 + 2.0 * a * gb[0] * gb[0] * ib3;
    hm[1] = -(ga[0] * gb[1] + gb[0] * ga[1]) * ib2 + 2.0 * a * gb[0] * gb[1] * ib3;
    hm[2] = ha * ib - 2.0 * ga[1] * gb[1] * ib2 + 2.0 * a * gb[1] * gb[1] * ib3;
    return true;
}

/* Sum of (*) over the triangles around v with v at position x; +inf outside the kernel.
 * With g, H non-NULL also the gradient and Hessian with respect to x. */
double sk__mips_ring_energy(const sk__mips_ctx *c, uint32_t v, const double *uv, const double x[2],
                          double g[2], double H[3])
{
    if (c->area_theta > 0.0)
        return sk__mips_area_ring_energy(c, v, uv, x, g, H);
    double e = 0.0;
    if (g) {
        g[0] = g[1] = 0.0;
        H[0] = H[1] = H[2] = 0.0;
    }
    for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
        double m, b, gm[2], gb[2], hm[3];
        if (!sk__mips_corner_terms(c->rec + i, uv, x, g != NULL, &m, &b, gm, gb, hm))
            return INFINITY;
        e += m;
        if (g) {
            g[0] += gm[0];
            g[1] += gm[1];
            H[0] += hm[0];
            H[1] += hm[1];
            H[2] += hm[2];
        }
    }
    return e;
}

/* One local step at v: damped Newton with backtracking inside the kernel. Returns the energy
 * decrease (>= 0). */
double sk__mips_local_step(const sk__mips_ctx *c, uint32_t v, double *uv)
{
    double *x = uv + 2 * (size_t)v;
    double g[2], H[3];
    double e0 = sk__mips_ring_energy(c, v, uv, x, g, H);
    if (!isfinite(e0))
        return 0.0;
    double det = H[0] * H[2] - H[1] * H[1];
    double d[2];
    if (det > 0.0 && H[0] > 0.0) {
        d[0] = -(H[2] * g[0] - H[1] * g[1]) / det;
        d[1] = -(-H[1] * g[0] + H[0] * g[1]) / det;
    } else { /* not expected (the local problem is convex); fall back to gradient descent */
        double s = 1.0 / (fabs(H[0]) + fabs(H[2]) + 1e-300);
        d[0] = -s * g[0];
        d[1] = -s * g[1];
    }
    double slope = g[0] * d[0] + g[1] * d[1];
    if (!(slope < 0.0))
        return 0.0;
    double t = 1.0;
    for (int it = 0; it < 40; ++it, t *= 0.5) {
        double y[2] = {x[0] + t * d[0], x[1] + t * d[1]};
        double e = sk__mips_ring_energy(c, v, uv, y, NULL, NULL);
        if (e <= e0 + 1e-4 * t * slope) { /* Armijo; +inf (left the kernel) fails it */
            x[0] = y[0];
            x[1] = y[1];
            return e0 - e;
        }
    }
    return 0.0;
}

double sk__mips_total_energy(const sk__mips_ctx *c, const double *uv, size_t *inverted)
{
    size_t nt = c->nt, nb = sk__mips_blocks(nt), bad[SK__MIPS_BLOCKS];
    double part[SK__MIPS_BLOCKS];
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 1) if (nb > 8)
#endif
    for (long b = 0; b < (long)nb; ++b) {
        double e = 0.0;
        size_t nbad = 0;
        for (size_t t = sk__mips_block_lo(nt, nb, (size_t)b); t < sk__mips_block_lo(nt, nb, (size_t)b + 1); ++t) {
            double et = tri_energy(c, t, uv);
            if (isfinite(et))
                e += et;
            else
                nbad++;
        }
        part[b] = e;
        bad[b] = nbad;
    }
    double e = 0.0;
    size_t nbad = 0;
    for (size_t b = 0; b < nb; ++b) {
        e += part[b];
        nbad += bad[b];
    }
    if (inverted)
        *inverted = nbad;
    return e;
}

/* Total energy with every corner checked against the margin of the local steps (+inf if any
 * triangle is inverted or too thin). */
double sk__mips_total_energy_strict(const sk__mips_ctx *c, const double *uv)
{
    size_t nt = c->nt, nb = sk__mips_blocks(nt);
    double part[SK__MIPS_BLOCKS];
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 1) if (nb > 8)
#endif
    for (long b = 0; b < (long)nb; ++b) {
        double e = 0.0;
        for (size_t t = sk__mips_block_lo(nt, nb, (size_t)b); t < sk__mips_block_lo(nt, nb, (size_t)b + 1); ++t) {
            const uint32_t *v = c->tri + 3 * t;
            const double *p0 = uv + 2 * (size_t)v[0], *p1 = uv + 2 * (size_t)v[1],
                         *p2 = uv + 2 * (size_t)v[2];
            if (!sk__mips_corner_ok(p0, p1, p2) || !sk__mips_corner_ok(p1, p2, p0) ||
                !sk__mips_corner_ok(p2, p0, p1)) {
                e = INFINITY;
                break;
            }
            e += tri_energy(c, t, uv);
        }
        part[b] = e;
    }
    double e = 0.0;
    for (size_t b = 0; b < nb; ++b)
        e += part[b];
    return e;
}

/* The free-boundary energy is invariant under similarities, so nothing holds the scale of uv:
 * over many steps it drifts (to 1e9 on nefertiti). Rescales the vertices of the triangles by a
 * power of two so that the larger side of their bounding box lies in [1, 2): exact in floating
 * point, so the optimization computes the same mantissas as without it. A box whose centre is
 * farther than SK__MIPS_FAR_CENTRE extents from the origin is also moved to the origin (which
 * rounds). Returns the exponent e of the factor 2^e applied (0: unchanged). */
#define SK__MIPS_FAR_CENTRE 4.0

int sk__mips_renormalize(const sk__mips_ctx *c, double *uv)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t v = 0; v < c->nv; ++v) {
        if (c->vt_start[v] == c->vt_start[v + 1])
            continue;
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], uv[2 * v + (size_t)k]);
            hi[k] = fmax(hi[k], uv[2 * v + (size_t)k]);
        }
    }
    double ext = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(ext > 0.0) || !isfinite(ext))
        return 0;
    int e = -ilogb(ext);
    double mid[2] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])};
    bool far = fmax(fabs(mid[0]), fabs(mid[1])) > SK__MIPS_FAR_CENTRE * ext;
    if (e == 0 && !far)
        return 0;
    for (size_t v = 0; v < c->nv; ++v) {
        if (c->vt_start[v] == c->vt_start[v + 1])
            continue;
        for (int k = 0; k < 2; ++k) {
            double x = uv[2 * v + (size_t)k];
            uv[2 * v + (size_t)k] = ldexp(far ? x - mid[k] : x, e);
        }
    }
    return e;
}

sk_status sk_mips_energy(const sk_mesh *mesh, const double *uv, double *energy, size_t *inverted,
                         sk_error *err)
{
    sk__mips_ctx c;
    sk_status st = sk__mips_ctx_init(&c, mesh, false, err);
    if (st)
        return st;
    *energy = sk__mips_total_energy(&c, uv, inverted);
    sk__mips_ctx_free(&c);
    return SK_OK;
}
