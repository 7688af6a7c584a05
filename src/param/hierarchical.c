/* Hierarchical parametrization (Hormann, Greiner, Campagna, section 4) and the conventional flat
 * MIPS optimization it is measured against (Table 1). */
#include "surfkit/hierarchical.h"
#include "core/internal.h"
#include "core/vec.h"
#include "param/mips_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


/* True when every triangle around v is counter-clockwise with the MIPS margin at v. */
static bool ring_ok(const sk_mesh *m, const double *uv, uint32_t v, const double x[2])
{
    uint32_t h0 = m->v_halfedge[v], h = h0;
    if (h0 == SK_INVALID)
        return true;
    do {
        if (m->h_face[h] != SK_INVALID) {
            uint32_t a = m->h_vertex[h], b = m->h_vertex[m->h_next[h]];
            if (!sk__mips_corner_ok(x, uv + 2 * (size_t)a, uv + 2 * (size_t)b))
                return false;
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    return true;
}

/* Moves v to the centroid of the kernel of its one ring: the convex polygon where every triangle
 * (v, a, b) around v is counter-clockwise, i.e. the intersection of the half-planes left of each
 * opposite edge a -> b, found by clipping a large box (Sutherland-Hodgman). Returns false when the
 * kernel is empty (or too thin for the margin). */
static bool move_into_kernel(const sk_mesh *m, double *uv, uint32_t v)
{
    enum { CAP = 256 };
    double poly[2][CAP][2];
    int n = 0, cur = 0;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        const double *q = uv + 2 * (size_t)m->h_vertex[h];
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], q[k]);
            hi[k] = fmax(hi[k], q[k]);
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    double pad = (hi[0] - lo[0]) + (hi[1] - lo[1]) + 1e-300;
    double box[4][2] = {{lo[0] - pad, lo[1] - pad}, {hi[0] + pad, lo[1] - pad},
                        {hi[0] + pad, hi[1] + pad}, {lo[0] - pad, hi[1] + pad}};
    for (n = 0; n < 4; ++n)
        memcpy(poly[0][n], box[n], sizeof box[n]);
    h = h0;
    do {
        if (m->h_face[h] != SK_INVALID) {
            const double *a = uv + 2 * (size_t)m->h_vertex[h];
            const double *b = uv + 2 * (size_t)m->h_vertex[m->h_next[h]];
            double e[2] = {b[0] - a[0], b[1] - a[1]};
            int nn = 0;
            for (int i = 0; i < n && nn < CAP - 1; ++i) {
                const double *p = poly[cur][i], *q = poly[cur][(i + 1) % n];
                double sp = e[0] * (p[1] - a[1]) - e[1] * (p[0] - a[0]);
                double sq = e[0] * (q[1] - a[1]) - e[1] * (q[0] - a[0]);
                if (sp > 0)
                    memcpy(poly[1 - cur][nn++], p, 2 * sizeof(double));
                if ((sp > 0) != (sq > 0) && sp != sq) {
                    double t = sp / (sp - sq);
                    poly[1 - cur][nn][0] = p[0] + t * (q[0] - p[0]);
                    poly[1 - cur][nn][1] = p[1] + t * (q[1] - p[1]);
                    nn++;
                }
            }
            n = nn;
            cur = 1 - cur;
            if (n < 3)
                return false;
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    double area = 0.0, c[2] = {0.0, 0.0};
    for (int i = 0; i < n; ++i) {
        const double *p = poly[cur][i], *q = poly[cur][(i + 1) % n];
        double w = p[0] * q[1] - q[0] * p[1];
        area += w;
        c[0] += (p[0] + q[0]) * w;
        c[1] += (p[1] + q[1]) * w;
    }
    if (!(area > 0.0))
        return false;
    c[0] /= 3.0 * area;
    c[1] /= 3.0 * area;
    if (!ring_ok(m, uv, v, c))
        return false;
    memcpy(uv + 2 * (size_t)v, c, sizeof c);
    return true;
}

/* Makes every triangle flip-free by moving the vertices of inverted triangles into the kernels of
 * their one rings, a few rounds; returns the number of moves, or -1 when some remain inverted. */
static long repair(const sk_mesh *m, double *uv)
{
    long moved = 0;
    for (int round = 0; round < 8; ++round) {
        size_t bad = 0;
        /* a scan over the faces (sequential memory); only the vertices of a face that fails the
         * margin somewhere get the one-ring test and, if needed, the move */
        for (uint32_t f = 0; f < m->num_faces; ++f) {
            if (m->f_deleted[f])
                continue;
            uint32_t h = m->f_halfedge[f], hb = m->h_next[h], hc = m->h_next[hb];
            uint32_t w[3] = {sk_from(m, h), sk_from(m, hb), sk_from(m, hc)};
            const double *q[3] = {uv + 2 * (size_t)w[0], uv + 2 * (size_t)w[1], uv + 2 * (size_t)w[2]};
            if (sk__mips_corner_ok(q[0], q[1], q[2]) && sk__mips_corner_ok(q[1], q[2], q[0]) &&
                sk__mips_corner_ok(q[2], q[0], q[1]))
                continue;
            for (int k = 0; k < 3; ++k) {
                if (ring_ok(m, uv, w[k], uv + 2 * (size_t)w[k]))
                    continue;
                bad++;
                moved += move_into_kernel(m, uv, w[k]);
            }
        }
        if (!bad)
            return moved;
    }
    return -1;
}

static sk_status linear_start(const sk_mesh *m, sk_mips_boundary boundary, const double *given,
                              double *uv, sk_error *err)
{
    sk_param_opts po = {0};
    po.method = SK_PARAM_FLOATER;
    if (given) { /* fixed boundary from the finest level */
        po.boundary.shape = SK_BOUNDARY_GIVEN;
        memcpy(uv, given, 2 * m->num_vertices * sizeof(double));
    } else {
        po.boundary.shape = boundary == SK_MIPS_BOUNDARY_SQUARE ? SK_BOUNDARY_SQUARE
                                                                : SK_BOUNDARY_CIRCLE;
    }
    return sk_param_linear(m, &po, uv, NULL, err);
}

sk_status sk_param_mips_flat(const sk_mesh *mesh, sk_mips_boundary boundary, size_t max_steps,
                             double tolerance, uint64_t seed, double *uv, sk_mips_stats *stats,
                             sk_error *err)
{
    sk_status st = linear_start(mesh, boundary, NULL, uv, err);
    if (st)
        return st;
    sk_mips_opts mo = {0};
    mo.fixed_boundary = boundary != SK_MIPS_BOUNDARY_FREE;
    mo.max_steps = max_steps;
    mo.max_sweeps = max_steps ? (size_t)-1 : 0; /* a budget, or the default sweeps */
    mo.tolerance = tolerance;
    mo.seed = seed;
    return sk_param_mips(mesh, &mo, uv, stats, err);
}

sk_status sk_param_hierarchical(const sk_mesh *mesh, const sk_hparam_opts *opts, double *uv,
                                sk_hparam_stats *stats, sk_error *err)
{
    sk_hparam_opts o = {0};
    if (opts)
        o = *opts;
    size_t sweeps_cap = o.sweeps_per_level ? o.sweeps_per_level : 400;

    double tol = o.tolerance == 0.0 ? 1e-5 : o.tolerance;
    bool fixed = o.boundary != SK_MIPS_BOUNDARY_FREE;
    size_t gsteps = o.global_steps == (size_t)-1 ? 0 : o.global_steps ? o.global_steps : 3;
    size_t gmax = o.global_max_vertices ? o.global_max_vertices : 25000;
    double work = o.level_work > 0.0 ? o.level_work : gsteps ? 2.0 : 5.0;
    size_t gsweeps = o.sweeps_per_global ? o.sweeps_per_global : 2;
    double growth = o.min_growth > 0.0 ? o.min_growth : 2.0;
    size_t last_opt = 0;
    double t0 = sk_seconds();
    sk_hparam_stats s;
    memset(&s, 0, sizeof s);
    sk_status st = sk_param_check_disk(mesh, err);
    if (st)
        return st;

    sk_hierarchy *hier = NULL;
    sk_mesh *m = NULL;
    double *cur = NULL, *next = NULL, *fixed_uv = NULL, *level_fixed = NULL;
    uint32_t **finest_id = NULL;
    sk_hierarchy_opts ho = o.hierarchy;
    ho.seed = o.seed;
    if ((st = sk_hierarchy_build(mesh, &ho, &hier, err)))
        goto done;
    s.hierarchy_seconds = sk_seconds() - t0;
    size_t L = sk_hierarchy_num_levels(hier);
    if (L > SK_HPARAM_MAX_LEVELS) {
        st = sk__fail(err, SK_ERR_ARG, "%zu hierarchy levels (at most %d)", L, SK_HPARAM_MAX_LEVELS);
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
    if (fixed) {
        /* the boundary of every level is fixed where the finest boundary map puts it */
        fixed_uv = sk__calloc_array(2 * nfine, sizeof(double));
        level_fixed = sk__malloc_array(2 * nfine, sizeof(double));
        finest_id = sk__calloc_array(L, sizeof *finest_id);
        if (!fixed_uv || !level_fixed || !finest_id) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto done;
        }
        sk_boundary_opts bo = {0};
        bo.shape = o.boundary == SK_MIPS_BOUNDARY_SQUARE ? SK_BOUNDARY_SQUARE : SK_BOUNDARY_CIRCLE;
        if ((st = sk_param_boundary(mesh, &bo, fixed_uv, err)))
            goto done;
        for (size_t l = L; l-- > 0;) {
            size_t nv = sk_hierarchy_level_info(hier, l).vertices;
            finest_id[l] = sk__malloc_array(nv ? nv : 1, sizeof(uint32_t));
            if (!finest_id[l]) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                goto done;
            }
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
    }

    if ((st = sk_mesh_copy(sk_hierarchy_coarsest(hier), &m, err)))
        goto done;
    for (size_t l = 0; l < L; ++l) {
        double tl = sk_seconds();
        sk_hparam_level *lv = &s.levels[l];
        if (l > 0) {
            /* section 3: insert the new vertices at rho p0 + sigma pi + tau pi+1 */
            if ((st = sk_hierarchy_prolong(hier, l - 1, cur, 2, next, err)) ||
                (st = sk_hierarchy_split(hier, l - 1, m, err)))
                goto done;
            double *t = cur;
            cur = next;
            next = t;
        }
        size_t nv = m->num_vertices;
        if (fixed)
            for (size_t v = 0; v < nv; ++v)
                memcpy(level_fixed + 2 * v, fixed_uv + 2 * (size_t)finest_id[l][v], 2 * sizeof(double));
        if (l == 0) {
            if ((st = linear_start(m, o.boundary, fixed ? level_fixed : NULL, cur, err)))
                goto done;
        } else {
            if (fixed)
                for (size_t v = 0; v < nv; ++v)
                    if (sk_is_boundary_v(m, (uint32_t)v))
                        memcpy(cur + 2 * v, level_fixed + 2 * v, 2 * sizeof(double));
            long moved = repair(m, cur);
            if (moved < 0) {
                /* no kernel to move into: restart this level from a linear map (never silent) */
                s.fallbacks++;
                if ((st = linear_start(m, o.boundary, fixed ? level_fixed : NULL, cur, err)))
                    goto done;
                moved = 0;
            }
            lv->repaired = (size_t)moved;
            s.repaired += (size_t)moved;
        }
        sk_mips_opts mo = {0};
        mo.fixed_boundary = fixed;
        double want = ceil(work * (double)nfine / (double)(nv ? nv : 1));
        mo.max_sweeps = want < (double)sweeps_cap ? (size_t)want : sweeps_cap;
        if (l + 1 == L && o.finest_sweeps)
            mo.max_sweeps = o.finest_sweeps;
        mo.tolerance = tol;
        mo.seed = o.seed + l;
        if (gsteps && nv <= gmax) {
            mo.global_steps = gsteps;
            mo.sweeps_per_global = gsweeps;
            mo.frozen_model = true;
            if (mo.max_sweeps < gsteps * gsweeps)
                mo.max_sweeps = gsteps * gsweeps;
        }
        sk_mips_stats ms = {0};
        bool skip = l + 1 < L && nv > gmax && last_opt && (double)nv < growth * (double)last_opt;
        /* with a step budget the coarser levels together use at most half of it, so that the
         * input level is always optimized however small the budget */
        size_t limit = o.max_steps && l + 1 < L ? o.max_steps / 2 : o.max_steps;
        if (skip) { /* insertion and repair only: optimized with the next levels */
            ms.energy = NAN;
        } else if (limit && s.steps >= limit) { /* budget spent: only measure */
            size_t inv = 0;
            if ((st = sk_mips_energy(m, cur, &ms.energy, &inv, err)))
                goto done;
        } else {
            mo.max_steps = limit ? limit - s.steps : 0;
            if ((st = sk_param_mips(m, &mo, cur, &ms, err)))
                goto done;
        }
        if (!skip)
            last_opt = nv;
        lv->vertices = nv;
        lv->faces = m->num_faces;
        lv->steps = ms.steps;
        lv->sweeps = ms.sweeps;
        lv->energy = ms.energy;
        lv->global_steps = ms.global_steps;
        lv->global_seconds = ms.global_seconds;
        s.steps += ms.steps;
        lv->seconds = sk_seconds() - tl;
        if ((st = sk__progress(o.progress, o.progress_user, (double)(l + 1) / (double)L, err)))
            goto done;
    }
    memcpy(uv, cur, 2 * nfine * sizeof(double));
    s.energy = s.levels[L - 1].energy;
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
    sk_mesh_destroy(&m);
    sk_hierarchy_destroy(&hier);
    if (stats)
        *stats = s;
    return st;
}
