/* MIPS: the most isometric parametrization energy of Hormann & Greiner, minimised by local
 * Newton steps that keep every vertex inside the kernel of its one ring (no triangle ever flips
 * or degenerates: the energy is infinite there and the line search never crosses).
 *
 * Energy (papers README): E = sum over triangles of sigma1/sigma2 + sigma2/sigma1, the singular
 * values of the Jacobian J of the linear map from the 3D triangle to its parameter triangle.
 * Minimum 2 per triangle (conformal). */
#ifndef SURFKIT_MIPS_H
#define SURFKIT_MIPS_H

#include "surfkit/mesh.h"
#include "surfkit/param.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* For a count whose default (0) is not "none" (sk_hparam_opts.global_steps), or to say "none"
 * explicitly anywhere: none at all. */
#define SK_MIPS_NONE ((size_t)-1)

/* Options of sk_param_mips; zero-initialized means every default. */
typedef struct sk_mips_opts {
    sk_boundary_shape boundary; /* SK_BOUNDARY_DEFAULT or SK_BOUNDARY_FREE: natural boundary;
                                   SK_BOUNDARY_GIVEN: the boundary vertices keep the uv given;
                                   others: SK_ERR_ARG */
    size_t max_sweeps;    /* sweeps over all vertices; 0 = 200 */
    size_t max_steps;     /* budget of local steps (vertex moves); 0 = no budget beyond sweeps */
    double tolerance;     /* stop when a sweep lowers the energy by less than this fraction;
                             0 = 1e-7; negative = never stop early */
    uint64_t seed;        /* random sweep order */
    sk_progress_fn progress;
    void *progress_user;
    /* Global steps (added after the paper, for large meshes): a descent direction for all vertices
     * at once from the Gauss-Newton-like model sum_t (H(a_t - 2 b_t) + mu H(a_t)) / b_t of the
     * energy (*) in mips.c (a_t the cotangent numerator, b_t twice the parameter area), solved
     * with CHOLMOD; step length at most 0.9 of the largest flip-free step (roots of each
     * triangle's signed-area quadratic), then backtracking on the total energy. Each global step
     * is followed by sweeps_per_global local sweeps. 0 (the default) or SK_MIPS_NONE = none
     * (local steps only). */
    size_t global_steps;
    size_t sweeps_per_global; /* 0 = 1 */
    bool frozen_model;        /* factorize the model at the first global step and reuse it for
                                 up to 3 steps (sooner when a line search had to cut one): cheap, and
                                 good when the start is close to the optimum (after an insertion);
                                 default: a new factorization every global step */
    bool frozen_keep;         /* with frozen_model: a cut step does not refactorize (only one
                                 that found no decrease does), so each factorization serves 3
                                 steps; the atlas's area refinement, where the area term's
                                 steps are nearly always cut (832k armadillo: 25% less CPU,
                                 MIPS and area-log within 0.6%) */
    size_t frozen_steps;      /* with frozen_keep: global steps one factorization serves at most
                                 (0 = 3); the atlas's area refinement gives all its steps to one
                                 (1.21M bunny: 3% less CPU, area-log 0.3% lower) */
    /* Area term (Degener et al. 2003): minimise sum_t (sigma1/sigma2 + sigma2/sigma1) *
     * (d_t + 1/d_t)^area_theta, d_t = det J_t times the mesh's 3D area / uv area at the start, so
     * that angle distortion is traded for area distortion; flip-free as plain MIPS. 0 (the
     * default) = plain MIPS; 1 is a balanced choice. Negative: SK_ERR_ARG. */
    double area_theta;
    /* Certified stop (plain MIPS only: ignored with area_theta > 0): every triangle's energy is at
     * least 2, so a converged run's energy is at least 2 T (T triangles) and (E - 2 T) / (2 T)
     * bounds how far E lies above it. Sweeps stop once that bound is at most gap_stop (checked
     * at the start and after each sweep, by the running sum); 0 = off. */
    double gap_stop;
} sk_mips_opts;

/* What sk_param_mips did (plain values, nothing to free). */
typedef struct sk_mips_stats {
    size_t sweeps;
    size_t steps;          /* local steps taken (attempted vertex moves) */
    double energy_start;
    double energy;         /* plain sum over triangles */
    size_t triangles;
    size_t global_steps;   /* global steps taken (accepted or not) */
    double global_seconds; /* time in global steps (assembly, factorization, line search) */
    bool gap_stopped;      /* the sweeps stopped on gap_stop */
} sk_mips_stats;

/* MIPS energy of uv (2 per vertex) over the alive triangles of mesh into *energy; *inverted
 * counts triangles with non-positive parameter area (their energy is not added). Neither output
 * may be NULL. Fails (SK_ERR_TOPOLOGY) on non-triangle faces and on triangles that are degenerate
 * in 3D (MIPS is undefined there). */
SK_API sk_status sk_mips_energy(const sk_mesh *mesh, const double *uv, double *energy, size_t *inverted,
                                sk_error *err);

/* Lowers the MIPS energy of uv (2 * num_vertices doubles, in and out; a flip-free start) by local
 * steps in random order. opts and stats may be NULL. Fails with SK_ERR_ARG if the start has an
 * inverted triangle; SK_WARN_FLIPS (uv complete) if the result has one (not expected). With a free boundary the energy
 * is invariant under similarities and the scale of uv would drift: uv is rescaled by powers of
 * two during the optimization (exact, so the result is the same) and comes back with the larger
 * side of its bounding box in [1, 2), translated to the origin if it had drifted far from it. */
SK_API sk_status sk_param_mips(const sk_mesh *mesh, const sk_mips_opts *opts, double *uv,
                               sk_mips_stats *stats, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
