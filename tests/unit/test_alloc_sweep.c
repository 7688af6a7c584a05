/* Allocation-failure sweep (issue 17): every library pipeline runs on a small mesh under an
 * sk_allocator that fails its k-th allocation, for every k up to the pipeline's allocation count.
 * Each run must return SK_ERR_NOMEM (or SK_OK with exactly the reference result), leave no block
 * of its own allocated (the allocator counts live blocks; LSan checks the rest in the ASan build)
 * and not crash. cairo and fontconfig are not in it (no picture is drawn). */
#include "testutil.h"

#include "solve/bordered.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* atomic: OpenMP workers allocate too (release build) */
typedef struct counter {
    _Atomic long count, live;
    long fail_at;
} counter;

/* Every block carries a header with a magic number, so that a block of the hook freed with libc's
 * free (an invalid pointer: glibc and ASan abort) or a libc block freed through the hook (no
 * magic: the test fails) shows a module that bypasses the allocator. */
#define T_MAGIC 0x736b616c6c6f6321ull
#define T_HEAD 16

static void *t_wrap(void *raw)
{
    if (!raw)
        return NULL;
    *(unsigned long long *)raw = T_MAGIC;
    return (char *)raw + T_HEAD;
}

static void *t_head(void *p)
{
    void *raw = (char *)p - T_HEAD;
    if (*(unsigned long long *)raw != T_MAGIC) {
        fprintf(stderr, "a block not allocated through sk_allocator was freed through it\n");
        abort();
    }
    return raw;
}

static void *t_malloc(void *user, size_t n)
{
    counter *c = user;
    if (++c->count == c->fail_at)
        return NULL;
    void *p = t_wrap(malloc(n + T_HEAD));
    if (p)
        c->live++;
    return p;
}

static void *t_realloc(void *user, void *p, size_t n)
{
    counter *c = user;
    if (++c->count == c->fail_at)
        return NULL;
    void *q = t_wrap(realloc(p ? t_head(p) : NULL, n + T_HEAD));
    if (q && !p)
        c->live++;
    return q;
}

static void t_free(void *user, void *p)
{
    counter *c = user;
    if (!p)
        return;
    c->live--;
    free(t_head(p));
}

static counter g_cnt; /* the installed allocator's state */
static sk_error g_err; /* the last run's message */

/* One pipeline: reads the mesh from memory and runs to the end, freeing everything; fills res
 * (at most RES_MAX doubles, counted in *nres) with what it computed. */
#define RES_MAX 4096
typedef sk_status (*pipeline_fn)(const char *off, size_t size, double *res, size_t *nres);

static sk_status read_mesh(const char *off, size_t size, sk_soup **soup, sk_mesh **mesh)
{
    sk_status st = sk_soup_read_memory(off, size, "sweep.off", NULL, soup, &g_err);
    if (st == SK_OK && mesh && (st = sk_mesh_from_soup(*soup, mesh, &g_err)) != SK_OK)
        sk_soup_destroy(soup);
    return st;
}

static sk_status p_read_validate(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_status st = read_mesh(off, size, &s, NULL);
    if (st)
        return st;
    sk_validation r;
    st = sk_soup_validate(s, &r, &g_err);
    if (st == SK_OK) {
        res[0] = (double)r.edges;
        res[1] = (double)r.boundary_loops;
        res[2] = r.angle_deficit_sum;
        res[3] = r.area;
        *nres = 4;
    }
    sk_soup_destroy(&s);
    return st;
}

static sk_status p_build_loops(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    sk_loops loops = {0};
    st = sk_mesh_boundary_loops(m, &loops, &g_err);
    if (st == SK_OK) {
        res[0] = (double)loops.count;
        res[1] = loops.count ? loops.lengths[0] : 0.0;
        *nres = 2;
        sk_loops_free(&loops);
    }
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

static sk_status p_hierarchy(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    sk_hierarchy_opts o = {.seed = 3};
    sk_hierarchy *h = NULL;
    st = sk_hierarchy_build(m, &o, &h, &g_err);
    if (st == SK_OK) {
        size_t L = sk_hierarchy_num_levels(h);
        for (size_t i = 0; i < L && 2 * i + 1 < RES_MAX; ++i) {
            sk_level_info li = sk_hierarchy_level_info(h, i);
            res[2 * i] = (double)li.vertices;
            res[2 * i + 1] = (double)li.faces;
        }
        *nres = 2 * L;
        sk_hierarchy_destroy(&h);
    }
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

static sk_status copy_uv(const sk_mesh *m, const double *uv, double *res, size_t *nres)
{
    size_t n = 2 * m->num_vertices;
    assert_true(n <= RES_MAX);
    memcpy(res, uv, n * sizeof(double));
    *nres = n;
    return SK_OK;
}

static sk_status param_method(const char *off, size_t size, double *res, size_t *nres, int method)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    double *uv = calloc(2 * m->num_vertices, sizeof(double)); /* the caller's, not the library's */
    assert_non_null(uv);
    const sk_mesh *out = m; /* the mesh parametrized, and its uv */
    const double *out_uv = uv;
    sk_parametrize_stats ps = {0};
    if (method <= SK_PARAM_LSCM) {
        sk_param_opts o = {.method = (sk_param_method)method};
        st = sk_param_linear(m, &o, uv, NULL, &g_err);
    } else if (method == 100) {
        sk_hparam_opts o = {0};
        st = sk_param_hierarchical(m, &o, uv, NULL, &g_err);
    } else if (method == 101) {
        sk_mips_flat_opts o = {.boundary = {.shape = SK_BOUNDARY_CIRCLE}, .max_steps = 50, .seed = 1};
        st = sk_param_mips_flat(m, &o, uv, NULL, &g_err);
    } else {
        /* the pipeline with the square boundary: 102 the corners found (at the grid's corners:
         * nothing to split), 103 given with the grid corner 5 inside a side (the inner edge of
         * its triangle is split) */
        sk_parametrize_opts o = {.boundary = {.shape = SK_BOUNDARY_SQUARE,
                                              .has_corners = method == 103,
                                              .corners = {1, 17, 35, 30}}};
        st = sk_parametrize(m, &o, uv, &ps, &g_err);
        assert_true(st < 0 || ps.split_edges == (method == 103 ? 1u : 0u));
        if (ps.split_mesh) {
            out = ps.split_mesh;
            out_uv = ps.split_mesh->uvs;
        }
    }
    if (st == SK_OK || st == SK_WARN_FLIPS)
        copy_uv(out, out_uv, res, nres);
    sk_parametrize_stats_release(&ps);
    free(uv);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

static sk_status p_tutte(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, SK_PARAM_TUTTE); }
static sk_status p_floater(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, SK_PARAM_FLOATER); }
static sk_status p_mvc(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, SK_PARAM_MEAN_VALUE); }
static sk_status p_harmonic(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, SK_PARAM_HARMONIC); }
static sk_status p_lscm(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, SK_PARAM_LSCM); }
static sk_status p_mips_hier(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, 100); }
static sk_status p_mips_flat(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, 101); }
static sk_status p_square(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, 102); }
static sk_status p_square_split(const char *o, size_t n, double *r, size_t *k) { return param_method(o, n, r, k, 103); }

/* the multilevel Krylov solves of the linear methods (issue 15): 16 unknowns, levels down to 2 */
static sk_status multilevel(const char *off, size_t size, double *res, size_t *nres,
                            sk_param_method method, sk_linear_solver solver)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    double *uv = calloc(2 * m->num_vertices, sizeof(double)); /* the caller's */
    assert_non_null(uv);
    sk_param_opts o = {.method = method, .solver = solver, .coarse_vertices = 2};
    st = sk_param_linear(m, &o, uv, NULL, &g_err);
    if (st == SK_OK)
        copy_uv(m, uv, res, nres);
    free(uv);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}
static sk_status p_floater_hier(const char *off, size_t size, double *res, size_t *nres)
{
    return multilevel(off, size, res, nres, SK_PARAM_FLOATER, SK_LINEAR_HIERARCHICAL);
}
/* the algebraic multigrid: W-cycle with BiCGStab (Floater), K-cycle with CG (harmonic) */
static sk_status p_floater_amg(const char *off, size_t size, double *res, size_t *nres)
{
    return multilevel(off, size, res, nres, SK_PARAM_FLOATER, SK_LINEAR_AMG);
}
static sk_status p_harmonic_amg(const char *off, size_t size, double *res, size_t *nres)
{
    return multilevel(off, size, res, nres, SK_PARAM_HARMONIC, SK_LINEAR_AMG);
}
static sk_status p_lscm_amg(const char *off, size_t size, double *res, size_t *nres)
{
    return multilevel(off, size, res, nres, SK_PARAM_LSCM, SK_LINEAR_AMG);
}

/* LSCM's bordered direct solve (src/solve/bordered.c; the LSCM route takes it from 5000
 * vertices, more than this sweep's disk): the disk's graph Laplacian plus the identity, boundary
 * last, coupled along the boundary by a small antisymmetric C */
static sk_status p_bordered(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    size_t nv = m->num_vertices, nb = 0;
    for (size_t v = 0; v < nv; ++v)
        nb += sk_is_boundary_v(m, (uint32_t)v);
    uint32_t *idx = calloc(nv, sizeof *idx); /* the test's own blocks: libc */
    double *c = calloc(nb * nb, sizeof *c), *b = calloc(2 * nv, sizeof *b);
    assert_true(idx && c && b && 2 * nv <= RES_MAX);
    size_t in = 0, bn = nv - nb;
    for (size_t v = 0; v < nv; ++v)
        idx[v] = (uint32_t)(sk_is_boundary_v(m, (uint32_t)v) ? bn++ : in++);
    for (size_t i = 0; i + 1 < nb; ++i) {
        c[i + nb * (i + 1)] = 0.1;
        c[(i + 1) + nb * i] = -0.1;
    }
    for (size_t i = 0; i < 2 * nv; ++i)
        b[i] = (double)(i % 7) - 3.0;
    sk_triplets t = {0};
    sk_sparse *a = NULL;
    for (size_t v = 0; v < nv && st == SK_OK; ++v) {
        uint32_t h0 = m->v_halfedge[v], h = h0;
        double deg = 1;
        do {
            uint32_t j = sk_to(m, h);
            deg += 1;
            if (idx[j] < idx[v] && (st = sk_triplets_add(&t, idx[v], idx[j], -1.0)))
                break;
            h = sk_cw_out(m, h);
        } while (h != h0);
        if (st == SK_OK)
            st = sk_triplets_add(&t, idx[v], idx[v], deg);
    }
    if (st == SK_OK && (st = sk_sparse_from_triplets(nv, &t, SK_SPARSE_LOWER, &a, &g_err)) == SK_OK &&
        (st = sk__solve_bordered_pair(a, nb, c, SK_ORDERING_AMD, b, res, NULL, NULL, NULL,
                                      &g_err)) == SK_OK)
        *nres = 2 * nv;
    sk_sparse_destroy(&a);
    sk_triplets_free(&t);
    free(idx);
    free(c);
    free(b);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

/* one B-spline surface fitted to the disk (issue 13) */
static sk_status p_fit(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    sk_bspline_surface *b = NULL;
    sk_fit_opts o = {0};
    st = sk_fit_bspline(m, &o, &b, NULL, &g_err);
    if (st == SK_OK) {
        size_t n = 3 * b->nu * b->nv;
        assert_true(n <= RES_MAX);
        memcpy(res, b->points, n * sizeof(double));
        *nres = n;
    }
    sk_bspline_destroy(&b);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

static sk_status p_smooth_export(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    sk_smooth *sm = NULL;
    sk_continuity_report rep;
    sk_export_stats es = {0};
    sk_export_opts eo = {.timestamp = "2000-01-01T00:00:00"};
    if ((st = sk_smooth_build(m, NULL, &sm, &g_err)) == SK_OK &&
        (st = sk_smooth_continuity(sm, NULL, &rep, &g_err)) == SK_OK &&
        (st = sk_export_step(skt_tmp_path("sweep.step"), &sm->surface, &eo, &es, &g_err)) == SK_OK &&
        (st = sk_export_iges(skt_tmp_path("sweep.igs"), &sm->surface, &eo, &es, &g_err)) == SK_OK) {
        res[0] = rep.max_normal_jump_deg;
        res[1] = rep.max_gap;
        res[2] = (double)sm->surface.count;
        res[3] = (double)es.bytes;
        *nres = 4;
    }
    sk_smooth_destroy(&sm);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

/* VC1 over the disk refined twice beyond itself (issue 13, refine_base.c) */
static sk_status p_smooth_refined(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    sk_smooth *sm = NULL;
    sk_continuity_report rep;
    sk_smooth_opts so = {.base_refinements = 2};
    if ((st = sk_smooth_build(m, &so, &sm, &g_err)) == SK_OK &&
        (st = sk_smooth_continuity(sm, NULL, &rep, &g_err)) == SK_OK) {
        res[0] = rep.max_normal_jump_deg;
        res[1] = rep.max_gap;
        res[2] = (double)sm->surface.count;
        res[3] = (double)sm->config->num_vertices;
        *nres = 4;
    }
    sk_smooth_destroy(&sm);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

static sk_status p_tolerance(const char *off, size_t size, double *res, size_t *nres)
{
    sk_soup *s = NULL;
    sk_mesh *m = NULL;
    sk_status st = read_mesh(off, size, &s, &m);
    if (st)
        return st;
    sk_smooth *sm = NULL;
    sk_tolerance_stats ts;
    sk_tolerance_opts to = {.tolerance_rel = 1e-2};
    if ((st = sk_smooth_tolerance(m, &to, &sm, NULL, &ts, &g_err)) == SK_OK) {
        res[0] = (double)ts.patches;
        res[1] = ts.deviation.hausdorff;
        res[2] = (double)ts.levels_tried;
        res[3] = (double)ts.rounds;
        *nres = 4;
    }
    sk_smooth_destroy(&sm);
    sk_mesh_destroy(&m);
    sk_soup_destroy(&s);
    return st;
}

typedef struct sweep_case {
    const char *name;
    pipeline_fn fn;
} sweep_case;

static void sweep(const sweep_case *c, const char *off, size_t size)
{
    static double ref[RES_MAX], got[RES_MAX];
    size_t nref = 0, ngot = 0;
    counter *cnt = &g_cnt;
    cnt->count = 0;
    cnt->live = 0;
    cnt->fail_at = 0;
    sk_allocator a = {t_malloc, t_realloc, t_free, cnt};
    sk_set_allocator(&a);
    sk_status st = c->fn(off, size, ref, &nref);
    long total = (long)cnt->count;
    assert_true(st == SK_OK || st == SK_WARN_FLIPS);
    assert_int_equal(cnt->live, 0);
    long nomem = 0, exact = 0;
    for (long k = 1; k <= total; ++k) {
        cnt->count = 0;
        cnt->live = 0;
        cnt->fail_at = k;
        ngot = 0;
        sk_status s2 = c->fn(off, size, got, &ngot);
        if (cnt->live != 0) {
            sk_set_allocator(NULL);
            fail_msg("%s: failing allocation %ld of %ld leaked %ld blocks (status %d)", c->name, k,
                     total, (long)cnt->live, (int)s2);
        }
        if (s2 == SK_ERR_NOMEM) {
            nomem++;
        } else if (s2 == st && ngot == nref && !memcmp(got, ref, nref * sizeof(double))) {
            exact++; /* the failed allocation had a fallback */
        } else {
            sk_set_allocator(NULL);
            fail_msg("%s: failing allocation %ld of %ld gave status %d (%s: %s) and %s result",
                     c->name, k, total, (int)s2, sk_status_string(s2), g_err.message,
                     ngot == nref && !memcmp(got, ref, nref * sizeof(double)) ? "the reference"
                                                                               : "a different");
        }
    }
    sk_set_allocator(NULL);
    print_message("%-18s %6ld allocations: %6ld out of memory, %4ld exact\n", c->name, total, nomem,
                  exact);
}

static char *disk_off(int n, size_t *size)
{
    sk_mesh *m = skt_planar_disk(n, 7);
    sk_soup *s = NULL;
    assert_int_equal(sk_mesh_to_soup(m, &s, NULL), SK_OK);
    sk_write_opts wo = {.format = SK_FORMAT_OFF};
    void *data = NULL;
    assert_int_equal(sk_soup_write_memory(s, &wo, &data, size, NULL), SK_OK);
    sk_soup_destroy(&s);
    sk_mesh_destroy(&m);
    return data;
}

static void given_kth_allocation_fails_then_every_pipeline_fails_cleanly(void **state)
{
    (void)state;
    size_t size = 0;
    char *off = disk_off(6, &size);
    const sweep_case cases[] = {
        {"read+validate", p_read_validate}, {"build+loops", p_build_loops},
        {"hierarchy", p_hierarchy},         {"tutte", p_tutte},
        {"floater", p_floater},             {"mvc", p_mvc},
        {"harmonic", p_harmonic},           {"lscm", p_lscm},
        {"mips-hierarchical", p_mips_hier}, {"mips-flat", p_mips_flat},
        {"smooth+export", p_smooth_export}, {"floater-hierarchical", p_floater_hier},
        {"floater-amg", p_floater_amg}, {"harmonic-amg", p_harmonic_amg}, {"lscm-amg", p_lscm_amg},
        {"lscm-bordered", p_bordered},
        {"fit", p_fit},                     {"square", p_square},
        {"square-split", p_square_split},   {"smooth-tolerance", p_tolerance},
        {"smooth-refined", p_smooth_refined},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        sweep(&cases[i], off, size);
    free(off);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_kth_allocation_fails_then_every_pipeline_fails_cleanly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
