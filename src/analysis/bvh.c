/* Closest points on a triangle set through a bounding-volume hierarchy of axis-aligned boxes.
 *
 * Build: top-down, binned surface-area heuristic over the triangle centroids (SAH_BINS bins along
 * the longest centroid axis; a median split when every centroid falls in one bin), leaves of at
 * most LEAF_SIZE triangles. Nodes are stored in one array, the two children of a node next to
 * each other, triangles reordered so that a leaf owns a contiguous range.
 * Query: depth-first, nearer child first, a subtree skipped when its box is farther than the best
 * distance so far. */
#include "analysis/bvh_internal.h"
#include "core/internal.h"
#include "core/vec.h"
#include "mesh/fan.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LEAF_SIZE = 4, SAH_BINS = 12, MAX_DEPTH = 64 };

typedef struct node {
    double lo[3], hi[3];
    uint32_t first; /* leaf: first triangle; inner: index of the left child (right = first + 1) */
    uint32_t count; /* leaf: number of triangles; inner: 0 */
} node;

struct sk_bvh {
    size_t num_tris;
    double *corners;  /* 9 per triangle, in leaf order */
    uint32_t *face;   /* soup face of each triangle, in leaf order */
    uint32_t *orig;   /* fan-triangle index (before reordering) of each triangle */
    node *nodes;
    size_t num_nodes;
};

/* min / max without fmin's NaN rules (a libm call without -ffinite-math-only); inputs are
 * finite (checked when building) */
static inline double lo2(double a, double b) { return a < b ? a : b; }
static inline double hi2(double a, double b) { return a > b ? a : b; }

typedef struct box {
    double lo[3], hi[3];
} box;

static void box_empty(box *b)
{
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = DBL_MAX;
        b->hi[k] = -DBL_MAX;
    }
}

static void box_add(box *b, const double p[3])
{
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = lo2(b->lo[k], p[k]);
        b->hi[k] = hi2(b->hi[k], p[k]);
    }
}

static void box_merge(box *b, const box *c)
{
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = lo2(b->lo[k], c->lo[k]);
        b->hi[k] = hi2(b->hi[k], c->hi[k]);
    }
}

static double box_area(const box *b)
{
    double d[3];
    for (int k = 0; k < 3; ++k)
        d[k] = hi2(0.0, b->hi[k] - b->lo[k]);
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* Build state: per triangle its box and centroid, and the permutation being partitioned. */
typedef struct builder {
    box *tbox;
    double *centroid; /* 3 per triangle */
    uint32_t *perm;
    node *nodes;
    size_t num_nodes;
} builder;

/* Chooses a split of perm[begin, end) and partitions it; returns the first index of the right
 * half (begin < mid < end). */
static size_t split_range(builder *b, size_t begin, size_t end)
{
    box cb;
    box_empty(&cb);
    for (size_t i = begin; i < end; ++i)
        box_add(&cb, b->centroid + 3 * (size_t)b->perm[i]);
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (cb.hi[k] - cb.lo[k] > cb.hi[axis] - cb.lo[axis])
            axis = k;
    double lo = cb.lo[axis], ext = cb.hi[axis] - lo;
    size_t mid = begin;
    if (ext > 0) {
        box bins[SAH_BINS];
        size_t cnt[SAH_BINS] = {0};
        for (int i = 0; i < SAH_BINS; ++i)
            box_empty(&bins[i]);
        double scale = SAH_BINS / ext;
        for (size_t i = begin; i < end; ++i) {
            uint32_t t = b->perm[i];
            int k = (int)((b->centroid[3 * (size_t)t + axis] - lo) * scale);
            k = k < 0 ? 0 : k >= SAH_BINS ? SAH_BINS - 1 : k;
            cnt[k]++;
            box_merge(&bins[k], &b->tbox[t]);
        }
        /* cost of splitting after bin i: area(left) * n(left) + area(right) * n(right) */
        double right_area[SAH_BINS];
        size_t right_cnt[SAH_BINS];
        box acc;
        box_empty(&acc);
        size_t n = 0;
        for (int i = SAH_BINS - 1; i > 0; --i) {
            box_merge(&acc, &bins[i]);
            n += cnt[i];
            right_area[i] = box_area(&acc);
            right_cnt[i] = n;
        }
        box_empty(&acc);
        n = 0;
        double best = DBL_MAX;
        int best_i = -1;
        for (int i = 0; i < SAH_BINS - 1; ++i) {
            box_merge(&acc, &bins[i]);
            n += cnt[i];
            if (n == 0 || right_cnt[i + 1] == 0)
                continue;
            double cost = box_area(&acc) * (double)n + right_area[i + 1] * (double)right_cnt[i + 1];
            if (cost < best) {
                best = cost;
                best_i = i;
            }
        }
        if (best_i >= 0) {
            size_t i = begin, j = end;
            while (i < j) {
                uint32_t t = b->perm[i];
                int k = (int)((b->centroid[3 * (size_t)t + axis] - lo) * scale);
                k = k < 0 ? 0 : k >= SAH_BINS ? SAH_BINS - 1 : k;
                if (k <= best_i) {
                    ++i;
                } else {
                    b->perm[i] = b->perm[--j];
                    b->perm[j] = t;
                }
            }
            mid = i;
        }
    }
    if (mid <= begin || mid >= end) /* all centroids in one place: split by count */
        mid = begin + (end - begin) / 2;
    return mid;
}

/* n nodes from the builder's array: the index of the first (the nodes of parallel subtree
 * builds interleave; the tree is the same, only where its nodes sit differs) */
static uint32_t take_nodes(builder *b, size_t n)
{
    size_t first;
#if defined(SK_HAVE_OPENMP)
#pragma omp atomic capture
#endif
    {
        first = b->num_nodes;
        b->num_nodes += n;
    }
    return (uint32_t)first;
}

/* the box of the triangles perm[begin, end) into node nd */
static void node_box(builder *b, node *nd, size_t begin, size_t end)
{
    box bb;
    box_empty(&bb);
    for (size_t i = begin; i < end; ++i)
        box_merge(&bb, &b->tbox[b->perm[i]]);
    memcpy(nd->lo, bb.lo, sizeof bb.lo);
    memcpy(nd->hi, bb.hi, sizeof bb.hi);
}

/* Builds the subtree of perm[begin, end) into node index ni (already allocated), depth0 levels
 * under the root. Iterative over an explicit stack so that no input can exhaust the C stack. */
static void build_serial(builder *b, uint32_t ni, size_t begin, size_t end, int depth0)
{
    struct item {
        uint32_t ni;
        size_t begin, end;
    } stack[2 * MAX_DEPTH + 8];
    int top = 0;
    stack[top++] = (struct item){ni, begin, end};
    while (top > 0) {
        struct item it = stack[--top];
        node *nd = &b->nodes[it.ni];
        node_box(b, nd, it.begin, it.end);
        /* the stack holds at most one pending sibling per level: bounded by 2 * depth; ranges
         * that would go deeper become (larger) leaves (build_top's levels above count as one
         * pending sibling each, as they would on one stack) */
        if (it.end - it.begin <= LEAF_SIZE || top + depth0 >= 2 * MAX_DEPTH) {
            nd->first = (uint32_t)it.begin;
            nd->count = (uint32_t)(it.end - it.begin);
            continue;
        }
        size_t mid = split_range(b, it.begin, it.end);
        uint32_t left = take_nodes(b, 2);
        nd->first = left;
        nd->count = 0;
        stack[top++] = (struct item){left + 1, mid, it.end};
        stack[top++] = (struct item){left, it.begin, mid};
    }
}

/* The top of the tree: ranges of more than TASK_TRIS triangles, up to TASK_DEPTH levels, split
 * here and their two halves built as separate OpenMP tasks (disjoint ranges of perm, nodes from
 * take_nodes); below, build_serial. The same tree for any number of threads. */
enum { TASK_TRIS = 16384, TASK_DEPTH = 10 };

static void build_top(builder *b, uint32_t ni, size_t begin, size_t end, int depth)
{
    if (end - begin <= TASK_TRIS || depth >= TASK_DEPTH) {
        build_serial(b, ni, begin, end, depth);
        return;
    }
    node *nd = &b->nodes[ni];
    node_box(b, nd, begin, end);
    size_t mid = split_range(b, begin, end);
    uint32_t left = take_nodes(b, 2);
    nd->first = left;
    nd->count = 0;
#if defined(SK_HAVE_OPENMP)
#pragma omp task default(none) firstprivate(b, left, mid, end, depth)
#endif
    build_top(b, left + 1, mid, end, depth + 1);
    build_top(b, left, begin, mid, depth + 1);
#if defined(SK_HAVE_OPENMP)
#pragma omp taskwait
#endif
}

static void build_tree(builder *b, size_t count)
{
    b->num_nodes = 1;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel if (count > TASK_TRIS)
#pragma omp single
#endif
    build_top(b, 0, 0, count, 0);
}

/* Fan triangles of the soup: count, and checks. */
static sk_status count_triangles(const sk_soup *s, size_t *out, sk_error *err)
{
    size_t n = 0;
    for (size_t v = 0; v < s->num_vertices; ++v)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(s->positions[3 * v + k]))
                return sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu has a non-finite coordinate", v);
    for (size_t f = 0; f < s->num_faces; ++f) {
        size_t m = sk_soup_face_size(s, f);
        if (m < 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has %zu corners", f, m);
        for (size_t c = 0; c < m; ++c) {
            uint32_t v = s->face_indices[s->face_offsets[f] + c];
            if (v >= s->num_vertices)
                return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has index %u but there are %zu vertices",
                                f, v, s->num_vertices);
        }
        n += m - 2;
    }
    if (n == 0)
        return sk__fail(err, SK_ERR_TOPOLOGY, "no faces");
    if (n >= UINT32_MAX / 2)
        return sk__fail(err, SK_ERR_ARG, "too many triangles (%zu)", n);
    *out = n;
    return SK_OK;
}

sk_status sk_bvh_build(const sk_soup *soup, sk_bvh **out, sk_error *err)
{
    *out = NULL;
    size_t nt = 0;
    sk_status st = count_triangles(soup, &nt, err);
    if (st)
        return st;
    builder b = {0};
    uint32_t *tri = NULL, *face = NULL;
    sk_bvh *t = NULL;
    if ((st = sk__soup_fan_triangles(soup, &tri, &face, &nt, err)) != SK_OK)
        goto done;
    /* Peak memory is the point here (the continuity report builds this over a fine
     * tessellation): the corners are copied from the soup once, in leaf order, and the boxes and
     * centroids are freed before that copy is made. */
    t = sk__calloc_array(1, sizeof *t);
    b.tbox = sk__malloc_array(nt, sizeof *b.tbox);
    b.centroid = sk__malloc_array(3 * nt, sizeof *b.centroid);
    b.perm = sk__malloc_array(nt, sizeof *b.perm);
    b.nodes = sk__malloc_array(2 * nt, sizeof *b.nodes);
    if (!t || !b.tbox || !b.centroid || !b.perm || !b.nodes) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < nt; ++i) {
        box_empty(&b.tbox[i]);
        for (int k = 0; k < 3; ++k)
            box_add(&b.tbox[i], soup->positions + 3 * (size_t)tri[3 * i + (size_t)k]);
        for (int k = 0; k < 3; ++k)
            b.centroid[3 * i + k] = 0.5 * (b.tbox[i].lo[k] + b.tbox[i].hi[k]);
        b.perm[i] = (uint32_t)i;
    }
    build_tree(&b, nt);
    sk__free(b.tbox);
    sk__free(b.centroid);
    b.tbox = NULL;
    b.centroid = NULL;
    if (b.num_nodes < 2 * nt) { /* give back the unused nodes (a shrink; keep them if it fails) */
        node *fit = sk__realloc_array(b.nodes, b.num_nodes, sizeof *b.nodes);
        if (fit)
            b.nodes = fit;
    }
    /* the triangles in leaf order */
    t->corners = sk__malloc_array(9 * nt, sizeof *t->corners);
    t->face = sk__malloc_array(nt, sizeof *t->face);
    if (!t->corners || !t->face) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t j = 0; j < nt; ++j) {
        const uint32_t *v = tri + 3 * (size_t)b.perm[j];
        for (int k = 0; k < 3; ++k)
            memcpy(t->corners + 9 * j + 3 * k, soup->positions + 3 * (size_t)v[k],
                   3 * sizeof *t->corners);
        t->face[j] = face[b.perm[j]];
    }
    t->num_tris = nt;
    t->nodes = b.nodes;
    t->num_nodes = b.num_nodes;
    t->orig = b.perm;
    b.nodes = NULL;
    b.perm = NULL;
    *out = t;
    t = NULL;
done:
    sk__free(tri);
    sk__free(face);
    sk__free(b.tbox);
    sk__free(b.centroid);
    sk__free(b.perm);
    sk__free(b.nodes);
    sk_bvh_destroy(&t);
    return st;
}

void sk_bvh_destroy(sk_bvh **bvh)
{
    if (!bvh || !*bvh)
        return;
    sk_bvh *t = *bvh;
    sk__free(t->corners);
    sk__free(t->face);
    sk__free(t->orig);
    sk__free(t->nodes);
    sk__free(t);
    *bvh = NULL;
}

size_t sk_bvh_triangles(const sk_bvh *bvh) { return bvh->num_tris; }

/* Closest point to p on the triangle (a, b, c), by the Voronoi region of p: a vertex region, an
 * edge region, or the face (barycentric coordinates from the areas). Returns the squared
 * distance. Degenerate triangles fall into vertex or edge regions and stay correct. */
static double closest_on_triangle(const double p[3], const double a[3], const double b[3],
                                  const double c[3], double q[3])
{
    double ab[3], ac[3], ap[3];
    sk__sub3(ab, b, a);
    sk__sub3(ac, c, a);
    sk__sub3(ap, p, a);
    double d1 = sk__dot3(ab, ap), d2 = sk__dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) { /* vertex a */
        memcpy(q, a, 3 * sizeof *q);
        return sk__dot3(ap, ap);
    }
    double bp[3];
    sk__sub3(bp, p, b);
    double d3 = sk__dot3(ab, bp), d4 = sk__dot3(ac, bp);
    double dd[3];
    if (d3 >= 0 && d4 <= d3) { /* vertex b */
        memcpy(q, b, 3 * sizeof *q);
        return sk__dot3(bp, bp);
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge ab */
        double s = d1 / (d1 - d3);
        sk__axpy3(q, a, s, ab);
        goto edge;
    }
    double cp[3];
    sk__sub3(cp, p, c);
    double d5 = sk__dot3(ab, cp), d6 = sk__dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) { /* vertex c */
        memcpy(q, c, 3 * sizeof *q);
        return sk__dot3(cp, cp);
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge ac */
        double s = d2 / (d2 - d6);
        sk__axpy3(q, a, s, ac);
        goto edge;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) { /* edge bc */
        double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        double bc[3];
        sk__sub3(bc, c, b);
        sk__axpy3(q, b, s, bc);
        goto edge;
    }
    { /* inside the face */
        double sum = va + vb + vc;
        if (!(sum > 0)) { /* degenerate: the nearest of the three edges' end points */
            double da = sk__dot3(ap, ap), db = sk__dot3(bp, bp), dc = sk__dot3(cp, cp);
            const double *m = da <= db && da <= dc ? a : db <= dc ? b : c;
            memcpy(q, m, 3 * sizeof *q);
            return fmin(da, fmin(db, dc));
        }
        double v = vb / sum, w = vc / sum;
        for (int k = 0; k < 3; ++k)
            q[k] = a[k] + v * ab[k] + w * ac[k];
    }
edge:
    sk__sub3(dd, p, q);
    return sk__dot3(dd, dd);
}

static double box_dist2(const node *n, const double p[3])
{
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        double d = p[k] < n->lo[k] ? n->lo[k] - p[k] : p[k] > n->hi[k] ? p[k] - n->hi[k] : 0.0;
        d2 += d * d;
    }
    return d2;
}

/* Pushes the children of the inner node n that are nearer than best, the farther first so that
 * the nearer is visited first. */
static void push_children(const sk_bvh *t, const node *n, const double p[3], double best,
                          uint32_t *stack, int *top)
{
    uint32_t near = n->first, far = near + 1;
    double dn = box_dist2(&t->nodes[near], p), df = box_dist2(&t->nodes[far], p);
    if (dn > df) {
        near = far--;
        double d = dn;
        dn = df;
        df = d;
    }
    if (df < best)
        stack[(*top)++] = far;
    if (dn < best)
        stack[(*top)++] = near;
}

/* The triangles of the leaf n nearer than *best: *best (squared) and *bt updated */
static void scan_leaf(const sk_bvh *t, const node *n, const double p[3], double *best,
                      uint32_t *bt)
{
    double q[3];
    for (uint32_t i = n->first; i < n->first + n->count; ++i) {
        const double *c = t->corners + 9 * (size_t)i;
        double d2 = closest_on_triangle(p, c, c + 3, c + 6, q);
        if (d2 < *best) {
            *best = d2;
            *bt = i;
        }
    }
}

void sk_bvh_closest(const sk_bvh *t, const double p[3], sk_closest *out)
{
    uint32_t stack[2 * MAX_DEPTH + 8];
    int top = 0;
    double best = DBL_MAX, bq[3] = {0, 0, 0};
    uint32_t bt = 0;
    stack[top++] = 0;
    while (top > 0) {
        const node *n = &t->nodes[stack[--top]];
        if (box_dist2(n, p) >= best)
            continue;
        if (n->count) {
            scan_leaf(t, n, p, &best, &bt);
            continue;
        }
        push_children(t, n, p, best, stack, &top);
    }
    if (best < DBL_MAX) { /* the point on the nearest triangle */
        const double *c = t->corners + 9 * (size_t)bt;
        closest_on_triangle(p, c, c + 3, c + 6, bq);
    }
    out->distance = sqrt(best);
    memcpy(out->point, bq, sizeof bq);
    out->face = t->face[bt];
    out->triangle = t->orig[bt];
}

double sk__bvh_distance_capped(const sk_bvh *t, const double p[3], double cap, uint32_t *hint,
                               uint32_t *face)
{
    uint32_t stack[2 * MAX_DEPTH + 8];
    int top = 0;
    double best = DBL_MAX, cap2 = cap * cap, q[3];
    uint32_t bt = 0;
    if (t->num_tris == 0) {
        *hint = SK_INVALID;
        if (face)
            *face = SK_INVALID;
        return DBL_MAX;
    }
    if (*hint < t->num_tris) {
        const double *c = t->corners + 9 * (size_t)*hint;
        best = closest_on_triangle(p, c, c + 3, c + 6, q);
        bt = *hint;
    }
    if (best > cap2)
        stack[top++] = 0;
    while (top > 0) {
        const node *n = &t->nodes[stack[--top]];
        if (box_dist2(n, p) >= best)
            continue;
        if (!n->count) {
            push_children(t, n, p, best, stack, &top);
            continue;
        }
        scan_leaf(t, n, p, &best, &bt);
        if (best <= cap2)
            break;
    }
    *hint = bt;
    if (face)
        *face = t->face[bt];
    return sqrt(best);
}

double sk_bvh_distance(void *bvh, const double p[3])
{
    sk_closest c;
    sk_bvh_closest(bvh, p, &c);
    return c.distance;
}

int sk__bvh_overlaps(const sk_bvh *t, const double lo[3], const double hi[3], sk__bvh_visit fn,
                     void *user)
{
    uint32_t stack[2 * MAX_DEPTH + 8];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const node *n = &t->nodes[stack[--top]];
        if (n->lo[0] > hi[0] || n->lo[1] > hi[1] || n->lo[2] > hi[2] || n->hi[0] < lo[0] ||
            n->hi[1] < lo[1] || n->hi[2] < lo[2])
            continue;
        if (!n->count) {
            stack[top++] = n->first + 1;
            stack[top++] = n->first;
            continue;
        }
        for (uint32_t i = n->first; i < n->first + n->count; ++i) {
            const double *c = t->corners + 9 * (size_t)i;
            bool apart = false;
            for (int k = 0; k < 3 && !apart; ++k)
                apart = lo2(c[k], lo2(c[3 + k], c[6 + k])) > hi[k] ||
                        hi2(c[k], hi2(c[3 + k], c[6 + k])) < lo[k];
            if (!apart && fn(user, c, t->face[i]))
                return 1;
        }
    }
    return 0;
}
