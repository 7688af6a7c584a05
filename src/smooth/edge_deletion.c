/* Edge deletion (Cottin & van Damme, section 3): delete interior edges of a triangle mesh so that
 * every interior vertex is surrounded by an odd number of faces, and every face is a triangle or a
 * quad.
 *
 * Algorithm Initialise: multi-source breadth-first search from the unpaired even vertices; every
 * edge where two searches meet (or a boundary vertex one search reaches: boundary vertices may stay
 * even, so they absorb a path) is a candidate pair, of length dist(u) + dist(v) + 1; candidates are
 * taken shortest first while both ends are unpaired ("grow distances until pairs meet"). Rounds
 * repeat with the vertices still unpaired.
 *
 * Algorithm Reduce Path: (1) cut loops at repeated vertices, (2) replace two consecutive edges of
 * one triangle by its third edge (Fig. 3).
 *
 * Algorithm Delete Even Edges, step 2, in the equivalent edge-set form: deleting the union of all
 * paths changes the parity of the face count exactly at the path ends, and so does the symmetric
 * difference of the paths. Case (2a) (paths sharing edges): shared edges cancel (the paper re-routes
 * the two paths so that the common part is used by neither). Case (2b) (an edge of path I and an
 * edge of path J in one triangle at the intersection point): the two edges are replaced by the third
 * edge of their triangle, which is what the paper's re-definition followed by Reduce Path does.
 * Both steps keep the parity of every vertex and strictly shrink the deleted set, so the loop ends;
 * at the end no triangle holds two deleted edges, so every face is a triangle or a quad. */
#include "surfkit/smooth.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct path_store {
    uint32_t *v;     /* vertices of all paths */
    uint32_t *start; /* path i: v[start[i] .. start[i + 1]) */
    size_t nv, cap_v, np, cap_p;
} path_store;

static int ps_push_vertex(path_store *ps, uint32_t v)
{
    if (ps->nv == ps->cap_v) {
        size_t cap = ps->cap_v ? 2 * ps->cap_v : 1024;
        uint32_t *p = sk__realloc_array(ps->v, cap, sizeof *p);
        if (!p)
            return 0;
        ps->v = p;
        ps->cap_v = cap;
    }
    ps->v[ps->nv++] = v;
    return 1;
}

static int ps_close_path(path_store *ps)
{
    if (ps->np + 2 > ps->cap_p) {
        size_t cap = ps->cap_p ? 2 * ps->cap_p : 256;
        uint32_t *p = sk__realloc_array(ps->start, cap, sizeof *p);
        if (!p)
            return 0;
        if (ps->cap_p == 0)
            p[0] = 0;
        ps->start = p;
        ps->cap_p = cap;
    }
    ps->start[++ps->np] = (uint32_t)ps->nv;
    return 1;
}

/* Half-edge from a to b, or SK_INVALID. */
static uint32_t find_halfedge(const sk_mesh *m, uint32_t a, uint32_t b)
{
    uint32_t h0 = m->v_halfedge[a], h = h0;
    if (h0 == SK_INVALID)
        return SK_INVALID;
    do {
        if (sk_to(m, h) == b)
            return h;
        h = sk_cw_out(m, h);
    } while (h != h0);
    return SK_INVALID;
}

/* True when a, b, c are the corners of one (triangle) face. */
static bool is_face(const sk_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t h = find_halfedge(m, a, b);
    if (h == SK_INVALID)
        return false;
    if (m->h_face[h] != SK_INVALID && sk_to(m, m->h_next[h]) == c)
        return true;
    uint32_t o = sk_opp(h);
    return m->h_face[o] != SK_INVALID && sk_to(m, m->h_next[o]) == c;
}

/* Reduce Path on the vertex list p[0..n): returns the new length. */
static size_t reduce_path(const sk_mesh *m, const uint8_t *forbid, uint32_t *p, size_t n,
                          size_t *reductions)
{
    /* (1) loops: keep the first occurrence, drop everything up to the last occurrence */
    size_t k = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t v = p[i];
        size_t j;
        for (j = 0; j < k; ++j) /* paths are short; a linear scan beats a hash */
            if (p[j] == v)
                break;
        if (j < k) {
            k = j + 1; /* cut the loop p[j] .. p[i] */
            ++*reductions;
            continue;
        }
        p[k++] = v;
    }
    n = k;
    /* (2) two consecutive edges of one triangle -> its third edge */
    k = 0;
    for (size_t i = 0; i < n; ++i) {
        p[k++] = p[i];
        while (k >= 3 && is_face(m, p[k - 3], p[k - 2], p[k - 1])) {
            uint32_t h = find_halfedge(m, p[k - 3], p[k - 1]);
            if (h == SK_INVALID || sk_is_boundary_e(m, sk_edge(h)) || forbid[sk_edge(h)])
                break;
            p[k - 2] = p[k - 1];
            --k;
            ++*reductions;
        }
    }
    return k;
}

/* Quads with a corner angle near pi make the vertex systems hard (the angle bound of section 4)
 * and the patches nearly singular; an edge whose deletion would make a quad corner larger than
 * this (sum of the two triangle angles at an end point) is avoided by the paths, except where an
 * even vertex has no other choice. */
#define SK_MAX_QUAD_CORNER_DEG 160.0

static double corner_angle(const sk_mesh *m, uint32_t h)
{
    /* angle at from(h) in face(h): between h and the reverse of prev(h) */
    const double *v = m->positions + 3 * (size_t)sk_from(m, h);
    const double *a = m->positions + 3 * (size_t)sk_to(m, h);
    const double *b = m->positions + 3 * (size_t)sk_from(m, m->h_prev[h]);
    double x[3], y[3], c[3];
    for (int k = 0; k < 3; ++k) {
        x[k] = a[k] - v[k];
        y[k] = b[k] - v[k];
    }
    c[0] = x[1] * y[2] - x[2] * y[1];
    c[1] = x[2] * y[0] - x[0] * y[2];
    c[2] = x[0] * y[1] - x[1] * y[0];
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 x[0] * y[0] + x[1] * y[1] + x[2] * y[2]);
}

/* largest quad corner (degrees) created by deleting interior edge e */
static double deletion_corner(const sk_mesh *m, uint32_t e)
{
    uint32_t h = 2 * e, o = h + 1;
    double at_a = corner_angle(m, h) + corner_angle(m, m->h_next[o]);
    double at_b = corner_angle(m, o) + corner_angle(m, m->h_next[h]);
    return fmax(at_a, at_b) * (180.0 / 3.14159265358979323846);
}

typedef struct cand {
    uint32_t len;
    uint32_t u, v; /* meeting edge (u, v), or v == SK_INVALID: u is a boundary vertex */
} cand;

static int cand_cmp(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    if (x->len != y->len)
        return x->len < y->len ? -1 : 1;
    if (x->u != y->u)
        return x->u < y->u ? -1 : 1;
    return (x->v > y->v) - (x->v < y->v);
}

static void merge_across_edge(sk_mesh *m, uint32_t e)
{
    uint32_t h = 2 * e, o = 2 * e + 1;
    uint32_t fh = m->h_face[h], fo = m->h_face[o];
    uint32_t hp = m->h_prev[h], hn = m->h_next[h], op = m->h_prev[o], on = m->h_next[o];
    m->h_next[hp] = on;
    m->h_prev[on] = hp;
    m->h_next[op] = hn;
    m->h_prev[hn] = op;
    uint32_t g = on;
    while (g != hn) {
        m->h_face[g] = fh;
        g = m->h_next[g];
    }
    m->f_halfedge[fh] = hn;
    uint32_t a = sk_from(m, h), b = sk_to(m, h);
    if (m->v_halfedge[a] == h)
        m->v_halfedge[a] = on;
    if (m->v_halfedge[b] == o)
        m->v_halfedge[b] = hn;
    m->e_deleted[e] = 1;
    m->f_deleted[fo] = 1;
    m->num_deleted_edges++;
    m->num_deleted_faces++;
}

sk_status sk_edge_deletion(const sk_mesh *m, sk_mesh **out, uint32_t **deleted_out,
                           sk_edge_deletion_stats *stats, sk_error *err)
{
    sk_edge_deletion_stats st0;
    memset(&st0, 0, sizeof st0);
    sk_status st = SK_OK;
    size_t nv = m->num_vertices, ne = sk_num_edges(m), nf = m->num_faces;
    uint8_t *even = NULL, *bnd = NULL, *dcnt = NULL, *forbid = NULL;
    uint32_t *comp = NULL, *queue = NULL, *dist = NULL, *src = NULL, *pred = NULL, *partner = NULL;
    uint32_t *remaining = NULL, *fq = NULL, *deleted = NULL;
    cand *cands = NULL;
    path_store ps = {0};
    sk_mesh *res = NULL;
    *out = NULL;
    if (deleted_out)
        *deleted_out = NULL;

    for (size_t f = 0; f < nf; ++f)
        if (!m->f_deleted[f] && sk_mesh_face_size(m, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY,
                            "edge deletion needs a triangle mesh, face %zu has %zu sides", f,
                            sk_mesh_face_size(m, (uint32_t)f));
    even = sk__calloc_array(nv ? nv : 1, 1);
    bnd = sk__calloc_array(nv ? nv : 1, 1);
    comp = sk__malloc_array(nv + 1, sizeof *comp);
    queue = sk__malloc_array(nv + 1, sizeof *queue);
    dist = sk__malloc_array(nv + 1, sizeof *dist);
    src = sk__malloc_array(nv + 1, sizeof *src);
    pred = sk__malloc_array(nv + 1, sizeof *pred);
    partner = sk__malloc_array(nv + 1, sizeof *partner);
    remaining = sk__malloc_array(nv + 1, sizeof *remaining);
    dcnt = sk__calloc_array(ne ? ne : 1, 1);
    forbid = sk__calloc_array(ne ? ne : 1, 1);
    if (!even || !bnd || !comp || !queue || !dist || !src || !pred || !partner || !remaining ||
        !dcnt || !forbid) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
        goto done;
    }

    /* even vertices and components (for the counting argument) */
    size_t nrem = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        comp[v] = SK_INVALID;
        partner[v] = SK_INVALID;
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        bnd[v] = sk_is_boundary_v(m, v);
        if (!bnd[v] && (sk_mesh_valence(m, v) & 1u) == 0) {
            even[v] = 1;
            remaining[nrem++] = v;
        }
    }
    st0.even_vertices = nrem;
    for (uint32_t e = 0; e < ne; ++e)
        if (!m->e_deleted[e] && !sk_is_boundary_e(m, e))
            forbid[e] = deletion_corner(m, e) > SK_MAX_QUAD_CORNER_DEG;
    /* an even vertex with every edge forbidden keeps its best one */
    for (size_t i = 0; i < nrem; ++i) {
        uint32_t v = remaining[i], h0 = m->v_halfedge[v], h = h0, best = SK_INVALID;
        double best_c = 1e300;
        bool any = false;
        do {
            uint32_t e = sk_edge(h);
            any |= !forbid[e];
            double c = deletion_corner(m, e);
            if (c < best_c) {
                best_c = c;
                best = e;
            }
            h = sk_cw_out(m, h);
        } while (h != h0 && !any);
        if (!any && best != SK_INVALID) {
            forbid[best] = 0;
            st0.forced_edges++;
        }
    }
    st0.lower_bound = (nrem + 1) / 2;
    for (uint32_t s = 0; s < nv; ++s) {
        if (comp[s] != SK_INVALID || m->v_deleted[s] || m->v_halfedge[s] == SK_INVALID)
            continue;
        size_t qh = 0, qt = 0, n_even = 0, n_vert = 0;
        bool has_boundary = false;
        comp[s] = s;
        queue[qt++] = s;
        while (qh < qt) {
            uint32_t v = queue[qh++];
            n_even += even[v];
            n_vert++;
            has_boundary |= bnd[v];
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t w = sk_to(m, h);
                if (comp[w] == SK_INVALID) {
                    comp[w] = s;
                    queue[qt++] = w;
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
        if (!has_boundary && (n_even & 1u)) {
            st = sk__fail(err, SK_ERR_TOPOLOGY,
                          "closed component of vertex %u: %zu vertices, odd, so its %zu even "
                          "vertices are odd in number (Euler: sum (6-n) V_n = 6 chi) and cannot "
                          "be paired; no edge deletion exists (--allow-split splits an edge)",
                          s, n_vert, n_even);
            goto done;
        }
    }

    /* Algorithm Initialise */
    for (uint32_t v = 0; v < nv; ++v)
        dist[v] = SK_INVALID;
    size_t cap_c = 0, nc = 0;
    bool relaxed_forbid = false;
    while (nrem > 0) {
        st0.initialise_rounds++;
        size_t qh = 0, qt = 0;
        for (uint32_t v = 0; v < nv; ++v)
            dist[v] = SK_INVALID;
        for (size_t i = 0; i < nrem; ++i) {
            uint32_t v = remaining[i];
            dist[v] = 0;
            src[v] = v;
            pred[v] = SK_INVALID;
            queue[qt++] = v;
        }
        nc = 0;
        while (qh < qt) {
            uint32_t v = queue[qh++];
            if (bnd[v])
                continue; /* boundary vertices end paths, the search does not pass them */
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do {
                uint32_t w = sk_to(m, h);
                if (forbid[sk_edge(h)]) {
                    h = sk_cw_out(m, h);
                    continue;
                }
                if (dist[w] == SK_INVALID) {
                    dist[w] = dist[v] + 1;
                    src[w] = src[v];
                    pred[w] = v;
                    queue[qt++] = w;
                    if (bnd[w]) {
                        if (nc == cap_c) {
                            cap_c = cap_c ? 2 * cap_c : 4096;
                            cand *c = sk__realloc_array(cands, cap_c, sizeof *c);
                            if (!c) {
                                st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
                                goto done;
                            }
                            cands = c;
                        }
                        cands[nc++] = (cand){dist[w], w, SK_INVALID};
                    }
                } else if (src[w] != src[v] && !bnd[w] && v < w) {
                    if (nc == cap_c) {
                        cap_c = cap_c ? 2 * cap_c : 4096;
                        cand *c = sk__realloc_array(cands, cap_c, sizeof *c);
                        if (!c) {
                            st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
                            goto done;
                        }
                        cands = c;
                    }
                    cands[nc++] = (cand){dist[v] + dist[w] + 1, v, w};
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
        /* a meeting edge is seen from its endpoint expanded last (the other one was reached
         * already, by another search); v < w keeps one of the two sightings */
        qsort(cands, nc, sizeof *cands, cand_cmp);
        size_t paired = 0;
        for (size_t i = 0; i < nc; ++i) {
            cand c = cands[i];
            uint32_t a = src[c.u], b = c.v == SK_INVALID ? SK_INVALID : src[c.v];
            if (partner[a] != SK_INVALID || (b != SK_INVALID && partner[b] != SK_INVALID))
                continue;
            /* the path: a ... u (reversed pred chain), then v ... b */
            size_t first = ps.nv;
            for (uint32_t x = c.u; x != SK_INVALID; x = pred[x])
                if (!ps_push_vertex(&ps, x))
                    goto nomem;
            for (size_t i0 = first, i1 = ps.nv - 1; i0 < i1; ++i0, --i1) {
                uint32_t t = ps.v[i0];
                ps.v[i0] = ps.v[i1];
                ps.v[i1] = t;
            }
            if (b != SK_INVALID)
                for (uint32_t x = c.v; x != SK_INVALID; x = pred[x])
                    if (!ps_push_vertex(&ps, x))
                        goto nomem;
            if (!ps_close_path(&ps))
                goto nomem;
            st0.path_edges += ps.nv - first - 1;
            partner[a] = b == SK_INVALID ? c.u : b;
            if (b != SK_INVALID) {
                partner[b] = a;
                st0.pairs++;
            } else {
                st0.boundary_paths++;
            }
            ++paired;
        }
        size_t k = 0;
        for (size_t i = 0; i < nrem; ++i)
            if (partner[remaining[i]] == SK_INVALID)
                remaining[k++] = remaining[i];
        nrem = k;
        if (paired == 0 && nrem > 0 && !relaxed_forbid) {
            /* the avoided edges cut some even vertex off: allow them all */
            memset(forbid, 0, ne);
            relaxed_forbid = true;
            continue;
        }
        if (paired == 0 && nrem > 0) {
            st = sk__fail(err, SK_ERR_TOPOLOGY,
                          "edge deletion: even vertex %u cannot be paired (no even partner or "
                          "boundary reachable)", remaining[0]);
            goto done;
        }
    }

    /* Reduce Path on every path, then the union with cancellation of shared edges (2a) */
    for (size_t p = 0; p < ps.np; ++p) {
        uint32_t *pv = ps.v + ps.start[p];
        size_t n = reduce_path(m, forbid, pv, ps.start[p + 1] - ps.start[p], &st0.reductions);
        for (size_t i = 0; i + 1 < n; ++i) {
            uint32_t h = find_halfedge(m, pv[i], pv[i + 1]);
            if (h == SK_INVALID) {
                st = sk__fail(err, SK_ERR_NUMERIC, "edge deletion: internal error, broken path");
                goto done;
            }
            uint32_t e = sk_edge(h);
            if (dcnt[e])
                st0.shared_edges++;
            dcnt[e] ^= 1u;
        }
    }
    /* edges joining two boundary vertices are never needed (boundary vertices may stay even) */
    for (uint32_t e = 0; e < ne; ++e)
        if (dcnt[e] && bnd[sk_from(m, 2 * e)] && bnd[sk_to(m, 2 * e)])
            dcnt[e] = 0;

    /* (2b): triangles holding two (or three) deleted edges */
    fq = sk__malloc_array(nf + 1, sizeof *fq);
    if (!fq)
        goto nomem;
    size_t nq = 0;
    for (uint32_t f = 0; f < nf; ++f)
        if (!m->f_deleted[f])
            fq[nq++] = f;
    /* process as a stack; faces are re-pushed when an edge of theirs changes (bounded by the strict
     * decrease of the deleted set) */
    uint8_t *inq = sk__calloc_array(nf ? nf : 1, 1);
    if (!inq)
        goto nomem;
    memset(inq, 1, nf);
    size_t cap_q = nf + 1;
    while (nq > 0) {
        uint32_t f = fq[--nq];
        inq[f] = 0;
        uint32_t h[3];
        h[0] = m->f_halfedge[f];
        h[1] = m->h_next[h[0]];
        h[2] = m->h_next[h[1]];
        int cnt = 0, which[3];
        for (int i = 0; i < 3; ++i)
            if (dcnt[sk_edge(h[i])])
                which[cnt++] = i;
        if (cnt < 2)
            continue;
        st0.triangle_fixes++;
        if (cnt == 3) {
            for (int i = 0; i < 3; ++i)
                dcnt[sk_edge(h[i])] = 0;
        } else {
            int third = 3 - which[0] - which[1];
            uint32_t et = sk_edge(h[third]);
            dcnt[sk_edge(h[which[0]])] = 0;
            dcnt[sk_edge(h[which[1]])] = 0;
            if (!sk_is_boundary_e(m, et) && !(bnd[sk_from(m, 2 * et)] && bnd[sk_to(m, 2 * et)])) {
                dcnt[et] = 1;
                st0.forced_edges += forbid[et];
            }
        }
        /* re-check the neighbouring faces */
        for (int i = 0; i < 3; ++i) {
            uint32_t g = m->h_face[sk_opp(h[i])];
            if (g != SK_INVALID && !inq[g]) {
                if (nq == cap_q) {
                    cap_q *= 2;
                    uint32_t *q2 = sk__realloc_array(fq, cap_q, sizeof *q2);
                    if (!q2) {
                        sk__free(inq);
                        goto nomem;
                    }
                    fq = q2;
                }
                inq[g] = 1;
                fq[nq++] = g;
            }
        }
    }
    sk__free(inq);

    /* verify: every interior vertex odd, every triangle at most one deleted edge */
    size_t nd = 0;
    for (uint32_t e = 0; e < ne; ++e)
        nd += dcnt[e];
    for (uint32_t v = 0; v < nv; ++v) {
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID || bnd[v])
            continue;
        size_t faces = 0;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        do {
            faces += 1 - dcnt[sk_edge(h)];
            h = sk_cw_out(m, h);
        } while (h != h0);
        if ((faces & 1u) == 0) {
            st = sk__fail(err, SK_ERR_NUMERIC,
                          "edge deletion: internal error, vertex %u is still even", v);
            goto done;
        }
    }
    st0.deleted_edges = nd;

    /* the triangle/quad mesh */
    if ((st = sk_mesh_copy(m, &res, err)) != SK_OK)
        goto done;
    deleted = sk__malloc_array(2 * nd + 1, sizeof *deleted);
    if (!deleted)
        goto nomem;
    nd = 0;
    for (uint32_t e = 0; e < ne; ++e) {
        if (!dcnt[e])
            continue;
        deleted[2 * nd] = sk_from(m, 2 * e);
        deleted[2 * nd + 1] = sk_to(m, 2 * e);
        ++nd;
        merge_across_edge(res, e);
    }
    if ((st = sk_mesh_compact(res, NULL, NULL, err)) != SK_OK)
        goto done;
    for (uint32_t f = 0; f < res->num_faces; ++f) {
        if (sk_mesh_face_size(res, f) == 3)
            st0.triangles++;
        else
            st0.quads++;
    }
    *out = res;
    res = NULL;
    if (deleted_out) {
        *deleted_out = deleted;
        deleted = NULL;
    }
    if (stats)
        *stats = st0;
    sk__ok(err);
    goto done;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "out of memory in edge deletion");
done:
    sk__free(even);
    sk__free(bnd);
    sk__free(dcnt);
    sk__free(forbid);
    sk__free(comp);
    sk__free(queue);
    sk__free(dist);
    sk__free(src);
    sk__free(pred);
    sk__free(partner);
    sk__free(remaining);
    sk__free(fq);
    sk__free(cands);
    sk__free(deleted);
    sk__free(ps.v);
    sk__free(ps.start);
    sk_mesh_destroy(&res);
    return st;
}
