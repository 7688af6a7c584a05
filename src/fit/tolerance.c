/* VC1 surfaces within a tolerance over coarse levels of the progressive mesh (tolerance.h): the
 * driver. The search over the levels finds the coarsest whose surface is within T; the local
 * refinement wants the vertices of the input faces that are out of tolerance (on either side),
 * rebuilds the cut from scratch (so the order stays that of the hierarchy) and builds its VC1
 * surface again, the edge deletion warm-started from the last round's deleted edges
 * (sk__edge_deletion_hinted: from nothing, the few new vertices of a round re-routed the
 * deletion far away; on armadillo after two Loop subdivisions at 1e-3 of the diagonal the
 * rounds then flagged 380, 288, 213, 165, 60, 93, 6 vertices after the first two, in 10 rounds
 * and 20,716 patches; warm-started 246, 46, 20, in 6 rounds and 19,407 patches).
 *
 * The pieces: tolerance_cut.c (cuts of the progressive mesh), tolerance_check.c (a cut's surface
 * and its distances to the input). */
#include "fit/tolerance_internal.h"
#include "surfkit/bezier.h"
#include "surfkit/deviation.h"
#include "analysis/bvh_internal.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

enum { MAX_FAILED_ROUNDS = 3 };

/* ---------------------------------------------------------------------------------------------
 * The driver
 * ------------------------------------------------------------------------------------------- */

/* within T and without singular patches: a surface the CLI writes (its continuity report
 * fails on a singular patch) */
static bool cut_ok(const cut_result *r)
{
    return r->s && r->met && r->singular == 0;
}

/* keeps the better of best and r (within T without singular patches first, then within T, then
 * fewer singular patches, then fewer patches when within T, else the smaller deviation); r is
 * emptied either way */
static void keep_better(cut_result *best, cut_result *r, bool *best_refined, bool r_refined)
{
    bool better = !best->s ||
                  (cut_ok(r) && !cut_ok(best)) ||
                  (cut_ok(r) == cut_ok(best) &&
                   ((r->met && !best->met) ||
                    (r->met == best->met &&
                     (r->singular < best->singular ||
                      (r->singular == best->singular &&
                       (r->met ? r->patches < best->patches : r->max < best->max))))));
    if (r->s && better) {
        sk__tol_cut_result_free(best);
        *best = *r;
        *best_refined = r_refined;
        memset(r, 0, sizeof *r);
        r->max = INFINITY;
    } else {
        sk__tol_cut_result_free(r);
    }
}

/* One run of the tolerance route: the context, the best surface so far and the scratch of the
 * refinement rounds. */
typedef struct tol_run {
    sk_tolerance_opts o;
    sk_tolerance_stats *stats;
    unsigned refine_levels, max_rounds, stall_rounds;
    tol_ctx c;
    cut_result best, r, at_hi;
    bool best_refined;
    uint8_t *alive, *bad, *fresh;
    uint32_t *stack, *stamp, stamp_value;
    check_buf b;
    tol_hint hint; /* the last round's deleted edges */
    sk_soup *fine_soup, *ts;
} tol_run;

static void run_free(tol_run *t)
{
    sk__tol_cut_result_free(&t->best);
    sk__tol_cut_result_free(&t->r);
    sk__tol_cut_result_free(&t->at_hi);
    sk__tol_check_buf_free(&t->b);
    sk__free(t->alive);
    sk__free(t->bad);
    sk__free(t->fresh);
    sk__free(t->stack);
    sk__free(t->stamp);
    sk__free(t->hint.pairs);
    sk_soup_destroy(&t->ts);
    sk_soup_destroy(&t->fine_soup);
    sk__tol_ctx_free(&t->c);
}

static sk_status check_input(const sk_mesh *mesh, const sk_tolerance_opts *o, sk_error *err)
{
    if (!mesh || mesh->num_faces == 0)
        return sk__fail(err, SK_ERR_ARG, "no mesh");
    if (o->smooth.scheme != SK_SMOOTH_VC1)
        return sk__fail(err, SK_ERR_ARG, "the tolerance route builds VC1 surfaces only");
    if (o->smooth.base_refinements)
        return sk__fail(err, SK_ERR_ARG, "the tolerance route refines locally itself: "
                        "smooth.base_refinements must be 0 there");
    if (!(o->tolerance >= 0) || !(o->tolerance_rel >= 0) || o->face_samples < 0 ||
        o->face_samples > 64 || o->tess > 64)
        return sk__fail(err, SK_ERR_ARG, "bad tolerance options (tolerance %g, relative %g, face "
                        "samples %d, tessellation %u)", o->tolerance, o->tolerance_rel,
                        o->face_samples, o->tess);
    if (mesh->num_deleted_vertices || mesh->num_deleted_faces)
        return sk__fail(err, SK_ERR_ARG, "the mesh has deleted elements (compact it first)");
    for (size_t f = 0; f < mesh->num_faces; ++f)
        if (sk_mesh_face_size(mesh, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu is not a triangle (the tolerance "
                            "route needs a triangle mesh)", f);
    return SK_OK;
}

/* The face samples of the deviation check: c->n x c->n sub-triangle centroids per face. */
static void sample_pattern(tol_ctx *c)
{
    size_t k = 0;
    for (int i = 0; i < c->n; ++i)
        for (int j = 0; i + j < c->n; ++j, ++k) {
            c->bary[k][0] = (i + 1.0 / 3.0) / c->n;
            c->bary[k][1] = (j + 1.0 / 3.0) / c->n;
        }
    for (int i = 0; i + 1 < c->n; ++i)
        for (int j = 0; i + j + 1 < c->n; ++j, ++k) {
            c->bary[k][0] = (i + 2.0 / 3.0) / c->n;
            c->bary[k][1] = (j + 2.0 / 3.0) / c->n;
        }
}

/* The context: options, samples, tolerance, fine normals, the hierarchy and its indexes, the
 * input's BVH. */
static sk_status setup(tol_run *t, const sk_mesh *mesh, sk_error *err)
{
    sk_status st = SK_OK;
    t->refine_levels = t->o.refine_levels ? t->o.refine_levels : 6;
    t->max_rounds = t->o.max_rounds ? t->o.max_rounds : 32;
    t->stall_rounds = t->o.stall_rounds ? t->o.stall_rounds : 4;
    t->c.fine = mesh;
    t->c.nv = mesh->num_vertices;
    t->c.nf = mesh->num_faces;
    t->c.so = t->o.smooth;
    t->c.so.progress = NULL;
    t->c.so.progress_user = NULL;
    t->c.so.estimate_normals = false; /* every cut carries the fine normals */
    t->c.so.allow_split = true; /* only where no split of the hierarchy evens a closed component */
    /* no re-routed rounds (reroute.c) in the search's builds: its own refinement splits the
     * collapses at singular patches, and with the rounds bunny00 at 1e-3 took 30.9 s instead of
     * 6.3 s (cow: 10 -> 3 singular patches, T missed either way, 1.0 -> 4.4 s) */
    t->c.so.reroute_rounds = -1;
    if (!t->c.so.fit_mesh) /* the fit to the scan (smooth.fit_weight) fits the input */
        t->c.so.fit_mesh = mesh;
    t->c.n = t->o.face_samples ? t->o.face_samples : 2;
    t->c.tess = t->o.tess ? t->o.tess : 4;
    t->c.incremental = !t->o.full_checks && t->c.tess <= 8 && t->c.n <= 4;
    sample_pattern(&t->c);
    t->stats->diagonal = sk_mesh_diagonal(mesh);
    double rel = t->o.tolerance_rel > 0 ? t->o.tolerance_rel : 1e-3;
    t->c.tol = t->o.tolerance > 0 ? t->o.tolerance : rel * t->stats->diagonal;
    t->stats->tolerance = t->c.tol;
    t->stats->input_faces = t->c.nf;

    /* fine normals */
    t->c.normals = sk__malloc_array(3 * t->c.nv, sizeof *t->c.normals);
    uint32_t *tri = sk__malloc_array(3 * t->c.nf, sizeof *tri);
    t->c.tri = tri;
    t->c.f2m = sk__malloc_array(t->c.nv, sizeof *t->c.f2m);
    t->alive = sk__malloc_array(t->c.nv, 1);
    t->bad = sk__calloc_array(t->c.nv, 1);
    t->stack = sk__malloc_array(t->c.nv, sizeof *t->stack);
    t->stamp = sk__calloc_array(t->c.nv, sizeof *t->stamp);
    t->b.fd = sk__malloc_array(t->c.nf, sizeof *t->b.fd);
    t->b.vd = sk__malloc_array(t->c.nv, sizeof *t->b.vd);
    t->b.fh = sk__malloc_array(t->c.nf, sizeof *t->b.fh);
    if (!t->c.normals || !tri || !t->c.f2m || !t->alive || !t->bad || !t->stack || !t->stamp ||
        !t->b.fd || !t->b.vd || !t->b.fh)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t f = 0; f < t->c.nf; ++f) {
        uint32_t h = mesh->f_halfedge[f];
        for (int q = 0; q < 3; ++q, h = mesh->h_next[h])
            tri[3 * f + q] = mesh->h_vertex[h ^ 1u];
    }
    double ta = sk_seconds();
    if (mesh->normals && !t->o.smooth.estimate_normals)
        memcpy(t->c.normals, mesh->normals, 3 * t->c.nv * sizeof *t->c.normals);
    else if ((st = sk_mesh_vertex_normals(mesh, t->o.smooth.normals, t->c.normals, err)))
        return st;
    double tb = sk_seconds();
    t->stats->seconds_normals = tb - ta;

    /* the hierarchy down to a handful of faces */
    sk_hierarchy_opts ho = {0};
    ho.seed = t->o.seed ? t->o.seed : 1;
    ho.target_faces = 8;
    /* coarse triangles that stay close to the fine normals and no valence-3 vertices: VC1 over
     * them has far fewer singular patches and spikes (measured on the sphere at 1e-2 of the
     * diagonal: 79 patches, against 210 with the hierarchy's defaults of 90 degrees and 3) */
    ho.collapse.max_normal_deviation_deg =
        t->o.collapse.max_normal_deviation_deg > 0 ? t->o.collapse.max_normal_deviation_deg : 15;
    ho.collapse.min_valence = t->o.collapse.min_valence ? t->o.collapse.min_valence : 4;
    if ((st = sk_hierarchy_build(mesh, &ho, &t->c.hier, err)))
        return st;
    t->c.levels = sk_hierarchy_num_levels(t->c.hier);
    t->stats->levels = t->c.levels;
    if ((st = sk__tol_index_hierarchy(&t->c, err)) || (st = sk__tol_index_mesh(&t->c, err)))
        return st;
    if ((st = sk_mesh_to_soup(mesh, &t->fine_soup, err)) ||
        (st = sk_bvh_build(t->fine_soup, &t->c.mesh_bvh, err)))
        return st;
    t->stats->seconds_hierarchy = sk_seconds() - tb;
    return SK_OK;
}

/* The level estimate: the coarsest level whose own triangles (the piecewise linear surface
 * through its vertices) are within T both ways, by bisection (the input itself is). A level's
 * linear check costs a BVH over its triangles and the walks, no VC1 build. */
static sk_status estimate_level(tol_run *t, size_t *est, sk_error *err)
{
    double t0 = sk_seconds();
    size_t lo = 0, hi = t->c.levels - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        double mx = INFINITY;
        sk__tol_level_cut(&t->c, mid, t->alive);
        sk_status st = sk__tol_check_linear(&t->c, t->alive, &t->b, &mx, err);
        if (st)
            return st;
        t->stats->linear_tried++;
        if (mx <= t->c.tol)
            hi = mid;
        else
            lo = mid + 1;
    }
    *est = hi;
    t->stats->estimate_level = hi;
    t->stats->seconds_estimate = sk_seconds() - t0;
    return SK_OK;
}

/* Which level the search builds next. First PROBE_BELOW levels below the estimate: the linear
 * surface is often farther from the mesh than the VC1 one (the chord error on smooth meshes:
 * the sphere, lion-head), and a level has about 1.3x the vertices of the one below, so this
 * costs about 0.4 of a build at the estimate. Met there: bisection below it. Else from the
 * estimate, steps of 1, 2, 4, ... downwards while the levels meet T (upwards while they miss),
 * then bisection between the last miss and the last met level (bisection throughout without
 * an estimate). On scans the estimate is often the level itself: three surfaces, that level,
 * the one below and PROBE_BELOW below. */
enum { PROBE_BELOW = 3 };

typedef struct probe {
    size_t next, step, est;
    int dir;      /* -1 going down (met so far), 1 going up (missed so far), 0 at the start */
    bool below;   /* the first probe, PROBE_BELOW under the estimate */
    bool bisect;
} probe;

static size_t probe_level(const probe *p, size_t lo, size_t hi)
{
    if (!p->bisect && p->next >= lo && p->next < hi)
        return p->next;
    return lo + (hi - lo) / 2;
}

static void probe_update(probe *p, size_t j, bool met)
{
    if (p->bisect)
        return;
    if (p->below) {
        p->below = false;
        p->bisect = met; /* the estimate is too fine: bisection below j */
        p->next = p->est;
        return;
    }
    if (met ? p->dir > 0 || j == 0 : p->dir < 0) {
        p->bisect = true; /* bracketed */
        return;
    }
    p->dir = met ? -1 : 1;
    p->next = met ? (j >= p->step ? j - p->step : 0) : j + p->step;
    p->step *= 2;
}

/* What the default search (probe_below) found PROBE_BELOW levels under the estimate */
typedef enum probed { PROBED_NONE, PROBED_MISSED, PROBED_MET } probed;

/* The default search's one VC1 build (see sk_tolerance_opts.full_search): the level
 * PROBE_BELOW under the estimate, when the estimate is neither too low for it nor the input
 * itself. Missed: its surface goes to t->best; met: it stays in t->r for the full search; no
 * VC1 surface there: PROBED_NONE (the full search builds it again and goes upwards). */
static sk_status probe_below(tol_run *t, size_t est, probed *out, sk_error *err)
{
    *out = PROBED_NONE;
    if (est < PROBE_BELOW || est + 1 >= t->c.levels)
        return SK_OK;
    size_t j = est - PROBE_BELOW, nvert = 0;
    sk_status vs = SK_OK;
    sk__tol_level_cut(&t->c, j, t->alive);
    sk_status st = sk__tol_build_surface(&t->c, t->alive, &t->b, NULL, NULL, &t->r, &vs, &nvert,
                                         t->stats, err);
    if (st)
        return st;
    t->stats->levels_tried++;
    sk__tol_record_try(t->stats, j, false, vs, nvert, &t->r);
    if (vs != SK_OK) {
        t->stats->failed_levels++;
        sk__tol_cut_result_free(&t->r);
        return SK_OK;
    }
    t->stats->singular_levels += t->r.singular > 0;
    *out = t->r.met ? PROBED_MET : PROBED_MISSED;
    if (!t->r.met)
        keep_better(&t->best, &t->r, &t->best_refined, false);
    return SK_OK;
}

/* The search: the coarsest level that meets T (*coarsest_met; the number of levels when none
 * does), assuming finer levels are closer, starting from the level estimate est (ignored with
 * no_estimate) after what probe_below found there (pr); the best surface seen is kept in
 * t->best. */
static sk_status search_levels(tol_run *t, size_t est, probed pr, size_t *coarsest_met,
                               sk_error *err)
{
    sk_status st = SK_OK;
    /* invariant: the levels below lo miss T (or have no VC1 surface); hi meets T when hi_met */
    size_t L = t->c.levels, lo = 0, hi = L - 1;
    bool hi_met = false;
    cut_result *at_hi = &t->at_hi; /* the surface of the met level hi */
    probe p = {.next = hi, .step = 1, .bisect = t->o.no_estimate};
    if (!p.bisect) {
        p.est = est;
        p.below = p.est >= PROBE_BELOW;
        p.next = p.below ? p.est - PROBE_BELOW : p.est;
    }
    if (pr != PROBED_NONE) { /* the state after the loop's first build, PROBE_BELOW under est */
        probe_update(&p, est - PROBE_BELOW, pr == PROBED_MET);
        if (pr == PROBED_MET) {
            hi = est - PROBE_BELOW;
            hi_met = true;
            *at_hi = t->r;
            memset(&t->r, 0, sizeof t->r);
            t->r.max = INFINITY;
        } else {
            lo = est - PROBE_BELOW + 1;
        }
    }
    for (;;) {
        bool last = lo >= hi; /* only hi is left: the input itself (or a met level) */
        if (last && hi_met)
            break;
        size_t j = last ? hi : probe_level(&p, lo, hi), end = last ? hi + 1 : hi;
        sk_status vs = SK_OK;
        /* from the middle upwards to the first level where VC1 can be built */
        for (; j < end; ++j) {
            sk__tol_level_cut(&t->c, j, t->alive);
            size_t nvert = 0;
            if ((st = sk__tol_build_surface(&t->c, t->alive, &t->b, NULL, NULL, &t->r, &vs,
                                            &nvert, t->stats, err)))
                return st;
            t->stats->levels_tried++;
            sk__tol_record_try(t->stats, j, false, vs, nvert, &t->r);
            if ((st = sk__progress(t->o.progress, t->o.progress_user,
                                   0.5 * (double)t->stats->levels_tried / (double)(L + 1), err)))
                return st;
            if (vs == SK_OK)
                break;
            t->stats->failed_levels++;
        }
        if (j >= end) { /* nothing builds in [mid, end) */
            if (last)
                break;
            lo = hi;
            continue;
        }
        t->stats->singular_levels += t->r.singular > 0;
        probe_update(&p, j, t->r.met);
        if (t->r.met) {
            hi = j;
            hi_met = true;
            sk__tol_cut_result_free(at_hi);
            *at_hi = t->r;
            memset(&t->r, 0, sizeof t->r);
            t->r.max = INFINITY;
        } else {
            keep_better(&t->best, &t->r, &t->best_refined, false);
            if (last)
                break; /* the input itself misses T */
            lo = j + 1;
        }
    }
    *coarsest_met = hi_met ? hi : L;
    if (at_hi->s)
        keep_better(&t->best, at_hi, &t->best_refined, false);
    t->stats->coarsest_met = *coarsest_met < L ? *coarsest_met : L - 1;
    t->stats->level_met = hi_met;
    return SK_OK;
}

/* Marks alive (2, then 1) the splits that bring back the bad vertices, or where they are all
 * there, their neighbours; t->fresh := what was added. Returns how many. */
static size_t split_back(tol_run *t)
{
    size_t added = 0;
    tol_ctx *c = &t->c;
    ++t->stamp_value;
    for (size_t v = 0; v < c->nv; ++v)
        if (t->bad[v] && !t->alive[v])
            added += sk__tol_want_step(c, t->alive, (uint32_t)v, t->stack, t->stamp, t->stamp_value);
    if (added == 0) {
        /* the out-of-tolerance faces are all there: refine around them */
        ++t->stamp_value;
        for (size_t v = 0; v < c->nv; ++v)
            if (t->bad[v])
                for (uint32_t k = c->ring_off[v]; k < c->ring_off[v + 1]; ++k)
                    if (!t->alive[c->ring[k]])
                        added += sk__tol_want_step(c, t->alive, c->ring[k], t->stack, t->stamp,
                                           t->stamp_value);
    }
    memset(t->fresh, 0, c->nv);
    for (size_t v = 0; v < c->nv; ++v)
        if (t->alive[v] == 2) {
            t->alive[v] = 1;
            t->fresh[v] = 1;
        }
    return added;
}

/* Progress of the refinement: the fewest offending vertices and the smallest max deviation of
 * its rounds so far, and the rounds since either was last lowered */
typedef struct round_progress {
    size_t fewest, since;
    double least;
} round_progress;

/* the number of flagged vertices */
static size_t count_bad(const tol_run *t)
{
    size_t n = 0;
    for (size_t v = 0; v < t->c.nv; ++v)
        n += t->bad[v] != 0;
    return n;
}

/* a round with `bad` offending vertices and max deviation mx: true when it is the
 * stall_rounds-th in a row that lowers neither the fewest offending vertices nor the smallest
 * deviation (the refinement does not converge: on fandisk at 3e-3 of the diagonal, where no
 * level meets T, the offending set stays between 3 and 40 vertices, moving round by round) */
static bool stalled(const tol_run *t, round_progress *pg, size_t bad, double mx)
{
    if (bad < pg->fewest || mx < pg->least) {
        pg->fewest = bad < pg->fewest ? bad : pg->fewest;
        pg->least = fmin(pg->least, mx);
        pg->since = 0;
        return false;
    }
    return ++pg->since >= t->stall_rounds;
}

/* Local refinement from a few levels below the coarsest met: split back where T is exceeded,
 * one collapse level at a time, until T holds, nothing is left to split, it stops paying or it
 * stalls (stall_rounds rounds in a row without progress). */
static sk_status refine(tol_run *t, size_t coarsest_met, sk_error *err)
{
    size_t base = coarsest_met > t->refine_levels ? coarsest_met - t->refine_levels : 0;
    t->stats->base_level = base;
    t->b.prev.valid = false; /* a search may have checked other surfaces since */
    t->hint.n = 0;           /* the first round's edge deletion starts from nothing */
    sk__tol_level_cut(&t->c, base, t->alive);
    size_t failures = 0;
    sk_status st = SK_OK;
    uint8_t *fresh = t->fresh; /* vertices made alive by the last round (to widen after a failure) */
    round_progress pg = {SIZE_MAX, 0, INFINITY};
    for (unsigned round = 0; round < t->max_rounds; ++round) {
        sk_status vs = SK_OK;
        size_t nvert = 0;
        memset(t->bad, 0, t->c.nv);
        if ((st = sk__tol_build_surface(&t->c, t->alive, &t->b, t->bad, &t->hint, &t->r, &vs,
                                        &nvert, t->stats, err)))
            return st;
        t->stats->rounds++;
        size_t nbad = vs == SK_OK ? count_bad(t) : 0;
        sk__tol_record_try(t->stats, base, true, vs, nvert, &t->r);
        if (t->stats->num_tried <= SK_TOLERANCE_MAX_TRIED && vs == SK_OK) {
            sk_tolerance_try *e = &t->stats->tried[t->stats->num_tried - 1];
            e->offending = nbad;
            e->paired = t->b.reused_patches;
            e->unmoved = t->b.unmoved_patches;
            e->moved_far = t->b.far_patches;
        }
        if ((st = sk__progress(t->o.progress, t->o.progress_user,
                               0.5 + 0.5 * (double)(round + 1) / t->max_rounds, err)))
            return st;
        if (vs != SK_OK) {
            t->stats->failed_rounds++;
            if (++failures > MAX_FAILED_ROUNDS)
                break;
            bool any = false;
            for (size_t v = 0; v < t->c.nv && !any; ++v)
                any = fresh[v];
            if (!any) { /* the base itself has no VC1 surface: a finer base */
                if (base + 1 >= coarsest_met)
                    break;
                t->stats->base_level = ++base;
                sk__tol_level_cut(&t->c, base, t->alive);
                continue;
            }
            /* widen: the neighbours of what the last round added */
            for (size_t v = 0; v < t->c.nv; ++v)
                if (fresh[v])
                    for (uint32_t k = t->c.ring_off[v]; k < t->c.ring_off[v + 1]; ++k)
                        t->bad[t->c.ring[k]] = 1;
        } else {
            /* within T with singular patches: go on splitting around them (they are in bad)
             * while that lowers their number (some meshes have singular patches even at the
             * input level: VC1 over cow.off has 15) */
            bool ok = cut_ok(&t->r);
            bool worse = t->best.met && t->r.patches >= t->best.patches &&
                         (cut_ok(&t->best) || (t->r.met && t->r.singular >= t->best.singular));
            double mx = t->r.max;
            keep_better(&t->best, &t->r, &t->best_refined, true);
            if (ok || worse)
                break;
            if (stalled(t, &pg, nbad, mx)) {
                t->stats->stalled++;
                break;
            }
        }
        size_t added = split_back(t);
        if (added == 0)
            break; /* the input mesh around every offending face */
    }
    return st;
}

/* The result against the input, as sk_deviation measures it; *out and *fine_ids handed out. */
static sk_status finish(tol_run *t, sk_smooth **out, uint32_t **fine_ids, sk_error *err)
{
    if (!t->best.s)
        return sk__fail(err, t->c.last_fail ? t->c.last_fail : SK_ERR_NUMERIC,
                        "no level of the hierarchy has a VC1 surface (the last failure: %.160s)",
                        t->c.last_msg);
    double te = sk_seconds();
    sk_status st = SK_OK;
    /* the result against the input, as sk_deviation measures it */
    sk_deviation_opts dop = {0};
    dop.face_samples = t->c.n;
    if ((st = sk_patch_set_tessellate(&t->best.s->surface, t->c.tess, &t->ts, err)) ||
        (st = sk__deviation_over(t->ts, t->fine_soup, t->c.mesh_bvh, &dop,
                                     &t->stats->deviation, err)))
        return st;
    t->stats->seconds_deviation = sk_seconds() - te;
    t->stats->refined = t->best_refined;
    t->stats->vertices = t->best.s->config->num_vertices;
    t->stats->patches = t->best.s->surface.count;
    t->stats->met = t->stats->deviation.hausdorff <= t->c.tol;
    if (fine_ids) {
        size_t nc = t->best.s->config->num_vertices;
        uint32_t *ids = sk__malloc_array(nc ? nc : 1, sizeof *ids);
        if (!ids)
            return sk__fail(err, SK_ERR_NOMEM, "out of memory");
        size_t built = t->stats->vertices - t->best.s->stats.split_edges;
        for (size_t k = 0; k < nc; ++k)
            ids[k] = k < built ? t->best.m2f[k] : SK_INVALID;
        *fine_ids = ids;
    }
    *out = t->best.s;
    t->best.s = NULL;
    if (!t->stats->met)
        return sk__fail(err, SK_WARN_TOLERANCE, "the tolerance %g is not met: the closest surface "
                      "found is %g from the mesh (%zu patches)", t->c.tol,
                      t->stats->deviation.hausdorff, t->stats->patches);
    sk__ok(err);
    return SK_OK;
}

/* The full search, then the refinement from the coarsest met level (when there is one below the
 * input); skip: the base level an earlier refinement started from (none: t->c.levels) */
static sk_status full_search(tol_run *t, size_t est, probed pr, size_t skip, double *search_s,
                             sk_error *err)
{
    size_t coarsest_met = 0;
    double t0 = sk_seconds();
    sk_status st = search_levels(t, est, pr, &coarsest_met, err);
    *search_s += sk_seconds() - t0;
    size_t base = coarsest_met > t->refine_levels ? coarsest_met - t->refine_levels : 0;
    if (!st && coarsest_met < t->c.levels && coarsest_met > 0 && base != skip)
        st = refine(t, coarsest_met, err);
    return st;
}

/* The search and the refinement: by default (sk_tolerance_opts.full_search) from the estimate
 * when the level PROBE_BELOW under it misses T, falling back to the full search when that ends
 * without a surface within T and without singular patches */
static sk_status search_and_refine(tol_run *t, sk_error *err)
{
    double t0 = sk_seconds(), search_s = 0;
    size_t est = 0;
    probed pr = PROBED_NONE;
    sk_status st = SK_OK;
    if (!t->o.no_estimate && (st = estimate_level(t, &est, err)))
        return st;
    if (!t->o.no_estimate && !t->o.full_search && (st = probe_below(t, est, &pr, err)))
        return st;
    search_s = sk_seconds() - t0;
    if (pr == PROBED_MISSED) {
        t->stats->level_assumed = true;
        t->stats->coarsest_met = est;
        if ((st = refine(t, est, err)))
            return st;
        if (!cut_ok(&t->best)) {
            t->stats->level_assumed = false;
            st = full_search(t, est, pr, t->stats->base_level, &search_s, err);
        }
    } else {
        st = full_search(t, est, pr, t->c.levels, &search_s, err);
    }
    t->stats->seconds_search = search_s;
    t->stats->seconds_refine = sk_seconds() - t0 - search_s;
    return st;
}

sk_status sk_smooth_tolerance(const sk_mesh *mesh, const sk_tolerance_opts *opts,
                              sk_smooth **out, uint32_t **fine_ids,
                              sk_tolerance_stats *stats_out, sk_error *err)
{
    tol_run t;
    memset(&t, 0, sizeof t);
    if (opts)
        t.o = *opts;
    *out = NULL;
    if (fine_ids)
        *fine_ids = NULL;
    sk_tolerance_stats stats_local;
    t.stats = stats_out ? stats_out : &stats_local;
    memset(t.stats, 0, sizeof *t.stats);
    t.best.max = t.r.max = t.at_hi.max = INFINITY;
    sk_status st = check_input(mesh, &t.o, err);
    if (st)
        return st;
    if ((st = setup(&t, mesh, err)))
        goto done;
    if (!(t.fresh = sk__calloc_array(t.c.nv, 1))) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    st = search_and_refine(&t, err);
    if (!st)
        st = finish(&t, out, fine_ids, err);
done:
    run_free(&t);
    return st;
}
