/* Two-sided deviation of two surfaces given as indexed faces (a tessellated smooth surface and the
 * scan it approximates): every vertex and n x n samples of every triangle of one side are
 * projected to the other through a BVH (bvh.c), in both directions. The larger of the two maxima
 * is the Hausdorff distance of the sampled surfaces; it approaches the true one as n grows (the
 * samples of a triangle are at most (longest edge) / (n sqrt 3) from any of its points). */
#include "surfkit/deviation.h"
#include "analysis/bvh_internal.h"
#include "core/internal.h"
#include "core/vec.h"
#include "mesh/fan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { CHUNK = 1 << 16 };

/* The sample points of one side: vertices first, then n*n per fan triangle. */
typedef struct samples {
    const sk_soup *soup;
    size_t num_tris;
    uint32_t *tri;   /* 3 vertex indices per fan triangle */
    uint32_t *face;  /* soup face of each fan triangle */
    uint32_t *vface; /* one face of each vertex, or SK_INVALID */
    int n;
    double (*bary)[2]; /* n*n barycentric (u, v) pairs of the sub-triangle centroids */
    size_t count;
} samples;

static void samples_free(samples *s)
{
    sk__free(s->tri);
    sk__free(s->face);
    sk__free(s->vface);
    sk__free(s->bary);
}

static sk_status samples_init(samples *s, const sk_soup *soup, int n, sk_error *err)
{
    memset(s, 0, sizeof *s);
    s->soup = soup;
    s->n = n;
    size_t nt = 0; /* faces of >= 3 corners: checked by sk_bvh_build */
    sk_status st = sk__soup_fan_triangles(soup, &s->tri, &s->face, &nt, err);
    if (st)
        return st;
    s->num_tris = nt;
    s->vface = sk__malloc_array(soup->num_vertices, sizeof *s->vface);
    s->bary = sk__malloc_array((size_t)n * n, sizeof *s->bary);
    if ((soup->num_vertices && !s->vface) || !s->bary)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    for (size_t v = 0; v < soup->num_vertices; ++v)
        s->vface[v] = SK_INVALID;
    for (size_t f = 0; f < soup->num_faces; ++f) {
        const uint32_t *idx = soup->face_indices + soup->face_offsets[f];
        for (size_t c = 0, m = sk_soup_face_size(soup, f); c < m; ++c)
            if (s->vface[idx[c]] == SK_INVALID)
                s->vface[idx[c]] = (uint32_t)f;
    }
    /* centroids of the n*n triangles of the n-fold subdivided triangle: n(n+1)/2 upright ones at
     * ((i + 1/3) / n, (j + 1/3) / n), n(n-1)/2 inverted ones at ((i + 2/3) / n, (j + 2/3) / n) */
    size_t k = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j, ++k) {
            s->bary[k][0] = (i + 1.0 / 3.0) / n;
            s->bary[k][1] = (j + 1.0 / 3.0) / n;
        }
    for (int i = 0; i + 1 < n; ++i)
        for (int j = 0; i + j + 1 < n; ++j, ++k) {
            s->bary[k][0] = (i + 2.0 / 3.0) / n;
            s->bary[k][1] = (j + 2.0 / 3.0) / n;
        }
    s->count = soup->num_vertices + nt * (size_t)n * (size_t)n;
    return SK_OK;
}

/* Position of sample i, and the face it lies on. */
static uint32_t sample_point(const samples *s, size_t i, double p[3])
{
    const double *pos = s->soup->positions;
    if (i < s->soup->num_vertices) {
        memcpy(p, pos + 3 * i, 3 * sizeof *p);
        return s->vface[i];
    }
    i -= s->soup->num_vertices;
    size_t nn = (size_t)s->n * (size_t)s->n, t = i / nn, k = i % nn;
    const double *a = pos + 3 * (size_t)s->tri[3 * t], *b = pos + 3 * (size_t)s->tri[3 * t + 1],
                 *c = pos + 3 * (size_t)s->tri[3 * t + 2];
    double u = s->bary[k][0], v = s->bary[k][1], w = 1 - u - v;
    for (int q = 0; q < 3; ++q)
        p[q] = w * a[q] + u * b[q] + v * c[q];
    return s->face[t];
}

/* Distances of all samples of s to the surface in bvh, into dist (s->count entries). The
 * samples go in blocks of WALK_BLOCK consecutive ones; each block's walks start from no
 * triangle and each walk first tries the triangle nearest to the sample before it (the samples
 * of one face, and consecutive vertices, are close): an exact distance from a tight bound
 * prunes most of the tree, the same distance as a walk from no bound (sk_bvh_closest). */
enum { WALK_BLOCK = 1024 };

static void project_block(const samples *s, const sk_bvh *bvh, double *dist, size_t begin,
                          size_t end)
{
    uint32_t hint = SK_INVALID;
    for (size_t i = begin; i < end; ++i) {
        double p[3];
        sample_point(s, i, p);
        dist[i] = sk__bvh_distance_capped(bvh, p, 0.0, &hint, NULL);
    }
}

static sk_status project_all(const samples *s, const sk_bvh *bvh, double *dist, double done,
                             double share, const sk_deviation_opts *o, sk_error *err)
{
    for (size_t c0 = 0; c0 < s->count; c0 += CHUNK) {
        size_t c1 = c0 + CHUNK < s->count ? c0 + CHUNK : s->count;
        ptrdiff_t blocks = (ptrdiff_t)((c1 - c0 + WALK_BLOCK - 1) / WALK_BLOCK);
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 1)
#endif
        for (ptrdiff_t k = 0; k < blocks; ++k) {
            size_t b0 = c0 + (size_t)k * WALK_BLOCK, b1 = b0 + WALK_BLOCK < c1 ? b0 + WALK_BLOCK : c1;
            project_block(s, bvh, dist, b0, b1);
        }
        sk_status st = sk__progress(o->progress, o->progress_user,
                                    done + share * (double)c1 / (double)s->count, err);
        if (st)
            return st;
    }
    return SK_OK;
}

static void summarize(const samples *s, const double *dist, double top, sk_distance_stats *out)
{
    memset(out, 0, sizeof *out);
    out->samples = s->count;
    out->max_face = SK_INVALID;
    double sum = 0, sum2 = 0;
    size_t imax = 0;
    for (size_t i = 0; i < s->count; ++i) {
        double d = dist[i];
        sum += d;
        sum2 += d * d;
        if (d > out->max || i == 0) {
            out->max = d;
            imax = i;
        }
        int b = top > 0 ? (int)(d / top * SK_DEVIATION_BINS) : 0;
        out->histogram[b < 0 ? 0 : b >= SK_DEVIATION_BINS ? SK_DEVIATION_BINS - 1 : b]++;
    }
    if (s->count) {
        out->mean = sum / (double)s->count;
        out->rms = sqrt(sum2 / (double)s->count);
        out->max_face = sample_point(s, imax, out->max_at);
    }
}

static double soup_diagonal(const sk_soup *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < s->num_vertices; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], s->positions[3 * v + k]);
            hi[k] = fmax(hi[k], s->positions[3 * v + k]);
        }
    double d[3];
    sk__sub3(d, hi, lo);
    return s->num_vertices ? sk__norm3(d) : 0;
}

/* Builds the BVH of one side, naming the side in the error. */
static sk_status build_side(const sk_soup *soup, const char *name, sk_bvh **out, sk_error *err)
{
    sk_error e;
    sk_status st = sk_bvh_build(soup, out, &e);
    if (st)
        return sk__fail(err, st, "%s: %s", name, e.message);
    return SK_OK;
}

/* sk_deviation, over the BVH of mesh when given (mesh_given: built from this soup, kept by the
 * caller; then opts->mesh_bvh gets none) */
static sk_status deviation(const sk_soup *surface, const sk_soup *mesh, const sk_bvh *mesh_given,
                           const sk_deviation_opts *opts, sk_deviation_report *report,
                           double *vertex_distance, sk_error *err)
{
    sk_deviation_opts o = {0};
    if (opts)
        o = *opts;
    if (o.face_samples < 0 || o.face_samples > 64)
        return sk__fail(err, SK_ERR_ARG, "face samples must be between 1 and 64 (got %d)",
                        o.face_samples);
    int n = o.face_samples ? o.face_samples : 2;
    if (o.surface_bvh)
        *o.surface_bvh = NULL;
    if (o.mesh_bvh)
        *o.mesh_bvh = NULL;
    double t0 = sk_seconds();
    memset(report, 0, sizeof *report);
    sk_bvh *bs = NULL, *bm = NULL;
    samples ss = {0}, sm = {0};
    double *ds = NULL, *dm = NULL;
    const sk_bvh *mesh_bvh = mesh_given;
    sk_status st = build_side(surface, "surface", &bs, err);
    if (!st && !mesh_given) {
        st = build_side(mesh, "mesh", &bm, err);
        mesh_bvh = bm;
    }
    if (!st)
        st = samples_init(&sm, mesh, n, err);
    if (!st)
        st = samples_init(&ss, surface, n, err);
    if (st)
        goto done;
    dm = sk__malloc_array(sm.count, sizeof *dm);
    ds = sk__malloc_array(ss.count, sizeof *ds);
    if (!dm || !ds) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    double share = (double)sm.count / (double)(sm.count + ss.count);
    st = project_all(&sm, bs, dm, 0.0, share, &o, err);
    if (!st)
        st = project_all(&ss, mesh_bvh, ds, share, 1.0 - share, &o, err);
    if (st)
        goto done;
    double top = 0;
    for (size_t i = 0; i < sm.count; ++i)
        top = fmax(top, dm[i]);
    for (size_t i = 0; i < ss.count; ++i)
        top = fmax(top, ds[i]);
    report->hausdorff = top;
    summarize(&sm, dm, top, &report->mesh_to_surface);
    summarize(&ss, ds, top, &report->surface_to_mesh);
    report->diagonal = soup_diagonal(mesh);
    if (vertex_distance)
        memcpy(vertex_distance, dm, mesh->num_vertices * sizeof *dm);
    report->seconds = sk_seconds() - t0;
    if (o.surface_bvh) { /* handed over to the caller */
        *o.surface_bvh = bs;
        bs = NULL;
    }
    if (o.mesh_bvh) {
        *o.mesh_bvh = bm;
        bm = NULL;
    }
done:
    sk__free(dm);
    sk__free(ds);
    samples_free(&sm);
    samples_free(&ss);
    sk_bvh_destroy(&bs);
    sk_bvh_destroy(&bm);
    return st;
}

sk_status sk_deviation(const sk_soup *surface, const sk_soup *mesh, const sk_deviation_opts *opts,
                       sk_deviation_report *report, double *vertex_distance, sk_error *err)
{
    return deviation(surface, mesh, NULL, opts, report, vertex_distance, err);
}

sk_status sk__deviation_over(const sk_soup *surface, const sk_soup *mesh, const sk_bvh *mesh_bvh,
                             const sk_deviation_opts *opts, sk_deviation_report *report,
                             sk_error *err)
{
    return deviation(surface, mesh, mesh_bvh, opts, report, NULL, err);
}
