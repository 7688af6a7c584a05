/* Benchmark of the direct solvers' fill-reducing orderings on a parametrization system: the
 * fixed-boundary system of METHOD (circle boundary) on MESH, assembled as sk_param_linear does
 * (interior unknowns, boundary in the right-hand side), factored with each ordering.
 *
 *   bench_solve MESH METHOD [ORDERING...]   orderings: default auto amd metis nesdis best
 *   one row per ordering: mesh method solver ordering n nnz factor_nnz analyse factor solve
 *   total relative_residual
 */
#include "surfkit/surfkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *base(const char *p)
{
    const char *s = strrchr(p, '/');
    return s ? s + 1 : p;
}

static bool parse_ordering(const char *s, sk_ordering *o)
{
    const char *names[] = {"default", "auto", "amd", "metis", "nesdis", "best"};
    for (int k = 0; k < 6; ++k)
        if (!strcmp(s, names[k])) {
            *o = (sk_ordering)k;
            return true;
        }
    return false;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_solve MESH METHOD [ORDERING...]\n");
        return 2;
    }
    sk_error err;
    sk_mesh *m = NULL;
    sk_param_method method;
    if (!sk_param_method_parse(argv[2], &method) || method == SK_PARAM_LSCM) {
        fprintf(stderr, "method: tutte, floater, mvc or harmonic\n");
        return 2;
    }
    if (sk_mesh_read(argv[1], NULL, &m, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    size_t nv = m->num_vertices;
    double *uv = calloc(2 * nv, sizeof *uv), *w = calloc(m->num_halfedges, sizeof *w);
    uint32_t *idx = calloc(nv, sizeof *idx);
    sk_boundary_opts bo = {0};
    if (sk_param_boundary(m, &bo, uv, &err) || sk_param_weights(m, method, w, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    bool sym = method == SK_PARAM_TUTTE || method == SK_PARAM_HARMONIC;
    size_t n = 0;
    for (size_t v = 0; v < nv; ++v)
        idx[v] = sk_is_boundary_v(m, (uint32_t)v) ? SK_INVALID : (uint32_t)n++;
    double *rhs = calloc(2 * n, sizeof *rhs), *x = calloc(2 * n, sizeof *x),
           *ax = calloc(n, sizeof *ax);
    sk_triplets t = {0};
    for (size_t v = 0; v < nv; ++v) {
        uint32_t i = idx[v];
        if (i == SK_INVALID)
            continue;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        double diag = 0;
        do {
            uint32_t j = sk_to(m, h);
            diag += w[h];
            if (idx[j] == SK_INVALID) {
                rhs[i] += w[h] * uv[2 * (size_t)j];
                rhs[n + i] += w[h] * uv[2 * (size_t)j + 1];
            } else if (!sym || idx[j] < i) {
                sk_triplets_add(&t, i, idx[j], -w[h]);
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
        sk_triplets_add(&t, i, i, diag);
    }
    sk_sparse *a = NULL;
    if (sk_sparse_from_triplets(n, &t, sym ? SK_SPARSE_LOWER : SK_SPARSE_FULL, &a, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const char *all[] = {"auto", "amd", "metis", "nesdis"};
    int no = argc > 3 ? argc - 3 : 4;
    for (int k = 0; k < no; ++k) {
        const char *name = argc > 3 ? argv[3 + k] : all[k];
        sk_solver_opts so = {0};
        if (!parse_ordering(name, &so.ordering)) {
            fprintf(stderr, "unknown ordering %s\n", name);
            return 2;
        }
        sk_solver *s = NULL;
        sk_solver_kind kind = sym ? SK_SOLVER_CHOLESKY : SK_SOLVER_LU;
        double t0 = sk_seconds();
        if (sk_solver_create_opts(a, kind, &so, &s, &err) || sk_solver_factorize(s, a, &err) ||
            sk_solver_solve(s, 2, rhs, x, &err)) {
            fprintf(stderr, "%s %s: %s\n", argv[2], name, err.message);
            sk_solver_destroy(&s);
            continue;
        }
        double total = sk_seconds() - t0;
        sk_solve_stats ss;
        sk_solver_stats(s, &ss);
        double worst = 0;
        for (int c = 0; c < 2; ++c) {
            sk_sparse_multiply(a, x + (size_t)c * n, ax);
            double rr = 0, bb = 0;
            for (size_t i = 0; i < n; ++i) {
                double d = rhs[(size_t)c * n + i] - ax[i];
                rr += d * d;
                bb += rhs[(size_t)c * n + i] * rhs[(size_t)c * n + i];
            }
            worst = fmax(worst, sqrt(rr / bb));
        }
        printf("%s %s %s %s %zu %zu %zu %.3f %.3f %.3f %.3f %.2e\n", base(argv[1]), argv[2],
               sym ? "cholmod" : "umfpack", name, ss.n, ss.nnz, ss.factor_nnz, ss.analyse_seconds,
               ss.factor_seconds, ss.solve_seconds, total, worst);
        fflush(stdout);
        sk_solver_destroy(&s);
    }
    sk_sparse_destroy(&a);
    sk_triplets_free(&t);
    free(uv);
    free(w);
    free(idx);
    free(rhs);
    free(x);
    free(ax);
    sk_mesh_destroy(&m);
    return 0;
}
