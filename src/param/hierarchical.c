/* Hierarchical parametrization (Hormann, Greiner, Campagna, section 4): the level loop. The repair
 * after an insertion is in kernel_repair.c, the flat method of Table 1 in mips_flat.c. */
#include "surfkit/hierarchical.h"
#include "core/internal.h"
#include "core/vec.h"
#include "param/mips_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


/* Above this many faces the input level's optimizer context is built on a second thread beside
 * the (serial) vertex splits of the level below */
#define SK__HPARAM_BESIDE_MIN 50000

/* The options with their defaults filled in. */
typedef struct schedule {
    size_t sweeps_cap, gsteps, gmax, gsweeps, max_steps, finest_sweeps;
    double tol, work, growth, gap;
    bool fixed;
    uint64_t seed;
} schedule;

static schedule schedule_from(const sk_hparam_opts *o)
{
    schedule c;
    c.sweeps_cap = o->sweeps_per_level ? o->sweeps_per_level : 400;
    c.tol = o->tolerance == 0.0 ? 1e-5 : o->tolerance;
    c.fixed = o->boundary.shape != SK_BOUNDARY_DEFAULT && o->boundary.shape != SK_BOUNDARY_FREE;
    c.gsteps = o->global_steps == SK_MIPS_NONE ? 0 : o->global_steps ? o->global_steps : 3;
    c.gmax = o->global_max_vertices ? o->global_max_vertices : 25000;
    c.work = o->level_work > 0.0 ? o->level_work : c.gsteps ? 2.0 : 5.0;
    c.gsweeps = o->sweeps_per_global ? o->sweeps_per_global : 2;
    c.growth = o->min_growth > 0.0 ? o->min_growth : 2.0;
    c.max_steps = o->max_steps;
    c.finest_sweeps = o->finest_sweeps;
    c.seed = o->seed;
    /* (the default certified stop goes with the default tolerance: an explicit tolerance asks
     * for that stopping rule alone) */
    c.gap = o->target_gap > 0.0 ? o->target_gap : o->target_gap == 0.0 && o->tolerance == 0.0 ? 5e-4 : 0.0;
    return c;
}

/* The splits of level `level` applied to m and, beside them, the optimizer context of the input
 * mesh into *ctx (*have_ctx: it was built; with fixed, its boundary vertices are not movable). */
static sk_status split_beside(const sk_hierarchy *hier, size_t level, sk_mesh *m,
                              const sk_mesh *mesh, bool fixed, sk__mips_ctx *ctx, bool *have_ctx,
                              sk_error *err)
{
    sk_status st = SK_OK;
    sk_error cerr;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel sections num_threads(2) if (mesh->num_faces > SK__HPARAM_BESIDE_MIN)
#endif
    {
#if defined(SK_HAVE_OPENMP)
#pragma omp section
#endif
        st = sk_hierarchy_split(hier, level, m, err);
#if defined(SK_HAVE_OPENMP)
#pragma omp section
#endif
        *have_ctx = sk__mips_ctx_init(ctx, mesh, fixed, &cerr) == SK_OK;
    }
    return st;
}

/* For a fixed boundary: per level, the input vertex of each level vertex (levels [0, L)). */
static sk_status finest_ids(const sk_hierarchy *hier, size_t L, uint32_t **finest_id, sk_error *err)
{
    for (size_t l = L; l-- > 0;) {
        size_t nv = sk_hierarchy_level_info(hier, l).vertices;
        finest_id[l] = sk__malloc_array(nv ? nv : 1, sizeof(uint32_t));
        if (!finest_id[l])
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
        if (l == L - 1) {
            for (size_t v = 0; v < nv; ++v)
                finest_id[l][v] = (uint32_t)v;
        } else {
            const uint32_t *map = sk_hierarchy_vertex_map(hier, l);
            size_t nf = sk_hierarchy_level_info(hier, l + 1).vertices;
            for (size_t f = 0; f < nf; ++f)
                if (map[f] != SK_INVALID)
                    finest_id[l][map[f]] = finest_id[l + 1][f];
        }
    }
    return SK_OK;
}

/* MIPS on level l of L (nv vertices, nfine on the input): the sweep schedule, global steps on
 * small levels, the step budget (the coarser levels together use at most half of it, so that the
 * input level is always optimized however small the budget), and the skipping of levels that
 * grew too little. *last_opt is the vertex count of the last optimized level. built (may be
 * NULL): the optimizer's context of m, taken over. */
static sk_status optimize_level(const sk_mesh *m, sk__mips_ctx *built, const schedule *c,
                                size_t l, size_t L, size_t nfine, size_t steps_so_far,
                                size_t *last_opt, double *uv, sk_mips_stats *ms, sk_error *err)
{
    size_t nv = m->num_vertices;
    sk_mips_opts mo = {0};
    mo.boundary = c->fixed ? SK_BOUNDARY_GIVEN : SK_BOUNDARY_FREE;
    double want = ceil(c->work * (double)nfine / (double)(nv ? nv : 1));
    mo.max_sweeps = want < (double)c->sweeps_cap ? (size_t)want : c->sweeps_cap;
    if (l + 1 == L && c->finest_sweeps)
        mo.max_sweeps = c->finest_sweeps;
    mo.tolerance = c->tol;
    mo.seed = c->seed + l;
    mo.gap_stop = c->gap;
    if (c->gsteps && nv <= c->gmax) {
        mo.global_steps = c->gsteps;
        mo.sweeps_per_global = c->gsweeps;
        mo.frozen_model = true;
        if (mo.max_sweeps < c->gsteps * c->gsweeps)
            mo.max_sweeps = c->gsteps * c->gsweeps;
    }
    memset(ms, 0, sizeof *ms);
    bool skip = l + 1 < L && nv > c->gmax && *last_opt &&
                (double)nv < c->growth * (double)*last_opt;
    size_t limit = c->max_steps && l + 1 < L ? c->max_steps / 2 : c->max_steps;
    sk_status st = SK_OK;
    if (skip) { /* insertion and repair only: optimized with the next levels */
        if (built)
            sk__mips_ctx_free(built);
        ms->energy = NAN;
        return SK_OK;
    }
    if (limit && steps_so_far >= limit) { /* budget spent: only measure */
        size_t inv = 0;
        if (built)
            sk__mips_ctx_free(built);
        st = sk_mips_energy(m, uv, &ms->energy, &inv, err);
    } else {
        mo.max_steps = limit ? limit - steps_so_far : 0;
        st = sk__param_mips_ctx(m, built, &mo, uv, ms, err);
    }
    *last_opt = nv;
    return st;
}

/* Level l > 0 after the insertion: the fixed boundary put back, the inverted one rings repaired;
 * a repair that fails re-solves the level with the linear start (counted in *fallbacks). Returns
 * the repaired vertex count in *repaired. */
static sk_status repair_level(const sk_mesh *m, const schedule *c, const sk_boundary_opts *bo,
                              const double *level_fixed, double *uv, size_t *repaired,
                              size_t *fallbacks, sk_error *err)
{
    size_t nv = m->num_vertices;
    if (c->fixed)
        for (size_t v = 0; v < nv; ++v)
            if (sk_is_boundary_v(m, (uint32_t)v))
                memcpy(uv + 2 * v, level_fixed + 2 * v, 2 * sizeof(double));
    long moved = sk__mips_repair(m, uv);
    *repaired = 0;
    if (moved < 0) {
        /* no kernel to move into: restart this level from a linear map (never silent) */
        (*fallbacks)++;
        return sk__mips_linear_start(m, bo, c->fixed ? level_fixed : NULL, uv, err);
    }
    *repaired = (size_t)moved;
    return SK_OK;
}

sk_status sk_param_hierarchical(const sk_mesh *mesh, const sk_hparam_opts *opts, double *uv,
                                sk_hparam_stats *stats, sk_error *err)
{
    sk_hparam_opts o = {0};
    if (opts)
        o = *opts;
    schedule c = schedule_from(&o);
    sk_boundary_opts bo = o.boundary; /* the fixed boundary's map, or the coarsest level's start */
    if (!c.fixed)
        bo.shape = SK_BOUNDARY_CIRCLE;
    if (bo.shape == SK_BOUNDARY_GIVEN)
        return sk__fail(err, SK_ERR_ARG, "hierarchical MIPS maps the boundary itself: circle, "
                        "square or free, not given");
    size_t last_opt = 0;
    double t0 = sk_seconds();
    sk_hparam_stats s;
    memset(&s, 0, sizeof s);
    sk_status st = sk_param_check_disk(mesh, err);
    if (st)
        return st;

    sk_hierarchy *hier = NULL;
    sk_mesh *m = NULL;
    sk__mips_ctx fine; /* the input level's optimizer context when built ahead */
    memset(&fine, 0, sizeof fine);
    bool have_fine = false;
    double *cur = NULL, *next = NULL, *fixed_uv = NULL, *level_fixed = NULL;
    uint32_t **finest_id = NULL;
    sk_hierarchy_opts ho = o.hierarchy;
    ho.seed = o.seed;
    st = sk_hierarchy_build(mesh, &ho, &hier, err);
    if (st)
        goto done;
    s.hierarchy_seconds = sk_seconds() - t0;
    size_t L = sk_hierarchy_num_levels(hier);
    s.levels = sk__calloc_array(L ? L : 1, sizeof *s.levels);
    if (!s.levels) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    s.num_levels = L;
    size_t nfine = sk_hierarchy_level_info(hier, L - 1).vertices;
    if (nfine != mesh->num_vertices - mesh->num_deleted_vertices) {
        st = sk__fail(err, SK_ERR_ARG, "the mesh has deleted vertices: compact it first");
        goto done;
    }
    cur = sk__malloc_array(2 * nfine, sizeof(double));
    next = sk__malloc_array(2 * nfine, sizeof(double));
    if (!cur || !next) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (c.fixed) {
        /* the boundary of every level is fixed where the finest boundary map puts it */
        fixed_uv = sk__calloc_array(2 * nfine, sizeof(double));
        level_fixed = sk__malloc_array(2 * nfine, sizeof(double));
        finest_id = sk__calloc_array(L, sizeof *finest_id);
        if (!fixed_uv || !level_fixed || !finest_id) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        if ((st = sk_param_boundary(mesh, &bo, fixed_uv, err)) ||
            (st = finest_ids(hier, L, finest_id, err)))
            goto done;
    }

    if ((st = sk_mesh_copy(sk_hierarchy_coarsest(hier), &m, err)))
        goto done;
    for (size_t l = 0; l < L; ++l) {
        double tl = sk_seconds();
        sk_hparam_level *lv = &s.levels[l];
        if (l > 0) {
            /* section 3: insert the new vertices at rho p0 + sigma pi + tau pi+1 */
            if ((st = sk_hierarchy_prolong(hier, l - 1, cur, 2, next, err)))
                goto done;
            /* the input level is the input mesh (the same oriented triangles on the same vertex
             * numbers, in the input's order): no split there. The split before it (serial) has
             * the input level's optimizer context built beside it on the second thread; a
             * context that fails is built again at the input level and fails there. */
            if (l + 2 == L)
                st = split_beside(hier, l - 1, m, mesh, c.fixed, &fine, &have_fine, err);
            else if (l + 1 < L)
                st = sk_hierarchy_split(hier, l - 1, m, err);
            if (st)
                goto done;
            double *t = cur;
            cur = next;
            next = t;
        }
        const sk_mesh *lm = l > 0 && l + 1 == L ? mesh : m; /* level l */
        size_t nv = lm->num_vertices;
        if (c.fixed)
            for (size_t v = 0; v < nv; ++v)
                memcpy(level_fixed + 2 * v, fixed_uv + 2 * (size_t)finest_id[l][v], 2 * sizeof(double));
        if (l == 0)
            st = sk__mips_linear_start(m, &bo, c.fixed ? level_fixed : NULL, cur, err);
        else
            st = repair_level(lm, &c, &bo, level_fixed, cur, &lv->repaired, &s.fallbacks, err);
        if (st)
            goto done;
        s.repaired += lv->repaired;
        sk_mips_stats ms;
        sk__mips_ctx *built = lm == mesh && have_fine ? &fine : NULL;
        if ((st = optimize_level(lm, built, &c, l, L, nfine, s.steps, &last_opt, cur, &ms, err)))
            goto done;
        lv->vertices = nv;
        lv->faces = lm->num_faces - lm->num_deleted_faces;
        lv->steps = ms.steps;
        lv->sweeps = ms.sweeps;
        lv->energy = ms.energy;
        lv->global_steps = ms.global_steps;
        lv->global_seconds = ms.global_seconds;
        s.steps += ms.steps;
        s.gap_stopped_levels += ms.gap_stopped;
        lv->seconds = sk_seconds() - tl;
        if ((st = sk__progress(o.progress, o.progress_user, (double)(l + 1) / (double)L, err)))
            goto done;
    }
    memcpy(uv, cur, 2 * nfine * sizeof(double));
    s.energy = s.levels[L - 1].energy;
    if (s.levels[L - 1].faces > 0) {
        double two_t = 2.0 * (double)s.levels[L - 1].faces;
        s.gap_bound = (s.energy - two_t) / two_t;
    }
    s.total_seconds = sk_seconds() - t0;
done:
    if (finest_id) {
        for (size_t l = 0; l < s.num_levels; ++l)
            sk__free(finest_id[l]);
        sk__free(finest_id);
    }
    sk__free(fixed_uv);
    sk__free(level_fixed);
    sk__free(cur);
    sk__free(next);
    sk__mips_ctx_free(&fine);
    sk_mesh_destroy(&m);
    sk_hierarchy_destroy(&hier);
    if (stats)
        *stats = s;
    else
        sk_hparam_stats_release(&s);
    return st;
}

void sk_hparam_stats_release(sk_hparam_stats *stats)
{
    if (!stats)
        return;
    sk__free(stats->levels);
    memset(stats, 0, sizeof *stats);
}
