/* MIPS optimizer driver (Hormann & Greiner; Hormann, Greiner, Campagna sec. 4): a colouring of
 * the vertices into independent sets, sweeps of local steps over the colours in random order,
 * global steps between them, the stopping rule, and the renormalization of a free boundary's
 * scale. The energy and the local step are in mips_energy.c, the global step in mips_global.c. */
#include "surfkit/mips.h"
#include "core/internal.h"
#include "param/mips_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* colours of the multicolour sweep (64 covers every valence below 64) */
#define SK__MIPS_MAX_COLORS 64

/* A colour's vertices are far apart in memory (its neighbours hold the other colours), so a step
 * waits on its corner records and its neighbours' uv: they are prefetched this many steps ahead
 * (records) and, once the records are near, the neighbours' uv (measured on the 1M-triangle
 * lion-head: a sweep 0.12 -> 0.075 CPU seconds, the same uv) */
#define SK__MIPS_AHEAD_REC 8
#define SK__MIPS_AHEAD_UV 4

static inline void prefetch_step(const sk__mips_ctx *c, const uint32_t *ord, size_t i, size_t end,
                                 const double *uv)
{
#if defined(__GNUC__)
    if (i + SK__MIPS_AHEAD_REC < end) {
        const char *r = (const char *)(c->rec + c->vt_start[ord[i + SK__MIPS_AHEAD_REC]]);
        for (int k = 0; k < 4; ++k) /* (six records of 40 bytes: four cache lines) */
            __builtin_prefetch(r + 64 * k);
    }
    if (i + SK__MIPS_AHEAD_UV < end) {
        uint32_t w = ord[i + SK__MIPS_AHEAD_UV];
        for (uint32_t r = c->vt_start[w]; r < c->vt_start[w + 1]; ++r)
            __builtin_prefetch(uv + 2 * (size_t)c->rec[r].j);
    }
#else
    (void)c, (void)ord, (void)i, (void)end, (void)uv;
#endif
}

/* Greedy colouring of the movable vertices: no two neighbours share a colour, so the steps of one
 * colour are independent (parallel, and the same result for any thread count). A sweep visits the
 * colours in random order, each colour's vertices in index order (cache friendly). */
typedef struct colouring {
    uint32_t *order;                        /* movable vertices by colour */
    uint32_t start[SK__MIPS_MAX_COLORS + 1]; /* colour k is order[start[k], start[k + 1]) */
    uint32_t count;                         /* colours used */
    size_t n;                               /* movable vertices */
    bool serial_last; /* the last colour may hold neighbours (valence > 60): run it serially */
} colouring;

static sk_status colouring_build(const sk__mips_ctx *c, colouring *cl, sk_error *err)
{
    memset(cl, 0, sizeof *cl);
    uint32_t *color = sk__malloc_array(c->nv ? c->nv : 1, sizeof(uint32_t));
    cl->order = sk__malloc_array(c->nv ? c->nv : 1, sizeof(uint32_t));
    if (!color || !cl->order) {
        sk__free(color);
        sk__free(cl->order);
        cl->order = NULL;
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t v = 0; v < c->nv; ++v) /* (all first: the neighbours after v are read below) */
        color[v] = SK_INVALID;
    for (size_t v = 0; v < c->nv; ++v) {
        if (!c->movable[v])
            continue;
        uint64_t used = 0;
        for (uint32_t i = c->vt_start[v]; i < c->vt_start[v + 1]; ++i) {
            uint32_t cj = color[c->rec[i].j], ck = color[c->rec[i].k];
            if (cj < 64)
                used |= 1ull << cj;
            if (ck < 64)
                used |= 1ull << ck;
        }
        uint32_t col = 0;
        while (col < SK__MIPS_MAX_COLORS - 1 && (used >> col & 1u))
            ++col;
        color[v] = col; /* (a vertex of valence > 60 may share the last colour: then serial) */
        cl->count = col + 1 > cl->count ? col + 1 : cl->count;
        cl->start[col + 1]++;
    }
    for (uint32_t k = 0; k < cl->count; ++k)
        cl->start[k + 1] += cl->start[k];
    cl->n = cl->start[cl->count];
    uint32_t fill[SK__MIPS_MAX_COLORS];
    memcpy(fill, cl->start, sizeof fill);
    for (size_t v = 0; v < c->nv; ++v)
        if (color[v] != SK_INVALID)
            cl->order[fill[color[v]]++] = (uint32_t)v;
    cl->serial_last = cl->count == SK__MIPS_MAX_COLORS;
    sk__free(color);
    return SK_OK;
}

/* One sweep of local steps over the colours in the order perm (shuffled here), at most
 * max_steps - *steps of them when max_steps is non-zero (then *budget_left turns false when it is
 * spent). Returns the energy decrease. */
static double sweep_local(const sk__mips_ctx *c, const colouring *cl, sk__rng *rng, uint32_t *perm,
                          size_t max_steps, size_t *steps, bool *budget_left, double *uv)
{
    for (uint32_t k = cl->count - 1; k > 0; --k) { /* random colour order (Fisher-Yates) */
        uint32_t j = sk__rng_below(rng, k + 1), t = perm[k];
        perm[k] = perm[j];
        perm[j] = t;
    }
    double drop = 0.0;
    for (uint32_t pk = 0; pk < cl->count && *budget_left; ++pk) {
        uint32_t col = perm[pk];
        long lo = (long)cl->start[col], hi = (long)cl->start[col + 1];
        if (max_steps && *steps + (size_t)(hi - lo) >= max_steps) {
            hi = lo + (long)(max_steps - *steps);
            *budget_left = false;
        }
        /* in parallel over fixed blocks of the colour (its steps are independent), the
         * decreases added in block order: the same uv and sums for any thread count */
        size_t n = (size_t)(hi - lo), nb = sk__mips_blocks(n);
        double part[SK__MIPS_BLOCKS];
        bool par = !(cl->serial_last && col == SK__MIPS_MAX_COLORS - 1) && nb > 1;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 1) if (par)
#endif
        for (long b = 0; b < (long)nb; ++b) {
            double db = 0.0;
            const uint32_t *ord = cl->order + lo;
            size_t i0 = sk__mips_block_lo(n, nb, (size_t)b);
            size_t i1 = sk__mips_block_lo(n, nb, (size_t)b + 1);
            for (size_t i = i0; i < i1; ++i) {
                prefetch_step(c, ord, i, i1, uv);
                db += sk__mips_local_step(c, ord[i], uv);
            }
            part[b] = db;
        }
        (void)par;
        double d = 0.0;
        for (size_t b = 0; b < nb; ++b)
            d += part[b];
        drop += d;
        *steps += (size_t)(hi - lo);
    }
    return drop;
}

sk_status sk_param_mips(const sk_mesh *mesh, const sk_mips_opts *opts, double *uv,
                        sk_mips_stats *stats, sk_error *err)
{
    return sk__param_mips_ctx(mesh, NULL, opts, uv, stats, err);
}

sk_status sk__param_mips_ctx(const sk_mesh *mesh, sk__mips_ctx *built, const sk_mips_opts *opts,
                             double *uv, sk_mips_stats *stats, sk_error *err)
{
    sk__mips_ctx c;
    memset(&c, 0, sizeof c);
    if (built) { /* taken over: freed below whatever happens */
        c = *built;
        memset(built, 0, sizeof *built);
    }
    sk_mips_opts o = {0};
    if (opts)
        o = *opts;
    size_t max_sweeps = o.max_sweeps ? o.max_sweeps : 200;
    double tol = o.tolerance == 0.0 ? 1e-7 : o.tolerance;
    size_t per_global = o.sweeps_per_global ? o.sweeps_per_global : 1;
    if (o.boundary != SK_BOUNDARY_DEFAULT && o.boundary != SK_BOUNDARY_FREE &&
        o.boundary != SK_BOUNDARY_GIVEN) {
        sk__mips_ctx_free(&c);
        return sk__fail(err, SK_ERR_ARG, "MIPS steps keep a %s boundary where the start has it: "
                        "pass SK_BOUNDARY_GIVEN", sk_boundary_shape_name(o.boundary));
    }
    if (!(o.area_theta >= 0.0) || !isfinite(o.area_theta)) {
        sk__mips_ctx_free(&c);
        return sk__fail(err, SK_ERR_ARG, "area_theta must be finite and >= 0, not %g",
                        o.area_theta);
    }
    bool free_scale = o.boundary != SK_BOUNDARY_GIVEN;
    sk_mips_stats s = {0};
    colouring cl = {0};
    sk__mips_global G;
    bool use_global = false, ran = false;
    size_t inverted = 0;
    sk_status st = built ? SK_OK : sk__mips_ctx_init(&c, mesh, !free_scale, err);
    if (st)
        return st;
    s.triangles = c.nt;
    if (o.area_theta > 0.0)
        sk__mips_area_setup(&c, o.area_theta, uv);
    s.energy_start = s.energy = sk__mips_total_energy(&c, uv, &inverted);
    if (inverted) {
        st = sk__fail(err, SK_ERR_ARG, "the start parametrization has %zu inverted or "
                      "degenerate triangles; MIPS needs a flip-free start", inverted);
        goto done;
    }
    if ((st = colouring_build(&c, &cl, err)))
        goto done;
    sk__rng rng;
    sk__rng_seed(&rng, o.seed);
    uint32_t perm[SK__MIPS_MAX_COLORS];
    for (uint32_t k = 0; k < cl.count; ++k)
        perm[k] = k;
    if (o.global_steps > 0 && cl.n > 0) {
        double tg = sk_seconds();
        if ((st = sk__mips_global_init(&G, &c, o.frozen_model, err)))
            goto done;
        G.keep = o.frozen_keep;
        G.serves = o.frozen_keep && o.frozen_steps ? o.frozen_steps : 3;
        use_global = true;
        s.global_seconds += sk_seconds() - tg;
    }
    if (free_scale) /* (the area term's k follows the exact rescale: energies unchanged) */
        c.area_k = ldexp(c.area_k, -2 * sk__mips_renormalize(&c, uv));
    bool budget_left = true;
    ran = true;
    /* gap_stop: E <= (1 + gap_stop) 2 T certifies the distance from any converged energy */
    double gap_energy = o.gap_stop > 0.0 && o.area_theta == 0.0
                            ? (1.0 + o.gap_stop) * 2.0 * (double)c.nt : -INFINITY;
    if (s.energy <= gap_energy) {
        s.gap_stopped = true;
        budget_left = false;
    }
    double block_start = s.energy;
    for (size_t sweep = 0; sweep < max_sweeps && cl.n && budget_left; ++sweep) {
        double gdrop = 0.0;
        if (use_global && s.global_steps < o.global_steps && sweep % per_global == 0) {
            double tg = sk_seconds();
            double e1 = sk__mips_global_step(&G, &c, uv, s.energy, &st, err);
            s.global_seconds += sk_seconds() - tg;
            s.global_steps++;
            if (st)
                break;
            gdrop = s.energy - e1;
            s.energy = e1;
        }
        double drop = sweep_local(&c, &cl, &rng, perm, o.max_steps, &s.steps, &budget_left, uv);
        s.sweeps++;
        if (free_scale) {
            int e = sk__mips_renormalize(&c, uv);
            c.area_k = ldexp(c.area_k, -2 * e);
            if (use_global)
                G.scale_exp += e;
        }
        if (sweep % per_global == 0)
            block_start = s.energy + gdrop;
        s.energy -= drop;
        if ((st = sk__progress(o.progress, o.progress_user, (double)(sweep + 1) / max_sweeps, err)))
            break;
        /* stopping rule over a block (a global step and its sweeps while global steps remain,
         * else one sweep) */
        bool globals_left = use_global && s.global_steps < o.global_steps;
        bool block_end = !globals_left || (sweep + 1) % per_global == 0;
        if (!globals_left)
            block_start = s.energy + drop;
        if (tol > 0.0 && block_end && block_start - s.energy < tol * block_start)
            break;
        if (block_end && s.energy <= gap_energy) {
            s.gap_stopped = true;
            break;
        }
    }
    s.energy = sk__mips_total_energy(&c, uv, &inverted); /* exact sum, not the running one */
    if (st == SK_OK && inverted)
        st = sk__fail(err, SK_WARN_FLIPS, "%zu triangles inverted", inverted);
done:
    if (use_global)
        sk__mips_global_free(&G);
    sk__free(cl.order);
    sk__mips_ctx_free(&c);
    if (stats && ran)
        *stats = s;
    return st;
}
