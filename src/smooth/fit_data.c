/* The data of the fit to the scan (fair_points.c's data term W * sum_i |S(u_i) - p_i|^2), both
 * ways, as the deviation is measured:
 *  - the mesh's side: points p_i of a fine mesh (every vertex and FIT_FACE_SAMPLES points inside
 *    every triangle), each with the patch and the parameters u_i of its foot point on the VC1
 *    surface as assembled (the point of the surface nearest to it: found on a tessellation of
 *    each patch on its own grid, whose vertices carry their patch parameters, then a few
 *    Gauss-Newton steps of the projection onto that patch);
 *  - the surface's side: the interior points u_i of a FIT_SURFACE_GRID grid on every patch, each
 *    with p_i the point of the fine mesh nearest to S(u_i) (a bulge between the mesh's points
 *    is seen from here).
 * The pairs are those of the surface before the fit and stay fixed while the control points
 * move (the data term is then a quadratic in the maps D, as fair_points.c needs); the fit finds
 * them again in its next round (vc1.c). */
#include "smooth/vc1_internal.h"
#include "surfkit/deviation.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

/* grid steps per patch side of the tessellation the foot points are searched on */
#define FIT_TESS 6
/* Gauss-Newton steps of the projection onto the patch after the search */
#define FIT_PROJECT_STEPS 3
/* the other way: the interior points of this grid on every patch, each paired with the point of
 * the fine mesh nearest to it */
#define FIT_SURFACE_GRID 4
/* points per fine triangle (barycentric, below) */
#define FIT_FACE_SAMPLES 4
static const double fit_bary[FIT_FACE_SAMPLES][3] = {
    {1.0 / 3, 1.0 / 3, 1.0 / 3}, {2.0 / 3, 1.0 / 6, 1.0 / 6},
    {1.0 / 6, 2.0 / 3, 1.0 / 6}, {1.0 / 6, 1.0 / 6, 2.0 / 3}};

void sk__fit_basis(int corners, double a, double b, double B[16])
{
    if (corners == 3) { /* b_{ijk} at sk_tri_index(4, j, k): 4! / (i! j! k!) u^i a^j b^k */
        double u = 1.0 - a - b, pu[5] = {1, u, u * u, u * u * u, u * u * u * u};
        double pa[5] = {1, a, a * a, a * a * a, a * a * a * a};
        double pb[5] = {1, b, b * b, b * b * b, b * b * b * b};
        static const double fact[5] = {1, 1, 2, 6, 24};
        for (unsigned k = 0; k <= 4; ++k)
            for (unsigned j = 0; j + k <= 4; ++j) {
                unsigned i = 4 - j - k;
                B[sk_tri_index(4, j, k)] =
                    24.0 / (fact[i] * fact[j] * fact[k]) * pu[i] * pa[j] * pb[k];
            }
        B[15] = 0.0;
        return;
    }
    double Ba[4], Bb[4]; /* cubic Bernstein */
    double x = a, y = 1.0 - a;
    Ba[0] = y * y * y, Ba[1] = 3 * x * y * y, Ba[2] = 3 * x * x * y, Ba[3] = x * x * x;
    x = b, y = 1.0 - b;
    Bb[0] = y * y * y, Bb[1] = 3 * x * y * y, Bb[2] = 3 * x * x * y, Bb[3] = x * x * x;
    for (unsigned j = 0; j < 4; ++j)
        for (unsigned i = 0; i < 4; ++i)
            B[sk_tensor_index(3, i, j)] = Ba[i] * Bb[j];
}

void sk__fit_data_free(sk__fit_data *d)
{
    sk__free(d->first);
    sk__free(d->uv);
    sk__free(d->p);
    d->first = NULL;
    d->uv = d->p = NULL;
    d->count = 0;
}

/* (a, b) clamped to the domain of a patch with `corners` corners */
static void clamp_domain(int corners, double *a, double *b)
{
    *a = fmin(fmax(*a, 0.0), 1.0);
    *b = fmin(fmax(*b, 0.0), 1.0);
    if (corners == 3 && *a + *b > 1.0) {
        double e = 0.5 * (*a + *b - 1.0);
        *a -= e, *b -= e;
        *a = fmax(*a, 0.0), *b = fmax(*b, 0.0);
    }
}

/* Gauss-Newton steps from (a, b) towards the foot point of p on patch f (kept while closer) */
static void project(const sk_patch_set *set, size_t f, const double p[3], double *a, double *b)
{
    int corners = (int)sk_patch_num_corners(&set->patches[f]);
    double x[3], du[3], dv[3], r[3];
    sk_patch_eval(set, f, *a, *b, x, du, dv, NULL);
    sk__sub3(r, x, p);
    double best = sk__dot3(r, r);
    for (int it = 0; it < FIT_PROJECT_STEPS; ++it) {
        double g00 = sk__dot3(du, du), g01 = sk__dot3(du, dv), g11 = sk__dot3(dv, dv);
        double r0 = sk__dot3(du, r), r1 = sk__dot3(dv, r), det = g00 * g11 - g01 * g01;
        if (!(det > 1e-30 * (g00 * g11)) || !(det > 0.0))
            return;
        double na = *a - (g11 * r0 - g01 * r1) / det, nb = *b - (g00 * r1 - g01 * r0) / det;
        clamp_domain(corners, &na, &nb);
        double y[3], dyu[3], dyv[3], s[3];
        sk_patch_eval(set, f, na, nb, y, dyu, dyv, NULL);
        sk__sub3(s, y, p);
        double d2 = sk__dot3(s, s);
        if (!(d2 < best))
            return;
        best = d2;
        *a = na, *b = nb;
        memcpy(du, dyu, sizeof du);
        memcpy(dv, dyv, sizeof dv);
        memcpy(r, s, sizeof r);
    }
}

/* The tessellation of every patch on its own FIT_TESS grid (no shared vertices), each vertex with
 * its patch parameters as uv; face_patch gets each soup face's patch. */
static sk_status patch_soup(const sk_patch_set *set, sk_soup **out, uint32_t **face_patch,
                            sk_error *err)
{
    const unsigned n = FIT_TESS;
    size_t nv = 0, nf = 0;
    for (size_t p = 0; p < set->count; ++p) {
        bool quad = set->patches[p].kind == SK_PATCH_TENSOR;
        nv += quad ? (size_t)(n + 1) * (n + 1) : (size_t)(n + 1) * (n + 2) / 2;
        nf += quad ? 2 * (size_t)n * n : (size_t)n * n;
    }
    *face_patch = sk__malloc_array(nf + 1, sizeof(uint32_t));
    if (!*face_patch)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory fitting the scan");
    sk_status st = sk_soup_create(nv, nf, 3 * nf, false, true, out, err);
    size_t face = 0;
    for (size_t p = 0; p < set->count && st == SK_OK; ++p) {
        bool quad = set->patches[p].kind == SK_PATCH_TENSOR;
        uint32_t v0 = (uint32_t)(*out)->num_vertices;
        for (unsigned j = 0; j <= n && st == SK_OK; ++j)
            for (unsigned i = 0; (quad ? i <= n : i + j <= n) && st == SK_OK; ++i) {
                double uv[2] = {(double)i / n, (double)j / n}, x[3];
                sk_patch_eval(set, p, uv[0], uv[1], x, NULL, NULL, NULL);
                st = sk_soup_push_vertex(*out, x, NULL, uv);
            }
        /* row j starts at: quad (n + 1) j; triangle sum_{r < j} (n + 1 - r) */
        for (unsigned j = 0; j < n && st == SK_OK; ++j) {
            uint32_t r0 = v0 + (quad ? (n + 1) * j : j * (n + 1) - j * (j - 1) / 2);
            uint32_t r1 = v0 + (quad ? (n + 1) * (j + 1) : (j + 1) * (n + 1) - (j + 1) * j / 2);
            for (unsigned i = 0; (quad ? i < n : i + j < n) && st == SK_OK; ++i) {
                uint32_t t1[3] = {r0 + i, r0 + i + 1, r1 + i};
                if ((st = sk_soup_push_face(*out, t1, 3)) != SK_OK)
                    break;
                (*face_patch)[face++] = (uint32_t)p;
                if (quad || i + j + 1 < n) {
                    uint32_t t2[3] = {r0 + i + 1, r1 + i + 1, r1 + i};
                    if ((st = sk_soup_push_face(*out, t2, 3)) != SK_OK)
                        break;
                    (*face_patch)[face++] = (uint32_t)p;
                }
            }
        }
    }
    return st;
}

/* The parameters of point q on soup face f (barycentric on the triangle, uv interpolated) */
static void soup_uv(const sk_soup *s, uint32_t f, const double q[3], double uv[2])
{
    const uint32_t *ix = s->face_indices + s->face_offsets[f];
    const double *a = s->positions + 3 * (size_t)ix[0], *b = s->positions + 3 * (size_t)ix[1],
                 *c = s->positions + 3 * (size_t)ix[2];
    double e0[3], e1[3], d[3];
    sk__sub3(e0, b, a);
    sk__sub3(e1, c, a);
    sk__sub3(d, q, a);
    double g00 = sk__dot3(e0, e0), g01 = sk__dot3(e0, e1), g11 = sk__dot3(e1, e1);
    double r0 = sk__dot3(e0, d), r1 = sk__dot3(e1, d), det = g00 * g11 - g01 * g01;
    double l1 = 1.0 / 3, l2 = 1.0 / 3;
    if (det > 0.0) {
        l1 = (g11 * r0 - g01 * r1) / det;
        l2 = (g00 * r1 - g01 * r0) / det;
    }
    const double *ua = s->uvs + 2 * (size_t)ix[0], *ub = s->uvs + 2 * (size_t)ix[1],
                 *uc = s->uvs + 2 * (size_t)ix[2];
    for (int x = 0; x < 2; ++x)
        uv[x] = ua[x] + l1 * (ub[x] - ua[x]) + l2 * (uc[x] - ua[x]);
}

sk_status sk__vc1_fit_data(const sk_smooth *s, const sk_mesh *fine, double weight,
                           sk__fit_data *out, sk_error *err)
{
    memset(out, 0, sizeof *out);
    out->weight = weight;
    const sk_patch_set *set = &s->surface;
    size_t np = set->count, count = 0;
    for (uint32_t v = 0; v < fine->num_vertices; ++v)
        count += !fine->v_deleted[v] && fine->v_halfedge[v] != SK_INVALID;
    for (uint32_t f = 0; f < fine->num_faces; ++f)
        count += fine->f_deleted[f] || sk_mesh_face_size(fine, f) != 3 ? 0 : FIT_FACE_SAMPLES;
    size_t nfine = count;
    const unsigned g = FIT_SURFACE_GRID;
    for (size_t p = 0; p < np; ++p)
        count += set->patches[p].kind == SK_PATCH_TENSOR ? (size_t)(g - 1) * (g - 1)
                                                         : (size_t)(g - 1) * (g - 2) / 2;
    sk_soup *fsoup = NULL;
    sk_bvh *fbvh = NULL;
    sk_soup *soup = NULL;
    sk_bvh *bvh = NULL;
    uint32_t *face_patch = NULL, *pt_patch = sk__malloc_array(count + 1, sizeof(uint32_t));
    double *pts = sk__malloc_array(count + 1, 3 * sizeof(double));
    double *uv = sk__malloc_array(count + 1, 2 * sizeof(double));
    out->first = sk__calloc_array(np + 2, sizeof(size_t));
    out->uv = sk__malloc_array(count + 1, 2 * sizeof(double));
    out->p = sk__malloc_array(count + 1, 3 * sizeof(double));
    sk_status st = SK_OK;
    if (!pt_patch || !pts || !uv || !out->first || !out->uv || !out->p) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory fitting the scan");
        goto done;
    }
    if ((st = patch_soup(set, &soup, &face_patch, err)) != SK_OK ||
        (st = sk_bvh_build(soup, &bvh, err)) != SK_OK)
        goto done;
    size_t k = 0;
    for (uint32_t v = 0; v < fine->num_vertices; ++v)
        if (!fine->v_deleted[v] && fine->v_halfedge[v] != SK_INVALID)
            memcpy(pts + 3 * k++, fine->positions + 3 * (size_t)v, 3 * sizeof(double));
    for (uint32_t f = 0; f < fine->num_faces; ++f) {
        if (fine->f_deleted[f] || sk_mesh_face_size(fine, f) != 3)
            continue;
        uint32_t h = fine->f_halfedge[f];
        const double *a = fine->positions + 3 * (size_t)sk_from(fine, h);
        const double *b = fine->positions + 3 * (size_t)sk_to(fine, h);
        const double *c = fine->positions + 3 * (size_t)sk_to(fine, fine->h_next[h]);
        for (int q = 0; q < FIT_FACE_SAMPLES; ++q, ++k)
            for (int x = 0; x < 3; ++x)
                pts[3 * k + x] =
                    fit_bary[q][0] * a[x] + fit_bary[q][1] * b[x] + fit_bary[q][2] * c[x];
    }
    /* the surface's side: interior grid points of every patch */
    for (size_t p = 0; p < np; ++p) {
        bool quad = set->patches[p].kind == SK_PATCH_TENSOR;
        for (unsigned j = 1; j < g; ++j)
            for (unsigned i = 1; quad ? i < g : i + j < g; ++i, ++k) {
                pt_patch[k] = (uint32_t)p;
                uv[2 * k] = (double)i / g;
                uv[2 * k + 1] = (double)j / g;
            }
    }
    if ((st = sk_mesh_to_soup(fine, &fsoup, err)) != SK_OK ||
        (st = sk_bvh_build(fsoup, &fbvh, err)) != SK_OK)
        goto done;
    long n = (long)nfine;
    long ns = (long)(count - nfine);
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1024)
#endif
    for (long i = 0; i < ns; ++i) {
        size_t q = nfine + (size_t)i;
        double x[3];
        sk_closest cl;
        sk_patch_eval(set, pt_patch[q], uv[2 * q], uv[2 * q + 1], x, NULL, NULL, NULL);
        sk_bvh_closest(fbvh, x, &cl);
        memcpy(pts + 3 * q, cl.point, 3 * sizeof(double));
    }
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1024)
#endif
    for (long i = 0; i < n; ++i) {
        sk_closest cl;
        sk_bvh_closest(bvh, pts + 3 * i, &cl);
        uint32_t p = face_patch[cl.face];
        pt_patch[i] = p;
        soup_uv(soup, cl.face, cl.point, uv + 2 * i);
        clamp_domain((int)sk_patch_num_corners(&set->patches[p]), uv + 2 * i, uv + 2 * i + 1);
        project(set, p, pts + 3 * i, uv + 2 * i, uv + 2 * i + 1);
    }
    /* counting sort by patch (stable: deterministic) */
    for (size_t i = 0; i < count; ++i)
        out->first[pt_patch[i] + 1]++;
    for (size_t p = 0; p < np; ++p)
        out->first[p + 1] += out->first[p];
    for (size_t i = 0; i < count; ++i) {
        size_t at = out->first[pt_patch[i]]++;
        memcpy(out->uv + 2 * at, uv + 2 * i, 2 * sizeof(double));
        memcpy(out->p + 3 * at, pts + 3 * i, 3 * sizeof(double));
    }
    for (size_t p = np; p > 0; --p) /* first[p] was advanced to the end of patch p */
        out->first[p] = out->first[p - 1];
    out->first[0] = 0;
    out->count = count;
done:
    if (st != SK_OK)
        sk__fit_data_free(out);
    sk_bvh_destroy(&bvh);
    sk_soup_destroy(&soup);
    sk_bvh_destroy(&fbvh);
    sk_soup_destroy(&fsoup);
    sk__free(face_patch);
    sk__free(pt_patch);
    sk__free(pts);
    sk__free(uv);
    return st;
}
