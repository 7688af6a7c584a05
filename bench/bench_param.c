/* Benchmark of the linear parametrizations: per method, the time split (check, boundary, weights
 * and assembly, analyse, factor, solve), MIPS sum and mean, flips.
 *
 *   bench_param MESH [METHOD...]     one row per method (default: all five, circle boundary)
 *   bench_param --uv MESH UV.bin     metrics of a peer's result (raw doubles u v per vertex)
 */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *base(const char *p)
{
    const char *s = strrchr(p, '/');
    return s ? s + 1 : p;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_param MESH [METHOD...] | bench_param --uv MESH UV.bin\n");
        return 2;
    }
    sk_error err;
    sk_mesh *m = NULL;
    bool uvmode = !strcmp(argv[1], "--uv");
    const char *path = uvmode ? argv[2] : argv[1];
    double t0 = sk_seconds();
    if (sk_mesh_read(path, NULL, &m, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    double tread = sk_seconds() - t0;
    size_t nv = m->num_vertices;
    double *uv = calloc(2 * nv, sizeof *uv);
    sk_param_metrics r;
    if (uvmode) {
        FILE *fp = fopen(argv[3], "rb");
        if (!fp || fread(uv, sizeof(double), 2 * nv, fp) != 2 * nv) {
            fprintf(stderr, "cannot read %s\n", argv[3]);
            return 1;
        }
        fclose(fp);
        if (sk_param_metrics_compute(m, uv, &r, &err)) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        printf("%.10f %.10f %zu\n", r.mips_sum, r.mips_mean, r.flipped);
        return 0;
    }
    const char *all[] = {"tutte", "floater", "mvc", "harmonic", "lscm"};
    int nm = argc > 2 ? argc - 2 : 5;
    fprintf(stderr, "# %s read in %.3f s\n", base(path), tread);
    for (int k = 0; k < nm; ++k) {
        const char *name = argc > 2 ? argv[2 + k] : all[k];
        sk_param_opts o = {0};
        if (!sk_param_method_parse(name, &o.method)) {
            fprintf(stderr, "unknown method %s\n", name);
            return 2;
        }
        sk_param_stats st;
        if (sk_param_linear(m, &o, uv, &st, &err)) {
            fprintf(stderr, "%s %s: %s\n", base(path), name, err.message);
            return 1;
        }
        sk_param_metrics_compute(m, uv, &r, NULL);
        /* mesh faces method check boundary weights analyse factor solve total mips_sum mips_mean flips factor_nnz */
        printf("%s %zu surfkit-%s %.3f %.3f %.3f %.3f %.3f %.3f %.3f %.6f %.6f %zu %zu\n", base(path),
               r.faces, sk_param_method_name(o.method), st.check_seconds, st.boundary_seconds,
               st.weights_seconds, st.solve.analyse_seconds, st.solve.factor_seconds,
               st.solve.solve_seconds, st.total_seconds, r.mips_sum, r.mips_mean, r.flipped,
               st.solve.factor_nnz);
        fflush(stdout);
    }
    free(uv);
    sk_mesh_destroy(&m);
    return 0;
}
