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
#include "surfkit/solve.h"
#include "core/internal.h"
#include "core/vec.h"
#include "param/mips_internal.h"

/* colours of the multicolour sweep (64 covers every valence below 64) */
#define SK__MIPS_MAX_COLORS 64

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What a local step at vertex i needs of one incident triangle (i, j, k), stored per vertex
 * contiguously so that a step touches one run of memory plus the neighbours' uv. */
typedef struct corner_rec {
    uint32_t j, k;     /* the other two vertices, counter-clockwise */
    double ci, cj, ck; /* cotangents of the 3D angles at i, j, k */
} corner_rec;

typedef struct mips_ctx {
    size_t nv, nt;
    uint32_t *tri;      /* 3 vertex ids per triangle (ccw) */
    double *cot;        /* cotangent of the 3D angle at each corner */
    uint32_t *vt_start; /* vertex -> its corner records (CSR) */
    corner_rec *rec;
    uint8_t *movable;
} mips_ctx;

static void ctx_free(mips_ctx *c)
{
    sk__free(c->tri);
    sk__free(c->cot);
    sk__free(c->vt_start);
    sk__free(c->rec);
    sk__free(c->movable);
}

static sk_status ctx_init(mips_ctx *c, const sk_mesh *m, bool fixed_boundary, sk_error *err)
{
    memset(c, 0, sizeof *c);
    size_t nf = m->num_faces, nv = m->num_vertices, nt = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_deleted[f])
            continue;
        if (sk_mesh_face_size(m, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu is not a triangle: MIPS needs a "
                            "triangle mesh", f);
        nt++;
    }
    c->nv = nv;
    c->nt = nt;
    c->tri = sk__malloc_array(3 * nt, sizeof(uint32_t));
    c->cot = sk__malloc_array(3 * nt, sizeof(double));
    c->vt_start = sk__calloc_array(nv + 1, sizeof(uint32_t));
    c->rec = sk__malloc_array(3 * nt, sizeof(corner_rec));
    c->movable = sk__malloc_array(nv, 1);
    if (!c->tri || !c->cot || !c->vt_start || !c->rec || !c->movable) {
        ctx_free(c);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    size_t t = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_deleted[f])
            continue;
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
            goto degenerate;
        for (int k = 0; k < 3; ++k) /* corner k: edges e[k] and -e[k+2] */
            c->cot[3 * t + k] = -sk__dot3(e[k], e[(k + 2) % 3]) / s;
        for (int k = 0; k < 3; ++k)
            c->vt_start[c->tri[3 * t + k] + 1]++;
        ++t;
        continue;
    degenerate:
        sk__fail(err, SK_ERR_TOPOLOGY, "face %zu is degenerate in 3D (zero area): MIPS is "
                 "undefined there; remove it first", f);
        ctx_free(c);
        return SK_ERR_TOPOLOGY;
    }
    for (size_t v = 0; v < nv; ++v)
        c->vt_start[v + 1] += c->vt_start[v];
    uint32_t *fill = sk__malloc_array(nv + 1, sizeof(uint32_t));
    if (!fill) {
        ctx_free(c);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memcpy(fill, c->vt_start, (nv + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * nt; ++i) {
        size_t t3 = i - i % 3, k = i % 3;
        corner_rec r = {c->tri[t3 + (k + 1) % 3], c->tri[t3 + (k + 2) % 3], c->cot[t3 + k],
                        c->cot[t3 + (k + 1) % 3], c->cot[t3 + (k + 2) % 3]};
        c->rec[fill[c->tri[i]]++] = r;
    }
    sk__free(fill);
    for (size_t v = 0; v < nv; ++v)
        c->movable[v] = !m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID &&
                        !(fixed_boundary && sk_is_boundary_v(m, (uint32_t)v));
    return SK_OK;
}

/* Energy (*) of triangle t; +inf if its parameter triangle is not positively oriented. */
static double tri_energy(const mips_ctx *c, size_t t, const double *uv)
{
    const uint32_t *v = c->tri + 3 * t;
    const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *d = uv + 2 * (size_t)v[2];
    double ab[2] = {b[0] - a[0], b[1] - a[1]}, ad[2] = {d[0] - a[0], d[1] - a[1]};
    double bd[2] = {d[0] - b[0], d[1] - b[1]};
    double twice = sk__cross2(ab, ad);
    if (!(twice > 0.0))
        return INFINITY;
    const double *ct = c->cot + 3 * t;
    return (ct[0] * sk__dot2(bd, bd) + ct[1] * sk__dot2(ad, ad) + ct[2] * sk__dot2(ab, ab)) / twice;
}

/* Sum of (*) over the triangles around v with v at position x; +inf outside the kernel.
 * With g, H non-NULL also the gradient and Hessian with respect to x. */
static double ring_energy(const mips_ctx *c, uint32_t v, const double *uv, const double x[2],
                          double g[2], double H[3])
{
    double e = 0.0;
    if (g) {
        g[0] = g[1] = 0.0;
        H[0] = H[1] = H[2] = 0.0;
    }
    for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
        const corner_rec *r = c->rec + i;
        const double *qj = uv + 2 * (size_t)r->j, *qk = uv + 2 * (size_t)r->k;
        double ci = r->ci, cj = r->cj, ck = r->ck;
        double dj[2] = {x[0] - qj[0], x[1] - qj[1]}, dk[2] = {x[0] - qk[0], x[1] - qk[1]};
        double jk[2] = {qk[0] - qj[0], qk[1] - qj[1]};
        /* b = 2 A_uv = (qj - x) x (qk - x), linear in x with gradient perp(qk - qj) */
        if (!sk__mips_corner_ok(x, qj, qk))
            return INFINITY;
        double b = sk__cross2(dj, dk);
        /* a = ck |x - qj|^2 + cj |x - qk|^2 + ci |qj - qk|^2 (edge opposite each corner) */
        double a = ck * sk__dot2(dj, dj) + cj * sk__dot2(dk, dk) + ci * sk__dot2(jk, jk);
        e += a / b;
        if (g) {
            double ga[2] = {2.0 * (ck * dj[0] + cj * dk[0]), 2.0 * (ck * dj[1] + cj * dk[1])};
            double gb[2] = {-jk[1], jk[0]};
            double ha = 2.0 * (cj + ck);
            double ib = 1.0 / b, ib2 = ib * ib, ib3 = ib2 * ib;
            g[0] += ga[0] * ib - a * gb[0] * ib2;
            g[1] += ga[1] * ib - a * gb[1] * ib2;
            /* H = Ha / b - (ga gb^T + gb ga^T) / b^2 + 2 a gb gb^T / b^3 */
            H[0] += ha * ib - 2.0 * ga[0] * gb[0] * ib2 + 2.0 * a * gb[0] * gb[0] * ib3;
            H[1] += -(ga[0] * gb[1] + gb[0] * ga[1]) * ib2 + 2.0 * a * gb[0] * gb[1] * ib3;
            H[2] += ha * ib - 2.0 * ga[1] * gb[1] * ib2 + 2.0 * a * gb[1] * gb[1] * ib3;
        }
    }
    return e;
}

/* One local step at v: damped Newton with backtracking inside the kernel. Returns the energy
 * decrease (>= 0). */
static double local_step(const mips_ctx *c, uint32_t v, double *uv)
{
    double *x = uv + 2 * (size_t)v;
    double g[2], H[3];
    double e0 = ring_energy(c, v, uv, x, g, H);
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
        double e = ring_energy(c, v, uv, y, NULL, NULL);
        if (e <= e0 + 1e-4 * t * slope) { /* Armijo; +inf (left the kernel) fails it */
            x[0] = y[0];
            x[1] = y[1];
            return e0 - e;
        }
    }
    return 0.0;
}

static double total_energy(const mips_ctx *c, const double *uv, size_t *inverted)
{
    double e = 0.0;
    size_t bad = 0;
    for (size_t t = 0; t < c->nt; ++t) {
        double et = tri_energy(c, t, uv);
        if (isfinite(et))
            e += et;
        else
            bad++;
    }
    if (inverted)
        *inverted = bad;
    return e;
}


/* ---------------------------------------------------------------------------------------------
 * Global step. With f_t = a_t - 2 b_t >= 0 (a_t the numerator of (*), b_t = 2 A_uv; f_t is the
 * conformal (LSCM) energy of the triangle, zero exactly for similarities), E_t = 2 + f_t / b_t and
 * its Hessian is H(f_t) / b_t plus terms that vanish with f_t. The model
 *
 *     P = sum_t (H(f_t) + mu H(a_t)) / b_t   (mu = 1e-3; H(a_t) = 2 K_t (x) I, K_t the cotangent matrix)
 *
 * is positive semidefinite (f_t >= 0 for every uv), its null space is the translations only
 * (mu > 0), and it is the Gauss-Newton matrix of the energy near a conformal map. The direction
 * solves P d = -grad E over the 2n unknowns (u0, v0, u1, v1, ...), assembled per vertex
 * (column gather, no atomics), factorized by CHOLMOD (pattern analysed once per mesh).
 * ------------------------------------------------------------------------------------------- */

#define SK__MIPS_GLOBAL_MU 0.001

typedef struct mips_global {
    bool scalar;  /* the n x n model without the area coupling (same matrix for u and v): 8x cheaper
                     factorizations but far slower convergence on lion-head (33470.5 vs 33468.3
                     after 30 steps); kept for comparison, not used */
    bool frozen;  /* factorize once, at the first step (the model at the start of the level) */
    bool factored;
    bool refactor; /* the frozen model did poorly (line search cut the step): factorize again */
    int since_factor; /* steps on the current factorization (a frozen model serves at most 3) */
    sk_sparse *P;
    sk_solver *solver;
    uint32_t *nb_start, *nb; /* per vertex: sorted movable neighbours w > v */
    double *g, *d, *x0, *tmp;
} mips_global;

static void global_free(mips_global *G)
{
    sk_sparse_destroy(&G->P);
    sk_solver_destroy(&G->solver);
    sk__free(G->nb_start);
    sk__free(G->nb);
    sk__free(G->g);
    sk__free(G->d);
    sk__free(G->x0);
    sk__free(G->tmp);
    memset(G, 0, sizeof *G);
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Pattern of the lower triangle: column 2v has rows 2v, 2v+1, then 2w, 2w+1 for each movable
 * neighbour w > v; column 2v+1 has rows 2v+1, then 2w, 2w+1. Non-movable vertices get identity
 * columns (their direction is zero). */
static sk_status global_init(mips_global *G, const mips_ctx *c, bool scalar, bool frozen,
                             sk_error *err)
{
    memset(G, 0, sizeof *G);
    G->scalar = scalar;
    G->frozen = frozen;
    size_t nv = c->nv, n2 = 2 * nv;
    G->nb_start = sk__calloc_array(nv + 1, sizeof(uint32_t));
    G->nb = sk__malloc_array(c->vt_start[nv] * 2 + 1, sizeof(uint32_t));
    G->g = sk__malloc_array(n2 + 1, sizeof(double));
    G->d = sk__malloc_array(n2 + 1, sizeof(double));
    G->x0 = sk__malloc_array(n2 + 1, sizeof(double));
    G->tmp = sk__malloc_array(2 * n2 + 1, sizeof(double));
    G->P = sk__calloc_array(1, sizeof *G->P);
    if (!G->nb_start || !G->nb || !G->g || !G->d || !G->x0 || !G->tmp || !G->P)
        goto nomem;
    size_t fill = 0;
    for (size_t v = 0; v < nv; ++v) {
        size_t s0 = fill;
        if (c->movable[v])
            for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
                uint32_t w[2] = {c->rec[i].j, c->rec[i].k};
                for (int q = 0; q < 2; ++q)
                    if (w[q] > v && c->movable[w[q]])
                        G->nb[fill++] = w[q];
            }
        qsort(G->nb + s0, fill - s0, sizeof(uint32_t), cmp_u32);
        size_t u = s0;
        for (size_t i = s0; i < fill; ++i)
            if (u == s0 || G->nb[u - 1] != G->nb[i])
                G->nb[u++] = G->nb[i];
        fill = u;
        G->nb_start[v + 1] = (uint32_t)fill;
    }
    sk_sparse *P = G->P;
    P->storage = SK_SPARSE_LOWER;
    if (scalar) {
        P->n = nv;
        P->nnz = nv + (size_t)fill;
        P->colptr = sk__malloc_array(nv + 1, sizeof(int));
        P->rowind = sk__malloc_array(P->nnz, sizeof(int));
        P->values = sk__calloc_array(P->nnz, sizeof(double));
        if (!P->colptr || !P->rowind || !P->values)
            goto nomem;
        size_t k = 0;
        for (size_t v = 0; v < nv; ++v) {
            P->colptr[v] = (int)k;
            P->rowind[k++] = (int)v;
            for (uint32_t i = G->nb_start[v]; i < G->nb_start[v + 1]; ++i)
                P->rowind[k++] = (int)G->nb[i];
        }
        P->colptr[nv] = (int)k;
        goto solver;
    }
    P->n = n2;
    P->nnz = 3 * nv + 4 * (size_t)fill;
    P->colptr = sk__malloc_array(n2 + 1, sizeof(int));
    P->rowind = sk__malloc_array(P->nnz, sizeof(int));
    P->values = sk__calloc_array(P->nnz, sizeof(double));
    if (!P->colptr || !P->rowind || !P->values)
        goto nomem;
    size_t k = 0;
    for (size_t v = 0; v < nv; ++v) {
        uint32_t a = G->nb_start[v], b = G->nb_start[v + 1];
        P->colptr[2 * v] = (int)k;
        P->rowind[k++] = (int)(2 * v);
        P->rowind[k++] = (int)(2 * v + 1);
        for (uint32_t i = a; i < b; ++i) {
            P->rowind[k++] = (int)(2 * G->nb[i]);
            P->rowind[k++] = (int)(2 * G->nb[i] + 1);
        }
        P->colptr[2 * v + 1] = (int)k;
        P->rowind[k++] = (int)(2 * v + 1);
        for (uint32_t i = a; i < b; ++i) {
            P->rowind[k++] = (int)(2 * G->nb[i]);
            P->rowind[k++] = (int)(2 * G->nb[i] + 1);
        }
    }
    P->colptr[n2] = (int)k;
solver:; /* a failed solver setup frees G too: the caller only frees a G that was made */
    sk_status st = sk_solver_create(P, SK_SOLVER_CHOLESKY, &G->solver, err);
    if (st)
        global_free(G);
    return st;
nomem:
    global_free(G);
    return sk__fail(err, SK_ERR_NOMEM, "out of memory");
}

/* Fills P's values at uv and the gradient g of the total energy. */
static void global_assemble(mips_global *G, const mips_ctx *c, const double *uv)
{
    sk_sparse *P = G->P;
    const double mu = SK__MIPS_GLOBAL_MU;
    long nv = (long)c->nv;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static, 4096) if (nv > 50000)
#endif
    for (long vl = 0; vl < nv; ++vl) {
        uint32_t v = (uint32_t)vl;
        uint32_t a = G->nb_start[v], b = G->nb_start[v + 1], m = b - a;
        bool sc = G->scalar;
        double *cu = P->values + P->colptr[sc ? v : 2 * v];
        double *cv = sc ? cu : P->values + P->colptr[2 * v + 1];
        memset(cu, 0, (sc ? 1 + m : 2 + 2 * m) * sizeof(double));
        if (!sc)
            memset(cv, 0, (1 + 2 * m) * sizeof(double));
        double *g = G->g + 2 * v;
        if (!c->movable[v]) {
            cu[0] = cv[0] = 1.0;
            g[0] = g[1] = 0.0;
            continue;
        }
        double H[3];
        ring_energy(c, v, uv, uv + 2 * (size_t)v, g, H);
        const double *x = uv + 2 * (size_t)v;
        for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
            const corner_rec *r = c->rec + i;
            const double *qj = uv + 2 * (size_t)r->j, *qk = uv + 2 * (size_t)r->k;
            double bt = (qj[0] - x[0]) * (qk[1] - x[1]) - (qj[1] - x[1]) * (qk[0] - x[0]);
            double w = 1.0 / bt, s = 2.0 * (1.0 + mu) * w;
            /* diagonal block: 2(1+mu) w K[0][0] I */
            cu[0] += s * (r->cj + r->ck);
            if (!sc)
                cv[0] += s * (r->cj + r->ck);
            uint32_t nbr[2] = {r->j, r->k};
            double kk[2] = {-r->ck, -r->cj};   /* K[j][v], K[k][v] */
            double hb[2] = {2.0 * w, -2.0 * w}; /* P[u_r][v_v] for r = j, k; P[v_r][u_v] = -that */
            for (int q = 0; q < 2; ++q) {
                uint32_t wv = nbr[q];
                if (wv < v || !c->movable[wv])
                    continue;
                uint32_t lo = a, hi = b; /* binary search of wv in nb[a, b) */
                while (lo < hi) {
                    uint32_t mid = (lo + hi) / 2;
                    if (G->nb[mid] < wv)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                uint32_t p = lo - a;
                if (sc) {
                    cu[1 + p] += s * kk[q];
                    continue;
                }
                cu[2 + 2 * p] += s * kk[q];     /* P[u_w][u_v] */
                cu[2 + 2 * p + 1] -= hb[q];     /* P[v_w][u_v] */
                cv[1 + 2 * p] += hb[q];         /* P[u_w][v_v] */
                cv[1 + 2 * p + 1] += s * kk[q]; /* P[v_w][v_v] */
            }
        }
        /* translations are P's null space (free boundary): a tiny ridge keeps it definite; the
         * gradient has no component there */
        cu[0] *= 1.0 + 1e-10;
        if (!sc)
            cv[0] *= 1.0 + 1e-10;
    }
}

/* Largest t in (0, tmax] for which every triangle stays positively oriented along uv + t d: the
 * smallest positive root of each triangle's signed-area quadratic b0 + b1 t + b2 t^2. */
static double max_flip_free_step(const mips_ctx *c, const double *uv, const double *d, double tmax)
{
    long nt = (long)c->nt;
    double best = tmax;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(min : best) if (nt > 100000)
#endif
    for (long t = 0; t < nt; ++t) {
        const uint32_t *v = c->tri + 3 * t;
        const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *q = uv + 2 * (size_t)v[2];
        const double *da = d + 2 * (size_t)v[0], *db = d + 2 * (size_t)v[1], *dq = d + 2 * (size_t)v[2];
        double e1[2] = {b[0] - a[0], b[1] - a[1]}, e2[2] = {q[0] - a[0], q[1] - a[1]};
        double f1[2] = {db[0] - da[0], db[1] - da[1]}, f2[2] = {dq[0] - da[0], dq[1] - da[1]};
        double b0 = sk__cross2(e1, e2), b1 = sk__cross2(e1, f2) + sk__cross2(f1, e2);
        double b2 = sk__cross2(f1, f2);
        double root = INFINITY;
        if (fabs(b2) < 1e-300 * fabs(b1) || b2 == 0.0) {
            if (b1 < 0.0)
                root = -b0 / b1;
        } else {
            double disc = b1 * b1 - 4.0 * b2 * b0;
            if (disc >= 0.0) {
                double sq = sqrt(disc);
                /* stable roots */
                double qq = -0.5 * (b1 + (b1 >= 0.0 ? sq : -sq));
                double r1 = qq / b2, r2 = qq != 0.0 ? b0 / qq : INFINITY;
                if (r1 > 0.0 && r1 < root)
                    root = r1;
                if (r2 > 0.0 && r2 < root)
                    root = r2;
            }
        }
        if (root < best)
            best = root;
    }
    return best;
}

/* Total energy with every corner checked against the margin of the local steps (+inf if any
 * triangle is inverted or too thin). */
static double total_energy_strict(const mips_ctx *c, const double *uv)
{
    long nt = (long)c->nt;
    double e = 0.0;
    int bad = 0;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(+ : e) reduction(| : bad) if (nt > 100000)
#endif
    for (long t = 0; t < nt; ++t) {
        const uint32_t *v = c->tri + 3 * t;
        const double *p0 = uv + 2 * (size_t)v[0], *p1 = uv + 2 * (size_t)v[1], *p2 = uv + 2 * (size_t)v[2];
        if (!sk__mips_corner_ok(p0, p1, p2) || !sk__mips_corner_ok(p1, p2, p0) ||
            !sk__mips_corner_ok(p2, p0, p1)) {
            bad |= 1;
            continue;
        }
        e += tri_energy(c, (size_t)t, uv);
    }
    return bad ? INFINITY : e;
}

/* One global step from uv (energy e0, finite); returns the new energy (<= e0; uv unchanged when
 * no decrease was found). */
static double global_step(mips_global *G, const mips_ctx *c, double *uv, double e0,
                          sk_status *st, sk_error *err)
{
    size_t n2 = 2 * c->nv;
    global_assemble(G, c, uv); /* (the values are only used when factorizing) */
    if (!G->frozen || !G->factored || G->refactor || G->since_factor >= 3) {
        if ((*st = sk_solver_factorize(G->solver, G->P, err)))
            return e0;
        G->factored = true;
        G->refactor = false;
        G->since_factor = 0;
    }
    G->since_factor++;
    for (size_t i = 0; i < n2; ++i)
        G->g[i] = -G->g[i];
    if (G->scalar) { /* two right-hand sides: u then v */
        size_t nv = c->nv;
        for (size_t v = 0; v < nv; ++v) {
            G->tmp[v] = G->g[2 * v];
            G->tmp[nv + v] = G->g[2 * v + 1];
        }
        if ((*st = sk_solver_solve(G->solver, 2, G->tmp, G->tmp + n2, err)))
            return e0;
        for (size_t v = 0; v < nv; ++v) {
            G->d[2 * v] = G->tmp[n2 + v];
            G->d[2 * v + 1] = G->tmp[n2 + nv + v];
        }
    } else if ((*st = sk_solver_solve(G->solver, 1, G->g, G->d, err))) {
        return e0;
    }
    double slope = 0.0;
    for (size_t i = 0; i < n2; ++i)
        slope -= G->g[i] * G->d[i]; /* g holds -grad */
    if (!(slope < 0.0))
        return e0;
    double t = 0.9 * max_flip_free_step(c, uv, G->d, 1.0 / 0.9);
    memcpy(G->x0, uv, n2 * sizeof(double));
    for (int it = 0; it < 30; ++it, t *= 0.5) {
        for (size_t i = 0; i < n2; ++i)
            uv[i] = G->x0[i] + t * G->d[i];
        double e = total_energy_strict(c, uv);
        if (e <= e0 + 1e-4 * t * slope) {
            G->refactor = it > 0 || t < 0.5;
            return e;
        }
    }
    memcpy(uv, G->x0, n2 * sizeof(double));
    G->refactor = true;
    return e0;
}

sk_status sk_mips_energy(const sk_mesh *mesh, const double *uv, double *energy, size_t *inverted,
                         sk_error *err)
{
    mips_ctx c;
    sk_status st = ctx_init(&c, mesh, false, err);
    if (st)
        return st;
    *energy = total_energy(&c, uv, inverted);
    ctx_free(&c);
    return SK_OK;
}

sk_status sk_param_mips(const sk_mesh *mesh, const sk_mips_opts *opts, double *uv,
                        sk_mips_stats *stats, sk_error *err)
{
    sk_mips_opts o = {0};
    if (opts)
        o = *opts;
    size_t max_sweeps = o.max_sweeps ? o.max_sweeps : 200;
    double tol = o.tolerance == 0.0 ? 1e-7 : o.tolerance;
    sk_mips_stats s = {0};
    mips_ctx c;
    sk_status st = ctx_init(&c, mesh, o.fixed_boundary, err);
    if (st)
        return st;
    size_t inverted = 0;
    s.triangles = c.nt;
    s.energy_start = s.energy = total_energy(&c, uv, &inverted);
    if (inverted) {
        ctx_free(&c);
        return sk__fail(err, SK_ERR_ARG, "the start parametrization has %zu inverted or "
                        "degenerate triangles; MIPS needs a flip-free start", inverted);
    }
    /* Greedy colouring of the movable vertices: no two neighbours share a colour, so the steps of
     * one colour are independent (parallel, and the same result for any thread count). A sweep
     * visits the colours in random order, each colour's vertices in index order (cache friendly). */
    uint32_t *color = sk__malloc_array(c.nv ? c.nv : 1, sizeof(uint32_t));
    uint32_t *order = sk__malloc_array(c.nv ? c.nv : 1, sizeof(uint32_t));
    uint32_t cstart[SK__MIPS_MAX_COLORS + 1] = {0};
    if (!color || !order) {
        sk__free(color);
        sk__free(order);
        ctx_free(&c);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    uint32_t ncolors = 0;
    for (size_t v = 0; v < c.nv; ++v) {
        color[v] = SK_INVALID;
        if (!c.movable[v])
            continue;
        uint64_t used = 0;
        for (uint32_t i = c.vt_start[v]; i < c.vt_start[v + 1]; ++i) {
            uint32_t cj = color[c.rec[i].j], ck = color[c.rec[i].k];
            if (cj < 64)
                used |= 1ull << cj;
            if (ck < 64)
                used |= 1ull << ck;
        }
        uint32_t col = 0;
        while (col < SK__MIPS_MAX_COLORS - 1 && (used >> col & 1u))
            ++col;
        color[v] = col; /* (a vertex of valence > 60 may share the last colour: then serial) */
        ncolors = col + 1 > ncolors ? col + 1 : ncolors;
        cstart[col + 1]++;
    }
    for (uint32_t k = 0; k < ncolors; ++k)
        cstart[k + 1] += cstart[k];
    size_t n = cstart[ncolors];
    {
        uint32_t fill[SK__MIPS_MAX_COLORS];
        memcpy(fill, cstart, sizeof fill);
        for (size_t v = 0; v < c.nv; ++v)
            if (color[v] != SK_INVALID)
                order[fill[color[v]]++] = (uint32_t)v;
    }
    bool serial_last = ncolors == SK__MIPS_MAX_COLORS;
    sk__rng rng;
    sk__rng_seed(&rng, o.seed);
    uint32_t perm[SK__MIPS_MAX_COLORS];
    for (uint32_t k = 0; k < ncolors; ++k)
        perm[k] = k;
    bool budget_left = true;
    size_t per_global = o.sweeps_per_global ? o.sweeps_per_global : 1;
    mips_global G;
    bool use_global = o.global_steps > 0 && n > 0;
    if (use_global) {
        double tg = sk_seconds();
        st = global_init(&G, &c, false, o.frozen_model, err);
        if (st) {
            sk__free(color);
            sk__free(order);
            ctx_free(&c);
            return st;
        }
        s.global_seconds += sk_seconds() - tg;
    }
    double block_start = s.energy;
    for (size_t sweep = 0; sweep < max_sweeps && n && budget_left; ++sweep) {
        double gdrop = 0.0;
        if (use_global && s.global_steps < o.global_steps && sweep % per_global == 0) {
            double tg = sk_seconds();
            double e1 = global_step(&G, &c, uv, s.energy, &st, err);
            s.global_seconds += sk_seconds() - tg;
            s.global_steps++;
            if (st)
                break;
            gdrop = s.energy - e1;
            s.energy = e1;
        }
        for (uint32_t k = ncolors - 1; k > 0; --k) { /* random colour order (Fisher-Yates) */
            uint32_t j = sk__rng_below(&rng, k + 1), t = perm[k];
            perm[k] = perm[j];
            perm[j] = t;
        }
        double drop = 0.0;
        for (uint32_t pk = 0; pk < ncolors && budget_left; ++pk) {
            uint32_t col = perm[pk];
            long lo = (long)cstart[col], hi = (long)cstart[col + 1];
            if (o.max_steps && s.steps + (size_t)(hi - lo) >= o.max_steps) {
                hi = lo + (long)(o.max_steps - s.steps);
                budget_left = false;
            }
            double d = 0.0;
            bool par = !(serial_last && col == SK__MIPS_MAX_COLORS - 1) && hi - lo > 32768;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(+ : d) if (par)
#endif
            for (long i = lo; i < hi; ++i)
                d += local_step(&c, order[i], uv);
            (void)par;
            drop += d;
            s.steps += (size_t)(hi - lo);
        }
        s.sweeps++;
        if (sweep % per_global == 0)
            block_start = s.energy + gdrop;
        s.energy -= drop;
        if ((st = sk__progress(o.progress, o.progress_user, (double)(sweep + 1) / max_sweeps, err)))
            break;
        /* stopping rule over a block (a global step and its sweeps while global steps remain,
         * else one sweep) */
        bool block_end = !(use_global && s.global_steps < o.global_steps) ||
                         (sweep + 1) % per_global == 0;
        if (!(use_global && s.global_steps < o.global_steps))
            block_start = s.energy + drop;
        if (tol > 0.0 && block_end && block_start - s.energy < tol * block_start)
            break;
    }
    sk__free(color);
    if (use_global)
        global_free(&G);
    s.energy = total_energy(&c, uv, &inverted); /* exact sum, not the running one */
    sk__free(order);
    ctx_free(&c);
    if (stats)
        *stats = s;
    if (st == SK_OK && inverted)
        return sk__fail(err, SK_WARN_FLIPS, "%zu triangles inverted", inverted);
    return st;
}
