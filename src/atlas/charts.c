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
    if (!w->vcount || !w->label || !w->parent || !w->local || !w->flocal || !w->dist || !w->heap ||
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
            if (g == SK_INVALID || w->label[g] != stamp || o < h)
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
                if (g == SK_INVALID || w->label[g] != stamp || w->side[w->flocal[g]])
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
