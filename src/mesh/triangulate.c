/* Triangulation of the polygons of a soup (sk_soup_triangulate): quads by their shorter
 * diagonal, larger polygons by ear clipping in the plane of their Newell normal. */
#include "surfkit/mesh.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

/* above this size a polygon takes the first ear found instead of the one with the shortest
 * diagonal (which costs a scan of all corners per ear) */
#define SK__EAR_SEARCH_MAX 64

/* The edges of the input and the diagonals made so far, in an open-addressing hash set: a
 * diagonal that is already an edge (a quad whose opposite corners are joined outside it, or two
 * quads that share two sides and would both take the diagonal between them) would make that edge
 * non-manifold. */
typedef struct edge_set {
    uint64_t *keys; /* UINT64_MAX: empty */
    size_t mask;
} edge_set;

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

static size_t slot_of(const edge_set *e, uint64_t k)
{
    size_t i = (size_t)((k * 0x9E3779B97F4A7C15ull) >> 17) & e->mask;
    while (e->keys[i] != UINT64_MAX && e->keys[i] != k)
        i = (i + 1) & e->mask;
    return i;
}

static bool has_edge(const edge_set *e, uint32_t a, uint32_t b)
{
    return e->keys[slot_of(e, edge_key(a, b))] != UINT64_MAX;
}

static void add_edge(edge_set *e, uint32_t a, uint32_t b)
{
    uint64_t k = edge_key(a, b);
    e->keys[slot_of(e, k)] = k;
}

/* room for every corner's edge and every diagonal, at most half full */
static sk_status edge_set_build(const sk_soup *s, size_t diagonals, edge_set *e)
{
    size_t need = 2 * (s->face_offsets[s->num_faces] + diagonals) + 16, cap = 16;
    while (cap < need)
        cap *= 2;
    e->mask = cap - 1;
    e->keys = sk__malloc_array(cap, sizeof *e->keys);
    if (!e->keys)
        return SK_ERR_NOMEM;
    memset(e->keys, 0xff, cap * sizeof *e->keys);
    for (size_t f = 0; f < s->num_faces; ++f) {
        const uint32_t *idx = s->face_indices + s->face_offsets[f];
        size_t m = sk_soup_face_size(s, f);
        for (size_t i = 0; m >= 2 && i < m; ++i)
            add_edge(e, idx[i], idx[(i + 1) % m]);
    }
    return SK_OK;
}

static double dist2(const double *p, uint32_t a, uint32_t b)
{
    double d = 0;
    for (int k = 0; k < 3; ++k)
        d += (p[3 * a + k] - p[3 * b + k]) * (p[3 * a + k] - p[3 * b + k]);
    return d;
}

/* twice the signed area of (a, b, c) in the plane */
static double orient(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* The polygon's corners projected to the plane of its Newell normal, counter-clockwise. */
static void project(const double *pos, const uint32_t *idx, size_t n, double *xy)
{
    double nn[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
        const double *p = pos + 3 * idx[i], *q = pos + 3 * idx[(i + 1) % n];
        nn[0] += (p[1] - q[1]) * (p[2] + q[2]);
        nn[1] += (p[2] - q[2]) * (p[0] + q[0]);
        nn[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    /* u: perpendicular to the normal's largest component's axis pair; v = n x u */
    int big = fabs(nn[0]) > fabs(nn[1]) ? (fabs(nn[0]) > fabs(nn[2]) ? 0 : 2)
                                        : (fabs(nn[1]) > fabs(nn[2]) ? 1 : 2);
    double u[3] = {0, 0, 0};
    u[(big + 1) % 3] = nn[big];
    u[big] = -nn[(big + 1) % 3];
    double v[3] = {nn[1] * u[2] - nn[2] * u[1], nn[2] * u[0] - nn[0] * u[2],
                   nn[0] * u[1] - nn[1] * u[0]};
    for (size_t i = 0; i < n; ++i) {
        const double *p = pos + 3 * idx[i];
        xy[2 * i] = p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
        xy[2 * i + 1] = p[0] * v[0] + p[1] * v[1] + p[2] * v[2];
    }
}

/* Whether corner ring[k] of the remaining polygon (m corners) is an ear: convex, and no other
 * remaining corner inside or on its triangle. */
static bool is_ear(const double *xy, const uint32_t *ring, size_t m, size_t k)
{
    const double *a = xy + 2 * ring[(k + m - 1) % m], *b = xy + 2 * ring[k],
                 *c = xy + 2 * ring[(k + 1) % m];
    if (!(orient(a, b, c) > 0))
        return false;
    for (size_t j = 0; j < m; ++j) {
        if (j == k || j == (k + 1) % m || j == (k + m - 1) % m)
            continue;
        const double *p = xy + 2 * ring[j];
        if (p == a || p == b || p == c)
            continue;
        if (orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0)
            return false;
    }
    return true;
}

/* Triangles of polygon idx[0..n) as corner numbers 0..n-1, 3 (n - 2) of them into tri. Ear
 * clipping; a polygon that is not simple in its plane (no ear left) is finished as a fan. */
static void clip_ears(const double *pos, const uint32_t *idx, size_t n, edge_set *edges,
                      double *xy, uint32_t *ring, uint32_t *tri)
{
    project(pos, idx, n, xy);
    for (size_t i = 0; i < n; ++i)
        ring[i] = (uint32_t)i;
    size_t m = n, t = 0, start = 0;
    while (m > 3) {
        /* the best ear whose diagonal is no edge yet, else the best ear */
        size_t best = SIZE_MAX, best_any = SIZE_MAX;
        double best_d = INFINITY, best_any_d = INFINITY;
        for (size_t s = 0; s < m; ++s) {
            size_t k = (start + s) % m;
            if (!is_ear(xy, ring, m, k))
                continue;
            uint32_t a = idx[ring[(k + m - 1) % m]], b = idx[ring[(k + 1) % m]];
            double d = dist2(pos, a, b);
            if (d < best_any_d)
                best_any = k, best_any_d = d;
            if (d < best_d && !has_edge(edges, a, b))
                best = k, best_d = d;
            if (n > SK__EAR_SEARCH_MAX && best != SIZE_MAX)
                break;
        }
        if (best == SIZE_MAX)
            best = best_any;
        if (best == SIZE_MAX)
            break; /* not simple: a fan of what is left */
        tri[t++] = ring[(best + m - 1) % m];
        tri[t++] = ring[best];
        tri[t++] = ring[(best + 1) % m];
        add_edge(edges, idx[ring[(best + m - 1) % m]], idx[ring[(best + 1) % m]]);
        memmove(ring + best, ring + best + 1, (m - best - 1) * sizeof *ring);
        --m;
        start = best < m ? best : 0;
    }
    for (size_t i = 1; i + 1 < m; ++i) {
        tri[t++] = ring[0];
        tri[t++] = ring[i];
        tri[t++] = ring[i + 1];
        if (i > 1)
            add_edge(edges, idx[ring[0]], idx[ring[i]]);
    }
}

/* Triangles of face f as corner numbers into tri; the count of triangles. Faces that are not
 * polygons with valid indices are left as they are (one "triangle" of all their corners). */
static size_t split_face(const sk_soup *s, size_t f, edge_set *edges, double *xy,
                         uint32_t *ring, uint32_t *tri, sk_triangulate_stats *st)
{
    const uint32_t *idx = s->face_indices + s->face_offsets[f];
    size_t n = sk_soup_face_size(s, f);
    bool valid = n > 3;
    for (size_t i = 0; valid && i < n; ++i)
        valid = idx[i] < s->num_vertices;
    if (!valid) {
        for (size_t i = 0; i < n; ++i)
            tri[i] = (uint32_t)i;
        return 0;
    }
    if (n == 4) { /* the shorter diagonal, unless it is an edge already and the other is not */
        static const uint32_t d02[6] = {0, 1, 2, 0, 2, 3}, d13[6] = {1, 2, 3, 1, 3, 0};
        bool first = dist2(s->positions, idx[0], idx[2]) <= dist2(s->positions, idx[1], idx[3]);
        bool e02 = has_edge(edges, idx[0], idx[2]), e13 = has_edge(edges, idx[1], idx[3]);
        if (e02 != e13)
            first = !e02;
        memcpy(tri, first ? d02 : d13, sizeof d02);
        add_edge(edges, idx[first ? 0 : 1], idx[first ? 2 : 3]);
        st->quads++;
    } else {
        clip_ears(s->positions, idx, n, edges, xy, ring, tri);
        st->polygons++;
    }
    st->triangles += n - 2;
    return n - 2;
}

/* The faces of s into out, polygons split; src[c] = the corner of s that corner c of out is. */
static sk_status push_faces(const sk_soup *s, sk_soup *out, uint32_t *src, size_t max_n,
                            size_t corners, sk_triangulate_stats *st, sk_error *err)
{
    edge_set edges = {NULL, 0};
    sk_status rc = edge_set_build(s, corners / 3, &edges);
    double *xy = sk__malloc_array(2 * max_n + 2, sizeof *xy);
    uint32_t *ring = sk__malloc_array(max_n + 1, sizeof *ring);
    uint32_t *tri = sk__malloc_array(3 * max_n + 3, sizeof *tri);
    if (rc || !xy || !ring || !tri) {
        rc = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto cleanup;
    }
    size_t c = 0;
    for (size_t f = 0; f < s->num_faces && rc == SK_OK; ++f) {
        const uint32_t first = s->face_offsets[f];
        size_t ntri = split_face(s, f, &edges, xy, ring, tri, st);
        size_t groups = ntri ? ntri : 1, size = ntri ? 3 : sk_soup_face_size(s, f);
        for (size_t t = 0; t < groups && rc == SK_OK; ++t) {
            uint32_t v[3];
            for (size_t k = 0; k < size; ++k) {
                src[c++] = first + tri[t * size + k];
                if (size == 3)
                    v[k] = s->face_indices[first + tri[t * 3 + k]];
            }
            rc = size == 3 ? sk_soup_push_face(out, v, 3)
                           : sk_soup_push_face(out, s->face_indices + first, size);
        }
    }
    if (rc)
        rc = sk__fail(err, rc, "out of memory");
cleanup:
    sk__free(tri);
    sk__free(ring);
    sk__free(xy);
    sk__free(edges.keys);
    return rc;
}

/* corner attribute of out: old[src[c]] */
static uint32_t *remap(const uint32_t *old, const uint32_t *src, size_t n)
{
    uint32_t *m = sk__malloc_array(n + 1, sizeof *m);
    for (size_t c = 0; m && c < n; ++c)
        m[c] = old[src[c]];
    return m;
}

sk_status sk_soup_triangulate(const sk_soup *soup, sk_soup **out, sk_triangulate_stats *stats,
                              sk_error *err)
{
    sk_triangulate_stats st = {0, 0, 0};
    if (!out)
        return sk__fail(err, SK_ERR_ARG, "no output soup");
    *out = NULL;
    if (!soup)
        return sk__fail(err, SK_ERR_ARG, "no soup");
    size_t corners = 0, max_n = 3;
    for (size_t f = 0; f < soup->num_faces; ++f) {
        size_t n = sk_soup_face_size(soup, f);
        corners += n > 3 ? 3 * (n - 2) : n;
        max_n = n > max_n ? n : max_n;
    }
    sk_soup *t = NULL;
    uint32_t *src = NULL, *cuv = NULL, *cn = NULL;
    sk_status rc = sk_soup_create(soup->num_vertices, corners / 3 + 1, corners,
                                  soup->normals != NULL, soup->uvs != NULL, &t, err);
    if (rc)
        goto cleanup;
    for (size_t v = 0; v < soup->num_vertices && rc == SK_OK; ++v)
        rc = sk_soup_push_vertex(t, soup->positions + 3 * v,
                                 soup->normals ? soup->normals + 3 * v : NULL,
                                 soup->uvs ? soup->uvs + 2 * v : NULL);
    if (rc) {
        rc = sk__fail(err, rc, "out of memory");
        goto cleanup;
    }
    src = sk__malloc_array(corners + 1, sizeof *src);
    if (!src) {
        rc = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto cleanup;
    }
    if ((rc = push_faces(soup, t, src, max_n, corners, &st, err)) != SK_OK)
        goto cleanup;
    corners = t->face_offsets[t->num_faces]; /* what was pushed */
    if ((soup->corner_uv && !(cuv = remap(soup->corner_uv, src, corners))) ||
        (soup->corner_normal && !(cn = remap(soup->corner_normal, src, corners)))) {
        rc = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto cleanup;
    }
    if (cuv && (rc = sk_soup_set_corner_uvs(t, soup->num_wedge_uvs, soup->wedge_uvs, cuv)) != SK_OK)
        rc = sk__fail(err, rc, "corner uvs: %s", sk_status_string(rc));
    if (!rc && cn &&
        (rc = sk_soup_set_corner_normals(t, soup->num_wedge_normals, soup->wedge_normals, cn)))
        rc = sk__fail(err, rc, "corner normals: %s", sk_status_string(rc));
cleanup:
    sk__free(cn);
    sk__free(cuv);
    sk__free(src);
    if (rc)
        sk_soup_destroy(&t);
    *out = t;
    if (stats)
        *stats = st;
    return rc;
}
