/* Hierarchical parametrization (Hormann, Greiner, Campagna, section 4): parametrize the coarsest
 * level of a progressive mesh, then level by level insert the removed vertices at their
 * barycentric coordinates in the parent triangle (section 3) and lower the MIPS energy by local
 * steps; and the "conventional" flat optimization it is compared with (Table 1). */
#ifndef SURFKIT_HIERARCHICAL_H
#define SURFKIT_HIERARCHICAL_H

#include "surfkit/hierarchy.h"
#include "surfkit/mips.h"
#include "surfkit/param.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Options of sk_param_hierarchical; zero-initialized means every default. */
typedef struct sk_hparam_opts {
    /* shape SK_BOUNDARY_DEFAULT or SK_BOUNDARY_FREE: natural boundary (MIPS is scale invariant);
     * SK_BOUNDARY_CIRCLE / SK_BOUNDARY_SQUARE: fixed on the unit circle / square on every level
     * where the input's boundary map puts it (spacing and corners as in sk_param_boundary);
     * SK_BOUNDARY_GIVEN: SK_ERR_ARG. */
    sk_boundary_opts boundary;
    /* Sweep schedule: level l (V_l vertices) gets min(sweeps_per_level, ceil(level_work * V / V_l))
     * sweeps, V the input's vertex count: about the same work on every level, many sweeps on the
     * cheap coarse levels where the low frequencies converge, few on the fine ones. */
    double level_work;        /* 0 = 2 with global steps, 5 without */
    size_t sweeps_per_level;  /* cap; 0 = 400 */
    size_t finest_sweeps;     /* sweeps on the input level; 0 = from the schedule */
    size_t max_steps;         /* budget of local steps over all levels (the coarser levels together use
                                 at most half); 0 = no budget */
    double tolerance;         /* per level: stop when a sweep lowers the energy by less than this
                                 fraction; 0 = 1e-5 */
    uint64_t seed;            /* hierarchy and sweep order */
    sk_hierarchy_opts hierarchy; /* seed is taken from above; zero = defaults */
    sk_progress_fn progress;
    void *progress_user;
    /* Global steps (sk_mips_opts.global_steps): a level with at most global_max_vertices
     * vertices starts with global_steps global steps, each followed by sweeps_per_global local
     * sweeps, before the schedule's sweeps; the coarse levels then carry the low frequencies
     * that local steps are slow to move. */
    size_t global_steps;        /* per level; 0 = 3; SK_MIPS_NONE = none (the paper's method) */
    size_t global_max_vertices; /* 0 = 25000 (a factorization there takes ~0.1 s) */
    size_t sweeps_per_global;   /* 0 = 2 */
    /* A level above global_max_vertices (and not the input) is optimized only when it has at
     * least min_growth times the vertices of the last optimized level; the others only get the
     * insertion and the repair (their energy is reported as NaN). 0 = 2; 1 = every level. */
    double min_growth;
    /* Certified stop on every level (sk_mips_opts.gap_stop): a level's sweeps end once its energy
     * is provably within target_gap of any converged energy of that level, (E - 2 T) / (2 T) <=
     * target_gap. 0 = 5e-4 (half the 0.1% of issue 15) with the default tolerance, off with an
     * explicit one; negative = off (the schedule alone). */
    double target_gap;
} sk_hparam_opts;

/* One level of the hierarchy as the driver saw it. */
typedef struct sk_hparam_level {
    size_t vertices, faces;
    size_t steps, sweeps;
    size_t repaired;       /* inserted vertices moved into the kernel of their one ring */
    double energy;         /* MIPS sum after optimization on this level (NaN: not optimized) */
    double seconds;
    size_t global_steps;   /* global steps on this level */
    double global_seconds;
} sk_hparam_level;

/* What sk_param_hierarchical did. levels is allocated by the library (any number of levels):
 * release it with sk_hparam_stats_release. */
typedef struct sk_hparam_stats {
    size_t num_levels;       /* levels of the hierarchy (input included) */
    sk_hparam_level *levels; /* num_levels entries, coarsest first; NULL when num_levels is 0 */
    size_t steps;          /* local steps over all levels */
    size_t repaired;       /* total inserted vertices repaired */
    size_t fallbacks;      /* levels re-solved with a linear method because repair failed */
    double energy;         /* final MIPS sum on the input */
    /* (energy - 2 T) / (2 T), T the input's triangles: every triangle's energy is at least 2, so
     * the result lies at most this fraction above a converged run's energy (a bound, often
     * several times the true distance; loose where no map is nearly conformal) */
    double gap_bound;
    size_t gap_stopped_levels; /* levels whose sweeps ended on target_gap */
    double hierarchy_seconds, total_seconds;
} sk_hparam_stats;

/* Hierarchical MIPS parametrization of a disk-topology triangle mesh (no deleted elements) into
 * uv (2 * num_vertices doubles, written). The coarsest level starts from Floater's
 * parametrization with a circle (or square) boundary. After each insertion, a vertex whose one
 * ring is not flip-free is moved to the centroid of the kernel of its one ring; if that kernel
 * is empty the level is re-solved with Floater's method (counted in fallbacks). The result has no
 * inverted triangle; with a free boundary its scale is a power of two (sk_param_mips), use
 * sk_param_normalize for the unit square. opts may be NULL (defaults). stats may be NULL; else
 * it is overwritten (whatever it held is not freed) whenever the hierarchy was built, also on a
 * later failure, and the caller releases it with sk_hparam_stats_release. */
SK_API sk_status sk_param_hierarchical(const sk_mesh *mesh, const sk_hparam_opts *opts, double *uv,
                                       sk_hparam_stats *stats, sk_error *err);

/* Frees stats->levels and zeroes *stats. NULL-safe; a zeroed stats is fine. */
SK_API void sk_hparam_stats_release(sk_hparam_stats *stats);

/* Options of sk_param_mips_flat; zero-initialized means every default. */
typedef struct sk_mips_flat_opts {
    sk_boundary_opts boundary; /* as in sk_hparam_opts (default free) */
    size_t max_steps;          /* budget of local steps; 0 = until the tolerance */
    double tolerance;          /* as in sk_mips_opts: 0 = 1e-7, negative = never stop early */
    uint64_t seed;             /* sweep order */
    sk_progress_fn progress;
    void *progress_user;
} sk_mips_flat_opts;

/* The conventional method of Table 1: Floater with a circle (or square) boundary on the full mesh,
 * then MIPS local steps in random order (sk_param_mips). opts and stats may be NULL. */
SK_API sk_status sk_param_mips_flat(const sk_mesh *mesh, const sk_mips_flat_opts *opts, double *uv,
                                    sk_mips_stats *stats, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
