/* Continuity report of a patch network: gaps and normal jumps sampled densely along every interior
 * edge, interpolation errors at the vertices, and the regularity of every patch (normal-cone test of
 * Ginkel, Peters, Umlauf, then sampling). Tolerances: Albat & Mueller's industrial values, G1 within
 * 0.5 degrees and gaps under 0.005 mm. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <stdlib.h>
#include <string.h>

/* (u, v) of the point at t along side `side` of a patch with `kind` corners */
static void side_param(int kind, int side, double t, double *u, double *v)
{
    if (kind == SK_SMOOTH_TRIANGLE) {
        switch (side) {
        case 0: *u = t, *v = 0.0; break;
        case 1: *u = 1.0 - t, *v = t; break;
        default: *u = 0.0, *v = 1.0 - t; break;
        }
    } else {
        switch (side) {
        case 0: *u = t, *v = 0.0; break;
        case 1: *u = 1.0, *v = t; break;
        case 2: *u = 1.0 - t, *v = 1.0; break;
        default: *u = 0.0, *v = 1.0 - t; break;
        }
    }
}

static int side_of(const sk_mesh *m, uint32_t f, uint32_t h)
{
    uint32_t g = m->f_halfedge[f];
    int i = 0;
    while (g != h) {
        g = m->h_next[g];
        ++i;
    }
    return i;
}

static void corner_param(int kind, int i, double *u, double *v)
{
    static const double tu[4] = {0, 1, 1, 0}, tv[4] = {0, 0, 1, 1};
    if (kind == SK_SMOOTH_TRIANGLE) {
        *u = i == 1 ? 1.0 : 0.0;
        *v = i == 2 ? 1.0 : 0.0;
    } else {
        *u = tu[i];
        *v = tv[i];
    }
}

#define RAD2DEG (180.0 / M_PI)

/* Work is split into fixed blocks whose partial results are combined in block order, so the report
 * is the same for any number of threads. */
#define BLOCK 4096

typedef struct edge_block {
    double max_gap, sum_gap, max_jump, sum_jump;
    long worst;
    size_t nint, nsamp;
} edge_block;

typedef struct patch_block {
    double max_verr, max_nerr;
    size_t uncert;
} patch_block;

static void edge_range(const sk_smooth *s, unsigned K, long e0, long e1, edge_block *b)
{
    const sk_mesh *m = s->config;
    memset(b, 0, sizeof *b);
    b->worst = -1;
    b->max_jump = -1.0;
    for (long e = e0; e < e1; ++e) {
        uint32_t h = (uint32_t)(2 * e), o = h + 1;
        uint32_t f = m->h_face[h], g = m->h_face[o];
        if (f == SK_INVALID || g == SK_INVALID)
            continue;
        ++b->nint;
        int sf = side_of(m, f, h), sg = side_of(m, g, o);
        int kf = s->patches[f].kind, kg = s->patches[g].kind;
        double local_max = 0.0;
        for (unsigned i = 0; i <= K; ++i) {
            double t = (double)i / K, u, v, x1[3], x2[3], n1[3], n2[3];
            side_param(kf, sf, t, &u, &v);
            sk_smooth_eval(s, f, u, v, x1, NULL, NULL, n1);
            side_param(kg, sg, 1.0 - t, &u, &v);
            sk_smooth_eval(s, g, u, v, x2, NULL, NULL, n2);
            double gap = sk__dist3(x1, x2), jump = sk__angle3(n1, n2) * RAD2DEG;
            if (sk__norm3(n1) == 0.0 || sk__norm3(n2) == 0.0)
                jump = 180.0; /* a vanishing normal on an edge counts as a full jump */
            b->max_gap = fmax(b->max_gap, gap);
            b->sum_gap += gap;
            b->sum_jump += jump;
            local_max = fmax(local_max, jump);
            ++b->nsamp;
        }
        if (local_max > b->max_jump) {
            b->max_jump = local_max;
            b->worst = e;
        }
    }
}

/* Regularity of patch p: certified by the control net (no sampling needed), else sampled on a
 * G x G grid for a vanishing normal or a normal turned away from the corner normals. */
static void patch_check(const sk_smooth *s, size_t p, patch_block *b, uint8_t *singular_out)
{
    const unsigned G = 8;
    const sk_mesh *m = s->config;
    const sk_smooth_patch *pa = s->patches + p;
    double ref[3] = {0, 0, 0};
    for (int i = 0; i < pa->kind; ++i) {
        double u, v, x[3], n[3];
        corner_param(pa->kind, i, &u, &v);
        sk_smooth_eval(s, p, u, v, x, NULL, NULL, n);
        const double *V = m->positions + 3 * (size_t)pa->corners[i];
        const double *N = s->normals + 3 * (size_t)pa->corners[i];
        b->max_verr = fmax(b->max_verr, sk__dist3(x, V));
        b->max_nerr = fmax(b->max_nerr, sk__norm3(n) == 0.0 ? 180.0 : sk__angle3(n, N) * RAD2DEG);
        sk__add3(ref, ref, N);
    }
    double scale, du[3], dv[3];
    sk_smooth_eval(s, p, 1.0 / 3.0, 1.0 / 3.0, NULL, du, dv, NULL);
    scale = sk__norm3(du) * sk__norm3(dv);
    bool cone, certified;
    sk__patch_certify(s, p, ref, scale, &cone, &certified);
    b->uncert += !cone;
    bool singular = false;
    for (unsigned i = 0; i <= G && !singular && !certified; ++i)
        for (unsigned j = 0; j <= G && !singular; ++j) {
            if (pa->kind == SK_SMOOTH_TRIANGLE && i + j > G)
                continue;
            double u = (double)i / G, v = (double)j / G, c[3];
            sk_smooth_eval(s, p, u, v, NULL, du, dv, NULL);
            sk__cross3(c, du, dv);
            double len = sk__norm3(c);
            if (!(len > 1e-10 * scale) || sk__dot3(c, ref) <= 0.0)
                singular = true;
        }
    *singular_out = singular;
}

sk_status sk_smooth_continuity(const sk_smooth *s, const sk_continuity_opts *opts,
                               sk_continuity_report *rep, sk_error *err)
{
    if (!s || !rep)
        return sk__fail(err, SK_ERR_ARG, "sk_smooth_continuity: NULL argument");
    unsigned K = opts && opts->samples ? opts->samples : 32;
    double tol_deg = opts && opts->max_angle_deg > 0 ? opts->max_angle_deg : 0.5;
    double tol_gap = opts && opts->max_gap > 0 ? opts->max_gap : 0.005;
    const sk_mesh *m = s->config;
    memset(rep, 0, sizeof *rep);
    long ne = (long)sk_num_edges(m), np = (long)s->num_patches;
    long neb = (ne + BLOCK - 1) / BLOCK, npb = (np + BLOCK - 1) / BLOCK;
    edge_block *eb = sk__malloc_array((size_t)neb + 1, sizeof *eb);
    patch_block *pb = sk__malloc_array((size_t)npb + 1, sizeof *pb);
    uint8_t *singular = sk__malloc_array((size_t)np + 1, 1);
    if (!eb || !pb || !singular) {
        free(eb);
        free(pb);
        free(singular);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory in the continuity report");
    }
#ifdef SK_HAVE_OPENMP
#pragma omp parallel
#endif
    {
#ifdef SK_HAVE_OPENMP
#pragma omp for schedule(dynamic, 1) nowait
#endif
        for (long k = 0; k < neb; ++k)
            edge_range(s, K, k * BLOCK, k + 1 < neb ? (k + 1) * BLOCK : ne, eb + k);
#ifdef SK_HAVE_OPENMP
#pragma omp for schedule(dynamic, 1)
#endif
        for (long k = 0; k < npb; ++k) {
            memset(pb + k, 0, sizeof pb[k]);
            long p1 = k + 1 < npb ? (k + 1) * BLOCK : np;
            for (long p = k * BLOCK; p < p1; ++p)
                patch_check(s, (size_t)p, pb + k, singular + p);
        }
    }
    double max_gap = 0.0, sum_gap = 0.0, max_jump = 0.0, sum_jump = 0.0;
    size_t nint = 0, nsamp = 0;
    long worst = -1;
    for (long k = 0; k < neb; ++k) {
        max_gap = fmax(max_gap, eb[k].max_gap);
        sum_gap += eb[k].sum_gap;
        sum_jump += eb[k].sum_jump;
        nint += eb[k].nint;
        nsamp += eb[k].nsamp;
        if (eb[k].worst >= 0 && eb[k].max_jump > max_jump) {
            max_jump = eb[k].max_jump;
            worst = eb[k].worst;
        }
    }
    rep->interior_edges = nint;
    rep->samples = nsamp;
    rep->max_gap = max_gap;
    rep->mean_gap = nsamp ? sum_gap / (double)nsamp : 0.0;
    rep->max_normal_jump_deg = max_jump;
    rep->mean_normal_jump_deg = nsamp ? sum_jump / (double)nsamp : 0.0;
    rep->worst_edge_vertices[0] = rep->worst_edge_vertices[1] = SK_INVALID;
    if (worst >= 0) {
        rep->worst_edge_vertices[0] = sk_from(m, (uint32_t)(2 * worst));
        rep->worst_edge_vertices[1] = sk_to(m, (uint32_t)(2 * worst));
    }
    double max_verr = 0.0, max_nerr = 0.0;
    size_t uncert = 0;
    for (long k = 0; k < npb; ++k) {
        max_verr = fmax(max_verr, pb[k].max_verr);
        max_nerr = fmax(max_nerr, pb[k].max_nerr);
        uncert += pb[k].uncert;
    }
    for (long p = 0; p < np; ++p) {
        if (!singular[p])
            continue;
        if (rep->num_singular_examples < SK_CONTINUITY_EXAMPLES)
            rep->singular_examples[rep->num_singular_examples++] = (uint32_t)p;
        rep->singular_patches++;
    }
    free(eb);
    free(pb);
    free(singular);
    rep->max_vertex_error = max_verr;
    rep->max_normal_error_deg = max_nerr;
    rep->uncertified_patches = uncert;
    rep->pass_g1 = rep->max_normal_jump_deg <= tol_deg;
    rep->pass_gap = rep->max_gap <= tol_gap;
    sk__ok(err);
    return SK_OK;
}
