/* Cuts of the progressive mesh in the input's numbering (tolerance_internal.h).
 *
 * Every surface is built over a "cut" of the hierarchy: the coarsest mesh with a set of the
 * vertex splits applied, in the order the hierarchy applies them (levels upwards, within a level
 * in reverse record order). A vertex is "alive" when its split is applied; a split needs its w0,
 * first and last alive, so wanting a vertex wants those first (the dependency closure). Level j
 * is the cut of every vertex born at level j or below.
 *
 * A closed component needs an even vertex count for the edge deletion; a cut with an odd count
 * gets one more split there (one whose dependencies are alive). */
#include "fit/tolerance_internal.h"
#include "analysis/bvh_internal.h"
#include "core/internal.h"

#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Hierarchy in fine numbering
 * ------------------------------------------------------------------------------------------- */

sk_status sk__tol_index_hierarchy(tol_ctx *c, sk_error *err)
{
    size_t L = c->levels, nv = c->nv;
    sk_status st = SK_OK;
    uint32_t *cur = sk__malloc_array(nv, sizeof *cur), *prev = sk__malloc_array(nv, sizeof *prev);
    size_t *off = sk__calloc_array(L + 1, sizeof *off);
    c->birth = sk__calloc_array(nv, sizeof *c->birth);
    c->rec = sk__calloc_array(nv, sizeof *c->rec);
    c->order = sk__malloc_array(nv + 1, sizeof *c->order);
    if (!cur || !prev || !off || !c->birth || !c->rec || !c->order) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t j = 0; j + 1 < L; ++j) {
        size_t ns = 0;
        sk_hierarchy_splits(c->hier, j, &ns);
        off[j + 1] = off[j] + ns;
    }
    c->num_order = off[L > 0 ? L - 1 : 0];
    for (size_t v = 0; v < nv; ++v)
        cur[v] = (uint32_t)v;
    for (size_t j = L - 1; j-- > 0;) {
        /* cur: level j + 1 -> fine; prev becomes level j -> fine */
        size_t nfine = sk_hierarchy_level_info(c->hier, j + 1).vertices, ns = 0;
        const uint32_t *map = sk_hierarchy_vertex_map(c->hier, j);
        for (size_t u = 0; u < nfine; ++u)
            if (map[u] != SK_INVALID)
                prev[map[u]] = cur[u];
        const sk_vertex_split *sp = sk_hierarchy_splits(c->hier, j, &ns);
        for (size_t k = 0; k < ns; ++k) {
            uint32_t v = cur[sp[k].v];
            sk_vertex_split r = sp[k];
            r.v = v;
            r.w0 = prev[r.w0];
            r.first = prev[r.first];
            r.last = prev[r.last];
            for (int q = 0; q < 3; ++q)
                r.parent[q] = prev[r.parent[q]];
            c->rec[v] = r;
            c->birth[v] = (uint32_t)(j + 1);
            c->order[off[j] + (ns - 1 - k)] = v; /* reverse record order, as sk_hierarchy_split */
        }
        uint32_t *t = cur;
        cur = prev;
        prev = t;
    }
    /* cur: level 0 -> fine */
    size_t nc = sk_hierarchy_coarsest(c->hier)->num_vertices;
    c->coarse_fine = sk__malloc_array(nc ? nc : 1, sizeof *c->coarse_fine);
    if (!c->coarse_fine) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    memcpy(c->coarse_fine, cur, nc * sizeof *cur);
done:
    sk__free(cur);
    sk__free(prev);
    sk__free(off);
    return st;
}

/* Components (per vertex), whether each is closed, and the one-rings of the fine mesh. */
sk_status sk__tol_index_mesh(tol_ctx *c, sk_error *err)
{
    const sk_mesh *m = c->fine;
    size_t nv = c->nv, nh = m->num_halfedges;
    c->comp = sk__malloc_array(nv, sizeof *c->comp);
    c->ring_off = sk__calloc_array(nv + 1, sizeof *c->ring_off);
    c->ring = sk__malloc_array(nh ? nh : 1, sizeof *c->ring);
    uint32_t *stack = sk__malloc_array(nv ? nv : 1, sizeof *stack);
    sk_status st = SK_OK;
    if (!c->comp || !c->ring_off || !c->ring || !stack) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t h = 0; h < nh; ++h)
        c->ring_off[m->h_vertex[h ^ 1u] + 1]++;
    for (size_t v = 0; v < nv; ++v)
        c->ring_off[v + 1] += c->ring_off[v];
    for (size_t v = 0; v < nv; ++v) {
        uint32_t h0 = m->v_halfedge[v], h = h0;
        size_t k = c->ring_off[v];
        if (h0 != SK_INVALID)
            do {
                c->ring[k++] = m->h_vertex[h];
                h = sk_cw_out(m, h);
            } while (h != h0 && k < c->ring_off[v + 1]);
    }
    for (size_t v = 0; v < nv; ++v)
        c->comp[v] = SK_INVALID;
    size_t nc = 0;
    for (size_t s = 0; s < nv; ++s) {
        if (c->comp[s] != SK_INVALID)
            continue;
        size_t top = 0;
        stack[top++] = (uint32_t)s;
        c->comp[s] = (uint32_t)nc;
        while (top) {
            uint32_t v = stack[--top];
            for (uint32_t k = c->ring_off[v]; k < c->ring_off[v + 1]; ++k)
                if (c->comp[c->ring[k]] == SK_INVALID) {
                    c->comp[c->ring[k]] = (uint32_t)nc;
                    stack[top++] = c->ring[k];
                }
        }
        ++nc;
    }
    c->num_comps = nc;
    c->comp_closed = sk__malloc_array(nc ? nc : 1, 1);
    c->comp_count = sk__malloc_array(nc ? nc : 1, sizeof *c->comp_count);
    if (!c->comp_closed || !c->comp_count) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    memset(c->comp_closed, 1, nc);
    for (size_t h = 0; h < nh; ++h)
        if (m->h_face[h] == SK_INVALID)
            c->comp_closed[c->comp[m->h_vertex[h]]] = 0;
    for (size_t v = 0; v < nv; ++v)
        if (m->v_halfedge[v] == SK_INVALID)
            c->comp_closed[c->comp[v]] = 0; /* an isolated vertex: no surface to build */
done:
    sk__free(stack);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * Cuts
 * ------------------------------------------------------------------------------------------- */

/* One step of refinement towards v: makes alive the splits on v's dependency chain (v, its w0,
 * first and last, theirs, ...) whose own dependencies are all alive already, i.e. the coarsest
 * missing collapses around v. stamp/stamp_value mark the vertices visited in this round.
 * Returns the number of vertices made alive. */
size_t sk__tol_want_step(const tol_ctx *c, uint8_t *alive, uint32_t v, uint32_t *stack,
                        uint32_t *stamp, uint32_t stamp_value)
{
    size_t top = 0, added = 0;
    if (alive[v] || stamp[v] == stamp_value)
        return 0;
    stamp[v] = stamp_value;
    stack[top++] = v;
    while (top) {
        uint32_t x = stack[--top];
        const sk_vertex_split *r = &c->rec[x];
        uint32_t dep[3] = {r->w0, r->first, r->last};
        bool ready = true;
        for (int q = 0; q < 3; ++q)
            if (alive[dep[q]] != 1) {
                ready = false;
                if (!alive[dep[q]] && stamp[dep[q]] != stamp_value) {
                    stamp[dep[q]] = stamp_value;
                    stack[top++] = dep[q];
                }
            }
        if (ready) {
            alive[x] = 2; /* alive from the next build on (not a dependency in this round) */
            ++added;
        }
    }
    return added;
}

/* Closed components with an odd number of alive vertices get one more: the first vertex in
 * application order whose split is ready. Returns the number added. */
size_t sk__tol_fix_parity(const tol_ctx *c, uint8_t *alive)
{
    size_t *cnt = c->comp_count, added = 0;
    memset(cnt, 0, c->num_comps * sizeof *cnt);
    for (size_t v = 0; v < c->nv; ++v)
        cnt[c->comp[v]] += alive[v];
    for (size_t k = 0; k < c->num_order; ++k) {
        uint32_t v = c->order[k], q = c->comp[v];
        if (alive[v] || !c->comp_closed[q] || cnt[q] % 2 == 0)
            continue;
        const sk_vertex_split *r = &c->rec[v];
        if (alive[r->w0] && alive[r->first] && alive[r->last]) {
            alive[v] = 1;
            cnt[q]++;
            ++added;
        }
    }
    return added;
}

/* The mesh of the cut: the coarsest mesh with the splits of the alive vertices. Vertices whose
 * split does not fit (not expected) are cleared from alive. m2f (room for every fine vertex)
 * gets mixed -> fine. */
sk_status sk__tol_build_cut(tol_ctx *c, uint8_t *alive, sk_mesh **out, uint32_t *m2f,
                           sk_error *err)
{
    const sk_mesh *co = sk_hierarchy_coarsest(c->hier);
    sk_mesh *m = NULL;
    sk_status st = sk_mesh_copy(co, &m, err);
    if (st)
        return st;
    sk__free(m->normals);
    sk__free(m->uvs);
    m->normals = NULL;
    m->uvs = NULL;
    sk_mesh_set_wedge_uvs(m, 0, NULL, NULL, NULL);
    size_t na = 0;
    for (size_t v = 0; v < c->nv; ++v)
        na += alive[v];
    size_t ns = na - co->num_vertices;
    if ((st = sk_mesh_reserve(m, na, m->num_halfedges + 6 * ns, m->num_faces + 2 * ns, err)))
        goto fail;
    for (size_t v = 0; v < c->nv; ++v)
        c->f2m[v] = SK_INVALID;
    for (size_t k = 0; k < co->num_vertices; ++k) {
        c->f2m[c->coarse_fine[k]] = (uint32_t)k;
        m2f[k] = c->coarse_fine[k];
    }
    for (size_t k = 0; k < c->num_order; ++k) {
        uint32_t v = c->order[k];
        if (!alive[v])
            continue;
        sk_vertex_split s = c->rec[v];
        s.w0 = c->f2m[s.w0];
        s.first = c->f2m[s.first];
        s.last = c->f2m[s.last];
        uint32_t id = SK_INVALID;
        if (s.w0 != SK_INVALID && s.first != SK_INVALID && s.last != SK_INVALID) {
            s.parent[0] = s.parent[1] = s.parent[2] = s.w0; /* no attributes to carry */
            id = sk__vertex_split(m, &s);
        }
        if (id == SK_INVALID) {
            alive[v] = 0;
            continue;
        }
        c->f2m[v] = id;
        m2f[id] = v;
    }
    if ((st = sk_mesh_add_normals(m, err)))
        goto fail;
    for (size_t k = 0; k < m->num_vertices; ++k)
        memcpy(m->normals + 3 * k, c->normals + 3 * (size_t)m2f[k], 3 * sizeof(double));
    *out = m;
    return SK_OK;
fail:
    sk_mesh_destroy(&m);
    return st;
}

void sk__tol_ctx_free(tol_ctx *c)
{
    sk__free(c->normals);
    sk_hierarchy_destroy(&c->hier);
    sk__free(c->birth);
    sk__free(c->rec);
    sk__free(c->order);
    sk__free(c->coarse_fine);
    sk__free(c->comp);
    sk__free(c->comp_closed);
    sk__free(c->ring_off);
    sk__free(c->ring);
    sk__free(c->f2m);
    sk__free(c->comp_count);
    sk_bvh_destroy(&c->mesh_bvh);
    sk__free((void *)c->tri);
}

/* alive := every vertex born at level <= j */
void sk__tol_level_cut(const tol_ctx *c, size_t j, uint8_t *alive)
{
    for (size_t v = 0; v < c->nv; ++v)
        alive[v] = c->birth[v] <= j;
}

