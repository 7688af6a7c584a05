/* Charts: components, wedges (fans of a chart's faces around a vertex), chart meshes and the
 * bisection of a chart into two edge-connected halves (two far seeds, nearest-seed growth over
 * the dual graph weighted by centroid distances). */
#include "atlas/atlas_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sk_status sk__chart_work_init(sk__chart_work *w, const sk_mesh *m, sk_error *err)
{
    memset(w, 0, sizeof *w);
    size_t nf = m->num_faces ? m->num_faces : 1, nh = m->num_halfedges ? m->num_halfedges : 1;
    w->label = sk__malloc_array(nf, sizeof(uint32_t));
    w->parent = sk__malloc_array(nh, sizeof(uint32_t));
    w->local = sk__malloc_array(nh, sizeof(uint32_t));
    w->flocal = sk__malloc_array(nf, sizeof(uint32_t));
    w->dist = sk__malloc_array(nf, sizeof(double));
    w->heap = sk__malloc_array(nf, sizeof(uint32_t));
    w->heap_pos = sk__malloc_array(nf, sizeof(uint32_t));
    w->side = sk__malloc_array(nf, 1);
    w->tmp = sk__malloc_array(nf, sizeof(uint32_t));
    w->centroid = sk__malloc_array(3 * nf, sizeof(double));
    w->fnormal = sk__malloc_array(4 * nf, sizeof(double));
    w->vcount = sk__calloc_array(m->num_vertices ? m->num_vertices : 1, sizeof(uint32_t));
    w->cut = sk__calloc_array(nh / 2 + 1, 1);
    if (!w->vcount || !w->cut || !w->label || !w->parent || !w->local || !w->flocal || !w->dist || !w->heap ||
        !w->heap_pos || !w->side || !w->tmp || !w->centroid || !w->fnormal) {
        sk__chart_work_free(w);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t f = 0; f < m->num_faces; ++f) {
        w->label[f] = SK_INVALID;
        double c[3] = {0, 0, 0};
        uint32_t h = m->f_halfedge[f];
        for (int k = 0; k < 3; ++k, h = m->h_next[h])
            sk__add3(c, c, m->positions + 3 * (size_t)sk_from(m, h));
        sk__scale3(w->centroid + 3 * f, c, 1.0 / 3.0);
        double n[3], twice = sk_mesh_face_normal(m, (uint32_t)f, n);
        sk__scale3(w->fnormal + 4 * f, n, 0.5 * twice);
        w->fnormal[4 * f + 3] = 0.5 * twice;
    }
    return SK_OK;
}

void sk__chart_work_free(sk__chart_work *w)
{
    sk__free(w->label);
    sk__free(w->parent);
    sk__free(w->local);
    sk__free(w->flocal);
    sk__free(w->dist);
    sk__free(w->heap);
    sk__free(w->heap_pos);
    sk__free(w->side);
    sk__free(w->tmp);
    sk__free(w->centroid);
    sk__free(w->fnormal);
    sk__free(w->vcount);
    sk__free(w->cut);
    memset(w, 0, sizeof *w);
}

size_t sk__face_components(const sk_mesh *m, uint32_t *comp, uint32_t *queue)
{
    size_t n = 0;
    for (size_t f = 0; f < m->num_faces; ++f)
        comp[f] = SK_INVALID;
    for (size_t s = 0; s < m->num_faces; ++s) {
        if (comp[s] != SK_INVALID)
            continue;
        size_t head = 0, tail = 0;
        comp[s] = (uint32_t)n;
        queue[tail++] = (uint32_t)s;
        while (head < tail) {
            uint32_t f = queue[head++], h = m->f_halfedge[f];
            for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
                uint32_t g = m->h_face[h ^ 1u];
                if (g != SK_INVALID && comp[g] == SK_INVALID) {
                    comp[g] = (uint32_t)n;
                    queue[tail++] = g;
                }
            }
        }
        n++;
    }
    return n;
}

uint32_t sk__wedge_find(sk__chart_work *w, uint32_t h)
{
    uint32_t r = h;
    while (w->parent[r] != r)
        r = w->parent[r];
    while (w->parent[h] != r) { /* path compression */
        uint32_t n = w->parent[h];
        w->parent[h] = r;
        h = n;
    }
    return r;
}

static void uf_union(sk__chart_work *w, uint32_t a, uint32_t b)
{
    a = sk__wedge_find(w, a);
    b = sk__wedge_find(w, b);
    if (a != b)
        w->parent[a < b ? b : a] = a < b ? a : b;
}

sk_status sk__chart_extract(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                            sk__chart_work *w, sk_mesh **chart, uint32_t **vert_h, sk_error *err)
{
    *chart = NULL;
    *vert_h = NULL;
    sk_status st = SK_OK;
    double *pos = NULL;
    uint32_t *off = NULL, *idx = NULL, *vh = NULL;
    /* corners: half-edge h is the corner at sk_from(h) in face(h) */
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h])
            w->parent[h] = h;
    }
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            uint32_t o = h ^ 1u, g = m->h_face[o];
            if (g == SK_INVALID || w->label[g] != stamp || o < h || w->cut[h >> 1])
                continue;
            /* edge a -> b in this face, b -> a in g: corner a here ~ corner a in g, same for b */
            uf_union(w, h, m->h_next[o]);
            uf_union(w, m->h_next[h], o);
        }
    }
    size_t nv = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h])
            w->local[h] = SK_INVALID;
    }
    vh = sk__malloc_array(3 * nf, sizeof(uint32_t));
    idx = sk__malloc_array(3 * nf, sizeof(uint32_t));
    off = sk__malloc_array(nf + 1, sizeof(uint32_t));
    pos = sk__malloc_array(9 * nf, sizeof(double));
    if (!vh || !idx || !off || !pos) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < nf; ++i) {
        off[i] = (uint32_t)(3 * i);
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            uint32_t r = sk__wedge_find(w, h);
            if (w->local[r] == SK_INVALID) {
                w->local[r] = (uint32_t)nv;
                vh[nv] = h;
                memcpy(pos + 3 * nv, m->positions + 3 * (size_t)sk_from(m, h), 3 * sizeof(double));
                nv++;
            }
            idx[3 * i + (size_t)k] = w->local[r];
        }
    }
    off[nf] = (uint32_t)(3 * nf);
    if ((st = sk_mesh_from_faces(nv, pos, nf, off, idx, chart, err)))
        goto done;
    *vert_h = vh;
    vh = NULL;
done:
    sk__free(vh);
    sk__free(idx);
    sk__free(off);
    sk__free(pos);
    return st;
}

/* ---- Dijkstra over the chart's dual graph (binary heap on local face indices) ---- */

static void heap_up(sk__chart_work *w, size_t i)
{
    uint32_t x = w->heap[i];
    while (i > 0) {
        size_t p = (i - 1) / 2;
        if (w->dist[w->heap[p]] <= w->dist[x])
            break;
        w->heap[i] = w->heap[p];
        w->heap_pos[w->heap[i]] = (uint32_t)i;
        i = p;
    }
    w->heap[i] = x;
    w->heap_pos[x] = (uint32_t)i;
}

static void heap_down(sk__chart_work *w, size_t i, size_t n)
{
    uint32_t x = w->heap[i];
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= n)
            break;
        if (c + 1 < n && w->dist[w->heap[c + 1]] < w->dist[w->heap[c]])
            c++;
        if (w->dist[w->heap[c]] >= w->dist[x])
            break;
        w->heap[i] = w->heap[c];
        w->heap_pos[w->heap[i]] = (uint32_t)i;
        i = c;
    }
    w->heap[i] = x;
    w->heap_pos[x] = (uint32_t)i;
}

/* Distances from the seeds (local indices; side[s] = index of the seed) to every face; side of
 * every face = side of its nearest seed. Returns the local index of the farthest face. */
static uint32_t dijkstra(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                         sk__chart_work *w, const uint32_t *seeds, size_t nseeds)
{
    const uint32_t NOT_SEEN = SK_INVALID, DONE = SK_INVALID - 1;
    for (size_t i = 0; i < nf; ++i) {
        w->dist[i] = INFINITY;
        w->heap_pos[i] = NOT_SEEN;
    }
    size_t n = 0;
    for (size_t s = 0; s < nseeds; ++s) {
        w->dist[seeds[s]] = 0;
        w->side[seeds[s]] = (uint8_t)s;
        w->heap[n] = seeds[s];
        w->heap_pos[seeds[s]] = (uint32_t)n;
        n++;
    }
    uint32_t last = seeds[0];
    while (n > 0) {
        uint32_t x = w->heap[0];
        w->heap_pos[x] = DONE;
        last = x;
        if (--n > 0) {
            w->heap[0] = w->heap[n];
            w->heap_pos[w->heap[0]] = 0;
            heap_down(w, 0, n);
        }
        uint32_t f = faces[x], h = m->f_halfedge[f];
        const double *cf = w->centroid + 3 * (size_t)f;
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            uint32_t g = m->h_face[h ^ 1u];
            if (g == SK_INVALID || w->label[g] != stamp)
                continue;
            uint32_t y = w->flocal[g];
            if (w->heap_pos[y] == DONE)
                continue;
            double d = w->dist[x] + sk__dist3(cf, w->centroid + 3 * (size_t)g);
            if (d < w->dist[y]) {
                w->dist[y] = d;
                w->side[y] = w->side[x];
                if (w->heap_pos[y] == NOT_SEEN) {
                    w->heap[n] = y;
                    w->heap_pos[y] = (uint32_t)n;
                    n++;
                }
                heap_up(w, w->heap_pos[y]);
            }
        }
    }
    return last;
}

/* The nearest-seed border zigzags along the triangles; a face with two or three neighbours on
 * the other side (a tooth) changes sides, a few rounds (pieces it cuts off become charts of their
 * own: the driver splits every chart into its components). */
static void smooth_sides(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                         sk__chart_work *w, const uint32_t seeds[2])
{
    for (int round = 0; round < 4; ++round) {
        size_t changed = 0;
        for (size_t i = 0; i < nf; ++i) {
            if (i == seeds[0] || i == seeds[1])
                continue;
            uint32_t h = m->f_halfedge[faces[i]];
            int other = 0;
            for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
                uint32_t g = m->h_face[h ^ 1u];
                if (g != SK_INVALID && w->label[g] == stamp && w->side[w->flocal[g]] != w->side[i])
                    other++;
            }
            if (other >= 2) {
                w->side[i] = (uint8_t)(1 - w->side[i]);
                changed++;
            }
        }
        if (!changed)
            break;
    }
}

sk_status sk__chart_bisect(const sk_mesh *m, uint32_t *faces, size_t nf, uint32_t stamp,
                           sk__chart_work *w, size_t *n0, sk_error *err)
{
    if (nf < 2)
        return sk__fail(err, SK_ERR_ARG, "cannot split a chart of %zu faces", nf);
    for (size_t i = 0; i < nf; ++i)
        w->flocal[faces[i]] = (uint32_t)i;
    /* the first seed: the face farthest (in space) from the first face, a cheap stand-in for the
     * first sweep of a double sweep; the second: the farthest from it along the dual graph */
    uint32_t seeds[2] = {0, 0};
    const double *c0 = w->centroid + 3 * (size_t)faces[0];
    double far = -1;
    for (size_t i = 0; i < nf; ++i) {
        double d = sk__dist3(c0, w->centroid + 3 * (size_t)faces[i]);
        if (d > far) {
            far = d;
            seeds[0] = (uint32_t)i;
        }
    }
    seeds[1] = dijkstra(m, faces, nf, stamp, w, seeds, 1);
    if (seeds[1] == seeds[0])
        return sk__fail(err, SK_ERR_ARG, "chart of %zu faces is not edge-connected", nf);
    dijkstra(m, faces, nf, stamp, w, seeds, 2);
    smooth_sides(m, faces, nf, stamp, w, seeds);
    size_t a = 0, b = 0;
    for (size_t i = 0; i < nf; ++i)
        if (w->side[i] == 0)
            faces[a++] = faces[i];
        else
            w->tmp[b++] = faces[i];
    memcpy(faces + a, w->tmp, b * sizeof(uint32_t));
    *n0 = a;
    if (a == 0 || b == 0)
        return sk__fail(err, SK_ERR_ARG, "chart of %zu faces did not split", nf);
    return SK_OK;
}

/* Can face f (local x) join the disk grown so far (w->side[y] == 1 for its faces)? */
static bool disk_accepts(const sk_mesh *m, uint32_t f, uint32_t stamp, const sk__chart_work *w)
{
    uint32_t h = m->f_halfedge[f], shared_h = SK_INVALID;
    int k = 0;
    for (int i = 0; i < 3; ++i, h = m->h_next[h]) {
        uint32_t g = m->h_face[h ^ 1u];
        if (g != SK_INVALID && w->label[g] == stamp && w->side[w->flocal[g]] == 1) {
            k++;
            shared_h = h;
        }
    }
    if (k == 1) /* the vertex opposite the shared edge must be new */
        return w->vcount[sk_to(m, m->h_next[shared_h])] == 0;
    return k == 2; /* closes the fan of the common vertex; k == 3 would close the surface */
}

sk_status sk__chart_grow_disk(const sk_mesh *m, uint32_t *faces, size_t nf, uint32_t stamp,
                              sk__chart_work *w, size_t *n0, sk_error *err)
{
    const uint32_t OUT = SK_INVALID;
    for (size_t i = 0; i < nf; ++i) {
        w->flocal[faces[i]] = (uint32_t)i;
        w->side[i] = 0;
        w->dist[i] = INFINITY;
        w->heap_pos[i] = OUT;
    }
    /* seed: the face farthest from faces[0], then distances from it order the growth */
    uint32_t seed = 0;
    seed = dijkstra(m, faces, nf, stamp, w, &seed, 1);
    for (size_t i = 0; i < nf; ++i) {
        w->side[i] = 0;
        w->heap_pos[i] = OUT;
    }
    /* priority = distance from the seed face's centroid (straight line): cheap and symmetric */
    const double *cs = w->centroid + 3 * (size_t)faces[seed];
    size_t n = 0, added = 0;
    w->heap[n] = seed;
    w->dist[seed] = 0;
    w->heap_pos[seed] = (uint32_t)n++;
    while (n > 0) {
        uint32_t x = w->heap[0];
        w->heap_pos[x] = OUT;
        if (--n > 0) {
            w->heap[0] = w->heap[n];
            w->heap_pos[w->heap[0]] = 0;
            heap_down(w, 0, n);
        }
        uint32_t f = faces[x];
        if (added > 0 && !disk_accepts(m, f, stamp, w))
            continue; /* may come back when another neighbour joins */
        w->side[x] = 1;
        added++;
        uint32_t h = m->f_halfedge[f];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            w->vcount[sk_from(m, h)]++;
            uint32_t g = m->h_face[h ^ 1u];
            if (g == SK_INVALID || w->label[g] != stamp)
                continue;
            uint32_t y = w->flocal[g];
            if (w->side[y] == 1 || w->heap_pos[y] != OUT)
                continue;
            w->dist[y] = sk__dist3(cs, w->centroid + 3 * (size_t)g);
            w->heap[n] = y;
            w->heap_pos[y] = (uint32_t)n;
            heap_up(w, n++);
        }
    }
    size_t a = 0, b = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t f = faces[i];
        if (w->side[i] == 1) {
            uint32_t h = m->f_halfedge[f];
            for (int k = 0; k < 3; ++k, h = m->h_next[h])
                w->vcount[sk_from(m, h)] = 0;
            faces[a++] = f;
        } else {
            w->tmp[b++] = f;
        }
    }
    memcpy(faces + a, w->tmp, b * sizeof(uint32_t));
    *n0 = a;
    if (a == 0)
        return sk__fail(err, SK_ERR_ARG, "no disk grew in a chart of %zu faces", nf);
    return SK_OK;
}

size_t sk__chart_components(const sk_mesh *m, uint32_t *faces, size_t nf, uint32_t stamp,
                            sk__chart_work *w, uint32_t *sizes)
{
    for (size_t i = 0; i < nf; ++i) {
        w->flocal[faces[i]] = (uint32_t)i;
        w->side[i] = 0;
    }
    size_t nc = 0, tail = 0;
    for (size_t s = 0; s < nf; ++s) {
        if (w->side[s])
            continue;
        size_t head = tail, start = tail;
        w->side[s] = 1;
        w->tmp[tail++] = faces[s];
        while (head < tail) {
            uint32_t f = w->tmp[head++], h = m->f_halfedge[f];
            for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
                uint32_t g = m->h_face[h ^ 1u];
                if (g == SK_INVALID || w->label[g] != stamp || w->side[w->flocal[g]] ||
                    w->cut[h >> 1])
                    continue;
                w->side[w->flocal[g]] = 1;
                w->tmp[tail++] = g;
            }
        }
        sizes[nc++] = (uint32_t)(tail - start);
    }
    memcpy(faces, w->tmp, nf * sizeof(uint32_t));
    return nc;
}

/* ---- cut graph of a disk with holes ---- */

/* Is the edge of h (its face in the chart labelled stamp) inside the chart: a chart face on the
 * other side too, and not cut? */
static bool inner_edge(const sk_mesh *m, const sk__chart_work *w, uint32_t h, uint32_t stamp)
{
    uint32_t g = m->h_face[h ^ 1u];
    return g != SK_INVALID && w->label[g] == stamp && !w->cut[h >> 1];
}

/* Scratch of the cut graph: the chart's vertices (local ids), their inner edges (CSR of
 * outgoing half-edges), boundary loops and a Dijkstra (binary heap, lazy deletion). */
typedef struct cut_graph {
    size_t nv, nloops;
    uint32_t *vloc;         /* per mesh vertex: local id or SK_INVALID */
    uint32_t *adj_off, *adj; /* per local vertex: outgoing inner half-edges */
    uint32_t *loop;         /* per local vertex: its boundary loop or SK_INVALID */
    uint8_t *source;        /* per local vertex: on the outer loop, an attached loop or a cut */
    uint8_t *attached;      /* per loop */
    uint32_t *hloop;        /* per mesh half-edge of the chart's boundary: its loop */
    double *dist;           /* per local vertex */
    uint32_t *prev;         /* per local vertex: the half-edge it was reached by */
    double *heap_d;         /* heap of (distance, local vertex) */
    uint32_t *heap_v;
    size_t heap_n, heap_cap;
} cut_graph;

static void cut_graph_free(cut_graph *g)
{
    sk__free(g->vloc);
    sk__free(g->adj_off);
    sk__free(g->adj);
    sk__free(g->loop);
    sk__free(g->source);
    sk__free(g->attached);
    sk__free(g->hloop);
    sk__free(g->dist);
    sk__free(g->prev);
    sk__free(g->heap_d);
    sk__free(g->heap_v);
}

static void heap_push(cut_graph *g, double d, uint32_t v)
{
    size_t i = g->heap_n++;
    while (i > 0 && g->heap_d[(i - 1) / 2] > d) {
        g->heap_d[i] = g->heap_d[(i - 1) / 2];
        g->heap_v[i] = g->heap_v[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    g->heap_d[i] = d;
    g->heap_v[i] = v;
}

static uint32_t heap_pop(cut_graph *g, double *d)
{
    uint32_t top = g->heap_v[0];
    *d = g->heap_d[0];
    double xd = g->heap_d[--g->heap_n];
    uint32_t xv = g->heap_v[g->heap_n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= g->heap_n)
            break;
        if (c + 1 < g->heap_n && g->heap_d[c + 1] < g->heap_d[c])
            c++;
        if (g->heap_d[c] >= xd)
            break;
        g->heap_d[i] = g->heap_d[c];
        g->heap_v[i] = g->heap_v[c];
        i = c;
    }
    g->heap_d[i] = xd;
    g->heap_v[i] = xv;
    return top;
}

/* Local vertices, inner-edge adjacency and boundary loops of the chart; false (g->nloops 0) when
 * the chart holds a cut edge already. */
static bool cut_graph_build(cut_graph *g, const sk_mesh *m, const uint32_t *faces, size_t nf,
                            uint32_t stamp, const sk__chart_work *w, bool allow_cuts)
{
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            uint32_t v = sk_from(m, h), o = m->h_face[h ^ 1u];
            if (!allow_cuts && w->cut[h >> 1] && o != SK_INVALID && w->label[o] == stamp)
                return false;
            if (g->vloc[v] == SK_INVALID)
                g->vloc[v] = (uint32_t)g->nv++;
            if (inner_edge(m, w, h, stamp))
                g->adj_off[g->vloc[v] + 1]++;
        }
    }
    for (size_t v = 0; v < g->nv; ++v) {
        g->adj_off[v + 1] += g->adj_off[v];
        g->loop[v] = SK_INVALID;
    }
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            g->hloop[h] = SK_INVALID;
            if (inner_edge(m, w, h, stamp))
                g->adj[g->prev[g->vloc[sk_from(m, h)]]++ + g->adj_off[g->vloc[sk_from(m, h)]]] = h;
        }
    }
    /* boundary loops: from a boundary half-edge a -> b, the next one leaves b across the chart's
     * faces around b */
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h0 = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h0 = m->h_next[h0]) {
            if (inner_edge(m, w, h0, stamp) || g->hloop[h0] != SK_INVALID)
                continue;
            uint32_t h = h0;
            do {
                g->hloop[h] = (uint32_t)g->nloops;
                g->loop[g->vloc[sk_from(m, h)]] = (uint32_t)g->nloops;
                h = m->h_next[h];
                while (inner_edge(m, w, h, stamp))
                    h = m->h_next[h ^ 1u];
            } while (h != h0 && g->hloop[h] == SK_INVALID);
            g->nloops++;
        }
    }
    return true;
}

/* One Dijkstra from the sources to the nearest vertex of a loop not attached yet; the path is cut
 * and becomes a source, its loop attached. Returns the edges cut (0: none reached). */
static size_t cut_one_path(cut_graph *g, const sk_mesh *m, sk__chart_work *w)
{
    g->heap_n = 0;
    for (size_t v = 0; v < g->nv; ++v) {
        g->prev[v] = SK_INVALID;
        g->dist[v] = INFINITY;
        if (g->source[v] || (g->loop[v] != SK_INVALID && g->attached[g->loop[v]])) {
            g->dist[v] = 0;
            heap_push(g, 0, (uint32_t)v);
        }
    }
    uint32_t t = SK_INVALID;
    while (g->heap_n > 0 && t == SK_INVALID) {
        double d;
        uint32_t v = heap_pop(g, &d);
        if (d > g->dist[v])
            continue;
        if (g->loop[v] != SK_INVALID && !g->attached[g->loop[v]]) {
            t = v;
            break;
        }
        for (uint32_t i = g->adj_off[v]; i < g->adj_off[v + 1]; ++i) {
            uint32_t h = g->adj[i], u = g->vloc[sk_to(m, h)];
            double nd = d + sk_mesh_edge_length(m, h >> 1);
            if (nd < g->dist[u]) {
                g->dist[u] = nd;
                g->prev[u] = h;
                heap_push(g, nd, u);
            }
        }
    }
    if (t == SK_INVALID)
        return 0;
    g->attached[g->loop[t]] = 1;
    size_t n = 0;
    for (uint32_t v = t; g->prev[v] != SK_INVALID; v = g->vloc[sk_from(m, g->prev[v])], ++n) {
        w->cut[g->prev[v] >> 1] = 1;
        g->source[v] = 1;
    }
    return n;
}

/* The cut graph's arrays for a chart of nf faces (vloc all SK_INVALID). */
static sk_status cut_graph_alloc(cut_graph *g, const sk_mesh *m, size_t nf, sk_error *err)
{
    memset(g, 0, sizeof *g);
    size_t nv = m->num_vertices ? m->num_vertices : 1, nc = 3 * nf + 1;
    g->vloc = sk__malloc_array(nv, sizeof(uint32_t));
    g->adj_off = sk__calloc_array(nc + 1, sizeof(uint32_t));
    g->adj = sk__malloc_array(nc, sizeof(uint32_t));
    g->loop = sk__malloc_array(nc, sizeof(uint32_t));
    g->source = sk__calloc_array(nc, 1);
    g->attached = sk__calloc_array(nc, 1);
    g->hloop = sk__malloc_array(m->num_halfedges ? m->num_halfedges : 1, sizeof(uint32_t));
    g->dist = sk__malloc_array(nc, sizeof(double));
    g->prev = sk__calloc_array(nc, sizeof(uint32_t));
    g->heap_cap = 3 * nf + nc; /* every inner half-edge pushes at most once, plus the sources */
    g->heap_d = sk__malloc_array(g->heap_cap, sizeof(double));
    g->heap_v = sk__malloc_array(g->heap_cap, sizeof(uint32_t));
    if (!g->vloc || !g->adj_off || !g->adj || !g->loop || !g->source || !g->attached ||
        !g->hloop || !g->dist || !g->prev || !g->heap_d || !g->heap_v) {
        cut_graph_free(g);
        memset(g, 0, sizeof *g);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t v = 0; v < m->num_vertices; ++v)
        g->vloc[v] = SK_INVALID;
    return SK_OK;
}

sk_status sk__chart_cut_slit(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                             sk__chart_work *w, const double *score, uint32_t *cut_edges,
                             size_t *ncut, double *length, sk_error *err)
{
    cut_graph g;
    *ncut = 0;
    *length = 0;
    sk_status st = cut_graph_alloc(&g, m, nf, err);
    if (st)
        return st;
    if (!cut_graph_build(&g, m, faces, nf, stamp, w, true) || g.nloops < 1)
        goto done;
    /* the target: the inner vertex of the largest score */
    uint32_t t = SK_INVALID;
    double best = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            uint32_t v = sk_from(m, h), l = g.vloc[v];
            if (g.loop[l] == SK_INVALID && score[v] > best) {
                best = score[v];
                t = l;
            }
        }
    }
    if (t == SK_INVALID)
        goto done;
    /* Dijkstra from every boundary vertex to t */
    g.heap_n = 0;
    for (size_t v = 0; v < g.nv; ++v) {
        g.prev[v] = SK_INVALID;
        g.dist[v] = INFINITY;
        if (g.loop[v] != SK_INVALID) {
            g.dist[v] = 0;
            heap_push(&g, 0, (uint32_t)v);
        }
    }
    bool reached = false;
    while (g.heap_n > 0) {
        double d;
        uint32_t v = heap_pop(&g, &d);
        if (d > g.dist[v])
            continue;
        if (v == t) {
            reached = true;
            break;
        }
        for (uint32_t i = g.adj_off[v]; i < g.adj_off[v + 1]; ++i) {
            uint32_t h = g.adj[i], u = g.vloc[sk_to(m, h)];
            double nd = d + sk_mesh_edge_length(m, h >> 1);
            if (nd < g.dist[u]) {
                g.dist[u] = nd;
                g.prev[u] = h;
                heap_push(&g, nd, u);
            }
        }
    }
    if (!reached)
        goto done;
    for (uint32_t v = t; g.prev[v] != SK_INVALID; v = g.vloc[sk_from(m, g.prev[v])]) {
        w->cut[g.prev[v] >> 1] = 1;
        cut_edges[(*ncut)++] = g.prev[v] >> 1;
        *length += sk_mesh_edge_length(m, g.prev[v] >> 1);
    }
done:
    cut_graph_free(&g);
    return st;
}

sk_status sk__chart_cut_holes(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                              sk__chart_work *w, size_t *ncut, sk_error *err)
{
    cut_graph g;
    *ncut = 0;
    sk_status st = cut_graph_alloc(&g, m, nf, err);
    if (st)
        return st;
    if (!cut_graph_build(&g, m, faces, nf, stamp, w, false) || g.nloops < 2 ||
        g.nloops > SK__ATLAS_MAX_HOLES + 1)
        goto done;
    /* the outer loop: the longest */
    double *len = g.dist, best = -1;
    uint32_t outer = 0;
    for (size_t l = 0; l < g.nloops; ++l)
        len[l] = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t h = m->f_halfedge[faces[i]];
        for (int k = 0; k < 3; ++k, h = m->h_next[h])
            if (g.hloop[h] != SK_INVALID)
                len[g.hloop[h]] += sk_mesh_edge_length(m, h >> 1);
    }
    for (uint32_t l = 0; l < g.nloops; ++l)
        if (len[l] > best) {
            best = len[l];
            outer = l;
        }
    g.attached[outer] = 1;
    for (size_t k = 1; k < g.nloops; ++k) {
        size_t n = cut_one_path(&g, m, w);
        if (n == 0)
            break;
        *ncut += n;
    }
done:
    cut_graph_free(&g);
    return st;
}
