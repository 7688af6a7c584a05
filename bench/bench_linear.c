/* Benchmark of the linear parametrizations, direct against hierarchical solve: one method and
 * solver per process (so that the peak memory is that run's).
 *
 *   bench_linear MESH METHOD direct|hierarchical|amg [REF.bin]
 *       one row: mesh faces method solver check boundary weights analyse factor solve total
 *       levels iterations residual factor_nnz mips_mean flips peak_MB max_uv_diff
 *       With REF.bin (raw doubles u v per vertex, e.g. a direct run's) the largest |uv - ref|
 *       relative to the layout size is printed, else "-".
 *   bench_linear --write MESH METHOD direct|hierarchical OUT.bin   the same row, uv to OUT.bin
 *   env ORDERING=default|auto|amd|metis|nesdis|geometric: the direct solver's ordering
 *   (sk_param_opts.ordering: auto and nesdis are the solver's own, amd, metis and geometric
 *   on the vertex graph)
 */
#include "surfkit/surfkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

static const char *base(const char *p)
{
    const char *s = strrchr(p, '/');
    return s ? s + 1 : p;
}

int main(int argc, char **argv)
{
    bool write = argc > 1 && !strcmp(argv[1], "--write");
    int a0 = write ? 2 : 1;
    if (argc < a0 + 3 || (write && argc < a0 + 4)) {
        fprintf(stderr, "usage: bench_linear [--write] MESH METHOD direct|hierarchical|amg|auto [REF.bin|OUT.bin]\n");
        return 2;
    }
    const char *path = argv[a0], *method = argv[a0 + 1], *solver = argv[a0 + 2];
    const char *extra = argc > a0 + 3 ? argv[a0 + 3] : NULL;
    sk_error err;
    sk_mesh *m = NULL;
    if (sk_mesh_read(path, NULL, &m, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    size_t nv = m->num_vertices;
    double *uv = calloc(2 * nv, sizeof *uv);
    sk_param_opts o = {0};
    if (!sk_param_method_parse(method, &o.method)) {
        fprintf(stderr, "unknown method %s\n", method);
        return 2;
    }
    if (!strcmp(solver, "hierarchical"))
        o.solver = SK_LINEAR_HIERARCHICAL;
    else if (!strcmp(solver, "amg"))
        o.solver = SK_LINEAR_AMG;
    else if (!strcmp(solver, "auto"))
        o.solver = SK_LINEAR_AUTO;
    else if (strcmp(solver, "direct")) {
        fprintf(stderr, "unknown solver %s\n", solver);
        return 2;
    }
    /* env ORDERING: sk_param_opts.ordering */
    const char *ord = getenv("ORDERING");
    if (ord && *ord) {
        static const char *names[] = {"default", "auto", "amd", "metis", "nesdis", "geometric"};
        static const sk_ordering ords[] = {SK_ORDERING_DEFAULT, SK_ORDERING_AUTO, SK_ORDERING_AMD,
                                           SK_ORDERING_METIS, SK_ORDERING_NESDIS,
                                           SK_ORDERING_GEOMETRIC};
        size_t k = 0;
        while (k < 6 && strcmp(ord, names[k]))
            k++;
        if (k == 6) {
            fprintf(stderr, "unknown ORDERING %s\n", ord);
            return 2;
        }
        o.ordering = ords[k];
    }
    sk_param_stats st;
    if (sk_param_linear(m, &o, uv, &st, &err)) {
        fprintf(stderr, "%s %s %s: %s\n", base(path), method, solver, err.message);
        return 1;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    double peak_mb = (double)ru.ru_maxrss / 1024.0;
    sk_param_metrics r;
    sk_param_metrics_compute(m, uv, &r, NULL);
    char diff[32] = "-";
    if (write && extra) {
        FILE *fp = fopen(extra, "wb");
        if (!fp || fwrite(uv, sizeof(double), 2 * nv, fp) != 2 * nv) {
            fprintf(stderr, "cannot write %s\n", extra);
            return 1;
        }
        fclose(fp);
    } else if (extra) {
        double *ref = calloc(2 * nv, sizeof *ref);
        FILE *fp = fopen(extra, "rb");
        if (!ref || !fp || fread(ref, sizeof(double), 2 * nv, fp) != 2 * nv) {
            fprintf(stderr, "cannot read %s\n", extra);
            return 1;
        }
        fclose(fp);
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, d = 0;
        for (size_t v = 0; v < nv; ++v)
            for (int c = 0; c < 2; ++c) {
                lo[c] = fmin(lo[c], ref[2 * v + c]);
                hi[c] = fmax(hi[c], ref[2 * v + c]);
                d = fmax(d, fabs(uv[2 * v + c] - ref[2 * v + c]));
            }
        snprintf(diff, sizeof diff, "%.2e", d / fmax(hi[0] - lo[0], hi[1] - lo[1]));
        free(ref);
    }
    printf("%s %zu %s %s %.3f %.3f %.3f %.3f %.3f %.3f %.3f %zu %zu %.2e %zu %.6f %zu %.0f %s\n",
           base(path), r.faces, sk_param_method_name(o.method), solver, st.check_seconds,
           st.boundary_seconds, st.weights_seconds, st.solve.analyse_seconds,
           st.solve.factor_seconds, st.solve.solve_seconds, st.total_seconds,
           st.levels ? st.levels : 1, st.iterations, st.residual, st.solve.factor_nnz, r.mips_mean,
           r.flipped, peak_mb, diff);
    free(uv);
    sk_mesh_destroy(&m);
    return 0;
}
