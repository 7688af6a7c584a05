/* Continuity report of a patch network: gaps and normal jumps sampled densely along every interior
 * edge, interpolation errors at the vertices, and the regularity of every patch (normal-cone test of
 * Ginkel, Peters, Umlauf, then sampling). Tolerances: Albat & Mueller's industrial values, G1 within
 * 0.5 degrees and gaps under 0.005 mm. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

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
    long ne = (long)sk_num_edges(m);
    double max_gap = 0.0, sum_gap = 0.0, max_jump = 0.0, sum_jump = 0.0;
    size_t nint = 0, nsamp = 0;
    long worst = -1;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) reduction(max : max_gap) \
    reduction(+ : sum_gap, sum_jump, nint, nsamp)
#endif
    for (long e = 0; e < ne; ++e) {
        uint32_t h = (uint32_t)(2 * e), o = h + 1;
        uint32_t f = m->h_face[h], g = m->h_face[o];
        if (f == SK_INVALID || g == SK_INVALID)
            continue;
        ++nint;
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
            max_gap = fmax(max_gap, gap);
            sum_gap += gap;
            sum_jump += jump;
            local_max = fmax(local_max, jump);
            ++nsamp;
        }
#ifdef SK_HAVE_OPENMP
#pragma omp critical(sk_cont_worst)
#endif
        if (local_max > max_jump) {
            max_jump = local_max;
            worst = e;
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

    /* vertices and patch regularity */
    long np = (long)s->num_patches;
    double max_verr = 0.0, max_nerr = 0.0;
    size_t uncert = 0;
    unsigned G = 8; /* regularity sampling grid */
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) reduction(max : max_verr, max_nerr) reduction(+ : uncert)
#endif
    for (long p = 0; p < np; ++p) {
        const sk_smooth_patch *pa = s->patches + p;
        double ref[3] = {0, 0, 0};
        for (int i = 0; i < pa->kind; ++i) {
            double u, v, x[3], n[3];
            corner_param(pa->kind, i, &u, &v);
            sk_smooth_eval(s, (size_t)p, u, v, x, NULL, NULL, n);
            const double *V = m->positions + 3 * (size_t)pa->corners[i];
            const double *N = s->normals + 3 * (size_t)pa->corners[i];
            max_verr = fmax(max_verr, sk__dist3(x, V));
            max_nerr = fmax(max_nerr, sk__norm3(n) == 0.0 ? 180.0 : sk__angle3(n, N) * RAD2DEG);
            sk__add3(ref, ref, N);
        }
        bool certified = sk__patch_cone_regular(s, (size_t)p);
        uncert += !certified;
        /* sampled check: vanishing normal or a normal turned away from the corner normals */
        bool singular = false;
        double scale = 0.0;
        {
            double du[3], dv[3];
            sk_smooth_eval(s, (size_t)p, 1.0 / 3.0, 1.0 / 3.0, NULL, du, dv, NULL);
            scale = sk__norm3(du) * sk__norm3(dv);
        }
        for (unsigned i = 0; i <= G && !singular; ++i)
            for (unsigned j = 0; j <= G && !singular; ++j) {
                if (pa->kind == SK_SMOOTH_TRIANGLE && i + j > G)
                    continue;
                double u = (double)i / G, v = (double)j / G, du[3], dv[3], c[3];
                sk_smooth_eval(s, (size_t)p, u, v, NULL, du, dv, NULL);
                sk__cross3(c, du, dv);
                double len = sk__norm3(c);
                if (!(len > 1e-10 * scale) || sk__dot3(c, ref) <= 0.0)
                    singular = true;
            }
        if (singular) {
#ifdef SK_HAVE_OPENMP
#pragma omp critical(sk_cont_singular)
#endif
            {
                if (rep->num_singular_examples < SK_CONTINUITY_EXAMPLES)
                    rep->singular_examples[rep->num_singular_examples++] = (uint32_t)p;
                rep->singular_patches++;
            }
        }
    }
    rep->max_vertex_error = max_verr;
    rep->max_normal_error_deg = max_nerr;
    rep->uncertified_patches = uncert;
    rep->pass_g1 = rep->max_normal_jump_deg <= tol_deg;
    rep->pass_gap = rep->max_gap <= tol_gap;
    sk__ok(err);
    return SK_OK;
}
