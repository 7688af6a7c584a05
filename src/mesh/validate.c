/* Validation of an indexed-face soup: every defect class of DESIGN.md, counted with the first few
 * offending elements, plus topology (edges, boundary loops, components, Euler characteristic,
 * genus) and the Gauss-Bonnet check of Alboul & Echeverria (sum of angle deficits = 2 pi chi).
 * Works on any input, manifold or not, so that `surfkit info` can report bad files fully. */
#include "surfkit/mesh.h"
#include "core/internal.h"
#include "core/vec.h"
#include "mesh/mesh_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static void note(sk_defect *d, uint32_t a, uint32_t b)
{
    if (d->num_examples < SK_DEFECT_EXAMPLES) {
        d->a[d->num_examples] = a;
        d->b[d->num_examples] = b;
        d->num_examples++;
    }
    d->count++;
}

bool sk_validation_is_manifold(const sk_validation *r)
{
    return r->out_of_range.count == 0 && r->small_faces.count == 0 &&
           r->repeated_vertex_faces.count == 0 && r->nonfinite_vertices.count == 0 &&
           r->non_manifold_edges.count == 0 && r->orientation_conflicts.count == 0 &&
           r->non_manifold_vertices.count == 0;
}

/* 64-bit mix of a sorted index list, for finding duplicate faces */
static uint64_t hash_sorted(const uint32_t *ix, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ULL ^ n;
    for (size_t i = 0; i < n; ++i) {
        h ^= ix[i];
        h *= 0x100000001b3ULL;
        h ^= h >> 29;
    }
    return h;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

typedef struct work {
    uint8_t *face_ok;      /* face usable for topology */
    uint32_t *cface;       /* corner -> face */
    uint64_t *keys;        /* corner edge keys, sorted */
    uint32_t *corner;      /* corners in key order */
    uint32_t *parent;      /* union-find */
    uint8_t *referenced;
    uint8_t *on_boundary;
    double *angle_sum;
} work;

static void work_free(work *w)
{
    sk__free(w->face_ok);
    sk__free(w->cface);
    sk__free(w->keys);
    sk__free(w->corner);
    sk__free(w->parent);
    sk__free(w->referenced);
    sk__free(w->on_boundary);
    sk__free(w->angle_sum);
}

static inline uint32_t next_corner(const sk_soup *s, const work *w, uint32_t c)
{
    uint32_t f = w->cface[c];
    return c + 1 < s->face_offsets[f + 1] ? c + 1 : s->face_offsets[f];
}

static inline uint32_t prev_corner(const sk_soup *s, const work *w, uint32_t c)
{
    uint32_t f = w->cface[c];
    return c > s->face_offsets[f] ? c - 1 : s->face_offsets[f + 1] - 1;
}

/* Face-level checks: sizes, indices, repeats, degeneracy. */
static void check_faces(const sk_soup *s, sk_validation *r, work *w, const uint8_t *vbad)
{
    size_t nv = s->num_vertices;
    for (size_t f = 0; f < s->num_faces; ++f) {
        uint32_t b = s->face_offsets[f], e = s->face_offsets[f + 1], n = e - b;
        const uint32_t *ix = s->face_indices + b;
        for (uint32_t c = b; c < e; ++c)
            w->cface[c] = (uint32_t)f;
        if (n == 3)
            r->triangles++;
        else if (n == 4)
            r->quads++;
        else if (n > 4)
            r->polygons++;
        bool ok = true;
        if (n < 3) {
            note(&r->small_faces, (uint32_t)f, n);
            ok = false;
        }
        for (uint32_t i = 0; i < n; ++i) {
            if (ix[i] >= nv) {
                note(&r->out_of_range, (uint32_t)f, ix[i]);
                ok = false;
                break;
            }
        }
        if (ok) {
            for (uint32_t i = 0; i < n && ok; ++i)
                for (uint32_t j = 0; j < i; ++j)
                    if (ix[i] == ix[j]) {
                        note(&r->repeated_vertex_faces, (uint32_t)f, ix[i]);
                        ok = false;
                        break;
                    }
        }
        for (uint32_t i = 0; ok && i < n; ++i)
            if (vbad[ix[i]])
                ok = false;
        w->face_ok[f] = ok;
        if (!ok)
            continue;
        /* Newell normal against the longest edge (SK_DEGENERATE_REL) */
        double nrm[3] = {0, 0, 0}, emax = 0.0;
        for (uint32_t i = 0; i < n; ++i) {
            const double *p = s->positions + 3 * (size_t)ix[i];
            const double *q = s->positions + 3 * (size_t)ix[(i + 1) % n];
            nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
            nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
            nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
            double l = sk__dist3(p, q);
            emax = l > emax ? l : emax;
        }
        double a2 = sk__norm3(nrm);
        r->area += 0.5 * a2;
        if (a2 <= SK_DEGENERATE_REL * emax * emax)
            note(&r->degenerate_faces, (uint32_t)f, SK_INVALID);
    }
}

static sk_status check_duplicates(const sk_soup *s, sk_validation *r, const work *w)
{
    size_t nf = s->num_faces, maxn = 0, k = 0;
    uint64_t *keys = sk__malloc_array(nf, sizeof(uint64_t));
    uint32_t *ids = sk__malloc_array(nf, sizeof(uint32_t));
    for (size_t f = 0; f < nf; ++f) {
        size_t n = sk_soup_face_size(s, f);
        maxn = n > maxn ? n : maxn;
    }
    uint32_t *ta = sk__malloc_array(2 * maxn + 2, sizeof(uint32_t));
    if (!keys || !ids || !ta) {
        sk__free(keys);
        sk__free(ids);
        sk__free(ta);
        return SK_ERR_NOMEM;
    }
    uint32_t *tb = ta + maxn + 1;
    for (size_t f = 0; f < nf; ++f) {
        if (!w->face_ok[f])
            continue;
        size_t n = sk_soup_face_size(s, f);
        memcpy(ta, s->face_indices + s->face_offsets[f], n * sizeof(uint32_t));
        qsort(ta, n, sizeof(uint32_t), cmp_u32);
        keys[k] = hash_sorted(ta, n);
        ids[k++] = (uint32_t)f;
    }
    sk_status st = sk__sort_u64_u32(keys, ids, k);
    for (size_t i = 0; st == SK_OK && i < k;) {
        size_t j = i + 1;
        while (j < k && keys[j] == keys[i])
            ++j;
        /* within a hash group, compare every face with the earlier ones exactly */
        for (size_t a = i + 1; a < j; ++a) {
            uint32_t fa = ids[a];
            size_t na = sk_soup_face_size(s, fa);
            memcpy(ta, s->face_indices + s->face_offsets[fa], na * sizeof(uint32_t));
            qsort(ta, na, sizeof(uint32_t), cmp_u32);
            for (size_t b = i; b < a; ++b) {
                uint32_t fb = ids[b];
                if (sk_soup_face_size(s, fb) != na)
                    continue;
                memcpy(tb, s->face_indices + s->face_offsets[fb], na * sizeof(uint32_t));
                qsort(tb, na, sizeof(uint32_t), cmp_u32);
                if (memcmp(ta, tb, na * sizeof(uint32_t)) == 0) {
                    note(&r->duplicate_faces, fa > fb ? fa : fb, fa > fb ? fb : fa);
                    break;
                }
            }
        }
        i = j;
    }
    sk__free(keys);
    sk__free(ids);
    sk__free(ta);
    return st;
}

/* Counts boundary loops by walking boundary edges: at a vertex with several outgoing boundary
 * edges (non-manifold), any unused one is taken. comp_loops[c] counts loops per component. */
/* nk: the number of corners in the edge table (only usable faces' corners; the rest of w->keys
 * and w->corner is not initialised). */
static sk_status walk_boundary(const sk_soup *s, sk_validation *r, work *w, size_t nk,
                               const uint32_t *vcomp, long *comp_loops)
{
    size_t nv = s->num_vertices, nc = nk;
    /* boundary directed edges: reverse of the boundary corner's edge, from next(c) to c */
    uint32_t *start = sk__calloc_array(nv + 1, sizeof(uint32_t));
    uint32_t *list = sk__malloc_array(r->boundary_edges + 1, sizeof(uint32_t));
    uint8_t *used = sk__calloc_array(r->boundary_edges + 1, 1);
    if (!start || !list || !used) {
        sk__free(start);
        sk__free(list);
        sk__free(used);
        return SK_ERR_NOMEM;
    }
    for (size_t i = 0; i < nc;) {
        size_t j = i + 1;
        while (j < nc && w->keys[j] == w->keys[i])
            ++j;
        if (j - i == 1)
            start[s->face_indices[next_corner(s, w, w->corner[i])] + 1]++;
        i = j;
    }
    for (size_t v = 0; v < nv; ++v)
        start[v + 1] += start[v];
    uint32_t *fill = sk__malloc_array(nv + 1, sizeof(uint32_t));
    if (!fill) {
        sk__free(start);
        sk__free(list);
        sk__free(used);
        return SK_ERR_NOMEM;
    }
    memcpy(fill, start, (nv + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < nc;) {
        size_t j = i + 1;
        while (j < nc && w->keys[j] == w->keys[i])
            ++j;
        if (j - i == 1) {
            uint32_t c = w->corner[i];
            uint32_t from = s->face_indices[next_corner(s, w, c)];
            list[fill[from]++] = s->face_indices[c]; /* target vertex */
        }
        i = j;
    }
    /* walk: each list slot is one directed boundary edge */
    for (size_t v0 = 0; v0 < nv; ++v0) {
        for (uint32_t k = start[v0]; k < start[v0 + 1]; ++k) {
            if (used[k])
                continue;
            used[k] = 1;
            uint32_t v = list[k];
            while (v != v0) {
                uint32_t t = start[v];
                while (t < start[v + 1] && used[t])
                    ++t;
                if (t == start[v + 1])
                    break; /* open chain (only in non-manifold input) */
                used[t] = 1;
                v = list[t];
            }
            r->boundary_loops++;
            comp_loops[vcomp[v0]]++;
        }
    }
    sk__free(start);
    sk__free(list);
    sk__free(used);
    sk__free(fill);
    return SK_OK;
}

/* The edge table over the corners of usable faces: one key (smaller vertex, larger vertex) per
 * corner's edge, sorted, with the corners in key order; marks the referenced vertices. nk: the
 * number of entries. Returns SK_ERR_NOMEM or SK_OK. */
static sk_status edge_table(const sk_soup *s, work *w, size_t *nk)
{
    size_t k = 0;
    for (size_t f = 0; f < s->num_faces; ++f) {
        if (!w->face_ok[f])
            continue;
        for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; ++c) {
            uint64_t a = s->face_indices[c], b = s->face_indices[next_corner(s, w, c)];
            w->keys[k] = a < b ? a << 32 | b : b << 32 | a;
            w->corner[k++] = c;
            w->referenced[a] = 1;
        }
    }
    *nk = k;
    return sk__sort_u64_u32(w->keys, w->corner, k) ? SK_ERR_NOMEM : SK_OK;
}

/* One pass over the edges: counts, lengths, boundary, non-manifold edges, orientation conflicts;
 * unions the corners of two faces at both ends of every edge they share (the vertex fans). */
static void edge_pass(const sk_soup *s, sk_validation *r, work *w, size_t nk)
{
    for (size_t c = 0; c < s->face_offsets[s->num_faces]; ++c)
        w->parent[c] = (uint32_t)c;
    double lsum = 0.0;
    r->edge_min = DBL_MAX;
    for (size_t i = 0; i < nk;) {
        size_t j = i + 1;
        while (j < nk && w->keys[j] == w->keys[i])
            ++j;
        uint32_t a = (uint32_t)(w->keys[i] >> 32), b = (uint32_t)w->keys[i];
        r->edges++;
        double len = sk__dist3(s->positions + 3 * (size_t)a, s->positions + 3 * (size_t)b);
        lsum += len;
        r->edge_min = len < r->edge_min ? len : r->edge_min;
        r->edge_max = len > r->edge_max ? len : r->edge_max;
        if (j - i == 1) {
            r->boundary_edges++;
            w->on_boundary[a] = w->on_boundary[b] = 1;
        } else if (j - i > 2) {
            note(&r->non_manifold_edges, a, b);
            w->on_boundary[a] = w->on_boundary[b] = 1;
        } else {
            uint32_t c1 = w->corner[i], c2 = w->corner[i + 1];
            if (s->face_indices[c1] == s->face_indices[c2])
                note(&r->orientation_conflicts, a, b);
            uint32_t c1n = next_corner(s, w, c1), c2n = next_corner(s, w, c2);
            /* the corner of each face at a, and at b */
            uint32_t c1a = s->face_indices[c1] == a ? c1 : c1n, c1b = c1a == c1 ? c1n : c1;
            uint32_t c2a = s->face_indices[c2] == a ? c2 : c2n, c2b = c2a == c2 ? c2n : c2;
            sk__uf_union(w->parent, c1a, c2a);
            sk__uf_union(w->parent, c1b, c2b);
        }
        i = j;
    }
    r->edge_mean = r->edges ? lsum / (double)r->edges : 0.0;
    if (!r->edges)
        r->edge_min = 0.0;
}

/* Non-manifold vertices: more than one fan of corners (after edge_pass). */
static sk_status count_fans(const sk_soup *s, sk_validation *r, work *w, size_t nk)
{
    uint32_t *fans = sk__calloc_array(s->num_vertices, sizeof(uint32_t));
    if (!fans)
        return SK_ERR_NOMEM;
    for (size_t i = 0; i < nk; ++i) {
        uint32_t c = w->corner[i]; /* every usable corner appears once in the table */
        if (sk__uf_find(w->parent, c) == c)
            fans[s->face_indices[c]]++;
    }
    for (size_t v = 0; v < s->num_vertices; ++v)
        if (fans[v] > 1)
            note(&r->non_manifold_vertices, (uint32_t)v, fans[v]);
    sk__free(fans);
    return SK_OK;
}

/* Components (faces united with their vertices): vcomp[v] (SK_INVALID for unreferenced
 * vertices, which are noted unless already bad) and r->components. */
static sk_status label_components(const sk_soup *s, sk_validation *r, work *w,
                                  const uint8_t *vbad, uint32_t **vcomp_out)
{
    size_t nv = s->num_vertices, nf = s->num_faces;
    for (size_t i = 0; i < nv + nf; ++i)
        w->parent[i] = (uint32_t)i;
    for (size_t f = 0; f < nf; ++f)
        if (w->face_ok[f])
            for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; ++c)
                sk__uf_union(w->parent, (uint32_t)(nv + f), s->face_indices[c]);
    uint32_t *vcomp = sk__malloc_array(nv + 1, sizeof(uint32_t));
    if (!vcomp)
        return SK_ERR_NOMEM;
    size_t ncomp = 0;
    for (size_t v = 0; v < nv; ++v) {
        if (!w->referenced[v]) {
            vcomp[v] = SK_INVALID;
            if (!vbad[v])
                note(&r->unreferenced_vertices, (uint32_t)v, SK_INVALID);
            continue;
        }
        if (sk__uf_find(w->parent, (uint32_t)v) == v)
            vcomp[v] = (uint32_t)ncomp++;
    }
    for (size_t v = 0; v < nv; ++v)
        if (w->referenced[v])
            vcomp[v] = vcomp[sk__uf_find(w->parent, (uint32_t)v)];
    r->components = ncomp;
    *vcomp_out = vcomp;
    return SK_OK;
}

/* Euler characteristic, boundary loops and genus (per component: 2 - 2g = chi + loops; undefined
 * where a component has a non-manifold edge, or for non-manifold vertices). */
static sk_status euler_and_genus(const sk_soup *s, sk_validation *r, work *w, size_t nk,
                                 const uint32_t *vcomp)
{
    size_t ncomp = r->components;
    long *cchi = sk__calloc_array(ncomp + 1, sizeof(long));
    long *cloops = sk__calloc_array(ncomp + 1, sizeof(long));
    uint8_t *cbad = sk__calloc_array(ncomp + 1, 1);
    sk_status st = SK_OK;
    if (!cchi || !cloops || !cbad) {
        st = SK_ERR_NOMEM;
        goto done;
    }
    size_t nref = 0, nfok = 0;
    for (size_t v = 0; v < s->num_vertices; ++v)
        if (w->referenced[v]) {
            cchi[vcomp[v]]++;
            nref++;
        }
    for (size_t i = 0; i < nk;) {
        size_t j = i + 1;
        while (j < nk && w->keys[j] == w->keys[i])
            ++j;
        uint32_t a = (uint32_t)(w->keys[i] >> 32);
        cchi[vcomp[a]]--;
        if (j - i > 2)
            cbad[vcomp[a]] = 1;
        i = j;
    }
    for (size_t f = 0; f < s->num_faces; ++f)
        if (w->face_ok[f]) {
            cchi[vcomp[s->face_indices[s->face_offsets[f]]]]++;
            nfok++;
        }
    r->euler_characteristic = (long)nref - (long)r->edges + (long)nfok;
    if ((st = walk_boundary(s, r, w, nk, vcomp, cloops)))
        goto done;
    r->genus = 0;
    r->genus_defined = r->non_manifold_vertices.count == 0;
    for (size_t c = 0; c < ncomp; ++c) {
        long twice = 2 - cchi[c] - cloops[c];
        if (cbad[c] || twice < 0 || twice % 2)
            r->genus_defined = false;
        else
            r->genus += twice / 2;
    }
done:
    sk__free(cchi);
    sk__free(cloops);
    sk__free(cbad);
    return st;
}

/* Geometry: bounding box of the referenced vertices, triangle angles, and the angle deficits of
 * Alboul & Echeverria against 2 pi chi (Gauss-Bonnet). */
static void geometry(const sk_soup *s, sk_validation *r, work *w, size_t nk)
{
    size_t nv = s->num_vertices, nref = 0;
    for (int d = 0; d < 3; ++d) {
        r->bbox_min[d] = DBL_MAX;
        r->bbox_max[d] = -DBL_MAX;
    }
    for (size_t v = 0; v < nv; ++v) {
        if (!w->referenced[v])
            continue;
        nref++;
        for (int d = 0; d < 3; ++d) {
            double x = s->positions[3 * v + d];
            r->bbox_min[d] = x < r->bbox_min[d] ? x : r->bbox_min[d];
            r->bbox_max[d] = x > r->bbox_max[d] ? x : r->bbox_max[d];
        }
    }
    if (!nref)
        for (int d = 0; d < 3; ++d)
            r->bbox_min[d] = r->bbox_max[d] = 0.0;
    r->min_angle_deg = nk ? 180.0 : 0.0;
    r->max_angle_deg = 0.0;
    for (size_t i = 0; i < nk; ++i) {
        uint32_t c = w->corner[i];
        uint32_t v = s->face_indices[c];
        const double *p = s->positions + 3 * (size_t)v;
        const double *q = s->positions + 3 * (size_t)s->face_indices[next_corner(s, w, c)];
        const double *o = s->positions + 3 * (size_t)s->face_indices[prev_corner(s, w, c)];
        double e1[3], e2[3];
        sk__sub3(e1, q, p);
        sk__sub3(e2, o, p);
        double ang = sk__angle3(e1, e2);
        w->angle_sum[v] += ang;
        if (sk_soup_face_size(s, w->cface[c]) == 3) {
            double deg = ang * (180.0 / M_PI);
            r->min_angle_deg = deg < r->min_angle_deg ? deg : r->min_angle_deg;
            r->max_angle_deg = deg > r->max_angle_deg ? deg : r->max_angle_deg;
        }
    }
    double deficit = 0.0;
    for (size_t v = 0; v < nv; ++v)
        if (w->referenced[v])
            deficit += (w->on_boundary[v] ? M_PI : 2.0 * M_PI) - w->angle_sum[v];
    r->angle_deficit_sum = deficit;
    r->gauss_bonnet_error = deficit - 2.0 * M_PI * (double)r->euler_characteristic;
}

sk_status sk_soup_validate(const sk_soup *s, sk_validation *r, sk_error *err)
{
    memset(r, 0, sizeof *r);
    size_t nv = s->num_vertices, nf = s->num_faces, nc = s->face_offsets[nf], nk = 0;
    r->vertices = nv;
    r->faces = nf;
    work w = {0};
    uint8_t *vbad = sk__calloc_array(nv, 1);
    uint32_t *vcomp = NULL;
    sk_status st = SK_OK;
    w.face_ok = sk__malloc_array(nf, 1);
    w.cface = sk__malloc_array(nc, sizeof(uint32_t));
    w.keys = sk__malloc_array(nc, sizeof(uint64_t));
    w.corner = sk__malloc_array(nc, sizeof(uint32_t));
    w.parent = sk__malloc_array(nc > nv + nf ? nc : nv + nf, sizeof(uint32_t));
    w.referenced = sk__calloc_array(nv, 1);
    w.on_boundary = sk__calloc_array(nv, 1);
    w.angle_sum = sk__calloc_array(nv, sizeof(double));
    if (!vbad || !w.face_ok || !w.cface || !w.keys || !w.corner || !w.parent || !w.referenced ||
        !w.on_boundary || !w.angle_sum)
        goto nomem;
    for (size_t v = 0; v < nv; ++v) {
        const double *p = s->positions + 3 * v;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            vbad[v] = 1;
            note(&r->nonfinite_vertices, (uint32_t)v, SK_INVALID);
        }
    }
    check_faces(s, r, &w, vbad);
    if (check_duplicates(s, r, &w) || edge_table(s, &w, &nk))
        goto nomem;
    edge_pass(s, r, &w, nk);
    if (count_fans(s, r, &w, nk) || label_components(s, r, &w, vbad, &vcomp) ||
        euler_and_genus(s, r, &w, nk, vcomp))
        goto nomem;
    geometry(s, r, &w, nk);
    goto done;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "out of memory validating the mesh");
done:
    work_free(&w);
    sk__free(vbad);
    sk__free(vcomp);
    return st;
}
