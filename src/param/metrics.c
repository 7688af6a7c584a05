/* Distortion metrics of a parametrization (per triangle from the Jacobian J of the linear map
 * from the 3D triangle to its parameter triangle, singular values sigma1 >= sigma2):
 *
 *   |J|_F^2 = sigma1^2 + sigma2^2,  det J = +-sigma1 sigma2 = A_uv / A,
 *   MIPS = sigma1/sigma2 + sigma2/sigma1 = |J|_F^2 / |det J|       (papers README definition)
 *   sigma1/sigma2 = k + sqrt(k^2 - 1) with k = MIPS / 2.
 *
 * Flipped triangles are decided by the exact orientation test sk_orient2d. */
#include "surfkit/param.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct tri_jac {
    double area3;  /* 3D area */
    double area_uv; /* signed uv area */
    double frob2;  /* |J|_F^2 */
    double det;    /* signed det J */
} tri_jac;

static void triangle_jacobian(const sk_mesh *m, const double *uv, uint32_t f, uint32_t v[3],
                              tri_jac *tj)
{
    uint32_t h = m->f_halfedge[f];
    for (int k = 0; k < 3; ++k, h = m->h_next[h])
        v[k] = sk_from(m, h);
    const double *p0 = m->positions + 3 * (size_t)v[0], *p1 = m->positions + 3 * (size_t)v[1],
                 *p2 = m->positions + 3 * (size_t)v[2];
    double e1[3], e2[3], x[3];
    sk__sub3(e1, p1, p0);
    sk__sub3(e2, p2, p0);
    sk__cross3(x, e1, e2);
    double l1 = sk__norm3(e1), twice_a = sk__norm3(x);
    /* local frame: x1 = (l1, 0), x2 = (a, b) */
    double a = sk__dot3(e1, e2) / l1, b = twice_a / l1;
    const double *q0 = uv + 2 * (size_t)v[0], *q1 = uv + 2 * (size_t)v[1],
                 *q2 = uv + 2 * (size_t)v[2];
    double d1[2] = {q1[0] - q0[0], q1[1] - q0[1]}, d2[2] = {q2[0] - q0[0], q2[1] - q0[1]};
    /* J = [d1 d2] [x1 x2]^-1, [x1 x2]^-1 = 1/(l1 b) [[b, -a], [0, l1]] */
    double inv = 1.0 / (l1 * b);
    double j00 = (d1[0] * b) * inv, j01 = (-d1[0] * a + d2[0] * l1) * inv;
    double j10 = (d1[1] * b) * inv, j11 = (-d1[1] * a + d2[1] * l1) * inv;
    tj->area3 = 0.5 * twice_a;
    tj->area_uv = 0.5 * sk__cross2(d1, d2);
    tj->frob2 = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11;
    tj->det = j00 * j11 - j01 * j10;
}

/* sigma1 / sigma2 from |J|_F^2 and det J (inf when det J = 0). */
static double conformal_ratio(double frob2, double det)
{
    if (det == 0)
        return INFINITY;
    double k = frob2 / (2.0 * fabs(det));
    return k + sqrt(fmax(k * k - 1.0, 0.0));
}

sk_status sk_param_face_distortion(const sk_mesh *m, const double *uv, double *conformal,
                                   int8_t *orientation, sk_error *err)
{
    (void)err;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (conformal)
            conformal[f] = 0;
        if (orientation)
            orientation[f] = 0;
        if (m->f_deleted[f] || sk_mesh_face_size(m, (uint32_t)f) != 3)
            continue;
        uint32_t v[3];
        tri_jac tj;
        triangle_jacobian(m, uv, (uint32_t)f, v, &tj);
        if (conformal)
            conformal[f] = conformal_ratio(tj.frob2, tj.det);
        if (orientation)
            orientation[f] = (int8_t)sk_orient2d(uv + 2 * (size_t)v[0], uv + 2 * (size_t)v[1],
                                                 uv + 2 * (size_t)v[2]);
    }
    return SK_OK;
}

/* ---- boundary self-intersections: sweep over boundary edges sorted by their smallest u ---- */

typedef struct bedge {
    uint32_t a, b;
    double lo, hi; /* u extent */
} bedge;

static int bedge_cmp(const void *x, const void *y)
{
    double a = ((const bedge *)x)->lo, b = ((const bedge *)y)->lo;
    return a < b ? -1 : a > b;
}

static bool on_segment(const double *p, const double *q, const double *r)
{
    /* r collinear with p q: inside its bounding box? */
    return fmin(p[0], q[0]) <= r[0] && r[0] <= fmax(p[0], q[0]) && fmin(p[1], q[1]) <= r[1] &&
           r[1] <= fmax(p[1], q[1]);
}

static bool segments_intersect(const double *p1, const double *p2, const double *p3,
                               const double *p4)
{
    int o1 = sk_orient2d(p1, p2, p3), o2 = sk_orient2d(p1, p2, p4);
    int o3 = sk_orient2d(p3, p4, p1), o4 = sk_orient2d(p3, p4, p2);
    if (o1 * o2 < 0 && o3 * o4 < 0)
        return true;
    return (o1 == 0 && on_segment(p1, p2, p3)) || (o2 == 0 && on_segment(p1, p2, p4)) ||
           (o3 == 0 && on_segment(p3, p4, p1)) || (o4 == 0 && on_segment(p3, p4, p2));
}

static sk_status boundary_intersections(const sk_mesh *m, const double *uv, size_t *count,
                                        sk_error *err)
{
    *count = 0;
    size_t nb = 0;
    for (size_t h = 0; h < m->num_halfedges; ++h)
        if (!m->e_deleted[h >> 1] && sk_is_boundary_h(m, (uint32_t)h))
            nb++;
    if (nb < 4)
        return SK_OK;
    bedge *e = sk__malloc_array(nb, sizeof *e);
    if (!e)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    nb = 0;
    for (size_t h = 0; h < m->num_halfedges; ++h) {
        if (m->e_deleted[h >> 1] || !sk_is_boundary_h(m, (uint32_t)h))
            continue;
        bedge *b = &e[nb++];
        b->a = sk_from(m, (uint32_t)h);
        b->b = sk_to(m, (uint32_t)h);
        b->lo = fmin(uv[2 * (size_t)b->a], uv[2 * (size_t)b->b]);
        b->hi = fmax(uv[2 * (size_t)b->a], uv[2 * (size_t)b->b]);
    }
    qsort(e, nb, sizeof *e, bedge_cmp);
    size_t n = 0;
    for (size_t i = 0; i < nb; ++i) {
        for (size_t j = i + 1; j < nb && e[j].lo <= e[i].hi; ++j) {
            if (e[i].a == e[j].a || e[i].a == e[j].b || e[i].b == e[j].a || e[i].b == e[j].b)
                continue;
            if (segments_intersect(uv + 2 * (size_t)e[i].a, uv + 2 * (size_t)e[i].b,
                                   uv + 2 * (size_t)e[j].a, uv + 2 * (size_t)e[j].b))
                n++;
        }
    }
    sk__free(e);
    *count = n;
    return SK_OK;
}

sk_status sk_param_metrics_compute(const sk_mesh *m, const double *uv, sk_param_metrics *out,
                                   sk_error *err)
{
    sk_param_metrics r;
    memset(&r, 0, sizeof r);
    double area3 = 0, area_uv_abs = 0, conf_w = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        if (sk_mesh_face_size(m, (uint32_t)f) != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu is not a triangle", f);
        uint32_t v[3];
        tri_jac tj;
        triangle_jacobian(m, uv, (uint32_t)f, v, &tj);
        r.faces++;
        int o = sk_orient2d(uv + 2 * (size_t)v[0], uv + 2 * (size_t)v[1], uv + 2 * (size_t)v[2]);
        if (o <= 0)
            r.flipped++;
        if (o == 0)
            r.degenerate++;
        double mips = tj.det != 0 ? tj.frob2 / fabs(tj.det) : INFINITY;
        r.mips_sum += mips;
        double c = conformal_ratio(tj.frob2, tj.det);
        conf_w += tj.area3 * c;
        r.conformal_max = fmax(r.conformal_max, c);
        area3 += tj.area3;
        area_uv_abs += fabs(tj.area_uv);
        r.area_uv += tj.area_uv;
    }
    if (r.faces == 0)
        return sk__fail(err, SK_ERR_TOPOLOGY, "the mesh has no faces");
    r.mips_mean = r.mips_sum / (double)r.faces;
    r.conformal_mean = area3 > 0 ? conf_w / area3 : INFINITY;
    /* second pass: area ratios and stretch with uv scaled to the 3D area */
    double scale = area_uv_abs > 0 ? sqrt(area3 / area_uv_abs) : INFINITY;
    double log_sum = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t v[3];
        tri_jac tj;
        triangle_jacobian(m, uv, (uint32_t)f, v, &tj);
        double ratio = (fabs(tj.area_uv) / area_uv_abs) / (tj.area3 / area3);
        log_sum += fabs(log(ratio));
        double sd = sqrt(fmax(tj.frob2 * tj.frob2 - 4 * tj.det * tj.det, 0.0));
        double s1 = sqrt(0.5 * (tj.frob2 + sd)) * scale;
        double s2 = s1 > 0 ? fabs(tj.det) * scale * scale / s1 : 0;
        double st = fmax(s1, s2 > 0 ? 1.0 / s2 : INFINITY);
        r.stretch_max = fmax(r.stretch_max, st);
    }
    r.area_log_mean = log_sum / (double)r.faces;
    sk_status st = boundary_intersections(m, uv, &r.boundary_self_intersections, err);
    if (st)
        return st;
    *out = r;
    return SK_OK;
}
