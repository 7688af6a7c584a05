/* Packing: the chart-shaped packer (raster_pack.c; up to 2000 charts, on a grid of at most 1024
 * texels a side) runs from the scale the boxes below reach and wins when it packs at a larger
 * scale; otherwise the box packer's result stands. Box packer: each chart is rotated to its
 * smallest-area bounding box (one of its convex hull's edge directions, Freeman & Shapira), laid
 * flat (width >= height), and the boxes, largest first, go onto a skyline at the lowest place
 * they fit, upright or flat (bottom-left rule); above 2000 charts, shelves (rows, tallest first)
 * instead, which cost linear time. The largest common scale that fits [0,1]^2 with the gutter is
 * found by bisection, for four orders of the boxes (by height, area, longer side, perimeter): the
 * order with the largest scale is kept. */
#include "atlas/atlas_internal.h"
#include "core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct rect {
    uint32_t chart;
    double w, h; /* at scale 1 */
    double key;  /* the sort key of the order being tried */
} rect;

static int cmp_pt(const void *x, const void *y)
{
    const double *a = x, *b = y;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

static double cross(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Andrew's monotone chain over pts (n points, sorted in place); hull (2n doubles of room)
 * receives the counter-clockwise hull; returns its size. */
static size_t convex_hull(double *pts, size_t n, double *hull)
{
    qsort(pts, n, 2 * sizeof(double), cmp_pt);
    if (n < 3) {
        memcpy(hull, pts, 2 * n * sizeof(double));
        return n;
    }
    size_t k = 0;
    for (size_t i = 0; i < n; ++i) {
        while (k >= 2 && cross(hull + 2 * (k - 2), hull + 2 * (k - 1), pts + 2 * i) <= 0)
            k--;
        memcpy(hull + 2 * k++, pts + 2 * i, 2 * sizeof(double));
    }
    for (size_t i = n - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(hull + 2 * (k - 2), hull + 2 * (k - 1), pts + 2 * i) <= 0)
            k--;
        memcpy(hull + 2 * k++, pts + 2 * i, 2 * sizeof(double));
    }
    return k - 1;
}

/* The smallest-area bounding box over the directions of the hull's nh edges: returns its area,
 * *bc, *bs the cosine and sine of the direction that lies flat. */
static double min_box(const double *hull, size_t nh, double *bc, double *bs)
{
    double best = INFINITY;
    *bc = 1;
    *bs = 0;
    for (size_t i = 0; i < nh; ++i) {
        const double *a = hull + 2 * i, *b = hull + 2 * ((i + 1) % nh);
        double dx = b[0] - a[0], dy = b[1] - a[1], l = hypot(dx, dy);
        if (!(l > 0))
            continue;
        double c = dx / l, s = dy / l; /* rotate by -angle: edge becomes horizontal */
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t j = 0; j < nh; ++j) {
            const double *p = hull + 2 * j;
            double x = c * p[0] + s * p[1], y = -s * p[0] + c * p[1];
            lo[0] = fmin(lo[0], x);
            hi[0] = fmax(hi[0], x);
            lo[1] = fmin(lo[1], y);
            hi[1] = fmax(hi[1], y);
        }
        double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        if (area < best) {
            best = area;
            *bc = c;
            *bs = s;
        }
    }
    return nh > 0 ? best : 0;
}

double sk__min_box_area(double *pts, size_t n, double *hull)
{
    double c, s;
    return n < 3 ? 0 : min_box(hull, convex_hull(pts, n, hull), &c, &s);
}

/* Rotates and translates the points of one chart so that its bounding box is the smallest over
 * the hull's edge directions, with width >= height and the corner at the origin. */
static void orient_chart(double *uv, size_t n, double *scratch, double *hull, double *w, double *h)
{
    memcpy(scratch, uv, 2 * n * sizeof(double));
    size_t nh = convex_hull(scratch, n, hull);
    double bc, bs;
    min_box(hull, nh, &bc, &bs);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t j = 0; j < n; ++j) {
        double *p = uv + 2 * j;
        double x = bc * p[0] + bs * p[1], y = -bs * p[0] + bc * p[1];
        p[0] = x;
        p[1] = y;
        lo[0] = fmin(lo[0], x);
        hi[0] = fmax(hi[0], x);
        lo[1] = fmin(lo[1], y);
        hi[1] = fmax(hi[1], y);
    }
    bool turn = hi[1] - lo[1] > hi[0] - lo[0];
    for (size_t j = 0; j < n; ++j) {
        double *p = uv + 2 * j;
        double x = p[0] - lo[0], y = p[1] - lo[1];
        /* a quarter turn counter-clockwise keeps the orientation: (x, y) -> (H - y, x) */
        p[0] = turn ? (hi[1] - lo[1]) - y : x;
        p[1] = turn ? x : y;
    }
    *w = turn ? hi[1] - lo[1] : hi[0] - lo[0];
    *h = turn ? hi[0] - lo[0] : hi[1] - lo[1];
}

/* Box orders tried (largest first by each key); the one that packs at the largest scale wins. */
enum { ORDER_HEIGHT, ORDER_AREA, ORDER_WIDTH, ORDER_PERIMETER, ORDERS };

static double rect_key(const rect *r, int order)
{
    switch (order) {
    case ORDER_AREA:
        return r->w * r->h;
    case ORDER_WIDTH:
        return r->w; /* laid flat: w >= h, so this is the longer side */
    case ORDER_PERIMETER:
        return r->w + r->h;
    default:
        return r->h;
    }
}

static int cmp_rect(const void *x, const void *y)
{
    const rect *a = x, *b = y;
    if (a->key != b->key)
        return a->key > b->key ? -1 : 1;
    return (a->chart > b->chart) - (a->chart < b->chart);
}

static void sort_rects(rect *r, size_t n, int order)
{
    for (size_t i = 0; i < n; ++i)
        r[i].key = rect_key(r + i, order);
    qsort(r, n, sizeof *r, cmp_rect);
}

/* Shelf placement at scale s; writes positions when pos is not NULL. Returns true when it fits. */
static bool shelves(const rect *r, size_t n, double s, double g, double *pos)
{
    double x = 0, y = 0, row = 0;
    for (size_t i = 0; i < n; ++i) {
        double w = r[i].w * s + g, h = r[i].h * s + g;
        if (w > 1.0)
            return false;
        if (x + w > 1.0) {
            y += row;
            x = 0;
            row = 0;
        }
        if (y + h > 1.0)
            return false;
        if (pos) {
            pos[2 * r[i].chart] = x + 0.5 * g;
            pos[2 * r[i].chart + 1] = y + 0.5 * g;
        }
        x += w;
        row = fmax(row, h);
    }
    return true;
}

/* Skyline: segments [x_i, x_{i+1}) at height y_i covering [0, 1). */
typedef struct skyline {
    double *x, *y;   /* segment starts and heights */
    double *bx, *by; /* scratch of the same capacity */
    size_t n, cap;   /* every box adds at most 2 segments: cap = 2 charts + 8 never runs out */
} skyline;

/* Lowest top for a w x h box starting at segment i (x + w <= 1); INFINITY if it does not fit. */
static double sky_fit(const skyline *k, size_t i, double w, double h, double *base)
{
    double x0 = k->x[i], x1 = x0 + w;
    if (x1 > 1.0)
        return INFINITY;
    double y = 0;
    for (size_t j = i; j < k->n && k->x[j] < x1; ++j)
        y = fmax(y, k->y[j]);
    *base = y;
    return y + h <= 1.0 ? y + h : INFINITY;
}

/* Raises [x0, x0 + w) to height top (x0 is a segment start). */
static bool sky_place(skyline *k, double x0, double w, double top)
{
    double x1 = x0 + w;
    size_t j = 0;
    while (j + 1 < k->n && k->x[j + 1] <= x1)
        j++;
    double after = k->y[j]; /* height just right of the box before it lands */
    size_t n = 0;
    for (size_t i = 0; i < k->n && k->x[i] < x0; ++i, ++n) {
        k->bx[n] = k->x[i];
        k->by[n] = k->y[i];
    }
    k->bx[n] = x0;
    k->by[n++] = top;
    if (x1 < 1.0) {
        k->bx[n] = x1;
        k->by[n++] = after;
        for (size_t i = 0; i < k->n; ++i)
            if (k->x[i] > x1) {
                k->bx[n] = k->x[i];
                k->by[n++] = k->y[i];
            }
    }
    size_t m = 0;
    for (size_t q = 0; q < n; ++q) { /* neighbours of equal height merge */
        if (m > 0 && k->by[q] == k->y[m - 1])
            continue;
        k->x[m] = k->bx[q];
        k->y[m++] = k->by[q];
    }
    k->n = m;
    return m + 2 <= k->cap;
}

/* Skyline placement at scale s (rot[c] receives 1 for an upright chart); true when all fit. */
static bool skyline_pack(const rect *r, size_t n, double s, double g, double *pos, uint8_t *rot,
                         skyline *k, bool *nomem)
{
    k->n = 1;
    k->x[0] = 0;
    k->y[0] = 0;
    for (size_t i = 0; i < n; ++i) {
        double best = INFINITY, bx = 0, bw = 0;
        int bt = 0;
        for (int turn = 0; turn < 2; ++turn) {
            double w = (turn ? r[i].h : r[i].w) * s + g, h = (turn ? r[i].w : r[i].h) * s + g;
            for (size_t j = 0; j < k->n; ++j) {
                double base;
                double top = sky_fit(k, j, w, h, &base);
                if (top < best || (top == best && k->x[j] < bx)) {
                    best = top;
                    bx = k->x[j];
                    bw = w;
                    bt = turn;
                }
            }
        }
        if (!isfinite(best))
            return false;
        double h = (bt ? r[i].w : r[i].h) * s + g;
        if (pos) {
            pos[2 * r[i].chart] = bx + 0.5 * g;
            pos[2 * r[i].chart + 1] = best - h + 0.5 * g;
            rot[r[i].chart] = (uint8_t)bt;
        }
        if (!sky_place(k, bx, bw, best)) {
            *nomem = true;
            return false;
        }
    }
    return true;
}

/* Above this many charts only the box packer runs; above this resolution the chart-shaped
 * packer works on a coarser grid of this many texels per side, the gutter rounded up to its
 * texels (so at least as wide), which keeps its time that of 1024. */
#define RASTER_MAX_CHARTS 2000
#define RASTER_MAX_RES 1024

/* The chart-shaped packer from orig (the charts as given) and uv (turned to their smallest
 * boxes), started at the box packer's scale s0: when it packs at a larger scale (*ok), uv holds
 * the packing and *scale its scale. */
static sk_status try_raster(size_t nc, const uint32_t *off, const uint32_t *uv_chart,
                            const double *orig, double *uv, size_t ne, const uint32_t *edges,
                            double res, double pad, double s0, double *scale, bool *ok,
                            sk_error *err)
{
    sk_status st = SK_OK;
    size_t n = off[nc];
    uint32_t *eoff = sk__calloc_array(nc + 1, sizeof(uint32_t));
    uint32_t *e = sk__malloc_array(2 * ne + 2, sizeof(uint32_t));
    double *area = sk__calloc_array(nc ? nc : 1, sizeof(double));
    double *boxed = sk__malloc_array(2 * (n ? n : 1), sizeof(double));
    double *packed = sk__malloc_array(2 * (n ? n : 1), sizeof(double));
    *ok = false;
    if (!eoff || !e || !area || !boxed || !packed) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    memcpy(boxed, uv, 2 * n * sizeof(double));
    for (size_t i = 0; i < ne; ++i)
        eoff[uv_chart[edges[2 * i]] + 1]++;
    for (size_t c = 0; c < nc; ++c)
        eoff[c + 1] += eoff[c];
    double total = 0;
    for (size_t i = 0; i < ne; ++i) { /* grouped by chart; the outline's area (shoelace) */
        uint32_t a = edges[2 * i], b = edges[2 * i + 1], c = uv_chart[a], at = eoff[c]++;
        e[2 * (size_t)at] = a;
        e[2 * (size_t)at + 1] = b;
        const double *p = orig + 2 * (size_t)a, *q = orig + 2 * (size_t)b;
        area[c] += 0.5 * (p[0] * q[1] - p[1] * q[0]);
    }
    for (size_t c = nc; c > 0; --c)
        eoff[c] = eoff[c - 1];
    eoff[0] = 0;
    for (size_t c = 0; c < nc; ++c) {
        area[c] = fabs(area[c]);
        total += area[c];
    }
    double grid = fmin(res, RASTER_MAX_RES);
    uint32_t p = (uint32_t)ceil(pad * grid / res - 1e-12);
    sk__raster_in in = {nc, off, {orig, boxed}, area, eoff, e, (uint32_t)grid, p, (p + 1) / 2};
    double rs = 0;
    if (total > 0 && !(st = sk__raster_pack(&in, s0, 1.0 / sqrt(total), packed, &rs, ok, err)))
        *ok = *ok && rs > s0;
    if (*ok) {
        memcpy(uv, packed, 2 * n * sizeof(double));
        *scale = rs;
    }
done:
    sk__free(packed);
    sk__free(eoff);
    sk__free(e);
    sk__free(area);
    sk__free(boxed);
    return st;
}

sk_status sk__pack_charts(size_t nc, const uint32_t *off, const uint32_t *uv_chart, double *uv,
                          size_t ne, const uint32_t *edges, double res, double pad,
                          double *scale, sk_error *err)
{
    sk_status st = SK_OK;
    double gutter = pad / res;
    bool raster = nc <= RASTER_MAX_CHARTS && ne > 0 && res >= 1;
    double *orig = raster ? sk__malloc_array(2 * (off[nc] ? off[nc] : 1), sizeof(double)) : NULL;
    uint8_t *rot = NULL;
    skyline k = {0};
    size_t maxn = 1;
    for (size_t c = 0; c < nc; ++c)
        if (off[c + 1] - off[c] > maxn)
            maxn = off[c + 1] - off[c];
    rect *r = sk__malloc_array(nc ? nc : 1, sizeof *r);
    double *pos = sk__malloc_array(2 * (nc ? nc : 1), sizeof(double));
    double *scratch = sk__malloc_array(2 * maxn, sizeof(double));
    double *hull = sk__malloc_array(4 * maxn + 4, sizeof(double));
    if (!r || !pos || !scratch || !hull || (raster && !orig)) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (raster)
        memcpy(orig, uv, 2 * (size_t)off[nc] * sizeof(double));
    double area = 0;
    for (size_t c = 0; c < nc; ++c) {
        r[c].chart = (uint32_t)c;
        orient_chart(uv + 2 * (size_t)off[c], off[c + 1] - off[c], scratch, hull, &r[c].w,
                     &r[c].h);
        area += r[c].w * r[c].h;
    }
    if (!(gutter >= 0) || gutter >= 0.5 || !(area > 0)) {
        st = sk__fail(err, SK_ERR_ARG, "cannot pack: gutter %g, chart box area %g", gutter, area);
        goto done;
    }
    /* bisection on the scale: the boxes' area bounds it from above */
    bool sky = nc <= 2000, nomem = false;
    rot = sk__calloc_array(nc ? nc : 1, 1);
    k.cap = 2 * nc + 8;
    k.x = sk__malloc_array(k.cap, sizeof(double));
    k.y = sk__malloc_array(k.cap, sizeof(double));
    k.bx = sk__malloc_array(k.cap, sizeof(double));
    k.by = sk__malloc_array(k.cap, sizeof(double));
    if (!rot || !k.x || !k.y || !k.bx || !k.by) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    double lo = 0;
    int best_order = ORDER_HEIGHT;
    for (int order = 0; order < (sky ? ORDERS : 1); ++order) {
        sort_rects(r, nc, order);
        double l = 0, hi = 1.0 / sqrt(area);
        for (int it = 0; it < 50; ++it) {
            double mid = 0.5 * (l + hi);
            bool fits = sky ? skyline_pack(r, nc, mid, gutter, NULL, NULL, &k, &nomem)
                            : shelves(r, nc, mid, gutter, NULL);
            if (nomem) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                goto done;
            }
            if (fits)
                l = mid;
            else
                hi = mid;
        }
        if (l > lo) {
            lo = l;
            best_order = order;
        }
    }
    if (raster && lo > 0) {
        bool won = false;
        if ((st = try_raster(nc, off, uv_chart, orig, uv, ne, edges, res, pad, lo, scale, &won,
                             err)) || won)
            goto done;
    }
    sort_rects(r, nc, best_order);
    bool ok = lo > 0 && (sky ? skyline_pack(r, nc, lo, gutter, pos, rot, &k, &nomem)
                             : shelves(r, nc, lo, gutter, pos));
    if (!ok) {
        st = nomem ? sk__fail(err, SK_ERR_NOMEM, "out of memory")
                   : sk__fail(err, SK_ERR_ARG, "the %zu charts do not fit with gutter %g", nc,
                              gutter);
        goto done;
    }
    for (size_t c = 0; c < nc; ++c) {
        /* upright: a quarter turn counter-clockwise, (x, y) -> (H - y, x), keeps orientation */
        double hgt = 0;
        if (rot[c])
            for (uint32_t i = off[c]; i < off[c + 1]; ++i)
                hgt = fmax(hgt, uv[2 * (size_t)i + 1]);
        for (uint32_t i = off[c]; i < off[c + 1]; ++i) {
            double x = uv[2 * (size_t)i], y = uv[2 * (size_t)i + 1];
            if (rot[c]) {
                double t = x;
                x = hgt - y;
                y = t;
            }
            uv[2 * (size_t)i] = pos[2 * c] + lo * x;
            uv[2 * (size_t)i + 1] = pos[2 * c + 1] + lo * y;
        }
    }
    *scale = lo;
done:
    sk__free(orig);
    sk__free(rot);
    sk__free(k.x);
    sk__free(k.y);
    sk__free(k.bx);
    sk__free(k.by);
    sk__free(r);
    sk__free(pos);
    sk__free(scratch);
    sk__free(hull);
    return st;
}
