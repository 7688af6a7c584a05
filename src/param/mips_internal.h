/* Shared between the MIPS energy (mips_energy.c), its global step (mips_global.c), the sweep driver
 * (mips.c), the kernel repair (kernel_repair.c) and the hierarchical and flat drivers. */
#ifndef SK_MIPS_INTERNAL_H
#define SK_MIPS_INTERNAL_H

#include "surfkit/mips.h"
#include "surfkit/param.h"
#include "surfkit/solve.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A parameter triangle counts as inverted when twice its signed area is below this fraction of
 * the product of its two edge lengths at a corner (sine of the angle there < 1e-12): the MIPS
 * energy is treated as infinite and the line search never goes there. */
#define SK_MIPS_MIN_SINE 1e-12

/* True when (x, qj, qk) is counter-clockwise with the margin above (x is the moving vertex). */
static inline bool sk__mips_corner_ok(const double x[2], const double qj[2], const double qk[2])
{
    double dj[2] = {x[0] - qj[0], x[1] - qj[1]}, dk[2] = {x[0] - qk[0], x[1] - qk[1]};
    double b = dj[0] * dk[1] - dj[1] * dk[0];
    double lj = dj[0] * dj[0] + dj[1] * dj[1], lk = dk[0] * dk[0] + dk[1] * dk[1];
    return b > 0.0 && b * b > SK_MIPS_MIN_SINE * SK_MIPS_MIN_SINE * lj * lk;
}

/* Sums over many terms run in parallel over fixed blocks, their partial sums added in block
 * order: the same result for any thread count (the stopping rules compare these sums, so the uv
 * does not depend on the threads either). A range of n terms has sk__mips_blocks(n) blocks, at
 * most SK__MIPS_BLOCKS, block b being [sk__mips_block_lo(n, nb, b), sk__mips_block_lo(n, nb, b + 1)). */
#define SK__MIPS_BLOCKS 64
#define SK__MIPS_BLOCK_MIN 2048 /* terms per block at least */
static inline size_t sk__mips_blocks(size_t n)
{
    size_t nb = n / SK__MIPS_BLOCK_MIN;
    return nb < 1 ? 1 : nb > SK__MIPS_BLOCKS ? SK__MIPS_BLOCKS : nb;
}
static inline size_t sk__mips_block_lo(size_t n, size_t nb, size_t b)
{
    return (size_t)((unsigned long long)n * b / nb);
}

/* What a local step at vertex i needs of one incident triangle (i, j, k), stored per vertex
 * contiguously so that a step touches one run of memory plus the neighbours' uv. */
typedef struct sk__mips_corner {
    uint32_t j, k;     /* the other two vertices, counter-clockwise */
    double ci, cj, ck; /* cotangents of the 3D angles at i, j, k */
    double s3;         /* 1 / (2 A) of the triangle's 3D area A (the area term, mips_area.c) */
} sk__mips_corner;

/* The mesh as the optimizer sees it: triangles, 3D cotangents, per-vertex corner records. */
typedef struct sk__mips_ctx {
    size_t nv, nt;
    uint32_t *tri;      /* 3 vertex ids per triangle (ccw) */
    double *cot;        /* cotangent of the 3D angle at each corner */
    uint32_t *vt_start; /* vertex -> its corner records (CSR) */
    sk__mips_corner *rec;
    uint8_t *movable;
    double *s3;         /* per triangle 1 / (2 A) of its 3D area */
    double area_theta;  /* exponent of the area factor (mips_area.c); 0: plain MIPS */
    double area_k;      /* chart normalization: 3D area / uv area of the whole mesh at the start
                           (times 4^-e after each renormalization by 2^e) */
} sk__mips_ctx;

/* Global-step state: the model's pattern and factorization and the work arrays. */
typedef struct sk__mips_global {
    bool frozen;  /* factorize once, at the first step (the model at the start of the level) */
    bool factored;
    bool refactor; /* the frozen model did poorly (line search cut the step): factorize again */
    bool keep;     /* frozen_keep: only a step without decrease sets refactor */
    int since_factor; /* steps on the current factorization */
    size_t serves;    /* steps a frozen model's factorization serves at most (frozen_steps) */
    int scale_exp;    /* uv was scaled by 2^scale_exp since the factorization (renormalize): the
                         model then scales by 2^-2scale_exp, its direction is corrected */
    sk_sparse *P;
    sk_solver *solver;
    uint32_t *nb_start, *nb; /* per vertex: sorted movable neighbours w > v */
    double *g, *d, *x0;
} sk__mips_global;

/* --- mips_energy.c ---------------------------------------------------------------------------- */

/* Builds the context of the alive triangles of m (SK_ERR_TOPOLOGY on a non-triangle face or one
 * degenerate in 3D); with fixed_boundary the boundary vertices are not movable. */
sk_status sk__mips_ctx_init(sk__mips_ctx *c, const sk_mesh *m, bool fixed_boundary, sk_error *err);
void sk__mips_ctx_free(sk__mips_ctx *c);

/* Sum of the energy (*) over the triangles around v with v at position x; +inf outside the
 * kernel. With g, H non-NULL also the gradient and the Hessian (xx, xy, yy) with respect to x. */
double sk__mips_ring_energy(const sk__mips_ctx *c, uint32_t v, const double *uv, const double x[2],
                            double g[2], double H[3]);
/* One damped Newton step at v with backtracking inside the kernel; returns the energy decrease. */
double sk__mips_local_step(const sk__mips_ctx *c, uint32_t v, double *uv);
/* Sum over the triangles; *inverted (may be NULL) counts those not positively oriented (their
 * energy is not added). */
double sk__mips_total_energy(const sk__mips_ctx *c, const double *uv, size_t *inverted);
/* Sum with every corner checked against the local steps' margin (+inf if any fails). */
double sk__mips_total_energy_strict(const sk__mips_ctx *c, const double *uv);
/* Rescales uv by a power of two 2^e so that the larger side of the bounding box lies in [1, 2)
 * (and moves a far-off box to the origin); returns e. */
int sk__mips_renormalize(const sk__mips_ctx *c, double *uv);

/* --- mips.c ---------------------------------------------------------------------------------- */

/* sk_param_mips on a context already built from mesh (sk__mips_ctx_init with fixed_boundary for
 * SK_BOUNDARY_GIVEN), which it takes over and frees; built NULL: built here. */
sk_status sk__param_mips_ctx(const sk_mesh *mesh, sk__mips_ctx *built, const sk_mips_opts *opts,
                             double *uv, sk_mips_stats *stats, sk_error *err);

/* --- mips_area.c ----------------------------------------------------------------------------- */

/* MIPS with an area term (Degener, Meseth, Klein 2003; Hormann & Greiner's later MIPS work):
 * E_t = (sigma1/sigma2 + sigma2/sigma1) * (d + 1/d)^theta with d = det J * area_k the area scale
 * of t relative to the whole mesh's. Sets c->area_theta and c->area_k (from uv). */
/* (*) of triangle t, M = (sum of cot-weighted squared uv edges) / 2 A_uv, and *twice = 2 A_uv;
 * +inf when the uv triangle is not positively oriented (mips_energy.c). */
double sk__mips_tri_terms(const sk__mips_ctx *c, size_t t, const double *uv, double *twice);

/* One corner record of a ring with the moving vertex at x: M = a / b of its triangle and b = 2 A_uv,
 * and (derivs) the gradient gm and Hessian hm of M and the gradient gb of b in x. False outside
 * the kernel (sk__mips_corner_ok). */
bool sk__mips_corner_terms(const sk__mips_corner *r, const double *uv, const double x[2],
                           bool derivs, double *m, double *b, double gm[2], double gb[2],
                           double hm[3]);

void sk__mips_area_setup(sk__mips_ctx *c, double theta, const double *uv);
/* (*) times the area factor of triangle t; +inf if t is not positively oriented. */
double sk__mips_area_tri_energy(const sk__mips_ctx *c, size_t t, const double *uv);
/* As sk__mips_ring_energy, with the area factor. */
double sk__mips_area_ring_energy(const sk__mips_ctx *c, uint32_t v, const double *uv,
                                 const double x[2], double g[2], double H[3]);

/* --- mips_global.c ---------------------------------------------------------------------------- */

/* Pattern and symbolic analysis of the model P; frozen: factorize once, reuse for 3 steps. */
sk_status sk__mips_global_init(sk__mips_global *G, const sk__mips_ctx *c, bool frozen,
                               sk_error *err);
void sk__mips_global_free(sk__mips_global *G);
/* One global step from uv (energy e0, finite); returns the new energy (<= e0; uv unchanged when
 * no decrease was found); a solver failure is returned in *st. */
double sk__mips_global_step(sk__mips_global *G, const sk__mips_ctx *c, double *uv, double e0,
                            sk_status *st, sk_error *err);

/* --- kernel_repair.c -------------------------------------------------------------------------- */

/* Makes every triangle of m flip-free (with the margin above) by moving the vertices of inverted
 * triangles to the centroids of the kernels of their one rings, a few rounds; returns the number
 * of moves, or -1 when some triangle remains inverted. */
long sk__mips_repair(const sk_mesh *m, double *uv);

/* --- mips_flat.c ------------------------------------------------------------------------------ */

/* Floater's parametrization as a MIPS start: with given (non-NULL) its boundary uv are kept (copied
 * into uv first), else the boundary is mapped as boundary says (circle by default). */
sk_status sk__mips_linear_start(const sk_mesh *m, const sk_boundary_opts *boundary,
                                const double *given, double *uv, sk_error *err);

#endif
