/* Global steps of the MIPS optimizer and the hierarchical driver: monotone energy, no flips after
 * any step, the planar optimum, and the paper's comparison (hierarchical vs conventional at equal
 * budgets). SK_TEST_QUICK=1 (the ASan run) uses fewer meshes and seeds. */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool quick(void)
{
    const char *q = getenv("SK_TEST_QUICK");
    return q && *q && strcmp(q, "0") != 0;
}

/* the disk meshes of the shared data (data/README.md: one boundary loop, Euler characteristic 1,
 * non-degenerate) */
static const char *const disks[] = {"nefertiti.off", "patch-01.off", "paraboloid-patch.off",
                                    "three_peaks.off", "mushroom.off", "lion-head.off",
                                    "in.off", "triangle.off", "fold.off"};
static const size_t num_disks = sizeof disks / sizeof disks[0];

static double *floater_start(const sk_mesh *m)
{
    double *uv = malloc(2 * m->num_vertices * sizeof(double));
    sk_param_opts po = {0};
    po.method = SK_PARAM_FLOATER;
    po.boundary.shape = SK_BOUNDARY_CIRCLE;
    assert_int_equal(sk_param_linear(m, &po, uv, NULL, NULL), SK_OK);
    return uv;
}

static size_t flips(const sk_mesh *m, const double *uv)
{
    sk_param_metrics pm;
    assert_int_equal(sk_param_metrics_compute(m, uv, &pm, NULL), SK_OK);
    return pm.flipped;
}

/* One global step and one sweep at a time, free and fixed boundary: the energy never rises and
 * no triangle is ever inverted (exact orientation test of the metrics). */
static void given_disk_meshes_when_global_blocks_then_energy_never_rises_and_no_flip(void **state)
{
    (void)state;
    size_t count = quick() ? 2 : 6;
    for (size_t i = 0; i < count; ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(disks[i]));
        for (int fixed = 0; fixed < 2; ++fixed) {
            double *uv = floater_start(m);
            double prev = INFINITY;
            for (int round = 0; round < 6; ++round) {
                sk_mips_opts o = {.boundary = fixed ? SK_BOUNDARY_GIVEN : SK_BOUNDARY_FREE, .global_steps = 1,
                                  .sweeps_per_global = 1, .max_sweeps = 1, .tolerance = -1,
                                  .seed = (uint64_t)round};
                sk_mips_stats s;
                assert_int_equal(sk_param_mips(m, &o, uv, &s, NULL), SK_OK);
                assert_int_equal(s.global_steps, 1);
                if (!(s.energy <= s.energy_start * (1 + 1e-14)) || !(s.energy <= prev * (1 + 1e-14)))
                    fail_msg("%s round %d: energy %.17g after %.17g (previous %.17g)", disks[i],
                             round, s.energy, s.energy_start, prev);
                prev = s.energy;
                if (flips(m, uv))
                    fail_msg("%s round %d: %zu flips", disks[i], round, flips(m, uv));
            }
            free(uv);
        }
        sk_mesh_destroy(&m);
    }
}

/* The hierarchical driver on every disk mesh over a few seeds, with and without global steps,
 * free and circle boundary: no flipped triangle, finite energy, and every optimized level's
 * energy is the MIPS sum of a flip-free map (>= 2 per triangle). */
static void given_every_disk_mesh_and_seeds_when_hierarchical_then_no_flip(void **state)
{
    (void)state;
    size_t seeds = quick() ? 1 : 3;
    for (size_t i = 0; i < num_disks; ++i) {
        if (quick() && !strcmp(disks[i], "lion-head.off"))
            continue;
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(disks[i]));
        double *uv = malloc(2 * m->num_vertices * sizeof(double));
        for (uint64_t seed = 1; seed <= seeds; ++seed)
            for (int mode = 0; mode < 3; ++mode) {
                sk_hparam_opts o = {.seed = seed};
                if (mode == 1)
                    o.global_steps = (size_t)-1; /* the paper's method */
                if (mode == 2)
                    o.boundary.shape = SK_BOUNDARY_CIRCLE;
                sk_hparam_stats s;
                sk_error err;
                if (sk_param_hierarchical(m, &o, uv, &s, &err))
                    fail_msg("%s seed %llu mode %d: %s", disks[i], (unsigned long long)seed, mode,
                             err.message);
                size_t f = flips(m, uv);
                if (f)
                    fail_msg("%s seed %llu mode %d: %zu flips", disks[i],
                             (unsigned long long)seed, mode, f);
                assert_true(isfinite(s.energy));
                assert_true(s.energy >= 2.0 * (double)m->num_faces * (1 - 1e-12));
                for (size_t l = 0; l < s.num_levels; ++l)
                    if (!isnan(s.levels[l].energy))
                        assert_true(s.levels[l].energy >= 2.0 * (double)s.levels[l].faces * (1 - 1e-12));
                sk_hparam_stats_release(&s);
            }
        free(uv);
        sk_mesh_destroy(&m);
    }
}

/* An irregular planar grid (points jittered in z = 0): its optimum is the identity up to a
 * similarity, 2 per triangle. */
static void given_planar_disk_when_global_steps_free_boundary_then_2_per_triangle(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(40, 9);
    double *uv = floater_start(m); /* circle boundary: far from the optimum */
    double opt = 2.0 * (double)m->num_faces;
    sk_mips_opts o = {.global_steps = 40, .sweeps_per_global = 1, .max_sweeps = 40,
                      .tolerance = 1e-15, .seed = 2};
    sk_mips_stats s;
    assert_int_equal(sk_param_mips(m, &o, uv, &s, NULL), SK_OK);
    assert_true(s.energy_start > 1.05 * opt);
    if (fabs(s.energy - opt) > 1e-9 * opt)
        fail_msg("flat: energy %.15g, optimum %.15g (%zu global steps)", s.energy, opt,
                 s.global_steps);
    assert_int_equal(flips(m, uv), 0);
    /* the hierarchical driver with a long budget gets there too */
    sk_hparam_opts ho = {.seed = 4, .global_steps = 30, .tolerance = 1e-15};
    sk_hparam_stats hs;
    assert_int_equal(sk_param_hierarchical(m, &ho, uv, &hs, NULL), SK_OK);
    if (fabs(hs.energy - opt) > 1e-9 * opt)
        fail_msg("hierarchical: energy %.15g, optimum %.15g", hs.energy, opt);
    sk_hparam_stats_release(&hs);
    assert_int_equal(flips(m, uv), 0);
    free(uv);
    sk_mesh_destroy(&m);
}

/* Table 1's comparison: the paper's hierarchical method (local steps only) against the
 * conventional flat optimization from Floater's map with the same number of local steps. */
static void given_three_meshes_when_equal_budget_then_hierarchical_beats_conventional(void **state)
{
    (void)state;
    /* (on the two smallest disks, nefertiti and patch-01, 700 steps per vertex let the flat
     * method converge: bench/bench_table1 shows both within 0.01%) */
    const char *names[] = {"mushroom.off", "three_peaks.off", "paraboloid-patch.off"};
    double per_vertex = quick() ? 100 : 300;
    for (int i = 0; i < 3; ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(names[i]));
        size_t nv = m->num_vertices, budget = (size_t)(per_vertex * (double)nv);
        double *uv = malloc(2 * nv * sizeof(double));
        sk_hparam_opts ho = {.seed = 1, .finest_sweeps = (size_t)-1, .max_steps = budget,
                             .tolerance = -1, .global_steps = (size_t)-1};
        sk_hparam_stats hs;
        assert_int_equal(sk_param_hierarchical(m, &ho, uv, &hs, NULL), SK_OK);
        assert_int_equal(hs.steps, budget);
        assert_int_equal(flips(m, uv), 0);
        sk_mips_stats cs;
        sk_mips_flat_opts fo = {.max_steps = hs.steps, .tolerance = -1.0, .seed = 1};
        sk_status st = sk_param_mips_flat(m, &fo, uv, &cs, NULL);
        assert_int_equal(st, SK_OK);
        assert_int_equal(cs.steps, hs.steps);
        if (!(hs.energy < cs.energy))
            fail_msg("%s: hierarchical %.6f, conventional %.6f at %zu steps", names[i], hs.energy,
                     cs.energy, budget);
        /* and the default (with global steps) is better still */
        sk_hparam_stats_release(&hs);
        sk_hparam_opts d = {.seed = 1};
        assert_int_equal(sk_param_hierarchical(m, &d, uv, &hs, NULL), SK_OK);
        assert_true(hs.energy < cs.energy);
        sk_hparam_stats_release(&hs);
        free(uv);
        sk_mesh_destroy(&m);
    }
}

/* The certified gap: every triangle's MIPS energy is at least 2, so (E - 2T) / 2T bounds the
 * distance from any converged energy. The reported bound is that value of the result, and a much
 * longer run (schedule x4, 20 finest sweeps, no certified stop) ends at most that far below. */
static void given_disk_meshes_when_hierarchical_then_gap_bound_holds_against_a_long_run(void **state)
{
    (void)state;
    size_t count = quick() ? 2 : 6;
    for (size_t i = 0; i < count; ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(disks[i]));
        double *uv = malloc(2 * m->num_vertices * sizeof(double));
        sk_hparam_opts o = {.seed = 1};
        sk_hparam_stats s;
        assert_int_equal(sk_param_hierarchical(m, &o, uv, &s, NULL), SK_OK);
        assert_int_equal(flips(m, uv), 0);
        double e = 0.0, two_t = 2.0 * (double)m->num_faces;
        size_t inv = 1;
        assert_int_equal(sk_mips_energy(m, uv, &e, &inv, NULL), SK_OK);
        assert_int_equal(inv, 0);
        assert_true(fabs(s.gap_bound - (e - two_t) / two_t) <= 1e-12 * (1.0 + s.gap_bound));
        assert_true(s.gap_bound >= 0.0);
        sk_hparam_stats_release(&s);
        sk_hparam_opts lo = {.seed = 2, .level_work = 8.0, .finest_sweeps = 20,
                             .tolerance = 1e-12, .target_gap = -1.0};
        assert_int_equal(sk_param_hierarchical(m, &lo, uv, &s, NULL), SK_OK);
        assert_int_equal(s.gap_stopped_levels, 0);
        if (!((e - s.energy) / s.energy <= (e - two_t) / two_t))
            fail_msg("%s: default %.12g, long run %.12g, bound %.3g", disks[i], e, s.energy,
                     (e - two_t) / two_t);
        sk_hparam_stats_release(&s);
        free(uv);
        sk_mesh_destroy(&m);
    }
}

/* A planar disk reaches 2 per triangle on every level: the default stops each level once it is
 * certified within 5e-4 (fewer steps than without the stop), flip-free and within the bound. */
static void given_planar_disk_when_default_then_levels_stop_on_the_certified_gap(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(60, 5);
    double *uv = malloc(2 * m->num_vertices * sizeof(double));
    double two_t = 2.0 * (double)m->num_faces;
    sk_hparam_opts o = {.seed = 1};
    sk_hparam_stats on, off;
    assert_int_equal(sk_param_hierarchical(m, &o, uv, &on, NULL), SK_OK);
    assert_int_equal(flips(m, uv), 0);
    assert_true(on.gap_stopped_levels > 0);
    assert_true(on.gap_bound <= 5e-4 + 1e-9);
    assert_true(on.energy <= two_t * (1.0 + 5e-4 + 1e-9));
    o.target_gap = -1.0;
    assert_int_equal(sk_param_hierarchical(m, &o, uv, &off, NULL), SK_OK);
    assert_int_equal(off.gap_stopped_levels, 0);
    assert_true(on.steps < off.steps);
    /* an explicit tolerance turns the default stop off; an explicit target turns it back on */
    sk_hparam_opts t = {.seed = 1, .tolerance = 1e-5};
    sk_hparam_stats ts;
    assert_int_equal(sk_param_hierarchical(m, &t, uv, &ts, NULL), SK_OK);
    assert_int_equal(ts.gap_stopped_levels, 0);
    assert_int_equal(ts.steps, off.steps);
    sk_hparam_stats_release(&ts);
    t.target_gap = 5e-4;
    assert_int_equal(sk_param_hierarchical(m, &t, uv, &ts, NULL), SK_OK);
    assert_int_equal(ts.steps, on.steps);
    assert_true(ts.energy == on.energy);
    sk_hparam_stats_release(&ts);
    sk_hparam_stats_release(&on);
    sk_hparam_stats_release(&off);
    free(uv);
    sk_mesh_destroy(&m);
}

/* sk_param_mips's gap_stop: a start already within it takes no sweep (its energy stays); with
 * the area term (whose energies are not bounded by 2) it is ignored. */
static void given_start_within_gap_when_mips_then_no_sweep_unless_area_term(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(20, 3);
    size_t nv = m->num_vertices;
    double *uv = malloc(2 * nv * sizeof(double));
    for (size_t v = 0; v < nv; ++v) /* the identity: 2 per triangle up to rounding */
        memcpy(uv + 2 * v, m->positions + 3 * v, 2 * sizeof(double));
    sk_mips_opts o = {.gap_stop = 1e-6, .seed = 1};
    sk_mips_stats s;
    assert_int_equal(sk_param_mips(m, &o, uv, &s, NULL), SK_OK);
    assert_true(s.gap_stopped);
    assert_int_equal(s.sweeps, 0);
    assert_int_equal(s.steps, 0);
    assert_true(fabs(s.energy - s.energy_start) <= 1e-12 * s.energy_start);
    assert_true(s.energy <= 2.0 * (double)m->num_faces * (1.0 + 1e-6));
    o.area_theta = 1.0;
    assert_int_equal(sk_param_mips(m, &o, uv, &s, NULL), SK_OK);
    assert_false(s.gap_stopped);
    assert_true(s.sweeps > 0);
    free(uv);
    sk_mesh_destroy(&m);
}

/* The input level is optimized on the input mesh itself, its optimizer context built beside the
 * last vertex splits (above 50,000 faces; lion-head Loop-subdivided once has 66,696): the
 * reported energy is exactly the input mesh's energy of the returned uv (the same triangles in
 * the same order), the last level has the input's faces, no triangle flips, and with the circle
 * boundary the boundary vertices stay on the unit circle (the context's fixed vertices). */
static void given_subdivided_lion_when_hierarchical_then_input_level_is_the_input_mesh(void **state)
{
    (void)state;
    sk_mesh *coarse = skt_read_mesh(skt_shared_mesh("lion-head.off")), *m = NULL;
    sk_subdiv_opts so = {.scheme = SK_SUBDIV_LOOP, .iterations = 1};
    assert_int_equal(sk_mesh_subdivide(coarse, &so, &m, NULL), SK_OK);
    sk_mesh_destroy(&coarse);
    assert_true(m->num_faces > 50000);
    double *uv = malloc(2 * m->num_vertices * sizeof(double));
    for (int fixed = 0; fixed < 2; ++fixed) {
        sk_hparam_opts o = {.seed = 3};
        if (fixed)
            o.boundary.shape = SK_BOUNDARY_CIRCLE;
        sk_hparam_stats s;
        assert_int_equal(sk_param_hierarchical(m, &o, uv, &s, NULL), SK_OK);
        assert_int_equal(s.levels[s.num_levels - 1].faces, m->num_faces);
        double e = 0.0;
        size_t inverted = 1;
        assert_int_equal(sk_mips_energy(m, uv, &e, &inverted, NULL), SK_OK);
        assert_int_equal(inverted, 0);
        assert_true(e == s.energy);
        assert_int_equal(flips(m, uv), 0);
        if (fixed) {
            size_t nb = 0;
            for (uint32_t v = 0; v < m->num_vertices; ++v)
                if (sk_is_boundary_v(m, v)) {
                    assert_true(fabs(hypot(uv[2 * v], uv[2 * v + 1]) - 1.0) < 1e-12);
                    nb++;
                }
            assert_int_equal(nb, 72); /* (lion-head: 36 boundary edges, split once) */
        } else {
            assert_true(s.gap_bound <= 1e-3);
        }
        sk_hparam_stats_release(&s);
    }
    free(uv);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_disk_meshes_when_global_blocks_then_energy_never_rises_and_no_flip),
        cmocka_unit_test(given_every_disk_mesh_and_seeds_when_hierarchical_then_no_flip),
        cmocka_unit_test(given_planar_disk_when_global_steps_free_boundary_then_2_per_triangle),
        cmocka_unit_test(given_three_meshes_when_equal_budget_then_hierarchical_beats_conventional),
        cmocka_unit_test(given_disk_meshes_when_hierarchical_then_gap_bound_holds_against_a_long_run),
        cmocka_unit_test(given_planar_disk_when_default_then_levels_stop_on_the_certified_gap),
        cmocka_unit_test(given_start_within_gap_when_mips_then_no_sweep_unless_area_term),
        cmocka_unit_test(given_subdivided_lion_when_hierarchical_then_input_level_is_the_input_mesh),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
