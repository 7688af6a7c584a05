/* Parametrization of one disk chart: the project's hierarchical MIPS with a free boundary (the
 * single place the atlas calls the parametrizer), scaled to the chart's 3D area, and measured. */
#include "atlas/atlas_internal.h"
#include "core/internal.h"
#include "core/vec.h"
#include "surfkit/mips.h"
#include "surfkit/parametrize.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sk__tri_distortion(const double *p0, const double *p1, const double *p2, const double *q0,
                        const double *q1, const double *q2, double *area3, double *area_uv,
                        double *mips, double *conformal)
{
    double e1[3], e2[3], x[3];
    sk__sub3(e1, p1, p0);
    sk__sub3(e2, p2, p0);
    sk__cross3(x, e1, e2);
    double l1 = sk__norm3(e1), twice_a = sk__norm3(x);
    double a = sk__dot3(e1, e2) / l1, b = twice_a / l1; /* local frame: (l1, 0), (a, b) */
    double d1[2] = {q1[0] - q0[0], q1[1] - q0[1]}, d2[2] = {q2[0] - q0[0], q2[1] - q0[1]};
    double inv = 1.0 / (l1 * b);
    double j00 = d1[0] * b * inv, j01 = (-d1[0] * a + d2[0] * l1) * inv;
    double j10 = d1[1] * b * inv, j11 = (-d1[1] * a + d2[1] * l1) * inv;
    double frob2 = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11, det = j00 * j11 - j01 * j10;
    *area3 = 0.5 * twice_a;
    *area_uv = 0.5 * sk__cross2(d1, d2);
    *mips = det != 0 ? frob2 / fabs(det) : INFINITY;
    double k = det != 0 ? frob2 / (2.0 * fabs(det)) : INFINITY;
    *conformal = isfinite(k) ? k + sqrt(fmax(k * k - 1.0, 0.0)) : INFINITY;
}

/* Sweeps of the area-term refinement at most (bench/atlas.sh), each after a global step. */
#define SK__CHART_AREA_SWEEPS 20

/* A chart of more vertices than this gets fewer global steps (each one a sparse factorization,
 * which grows faster than the chart) and more local sweeps instead: on the 0.8M-triangle
 * armadillo (two charts of 90k and 111k triangles, 45k and 55k vertices) 6 global steps and 80
 * sweeps take 32 s of CPU against 48 s for 20 and 20, at area-log mean 0.062 against 0.065; on
 * the scans whose charts are all below it (lion, cow) 20 global steps give the lower area
 * distortion (lion 0.057 against 0.066) at a small cost. */
#define SK__CHART_AREA_LARGE 5000
#define SK__CHART_AREA_LARGE_GLOBALS 6
#define SK__CHART_AREA_LARGE_SWEEPS 80

/* The one call into the parametrization module. */
static sk_status parametrize(const sk_mesh *chart, uint64_t seed, double *uv, sk_error *err)
{
    sk_parametrize_opts o = {0};
    o.method = SK_PARAM_MIPS;
    o.boundary.shape = SK_BOUNDARY_FREE;
    o.seed = seed;
    o.raw = true; /* the chart is scaled to its 3D area afterwards */
    sk_parametrize_stats ps;
    sk_status st = sk_parametrize(chart, &o, uv, &ps, err);
    sk_parametrize_stats_release(&ps);
    return st;
}

/* LSCM: one linear solve, the predictor of the distortion MIPS will reach (both maps are close
 * to conformal; their area distortions are close, see sk__chart_predict). */
static sk_status lscm(const sk_mesh *chart, double *uv, sk_error *err)
{
    sk_parametrize_opts o = {0};
    o.method = SK_PARAM_LSCM;
    o.boundary.shape = SK_BOUNDARY_FREE;
    o.raw = true;
    sk_parametrize_stats ps;
    sk_status st = sk_parametrize(chart, &o, uv, &ps, err);
    sk_parametrize_stats_release(&ps);
    return st;
}

/* A single triangle laid out isometrically, counter-clockwise. */
static void lay_triangle(const sk_mesh *c, double *uv)
{
    uint32_t h = c->f_halfedge[0], v[3];
    for (int k = 0; k < 3; ++k, h = c->h_next[h])
        v[k] = sk_from(c, h);
    const double *p0 = c->positions + 3 * (size_t)v[0], *p1 = c->positions + 3 * (size_t)v[1],
                 *p2 = c->positions + 3 * (size_t)v[2];
    double e1[3], e2[3], x[3];
    sk__sub3(e1, p1, p0);
    sk__sub3(e2, p2, p0);
    sk__cross3(x, e1, e2);
    double l1 = sk__norm3(e1);
    uv[2 * v[0]] = 0;
    uv[2 * v[0] + 1] = 0;
    uv[2 * v[1]] = l1;
    uv[2 * v[1] + 1] = 0;
    uv[2 * v[2]] = sk__dot3(e1, e2) / l1;
    uv[2 * v[2] + 1] = sk__norm3(x) / l1;
}

static void measure(const sk_mesh *c, const double *uv, sk__chart_quality *q, double *log_scale)
{
    memset(q, 0, sizeof *q);
    double conf = 0;
    for (size_t f = 0; f < c->num_faces; ++f) {
        uint32_t h = c->f_halfedge[f], v[3];
        for (int k = 0; k < 3; ++k, h = c->h_next[h])
            v[k] = sk_from(c, h);
        const double *q0 = uv + 2 * (size_t)v[0], *q1 = uv + 2 * (size_t)v[1],
                     *q2 = uv + 2 * (size_t)v[2];
        if (sk_orient2d(q0, q1, q2) <= 0)
            q->flipped++;
        double a3, auv, mips, cr;
        sk__tri_distortion(c->positions + 3 * (size_t)v[0], c->positions + 3 * (size_t)v[1],
                           c->positions + 3 * (size_t)v[2], q0, q1, q2, &a3, &auv, &mips, &cr);
        q->area3 += a3;
        q->area_uv += fabs(auv);
        conf += a3 * cr;
        if (log_scale)
            log_scale[f] = log(fabs(auv) / a3);
    }
    q->conformal_mean = conf / q->area3;
}

/* Scales uv to the chart's 3D area and measures it (area_log_dev included). */
static sk_status scale_measure(const sk_mesh *chart, double *uv, sk__chart_quality *q,
                               sk_error *err)
{
    double *ls = NULL;
    /* MIPS is scale invariant: give the chart its 3D area so that one scale fits all charts */
    ls = sk__malloc_array(chart->num_faces, sizeof(double));
    if (!ls)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    measure(chart, uv, q, NULL);
    double s = q->area_uv > 0 ? sqrt(q->area3 / q->area_uv) : 1.0;
    for (size_t i = 0; i < 2 * chart->num_vertices; ++i)
        uv[i] *= s;
    measure(chart, uv, q, ls);
    /* area distortion: 3D-area weighted |log scale - mean log scale| */
    double mean = 0, dev = 0;
    for (size_t f = 0; f < chart->num_faces; ++f)
        mean += sk_mesh_face_area(chart, (uint32_t)f) * ls[f];
    mean /= q->area3;
    for (size_t f = 0; f < chart->num_faces; ++f)
        dev += sk_mesh_face_area(chart, (uint32_t)f) * fabs(ls[f] - mean);
    q->area_log_dev = dev / q->area3;
    sk__free(ls);
    return SK_OK;
}

sk_status sk__chart_param(const sk_mesh *chart, uint64_t seed, double *uv, sk__chart_quality *q,
                          sk_error *err)
{
    sk_status st = SK_OK;
    if (chart->num_faces == 1)
        lay_triangle(chart, uv);
    else if ((st = parametrize(chart, seed, uv, err)))
        return st;
    return scale_measure(chart, uv, q, err);
}

sk_status sk__chart_predict(const sk_mesh *chart, double *uv, sk__chart_quality *q, bool *ok,
                            sk_error *err)
{
    *ok = false;
    sk_error lerr = {0};
    sk_status st = lscm(chart, uv, &lerr);
    if (st == SK_ERR_NOMEM || st == SK_ERR_CANCELLED) {
        if (err)
            *err = lerr;
        return st;
    }
    if (st != SK_OK)
        return SK_OK; /* flipped or failed: no prediction */
    if ((st = scale_measure(chart, uv, q, err)))
        return st;
    *ok = isfinite(q->area_log_dev) && isfinite(q->conformal_mean) && q->flipped == 0;
    return SK_OK;
}

sk_status sk__chart_area(const sk_mesh *chart, uint64_t seed, double theta, double *uv,
                         sk__chart_quality *q, bool *ok, sk_error *err)
{
    *ok = false;
    sk_mips_opts o = {0};
    o.boundary = SK_BOUNDARY_FREE;
    o.seed = seed;
    o.area_theta = theta;
    o.max_sweeps = SK__CHART_AREA_SWEEPS;
    o.tolerance = 1e-5;
    o.global_steps = chart->num_vertices > 64 ? SK__CHART_AREA_SWEEPS : 0;
    if (chart->num_vertices > SK__CHART_AREA_LARGE) {
        o.global_steps = SK__CHART_AREA_LARGE_GLOBALS;
        o.max_sweeps = SK__CHART_AREA_LARGE_SWEEPS;
    }
    o.frozen_model = true;
    o.frozen_keep = true;
    o.frozen_steps = o.global_steps; /* one factorization unless a step finds no decrease */
    sk_error lerr = {0};
    sk_status st = sk_param_mips(chart, &o, uv, NULL, &lerr);
    if (st == SK_ERR_NOMEM || st == SK_ERR_CANCELLED) {
        if (err)
            *err = lerr;
        return st;
    }
    if (st != SK_OK)
        return SK_OK;
    if ((st = scale_measure(chart, uv, q, err)))
        return st;
    *ok = isfinite(q->area_log_dev) && isfinite(q->conformal_mean) && q->flipped == 0;
    return SK_OK;
}
