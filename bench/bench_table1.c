/* Table 1 of Hormann, Greiner, Campagna, reproduced: the MIPS energy reached with the same number
 * of local steps (about 700 per vertex) by the hierarchical method and by conventional (flat)
 * optimization from Floater's parametrization, against the optimum (a long converged run).
 *   bench_table1 [STEPS_PER_VERTEX] MESH...
 * Free boundary (the paper's Table 1 setting is not stated; fixed circle with --circle). */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    int first = 1;
    double per_vertex = 700.0;
    sk_boundary_shape boundary = SK_BOUNDARY_FREE;
    while (first < argc && argv[first][0] == '-') {
        if (!strcmp(argv[first], "--circle"))
            boundary = SK_BOUNDARY_CIRCLE;
        else if (!strcmp(argv[first], "--steps") && first + 1 < argc)
            per_vertex = atof(argv[++first]);
        first++;
    }
    if (first >= argc) {
        fprintf(stderr, "usage: bench_table1 [--steps PER_VERTEX] [--circle] MESH...\n");
        return 2;
    }
    printf("boundary: %s; budget: %.0f local steps per vertex\n\n",
           sk_boundary_shape_name(boundary), per_vertex);
    printf("| mesh | triangles | optimum | hierarchical | excess | conventional | excess | "
           "ratio | flips h/c |\n|---|---|---|---|---|---|---|---|---|\n");
    int rc = 0;
    for (int i = first; i < argc; ++i) {
        sk_error err;
        sk_mesh *m = NULL;
        if (sk_mesh_read(argv[i], NULL, &m, &err)) {
            fprintf(stderr, "bench_table1: %s\n", err.message);
            return 1;
        }
        size_t nv = m->num_vertices;
        size_t budget = (size_t)(per_vertex * (double)nv);
        double *uv = malloc(2 * nv * sizeof(double));
        /* optimum: hierarchical start, then sweeps until the energy stops moving */
        sk_hparam_opts opt = {.boundary = {.shape = boundary}, .seed = 7, .level_work = 1e6,
                              .sweeps_per_level = 2000, .finest_sweeps = 20000,
                              .tolerance = 1e-14};
        sk_hparam_stats so;
        sk_param_metrics mh, mc;
        if (sk_param_hierarchical(m, &opt, uv, &so, &err)) {
            fprintf(stderr, "bench_table1: %s: %s\n", argv[i], err.message);
            return 1;
        }
        sk_mips_opts po = {.global_steps = 40, .sweeps_per_global = 4, .max_sweeps = 400,
                           .tolerance = 1e-14, .seed = 3};
        sk_mips_stats ps;
        if (sk_param_mips(m, &po, uv, &ps, &err)) { /* polished by global steps */
            fprintf(stderr, "bench_table1: %s: %s\n", argv[i], err.message);
            return 1;
        }
        double optimum = ps.energy;
        /* the budget: the schedule's sweeps on the coarser levels (about 5 of the finest level's
         * size each), all the rest on the input level */
        sk_hparam_opts ho = {.boundary = {.shape = boundary}, .seed = 1, .finest_sweeps = (size_t)-1,
                             .max_steps = budget, .tolerance = -1,
                             .global_steps = (size_t)-1}; /* the paper's method: local steps */
        sk_hparam_stats sh;
        if (sk_param_hierarchical(m, &ho, uv, &sh, &err)) {
            fprintf(stderr, "bench_table1: %s: %s\n", argv[i], err.message);
            return 1;
        }
        sk_param_metrics_compute(m, uv, &mh, &err);
        sk_mips_stats sc;
        sk_mips_flat_opts fo = {.boundary = {.shape = boundary}, .max_steps = sh.steps,
                              .tolerance = -1.0, .seed = 1};
        sk_status st = sk_param_mips_flat(m, &fo, uv, &sc, &err);
        if (st != SK_OK && st != SK_WARN_FLIPS) {
            fprintf(stderr, "bench_table1: %s: %s\n", argv[i], err.message);
            return 1;
        }
        sk_param_metrics_compute(m, uv, &mc, &err);
        const char *name = strrchr(argv[i], '/') ? strrchr(argv[i], '/') + 1 : argv[i];
        double eh = 100.0 * (sh.energy - optimum) / optimum, ec = 100.0 * (sc.energy - optimum) / optimum;
        printf("| %s | %zu | %.2f | %.2f | %.4f%% | %.2f | %.4f%% | %.1f | %zu/%zu |\n", name,
               m->num_faces, optimum, sh.energy, eh, sc.energy, ec, eh > 0 ? ec / eh : 0.0,
               mh.flipped, mc.flipped);
        if (sh.steps != sc.steps)
            fprintf(stderr, "bench_table1: unequal step counts %zu vs %zu\n", sh.steps, sc.steps);
        if (!(sh.energy < sc.energy))
            rc = 1;
        sk_hparam_stats_release(&so);
        sk_hparam_stats_release(&sh);
        free(uv);
        sk_mesh_destroy(&m);
    }
    printf("\npaper (1,999 / 864 triangles): hierarchical 4010.98 vs conventional 4034.79 against "
           "4009.09 (0.047%% vs 0.64%%); 1736.43 vs 1743.85 against 1735.87 (0.032%% vs 0.46%%)\n");
    return rc;
}
