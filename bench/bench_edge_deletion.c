/* bench_edge_deletion MESH ...: sk_edge_deletion on the input's triangles (no edge flips, no
 * creases: the same graph as bench/tjoin_lemon.cpp's minimum T-join), one line per mesh with the
 * statistics and the CPU (all threads) and wall seconds of the call (bench/tjoin.sh). */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <time.h>

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_edge_deletion MESH ...\n");
        return 2;
    }
    for (int a = 1; a < argc; ++a) {
        sk_mesh *m = NULL, *out = NULL;
        sk_error err = {0};
        if (sk_mesh_read(argv[a], NULL, &m, &err) != SK_OK) {
            fprintf(stderr, "%s: %s\n", argv[a], err.message);
            return 1;
        }
        sk_edge_deletion_stats st;
        clock_t c0 = clock();
        double w0 = sk_seconds();
        sk_status s = sk_edge_deletion(m, &out, NULL, &st, &err);
        double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC, wall = sk_seconds() - w0;
        if (s != SK_OK) {
            printf("%s failed: %s\n", argv[a], err.message);
        } else {
            printf("%s even %zu bound %zu deleted %zu ratio %.3f adjacent_pairs %zu augmenting %zu "
                   "pairs %zu boundary_paths %zu rounds %zu path_edges %zu reductions %zu shared %zu "
                   "fixes %zu forced %zu cpu_s %.4f wall_s %.4f\n",
                   argv[a], st.even_vertices, st.lower_bound, st.deleted_edges,
                   st.lower_bound ? (double)st.deleted_edges / (double)st.lower_bound : 1.0,
                   st.adjacent_pairs, st.augmenting_paths, st.pairs, st.boundary_paths,
                   st.initialise_rounds, st.path_edges, st.reductions, st.shared_edges,
                   st.triangle_fixes, st.forced_edges, cpu, wall);
        }
        sk_mesh_destroy(&out);
        sk_mesh_destroy(&m);
    }
    return 0;
}
