/* Geometric nested dissection (George's nested dissection with separators found by coordinate
 * bisection): each part of the points of the unknowns is cut by a plane across its principal
 * axis or one of the coordinate axes, placed between the part's 35% and 65% quantiles where it
 * cuts the fewest edges relative to its balance (or by breadth-first levels when those give a
 * smaller separator); the vertices of the side with fewer of them that touch the other side form
 * the separator, both halves are ordered recursively and the separator after them. The
 * dissection tree only constrains the order: each leaf part and each separator is one
 * constraint set, numbered in postorder, and CHOLMOD's constrained minimum degree (CAMD) orders
 * within the sets (as CHOLMOD's own nested dissection does after its METIS partitions). For the
 * matrices of a surface mesh (a planar-like graph with O(sqrt n) separators) the geometry
 * replaces the graph partitioning. */
#include "surfkit/solve.h"
#include "core/internal.h"
#include "solve/solver_internal.h"

#include <cholmod.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Parts of at most this many points are not split further (their fill is negligible). */
#define SK_ND_LEAF 256
/* Candidate cut planes per direction (see plane_position). */
#define SK_ND_BINS 256

typedef struct nd_ctx {
    const double *xyz;   /* 3 per point */
    const size_t *adj_ptr;
    const uint32_t *adj;
    uint32_t *label;     /* per point: stamp of the side it is on in the current split */
    uint32_t stamp;
    double *key;         /* scratch, per point of the current part */
    uint32_t *tmp;       /* scratch, per point of the current part */
    uint32_t *level;     /* per point: breadth-first level */
    uint16_t *first;     /* SK_ND_DIRECTIONS per point: its first plane above (plane_positions) */
    size_t *hist;        /* 2 SK_ND_DIRECTIONS (SK_ND_BINS + 1) counts: points, cut edges */
    int *cmember;        /* per point: its constraint set (leaf or separator, postorder) */
    int ncomp;
} nd_ctx;

static void emit(nd_ctx *c, const uint32_t *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        c->cmember[v[i]] = c->ncomp;
    c->ncomp++;
}

/* Reorders v[0..n) so that v[k] has the k-th smallest key (keys move along); ties by index. */
static void select_kth(uint32_t *v, double *key, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (hi > lo) {
        size_t mid = lo + (hi - lo) / 2;
        /* median of three as pivot */
        double a = key[lo], b = key[mid], c = key[hi];
        double piv = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
        size_t i = lo, j = hi;
        while (i <= j) {
            while (key[i] < piv)
                i++;
            while (key[j] > piv)
                j--;
            if (i <= j) {
                double tk = key[i];
                key[i] = key[j];
                key[j] = tk;
                uint32_t tv = v[i];
                v[i] = v[j];
                v[j] = tv;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

/* Moves the points of v[0..n) whose flag is want to the front; returns their count. */
static size_t partition_by(uint32_t *v, size_t n, uint8_t *flag, uint8_t want)
{
    size_t q = 0;
    for (size_t i = 0; i < n; ++i)
        if (flag[i] == want) {
            uint32_t t = v[q];
            v[q] = v[i];
            v[i] = t;
            uint8_t tf = flag[q]; /* flags travel with their points */
            flag[q] = flag[i];
            flag[i] = tf;
            q++;
        }
    return q;
}

/* flag: 0 left, 1 right, 2 left touching right, 3 right touching left (sides by label) */
static void mark_touching(nd_ctx *c, const uint32_t *v, uint8_t *flag, size_t n, uint32_t left,
                          uint32_t right, size_t touch[2])
{
    touch[0] = touch[1] = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t p = v[i], other = c->label[p] == left ? right : left;
        int side = c->label[p] == right;
        flag[i] = (uint8_t)side;
        for (size_t e = c->adj_ptr[p]; e < c->adj_ptr[p + 1]; ++e)
            if (c->label[c->adj[e]] == other) {
                flag[i] = (uint8_t)(2 + side);
                touch[side]++;
                break;
            }
    }
}

/* The split directions: the part's principal axis and the three coordinate axes. */
#define SK_ND_DIRECTIONS 4
static double along(const double *p, const double *d)
{
    return d[0] * p[0] + d[1] * p[1] + d[2] * p[2];
}

/* The principal axis of the part's points (largest eigenvector of their covariance, by power
 * iteration from the longest bounding-box axis). */
static void principal_axis(const nd_ctx *c, const uint32_t *v, size_t n, double d[3])
{
    double mean[3] = {0, 0, 0}, cov[6] = {0, 0, 0, 0, 0, 0}, lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double x = c->xyz[3 * (size_t)v[i] + k];
            mean[k] += x;
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
    for (int k = 0; k < 3; ++k)
        mean[k] /= (double)n;
    for (size_t i = 0; i < n; ++i) {
        const double *p = c->xyz + 3 * (size_t)v[i];
        double x = p[0] - mean[0], y = p[1] - mean[1], z = p[2] - mean[2];
        cov[0] += x * x;
        cov[1] += x * y;
        cov[2] += x * z;
        cov[3] += y * y;
        cov[4] += y * z;
        cov[5] += z * z;
    }
    int axis = hi[1] - lo[1] > hi[0] - lo[0] ? 1 : 0;
    axis = hi[2] - lo[2] > hi[axis] - lo[axis] ? 2 : axis;
    d[0] = axis == 0;
    d[1] = axis == 1;
    d[2] = axis == 2;
    for (int it = 0; it < 30; ++it) {
        double e[3] = {cov[0] * d[0] + cov[1] * d[1] + cov[2] * d[2],
                       cov[1] * d[0] + cov[3] * d[1] + cov[4] * d[2],
                       cov[2] * d[0] + cov[4] * d[1] + cov[5] * d[2]};
        double len = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (!(len > 0))
            return;
        for (int k = 0; k < 3; ++k)
            d[k] = e[k] / len;
    }
}

/* Where to cut the part v[0..n) across each of the SK_ND_DIRECTIONS directions dirs (one pass
 * over the part's edges for all of them): of SK_ND_BINS planes evenly spaced over the part's
 * extent, the one between its 35% and 65% quantiles that cuts the fewest edges of the part
 * relative to its balance (cut edges / (4 nl nr / n^2): a cut through a sparser region of a
 * non-uniform mesh beats the median's). at[d]: the plane's position, score[d] its score
 * (INFINITY when no plane is in that range; at[d] is the median then). */
static void plane_positions(nd_ctx *c, const uint32_t *v, size_t n,
                            double dirs[SK_ND_DIRECTIONS][3], double at[SK_ND_DIRECTIONS],
                            double score[SK_ND_DIRECTIONS])
{
    enum { D = SK_ND_DIRECTIONS, B = SK_ND_BINS };
    uint32_t part = c->stamp++;
    double lo[D], h[D];
    for (int d = 0; d < D; ++d) {
        lo[d] = INFINITY;
        h[d] = -INFINITY; /* the largest key, then the spacing */
    }
    for (size_t i = 0; i < n; ++i) {
        c->label[v[i]] = part;
        for (int d = 0; d < D; ++d) {
            double x = along(c->xyz + 3 * (size_t)v[i], dirs[d]);
            lo[d] = fmin(lo[d], x);
            h[d] = fmax(h[d], x);
        }
    }
    for (int d = 0; d < D; ++d)
        h[d] = (h[d] - lo[d]) / B;
    /* plane j at lo + j h (j = 1..B - 1); first[p]: the first plane above p; below[j]: the
     * points whose first plane is j; cut[j] by differences: an edge is cut by the planes from
     * its lower end's first plane up to (not including) its upper end's */
    uint16_t *first = c->first;
    size_t(*below)[B + 1] = (size_t(*)[B + 1])c->hist, (*cut)[B + 1] = below + D;
    memset(c->hist, 0, 2 * D * (B + 1) * sizeof *c->hist);
    for (size_t i = 0; i < n; ++i)
        for (int d = 0; d < D; ++d) {
            double x = along(c->xyz + 3 * (size_t)v[i], dirs[d]);
            double f = h[d] > 0 ? floor((x - lo[d]) / h[d]) + 1 : 1;
            first[D * (size_t)v[i] + d] = f < 1 ? 1 : f > B ? B : (uint16_t)f;
        }
    for (size_t i = 0; i < n; ++i) {
        uint32_t p = v[i];
        const uint16_t *fp = first + D * (size_t)p;
        for (int d = 0; d < D; ++d)
            below[d][fp[d]]++;
        for (size_t e = c->adj_ptr[p]; e < c->adj_ptr[p + 1]; ++e) {
            uint32_t q = c->adj[e];
            if (c->label[q] != part)
                continue;
            const uint16_t *fq = first + D * (size_t)q;
            for (int d = 0; d < D; ++d)
                if (fq[d] > fp[d]) {
                    cut[d][fp[d]]++;
                    cut[d][fq[d]]--;
                }
        }
    }
    for (int d = 0; d < D; ++d) {
        score[d] = INFINITY;
        size_t nl = 0, nc = 0;
        for (size_t j = 1; j < B; ++j) {
            nl += below[d][j];
            nc += cut[d][j];
            if (20 * nl < 7 * n || 20 * nl > 13 * n)
                continue;
            double sc = (double)nc * (double)n * (double)n / (4.0 * (double)nl * (double)(n - nl));
            if (sc < score[d]) {
                score[d] = sc;
                at[d] = lo[d] + (double)j * h[d];
            }
        }
        if (score[d] == INFINITY) { /* the median by selection */
            for (size_t i = 0; i < n; ++i) {
                c->key[i] = along(c->xyz + 3 * (size_t)v[i], dirs[d]);
                c->tmp[i] = v[i];
            }
            select_kth(c->tmp, c->key, n, n / 2);
            at[d] = c->key[n / 2];
        }
    }
}

/* Splits the part v[0..n) by the plane along(x, dir) = *med, points below it on the left (ties
 * on the side that keeps both sides non-empty); flag: 0 left, 1 right, 2 left touching right,
 * 3 right touching left; touch: how many of each side touch the other. Returns the number of
 * points on the left. */
static size_t split(nd_ctx *c, const uint32_t *v, uint8_t *flag, size_t n, const double *dir,
                    const double *med, size_t touch[2])
{
    size_t below = 0;
    for (size_t i = 0; i < n; ++i)
        below += along(c->xyz + 3 * (size_t)v[i], dir) < *med;
    bool ties_left = below == 0; /* every point at or above the median: ties go left */
    uint32_t left = c->stamp++, right = c->stamp++;
    size_t nleft = 0;
    for (size_t i = 0; i < n; ++i) {
        double x = along(c->xyz + 3 * (size_t)v[i], dir);
        bool l = x < *med || (ties_left && x == *med);
        c->label[v[i]] = l ? left : right;
        nleft += l;
    }
    mark_touching(c, v, flag, n, left, right, touch);
    return nleft;
}

/* Splits the part by breadth-first levels from start (level sets follow the surface where a
 * plane would cut a curved one several times): the levels before the one holding the middle
 * point on the left, the rest (and points start does not reach) on the right. */
static size_t split_bfs(nd_ctx *c, const uint32_t *v, uint8_t *flag, size_t n, uint32_t start,
                        size_t touch[2])
{
    uint32_t part = c->stamp++, seen = c->stamp++;
    for (size_t i = 0; i < n; ++i)
        c->label[v[i]] = part;
    uint32_t *queue = c->tmp;
    size_t head = 0, tail = 0;
    queue[tail++] = start;
    c->label[start] = seen;
    c->level[start] = 0;
    while (head < tail) {
        uint32_t p = queue[head++];
        for (size_t e = c->adj_ptr[p]; e < c->adj_ptr[p + 1]; ++e) {
            uint32_t q = c->adj[e];
            if (c->label[q] == part) {
                c->label[q] = seen;
                c->level[q] = c->level[p] + 1;
                queue[tail++] = q;
            }
        }
    }
    uint32_t cut = c->level[queue[tail > n / 2 ? n / 2 : tail - 1]];
    if (tail <= n / 2)
        cut = UINT32_MAX; /* start's component is small: it alone is the left */
    else if (cut == 0)
        cut = 1;
    uint32_t left = c->stamp++, right = c->stamp++;
    size_t nleft = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t p = v[i];
        bool l = c->label[p] == seen && c->level[p] < cut;
        c->label[p] = l ? left : right;
        nleft += l;
    }
    mark_touching(c, v, flag, n, left, right, touch);
    return nleft;
}

static void nested_dissection(nd_ctx *c, uint32_t *v, uint8_t *flag, size_t n, int depth)
{
    if (n <= SK_ND_LEAF || depth > 60) {
        emit(c, v, n);
        return;
    }
    /* the split direction: the one whose plane scores best */
    double dirs[SK_ND_DIRECTIONS][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    principal_axis(c, v, n, dirs[0]);
    double at[SK_ND_DIRECTIONS], score[SK_ND_DIRECTIONS];
    plane_positions(c, v, n, dirs, at, score);
    int best = 0;
    for (int d = 1; d < SK_ND_DIRECTIONS; ++d)
        if (score[d] < score[best])
            best = d;
    double best_med = at[best];
    size_t touch[2];
    size_t nleft = split(c, v, flag, n, dirs[best], &best_med, touch);
    size_t best_size = touch[0] < touch[1] ? touch[0] : touch[1];
    if (nleft == 0 || nleft == n)
        best = -1;
    if (best < 0) { /* every point at one spot */
        emit(c, v, n);
        return;
    }
    /* and breadth-first levels from the extreme point along the best direction */
    uint32_t start = v[0];
    for (size_t i = 1; i < n; ++i)
        if (along(c->xyz + 3 * (size_t)v[i], dirs[best]) <
            along(c->xyz + 3 * (size_t)start, dirs[best]))
            start = v[i];
    nleft = split_bfs(c, v, flag, n, start, touch);
    size_t size = touch[0] < touch[1] ? touch[0] : touch[1];
    if (!(nleft > 0 && nleft < n && size < best_size))
        split(c, v, flag, n, dirs[best], &best_med, touch);
    /* the separator: the touching points of the side with fewer of them; the others rejoin
     * their side */
    uint8_t sep = touch[0] <= touch[1] ? 2 : 3;
    for (size_t i = 0; i < n; ++i)
        if (flag[i] >= 2 && flag[i] != sep)
            flag[i] = (uint8_t)(flag[i] - 2);
    size_t nl = partition_by(v, n, flag, 0);
    size_t nr = partition_by(v + nl, n - nl, flag + nl, 1);
    size_t ns = n - nl - nr;
    if (ns == n) { /* no progress (all points on one spot): stop here */
        emit(c, v, n);
        return;
    }
    nested_dissection(c, v, flag, nl, depth + 1);
    nested_dissection(c, v + nl, flag + nl, nr, depth + 1);
    if (ns)
        emit(c, v + nl + nr, ns);
}

/* The point graph of a (dim unknowns per point): adjacency lists without duplicates or loops,
 * and its lower-triangle pattern (diagonal included) as a CHOLMOD matrix for the orderings. */
static sk_status point_graph(const sk_sparse *a, unsigned dim, size_t **ptr_out, uint32_t **adj_out,
                             int **lp_out, int **li_out, sk_error *err)
{
    size_t np = a->n / dim;
    sk_status st = SK_OK;
    size_t *ptr = sk__calloc_array(np + 1, sizeof *ptr);
    uint32_t *adj = NULL, *mark = sk__malloc_array(np ? np : 1, sizeof *mark);
    int *lp = sk__calloc_array(np + 1, sizeof *lp), *li = NULL;
    if (!ptr || !mark || !lp)
        goto nomem;
    for (size_t col = 0; col < a->n; ++col)
        for (int q = a->colptr[col]; q < a->colptr[col + 1]; ++q) {
            size_t pr = (size_t)a->rowind[q] / dim, pc = col / dim;
            if (pr != pc) {
                ptr[pr + 1]++;
                ptr[pc + 1]++;
            }
        }
    for (size_t p = 0; p < np; ++p)
        ptr[p + 1] += ptr[p];
    adj = sk__malloc_array(ptr[np] ? ptr[np] : 1, sizeof *adj);
    if (!adj)
        goto nomem;
    for (size_t col = 0; col < a->n; ++col)
        for (int q = a->colptr[col]; q < a->colptr[col + 1]; ++q) {
            size_t pr = (size_t)a->rowind[q] / dim, pc = col / dim;
            if (pr != pc) {
                adj[ptr[pr]++] = (uint32_t)pc;
                adj[ptr[pc]++] = (uint32_t)pr;
            }
        }
    for (size_t p = np; p > 0; --p)
        ptr[p] = ptr[p - 1];
    ptr[0] = 0;
    /* drop duplicates in place, count the lower entries */
    for (size_t p = 0; p < np; ++p)
        mark[p] = UINT32_MAX;
    size_t w = 0, start = 0;
    for (size_t p = 0; p < np; ++p) {
        size_t end = ptr[p + 1];
        ptr[p] = w;
        mark[p] = (uint32_t)p;
        lp[p + 1] = 1; /* the diagonal */
        for (size_t e = start; e < end; ++e) {
            uint32_t q = adj[e];
            if (mark[q] == (uint32_t)p)
                continue;
            mark[q] = (uint32_t)p;
            adj[w++] = q;
            lp[p + 1] += q > p;
        }
        start = end;
    }
    ptr[np] = w;
    for (size_t p = 0; p < np; ++p)
        lp[p + 1] += lp[p];
    li = sk__malloc_array((size_t)lp[np] ? (size_t)lp[np] : 1, sizeof *li);
    if (!li)
        goto nomem;
    for (size_t p = 0; p < np; ++p) {
        int q = lp[p];
        li[q++] = (int)p;
        for (size_t e = ptr[p]; e < ptr[p + 1]; ++e)
            if (adj[e] > p)
                li[q++] = (int)adj[e];
    }
    goto done;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "out of memory for an ordering");
done:
    sk__free(mark);
    if (st) {
        sk__free(ptr);
        sk__free(adj);
        sk__free(lp);
        sk__free(li);
        ptr = NULL;
        adj = NULL;
        lp = li = NULL;
    }
    *ptr_out = ptr;
    *adj_out = adj;
    *lp_out = lp;
    *li_out = li;
    return st;
}

/* The constraint sets of the geometric dissection of the point graph. */
static sk_status dissect(const double *xyz, size_t np, const size_t *ptr, const uint32_t *adj,
                         int *cmember, sk_error *err)
{
    sk_status st = SK_OK;
    uint32_t *v = sk__malloc_array(np ? np : 1, sizeof *v);
    uint32_t *label = sk__calloc_array(np ? np : 1, sizeof *label);
    uint8_t *flag = sk__malloc_array(np ? np : 1, 1);
    double *key = sk__malloc_array(np ? np : 1, sizeof *key);
    uint32_t *tmp = sk__malloc_array(np ? np : 1, sizeof *tmp);
    uint32_t *level = sk__malloc_array(np ? np : 1, sizeof *level);
    uint16_t *first = sk__malloc_array(np ? SK_ND_DIRECTIONS * np : 1, sizeof *first);
    size_t hist[2 * SK_ND_DIRECTIONS * (SK_ND_BINS + 1)];
    if (!v || !label || !flag || !key || !tmp || !level || !first) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for an ordering");
        goto done;
    }
    for (size_t p = 0; p < np; ++p) {
        v[p] = (uint32_t)p;
        if (!isfinite(xyz[3 * p]) || !isfinite(xyz[3 * p + 1]) || !isfinite(xyz[3 * p + 2])) {
            st = sk__fail(err, SK_ERR_ARG, "point %zu of the ordering is not finite", p);
            goto done;
        }
    }
    nd_ctx c = {xyz, ptr, adj, label, 1, key, tmp, level, first, hist, cmember, 0};
    nested_dissection(&c, v, flag, np, 0);
done:
    sk__free(v);
    sk__free(label);
    sk__free(flag);
    sk__free(key);
    sk__free(tmp);
    sk__free(level);
    sk__free(first);
    return st;
}

sk_status sk_sparse_point_ordering(const sk_sparse *a, unsigned dim, const double *xyz,
                                   sk_ordering method, int *perm, sk_error *err)
{
    if (dim == 0 || a->n % dim)
        return sk__fail(err, SK_ERR_ARG, "%zu unknowns are not a multiple of %u per point", a->n,
                        dim);
    if (method != SK_ORDERING_GEOMETRIC && method != SK_ORDERING_METIS &&
        method != SK_ORDERING_AMD)
        return sk__fail(err, SK_ERR_ARG, "the point ordering is geometric, METIS or AMD");
    if (method == SK_ORDERING_GEOMETRIC && !xyz)
        return sk__fail(err, SK_ERR_ARG, "the geometric ordering needs the points");
    size_t np = a->n / dim;
    if (np > (size_t)INT_MAX / (dim ? dim : 1))
        return sk__fail(err, SK_ERR_ARG, "%zu unknowns are too many for an ordering", a->n);
    sk_status st = SK_OK;
    size_t *ptr = NULL;
    uint32_t *adj = NULL;
    int *lp = NULL, *li = NULL, *cmember = NULL;
    int *pperm = sk__malloc_array(np ? np : 1, sizeof *pperm);
    cholmod_common cc;
    bool cc_started = false;
    if (!pperm) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory for an ordering");
        goto done;
    }
    if ((st = point_graph(a, dim, &ptr, &adj, &lp, &li, err)))
        goto done;
    if (method == SK_ORDERING_GEOMETRIC) {
        cmember = sk__malloc_array(np ? np : 1, sizeof *cmember);
        if (!cmember) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory for an ordering");
            goto done;
        }
        if ((st = dissect(xyz, np, ptr, adj, cmember, err)))
            goto done;
    }
    sk__free(adj); /* the orderings below make their own graphs */
    adj = NULL;
    cholmod_start(&cc);
    cc_started = true;
    cc.print = 0;
    cc.error_handler = NULL;
    cholmod_sparse A;
    memset(&A, 0, sizeof A);
    A.nrow = A.ncol = np;
    A.nzmax = (size_t)lp[np];
    A.p = lp;
    A.i = li;
    A.stype = -1;
    A.itype = CHOLMOD_INT;
    A.xtype = CHOLMOD_PATTERN;
    A.dtype = CHOLMOD_DOUBLE;
    A.sorted = 0;
    A.packed = 1;
    int ok;
    if (method == SK_ORDERING_METIS) {
        sk__metis_lock(); /* one METIS call at a time in the process (solver.c) */
        ok = cholmod_metis(&A, NULL, 0, 1, pperm, &cc);
        sk__metis_unlock();
    } else {
        ok = method == SK_ORDERING_GEOMETRIC ? cholmod_camd(&A, NULL, 0, cmember, pperm, &cc)
                                             : cholmod_amd(&A, NULL, 0, pperm, &cc);
    }
    if (!ok || cc.status < 0) {
        st = sk__fail(err, cc.status == CHOLMOD_OUT_OF_MEMORY ? SK_ERR_NOMEM : SK_ERR_NUMERIC,
                      "ordering of a %zu-point graph failed", np);
        goto done;
    }
    /* the unknowns of a point stay together (dense blocks: wider supernodes) */
    for (size_t k = 0; k < np; ++k)
        for (unsigned d = 0; d < dim; ++d)
            perm[dim * k + d] = (int)(dim * (size_t)pperm[k] + d);
done:
    if (cc_started)
        cholmod_finish(&cc);
    sk__free(ptr);
    sk__free(adj);
    sk__free(lp);
    sk__free(li);
    sk__free(cmember);
    sk__free(pperm);
    return st;
}
