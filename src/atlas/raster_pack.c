/* Chart-shaped packing on a texel grid: at a trial scale every chart's outline (its boundary
 * edges, conservatively rasterized, and the texels whose centre lies inside, even-odd) becomes a
 * bitmap C, dilated by the padding into D. Charts, in one order (largest first by outline area,
 * by the smallest box's longer side or by its perimeter), go where their D misses every placed
 * chart's C (64 texels per word, a colliding row skips the search past its last colliding texel,
 * rows whose longest free run is too short skip whole heights), by one of two rules: the lowest,
 * then leftmost position, or the position that keeps the square from the grid's corner around all
 * placed charts smallest (inside it when D fits there: concave voids and holes first; then the
 * least growth), trying two orientations (the chart's own and its smallest-box one) in four
 * quarter turns each, and for few charts 5 angles more. The common scale is bisected from the box
 * packer's; the variants (orientations x rule x order) each start from the best scale so far and
 * the largest scale wins; its variant is searched once more, finer. Two points of different
 * charts lie in texels at least padding + 1 apart in x or y, so at least padding texels apart. */
#include "atlas/atlas_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* slack on texel boundaries against rounding (texel units) */
#define RASTER_EPS 1e-9
/* charts up to this many also try EXTRA_ANGLES turns between the box's quarter turns (24 before:
 * at 40, elephant's 31 charts pack to utilization 0.586 instead of 0.569, bunny00's 28 to 0.741
 * instead of 0.702, at about twice the packing's CPU there; docs/param.md) */
#define FEW_CHARTS 40
#define EXTRA_ANGLES 5
#define ORIENTS (2 + EXTRA_ANGLES)
/* a variant after the first starts at the best scale so far times this (and stops when that
 * does not fit) */
#define VARIANT_GAIN 1.003
/* the winning variant is tried once more from the best scale times this, with RASTER_TRIALS */
#define FINAL_GAIN 1.001
/* placements tried per packing (each at one scale) */
#define RASTER_TRIALS 10
#define VARIANT_TRIALS 5

typedef struct bitmap {
    uint32_t w, h, words; /* texels per row, rows, words per row */
    uint64_t *bits;
} bitmap;

typedef struct row_info {
    uint32_t first, end; /* its runs of set texels: runs[first .. end) */
    uint32_t run;        /* its longest run */
} row_info;

typedef struct span {
    uint32_t a, b; /* texels a..b inclusive */
} span;

typedef struct crossing {
    uint32_t row;
    double x;
} crossing;

typedef struct cand { /* a free position of D and the square side it leaves (RULE_SQUARE) */
    uint32_t x, y, side;
} cand;

/* how a chart's position is chosen among the free ones (see search) */
enum { RULE_LOW_LEFT, RULE_SQUARE };
/* the orders of the charts tried: largest first by outline area, the smallest box's longer side,
 * its perimeter */
enum { KEY_AREA, KEY_SIDE, KEY_PERIM, KEYS };

typedef struct place {
    uint8_t orient, turn;
    uint32_t x, y; /* grid position of D */
} place;

typedef struct raster {
    const sk__raster_in *in;
    uint32_t grid, gw;    /* grid texels per side, words per grid row */
    uint64_t *occ;        /* grid: the placed charts' C */
    uint32_t *maxfree;    /* per grid row: its longest run of free texels */
    bitmap c, d, tmp;     /* scratch: one candidate's C, its D, the dilation's middle step */
    uint64_t *wide;       /* one row of D */
    row_info *info;       /* per D row */
    span *runs;           /* of D's rows */
    uint32_t anchor, anchor_row; /* D's longest run (index in runs) and its row */
    size_t runs_cap;
    crossing *cross, *sorted; /* the outline's row crossings, as found and by (row, x) */
    size_t cross_cap;
    uint32_t *row_start;  /* per C row + 1: its crossings' start in sorted */
    uint32_t *order;      /* KEYS orders of the charts, largest first */
    int key;              /* the order in use */
    double *lo;           /* 2 orientations x 2 (min x, min y) per chart */
    double *ext;          /* 2 orientations x 2 (width, height) per chart */
    place *pl;            /* per chart */
    place *best;          /* per chart: the placement at the largest scale that fitted */
    uint32_t top;         /* grid rows used by the last placement */
    uint32_t used_w, used_h; /* the placed charts' D: columns and rows from the grid's corner */
    int rule;             /* RULE_LOW_LEFT or RULE_SQUARE */
    uint64_t work;        /* positions tested so far (the variants' budget) */
    int orients;          /* orientations tried */
    double rot[2 * ORIENTS]; /* cos, sin of each orientation's turn */
    bool nomem;
} raster;

static void set_range(uint64_t *row, uint32_t a, uint32_t b) /* texels a..b inclusive */
{
    uint32_t wa = a >> 6, wb = b >> 6;
    uint64_t ma = ~0ull << (a & 63), mb = ~0ull >> (63 - (b & 63));
    if (wa == wb) {
        row[wa] |= ma & mb;
        return;
    }
    row[wa] |= ma;
    for (uint32_t i = wa + 1; i < wb; ++i)
        row[i] = ~0ull;
    row[wb] |= mb;
}

/* Highest set texel of row in a..b (inclusive), or -1. */
static int64_t last_set(const uint64_t *row, uint32_t a, uint32_t b)
{
    uint32_t wa = a >> 6;
    for (uint32_t i = (b >> 6) + 1; i-- > wa;) {
        uint64_t w = row[i];
        if (i == b >> 6)
            w &= ~0ull >> (63 - (b & 63));
        if (i == wa)
            w &= ~0ull << (a & 63);
        if (w)
            return 64 * (int64_t)i + 63 - __builtin_clzll(w);
    }
    return -1;
}

/* Point u in orientation o (scale 1): the chart as given (0), turned to its smallest box (1), or
 * that turned further by (o - 1) * 90 / EXTRA_ANGLES degrees (charts below FEW_CHARTS). */
static void oriented(const raster *k, int o, uint32_t u, double *q)
{
    const double *p = k->in->uv[o ? 1 : 0] + 2 * (size_t)u;
    double c = k->rot[2 * o], s = k->rot[2 * o + 1];
    q[0] = c * p[0] - s * p[1];
    q[1] = s * p[0] + c * p[1];
}

/* The chart's points in texel units for orientation o, quarter turn t at scale s (texel per uv
 * unit factor f = s * res); *w, *h the bitmap size. */
static void chart_dims(const raster *k, uint32_t c, int o, int t, double f, uint32_t *w,
                       uint32_t *h)
{
    const double *e = k->ext + 2 * (ORIENTS * (size_t)c + (size_t)o);
    uint32_t bw = (uint32_t)fmax(1.0, ceil(e[0] * f - RASTER_EPS));
    uint32_t bh = (uint32_t)fmax(1.0, ceil(e[1] * f - RASTER_EPS));
    *w = t & 1 ? bh : bw;
    *h = t & 1 ? bw : bh;
}

/* Point u of chart c in texel units of the turned bitmap (bw, bh: the unturned size). */
static void texel_point(const raster *k, uint32_t c, int o, int t, double f, uint32_t u,
                        double *q)
{
    const double *l = k->lo + 2 * (ORIENTS * (size_t)c + (size_t)o);
    const double *e = k->ext + 2 * (ORIENTS * (size_t)c + (size_t)o);
    double p[2];
    oriented(k, o, u, p);
    double bw = fmax(1.0, ceil(e[0] * f - RASTER_EPS)), bh = fmax(1.0, ceil(e[1] * f - RASTER_EPS));
    double x = (p[0] - l[0]) * f, y = (p[1] - l[1]) * f;
    switch (t) { /* quarter turns counter-clockwise keep the orientation */
    case 1:
        q[0] = bh - y;
        q[1] = x;
        break;
    case 2:
        q[0] = bw - x;
        q[1] = bh - y;
        break;
    case 3:
        q[0] = y;
        q[1] = bw - x;
        break;
    default:
        q[0] = x;
        q[1] = y;
    }
}

static uint32_t clampi(double v, uint32_t n)
{
    if (!(v > 0))
        return 0;
    return v >= (double)n ? n - 1 : (uint32_t)v;
}

/* Every texel of C whose closed square the segment a-b meets (at least the one holding each of
 * its points). */
static void raster_segment(bitmap *c, const double *a, const double *b)
{
    double y0 = fmin(a[1], b[1]), y1 = fmax(a[1], b[1]);
    uint32_t j0 = clampi(floor(y0 - RASTER_EPS), c->h), j1 = clampi(floor(y1 + RASTER_EPS), c->h);
    for (uint32_t j = j0; j <= j1; ++j) {
        double xa = a[0], xb = b[0];
        if (y1 > y0) { /* the part of the segment inside rows [j, j + 1] */
            double ta = ((double)j - a[1]) / (b[1] - a[1]);
            double tb = ((double)j + 1 - a[1]) / (b[1] - a[1]);
            double t0 = fmax(0.0, fmin(ta, tb)), t1 = fmin(1.0, fmax(ta, tb));
            xa = a[0] + t0 * (b[0] - a[0]);
            xb = a[0] + t1 * (b[0] - a[0]);
        }
        double x0 = fmin(xa, xb), x1 = fmax(xa, xb);
        set_range(c->bits + (size_t)j * c->words, clampi(floor(x0 - RASTER_EPS), c->w),
                  clampi(floor(x1 + RASTER_EPS), c->w));
    }
}

/* p (*cap elements of size) grown to twice as many and 64 more; NULL (p kept) when out of memory. */
static void *grow(void *p, size_t *cap, size_t size)
{
    size_t n = 2 * *cap + 64;
    void *q = sk__realloc_array(p, n, size);
    if (q)
        *cap = n;
    return q;
}

static int cmp_cross(const void *x, const void *y)
{
    const crossing *a = x, *b = y;
    if (a->row != b->row)
        return a->row < b->row ? -1 : 1;
    return (a->x > b->x) - (a->x < b->x);
}

/* k->cross[0..nx) by (row, x) into k->sorted: counted into rows (h of them), each row by x
 * (insertion for the usual few crossings; equal keys are equal values, so the order is the one
 * qsort gave). qsort of all crossings was a sixth of the packer's time on small meshes. */
static void sort_crossings(raster *k, size_t nx, uint32_t h)
{
    uint32_t *rs = k->row_start;
    memset(rs, 0, ((size_t)h + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < nx; ++i)
        rs[k->cross[i].row + 1]++;
    for (uint32_t j = 0; j < h; ++j)
        rs[j + 1] += rs[j];
    for (size_t i = 0; i < nx; ++i) /* rs[row] runs ahead: the row's next slot */
        k->sorted[rs[k->cross[i].row]++] = k->cross[i];
    for (uint32_t j = h; j > 0; --j)
        rs[j] = rs[j - 1];
    rs[0] = 0;
    for (uint32_t j = 0; j < h; ++j) {
        crossing *r = k->sorted + rs[j];
        size_t n = rs[j + 1] - rs[j];
        if (n > 32) {
            qsort(r, n, sizeof *r, cmp_cross);
            continue;
        }
        for (size_t i = 1; i < n; ++i) {
            crossing x = r[i];
            size_t at = i;
            for (; at > 0 && r[at - 1].x > x.x; --at)
                r[at] = r[at - 1];
            r[at] = x;
        }
    }
}

/* C of chart c (orientation o, turn t) at texel factor f. */
static void raster_chart(raster *k, uint32_t c, int o, int t, double f)
{
    const sk__raster_in *in = k->in;
    bitmap *bm = &k->c;
    chart_dims(k, c, o, t, f, &bm->w, &bm->h);
    bm->words = (bm->w + 63) / 64;
    memset(bm->bits, 0, (size_t)bm->h * bm->words * sizeof(uint64_t));
    size_t nx = 0;
    for (uint32_t i = in->edge_off[c]; i < in->edge_off[c + 1]; ++i) {
        double a[2], b[2];
        texel_point(k, c, o, t, f, in->edge[2 * (size_t)i], a);
        texel_point(k, c, o, t, f, in->edge[2 * (size_t)i + 1], b);
        raster_segment(bm, a, b);
        double y0 = fmin(a[1], b[1]), y1 = fmax(a[1], b[1]);
        /* rows whose centre j + 0.5 is in [y0, y1): the even-odd crossings */
        double jlo = ceil(y0 - 0.5), jhi = ceil(y1 - 0.5);
        for (double j = fmax(jlo, 0); j < jhi && j < bm->h; ++j) {
            if (nx == k->cross_cap) {
                size_t cap = k->cross_cap;
                crossing *nc = grow(k->cross, &cap, sizeof *nc);
                if (nc)
                    k->cross = nc;
                crossing *ns = nc ? sk__realloc_array(k->sorted, cap, sizeof *ns) : NULL;
                if (ns) {
                    k->sorted = ns;
                    k->cross_cap = cap;
                }
                if ((k->nomem = !ns))
                    return;
            }
            double yc = j + 0.5;
            k->cross[nx].row = (uint32_t)j;
            k->cross[nx++].x = a[0] + (yc - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
        }
    }
    sort_crossings(k, nx, bm->h);
    const crossing *x = k->sorted;
    for (size_t i = 0; i + 1 < nx; i += 2) {
        if (x[i].row != x[i + 1].row) { /* odd count: rounding; resync */
            i--;
            continue;
        }
        double x0 = ceil(x[i].x - 0.5), x1 = floor(x[i + 1].x - 0.5);
        if (x1 >= x0 && x1 >= 0 && x0 < bm->w)
            set_range(bm->bits + (size_t)x[i].row * bm->words, clampi(x0, bm->w),
                      clampi(x1, bm->w));
    }
}

/* dst |= src shifted by sh texels (positive: towards higher texels) */
static void or_shifted(uint64_t *dst, const uint64_t *src, uint32_t words, int sh)
{
    int ws = sh >= 0 ? sh / 64 : -((-sh + 63) / 64);
    int bs = sh - 64 * ws; /* 0..63 */
    for (int i = 0; i < (int)words; ++i) {
        int j = i - ws;
        uint64_t v = 0;
        if (j >= 0 && j < (int)words)
            v = src[j] << bs;
        if (bs && j - 1 >= 0 && j - 1 < (int)words)
            v |= src[j - 1] >> (64 - bs);
        dst[i] |= v;
    }
}

/* D = C dilated by p texels (a square), C at (p, p); row info of D. */
static void dilate(raster *k, uint32_t p)
{
    bitmap *c = &k->c, *d = &k->d, *t = &k->tmp;
    d->w = t->w = c->w + 2 * p;
    d->h = c->h + 2 * p;
    t->h = c->h;
    d->words = t->words = (d->w + 63) / 64;
    memset(t->bits, 0, (size_t)t->h * t->words * sizeof(uint64_t));
    memset(d->bits, 0, (size_t)d->h * d->words * sizeof(uint64_t));
    for (uint32_t j = 0; j < c->h; ++j) { /* t row j: C row j widened by 2p texels */
        uint64_t *row = t->bits + (size_t)j * t->words, *wide = k->wide;
        memset(wide, 0, t->words * sizeof(uint64_t));
        memcpy(wide, c->bits + (size_t)j * c->words, c->words * sizeof(uint64_t));
        if (2 * p < 64) { /* every shift within a word and its predecessor */
            for (uint32_t i = 0; i < t->words; ++i) {
                uint64_t cur = wide[i], prev = i ? wide[i - 1] : 0, v = cur;
                for (uint32_t s = 1; s <= 2 * p; ++s)
                    v |= cur << s | prev >> (64 - s);
                row[i] = v;
            }
            continue;
        }
        for (int s = 0; s <= 2 * (int)p; ++s)
            or_shifted(row, wide, t->words, s);
    }
    for (uint32_t j = 0; j < d->h; ++j) {
        uint64_t *row = d->bits + (size_t)j * d->words;
        uint32_t a = j >= 2 * p ? j - 2 * p : 0; /* C rows j - 2p .. j */
        for (uint32_t i = a; i <= j && i < c->h; ++i)
            for (uint32_t w = 0; w < d->words; ++w)
                row[w] |= t->bits[(size_t)i * t->words + w];
    }
    size_t nr = 0;
    k->anchor = 0;
    k->anchor_row = 0;
    for (uint32_t j = 0; j < d->h; ++j) {
        const uint64_t *row = d->bits + (size_t)j * d->words;
        row_info *ri = k->info + j;
        ri->first = (uint32_t)nr;
        ri->run = 0;
        for (uint32_t x = 0; x < d->w;) { /* the runs of set texels */
            uint64_t w = row[x >> 6] >> (x & 63);
            if (!w) {
                x = (x | 63) + 1;
                continue;
            }
            x += (uint32_t)__builtin_ctzll(w);
            uint32_t e = x;
            for (;;) {
                uint64_t ones = ~(row[e >> 6] >> (e & 63));
                uint32_t o = ones ? (uint32_t)__builtin_ctzll(ones) : 64 - (e & 63);
                e += o;
                if ((e & 63) || e >= d->w || !(row[e >> 6] & 1))
                    break;
            }
            if (nr == k->runs_cap) {
                span *nrun = grow(k->runs, &k->runs_cap, sizeof *nrun);
                if (!(k->nomem = !nrun))
                    k->runs = nrun;
                else
                    return;
            }
            if (nr == 0 || e - x > k->runs[k->anchor].b - k->runs[k->anchor].a + 1) {
                k->anchor = (uint32_t)nr;
                k->anchor_row = j;
            }
            k->runs[nr++] = (span){x, e - 1};
            ri->run = e - x > ri->run ? e - x : ri->run;
            x = e;
        }
        ri->end = (uint32_t)nr;
    }
}

/* Does row j of D at (x, y) hit a placed chart? *next receives the smallest x' > x that its runs
 * might not hit: run [a, b] hitting the grid at most at q also hits at every x' <= q - a. */
static bool row_hits(const raster *k, uint32_t j, uint32_t x, uint32_t y, uint32_t *next)
{
    const row_info *ri = k->info + j;
    const uint64_t *g = k->occ + (size_t)(y + j) * k->gw;
    const uint64_t *r = k->d.bits + (size_t)j * k->d.words;
    if (ri->first == ri->end)
        return false;
    /* the word test first, over the words the row's runs span; the runs only for the skip */
    uint32_t g0 = x >> 6, sh = x & 63, w0 = k->runs[ri->first].a >> 6;
    uint32_t w1 = (k->runs[ri->end - 1].b >> 6) + 1;
    uint64_t any = 0;
    if (sh)
        for (uint32_t w = w0; w < w1; ++w)
            any |= (g[g0 + w] & (r[w] << sh)) | (g[g0 + w + 1] & (r[w] >> (64 - sh)));
    else
        for (uint32_t w = w0; w < w1; ++w)
            any |= g[g0 + w] & r[w];
    if (!any)
        return false;
    bool hit = false;
    for (uint32_t i = ri->first; i < ri->end; ++i) {
        int64_t q = last_set(g, x + k->runs[i].a, x + k->runs[i].b);
        if (q >= 0) {
            uint32_t nx = (uint32_t)(q - k->runs[i].a + 1);
            *next = hit && *next > nx ? *next : nx;
            hit = true;
        }
    }
    return hit;
}

/* Does D at (x, y) hit a placed chart? *next receives the next x worth trying (the largest skip
 * of the rows tried); *hint the row that hit (tried first next time). */
static bool collides(const raster *k, uint32_t x, uint32_t y, uint32_t *next, uint32_t *hint)
{
    const bitmap *d = &k->d;
    uint32_t probe[4] = {*hint, 0, d->h / 2, d->h - 1}, nx = 0;
    bool hit = false;
    for (int i = 0; i < 4; ++i) /* a few rows spread over D: their skips add up */
        if (probe[i] < d->h && row_hits(k, probe[i], x, y, &nx)) {
            *next = hit && *next > nx ? *next : nx;
            hit = true;
        }
    if (hit)
        return true;
    for (uint32_t j = 0; j < d->h; ++j)
        if (row_hits(k, j, x, y, next)) {
            *hint = j;
            return true;
        }
    return false;
}

/* First texel >= x of the row (n texels) that is free (want 0) or taken (want 1); n if none. */
static uint32_t next_texel(const uint64_t *row, uint32_t x, uint32_t n, int want)
{
    while (x < n) {
        uint64_t w = row[x >> 6] ^ (want ? 0 : ~0ull);
        w >>= x & 63;
        if (w) {
            x += (uint32_t)__builtin_ctzll(w);
            return x < n ? x : n;
        }
        x = (x | 63) + 1;
    }
    return n;
}

/* Leftmost free position x < xend of D in grid row y (false when none). */
static bool row_first(raster *k, uint32_t y, uint32_t xend, uint32_t *bx)
{
    uint32_t hint = 0;
    /* D's longest run must lie in a free span of its grid row: only those x are tried */
    const uint64_t *g = k->occ + (size_t)(y + k->anchor_row) * k->gw;
    uint32_t aa = k->runs[k->anchor].a, len = k->runs[k->anchor].b - aa + 1;
    for (uint32_t x = 0; x < xend;) {
        uint32_t s0 = next_texel(g, x + aa, k->grid, 0);
        if (s0 >= k->grid)
            return false;
        uint32_t e = next_texel(g, s0, k->grid, 1);
        if (e - s0 >= len)
            for (x = s0 - aa; x + aa + len <= e && x < xend;) {
                uint32_t nx;
                k->work++;
                if (!collides(k, x, y, &nx, &hint)) {
                    *bx = x;
                    return true;
                }
                x = nx;
            }
        if (e >= k->grid)
            return false;
        x = e - aa > x ? e - aa : x; /* on to the next span */
    }
    return false;
}

/* Is row y of the grid too full for D anywhere (some row's longest free run too short)? */
static bool rows_full(const raster *k, uint32_t y, uint32_t *tight)
{
    if (k->maxfree[y + *tight] < k->info[*tight].run)
        return true;
    for (uint32_t j = 0; j < k->d.h; ++j)
        if (k->maxfree[y + j] < k->info[j].run) {
            *tight = j;
            return true;
        }
    return false;
}

/* The side of the square from the grid's corner that holds the placed charts and D at (x, y). */
static uint32_t square_side(const raster *k, uint32_t x, uint32_t y)
{
    uint32_t s = k->used_w > k->used_h ? k->used_w : k->used_h;
    s = x + k->d.w > s ? x + k->d.w : s;
    return y + k->d.h > s ? y + k->d.h : s;
}

/* The lowest, then leftmost free position of D inside the square [0, lim)^2 of the grid that
 * comes before (y0, x0) (rows, then columns); false when none. */
static bool low_left(raster *k, uint32_t lim, uint32_t y0, uint32_t x0, uint32_t *bx,
                     uint32_t *by)
{
    const bitmap *d = &k->d;
    if (d->w > lim || d->h > lim)
        return false;
    uint32_t ymax = lim - d->h, xmax = lim - d->w, tight = 0;
    ymax = y0 < ymax ? y0 : ymax;
    for (uint32_t y = 0; y <= ymax; ++y) {
        uint32_t xend = y == y0 && x0 < xmax + 1 ? x0 : xmax + 1;
        if (!rows_full(k, y, &tight) && row_first(k, y, xend, bx)) {
            *by = y;
            return true;
        }
    }
    return false;
}

/* A free position of D better than *b (b->side UINT32_MAX: none yet) by the rule: RULE_LOW_LEFT
 * the lowest, then leftmost; RULE_SQUARE the one that keeps the square from the grid's corner
 * around all placed charts smallest (inside the square so far when D fits there), then the
 * lowest, then leftmost. */
static bool search(raster *k, cand *b)
{
    const bitmap *d = &k->d;
    if (k->rule != RULE_SQUARE)
        return low_left(k, k->grid, b->y, b->x, &b->x, &b->y);
    uint32_t used = k->used_w > k->used_h ? k->used_w : k->used_h, x, y;
    if (b->side <= used) /* b is inside: only a lower, then more left place inside is better */
        return low_left(k, used, b->y, b->x, &b->x, &b->y);
    if (low_left(k, used, UINT32_MAX, UINT32_MAX, &x, &y)) {
        *b = (cand){x, y, used};
        return true;
    }
    /* D grows the square: the smallest side, row by row (the leftmost place of each) */
    bool found = false;
    uint32_t tight = 0;
    for (y = 0; d->h <= k->grid && d->w <= k->grid && y <= k->grid - d->h; ++y) {
        uint32_t xend = k->grid - d->w + 1;
        if (b->side != UINT32_MAX) { /* later rows, columns: larger squares */
            if (y + d->h > b->side || d->w > b->side)
                break;
            if (b->side - d->w + 1 < xend)
                xend = b->side - d->w + 1;
        }
        if (rows_full(k, y, &tight) || !row_first(k, y, xend, &x))
            continue;
        uint32_t side = square_side(k, x, y);
        if (side < b->side || (side == b->side && (y < b->y || (y == b->y && x < b->x)))) {
            *b = (cand){x, y, side};
            found = true;
        }
    }
    return found;
}

static uint32_t longest_free(const uint64_t *row, uint32_t n)
{
    uint32_t best = 0, run = 0;
    for (uint32_t x = 0; x < n;) {
        uint64_t w = row[x >> 6] >> (x & 63);
        uint32_t left = 64 - (x & 63);
        if (left > n - x)
            left = n - x;
        uint32_t z = w ? (uint32_t)__builtin_ctzll(w) : 64;
        if (z >= left) { /* the rest of the word is free */
            run += left;
            x += left;
            continue;
        }
        run += z;
        best = run > best ? run : best;
        run = 0;
        x += z;
        uint64_t ones = ~(row[x >> 6] >> (x & 63));
        uint32_t o = ones ? (uint32_t)__builtin_ctzll(ones) : 64 - (x & 63);
        x += o ? o : 1;
    }
    return run > best ? run : best;
}

/* Ors C at grid (x, y) into the grid and refreshes the rows' longest free runs. */
static void stamp(raster *k, uint32_t x, uint32_t y)
{
    const bitmap *c = &k->c;
    for (uint32_t j = 0; j < c->h; ++j) {
        uint64_t *g = k->occ + (size_t)(y + j) * k->gw;
        const uint64_t *r = c->bits + (size_t)j * c->words;
        uint32_t g0 = x >> 6, sh = x & 63;
        for (uint32_t w = 0; w < c->words; ++w) {
            g[g0 + w] |= r[w] << sh;
            if (sh && g0 + w + 1 < k->gw)
                g[g0 + w + 1] |= r[w] >> (64 - sh);
        }
        k->maxfree[y + j] = longest_free(g, k->grid);
    }
}

/* Tries chart c in orientation o, turn t at texel factor f against the best position so far. */
static bool try_candidate(raster *k, uint32_t c, int o, int t, double f, cand *b)
{
    uint32_t w, h, p = k->in->pad;
    chart_dims(k, c, o, t, f, &w, &h);
    if (w + 2 * p > k->grid || h + 2 * p > k->grid)
        return false;
    raster_chart(k, c, o, t, f);
    if (k->nomem)
        return false;
    dilate(k, p);
    return !k->nomem && search(k, b);
}

/* Places every chart at texel factor f; true when all fit (positions in k->pl, the highest row
 * used in k->top). The candidate that won in the last trial is tried first (k->pl). */
static bool place_all(raster *k, double f)
{
    uint32_t p = k->in->pad;
    memset(k->occ, 0, (size_t)k->grid * k->gw * sizeof(uint64_t));
    for (uint32_t j = 0; j < k->grid; ++j)
        k->maxfree[j] = k->grid;
    k->top = k->used_w = k->used_h = 0;
    const uint32_t *order = k->order + (size_t)k->key * k->in->nc;
    for (size_t i = 0; i < k->in->nc; ++i) {
        uint32_t c = order[i];
        cand b = {UINT32_MAX, UINT32_MAX, UINT32_MAX};
        int first = 4 * k->pl[c].orient + k->pl[c].turn, best = -1;
        for (int n = -1; n < 4 * k->orients; ++n) {
            int o = n < 0 ? first : n;
            if (n == first)
                continue;
            if (try_candidate(k, c, o / 4, o % 4, f, &b))
                best = o;
            if (k->nomem)
                return false;
        }
        if (best < 0)
            return false;
        raster_chart(k, c, best / 4, best % 4, f);
        stamp(k, b.x + p, b.y + p);
        k->pl[c] = (place){(uint8_t)(best / 4), (uint8_t)(best % 4), b.x, b.y};
        uint32_t w = b.x + 2 * p + k->c.w, h = b.y + 2 * p + k->c.h;
        k->used_w = w > k->used_w ? w : k->used_w;
        k->used_h = h > k->used_h ? h : k->used_h;
    }
    /* the rows a full-width packing of the same area would use (the scale step's estimate) */
    if (k->rule == RULE_SQUARE) {
        uint32_t side = k->used_w > k->used_h ? k->used_w : k->used_h;
        k->top = (uint32_t)ceil((double)side * side / k->grid);
    } else {
        k->top = k->used_h;
    }
    return true;
}

static int cmp_area(const void *x, const void *y)
{
    const double *a = x, *b = y;
    if (a[0] != b[0])
        return a[0] > b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

static sk_status raster_init(raster *k, const sk__raster_in *in, sk_error *err)
{
    size_t nc = in->nc;
    k->in = in;
    k->grid = in->res + 2 * (in->pad - in->margin);
    k->gw = (k->grid + 63) / 64 + 1;
    size_t side = (size_t)k->grid + 2 * in->pad + 64, bm = side * ((side + 63) / 64 + 1);
    k->occ = sk__calloc_array((size_t)k->grid * k->gw, sizeof(uint64_t));
    k->maxfree = sk__malloc_array(k->grid, sizeof(uint32_t));
    k->c.bits = sk__malloc_array(bm, sizeof(uint64_t));
    k->d.bits = sk__malloc_array(bm, sizeof(uint64_t));
    k->tmp.bits = sk__malloc_array(bm, sizeof(uint64_t));
    k->wide = sk__malloc_array(side / 64 + 2, sizeof(uint64_t));
    k->info = sk__malloc_array(side, sizeof(row_info));
    k->row_start = sk__malloc_array(side + 1, sizeof(uint32_t));
    k->order = sk__malloc_array(KEYS * (nc ? nc : 1), sizeof(uint32_t));
    k->orients = nc <= FEW_CHARTS ? ORIENTS : 2;
    for (int o = 0; o < ORIENTS; ++o) {
        double a = o < 2 ? 0 : (o - 1) * (M_PI / 2) / (EXTRA_ANGLES + 1);
        k->rot[2 * o] = cos(a);
        k->rot[2 * o + 1] = sin(a);
    }
    k->lo = sk__malloc_array(2 * ORIENTS * (nc ? nc : 1), sizeof(double));
    k->ext = sk__malloc_array(2 * ORIENTS * (nc ? nc : 1), sizeof(double));
    k->pl = sk__calloc_array(nc ? nc : 1, sizeof(place));
    k->best = sk__malloc_array(nc ? nc : 1, sizeof(place));
    double *keys = sk__malloc_array(2 * (nc ? nc : 1), sizeof(double));
    if (!k->occ || !k->maxfree || !k->c.bits || !k->d.bits || !k->tmp.bits || !k->wide || !k->info || !k->row_start ||
        !k->order || !k->lo || !k->ext || !k->pl || !k->best || !keys) {
        sk__free(keys);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t c = 0; c < nc; ++c) {
        for (int o = 0; o < k->orients; ++o) {
            double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
            for (uint32_t u = in->off[c]; u < in->off[c + 1]; ++u) {
                double q[2];
                oriented(k, o, u, q);
                for (int a = 0; a < 2; ++a) {
                    lo[a] = fmin(lo[a], q[a]);
                    hi[a] = fmax(hi[a], q[a]);
                }
            }
            for (int a = 0; a < 2; ++a) {
                k->lo[2 * (ORIENTS * c + (size_t)o) + (size_t)a] = lo[a];
                k->ext[2 * (ORIENTS * c + (size_t)o) + (size_t)a] = hi[a] - lo[a];
            }
        }
    }
    for (int key = 0; key < KEYS; ++key) { /* the orders, largest first */
        for (size_t c = 0; c < nc; ++c) {
            const double *e = k->ext + 2 * (ORIENTS * c + 1); /* the smallest box */
            keys[2 * c] = key == KEY_AREA ? in->area[c] : key == KEY_SIDE ? fmax(e[0], e[1])
                                                                          : e[0] + e[1];
            keys[2 * c + 1] = (double)c;
        }
        qsort(keys, nc, 2 * sizeof(double), cmp_area);
        for (size_t i = 0; i < nc; ++i)
            k->order[(size_t)key * nc + i] = (uint32_t)keys[2 * i + 1];
    }
    sk__free(keys);
    return SK_OK;
}

static void raster_free(raster *k)
{
    sk__free(k->occ);
    sk__free(k->maxfree);
    sk__free(k->c.bits);
    sk__free(k->d.bits);
    sk__free(k->tmp.bits);
    sk__free(k->wide);
    sk__free(k->info);
    sk__free(k->runs);
    sk__free(k->cross);
    sk__free(k->sorted);
    sk__free(k->row_start);
    sk__free(k->order);
    sk__free(k->lo);
    sk__free(k->ext);
    sk__free(k->pl);
    sk__free(k->best);
}

/* Writes the uv of every chart from its placement at texel factor f. */
static void write_uv(const raster *k, double f, double *uv)
{
    const sk__raster_in *in = k->in;
    double res = (double)in->res;
    for (size_t c = 0; c < in->nc; ++c) {
        const place *q = k->pl + c;
        for (uint32_t u = in->off[c]; u < in->off[c + 1]; ++u) {
            double t[2];
            texel_point(k, (uint32_t)c, q->orient, q->turn, f, u, t);
            uv[2 * (size_t)u] = (t[0] + (double)q->x + (double)in->margin) / res;
            uv[2 * (size_t)u + 1] = (t[1] + (double)q->y + (double)in->margin) / res;
        }
    }
}

/* The largest scale (returned; 0 when none fits) at which every chart is placed, searched from
 * s0 (lowered by 5% steps while nothing fits when descend) below the bound s1; its placement in
 * k->best. */
static double scale_search(raster *k, double s0, double s1, bool descend, int most)
{
    double res = (double)k->in->res, lo = 0, hi = s1, top = 0;
    int trials = 0;
    for (double s = s0; s > 0.5 * s0 && lo == 0 && !k->nomem; s *= 0.95, trials++) {
        if (place_all(k, s * res)) { /* a scale that fits */
            lo = s;
            top = k->top;
            memcpy(k->best, k->pl, k->in->nc * sizeof(place));
        } else {
            hi = s;
        }
        if (!descend)
            break;
    }
    /* up: the used height says how much room is left (a scale step of sqrt(rows / used)),
     * bisection once the step lands past a failure; stops within 0.2% (0.5% above FEW_CHARTS
     * charts, where a trial costs more) */
    double tol = k->in->nc <= FEW_CHARTS ? 1.002 : 1.005;
    for (; lo > 0 && !k->nomem && trials < most && hi > lo * tol; trials++) {
        double s = lo * sqrt((double)k->grid / fmax(top, 1.0)) * 0.998;
        if (!(s > lo * 1.001) || s >= hi * 0.999)
            s = 0.5 * (lo + hi);
        if (place_all(k, s * res)) {
            lo = s;
            top = k->top;
            memcpy(k->best, k->pl, k->in->nc * sizeof(place));
        } else {
            hi = s;
        }
    }
    return k->nomem ? 0 : lo;
}

/* The packings tried: every orientation (all) or the two of each chart, the rule, the order.
 * The first two (each climbing with RASTER_TRIALS from the scale before) come first; the others,
 * best first as measured on the shared meshes, while the positions they test stay within
 * VARIANT_BUDGET times those of the first two. */
static const struct variant {
    bool all;
    int rule, key;
} variants[] = {
    {false, RULE_LOW_LEFT, KEY_AREA}, {true, RULE_LOW_LEFT, KEY_AREA},
    {false, RULE_SQUARE, KEY_AREA},   {false, RULE_LOW_LEFT, KEY_SIDE},
    {true, RULE_SQUARE, KEY_AREA},    {true, RULE_LOW_LEFT, KEY_SIDE},
    {true, RULE_SQUARE, KEY_SIDE},    {true, RULE_SQUARE, KEY_PERIM},
    {true, RULE_LOW_LEFT, KEY_PERIM},
};
#define BASE_VARIANTS 2
#define VARIANT_BUDGET 1

sk_status sk__raster_pack(const sk__raster_in *in, double s0, double s1, double *uv,
                          double *scale, bool *ok, sk_error *err)
{
    raster k;
    memset(&k, 0, sizeof k);
    *ok = false;
    sk_status st = raster_init(&k, in, err);
    if (st)
        goto done;
    /* the variants in turn, each from the best scale so far (the first from s0 down): the
     * greedy placement may do worse with more choice, so the largest scale wins */
    int most = k.orients;
    double best = 0;
    size_t won = 0, nv = sizeof variants / sizeof variants[0];
    uint64_t budget = 0;
    for (size_t v = 0; v <= nv && !k.nomem; ++v) {
        bool last = v == nv; /* the winner once more, finer (when it had fewer trials) */
        const struct variant *var = variants + (last ? won : v);
        if ((v > 0 && var->all && most == 2) || (last && won < BASE_VARIANTS))
            continue;
        if (v == BASE_VARIANTS)
            budget = VARIANT_BUDGET * k.work + k.work;
        if (v >= BASE_VARIANTS && !last && k.work > budget)
            continue;
        k.orients = var->all ? most : 2;
        k.rule = var->rule;
        k.key = var->key;
        memset(k.pl, 0, in->nc * sizeof(place));
        bool extra = v >= BASE_VARIANTS && !last;
        double from = v == 0 ? s0 : last ? best * FINAL_GAIN : extra ? best * VARIANT_GAIN : best;
        double lo = scale_search(&k, from, s1, v == 0, extra ? VARIANT_TRIALS : RASTER_TRIALS);
        if (lo > best) {
            memcpy(k.pl, k.best, in->nc * sizeof(place));
            write_uv(&k, lo * (double)in->res, uv);
            best = lo;
            won = last ? won : v;
        }
        if (best == 0)
            break;
    }
    if (k.nomem) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    *scale = best;
    *ok = best > 0;
done:
    raster_free(&k);
    return st;
}
