/* Shape of the VC1 surfaces on the shared meshes (issue 12): singular patches, overshoot (the
 * largest distance of a patch from its mesh face divided by the face's longest edge; a spike is
 * > 1), with the per-patch diagnostics that explain a singular patch (the face's smallest angle,
 * the dihedral angles at its edges, the ratios nu of its edges, the worst control point).
 * SK_SHAPE_DIAG=1 prints the diagnostics of every singular patch, with SK_SHAPE_GRID=1 also the
 * angle (degrees) between du x dv and the sum of the corner normals on a 9 x 9 grid of the patch
 * (-1 where du x dv vanishes; over 90 is where the test calls it singular). */
#include "testutil.h"
#include "surfkit/smooth.h"
#include "surfkit/deviation.h"
#include "smooth/smooth_internal.h"
#include "smooth/vc1_internal.h"
#include "analysis/intersect_internal.h"
#include "core/internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void sub(double *d, const double *a, const double *b)
{
    for (int x = 0; x < 3; ++x)
        d[x] = a[x] - b[x];
}
static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(double *c, const double *a, const double *b)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dist(const double *a, const double *b)
{
    double d[3];
    sub(d, a, b);
    return sqrt(dot(d, d));
}

/* distance from p to the segment ab */
static double seg_dist(const double *p, const double *a, const double *b)
{
    double ab[3], ap[3];
    sub(ab, b, a);
    sub(ap, p, a);
    double l2 = dot(ab, ab), t = l2 > 0.0 ? dot(ap, ab) / l2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double q[3] = {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
    return dist(p, q);
}

/* distance from p to the triangle abc: inside the prism over it the distance to its plane, else
 * the distance to the nearest side */
static double tri_dist(const double *p, const double *a, const double *b, const double *c)
{
    double e0[3], e1[3], n[3], ap[3];
    sub(e0, b, a);
    sub(e1, c, a);
    cross(n, e0, e1);
    double nn = dot(n, n);
    sub(ap, p, a);
    if (nn > 0.0) {
        double t0[3], t1[3], t2[3], pb[3], pc[3], ca[3], bc[3];
        sub(pb, p, b);
        sub(pc, p, c);
        sub(bc, c, b);
        sub(ca, a, c);
        cross(t0, e0, ap);
        cross(t1, bc, pb);
        cross(t2, ca, pc);
        if (dot(t0, n) >= 0.0 && dot(t1, n) >= 0.0 && dot(t2, n) >= 0.0)
            return fabs(dot(ap, n)) / sqrt(nn);
    }
    double d = seg_dist(p, a, b), d1 = seg_dist(p, b, c), d2 = seg_dist(p, c, a);
    return fmin(d, fmin(d1, d2));
}

typedef struct {
    const sk_smooth *s;
    uint64_t *deleted; /* sorted (min, max) vertex pairs of the deleted edges */
    size_t nd;
} shape_ctx;

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static uint64_t pair_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

static bool is_deleted(const shape_ctx *c, uint32_t a, uint32_t b)
{
    uint64_t k = pair_key(a, b);
    return bsearch(&k, c->deleted, c->nd, sizeof k, cmp_u64) != NULL;
}

/* corner positions of patch p, its mesh triangles (1 or 2, by the deleted diagonal of a quad) */
static int patch_tris(const shape_ctx *c, size_t p, const double *T[2][3], double *longest)
{
    const sk_smooth *s = c->s;
    const sk_patch *pa = &s->surface.patches[p];
    unsigned n = sk_patch_num_corners(pa);
    const double *X[4];
    for (unsigned i = 0; i < n; ++i)
        X[i] = s->config->positions + 3 * (size_t)pa->corner_ids[i];
    *longest = 0.0;
    for (unsigned i = 0; i < n; ++i)
        *longest = fmax(*longest, dist(X[i], X[(i + 1) % n]));
    if (n == 3) {
        T[0][0] = X[0], T[0][1] = X[1], T[0][2] = X[2];
        return 1;
    }
    int d13 = !is_deleted(c, pa->corner_ids[0], pa->corner_ids[2]);
    const unsigned k[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};
    for (int t = 0; t < 2; ++t)
        for (int i = 0; i < 3; ++i)
            T[t][i] = X[k[d13][t][i]];
    return 2;
}

static double face_dist(const double *q, const double *T[2][3], int nt)
{
    double d = tri_dist(q, T[0][0], T[0][1], T[0][2]);
    if (nt == 2)
        d = fmin(d, tri_dist(q, T[1][0], T[1][1], T[1][2]));
    return d;
}

#define OVERSHOOT_GRID 12

/* overshoot of patch p: max over a grid of parameters of dist(S, face) / longest edge */
static double patch_overshoot(const shape_ctx *c, size_t p)
{
    const sk_smooth *s = c->s;
    const double *T[2][3];
    double longest;
    int nt = patch_tris(c, p, T, &longest);
    bool tri = s->surface.patches[p].kind == SK_PATCH_TRIANGLE;
    double worst = 0.0;
    for (unsigned i = 0; i <= OVERSHOOT_GRID; ++i)
        for (unsigned j = 0; j <= OVERSHOOT_GRID; ++j) {
            if (tri && i + j > OVERSHOOT_GRID)
                continue;
            double q[3];
            sk_patch_eval(&s->surface, p, (double)i / OVERSHOOT_GRID, (double)j / OVERSHOOT_GRID,
                          q, NULL, NULL, NULL);
            worst = fmax(worst, face_dist(q, T, nt));
        }
    return longest > 0.0 ? worst / longest : 0.0;
}

static void ctx_init(shape_ctx *c, const sk_smooth *s)
{
    c->s = s;
    c->nd = s->num_deleted;
    c->deleted = malloc((c->nd + 1) * sizeof *c->deleted);
    assert_non_null(c->deleted);
    for (size_t i = 0; i < c->nd; ++i)
        c->deleted[i] = pair_key(s->deleted[2 * i], s->deleted[2 * i + 1]);
    qsort(c->deleted, c->nd, sizeof *c->deleted, cmp_u64);
}

/* Newell normal of face f of the configuration */
static void face_normal(const sk_mesh *m, uint32_t f, double n[3])
{
    n[0] = n[1] = n[2] = 0.0;
    uint32_t h0 = m->f_halfedge[f], h = h0;
    do {
        const double *a = m->positions + 3 * (size_t)sk_from(m, h);
        const double *b = m->positions + 3 * (size_t)sk_to(m, h);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
        h = m->h_next[h];
    } while (h != h0);
    double l = sqrt(dot(n, n));
    if (l > 0.0)
        for (int x = 0; x < 3; ++x)
            n[x] /= l;
}

/* The diagnostics of one singular patch p (face p of the configuration). */
static void diagnose(const shape_ctx *c, size_t p, const double *r)
{
    const sk_smooth *s = c->s;
    const sk_mesh *m = s->config;
    uint32_t f = (uint32_t)p, h0 = m->f_halfedge[f], h = h0;
    double nf[3];
    face_normal(m, f, nf);
    double min_angle = 180.0, max_dihedral = 0.0, nu_lo = INFINITY, nu_hi = 0.0;
    char buf[512];
    int len = 0;
    do {
        const double *a = m->positions + 3 * (size_t)sk_from(m, h);
        const double *b = m->positions + 3 * (size_t)sk_to(m, h);
        const double *z = m->positions + 3 * (size_t)sk_from(m, m->h_prev[h]);
        double u[3], v[3];
        sub(u, b, a);
        sub(v, z, a);
        double ang = acos(fmax(-1.0, fmin(1.0, dot(u, v) / sqrt(dot(u, u) * dot(v, v))))) * 180 / M_PI;
        min_angle = fmin(min_angle, ang);
        uint32_t g = m->h_face[sk_opp(h)];
        if (g != SK_INVALID) {
            double ng[3];
            face_normal(m, g, ng);
            double dih = acos(fmax(-1.0, fmin(1.0, dot(nf, ng)))) * 180 / M_PI;
            max_dihedral = fmax(max_dihedral, dih);
            double nu = fabs(r[f] / r[g]);
            nu_lo = fmin(nu_lo, nu);
            nu_hi = fmax(nu_hi, nu);
            len += snprintf(buf + len, sizeof buf - (size_t)len, " %.0f/%.2g", dih, nu);
        }
        h = m->h_next[h];
    } while (h != h0 && len < 400);
    const double *T[2][3];
    double longest;
    int nt = patch_tris(c, p, T, &longest);
    const sk_patch *pa = &s->surface.patches[p];
    double worst_cp = 0.0;
    const double *cp = sk_patch_cp(&s->surface, p);
    for (unsigned i = 0; i < sk_patch_num_points(pa); ++i)
        worst_cp = fmax(worst_cp, face_dist(cp + 3 * i, T, nt) / longest);
    /* the largest angle between a corner normal and the face normal; per corner: vertex id,
     * valence, angle of its (sector) normal to the face normal */
    double nrm = 0.0;
    char corners[200];
    int clen = 0;
    for (unsigned i = 0; i < sk_patch_num_corners(pa); ++i) {
        double a = acos(fmax(-1.0, fmin(1.0, dot(nf, sk__corner_normal(s, p, i))))) * 180 / M_PI;
        nrm = fmax(nrm, a);
        clen += snprintf(corners + clen, sizeof corners - (size_t)clen, " %u/%zu/%.0f",
                         pa->corner_ids[i], sk_mesh_valence(m, pa->corner_ids[i]), a);
    }
    if (getenv("SK_SHAPE_GRID")) {
        double ref[3] = {0, 0, 0};
        for (unsigned i = 0; i < sk_patch_num_corners(pa); ++i) {
            const double *cn = sk__corner_normal(s, p, i);
            for (int x = 0; x < 3; ++x) ref[x] += cn[x];
        }
        double rl = sqrt(dot(ref, ref));
        for (unsigned i = 0; i <= 8; ++i) {
            char row[200]; int rlen = 0;
            for (unsigned j = 0; j <= 8; ++j) {
                if (pa->kind == SK_PATCH_TRIANGLE && i + j > 8) break;
                double du[3], dv[3], cc[3];
                sk_patch_eval(&s->surface, p, i / 8.0, j / 8.0, NULL, du, dv, NULL);
                cross(cc, du, dv);
                double l = sqrt(dot(cc, cc));
                rlen += snprintf(row + rlen, sizeof row - (size_t)rlen, "%5.0f", l > 0 ? acos(fmax(-1, fmin(1, dot(cc, ref) / (l * rl)))) * 180 / M_PI : -1.0);
            }
            print_message("    %s\n", row);
        }
    }
    print_message("  singular patch %zu (%s): min angle %.1f deg, dihedral/|nu| per edge%s, "
                  "corners (id/valence/normal vs face)%s, "
                  "corner normal vs face %.0f deg, worst control point %.2f, overshoot %.2f\n",
                  p, pa->kind == SK_PATCH_TRIANGLE ? "tri" : "quad", min_angle, buf, corners, nrm,
                  worst_cp,
                  patch_overshoot(c, p));
}

typedef struct {
    size_t singular;
    double max_overshoot;
    size_t worst_patch;
    double max_jump, max_nerr, max_verr, seconds;
    size_t flipped, singular_before_repair;
    double bending; /* sum of the patches' bending energies (Miao et al.) */
} shape_result;

static shape_result measure_with(const char *name, bool keep_triangulation, sk_free_points fp)
{
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh(name));
    sk_smooth_opts o = {0};
    o.keep_triangulation = keep_triangulation;
    o.free_points = fp;
    o.allow_split = true; /* fandisk has an odd vertex count */
    sk_smooth *s = NULL;
    sk_error err = {0};
    double t0 = sk_seconds();
    if (sk_smooth_build(mesh, &o, &s, &err) != SK_OK)
        fail_msg("%s: %s", name, err.message);
    shape_result res = {0};
    res.seconds = sk_seconds() - t0;
    res.flipped = s->stats.flipped_edges;
    res.singular_before_repair = s->stats.singular_before_repair;
    {
        double qt[15 * 15], qq[16 * 16];
        sk__fair_energy_matrices(qt, qq);
        for (size_t p = 0; p < s->surface.count; ++p)
            res.bending += sk__fair_patch_energy(qt, qq,
                                                 (int)sk_patch_num_corners(&s->surface.patches[p]),
                                                 sk_patch_cp(&s->surface, p));
    }
    sk_continuity_opts co = {0};
    co.samples = 16;
    co.intersection_tess = (unsigned)-1;
    sk_continuity_report rep;
    assert_int_equal(sk_smooth_continuity(s, &co, &rep, &err), SK_OK);
    res.singular = rep.singular_patches;
    res.max_jump = rep.max_normal_jump_deg;
    res.max_nerr = rep.max_normal_error_deg;
    res.max_verr = rep.max_vertex_error / sk_mesh_diagonal(s->config);
    shape_ctx c;
    ctx_init(&c, s);
    for (size_t p = 0; p < s->surface.count; ++p) {
        double ov = patch_overshoot(&c, p);
        if (ov > res.max_overshoot) {
            res.max_overshoot = ov;
            res.worst_patch = p;
        }
    }
    print_message("%-16s %s %s flipped %5zu singular %3zu (%3zu before repair) bending %.4g "
                  "overshoot %.3f (patch %zu) jump %.1e "
                  "nerr %.1e verr %.1e deleted %zu/%zu %.2f s (flips %.3f deletion %.3f systems "
                  "%.3f patches %.3f repair %.3f)\n",
                  name, fp == SK_FREE_POINTS_LSQ ? "lsq " : "fair",
                  keep_triangulation ? "kept   " : "flipped", res.flipped, res.singular,
                  res.singular_before_repair, res.bending,
                  res.max_overshoot, res.worst_patch, res.max_jump, res.max_nerr, res.max_verr,
                  s->stats.deletion.deleted_edges, s->stats.deletion.lower_bound, res.seconds,
                  s->stats.seconds_flips, s->stats.seconds_deletion, s->stats.seconds_systems,
                  s->stats.seconds_patches, s->stats.seconds_repair);
    if (getenv("SK_SHAPE_DIAG") && res.singular) {
        size_t nh = s->config->num_halfedges, nf = s->config->num_faces;
        double *target = malloc(nh * 3 * sizeof(double)), *r = malloc((nf + 1) * sizeof(double));
        assert_non_null(target);
        assert_non_null(r);
        assert_int_equal(sk__wireframe_targets(s->config, s->normals, target, &err), SK_OK);
        sk__patch_ratios(s->config, target, r);
        for (size_t p = 0; p < s->surface.count; ++p)
            if (sk__patch_singular(s, p, NULL))
                diagnose(&c, p, r);
        free(target);
        free(r);
    }
    free(c.deleted);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
    return res;
}

static shape_result measure(const char *name, bool keep_triangulation)
{
    return measure_with(name, keep_triangulation, SK_FREE_POINTS_FAIR);
}

static const char *const shape_meshes[] = {"cow.off", "armadillo.off", "lion-head.off", "pig.off",
                                           "mushroom.off", "three_peaks.off", "bunny00.off",
                                           "fandisk.off", "nefertiti.off", "knot1.off",
                                           "eight.off"};
#define N_SHAPE (sizeof shape_meshes / sizeof shape_meshes[0])

/* Given a sheared grid (parallelograms) triangulated along the long diagonals, when the
 * triangulation pass runs, then every long diagonal whose end points keep enough faces is flipped
 * to the short one (Delaunay), the vertices stay where they were and the mesh stays valid. */
static void test_flips_sheared_grid(void **state)
{
    (void)state;
    enum { N = 6 };
    double pos[3 * (N + 1) * (N + 1)];
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            double *p = pos + 3 * (j * (N + 1) + i);
            p[0] = i + 0.8 * j, p[1] = j, p[2] = 0.0;
        }
    uint32_t idx[6 * N * N], off[2 * N * N + 1];
    size_t nf = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            uint32_t a = (uint32_t)(j * (N + 1) + i), b = a + 1, c = a + N + 2, d = a + N + 1;
            uint32_t t[6] = {a, b, c, a, c, d}; /* long diagonal a-c */
            memcpy(idx + 3 * nf, t, sizeof t);
            nf += 2;
        }
    for (size_t f = 0; f <= nf; ++f)
        off[f] = (uint32_t)(3 * f);
    sk_mesh *m = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces((N + 1) * (N + 1), pos, nf, off, idx, &m, &err), SK_OK);
    double normals[3 * (N + 1) * (N + 1)];
    for (int v = 0; v < (N + 1) * (N + 1); ++v)
        normals[3 * v] = normals[3 * v + 1] = 0.0, normals[3 * v + 2] = 1.0;
    size_t flipped = 0;
    assert_int_equal(sk__improve_triangulation(m, normals, &flipped, &err), SK_OK);
    /* the two grid corners on the long diagonals have two faces each: their diagonals stay */
    assert_int_equal(flipped, N * N - 2);
    assert_int_equal(sk_mesh_check(m, &err), SK_OK);
    assert_memory_equal(m->positions, pos, sizeof pos);
    /* every face now has its smallest angle at least that of the short-diagonal triangles
     * (about 41 degrees; the long-diagonal ones had 24), but for the two kept corners */
    size_t narrow = 0;
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        uint32_t h = m->f_halfedge[f];
        double lo = M_PI;
        for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
            const double *a = m->positions + 3 * (size_t)sk_from(m, h);
            const double *b = m->positions + 3 * (size_t)sk_to(m, h);
            const double *c = m->positions + 3 * (size_t)sk_from(m, m->h_prev[h]);
            double u[3], v[3], x[3];
            sub(u, b, a);
            sub(v, c, a);
            cross(x, u, v);
            lo = fmin(lo, atan2(sqrt(dot(x, x)), dot(u, v)));
            assert_true(x[2] > 0.0); /* no face turned over */
        }
        narrow += lo < 40.0 * M_PI / 180.0;
    }
    assert_int_equal(narrow, 4);
    sk_mesh_destroy(&m);
}

/* The meshes where the targets are reached: 0 singular patches, overshoot <= 0.5, VC1 to
 * rounding, exact interpolation (the default triangulation pass and fair free points on; eight,
 * three_peaks and lion-head reach them since the fair free points: 1, 1 and 2 singular patches
 * with the least-squares rule; pig and armadillo since the flips of bad faces and the pair
 * round of the regularity repair: 3 and 3 before). */
static void test_targets_reached(void **state)
{
    (void)state;
    const char *names[] = {"fandisk.off", "nefertiti.off", "knot1.off",  "mushroom.off",
                           "eight.off",   "three_peaks.off", "pig.off", "lion-head.off",
                           "bunny00.off", "armadillo.off"};
    size_t n = getenv("SK_TEST_QUICK") ? 7 : 10;
    for (size_t i = 0; i < n; ++i) {
        shape_result r = measure(names[i], false);
        assert_int_equal(r.singular, 0);
        assert_true(r.max_overshoot <= 0.5);
        assert_true(r.max_jump < 1e-7);
        assert_true(r.max_nerr < 1e-7);
        assert_true(r.max_verr < 1e-12);
    }
}

/* Given the bending-energy matrices of the fair free points, then a net that is an affine image of
 * the parameter domain has energy 0 (it is flat, with no second derivative), a quadratic gives
 * the integral of its second derivatives worked out by hand, and the matrices are symmetric. */
static void test_fair_energy_matrices(void **state)
{
    (void)state;
    double qt[15 * 15], qq[16 * 16], bt[15 * 3], bq[16 * 3];
    sk__fair_energy_matrices(qt, qq);
    for (int i = 0; i < 15; ++i)
        for (int j = 0; j < 15; ++j)
            assert_true(fabs(qt[15 * i + j] - qt[15 * j + i]) < 1e-9);
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j)
            assert_true(fabs(qq[16 * i + j] - qq[16 * j + i]) < 1e-9);
    /* triangle: b_{ijk} = (j/4, k/4, 2 + j/4 - 3 k/4) is affine in (v, w): energy 0; then
     * z = v^2, whose Bernstein coefficients are j (j - 1) / 12: with (v, w) as the coordinates
     * z_ss = 2 (energy 4 x area 1/2 = 2), with (u, v) the same, with (w, u) v = 1 - s - t gives
     * 2, 2, 2 (energy (4 + 8 + 4) / 2 = 8): the mean is 4 */
    for (unsigned k = 0; k <= 4; ++k)
        for (unsigned j = 0; j + k <= 4; ++j) {
            double *b = bt + 3 * sk_tri_index(4, j, k);
            b[0] = j / 4.0, b[1] = k / 4.0, b[2] = 2.0 + j / 4.0 - 0.75 * k;
        }
    assert_true(fabs(sk__fair_patch_energy(qt, qq, 3, bt)) < 1e-9);
    for (unsigned k = 0; k <= 4; ++k)
        for (unsigned j = 0; j + k <= 4; ++j) {
            double *b = bt + 3 * sk_tri_index(4, j, k);
            b[0] = b[1] = 0.0, b[2] = j * (j - 1.0) / 12.0;
        }
    assert_true(fabs(sk__fair_patch_energy(qt, qq, 3, bt) - 4.0) < 1e-9);
    /* bicubic: (s, t, s - 2 t) affine: 0; (s, t, s^2): s^2 has coefficients 0, 0, 1/3, 1, its
     * energy is the integral of |z_ss|^2 = 4 over the unit square */
    for (unsigned j = 0; j < 4; ++j)
        for (unsigned i = 0; i < 4; ++i) {
            double *b = bq + 3 * sk_tensor_index(3, i, j);
            b[0] = i / 3.0, b[1] = j / 3.0, b[2] = i / 3.0 - 2.0 * j / 3.0;
        }
    assert_true(fabs(sk__fair_patch_energy(qt, qq, 4, bq)) < 1e-9);
    static const double sq[4] = {0.0, 0.0, 1.0 / 3.0, 1.0};
    for (unsigned j = 0; j < 4; ++j)
        for (unsigned i = 0; i < 4; ++i) {
            double *b = bq + 3 * sk_tensor_index(3, i, j);
            b[0] = b[1] = 0.0, b[2] = sq[i];
        }
    assert_true(fabs(sk__fair_patch_energy(qt, qq, 4, bq) - 4.0) < 1e-9);
}

/* cow and three_peaks, fair free points against the least-squares rule (issue 12): the fair
 * choice leaves under half the singular patches before the repair and no more after it, lowers
 * the bending energy, and brings the cow's spikes under the bound (overshoot 1.38 with
 * least squares: the horn tip); both exactly VC1 and interpolating. (Measured before the repair,
 * fair against least squares: cow 22 against 74, three_peaks 0 against 17 (20 with the edge
 * deletion's Initialise searching depth first). The pig was the second mesh until the
 * breadth-first Initialise: its least-squares build went from 24 to 6, the fair one from 2 to 3,
 * at half, no longer under it.) */
static void test_fair_vs_lsq(void **state)
{
    (void)state;
    const char *names[] = {"cow.off", "three_peaks.off"};
    for (size_t i = 0; i < 2; ++i) {
        shape_result lsq = measure_with(names[i], false, SK_FREE_POINTS_LSQ);
        shape_result fair = measure_with(names[i], false, SK_FREE_POINTS_FAIR);
        assert_true(2 * fair.singular_before_repair < lsq.singular_before_repair);
        /* after the repair and the re-routed deletions both may be regular (the pig) */
        assert_true(fair.singular <= lsq.singular);
        assert_int_equal(fair.singular, 0);
        assert_true(fair.bending < lsq.bending);
        assert_true(fair.max_overshoot <= 0.5);
        assert_true(fair.max_jump < 1e-7);
        assert_true(fair.max_nerr < 1e-7);
        assert_true(fair.max_verr < 1e-12);
    }
}

/* eight (a closed genus-2 mesh, 1.5k faces): the fair free points against the least-squares rule
 * on the same configuration, checked from the control nets alone: the fair stage moved some
 * vertices and left the patches away from its region exactly as they were, lowered the total
 * bending energy, kept every corner on its vertex and every tangent control point at a corner in
 * the plane of the vertex normal (the tangent-plane part of eq. 8), and the surface is VC1 to
 * rounding (normal jump across every edge, 16 samples per edge). */
static void test_fair_points_eight(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("eight.off"));
    sk_smooth *s[2] = {NULL, NULL};
    sk_error err = {0};
    for (int i = 0; i < 2; ++i) {
        sk_smooth_opts o = {0};
        o.free_points = i ? SK_FREE_POINTS_FAIR : SK_FREE_POINTS_LSQ;
        o.allow_split = true;
        if (sk_smooth_build(mesh, &o, &s[i], &err) != SK_OK)
            fail_msg("eight: %s", err.message);
    }
    const sk_patch_set *L = &s[0]->surface, *F = &s[1]->surface;
    assert_true(s[1]->stats.fair_steps > 0);
    assert_int_equal(L->count, F->count);
    double qt[15 * 15], qq[16 * 16], eL = 0.0, eF = 0.0;
    sk__fair_energy_matrices(qt, qq);
    size_t same = 0, moved = 0;
    const sk_mesh *c = s[1]->config;
    double scale = sk_mesh_diagonal(c), worst_plane = 0.0;
    for (size_t p = 0; p < F->count; ++p) {
        const sk_patch *pa = &F->patches[p];
        unsigned nc = sk_patch_num_corners(pa), np = sk_patch_num_points(pa);
        assert_int_equal(nc, sk_patch_num_corners(&L->patches[p]));
        const double *bf = sk_patch_cp(F, p), *bl = sk_patch_cp(L, p);
        eL += sk__fair_patch_energy(qt, qq, (int)nc, bl);
        eF += sk__fair_patch_energy(qt, qq, (int)nc, bf);
        bool eq = memcmp(bf, bl, np * 3 * sizeof(double)) == 0;
        same += eq, moved += !eq;
        /* corner k at its vertex; its two neighbours along the sides in the vertex's plane */
        for (unsigned k = 0; k < nc; ++k) {
            unsigned at, nb[2];
            if (nc == 3) {
                unsigned j[3] = {0, 4, 0}, kk[3] = {0, 0, 4};
                at = sk_tri_index(4, j[k], kk[k]);
                /* the points one step from the corner along both sides */
                unsigned dj[3][2][2] = {{{1, 0}, {0, 1}}, {{3, 0}, {3, 1}}, {{0, 3}, {1, 3}}};
                for (int q = 0; q < 2; ++q)
                    nb[q] = sk_tri_index(4, dj[k][q][0], dj[k][q][1]);
            } else {
                unsigned ci[4][2] = {{0, 0}, {3, 0}, {3, 3}, {0, 3}};
                int di = ci[k][0] ? -1 : 1, dj = ci[k][1] ? -1 : 1;
                at = sk_tensor_index(3, ci[k][0], ci[k][1]);
                nb[0] = sk_tensor_index(3, (unsigned)((int)ci[k][0] + di), ci[k][1]);
                nb[1] = sk_tensor_index(3, ci[k][0], (unsigned)((int)ci[k][1] + dj));
            }
            const double *V = c->positions + 3 * (size_t)pa->corner_ids[k];
            const double *n = s[1]->normals + 3 * (size_t)pa->corner_ids[k];
            assert_memory_equal(bf + 3 * at, V, 3 * sizeof(double));
            for (int q = 0; q < 2; ++q) {
                const double *P = bf + 3 * nb[q];
                double d = (P[0] - V[0]) * n[0] + (P[1] - V[1]) * n[1] + (P[2] - V[2]) * n[2];
                worst_plane = fmax(worst_plane, fabs(d) / scale);
            }
        }
    }
    print_message("eight: fair steps %zu, patches moved %zu of %zu, bending %.6g (lsq %.6g), "
                  "worst tangent off its plane %.2e of the diagonal\n",
                  s[1]->stats.fair_steps, moved, F->count, eF, eL, worst_plane);
    assert_true(moved > 0 && same > 0);
    assert_true(eF < eL);
    assert_true(worst_plane < 1e-13);
    sk_continuity_opts co = {0};
    co.samples = 16;
    sk_continuity_report rep;
    assert_int_equal(sk_smooth_continuity(s[1], &co, &rep, &err), SK_OK);
    assert_true(rep.max_normal_jump_deg < 1e-7);
    assert_true(rep.max_vertex_error < 1e-12 * scale);
    for (int i = 0; i < 2; ++i)
        sk_smooth_destroy(&s[i]);
    sk_mesh_destroy(&mesh);
}

/* The fair stage runs on a quadratic model of the bending energy in the vertices' maps (the
 * patches it moves are affine in them): the energy after it (stats, from the model) must be that
 * of the control nets themselves, summed patch by patch, to rounding (1e-10: a near-flat patch's
 * energy cancels), where the regularity repair moved nothing afterwards (eight; the elephant also
 * has creases), and below the energy before. (The fandisk was the mesh with creases until the
 * breadth-first Initialise of the edge deletion: on its configuration no patch is singular or
 * strays from its face, so the fair stage has no region to start from and makes no step.) */
static void test_fair_model_energy(void **state)
{
    (void)state;
    const char *names[] = {"eight.off", "elephant.off"};
    double qt[15 * 15], qq[16 * 16];
    sk__fair_energy_matrices(qt, qq);
    for (size_t t = 0; t < (getenv("SK_TEST_QUICK") ? 1u : 2u); ++t) {
        sk_mesh *mesh = skt_read_mesh(skt_shared_mesh(names[t]));
        sk_smooth *s = NULL;
        sk_error err = {0};
        sk_smooth_opts o = {0};
        o.allow_split = true;
        if (sk_smooth_build(mesh, &o, &s, &err) != SK_OK)
            fail_msg("%s: %s", names[t], err.message);
        assert_int_equal(s->stats.repaired_vertices, 0);
        double e = 0.0;
        for (size_t p = 0; p < s->surface.count; ++p)
            e += sk__fair_patch_energy(qt, qq, (int)sk_patch_num_corners(&s->surface.patches[p]),
                                       sk_patch_cp(&s->surface, p));
        const sk_smooth_stats *st = &s->stats;
        print_message("%s: fair steps %zu, bending before %.12g, after %.12g (model) %.12g "
                      "(patches)\n",
                      names[t], st->fair_steps, st->fair_energy_before, st->fair_energy_after, e);
        assert_true(st->fair_steps > 0);
        assert_true(st->fair_energy_after < st->fair_energy_before);
        assert_true(fabs(e - st->fair_energy_after) <= 1e-10 * e);
        sk_smooth_destroy(&s);
        sk_mesh_destroy(&mesh);
    }
}

/* cow: the triangulation pass halves the spikes (with the fair free points overshoot 2.05 with
 * the input's triangulation, 0.41 with flips, asserted <= 0.5 in test_fair_vs_lsq) and removes
 * at least a third of the singular patches; still VC1 to rounding and interpolating. */
static void test_cow_flips(void **state)
{
    (void)state;
    shape_result kept = measure("cow.off", true), flipped = measure("cow.off", false);
    assert_true(flipped.flipped > 0);
    assert_int_equal(kept.flipped, 0);
    assert_true(flipped.max_overshoot < 0.75 * kept.max_overshoot);
    assert_true(3 * flipped.singular <= 2 * kept.singular);
    /* 15 before the flips of bad faces and the wide and pair rounds of the repair, 6 with them */
    assert_true(flipped.singular <= 6);
    assert_true(flipped.max_jump < 1e-7);
    assert_true(flipped.max_nerr < 1e-7);
    assert_true(flipped.max_verr < 1e-12);
}

/* the cow's default VC1 surface: at most max_singular singular patches, no spike (overshoot at
 * most 0.5), normal jumps and normal errors at rounding level, the vertices interpolated */
static void assert_cow_shape(size_t max_singular)
{
    shape_result r = measure("cow.off", false);
    assert_true(r.singular <= max_singular);
    assert_true(r.max_overshoot <= 0.5);
    assert_true(r.max_jump < 1e-7);
    assert_true(r.max_nerr < 1e-7);
    assert_true(r.max_verr < 1e-12);
}

/* smallest cosine between n and the unit normals of the faces around v */
static double star_smallest_cos(const sk_mesh *m, uint32_t v, const double *n)
{
    double lo = 2.0;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        if (m->h_face[h] != SK_INVALID) {
            double f[3];
            face_normal(m, m->h_face[h], f);
            if (dot(f, f) > 0.0)
                lo = fmin(lo, dot(f, n));
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
    return lo;
}

/* Given the cow's estimated normals, when the normals of folded stars are refitted
 * (fold_normals.c), then only vertices that saw a face from behind (more than 90 degrees off)
 * change, each changed normal sees every face within 84 degrees and no other direction sees its
 * faces better (random directions and small turns of the chosen one); the others stay bit for
 * bit. The tail tip's neighbour 2340 (face 4728 seen at 94 degrees) is among them. With the
 * refit, the cow's surface has at most 4 singular patches (6 before: the tail tip's two are
 * gone; 26 before the repair, 36 without the refit). */
static void test_fold_normals(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("cow.off"));
    size_t nv = mesh->num_vertices;
    double *n0 = malloc(3 * nv * sizeof(double)), *n1 = malloc(3 * nv * sizeof(double));
    assert_non_null(n0);
    assert_non_null(n1);
    sk_error err = {0};
    assert_int_equal(sk_mesh_vertex_normals(mesh, SK_NORMALS_ANGLE, n0, &err), SK_OK);
    memcpy(n1, n0, 3 * nv * sizeof(double));
    size_t changed = sk__fold_normals(mesh, n1, NULL, SK_FOLD_SEE_DEG), seen = 0;
    assert_true(changed > 0);
    uint64_t rng = 12345;
    for (uint32_t v = 0; v < nv; ++v) {
        const double *a = n0 + 3 * (size_t)v, *b = n1 + 3 * (size_t)v;
        if (memcmp(a, b, 3 * sizeof(double)) == 0)
            continue;
        ++seen;
        assert_true(star_smallest_cos(mesh, v, a) < 0.0);
        double got = star_smallest_cos(mesh, v, b);
        assert_true(got >= cos(84.0 * M_PI / 180.0));
        assert_true(fabs(dot(b, b) - 1.0) < 1e-12);
        for (int t = 0; t < 4000; ++t) {
            double x[3];
            for (int k = 0; k < 3; ++k) {
                rng = rng * 6364136223846793005ull + 1442695040888963407ull;
                double r = (double)(rng >> 11) / 9007199254740992.0 - 0.5;
                /* half the samples anywhere, half within a few degrees of the choice */
                x[k] = t & 1 ? 2.0 * r : b[k] + 0.1 * r;
            }
            double l = sqrt(dot(x, x));
            for (int k = 0; k < 3; ++k)
                x[k] /= l;
            assert_true(star_smallest_cos(mesh, v, x) <= got + 1e-9);
        }
    }
    assert_int_equal(seen, changed);
    assert_memory_not_equal(n0 + 3 * 2340, n1 + 3 * 2340, 3 * sizeof(double));
    free(n0);
    free(n1);
    sk_mesh_destroy(&mesh);
    assert_cow_shape(4);
}

/* Given the cow, whose tail root folds at vertex 43 (the hinges 43-956 and 43-2384, crease.c
 * step 4b), when its VC1 surface is built, then both hinges are G0 crease edges of the surface
 * (one normal per side at 43); the ends of the hinge line, 956 and 2384, have their normals
 * refitted after the flips (vc1.c, refit_hinge_ends): the estimate saw a face of each hinge from
 * behind (956: 113 degrees), the refit sees every face of their stars within 85 degrees; the
 * surface has no singular patch (2 before the second refit, patches 956-43-961 and
 * 2384-2391-970-43; 4 when the cluster of sharp edges there was dropped whole and 43 kept one
 * normal), no spike, normal jumps at rounding level away from the creases, and it interpolates. */
static void test_cow_fold_crease(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("cow.off"));
    sk_smooth *s = NULL;
    sk_error err = {0};
    assert_int_equal(sk_smooth_build(mesh, NULL, &s, &err), SK_OK);
    assert_non_null(s->crease_edge);
    const uint32_t hinge[2][2] = {{43, 956}, {43, 2384}};
    size_t nv = mesh->num_vertices;
    double *est = malloc(3 * nv * sizeof(double));
    assert_non_null(est);
    assert_int_equal(sk_mesh_vertex_normals(mesh, SK_NORMALS_ANGLE, est, &err), SK_OK);
    for (int i = 0; i < 2; ++i) {
        uint32_t h = sk__find_halfedge(s->config, hinge[i][0], hinge[i][1]);
        assert_true(h != SK_INVALID);
        assert_int_equal(s->crease_edge[sk_edge(h)], 1);
        uint32_t end = hinge[i][1];
        assert_true(star_smallest_cos(mesh, end, est + 3 * (size_t)end) < 0.0);
        assert_true(star_smallest_cos(mesh, end, s->normals + 3 * (size_t)end) >=
                    cos(SK_FOLD_HINGE_SEE_DEG * M_PI / 180.0));
    }
    free(est);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
    assert_cow_shape(0);
}

/* Given the cow and the pig, when their VC1 surfaces are built over the input refined
 * (opts.base_refinements, refine_base.c), then the cow once: the new vertices are the midpoints
 * of the input's edges but its near-folds (facet normals more than SK_REFINE_FOLD_DEG apart; some
 * left whole, none split, the cow's closed component keeping an even vertex count), numbered in
 * edge order, with the normalised sum of the edge's two facet normals as normal; the old vertices
 * keep the normals of the unrefined build (input triangulation), and the crease edges are the
 * input's, split ones as their two halves (detected again on the refined mesh, as `surfkit
 * subdivide --scheme midpoint` then `smooth` does, they are 543 for the input's 13); and the pig
 * twice: every vertex system converges and the surface is exactly VC1 and interpolates (over the
 * pig subdivided twice by sk_mesh_subdivide and built from scratch, vertex 2007's system does not
 * converge: residual 1.3e-6, SK_ERR_NUMERIC; on the cow vertex 2355, 1.1e-5). */
static void test_refine_base(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("cow.off"));
    size_t nv = mesh->num_vertices, ne = sk_num_edges(mesh), k = 0, folds = 0, folds_split = 0;
    sk_error err = {0};
    sk_smooth *s0 = NULL, *s1 = NULL, *s2 = NULL;
    sk_smooth_opts o = {.keep_triangulation = true};
    assert_int_equal(sk_smooth_build(mesh, &o, &s0, &err), SK_OK);
    o.keep_triangulation = false;
    o.base_refinements = 1;
    assert_int_equal(sk_smooth_build(mesh, &o, &s1, &err), SK_OK);
    assert_memory_equal(s1->normals, s0->normals, 3 * nv * sizeof(double));
    for (uint32_t e = 0; e < ne; ++e) {
        uint32_t va = sk_from(mesh, 2 * e), vb = sk_to(mesh, 2 * e);
        const double *a = mesh->positions + 3 * (size_t)va, *b = mesh->positions + 3 * (size_t)vb;
        double fn[2][3], want[3];
        face_normal(mesh, mesh->h_face[2 * e], fn[0]);
        face_normal(mesh, mesh->h_face[2 * e + 1], fn[1]);
        bool fold = dot(fn[0], fn[1]) < cos(SK_REFINE_FOLD_DEG * M_PI / 180.0);
        folds += fold;
        const double *p = s1->config->positions + 3 * (nv + k), *n = s1->normals + 3 * (nv + k);
        bool split = nv + k < s1->config->num_vertices && p[0] == 0.5 * (a[0] + b[0]) &&
                     p[1] == 0.5 * (a[1] + b[1]) && p[2] == 0.5 * (a[2] + b[2]);
        if (!split) { /* left whole: only a near-fold */
            assert_true(fold);
            continue;
        }
        folds_split += fold;
        for (int i = 0; i < 3; ++i)
            want[i] = fn[0][i] + fn[1][i];
        double l = sqrt(dot(want, want));
        for (int i = 0; i < 3; ++i)
            assert_true(fabs(n[i] - want[i] / l) < 1e-12);
        ++k;
    }
    print_message("cow refined once: %zu of %zu edges split, %zu near-folds (%zu split), %zu "
                  "creases (input %zu)\n", k, ne, folds, folds_split, s1->num_creases,
                  s0->num_creases);
    assert_int_equal(s1->config->num_vertices, nv + k);
    assert_int_equal((nv + k) % 2, 0);
    assert_true(folds > 0 && k < ne);
    assert_true(folds_split <= 1); /* the parity exception: one closed component */
    assert_true(s0->num_creases > 0);
    assert_true(s1->num_creases > s0->num_creases);
    assert_true(s1->num_creases <= 2 * s0->num_creases);
    for (size_t i = 0; i < s1->num_creases; ++i) { /* a half, or an input crease left whole */
        uint32_t a = s1->creases[2 * i], b = s1->creases[2 * i + 1];
        bool half = (a < nv) != (b < nv), whole = false;
        for (size_t j = 0; !half && j < s0->num_creases; ++j)
            whole = whole || (s0->creases[2 * j] == a && s0->creases[2 * j + 1] == b);
        assert_true(half || whole);
    }
    sk_mesh_destroy(&mesh);
    mesh = skt_read_mesh(skt_shared_mesh("pig.off"));
    o.base_refinements = 2;
    assert_int_equal(sk_smooth_build(mesh, &o, &s2, &err), SK_OK);
    assert_int_equal(s2->stats.failed_vertices, 0);
    assert_true(s2->stats.max_residual < 1e-12);
    sk_continuity_opts co = {.samples = 16, .intersection_tess = (unsigned)-1};
    sk_continuity_report rep;
    assert_int_equal(sk_smooth_continuity(s2, &co, &rep, &err), SK_OK);
    double scale = sk_mesh_diagonal(mesh);
    print_message("pig refined twice: %zu patches, %zu singular, max jump %.2e deg\n",
                  s2->surface.count, rep.singular_patches, rep.max_normal_jump_deg);
    assert_true(rep.max_normal_jump_deg < 1e-7);
    assert_true(rep.max_vertex_error < 1e-12 * scale);
    assert_true(rep.max_gap < 1e-12 * scale);
    sk_smooth_destroy(&s0);
    sk_smooth_destroy(&s1);
    sk_smooth_destroy(&s2);
    sk_mesh_destroy(&mesh);
}

/* The two-sided deviation (sk_deviation, tessellation 4 per patch) of s's surface from mesh */
static sk_deviation_report surface_deviation(const sk_smooth *s, const sk_mesh *mesh)
{
    sk_soup *tess = NULL, *scan = NULL;
    sk_deviation_report dev;
    assert_int_equal(sk_patch_set_tessellate(&s->surface, 4, &tess, NULL), SK_OK);
    assert_int_equal(sk_mesh_to_soup(mesh, &scan, NULL), SK_OK);
    assert_int_equal(sk_deviation(tess, scan, NULL, &dev, NULL, NULL), SK_OK);
    sk_soup_destroy(&tess);
    sk_soup_destroy(&scan);
    return dev;
}

/* Given the pig, whose face 534 is folded under its neighbours (facet normals 179 degrees apart
 * at edge 332-343), when its VC1 surface is built over the input refined once
 * (opts.base_refinements), then the patches that the regularity repair leaves singular beside
 * that fold are gone after the re-routed rounds, which flip slivers of the refined base too
 * (reroute.c; a round whose flips do not pay is tried again without them): 0 singular patches,
 * against at least one without the re-routed rounds; the surface is exactly VC1 (normal jumps
 * under 1e-7 degrees, no spike: overshoot at most 0.5) and closer to the mesh both ways than the
 * surface over the input itself (measured: 0.0043 / 0.0046 of the diagonal, mesh->surface /
 * surface->mesh, against 0.0080 / 0.0091). */
static void test_refine_base_folds(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("pig.off"));
    sk_error err = {0};
    sk_smooth *s0 = NULL, *s1 = NULL, *s1_plain = NULL;
    sk_continuity_opts co = {.samples = 16, .intersection_tess = (unsigned)-1};
    sk_continuity_report rep0, rep1, rep_plain;
    assert_int_equal(sk_smooth_build(mesh, NULL, &s0, &err), SK_OK);
    sk_smooth_opts o = {.base_refinements = 1, .reroute_rounds = -1};
    assert_int_equal(sk_smooth_build(mesh, &o, &s1_plain, &err), SK_OK);
    o.reroute_rounds = 0; /* the default: 12 over a refined base */
    assert_int_equal(sk_smooth_build(mesh, &o, &s1, &err), SK_OK);
    assert_int_equal(sk_smooth_continuity(s0, &co, &rep0, &err), SK_OK);
    assert_int_equal(sk_smooth_continuity(s1_plain, &co, &rep_plain, &err), SK_OK);
    assert_int_equal(sk_smooth_continuity(s1, &co, &rep1, &err), SK_OK);
    sk_deviation_report d0 = surface_deviation(s0, mesh), d1 = surface_deviation(s1, mesh);
    double diag = d0.diagonal;
    print_message("pig refined once: %zu patches, %zu singular (%zu without re-routed rounds, "
                  "%zu rounds), overshoot %.3f, jump %.2e deg; deviation %.4f / %.4f (input: "
                  "%.4f / %.4f)\n",
                  s1->surface.count, rep1.singular_patches, rep_plain.singular_patches,
                  s1->stats.rerouted_rounds, rep1.max_overshoot, rep1.max_normal_jump_deg,
                  d1.mesh_to_surface.max / diag, d1.surface_to_mesh.max / diag,
                  d0.mesh_to_surface.max / diag, d0.surface_to_mesh.max / diag);
    assert_true(rep_plain.singular_patches > 0);
    assert_int_equal(rep1.singular_patches, 0);
    assert_int_equal(s1->stats.failed_vertices, 0);
    assert_true(rep1.max_normal_jump_deg < 1e-7);
    assert_true(rep1.max_overshoot <= 0.5);
    assert_true(d1.mesh_to_surface.max < d0.mesh_to_surface.max);
    assert_true(d1.surface_to_mesh.max < d0.surface_to_mesh.max);
    sk_smooth_destroy(&s0);
    sk_smooth_destroy(&s1);
    sk_smooth_destroy(&s1_plain);
    sk_mesh_destroy(&mesh);
}

/* the before/after table of the meshes (SK_SHAPE_TABLE=1; SK_SHAPE_MESH=name for one) */
static void test_table(void **state)
{
    (void)state;
    if (!getenv("SK_SHAPE_TABLE") && !getenv("SK_SHAPE_MESH"))
        skip();
    const char *only = getenv("SK_SHAPE_MESH");
    for (size_t i = 0; i < N_SHAPE; ++i) {
        if (only && strcmp(only, shape_meshes[i]) != 0)
            continue;
        measure(shape_meshes[i], true);
        measure(shape_meshes[i], false);
    }
}

/* The self-intersection test's candidates (box_candidates.c) against brute force on lion-head's
 * and the cow's surfaces: every patch whose control-point box overlaps that of a patch sharing no
 * corner is a candidate, and the grid leaves out most of the others (it may keep some: crowded
 * cells). */
/* sk__patch_singular_from gives the answer of sk__patch_singular from any first sample, and a
 * singular answer names a sample that fails again. Some of the pig's patches are folded first
 * (a control point next to a corner pushed through the surface) so both answers occur. */
static void test_singular_any_start(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("pig.off"));
    sk_smooth *s = NULL;
    sk_error err = {0};
    if (sk_smooth_build(mesh, NULL, &s, &err) != SK_OK)
        fail_msg("pig: %s", err.message);
    sk_patch_set *set = &s->surface;
    for (size_t p = 0; p < set->count; p += 5) {
        double *cp = set->points + 3 * set->patches[p].first;
        const double *nrm = sk__corner_normal(s, p, 0);
        double len = dist(cp, cp + 3 * sk_patch_num_points(&set->patches[p]) - 3);
        for (int k = 0; k < 3; ++k) /* point 1: next to corner 0 on its first edge */
            cp[3 + k] -= (double)(p % 3) * len * nrm[k];
    }
    const uint8_t starts[] = {0, 1, 7, 30, 44, 45, 80, 81, 255};
    size_t singular = 0, regular = 0;
    for (size_t p = 0; p < set->count; ++p) {
        bool want = sk__patch_singular(s, p, NULL);
        singular += want;
        regular += !want;
        for (size_t i = 0; i < sizeof starts; ++i) {
            uint8_t first = starts[i];
            assert_int_equal(sk__patch_singular_from(s, p, NULL, &first), want);
            if (!want) {
                assert_int_equal(first, starts[i]); /* untouched when regular */
                continue;
            }
            uint8_t again = first;
            assert_true(sk__patch_singular_from(s, p, NULL, &again));
            assert_int_equal(again, first); /* it failed at the first sample tried */
        }
    }
    print_message("pig with folded patches: %zu singular, %zu regular\n", singular, regular);
    assert_true(singular >= 10);
    assert_true(regular >= 100);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
}

/* mesh renumbered: vertex v becomes perm[v], faces in a shuffled order (seeded) */
static sk_mesh *renumbered(const sk_mesh *m, uint64_t seed)
{
    size_t nv = m->num_vertices, nf = m->num_faces;
    uint32_t *perm = malloc(nv * sizeof *perm), *forder = malloc(nf * sizeof *forder);
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(3 * nf * sizeof *idx);
    double *pos = malloc(3 * nv * sizeof *pos);
    assert_non_null(perm && forder && off && idx && pos);
    sk__rng rng;
    sk__rng_seed(&rng, seed);
    for (uint32_t i = 0; i < nv; ++i)
        perm[i] = i;
    for (uint32_t i = 0; i < nf; ++i)
        forder[i] = i;
    for (size_t i = nv; i > 1; --i) { /* Fisher-Yates */
        uint32_t j = sk__rng_below(&rng, (uint32_t)i), t = perm[i - 1];
        perm[i - 1] = perm[j], perm[j] = t;
    }
    for (size_t i = nf; i > 1; --i) {
        uint32_t j = sk__rng_below(&rng, (uint32_t)i), t = forder[i - 1];
        forder[i - 1] = forder[j], forder[j] = t;
    }
    for (size_t v = 0; v < nv; ++v)
        memcpy(pos + 3 * (size_t)perm[v], m->positions + 3 * v, 3 * sizeof(double));
    for (size_t k = 0; k < nf; ++k) {
        uint32_t h = m->f_halfedge[forder[k]];
        off[k] = (uint32_t)(3 * k);
        for (int c = 0; c < 3; ++c, h = m->h_next[h])
            idx[3 * k + (size_t)c] = perm[sk_from(m, h)];
    }
    off[nf] = (uint32_t)(3 * nf);
    sk_mesh *out = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces(nv, pos, nf, off, idx, &out, &err), SK_OK);
    free(perm), free(forder), free(off), free(idx), free(pos);
    return out;
}

/* singular patches of the continuity report of m's surface with the given re-routed rounds;
 * asserts the surface is exactly VC1 and interpolating */
static size_t singular_with_rounds(const sk_mesh *m, int rounds, size_t *done)
{
    sk_smooth_opts o = {0};
    o.reroute_rounds = rounds;
    sk_smooth *s = NULL;
    sk_error err = {0};
    if (sk_smooth_build(m, &o, &s, &err) != SK_OK)
        fail_msg("cow renumbered: %s", err.message);
    sk_continuity_opts co = {0};
    sk_continuity_report rep;
    assert_int_equal(sk_smooth_continuity(s, &co, &rep, &err), SK_OK);
    assert_true(rep.max_normal_jump_deg < 1e-7);
    assert_true(rep.max_vertex_error < 1e-12 * sk_mesh_diagonal(m));
    assert_true(rep.max_normal_error_deg < 1e-7);
    assert_int_equal(rep.singular_patches, s->stats.singular_after_repair);
    *done = s->stats.rerouted_rounds;
    size_t n = rep.singular_patches;
    sk_smooth_destroy(&s);
    return n;
}

/* The re-routed deletion (reroute.c) on the cow renumbered at random (issue 12: the singular
 * patches depended on the input's order, 0 to 10 on the cow): with the rounds, the file's own
 * order and each of four random orders have none (bench/smooth_orders.sh tries more), fewer in
 * all than without, and each surface stays exactly VC1; an order with none without the rounds
 * runs no round (order 3). (Until the breadth-first Initialise the file's order had none without
 * rounds and the test asserted that it ran none; it now has one singular quad, cleared in 2.) */
static void test_reroute_orders(void **state)
{
    (void)state;
    sk_mesh *cow = skt_read_mesh(skt_shared_mesh("cow.off"));
    size_t rounds = 0, without = 0, with = 0, none_without = 0;
    assert_int_equal(singular_with_rounds(cow, 0, &rounds), 0);
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        sk_mesh *m = renumbered(cow, seed);
        size_t a = singular_with_rounds(m, -1, &rounds), b = singular_with_rounds(m, 0, &rounds);
        print_message("cow order %d: %zu singular patches without re-routed rounds, %zu with "
                      "(%zu rounds)\n", (int)seed, a, b, rounds);
        if (a == 0) {
            assert_int_equal(rounds, 0);
            none_without++;
        }
        assert_true(b <= a);
        assert_int_equal(b, 0); /* issue 12's target, on every order tried */
        without += a, with += b;
        sk_mesh_destroy(&m);
    }
    assert_true(with < without);
    assert_true(none_without > 0); /* the no-round check above was exercised */
    sk_mesh_destroy(&cow);
}

/* vertex system k of a fixed family (valence 3, 5, 7, closed or a chain): targets near an even
 * spread, face deltas and ratios nu of the kinds VC1 uses */
static void vsys_case(sk__vsys *s, int k)
{
    static const int val[] = {3, 5, 7, 4, 6};
    memset(s, 0, sizeof *s);
    s->n_edges = val[k % 5];
    s->closed = k % 4 != 3;
    s->fixed_first = !s->closed && k % 8 == 7;
    for (int m = 0; m < s->n_edges; ++m) {
        double a = 6.283185307179586 * m / s->n_edges + 0.05 * sin(1.0 + k + 3.0 * m);
        double r = 1.0 + 0.2 * cos(2.0 * k + m);
        s->pstar[2 * m] = r * cos(a);
        s->pstar[2 * m + 1] = r * sin(a);
        s->du[m] = (m + k) % 3 ? 2.0 * cos(6.283185307179586 / 3.0) + 1.0 : 0.0;
        s->dd[m] = (m + 2 * k) % 3 ? 1.0 : 0.0;
        s->nu[m] = -1.0 - 0.1 * sin(k + 2.0 * m);
    }
}

static void assert_same_solution(const sk__vsys *a, int ra, const sk__vsys *b, int rb)
{
    assert_int_equal(ra, rb);
    assert_memory_equal(a->p, b->p, 2 * (size_t)a->n_edges * sizeof(double));
    assert_memory_equal(a->w, b->w, (size_t)a->n_edges * sizeof(double));
    assert_memory_equal(&a->residual, &b->residual, sizeof(double));
    assert_int_equal(a->iterations, b->iterations);
    assert_int_equal(a->newton_tries, b->newton_tries);
    assert_int_equal(a->used_fallback, b->used_fallback);
}

/* A crease sector of the cow (both ends fixed at the crease tangents) on which the Newton steps
 * of the vertex-system solver are undone every time: the iteration runs to its bound with
 * Gauss-Newton, then projects onto the constraints. Given that system, when it is solved, then
 * it meets the constraints with the fixed ends kept exactly, and stops trying Newton after 40
 * undone steps in a row (it tried one every other iteration, 94, before). */
static void test_vsys_stalled_newton(void **state)
{
    (void)state;
    static const double in[4][5] = {
        {0.0060842864043658485, 0.0011488419543707192, 1, 1, -1},
        {2.0381502325522961e-06, 0.0010682758397196433, 0.75, 1, -0.66580384071706933},
        {-0.0032763356228596241, -0.0014558610407697395, 0.75, 0.75, -1.2021433780386597},
        {-0.0062861821689568741, -0.0011869641447734235, 1, 1, -1}};
    sk__vsys s;
    memset(&s, 0, sizeof s);
    s.n_edges = 4;
    s.fixed_first = s.fixed_last = 1;
    for (int k = 0; k < 4; ++k) {
        s.pstar[2 * k] = in[k][0], s.pstar[2 * k + 1] = in[k][1];
        s.du[k] = in[k][2], s.dd[k] = in[k][3], s.nu[k] = in[k][4];
    }
    int ret = sk__vsys_solve(&s);
    print_message("stalled sector: ret %d, %d iterations, %d Newton tries, residual %.3g\n", ret,
                  s.iterations, s.newton_tries, s.residual);
    assert_int_equal(ret, 0);
    assert_true(s.residual <= 1e-12);
    assert_memory_equal(s.p, s.pstar, 2 * sizeof(double));
    assert_memory_equal(s.p + 6, s.pstar + 6, 2 * sizeof(double));
    for (int m = 1; m <= 2; ++m) /* (8) at the two interior edges, relative to the targets */
        for (int x = 0; x < 2; ++x) {
            double c = s.du[m] * s.p[2 * (m + 1) + x] - s.nu[m] * s.dd[m] * s.p[2 * (m - 1) + x] -
                       s.w[m] * s.p[2 * m + x];
            assert_true(fabs(c) <= 1e-12 * 0.0063);
        }
    assert_true(s.iterations >= 150); /* the stall this test is about */
    assert_true(s.newton_tries >= 40 && s.newton_tries <= 44);
}

/* The memo of vertex-system solves returns what a plain solve returns: on a first solve, on a
 * repeat, after a change of one input by one ulp or of nu alone (a different system), and after
 * the ring has turned over. */
static void test_vsys_memo(void **state)
{
    (void)state;
    sk__vsys_memo *memo = sk__vsys_memo_create();
    assert_non_null(memo);
    int differ = 0, converged = 0;
    for (int k = 0; k < 40; ++k) {
        sk__vsys plain, a, b;
        vsys_case(&plain, k);
        a = b = plain;
        int rp = sk__vsys_solve(&plain);
        assert_same_solution(&plain, rp, &a, sk__vsys_solve_memo(&a, memo));
        assert_same_solution(&plain, rp, &b, sk__vsys_solve_memo(&b, memo));
        /* one ulp in one target, then nu alone: solved afresh, not taken from the memo */
        sk__vsys c, d;
        vsys_case(&c, k);
        c.pstar[1] = nextafter(c.pstar[1], 2.0);
        d = c;
        int rc = sk__vsys_solve(&c);
        assert_same_solution(&c, rc, &d, sk__vsys_solve_memo(&d, memo));
        vsys_case(&c, k);
        c.nu[0] *= 1.5;
        d = c;
        rc = sk__vsys_solve(&c);
        assert_same_solution(&c, rc, &d, sk__vsys_solve_memo(&d, memo));
        differ += memcmp(c.p, plain.p, 2 * (size_t)c.n_edges * sizeof(double)) != 0;
        converged += rp == 0;
    }
    print_message("vsys memo: %d of 40 systems converged, nu changed the solution of %d\n",
                  converged, differ);
    assert_true(differ >= 15); /* the nu variants are other systems (a memo keyed without nu
                                  would have returned the first solution for them) */
    sk__vsys plain, a;
    vsys_case(&plain, 0);
    a = plain;
    int rp = sk__vsys_solve(&plain);
    assert_same_solution(&plain, rp, &a, sk__vsys_solve_memo(&a, memo));
    sk__vsys_memo_destroy(memo);
}

/* The vertex systems solved in lanes (sk__vsys_solve_lanes: closed systems of 3, 5 and 7 edges,
 * 4 at a time in lockstep) give what sk__vsys_solve gives, to the bit: a batch of 90 systems of
 * 3..7 edges, closed and open, with ratios nu that satisfy the product condition (5) (converged
 * in the lanes) and that do not (Newton steps, so solved again alone), lanes refilled as they
 * finish. */
static void test_vsys_lanes(void **state)
{
    (void)state;
    enum { N = 90 };
    static sk__vsys plain[N], lanes[N];
    sk__vsys *batch[N];
    int rp[N], rl[N], in_lanes = 0, newton = 0, converged = 0;
    for (int k = 0; k < N; ++k) {
        vsys_case(&plain[k], k);
        if (k % 3 != 2) /* a star of equal faces: nu = -1, equal Deltas; feasible near the targets */
            for (int m = 0; m < plain[k].n_edges; ++m) {
                plain[k].nu[m] = -1.0;
                plain[k].du[m] = plain[k].dd[m] = k % 2 ? 1.0 : 0.75;
            }
        lanes[k] = plain[k];
        batch[k] = &lanes[k];
        rp[k] = sk__vsys_solve(&plain[k]);
    }
    sk__vsys_solve_lanes(batch, N, rl);
    for (int k = 0; k < N; ++k) {
        assert_same_solution(&plain[k], rp[k], &lanes[k], rl[k]);
        int lane = plain[k].closed && plain[k].n_edges % 2 == 1;
        in_lanes += lane && plain[k].newton_tries == 0 && rp[k] == 0;
        newton += lane && plain[k].newton_tries > 0;
        converged += rp[k] == 0;
    }
    print_message("vsys lanes: %d of %d converged, %d finished in the lanes, %d with Newton steps\n",
                  converged, N, in_lanes, newton);
    assert_true(in_lanes >= 20); /* the lanes' own path is exercised ... */
    assert_true(newton >= 3);    /* ... and so is the hand-over to sk__vsys_solve */
}

/* the largest residual of (8) at p, w (constraint m uses p_{m-1}, p_m, p_{m+1}) */
static double vsys_residual(const sk__vsys *s, const double *p, const double *w)
{
    int n = s->n_edges, first = s->closed ? 0 : 1, last = s->closed ? n : n - 1;
    double worst = 0.0;
    for (int m = first; m < last; ++m) {
        int a = (m + n - 1) % n, b = (m + 1) % n;
        for (int k = 0; k < 2; ++k)
            worst = fmax(worst, fabs(s->du[m] * p[2 * b + k] - s->nu[m] * s->dd[m] * p[2 * a + k] -
                                     w[m] * p[2 * m + k]));
    }
    return worst;
}

/* The premise of the regularity repair's length-scale variants (regularity_repair.c,
 * variant_at: a variant of scale ls is ls times the solution of its blend): (8) is homogeneous
 * in the p, so ls p with the same w meets it to rounding, and the solver gives the scaled
 * targets the same code. (It need not give them ls p: the least-squares problem is not convex,
 * and from the rounded scaled targets its path may end at another solution.) */
static void test_vsys_scale(void **state)
{
    (void)state;
    static const double scales[] = {0.3, 0.75, 1.3, 3.2};
    int close = 0, exact = 0;
    for (int k = 0; k < 40; ++k)
        for (size_t t = 0; t < sizeof scales / sizeof scales[0]; ++t) {
            sk__vsys plain, scaled;
            vsys_case(&plain, k);
            scaled = plain;
            for (int j = 0; j < 2 * plain.n_edges; ++j)
                scaled.pstar[j] *= scales[t];
            int rp = sk__vsys_solve(&plain), rs = sk__vsys_solve(&scaled);
            assert_int_equal(rp, rs);
            if (rp != 0)
                continue;
            double p[2 * SK_VSYS_MAX], dp = 0.0;
            for (int j = 0; j < 2 * plain.n_edges; ++j) {
                p[j] = scales[t] * plain.p[j];
                dp = fmax(dp, fabs(scaled.p[j] - p[j]) / scales[t]);
            }
            assert_true(vsys_residual(&plain, plain.p, plain.w) <= 1e-12);
            assert_true(vsys_residual(&plain, p, plain.w) <= 1e-12 * scales[t]);
            ++exact;
            close += dp < 1e-6;
        }
    print_message("vsys scale: %d scaled solutions meet (8), %d of them within 1e-6 of the "
                  "scaled targets' own solve\n", exact, close);
    assert_true(exact >= 80);
}

static int cmp_key(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static void test_box_candidates(void **state)
{
    (void)state;
    const char *names[] = {"lion-head.off", "cow.off"};
    for (int i = 0; i < 2; ++i) {
        sk_mesh *mesh = skt_read_mesh(skt_shared_mesh(names[i]));
        sk_smooth *s = NULL;
        sk_error err = {0};
        if (sk_smooth_build(mesh, NULL, &s, &err) != SK_OK)
            fail_msg("%s: %s", names[i], err.message);
        const sk_patch_set *set = &s->surface;
        size_t np = set->count;
        uint8_t *cand = malloc(np), *need = calloc(np, 1);
        double *box = malloc(6 * np * sizeof *box);
        assert_non_null(cand);
        assert_non_null(need);
        assert_non_null(box);
        assert_int_equal(sk__patch_box_candidates(set, cand, NULL), SK_OK);
        for (size_t p = 0; p < np; ++p) {
            const double *cp = sk_patch_cp(set, p);
            for (int k = 0; k < 3; ++k)
                box[6 * p + k] = INFINITY, box[6 * p + 3 + k] = -INFINITY;
            for (unsigned j = 0; j < sk_patch_num_points(&set->patches[p]); ++j)
                for (int k = 0; k < 3; ++k) {
                    box[6 * p + k] = fmin(box[6 * p + k], cp[3 * j + k]);
                    box[6 * p + 3 + k] = fmax(box[6 * p + 3 + k], cp[3 * j + k]);
                }
        }
        for (size_t a = 0; a < np; ++a)
            for (size_t b = a + 1; b < np; ++b) {
                bool overlap = true, shared = false;
                for (int k = 0; k < 3; ++k)
                    overlap = overlap && box[6 * a + k] <= box[6 * b + 3 + k] &&
                              box[6 * b + k] <= box[6 * a + 3 + k];
                const sk_patch *pa = &set->patches[a], *pb = &set->patches[b];
                for (unsigned x = 0; x < sk_patch_num_corners(pa); ++x)
                    for (unsigned y = 0; y < sk_patch_num_corners(pb); ++y)
                        shared = shared || pa->corner_ids[x] == pb->corner_ids[y];
                if (overlap && !shared)
                    need[a] = need[b] = 1;
            }
        size_t nneed = 0, ncand = 0;
        for (size_t p = 0; p < np; ++p) {
            assert_true(cand[p] || !need[p]);
            nneed += need[p];
            ncand += cand[p];
        }
        print_message("%s: %zu patches, %zu candidates, %zu needed\n", names[i], np, ncand, nneed);
        assert_true(ncand < np / 2);
        /* the pairs: sorted, each with no shared corner and boxes that meet (padded by 1e-9 of
         * the largest coordinate), every pair of the brute force listed */
        uint64_t *pairs = NULL;
        size_t npairs = 0, nfound = 0;
        assert_int_equal(sk__patch_box_pairs(set, &pairs, &npairs, NULL), SK_OK);
        assert_non_null(pairs);
        double big = 0;
        for (size_t q = 0; q < 6 * np; ++q)
            big = fmax(big, fabs(box[q]));
        for (size_t k = 0; k < npairs; ++k) {
            size_t a = pairs[k] >> 32, b = (uint32_t)pairs[k];
            assert_true(a < b && b < np);
            assert_true(k == 0 || pairs[k - 1] < pairs[k]);
            for (int q = 0; q < 3; ++q)
                assert_true(box[6 * a + q] <= box[6 * b + 3 + q] + 2.1e-9 * big &&
                            box[6 * b + q] <= box[6 * a + 3 + q] + 2.1e-9 * big);
        }
        for (size_t a = 0; a < np; ++a)
            for (size_t b = a + 1; b < np; ++b) {
                bool overlap = true, shared = false;
                for (int k = 0; k < 3; ++k)
                    overlap = overlap && box[6 * a + k] <= box[6 * b + 3 + k] &&
                              box[6 * b + k] <= box[6 * a + 3 + k];
                const sk_patch *pa = &set->patches[a], *pb = &set->patches[b];
                for (unsigned x = 0; x < sk_patch_num_corners(pa); ++x)
                    for (unsigned y = 0; y < sk_patch_num_corners(pb); ++y)
                        shared = shared || pa->corner_ids[x] == pb->corner_ids[y];
                uint64_t key = (uint64_t)a << 32 | b;
                bool listed = bsearch(&key, pairs, npairs, sizeof key, cmp_key) != NULL;
                if (overlap && !shared)
                    assert_true(listed);
                if (listed)
                    assert_false(shared);
                nfound += listed;
            }
        assert_int_equal(nfound, npairs);
        /* the crossings of the pairs on a tessellation of the whole surface are those of the
         * test of every patch against every other */
        sk_soup *tess = NULL, *groups = NULL;
        assert_int_equal(sk_patch_set_tessellate(set, 4, &tess, NULL), SK_OK);
        assert_int_equal(sk_soup_create(0, np, 4 * np, false, false, &groups, NULL), SK_OK);
        uint32_t *face_patch = malloc(tess->num_faces * sizeof *face_patch);
        assert_non_null(face_patch);
        size_t f = 0;
        for (size_t p = 0; p < np; ++p) {
            const sk_patch *pp = &set->patches[p];
            for (int k = 0; k < (pp->kind == SK_PATCH_TRIANGLE ? 16 : 32); ++k)
                face_patch[f++] = (uint32_t)p;
            assert_int_equal(sk_soup_push_face(groups, pp->corner_ids, sk_patch_num_corners(pp)),
                             SK_OK);
        }
        assert_int_equal(f, tess->num_faces);
        sk_intersection_report all, some;
        bool fallback = true;
        assert_int_equal(sk_self_intersections(tess, face_patch, groups, &all, NULL), SK_OK);
        assert_int_equal(sk__self_intersections_pairs(tess, face_patch, np, pairs, npairs, &some,
                                                      &fallback, NULL),
                         SK_OK);
        assert_false(fallback);
        print_message("%s: %zu box pairs, %zu crossing pairs (%zu triangle tests; all against "
                      "all %zu)\n",
                      names[i], npairs, some.pairs, some.triangle_tests, all.triangle_tests);
        assert_int_equal(some.pairs, all.pairs);
        assert_int_equal(some.groups, all.groups);
        assert_int_equal(some.num_examples, all.num_examples);
        assert_memory_equal(some.examples, all.examples, 2 * all.num_examples * sizeof *all.examples);
        if (i == 1)
            assert_true(all.pairs > 0); /* the cow's surface crosses itself */
        free(face_patch);
        sk_soup_destroy(&tess);
        sk_soup_destroy(&groups);
        sk__free(pairs);
        free(cand);
        free(need);
        free(box);
        sk_smooth_destroy(&s);
        sk_mesh_destroy(&mesh);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flips_sheared_grid),
        cmocka_unit_test(test_targets_reached),
        cmocka_unit_test(test_cow_flips),
        cmocka_unit_test(test_fold_normals),
        cmocka_unit_test(test_cow_fold_crease),
        cmocka_unit_test(test_refine_base),
        cmocka_unit_test(test_refine_base_folds),
        cmocka_unit_test(test_fair_energy_matrices),
        cmocka_unit_test(test_fair_vs_lsq),
        cmocka_unit_test(test_fair_points_eight),
        cmocka_unit_test(test_fair_model_energy),
        cmocka_unit_test(test_vsys_stalled_newton),
        cmocka_unit_test(test_table),
        cmocka_unit_test(test_box_candidates),
        cmocka_unit_test(test_singular_any_start),
        cmocka_unit_test(test_reroute_orders),
        cmocka_unit_test(test_vsys_memo),
        cmocka_unit_test(test_vsys_lanes),
        cmocka_unit_test(test_vsys_scale),
    };
    /* SK_SHAPE_ONLY=name runs that test alone (the diagnostics while working) */
    if (getenv("SK_SHAPE_ONLY"))
        cmocka_set_test_filter(getenv("SK_SHAPE_ONLY"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
