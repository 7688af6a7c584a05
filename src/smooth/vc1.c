/* The VC1 construction of Cottin & van Damme (section 4): the driver from a triangle mesh with
 * normals to the network of quartic triangles and bicubic quads (normals, parity split, edge
 * deletion, wire frame targets, vertex systems (8), interior points (4), patches, regularity
 * repair), and the PN baseline's entry. */
#include "smooth/vc1_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>
#include <string.h>
#ifdef SK_HAVE_OPENMP
#include <omp.h>
#endif

void sk_smooth_destroy(sk_smooth **smooth)
{
    if (!smooth || !*smooth)
        return;
    sk_smooth *s = *smooth;
    sk_mesh_destroy(&s->config);
    sk__free(s->normals);
    sk_patch_set_free(&s->surface);
    sk__free(s->deleted);
    sk__free(s->problems);
    sk__free(s->creases);
    sk__free(s->crease_edge);
    sk__free(s->corner_normals);
    sk__free(s);
    *smooth = NULL;
}

/* One patch per face of s->config, points in one block: the headers here (in parallel, the
 * offsets in order), the points left for vc1_assemble to write (every one of them; the block's
 * pages were touched beside the edge deletion (prefault_surface), else its parallel loop makes
 * the first touch, which a zero fill here made serially: most of the patches stage at 832k
 * triangles). */
static sk_status add_patches(sk_smooth *s, sk_error *err)
{
    const sk_mesh *m = s->config;
    size_t nf = m->num_faces, nquads = 0;
    long nfl = (long)nf;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) reduction(+ : nquads) if (nfl > 100000)
#endif
    for (long f = 0; f < nfl; ++f) { /* a quad: its fourth half-edge is not the first */
        uint32_t h0 = m->f_halfedge[f];
        nquads += m->h_next[m->h_next[m->h_next[h0]]] != h0;
    }
    size_t npts = 15 * nf + nquads, first = s->surface.num_points, base = s->surface.count;
    sk_status st = sk__patch_set_extend_unset(&s->surface, nf, npts, err);
    if (st)
        return st;
    sk__huge_hint(s->surface.points + 3 * first, npts * 3 * sizeof(double));
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl > 100000)
#endif
    for (long f = 0; f < nfl; ++f) {
        sk_patch *p = &s->surface.patches[base + (size_t)f];
        sk__vc1_patch_header(m, (uint32_t)f, p);
        p->reserved = 0;
    }
    for (size_t f = 0; f < nf; ++f) {
        sk_patch *p = &s->surface.patches[base + f];
        p->first = first;
        first += sk_bezier_num_points((sk_patch_kind)p->kind, p->degree, p->degree_v);
    }
    return SK_OK;
}

/* A stage's start: wall and CPU clocks (sk_seconds, sk_cpu_seconds). */
static void clock_now(double t[2])
{
    t[0] = sk_seconds();
    t[1] = sk_cpu_seconds();
}

/* The wall and CPU seconds since t into *wall, *cpu (NULL: not wanted). */
static void clock_since(const double t[2], double *wall, double *cpu)
{
    if (wall)
        *wall = sk_seconds() - t[0];
    if (cpu)
        *cpu = sk_cpu_seconds() - t[1];
}

/* Step 1: the wire frame targets, the ratios r_m of eq. (7) (bounded by max_nu) and nu per
 * half-edge (upper patch = face(h)). */
static sk_status vc1_targets_and_ratios(sk__vc1_work *W, double *target, double *r,
                                        double max_nu, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t nh = m->num_halfedges;
    sk_status st = sk__wireframe_targets_cn(m, W->normals, W->cn, W->crease_e, target, err);
    if (st != SK_OK)
        return st;
    if (W->crease_e)
        sk__crease_targets(m, W->crease_e, W->cn, target);
    sk__patch_ratios(m, target, r);
    for (size_t h = 0; h < nh; ++h) {
        uint32_t f = m->h_face[h], g = m->h_face[h ^ 1u];
        if (f != SK_INVALID && g != SK_INVALID && !(r[f] > 0.0 && r[g] > 0.0))
            return sk__fail(err, SK_ERR_NUMERIC,
                            "edge (%u, %u): a neighbouring patch has zero target area (r_m = 0 in "
                            "eq. 7), the wire frame targets are collinear",
                            sk_from(m, (uint32_t)h), sk_to(m, (uint32_t)h));
    }
    if (max_nu > 0.0)
        sk__bound_ratios(m, r, max_nu);
    long nhl = (long)nh;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nhl > 100000)
#endif
    for (long hl = 0; hl < nhl; ++hl) {
        size_t h = (size_t)hl;
        uint32_t f = m->h_face[h], g = m->h_face[h ^ 1u];
        W->nu[h] = (f != SK_INVALID && g != SK_INVALID) ? sk__nu(r[f], r[g]) : NAN;
    }
    for (size_t h = 0; W->crease_e && h < nh; ++h)
        if (W->crease_e[sk_edge((uint32_t)h)])
            W->nu[h] = NAN; /* no constraint (8) across a crease, as on a boundary */
    if (W->crease_e)
        sk__crease_tangent_ratios(W, r, target);
    return SK_OK;
}

/* Step 2: the vertex systems (8), least squares to the targets; status[v] gets the code of
 * sk__vc1_solve_vertex, fig[v] its figures; only (NULL: every vertex) the vertices to solve (the
 * others' solutions, codes and figures are set already: a re-routed round's reuse). The solver
 * figures go to s->stats, summed in vertex order from fig (the same for any number of threads). */
static sk_status vc1_vertex_systems(sk_smooth *s, sk__vc1_work *W, uint8_t *status,
                                    sk__vsys_fig *fig, const uint8_t *only, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t nv = m->num_vertices;
    double max_res = 0.0, dev_sum = 0.0;
    size_t max_it = 0, fallback = 0, dev_n = 0, relaxed = 0;
    long nvl = (long)nv;
    int too_many = -1;
    long nchunks = (nvl + SK_VC1_VERTEX_CHUNK - 1) / SK_VC1_VERTEX_CHUNK;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 16) if (nvl >= SK_SMOOTH_TEAM_MIN)
#endif
    for (long c = 0; c < nchunks; ++c) {
        uint32_t vs[SK_VC1_VERTEX_CHUNK];
        sk__vsys sys[SK_VC1_VERTEX_CHUNK];
        int code[SK_VC1_VERTEX_CHUNK], count = 0;
        for (long i = c * SK_VC1_VERTEX_CHUNK; i < nvl && i < (c + 1) * SK_VC1_VERTEX_CHUNK; ++i)
            if (!m->v_deleted[i] && m->v_halfedge[i] != SK_INVALID && (!only || only[i]))
                vs[count++] = (uint32_t)i;
        sk__vc1_solve_vertices(W, vs, count, sys, code);
        for (int i = 0; i < count; ++i) {
            uint32_t v = vs[i];
            sk__vsys_fig *F = &fig[v];
            status[v] = (uint8_t)code[i];
            *F = (sk__vsys_fig){.relaxed = (uint8_t)sys[i].relaxed};
            if (code[i] == 3)
                continue;
            F->residual = sys[i].residual;
            F->iterations = (uint32_t)sys[i].iterations;
            F->fallback = (uint8_t)sys[i].used_fallback;
            for (int k = 0; k < sys[i].n_edges; ++k) {
                double len = hypot(sys[i].pstar[2 * k], sys[i].pstar[2 * k + 1]);
                if (len > 0.0) {
                    F->dev += hypot(sys[i].p[2 * k] - sys[i].pstar[2 * k],
                                    sys[i].p[2 * k + 1] - sys[i].pstar[2 * k + 1]) / len;
                    F->dev_n++;
                }
            }
        }
    }
    for (size_t v = 0; v < nv; ++v) {
        const sk__vsys_fig *F = &fig[v];
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        relaxed += F->relaxed;
        if (status[v] == 3) {
            too_many = too_many < 0 ? (int)v : too_many;
            continue;
        }
        max_res = fmax(max_res, F->residual);
        max_it = F->iterations > max_it ? F->iterations : max_it;
        fallback += F->fallback;
        dev_sum += F->dev;
        dev_n += F->dev_n;
    }
    if (too_many >= 0)
        return sk__fail(err, SK_ERR_TOPOLOGY, "vertex %d has more than %d edges", too_many,
                        SK_VSYS_MAX);
    s->stats.vertex_systems = nv;
    s->stats.max_iterations = max_it;
    s->stats.fallback_solves = fallback;
    s->stats.relaxed_vertices = relaxed;
    s->stats.max_residual = max_res;
    s->stats.mean_target_deviation = dev_n ? dev_sum / (double)dev_n : 0.0;
    return SK_OK;
}

/* Step 3: the interior points (4) around every vertex. */
static void vc1_interior_points(sk__vc1_work *W)
{
    const sk_mesh *m = W->m;
    long nvl = (long)m->num_vertices;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nvl >= SK_SMOOTH_TEAM_MIN)
#endif
    for (long i = 0; i < nvl; ++i)
        if (!m->v_deleted[i] && m->v_halfedge[i] != SK_INVALID)
            sk__vc1_interior_points(W, (uint32_t)i);
}

/* Step 4: the patch of every face of s->config (added by add_patches) from the cubic boundary
 * curves and the interior points. */
static void vc1_assemble(sk_smooth *s, const sk__vc1_work *W)
{
    long nfl = (long)W->m->num_faces;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl >= SK_SMOOTH_TEAM_MIN)
#endif
    for (long f = 0; f < nfl; ++f)
        sk__vc1_assemble_patch(W, (uint32_t)f, sk_patch_cp(&s->surface, (size_t)f));
}

/* Step 6: exactness or a named failure (eq. (8) holds to rounding at every vertex, else no
 * surface: *failed_v names the vertex), then the list of problem vertices (failed or
 * angle-violating) in s->problems. */
static sk_status vc1_problems(sk_smooth *s, sk__vc1_work *W, const uint8_t *status,
                              uint32_t *failed_v, sk_error *err)
{
    size_t nv = W->m->num_vertices, nprob = 0;
    for (size_t v = 0; v < nv; ++v) {
        s->stats.angle_violations += status[v] == 1;
        s->stats.failed_vertices += status[v] == 2;
        nprob += status[v] != 0;
    }
    for (size_t v = 0; v < nv && s->stats.failed_vertices; ++v)
        if (status[v] == 2) {
            sk__vsys sys;
            sk__vc1_solve_vertex(W, (uint32_t)v, &sys, 0.0, 1.0);
            *failed_v = (uint32_t)v;
            return sk__fail(err, SK_ERR_NUMERIC,
                            "vertex %zu: its vertex system (eq. 8) did not converge (residual "
                            "%.3g of its scale), so the surface would not be VC1 there (%zu such "
                            "vertices)",
                            v, sys.residual, s->stats.failed_vertices);
        }
    if (!nprob)
        return SK_OK;
    s->problems = sk__malloc_array(nprob, sizeof(uint32_t));
    if (!s->problems)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t v = 0; v < nv; ++v)
        if (status[v])
            s->problems[s->num_problems++] = (uint32_t)v;
    return SK_OK;
}

/* Sweeps of the fair free points (fair_points.c; measured: more gained little) */
#define VC1_FAIR_SWEEPS 10

/* Rounds of the fit to the scan: foot points, sweeps (measured: see docs) */
#ifndef VC1_FIT_ROUNDS
#define VC1_FIT_ROUNDS 3
#endif

/* Rounds of the guard after the fit to the scan (see fit_guard) before it undoes the whole fit */
#define VC1_FIT_GUARD_ROUNDS 4

/* v's tangents back to P0 (mark: v and its neighbours, whose system (4) is to be solved again) */
static void undo_vertex(sk__vc1_work *W, const double *P0, uint32_t v, uint8_t *mark)
{
    const sk_mesh *m = W->m;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    mark[v] = 1;
    do {
        memcpy(W->P + 3 * (size_t)h, P0 + 3 * (size_t)h, 3 * sizeof(double));
        mark[sk_to(m, h)] = 1;
        h = sk_cw_out(m, h);
    } while (h != h0);
}

/* The fit to the scan makes no patch singular (sing: SK_SING_UNKNOWN for the patches the sweeps
 * moved, assembled again; before: the test before the sweeps): the tangents at the corners of a
 * patch it made singular go back to P0 (those before the sweeps), from the second round also
 * their neighbours', system (4) is solved again around them and their patches assembled and
 * tested again; after VC1_FIT_GUARD_ROUNDS rounds the whole fit is undone. The corners of a
 * moved patch that was singular before and still is go back too, once (in the first round),
 * for the regularity repair: on the cow it repaired all of them without the fit, and left one
 * when the fit had moved them. Every state is exactly VC1 (the tangents of each vertex are those
 * of a solution of (8), system (4) solved again). */
static sk_status fit_guard(sk_smooth *s, sk__vc1_work *W, const double *P0, const uint8_t *before,
                           uint8_t *sing, sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t nf = m->num_faces, nv = m->num_vertices;
    uint8_t *mark = sk__calloc_array(nv + 1, 1), *bad = sk__calloc_array(nf + 1, 1);
    if (!mark || !bad) {
        sk__free(mark);
        sk__free(bad);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
    }
    for (int round = 0;; ++round) {
        long nfl = (long)nf;
        size_t nnew = 0, nold = 0;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : nnew, nold) \
    if (nfl >= SK_SMOOTH_TEAM_MIN)
#endif
        for (long f = 0; f < nfl; ++f) { /* 1: made singular by the fit, 2: singular before */
            bad[f] = sing[f] == SK_SING_UNKNOWN && sk__patch_singular(s, (size_t)f, NULL)
                         ? (before[f] ? 2 : 1)
                         : 0;
            nnew += bad[f] == 1;
            nold += bad[f] == 2;
        }
        if (!nnew && (round > 0 || !nold))
            break;
        s->stats.fit_undone += nnew + (round == 0 ? nold : 0);
        if (round == VC1_FIT_GUARD_ROUNDS) { /* the whole fit undone */
            memcpy(W->P, P0, m->num_halfedges * 3 * sizeof(double));
            memset(mark, 1, nv);
        } else {
            for (uint32_t f = 0; f < nf; ++f) {
                if (!(bad[f] == 1 || (bad[f] == 2 && round == 0)))
                    continue;
                uint32_t h0 = m->f_halfedge[f], h = h0;
                do {
                    uint32_t v = sk_from(m, h);
                    undo_vertex(W, P0, v, mark);
                    if (round > 0) {
                        uint32_t g0 = m->v_halfedge[v], g = g0;
                        do {
                            undo_vertex(W, P0, sk_to(m, g), mark);
                            g = sk_cw_out(m, g);
                        } while (g != g0);
                    }
                    h = m->h_next[h];
                } while (h != h0);
            }
        }
        for (uint32_t v = 0; v < nv; ++v) {
            if (!mark[v] || m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID) {
                mark[v] = 0;
                continue;
            }
            sk__vc1_interior_points(W, v);
            mark[v] = 0;
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t f = m->h_face[h];
                if (f != SK_INVALID)
                    sk__vc1_assemble_patch(W, f, sk_patch_cp(&s->surface, f));
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
        if (round == VC1_FIT_GUARD_ROUNDS)
            break;
    }
    sk__free(mark);
    sk__free(bad);
    return SK_OK;
}

/* The patches of *singular (s->stats.singular_after_repair of them) that the fit to the scan
 * made regular taken out of the list (it moves no patch into it: fit_guard) */
static void drop_regular(sk_smooth *s, uint32_t **singular)
{
    size_t n = s->stats.singular_after_repair, k = 0;
    if (!singular || !*singular)
        return;
    for (size_t i = 0; i < n; ++i)
        if (sk__patch_singular(s, (*singular)[i], NULL))
            (*singular)[k++] = (*singular)[i];
    s->stats.singular_after_repair = k;
    if (k == 0) {
        sk__free(*singular);
        *singular = NULL;
    }
}

void sk__vc1_state_free(sk__vc1_state **state)
{
    if (!state || !*state)
        return;
    sk__vc1_state *k = *state;
    sk__free(k->target);
    sk__free(k->nu);
    sk__free(k->P);
    sk__free(k->w1);
    sk__free(k->C);
    sk__free(k->status);
    sk__free(k->fig);
    sk__free(k->corners);
    sk__free(k);
    *state = NULL;
}

/* The fit of the free points to fit_mesh (fit_weight > 0), VC1_FIT_ROUNDS rounds from the surface
 * as it stands, each guarded against new singular patches (fit_guard); *sing allocated here when
 * the build has none yet. */
static sk_status vc1_fit(sk_smooth *s, sk__vc1_work *W, uint8_t *status, const sk_mesh *fit_mesh,
                         double fit_weight, uint8_t **sing, uint32_t **singular, sk_error *err)
{
    size_t nh = W->m->num_halfedges, nf = W->m->num_faces;
    sk__fit_data fit = {0};
    sk_status st = SK_OK;
    double t4[2];
    clock_now(t4);
    uint8_t *before = sk__malloc_array(nf + 1, 1);
    double *P0 = sk__malloc_array(nh + 1, 3 * sizeof(double));
    if ((!*sing && !(*sing = sk__malloc_array(nf + 1, 1))) || !before || !P0) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
        goto done;
    }
    s->stats.fit_steps = 0;
    s->stats.fit_undone = 0;
    for (int round = 0; round < VC1_FIT_ROUNDS; ++round) {
        sk__fit_data_free(&fit);
        if ((st = sk__vc1_fit_data(s, fit_mesh, fit_weight, &fit, err)) != SK_OK)
            goto done;
        s->stats.fit_points = fit.count;
        memcpy(P0, W->P, nh * 3 * sizeof(double));
        size_t steps = 0;
        if ((st = sk__vc1_fair_points(s, W, status, VC1_FAIR_SWEEPS, &fit, *sing, before, &steps,
                                      NULL, err)) != SK_OK)
            goto done;
        s->stats.fit_steps += steps;
        for (uint32_t f = 0; f < nf; ++f) /* the patches the fit may have moved */
            if ((*sing)[f] == SK_SING_UNKNOWN)
                sk__vc1_assemble_patch(W, f, sk_patch_cp(&s->surface, f));
        if ((st = fit_guard(s, W, P0, before, *sing, err)) != SK_OK)
            goto done;
    }
    drop_regular(s, singular);
    clock_since(t4, &s->stats.seconds_fit, &s->stats.cpu_fit);
done:
    sk__fit_data_free(&fit);
    sk__free(before);
    sk__free(P0);
    return st;
}

/* The state a re-routed round builds on (reroute.c): the corners of the singular patches, and
 * the build's configuration, patches, targets, vertex solutions and figures, which the state
 * takes over from W, target, status and fig (the caller drops its pointers). NULL when out of
 * memory: the rounds then build from nothing. */
static sk__vc1_state *vc1_keep_state(sk_smooth *s, const sk__vc1_work *W, const uint32_t *singular,
                                     double *target, uint8_t *status, sk__vsys_fig *fig)
{
    sk__vc1_state *k = sk__calloc_array(1, sizeof *k);
    size_t nc = 0;
    for (size_t i = 0; k && i < s->stats.singular_after_repair; ++i)
        nc += sk_patch_num_corners(&s->surface.patches[singular[i]]);
    if (!k || !(k->corners = sk__malloc_array(nc + 1, sizeof(uint32_t)))) {
        sk__free(k);
        return NULL;
    }
    for (size_t i = 0; i < s->stats.singular_after_repair; ++i) {
        const sk_patch *p = &s->surface.patches[singular[i]];
        for (unsigned c = 0; c < sk_patch_num_corners(p); ++c)
            k->corners[k->num_corners++] = p->corner_ids[c];
    }
    k->config = s->config;
    k->crease_edge = s->crease_edge;
    k->corner_normals = s->corner_normals;
    k->patches = s->surface.patches;
    k->points = s->surface.points;
    k->target = target, k->nu = W->nu, k->P = W->P, k->w1 = W->w1, k->C = W->C;
    k->status = status, k->fig = fig;
    k->stats = s->stats;
    return k;
}

/* The construction on s->config: targets and ratios, vertex systems, interior points, fair free
 * points (unless LSQ), patches, regularity repair, exactness check (failed_v: the vertex named
 * when a vertex system fails, SK_ERR_NUMERIC). G0 at the creases of s->crease_edge. */
static sk_status vc1_build(sk_smooth *s, double alpha, double max_nu, sk_free_points free_points,
                           const sk_mesh *fit_mesh, double fit_weight, const sk__vc1_state *prev,
                           sk__vc1_state **state, uint32_t *failed_v, uint32_t **singular,
                           sk_error *err)
{
    sk_mesh *m = s->config;
    size_t nh = m->num_halfedges, nf = m->num_faces, nv = m->num_vertices;
    sk_status st = SK_OK;
    sk__vc1_work W = {0};
    double *target = sk__malloc_array(nh, 3 * sizeof(double));
    double *r = sk__malloc_array(nf + 1, sizeof(double));
    W.P = sk__calloc_array(nh, 3 * sizeof(double));
    W.w1 = sk__malloc_array(nh, sizeof(double));
    W.nu = sk__malloc_array(nh, sizeof(double));
    W.C = sk__calloc_array(nh, 3 * sizeof(double));
    uint8_t *status = sk__calloc_array(nv ? nv : 1, 1), *sing = NULL;
    sk__vsys_fig *fig = sk__calloc_array(nv ? nv : 1, sizeof *fig);
    uint8_t *crease_v = s->crease_edge ? sk__calloc_array(nv ? nv : 1, 1) : NULL;
    sk__vc1_reuse plan = {0};
    if (prev && fit_weight <= 0.0 && !sk__vc1_reuse_alloc(&plan, m)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
        goto done;
    }
    if (!target || !r || !W.P || !W.w1 || !W.nu || !W.C || !status || !fig ||
        (s->crease_edge && !crease_v)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
        goto done;
    }
    W.m = m;
    W.normals = s->normals;
    W.target = target;
    W.r = r;
    W.alpha = alpha;
    if (s->crease_edge) { /* G0 at the creases: sectors, their normals, the shared curves */
        for (uint32_t e = 0; e < sk_num_edges(m); ++e)
            if (s->crease_edge[e])
                crease_v[sk_from(m, 2 * e)] = crease_v[sk_to(m, 2 * e)] = 1;
        W.crease_e = s->crease_edge;
        W.crease_v = crease_v;
        W.cn = s->corner_normals;
    }
    double t0[2], t1[2], t2[2], t3[2];
    clock_now(t0);
    if ((st = vc1_targets_and_ratios(&W, target, r, max_nu, err)) != SK_OK)
        goto done;
    if (plan.hmap) { /* a re-routed round: what did not change is taken from the build before */
        sk__vc1_reuse_plan(&W, prev, &plan);
        sk__vc1_reuse_solutions(&W, prev, &plan, status, fig);
        W.limit = plan.near;
    }
    if ((st = vc1_vertex_systems(s, &W, status, fig, plan.near, err)) != SK_OK)
        goto done;
    if (plan.hmap)
        sk__vc1_reuse_interior_points(&W, prev, &plan);
    else
        vc1_interior_points(&W);
    clock_since(t0, &s->stats.seconds_systems, &s->stats.cpu_systems);
    clock_now(t1);
    if ((st = add_patches(s, err)) != SK_OK)
        goto done;
    if (plan.hmap)
        sk__vc1_reuse_patches(s, &W, prev, &plan);
    else
        vc1_assemble(s, &W);
    clock_since(t1, &s->stats.seconds_patches, &s->stats.cpu_patches);
    clock_now(t2);
    if (plan.hmap && !(sing = sk__malloc_array(nf + 1, 1))) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
        goto done;
    }
    if (free_points == SK_FREE_POINTS_FAIR) {
        if (!sing && !(sing = sk__malloc_array(nf + 1, 1))) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
            goto done;
        }
        double energy[2];
        if ((st = sk__vc1_fair_points(s, &W, status, VC1_FAIR_SWEEPS, NULL, sing, NULL,
                                      &s->stats.fair_steps, energy, err)) != SK_OK)
            goto done;
        s->stats.fair_energy_before = energy[0];
        s->stats.fair_energy_after = energy[1];
        for (uint32_t f = 0; f < nf; ++f) /* the patches the fair points may have moved */
            if (sing[f] == SK_SING_UNKNOWN)
                sk__vc1_assemble_patch(&W, f, sk_patch_cp(&s->surface, f));
    }
    if (plan.hmap) /* untested: the patches the round assembled again, outside the fair's test */
        sk__vc1_reuse_untested(&W, &plan, free_points == SK_FREE_POINTS_FAIR, sing);
    clock_since(t2, &s->stats.seconds_fair, &s->stats.cpu_fair);
    clock_now(t3);
    if ((st = sk__vc1_repair_regularity(s, &W, status, sing, singular, err)) != SK_OK)
        goto done;
    clock_since(t3, &s->stats.seconds_repair, &s->stats.cpu_repair);
    if (plan.hmap) {
        /* the round's steps and gains added to the build's it started from; its time is the
         * repair stage's (sk__vc1_reroute_singular), the other stages keep the first build's */
        const sk_smooth_stats *f = &prev->stats;
        s->stats.seconds_deletion = f->seconds_deletion, s->stats.cpu_deletion = f->cpu_deletion;
        s->stats.seconds_systems = f->seconds_systems, s->stats.cpu_systems = f->cpu_systems;
        s->stats.seconds_patches = f->seconds_patches, s->stats.cpu_patches = f->cpu_patches;
        s->stats.seconds_fair = f->seconds_fair, s->stats.cpu_fair = f->cpu_fair;
        s->stats.singular_before_repair = prev->stats.singular_before_repair;
        s->stats.repaired_vertices += prev->stats.repaired_vertices;
        s->stats.fair_steps += prev->stats.fair_steps;
    }
    if (fit_weight > 0.0 && /* the fit to the scan, from the surface as it stands */
        (st = vc1_fit(s, &W, status, fit_mesh, fit_weight, &sing, singular, err)) != SK_OK)
        goto done;
    st = vc1_problems(s, &W, status, failed_v, err);
    if (st == SK_OK && state && singular && *singular && fit_weight <= 0.0 &&
        (*state = vc1_keep_state(s, &W, *singular, target, status, fig))) {
        target = NULL, W.nu = W.P = W.w1 = W.C = NULL; /* now the state's */
        status = NULL, fig = NULL;
    }
done:
    sk__vc1_reuse_free(&plan);
    sk__free(fig);
    sk__free(target);
    sk__free(r);
    sk__free(W.P);
    sk__free(W.w1);
    sk__free(W.nu);
    sk__free(W.C);
    sk__free(status);
    sk__free(sing);
    sk__free(crease_v);
    return st;
}

/* The crease edges of the input as vertex pairs (s->creases): detected, and (file_normals) the
 * edges whose per-corner normals differ at an end; *hinge_end (NULL when there is none; one flag
 * per vertex of mesh): the vertices where a line of fold hinges ends (one detected crease edge,
 * a fold hinge of crease.c step 4b). */
static sk_status detect_creases(sk_smooth *s, const sk_mesh *mesh, double angle, bool file_normals,
                                uint8_t **hinge_end, sk_error *err)
{
    size_t ne = sk_num_edges(mesh), nv = mesh->num_vertices, n = 0;
    uint8_t *crease = sk__malloc_array(ne ? ne : 1, 1), *hinge = sk__malloc_array(ne ? ne : 1, 1);
    uint32_t *deg = sk__calloc_array(nv ? nv : 1, sizeof(uint32_t));
    sk_crease_opts co = {.angle_deg = angle};
    sk_status st = crease && hinge && deg ? SK_OK : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    *hinge_end = NULL;
    if (st == SK_OK)
        st = sk__crease_edges_hinges(mesh, &co, crease, hinge, &n, err);
    bool any_hinge = false;
    for (uint32_t e = 0; st == SK_OK && e < ne; ++e)
        if (crease[e]) {
            deg[sk_from(mesh, 2 * e)]++;
            deg[sk_to(mesh, 2 * e)]++;
            any_hinge = any_hinge || hinge[e];
        }
    if (any_hinge && !(*hinge_end = sk__calloc_array(nv, 1)))
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (uint32_t e = 0; st == SK_OK && any_hinge && e < ne; ++e)
        for (int k = 0; hinge[e] && k < 2; ++k) {
            uint32_t v = k ? sk_to(mesh, 2 * e) : sk_from(mesh, 2 * e);
            (*hinge_end)[v] = deg[v] == 1;
        }
    sk__free(hinge);
    sk__free(deg);
    if (st == SK_OK && file_normals && mesh->h_wedge_normal)
        n += sk__corner_normal_creases(mesh, crease);
    if (st == SK_OK && n > 0) {
        s->creases = sk__malloc_array(2 * n, sizeof(uint32_t));
        if (!s->creases)
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        for (uint32_t e = 0; st == SK_OK && e < ne; ++e)
            if (crease[e]) {
                s->creases[2 * s->num_creases] = sk_from(mesh, 2 * e);
                s->creases[2 * s->num_creases + 1] = sk_to(mesh, 2 * e);
                s->num_creases++;
            }
    }
    sk__free(crease);
    return st;
}

/* rounds of dropping crease lines whose sectors cannot be built */
#define SK_CREASE_ROUNDS 4

/* the crease edges (s->creases) as flags per edge of m */
static sk_status crease_flags_of(const sk_smooth *s, const sk_mesh *m, uint8_t **flags,
                                 sk_error *err)
{
    size_t ne = sk_num_edges(m);
    *flags = sk__malloc_array(ne ? ne : 1, 1);
    if (!*flags)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    sk__crease_flags(m, s->creases, s->num_creases, *flags);
    return SK_OK;
}

static sk_status check_input(const sk_mesh *mesh, sk_error *err)
{
    for (uint32_t f = 0; f < mesh->num_faces; ++f)
        if (!mesh->f_deleted[f] && sk_mesh_face_size(mesh, f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "face %u has %zu sides: a triangle mesh is needed", f,
                            sk_mesh_face_size(mesh, f));
    for (size_t i = 0; i < 3 * mesh->num_vertices; ++i)
        if (!isfinite(mesh->positions[i]))
            return sk__fail(err, SK_ERR_NUMERIC, "vertex %zu has a non-finite coordinate", i / 3);
    return sk_mesh_check_scale(mesh, err);
}

/* The unit normals the surface interpolates: the file's (checked), or estimated. */
static sk_status input_normals(const sk_mesh *mesh, const sk_smooth_opts *opts, double **out,
                               sk_error *err)
{
    size_t nv = mesh->num_vertices;
    double *normals = sk__malloc_array(nv + 1, 3 * sizeof(double));
    if (!normals)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    *out = normals;
    if (!mesh->normals || opts->estimate_normals)
        return sk_mesh_vertex_normals(mesh, opts->normals, normals, err);
    for (size_t v = 0; v < nv; ++v) {
        double *n = normals + 3 * v;
        memcpy(n, mesh->normals + 3 * v, 3 * sizeof(double));
        if (mesh->v_halfedge[v] != SK_INVALID &&
            (!isfinite(n[0] + n[1] + n[2]) || sk__normalize3(n) == 0.0))
            return sk__fail(err, SK_ERR_NUMERIC, "vertex %zu has a zero or non-finite normal", v);
    }
    return SK_OK;
}

/* The estimated normals at folded stars refitted (fold_normals.c), but not at the vertices of
 * the crease edges s->creases and their neighbours: a fold across a crease is the crease's, and
 * a crease vertex's sectors build on its neighbours' normals (the crease tangents, the targets);
 * refitting vertices 9 and 2882 of mech-holes-shark lost its crease line 2880-9-3534-918 and left
 * 6 singular patches instead of 4) */
static sk_status refit_folded_normals(sk_smooth *s, const sk_mesh *mesh, double *normals,
                                      sk_error *err)
{
    size_t nv = mesh->num_vertices;
    uint8_t *skip = sk__calloc_array(nv ? nv : 1, 1);
    if (!skip)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < 2 * s->num_creases; ++i) {
        uint32_t c = s->creases[i], h0 = mesh->v_halfedge[c], h = h0;
        skip[c] = 1;
        do {
            skip[sk_to(mesh, h)] = 1;
            h = sk_cw_out(mesh, h);
        } while (h != h0);
    }
    s->stats.folded_normals = sk__fold_normals(mesh, normals, skip, SK_FOLD_SEE_DEG);
    sk__free(skip);
    return SK_OK;
}

/* The second refit (fold_normals.c), on the triangulation after the edge flips: at the ends of
 * the lines of fold hinges (hinge_end, flags per vertex of the input; the first refit skipped
 * them) and their neighbours on no crease, with the wider limit SK_FOLD_HINGE_SEE_DEG. Such an
 * end has one normal for both faces of its hinge, which are more than 90 degrees apart (the cow's
 * 956 and 2384, ends of 956-43-2384, 160 degrees): the estimate sees one of them from behind
 * (956: 113 degrees), and that patch is singular. After the flips, since the flips judge faces
 * by the normals (measured on the cow: refitting 2384 before the flips gave 6 singular patches
 * where it gave none after). */
static sk_status refit_hinge_ends(sk_smooth *s, const sk_mesh *m, double *normals,
                                  const uint8_t *hinge_end, size_t nv_input, sk_error *err)
{
    size_t nv = m->num_vertices;
    uint8_t *skip = sk__malloc_array(nv ? nv : 1, 1), *on_crease = sk__calloc_array(nv ? nv : 1, 1);
    if (!skip || !on_crease) {
        sk__free(skip);
        sk__free(on_crease);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memset(skip, 1, nv);
    for (size_t i = 0; i < 2 * s->num_creases; ++i)
        on_crease[s->creases[i]] = 1;
    for (uint32_t v = 0; v < nv && v < nv_input; ++v) {
        uint32_t h0 = m->v_halfedge[v], h = h0;
        if (!hinge_end[v] || h0 == SK_INVALID)
            continue;
        skip[v] = 0;
        do {
            uint32_t w = sk_to(m, h);
            if (!on_crease[w])
                skip[w] = 0;
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
    s->stats.folded_normals += sk__fold_normals(m, normals, skip, SK_FOLD_HINGE_SEE_DEG);
    sk__free(skip);
    sk__free(on_crease);
    return SK_OK;
}

void sk__vc1_forget_build(sk_smooth *s, const sk_smooth_stats *saved)
{
    sk_mesh_destroy(&s->config);
    sk_patch_set_free(&s->surface);
    sk__free(s->deleted);
    sk__free(s->problems);
    sk__free(s->crease_edge);
    sk__free(s->corner_normals);
    s->deleted = s->problems = NULL;
    s->crease_edge = NULL;
    s->corner_normals = NULL;
    s->num_deleted = s->num_problems = 0;
    s->stats = *saved;
}

/* Faces from which the surface's points are touched beside the edge deletion */
#define VC1_PREFAULT_FACES 100000

/* The surface's patch set reserved for the build on base (at most one triangle of 15 points per
 * face: the deletion only merges faces) and its pages touched on a second thread while the edge
 * deletion, mostly serial, runs on this one (pf; sk__prefault_end before the set is used): the
 * patches' first touch was half the patch stage at 1M triangles. Only with more than one thread
 * allowed and from VC1_PREFAULT_FACES faces; nothing when the reserve fails (the patch stage
 * reserves and reports as before). */
static void prefault_surface(sk_smooth *s, const sk_mesh *base, sk__prefault *pf)
{
    size_t nf = base->num_faces, npts = 15 * nf;
    pf->running = false;
    int threads = 1;
#ifdef SK_HAVE_OPENMP
    threads = omp_get_max_threads();
#endif
    if (threads < 2 || nf < VC1_PREFAULT_FACES || s->surface.count != 0)
        return;
    sk_error e = {0};
    if (sk_patch_set_reserve(&s->surface, nf, npts, &e) != SK_OK)
        return;
    sk__prefault_begin(pf, s->surface.points, npts * 3 * sizeof(double));
}

/* passes of the flips chosen for the edge deletion, each followed by the deletion again */
#define VC1_DELETION_FLIP_PASSES 4
/* the flips are tried only while deleted / bound is above this: below, at most 1% is to gain and
 * the deletion again would cost the clean meshes (whose deletion meets the bound) time */
#define VC1_DELETION_FLIP_RATIO 1.01

/* x has fewer deleted edges and a lower deleted / bound than y (x.d / x.b < y.d / y.b) */
static bool deletion_better(const sk_edge_deletion_stats *x, const sk_edge_deletion_stats *y)
{
    return x->deleted_edges < y->deleted_edges &&
           (double)x->deleted_edges * (double)y->lower_bound <
               (double)y->deleted_edges * (double)x->lower_bound;
}

/* sk__deletion_flips on c->flippable, s->deleted, each pass followed by the edge deletion of the
 * flipped base, from nothing and warm-started from the deleted edges the flips left; a pass is
 * kept when the better of the two has fewer edges and a lower deleted / bound, else its flips are
 * undone and the passes end. s->config, s->deleted and s->stats.deletion are those of the last
 * kept pass; fl->n counts the kept flips, fl->saved is the base before the first. */
static sk_status deletion_flips(sk_smooth *s, const sk__build_ctx *c, const uint8_t *keep,
                                sk__deletion_flip_log *fl, sk_error *err)
{
    for (int pass = 0; pass < VC1_DELETION_FLIP_PASSES; ++pass) {
        sk_edge_deletion_stats old = s->stats.deletion;
        if (!((double)old.deleted_edges > VC1_DELETION_FLIP_RATIO * (double)old.lower_bound))
            return SK_OK;
        sk_status cst = fl->saved ? SK_OK : sk_mesh_copy(c->flippable, &fl->saved, err);
        if (cst != SK_OK)
            return cst;
        size_t flipped = 0, nhint = 0;
        uint32_t *flips = NULL, *hint = NULL, *deleted[2] = {NULL, NULL};
        sk_mesh *config[2] = {NULL, NULL};
        sk_edge_deletion_stats st2[2] = {{0}, {0}};
        sk_status st = sk__deletion_flips(c->flippable, s->normals, keep, s->deleted,
                                          old.deleted_edges, old.even_vertices, &flips,
                                          &flipped, &hint, &nhint, err);
        /* the deletion of the flipped base from nothing (0) and warm-started from the deleted
         * edges the flips left (1): neither is better on all of the shared meshes */
        for (int k = 0; k < 2 && st == SK_OK && flipped; ++k)
            st = sk__edge_deletion_hinted(c->base, keep, k ? hint : NULL, k ? nhint : 0, NULL,
                                          &config[k], &deleted[k], &st2[k], err);
        sk__free(hint);
        int best = deletion_better(&st2[1], &st2[0]) ? 1 : 0;
        bool gain = st == SK_OK && flipped && deletion_better(&st2[best], &old);
        if (st == SK_OK && gain) {
            fl->n += flipped;
            sk_mesh_destroy(&s->config);
            sk__free(s->deleted);
            s->config = config[best];
            s->deleted = deleted[best];
            s->stats.deletion = st2[best];
            config[best] = NULL;
            deleted[best] = NULL;
        } else {
            while (flipped > 0)
                sk__flip_edge(c->flippable, flips[--flipped]);
        }
        for (int k = 0; k < 2; ++k) {
            sk_mesh_destroy(&config[k]);
            sk__free(deleted[k]);
        }
        sk__free(flips);
        if (st != SK_OK || !gain)
            return st;
    }
    return SK_OK;
}

sk_status sk__vc1_build_creases(sk_smooth *s, const sk__build_ctx *c, uint8_t *keep,
                                const uint32_t *hint, size_t nhint, const uint8_t *avoid,
                                uint32_t **singular, double t0[2], sk_error *err)
{
    return sk__vc1_build_reusing(s, c, keep, hint, nhint, avoid, NULL, NULL, singular, t0, err);
}

sk_status sk__vc1_build_reusing(sk_smooth *s, const sk__build_ctx *c, uint8_t *keep,
                                const uint32_t *hint, size_t nhint, const uint8_t *avoid,
                                const sk__vc1_state *prev, sk__vc1_state **state,
                                uint32_t **singular, double t0[2], sk_error *err)
{
    sk_status st = SK_OK;
    sk_smooth_stats saved = s->stats;
    for (int round = 0;; ++round) {
        sk__prefault pf;
        prefault_surface(s, c->base, &pf);
        st = sk__edge_deletion_hinted(c->base, keep, hint, nhint, avoid, &s->config, &s->deleted,
                                      &s->stats.deletion, err);
        if (st == SK_OK && !hint && !avoid && c->flippable && c->deletion_flips &&
            !c->deletion_flips->off)
            st = deletion_flips(s, c, keep, c->deletion_flips, err);
        sk__prefault_end(&pf);
        if (st != SK_OK)
            return st;
        if (keep && (st = sk__crease_setup(s->config, s->normals, c->base, keep,
                                           c->file_normals ? c->mesh : NULL, &s->crease_edge,
                                           &s->corner_normals, err)) != SK_OK)
            return st;
        s->num_deleted = s->stats.deletion.deleted_edges;
        clock_since(t0, &s->stats.seconds_deletion, &s->stats.cpu_deletion);
        if (round == 0 &&
            (st = sk__progress(c->opts->progress, c->opts->progress_user, 0.3, err)) != SK_OK)
            return st;
        uint32_t failed_v = SK_INVALID;
        st = vc1_build(s, c->alpha, c->max_nu, c->opts->free_points,
                       c->opts->fit_mesh ? c->opts->fit_mesh : c->mesh, c->opts->fit_weight,
                       round == 0 ? prev : NULL, state, &failed_v, singular, err);
        if (st != SK_OK && st != SK_ERR_NUMERIC)
            return st;
        /* creases whose sectors cannot be built (a vertex system that fails or misses its angle
         * bounds at a crease vertex: on scans, mostly bands of sharp edges that are no feature
         * line) are dropped, whole lines, and the surface is built again without them */
        size_t dropped = 0;
        if (keep && round < SK_CREASE_ROUNDS) {
            if (st == SK_ERR_NUMERIC && failed_v != SK_INVALID)
                dropped += sk__crease_drop_at(c->base, keep, failed_v);
            for (size_t i = 0; st == SK_OK && i < s->num_problems; ++i)
                dropped += sk__crease_drop_at(c->base, keep, s->problems[i]);
        }
        if (dropped == 0)
            return st;
        sk__free(*singular);
        *singular = NULL;
        if (state)
            sk__vc1_state_free(state);
        sk__vc1_forget_build(s, &saved);
        clock_now(t0);
    }
}

/* The build (sk__vc1_build_creases), then the re-routed rounds where patches stay singular. With
 * flips chosen for the deletion (c->deletion_flips), a build left with singular patches after the
 * regularity repair, or with a failed vertex system, is done again without them (their flips
 * undone) before any re-routed round: they never cost a patch, and the rounds run as without
 * them. */
static sk_status build_rounds(sk_smooth *s, const sk__build_ctx *c_in, const uint32_t *hint,
                              size_t nhint, double t0[2], sk_error *err)
{
    sk_smooth_stats fresh = s->stats;
    sk__deletion_flip_log dflips = {0};
    sk__build_ctx cf = *c_in, *c = &cf;
    if (c->flippable && !hint && c->opts->deletion_flips)
        cf.deletion_flips = &dflips;
    sk__deletion_flip_log *fl = c->deletion_flips;
    uint32_t *singular = NULL;
    sk__vc1_state *state = NULL;
    bool rounds = c->opts->reroute_rounds >= 0;
    size_t ne = sk_num_edges(c->base);
    /* the crease flags as they were: the build drops crease lines it cannot build */
    uint8_t *keep0 = fl && c->keep ? sk__malloc_array(ne + 1, 1) : NULL;
    if (fl && c->keep && !keep0)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory building the VC1 surface");
    if (keep0)
        memcpy(keep0, c->keep, ne);
    sk_status st = sk__vc1_build_reusing(s, c, c->keep, hint, nhint, NULL, NULL,
                                         rounds ? &state : NULL, &singular, t0, err);
    sk__build_ctx c2 = *c;
    if (fl && fl->n && ((st == SK_OK && singular) || st == SK_ERR_NUMERIC)) {
        /* the base as it was (flipping back would change half-edge and face order, and so
         * the deletion's tie-breaks) */
        if (keep0)
            memcpy(c->keep, keep0, ne);
        sk__free(singular);
        singular = NULL;
        sk__vc1_state_free(&state);
        fl->n = 0;
        fl->off = true;
        c2.base = c2.flippable = fl->saved;
        sk__vc1_forget_build(s, &fresh);
        clock_now(t0);
        st = sk__vc1_build_reusing(s, &c2, c->keep, hint, nhint, NULL, NULL,
                                   rounds ? &state : NULL, &singular, t0, err);
    }
    sk__free(keep0);
    if (st == SK_OK)
        st = sk__vc1_reroute_singular(s, &c2, &fresh, &singular, &state, err);
    sk__vc1_state_free(&state);
    sk__free(singular);
    s->stats.deletion_flipped_edges = fl ? fl->n : 0;
    sk_mesh_destroy(&dflips.saved);
    return st;
}

sk_status sk_smooth_build(const sk_mesh *mesh, const sk_smooth_opts *opts_in, sk_smooth **out,
                          sk_error *err)
{
    return sk__smooth_build_hinted(mesh, opts_in, NULL, 0, out, err);
}

sk_status sk__smooth_build_hinted(const sk_mesh *mesh, const sk_smooth_opts *opts_in,
                                  const uint32_t *hint, size_t nhint, sk_smooth **out,
                                  sk_error *err)
{
    sk_smooth_opts opts = {0};
    if (opts_in)
        opts = *opts_in;
    if (!mesh || !out)
        return sk__fail(err, SK_ERR_ARG, "sk_smooth_build: NULL argument");
    *out = NULL;
    if (opts.scheme != SK_SMOOTH_VC1 && opts.scheme != SK_SMOOTH_PN)
        return sk__fail(err, SK_ERR_ARG, "unknown smooth scheme %d", (int)opts.scheme);
    double alpha = opts.alpha > 0.0 ? opts.alpha : 0.01;
    double max_nu = opts.max_nu > 0.0 ? opts.max_nu : opts.max_nu < 0.0 ? 0.0 : 16.0;
    sk_status st = SK_OK;
    sk_mesh *work = NULL;
    double *normals = NULL;
    uint8_t *keep = NULL; /* crease flags of the mesh being flipped / deleted */
    uint8_t *hinge_end = NULL; /* the ends of lines of fold hinges (detect_creases) */
    sk_smooth *s = sk__calloc_array(1, sizeof *s);
    if (!s)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    int blas_threads = sk__blas_serial_begin(); /* per-vertex and per-patch dense solves */
    s->scheme = opts.scheme;
    double t0[2];
    clock_now(t0);
    if ((st = check_input(mesh, err)) != SK_OK ||
        (st = input_normals(mesh, &opts, &normals, err)) != SK_OK)
        goto fail;
    clock_since(t0, &s->stats.seconds_normals, &s->stats.cpu_normals);
    bool file_normals = mesh->normals && !opts.estimate_normals;
    if (opts.crease_angle_deg >= 0.0 &&
        (st = detect_creases(s, mesh, opts.crease_angle_deg, file_normals, &hinge_end, err)))
        goto fail;
    if (opts.scheme == SK_SMOOTH_VC1 && !file_normals &&
        (st = refit_folded_normals(s, mesh, normals, err)) != SK_OK)
        goto fail;
    if ((st = sk__progress(opts.progress, opts.progress_user, 0.1, err)) != SK_OK)
        goto fail;

    if (opts.scheme == SK_SMOOTH_PN) {
        if ((st = sk_mesh_copy(mesh, &s->config, err)) != SK_OK ||
            (st = sk_mesh_compact(s->config, NULL, NULL, err)) != SK_OK)
            goto fail;
        s->normals = normals;
        normals = NULL;
        clock_now(t0);
        if ((st = sk__pn_build(s, err)) != SK_OK)
            goto fail;
        clock_since(t0, &s->stats.seconds_patches, &s->stats.cpu_patches);
        sk__free(hinge_end); /* the hinge refit is VC1's */
        *out = s;
        sk__ok(err);
        sk__blas_serial_end(blas_threads);
        return sk__progress(opts.progress, opts.progress_user, 1.0, err);
    }

    /* parity split */
    const sk_mesh *base = mesh;
    if (opts.allow_split) {
        double *n2 = NULL;
        if ((st = sk__split_odd_components(mesh, normals, &work, &n2, &s->stats.split_edges,
                                           err)) != SK_OK)
            goto fail;
        if (work) {
            sk__free(normals);
            normals = n2;
            base = work;
        }
    }
    /* a better triangulation of the same vertices (crease edges kept); not before a refinement of
     * the base, whose new vertices must lie on the input's facets (refine_base.c) */
    if (!opts.keep_triangulation && !opts.base_refinements) {
        clock_now(t0);
        if (!work && (st = sk_mesh_copy(mesh, &work, err)) != SK_OK)
            goto fail;
        if (s->num_creases && (st = crease_flags_of(s, work, &keep, err)) != SK_OK)
            goto fail;
        if ((st = sk__improve_triangulation_keep(work, normals, keep,
                                                 &s->stats.flipped_edges, err)) != SK_OK)
            goto fail;
        if (opts.parity_flips &&
            (st = sk__parity_flips(work, normals, keep, &s->stats.parity_flipped_edges, err)))
            goto fail;
        s->stats.flipped_edges += s->stats.parity_flipped_edges;
        base = work;
        clock_since(t0, &s->stats.seconds_flips, &s->stats.cpu_flips);
    }
    if (hinge_end && !file_normals &&
        (st = refit_hinge_ends(s, base, normals, hinge_end, mesh->num_vertices, err)) != SK_OK)
        goto fail;
    for (unsigned k = 0; k < opts.base_refinements; ++k) { /* refine_base.c */
        sk_mesh *r = NULL;
        double *n2 = NULL;
        uint32_t *c2 = NULL;
        size_t nc2 = 0, nsplit = 0;
        uint8_t *split = sk__malloc_array(sk_num_edges(base) + 1, 1);
        if (!split) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto fail;
        }
        st = sk__refine_base_flags(base, SK_REFINE_FOLD_DEG, split, &nsplit, err);
        if (st == SK_OK)
            st = sk__refine_base_split(base, normals, split, s->creases, s->num_creases, &r, &n2,
                                       &c2, &nc2, &nsplit, err);
        sk__free(split);
        if (st != SK_OK)
            goto fail;
        sk_mesh_destroy(&work);
        sk__free(normals);
        sk__free(s->creases);
        work = r;
        base = work;
        normals = n2;
        s->creases = c2;
        s->num_creases = nc2;
    }
    clock_now(t0);
    sk__free(keep);
    keep = NULL;
    if (s->num_creases && (st = crease_flags_of(s, base, &keep, err)) != SK_OK)
        goto fail;
    if (keep && work && !opts.keep_triangulation) {
        /* no one-face sector between two crease edges in a line (crease_g0.c); with the input's
         * triangulation kept, such a crease line is dropped below instead */
        s->stats.flipped_edges += sk__crease_split_sectors(work, keep);
    }
    if (keep)
        sk__crease_validate(base, keep);
    s->normals = normals;
    normals = NULL;
    /* the re-routed rounds may flip slivers of the refined base too (reroute.c) */
    sk__build_ctx ctx = {.mesh = mesh, .base = base,
                         .flippable = opts.keep_triangulation ? NULL : work,
                         .keep = keep,
                         .file_normals = file_normals, .alpha = alpha, .max_nu = max_nu,
                         .opts = &opts};
    if ((st = build_rounds(s, &ctx, hint, nhint, t0, err)) != SK_OK)
        goto fail;
    sk__free(keep);
    sk__free(hinge_end);
    sk_mesh_destroy(&work);
    *out = s;
    sk__ok(err);
    sk__blas_serial_end(blas_threads);
    return sk__progress(opts.progress, opts.progress_user, 1.0, err);
fail:
    sk_mesh_destroy(&work);
    sk__free(keep);
    sk__free(hinge_end);
    sk__free(normals);
    sk_smooth_destroy(&s);
    sk__blas_serial_end(blas_threads);
    return st;
}
