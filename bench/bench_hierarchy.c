/* Benchmark: full progressive-mesh hierarchy (random independent sets of half-edge collapses) of a
 * mesh. Usage: bench_hierarchy MESH [--seed S] [--repeat R] [--levels-table]
 * Prints the read time, the best build time over R runs, and (--levels-table) the levels of the
 * last run: level, vertices, faces, ratio to the next finer level, seconds. */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    const char *path = NULL;
    unsigned long long seed = 1;
    int repeat = 3;
    int table = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--seed") && i + 1 < argc)
            seed = strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--levels-table"))
            table = 1;
        else
            path = argv[i];
    }
    if (!path || repeat < 1) {
        fprintf(stderr, "usage: bench_hierarchy MESH [--seed S] [--repeat R] [--levels-table]\n");
        return 2;
    }
    sk_error err;
    sk_mesh *mesh = NULL;
    double t0 = sk_seconds();
    if (sk_mesh_read(path, NULL, &mesh, &err)) {
        fprintf(stderr, "bench_hierarchy: %s\n", err.message);
        return 1;
    }
    double t_read = sk_seconds() - t0;
    double best = 1e30;
    sk_hierarchy *h = NULL;
    for (int r = 0; r < repeat; ++r) {
        sk_hierarchy_destroy(&h);
        sk_hierarchy_opts o = {0};
        o.seed = seed;
        t0 = sk_seconds();
        if (sk_hierarchy_build(mesh, &o, &h, &err)) {
            fprintf(stderr, "bench_hierarchy: %s\n", err.message);
            return 1;
        }
        double t = sk_seconds() - t0;
        best = t < best ? t : best;
    }
    size_t L = sk_hierarchy_num_levels(h);
    /* walk back up with the splits (what the parametrization does) */
    t0 = sk_seconds();
    sk_mesh *m = NULL;
    sk_mesh_copy(sk_hierarchy_coarsest(h), &m, &err);
    for (size_t i = 0; i + 1 < L; ++i)
        if (sk_hierarchy_split(h, i, m, &err)) {
            fprintf(stderr, "bench_hierarchy: %s\n", err.message);
            return 1;
        }
    double t_up = sk_seconds() - t0;
    printf("mesh %s: %zu vertices, %zu faces, read %.3f s\n", path, mesh->num_vertices,
           mesh->num_faces, t_read);
    printf("surfkit hierarchy: %zu levels, %zu -> %zu faces, build %.3f s (best of %d), "
           "splits back to the input %.3f s\n",
           L, sk_hierarchy_level_info(h, L - 1).faces, sk_hierarchy_level_info(h, 0).faces, best,
           repeat, t_up);
    if (table) {
        printf("\n| level | vertices | faces | ratio | seconds |\n|---:|---:|---:|---:|---:|\n");
        for (size_t i = L; i-- > 0;) {
            sk_level_info li = sk_hierarchy_level_info(h, i);
            double ratio = i + 1 < L ? (double)sk_hierarchy_level_info(h, i + 1).faces / (double)li.faces : 0;
            if (i + 1 < L)
                printf("| M^%zu | %zu | %zu | %.3f | %.3f |\n", i, li.vertices, li.faces, ratio,
                       li.seconds);
            else
                printf("| M^%zu (input) | %zu | %zu | - | %.3f |\n", i, li.vertices, li.faces,
                       li.seconds);
        }
    }
    sk_mesh_destroy(&m);
    sk_hierarchy_destroy(&h);
    sk_mesh_destroy(&mesh);
    return 0;
}
