/* bench_smooth MESH: VC1 surface of a mesh, one table row per stage (read excluded), plus the
 * deletion counts and the continuity result (report stage: 4 samples per edge, shape measures on a
 * 4-step grid per patch). */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <time.h>

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_smooth MESH\n");
        return 2;
    }
    sk_mesh *m = NULL;
    sk_error err = {0};
    double t0 = sk_seconds();
    if (sk_mesh_read(argv[1], NULL, &m, &err) != SK_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    double t1 = sk_seconds();
    clock_t c1 = clock(); /* process CPU time (all threads): stage seconds are wall clock */
    sk_smooth *s = NULL;
    if (sk_smooth_build(m, NULL, &s, &err) != SK_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    double t2 = sk_seconds();
    clock_t c2 = clock();
    sk_continuity_report r;
    sk_continuity_opts co = {0};
    co.samples = 4;
    co.shape_samples = 4; /* overshoot and fairness on a 4-step grid per patch, like the edges */
    sk_smooth_continuity(s, &co, &r, &err);
    double t3 = sk_seconds();
    clock_t c3 = clock();
    const sk_smooth_stats *st = &s->stats;
    printf("mesh: %s, %zu vertices, %zu triangles (read %.2f s, not counted)\n\n", argv[1],
           m->num_vertices, m->num_faces, t1 - t0);
    /* seconds and microseconds per input triangle of each stage (the bound: 5 us) */
    const char *names[] = {"normals", "edge flips", "edge deletion", "vertex systems",
                           "fair points", "patches", "repair", "report"};
    double secs[] = {st->seconds_normals, st->seconds_flips, st->seconds_deletion,
                     st->seconds_systems, st->seconds_fair, st->seconds_patches,
                     st->seconds_repair, t3 - t2};
    double per = m->num_faces ? 1e6 / (double)m->num_faces : 0.0;
    printf("| stage          | seconds | us / triangle |\n|----------------|---------|---------------|\n");
    for (size_t i = 0; i < sizeof secs / sizeof secs[0]; ++i)
        printf("| %-14s | %7.3f | %13.2f |\n", names[i], secs[i], secs[i] * per);
    printf("| total build    | %7.3f | %13.2f |\n| build + report | %7.3f | %13.2f |\n\n", t2 - t1,
           (t2 - t1) * per, t3 - t1, (t3 - t1) * per);
    printf("CPU seconds (process, all threads): build %.3f, report %.3f\n\n",
           (double)(c2 - c1) / CLOCKS_PER_SEC, (double)(c3 - c2) / CLOCKS_PER_SEC);
    printf("| even vertices | lower bound | deleted edges | ratio | triangles | quads | forced |\n");
    printf("|---------------|-------------|---------------|-------|-----------|-------|--------|\n");
    printf("| %13zu | %11zu | %13zu | %5.3f | %9zu | %5zu | %6zu |\n\n", st->deletion.even_vertices,
           st->deletion.lower_bound, st->deletion.deleted_edges,
           st->deletion.lower_bound ? (double)st->deletion.deleted_edges / st->deletion.lower_bound : 1.0,
           st->deletion.triangles, st->deletion.quads, st->deletion.forced_edges);
    printf("max overshoot %.3g (patch %u, %zu over 0.5), fairness max %.3g deg (patch %u) mean %.3g "
           "deg\n",
           r.max_overshoot, r.max_overshoot_patch, r.overshoot_patches, r.max_fairness_deg,
           r.max_fairness_patch, r.mean_fairness_deg);
    printf("max normal jump %.3g deg, mean %.3g deg, max gap %.3g, singular patches %zu (before repair %zu, repaired vertices %zu), relaxed "
           "vertices %zu, angle violations %zu, failed vertices %zu, max iterations %zu\n",
           r.max_normal_jump_deg, r.mean_normal_jump_deg, r.max_gap, r.singular_patches,
           st->singular_before_repair, st->repaired_vertices,
           st->relaxed_vertices, st->angle_violations, st->failed_vertices, st->max_iterations);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&m);
    return 0;
}
