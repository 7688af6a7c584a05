/* The chart packer (src/atlas/pack.c, raster_pack.c) on charts given as outlines. Given a U-shaped
 * chart with a deep notch and small squares that fit into the notch, when packed at 1024 texels
 * with a gutter of 2, then every point is in [0,1]^2, the outlines of different charts are at
 * least 2 texels apart and never cross, every chart keeps its area times the one common scale
 * squared, the squares sit inside the U's bounding box (the packer fills the concave void), and
 * the utilization reaches 0.7 (a box packer leaves the notch empty: the U fills 5.92 of its box's 9). */
#include "testutil.h"
#include "atlas/atlas_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PTS 64

typedef struct charts {
    size_t nc, n;
    uint32_t off[16], chart[MAX_PTS], edges[2 * MAX_PTS];
    double uv[2 * MAX_PTS], area[16];
} charts;

/* Adds a closed counter-clockwise polygon (m points) as one chart, rotated by angle a. */
static void add_chart(charts *c, const double *p, size_t m, double a)
{
    c->off[c->nc] = (uint32_t)c->n;
    double area = 0;
    for (size_t i = 0; i < m; ++i) {
        const double *q = p + 2 * i, *r = p + 2 * ((i + 1) % m);
        area += 0.5 * (q[0] * r[1] - q[1] * r[0]);
        c->uv[2 * c->n] = cos(a) * q[0] - sin(a) * q[1] + 5;
        c->uv[2 * c->n + 1] = sin(a) * q[0] + cos(a) * q[1] - 3;
        c->chart[c->n] = (uint32_t)c->nc;
        c->edges[2 * c->n] = (uint32_t)c->n;
        c->edges[2 * c->n + 1] = (uint32_t)(c->off[c->nc] + (i + 1) % m);
        c->n++;
    }
    c->area[c->nc++] = area;
    c->off[c->nc] = (uint32_t)c->n;
}

static double polygon_area(const double *uv, uint32_t a, uint32_t b)
{
    double s = 0;
    for (uint32_t i = a; i < b; ++i) {
        const double *q = uv + 2 * i, *r = uv + 2 * (i + 1 < b ? i + 1 : a);
        s += 0.5 * (q[0] * r[1] - q[1] * r[0]);
    }
    return s;
}

static double seg_point(const double *p, const double *a, const double *b)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], ll = dx * dx + dy * dy;
    double t = ll > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / ll : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

static double side(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Distance between segments a-b and c-d (0 when they cross). */
static double seg_seg(const double *a, const double *b, const double *c, const double *d)
{
    if (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0)
        return 0;
    return fmin(fmin(seg_point(c, a, b), seg_point(d, a, b)),
                fmin(seg_point(a, c, d), seg_point(b, c, d)));
}

/* Is p inside the closed polygon [a, b) (even-odd)? */
static bool inside(const double *uv, uint32_t a, uint32_t b, const double *p)
{
    bool in = false;
    for (uint32_t i = a; i < b; ++i) {
        const double *q = uv + 2 * i, *r = uv + 2 * (i + 1 < b ? i + 1 : a);
        if ((q[1] > p[1]) != (r[1] > p[1]) &&
            p[0] < q[0] + (p[1] - q[1]) / (r[1] - q[1]) * (r[0] - q[0]))
            in = !in;
    }
    return in;
}

static void test_fills_the_notch(void **state)
{
    (void)state;
    static const double u[] = {0, 0, 3, 0, 3, 3, 2.2, 3, 2.2, 0.8, 0.8, 0.8, 0.8, 3, 0, 3};
    static const double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
    charts c;
    memset(&c, 0, sizeof c);
    add_chart(&c, u, 8, 0.3);
    for (int i = 0; i < 2; ++i) {
        double s[8];
        for (int k = 0; k < 8; ++k)
            s[k] = 0.62 * sq[k];
        add_chart(&c, s, 4, 0.1 * i);
    }
    double before[16];
    for (size_t k = 0; k < c.nc; ++k)
        before[k] = polygon_area(c.uv, c.off[k], c.off[k + 1]);
    double scale = 0;
    sk_error err;
    const double res = 1024, pad = 2;
    if (sk__pack_charts(c.nc, c.off, c.chart, c.uv, c.n, c.edges, res, pad, &scale, &err))
        fail_msg("%s", err.message);
    double total = 0;
    for (size_t i = 0; i < 2 * c.n; ++i)
        assert_true(c.uv[i] >= 0 && c.uv[i] <= 1);
    for (size_t k = 0; k < c.nc; ++k) {
        double a = polygon_area(c.uv, c.off[k], c.off[k + 1]);
        assert_true(fabs(a / (before[k] * scale * scale) - 1) < 1e-9);
        total += a;
    }
    double gap = INFINITY;
    for (size_t i = 0; i < c.n; ++i)
        for (size_t j = 0; j < c.n; ++j) {
            const uint32_t *e = c.edges + 2 * i, *f = c.edges + 2 * j;
            if (c.chart[e[0]] < c.chart[f[0]])
                gap = fmin(gap, seg_seg(c.uv + 2 * e[0], c.uv + 2 * e[1], c.uv + 2 * f[0],
                                        c.uv + 2 * f[1]));
        }
    print_message("U and 2 squares: utilization %.4f, smallest gap %.3f texels\n", total,
                  gap * res);
    assert_true(gap * res >= pad - 1e-6);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (uint32_t i = c.off[0]; i < c.off[1]; ++i)
        for (int a = 0; a < 2; ++a) {
            lo[a] = fmin(lo[a], c.uv[2 * i + (size_t)a]);
            hi[a] = fmax(hi[a], c.uv[2 * i + (size_t)a]);
        }
    for (size_t k = 1; k < c.nc; ++k) { /* the squares: in the U's box, outside the U */
        double m[2] = {0, 0};
        for (uint32_t i = c.off[k]; i < c.off[k + 1]; ++i)
            for (int a = 0; a < 2; ++a)
                m[a] += c.uv[2 * i + (size_t)a] / (c.off[k + 1] - c.off[k]);
        assert_true(m[0] > lo[0] && m[0] < hi[0] && m[1] > lo[1] && m[1] < hi[1]);
        assert_false(inside(c.uv, c.off[0], c.off[1], m));
    }
    assert_true(total >= 0.7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fills_the_notch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
