/* Global steps of the MIPS optimizer (added after the paper, for large meshes): a descent
 * direction for all vertices at once, a flip-free step length, backtracking on the total energy.
 *
 * With f_t = a_t - 2 b_t >= 0 (a_t the numerator of (*), b_t = 2 A_uv; f_t is the
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
#include "surfkit/solve.h"
#include "core/internal.h"
#include "core/vec.h"
#include "param/mips_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SK__MIPS_GLOBAL_MU 0.001

void sk__mips_global_free(sk__mips_global *G)
{
    sk_sparse_destroy(&G->P);
    sk_solver_destroy(&G->solver);
    sk__free(G->nb_start);
    sk__free(G->nb);
    sk__free(G->g);
    sk__free(G->d);
    sk__free(G->x0);
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
sk_status sk__mips_global_init(sk__mips_global *G, const sk__mips_ctx *c, bool frozen,
                               sk_error *err)
{
    memset(G, 0, sizeof *G);
    G->frozen = frozen;
    size_t nv = c->nv, n2 = 2 * nv;
    G->nb_start = sk__calloc_array(nv + 1, sizeof(uint32_t));
    G->nb = sk__malloc_array(c->vt_start[nv] * 2 + 1, sizeof(uint32_t));
    G->g = sk__malloc_array(n2 + 1, sizeof(double));
    G->d = sk__malloc_array(n2 + 1, sizeof(double));
    G->x0 = sk__malloc_array(n2 + 1, sizeof(double));
    G->P = sk__calloc_array(1, sizeof *G->P);
    if (!G->nb_start || !G->nb || !G->g || !G->d || !G->x0 || !G->P)
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
    /* a failed solver setup frees G too: the caller only frees a G that was made */
    sk_status st = sk_solver_create(P, SK_SOLVER_CHOLESKY, &G->solver, err);
    if (st)
        sk__mips_global_free(G);
    return st;
nomem:
    sk__mips_global_free(G);
    return sk__fail(err, SK_ERR_NOMEM, "out of memory");
}

/* Fills P's values at uv and the gradient g of the total energy. */
static void global_assemble(sk__mips_global *G, const sk__mips_ctx *c, const double *uv)
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
        double *cu = P->values + P->colptr[2 * v];
        double *cv = P->values + P->colptr[2 * v + 1];
        memset(cu, 0, (2 + 2 * m) * sizeof(double));
        memset(cv, 0, (1 + 2 * m) * sizeof(double));
        double *g = G->g + 2 * v;
        if (!c->movable[v]) {
            cu[0] = cv[0] = 1.0;
            g[0] = g[1] = 0.0;
            continue;
        }
        double H[3];
        sk__mips_ring_energy(c, v, uv, uv + 2 * (size_t)v, g, H);
        const double *x = uv + 2 * (size_t)v;
        for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
            const sk__mips_corner *r = c->rec + i;
            const double *qj = uv + 2 * (size_t)r->j, *qk = uv + 2 * (size_t)r->k;
            double bt = (qj[0] - x[0]) * (qk[1] - x[1]) - (qj[1] - x[1]) * (qk[0] - x[0]);
            double w = 1.0 / bt, s = 2.0 * (1.0 + mu) * w;
            /* diagonal block: 2(1+mu) w K[0][0] I */
            cu[0] += s * (r->cj + r->ck);
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
                cu[2 + 2 * p] += s * kk[q];     /* P[u_w][u_v] */
                cu[2 + 2 * p + 1] -= hb[q];     /* P[v_w][u_v] */
                cv[1 + 2 * p] += hb[q];         /* P[u_w][v_v] */
                cv[1 + 2 * p + 1] += s * kk[q]; /* P[v_w][v_v] */
            }
        }
        /* translations are P's null space (free boundary): a tiny ridge keeps it definite; the
         * gradient has no component there */
        cu[0] *= 1.0 + 1e-10;
        cv[0] *= 1.0 + 1e-10;
    }
}

/* Largest t in (0, tmax] for which every triangle stays positively oriented along uv + t d: the
 * smallest positive root of each triangle's signed-area quadratic b0 + b1 t + b2 t^2. */
static double max_flip_free_step(const sk__mips_ctx *c, const double *uv, const double *d, double tmax)
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


/* One global step from uv (energy e0, finite); returns the new energy (<= e0; uv unchanged when
 * no decrease was found). */
double sk__mips_global_step(sk__mips_global *G, const sk__mips_ctx *c, double *uv, double e0,
                          sk_status *st, sk_error *err)
{
    size_t n2 = 2 * c->nv;
    global_assemble(G, c, uv); /* (the values are only used when factorizing) */
    if (!G->frozen || !G->factored || G->refactor || (size_t)G->since_factor >= G->serves) {
        if ((*st = sk_solver_factorize(G->solver, G->P, err)))
            return e0;
        G->factored = true;
        G->refactor = false;
        G->since_factor = 0;
        G->scale_exp = 0;
    }
    G->since_factor++;
    for (size_t i = 0; i < n2; ++i)
        G->g[i] = -G->g[i];
    if ((*st = sk_solver_solve(G->solver, 1, G->g, G->d, err)))
        return e0;
    if (G->scale_exp != 0) /* P was factorized at 2^-scale_exp times the present scale */
        for (size_t i = 0; i < n2; ++i)
            G->d[i] = ldexp(G->d[i], 2 * G->scale_exp);
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
        double e = sk__mips_total_energy_strict(c, uv);
        if (e <= e0 + 1e-4 * t * slope) {
            G->refactor = !G->keep && (it > 0 || t < 0.5);
            return e;
        }
    }
    memcpy(uv, G->x0, n2 * sizeof(double));
    G->refactor = true;
    return e0;
}
