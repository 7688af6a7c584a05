/* Hierarchical MIPS performance (issue 5, bench/mips.sh): per mesh, the hierarchical method with
 * its default schedule (table of levels), a flat run from a harmonic start (how libigl's SLIM was
 * measured on lion-head: 200 iterations, 23 s, MIPS sum 33474.8), a converged reference (the
 * hierarchical result polished with many global steps), and CGAL 5.5's ARAP and discrete
 * conformal parametrizers run as a peer process on the same file. Every uv is judged by
 * sk_param_metrics_compute (MIPS sum, flips, boundary self-intersections).
 *   bench_mips [--peer CGAL_MIPS_BIN] [--peer-timeout S] [--scratch DIR] MESH.off...
 * Free boundary everywhere except the discrete conformal map (circle) and the harmonic start. */
#define _POSIX_C_SOURCE 200809L
#include "surfkit/surfkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct row {
    const char *method;
    double seconds;
    sk_param_metrics m;
    bool ok;
    char note[96];
} row;

static void judge(const sk_mesh *mesh, const double *uv, row *r)
{
    sk_error err;
    if (sk_param_metrics_compute(mesh, uv, &r->m, &err)) {
        snprintf(r->note, sizeof r->note, "metrics: %.80s", err.message);
        r->ok = false;
        return;
    }
    r->ok = true;
}

static void run_peer(const char *peer, int timeout, const char *mesh_path, const char *method,
                     const char *scratch, const sk_mesh *mesh, row *r)
{
    char out[4096], cmd[8192];
    snprintf(out, sizeof out, "%s/peer-%s.bin", scratch, method);
    remove(out);
    snprintf(cmd, sizeof cmd, "timeout %d '%s' '%s' %s '%s' 2>&1", timeout, peer, mesh_path,
             method, out);
    r->method = method;
    r->ok = false;
    FILE *p = popen(cmd, "r");
    if (!p) {
        snprintf(r->note, sizeof r->note, "cannot run the peer");
        return;
    }
    char line[256] = "";
    double secs = NAN;
    while (fgets(line, sizeof line, p))
        if (sscanf(line, "%lf", &secs) != 1)
            snprintf(r->note, sizeof r->note, "%.80s", line);
    int rc = pclose(p);
    if (rc != 0 || !isfinite(secs)) {
        if (!r->note[0] || rc == 124 * 256)
            snprintf(r->note, sizeof r->note, rc == 124 * 256 ? "timeout (%d s)" : "failed (%d)",
                     rc == 124 * 256 ? timeout : rc);
        return;
    }
    size_t nv = mesh->num_vertices;
    double *uv = malloc(2 * nv * sizeof(double));
    FILE *f = fopen(out, "rb");
    size_t got = f ? fread(uv, sizeof(double), 2 * nv, f) : 0;
    if (f)
        fclose(f);
    remove(out);
    if (got != 2 * nv) {
        snprintf(r->note, sizeof r->note, "uv file has %zu of %zu values", got, 2 * nv);
        free(uv);
        return;
    }
    r->seconds = secs;
    judge(mesh, uv, r);
    free(uv);
}

static void print_levels(const sk_hparam_stats *s)
{
    printf("| level | vertices | faces | local steps | sweeps | global steps | repaired | energy | "
           "per triangle | seconds |\n|---|---|---|---|---|---|---|---|---|---|\n");
    size_t small = 0, small_steps = 0;
    double small_secs = 0;
    for (size_t l = 0; l < s->num_levels; ++l) {
        const sk_hparam_level *v = &s->levels[l];
        if (v->vertices < 2000) {
            small++;
            small_steps += v->steps;
            small_secs += v->seconds;
            continue;
        }
        if (small) {
            printf("| 0-%zu | < 2000 | | %zu | | | | | | %.3f |\n", small - 1, small_steps,
                   small_secs);
            small = 0;
        }
        if (isnan(v->energy))
            printf("| %zu | %zu | %zu | - | - | - | %zu | (insertion only) | | %.3f |\n", l,
                   v->vertices, v->faces, v->repaired, v->seconds);
        else
            printf("| %zu | %zu | %zu | %zu | %zu | %zu | %zu | %.4f | %.6f | %.3f |\n", l,
                   v->vertices, v->faces, v->steps, v->sweeps, v->global_steps, v->repaired,
                   v->energy, v->energy / (double)v->faces, v->seconds);
    }
    size_t g = 0;
    for (size_t l = 0; l < s->num_levels; ++l)
        g += s->levels[l].global_steps;
    printf("| total | | | %zu | | %zu | %zu | %.4f | | %.3f (hierarchy %.3f) |\n\n", s->steps, g,
           s->repaired, s->energy, s->total_seconds, s->hierarchy_seconds);
}

int main(int argc, char **argv)
{
    const char *peer = NULL, *scratch = "/tmp";
    int timeout = 600, first = 1;
    while (first < argc && argv[first][0] == '-') {
        if (!strcmp(argv[first], "--peer") && first + 1 < argc)
            peer = argv[++first];
        else if (!strcmp(argv[first], "--peer-timeout") && first + 1 < argc)
            timeout = atoi(argv[++first]);
        else if (!strcmp(argv[first], "--scratch") && first + 1 < argc)
            scratch = argv[++first];
        first++;
    }
    if (first >= argc) {
        fprintf(stderr, "usage: bench_mips [--peer CGAL_MIPS] [--peer-timeout S] [--scratch DIR] "
                        "MESH.off...\n");
        return 2;
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* tables appear as they are measured */
    int rc = 0;
    for (int i = first; i < argc; ++i) {
        sk_error err;
        sk_mesh *m = NULL;
        if (sk_mesh_read(argv[i], NULL, &m, &err)) {
            fprintf(stderr, "bench_mips: %s\n", err.message);
            return 1;
        }
        const char *name = strrchr(argv[i], '/') ? strrchr(argv[i], '/') + 1 : argv[i];
        size_t nv = m->num_vertices, nf = m->num_faces;
        printf("## %s: %zu vertices, %zu triangles\n\n", name, nv, nf);
        double *uv = malloc(2 * nv * sizeof(double)), *ref = malloc(2 * nv * sizeof(double));
        row rows[6];
        int nrows = 0;
        memset(rows, 0, sizeof rows);

        /* the hierarchical method, default schedule, free boundary */
        sk_hparam_opts ho = {.seed = 1};
        sk_hparam_stats hs;
        double t0 = sk_seconds();
        if (sk_param_hierarchical(m, &ho, uv, &hs, &err)) {
            fprintf(stderr, "bench_mips: %s: %s\n", name, err.message);
            return 1;
        }
        row *h = &rows[nrows++];
        h->method = "surfkit hierarchical MIPS";
        h->seconds = sk_seconds() - t0;
        judge(m, uv, h);
        print_levels(&hs);
        sk_hparam_stats_release(&hs);

        /* converged reference: the same result polished by global steps (one factorization,
         * many solves) and local sweeps until the energy stops moving */
        memcpy(ref, uv, 2 * nv * sizeof(double));
        sk_mips_opts co = {.global_steps = nv > 100000 ? 6 : 40, .sweeps_per_global = 4,
                           .max_sweeps = nv > 100000 ? 40 : 400, .tolerance = 1e-12, .seed = 3,
                           .frozen_model = nv > 100000}; /* (a 1M factorization takes ~40 s) */
        sk_mips_stats cs;
        t0 = sk_seconds();
        sk_status st = sk_param_mips(m, &co, ref, &cs, &err);
        double conv_secs = sk_seconds() - t0;
        if (st) {
            fprintf(stderr, "bench_mips: %s: converged run: %s\n", name, err.message);
            return 1;
        }
        row *c = &rows[nrows++];
        c->method = "converged reference";
        c->seconds = conv_secs + h->seconds;
        judge(m, ref, c);
        snprintf(c->note, sizeof c->note, "%zu global steps, %zu sweeps after the above",
                 cs.global_steps, cs.sweeps);
        double best = c->m.mips_sum;

        /* flat: harmonic start (circle), then MIPS with global steps (as SLIM was measured) */
        if (nv <= 100000) {
            sk_param_opts po = {0};
            po.method = SK_PARAM_HARMONIC;
            po.boundary.shape = SK_BOUNDARY_CIRCLE;
            row *f = &rows[nrows++];
            f->method = "surfkit flat MIPS, harmonic start";
            t0 = sk_seconds();
            st = sk_param_linear(m, &po, uv, NULL, &err);
            sk_mips_opts fo = {.global_steps = 8, .sweeps_per_global = 2, .max_sweeps = 16,
                               .tolerance = -1, .seed = 1};
            sk_mips_stats fs;
            if (st == SK_OK)
                st = sk_param_mips(m, &fo, uv, &fs, &err);
            f->seconds = sk_seconds() - t0;
            if (st) {
                snprintf(f->note, sizeof f->note, "%.90s", err.message);
            } else {
                judge(m, uv, f);
                snprintf(f->note, sizeof f->note, "%zu global steps, %zu sweeps", fs.global_steps,
                         fs.sweeps);
            }
        }
        if (peer) {
            run_peer(peer, timeout, argv[i], "arap", scratch, m, &rows[nrows]);
            rows[nrows++].method = "CGAL ARAP (free border)";
            run_peer(peer, timeout, argv[i], "dcm", scratch, m, &rows[nrows]);
            rows[nrows++].method = "CGAL discrete conformal (circle)";
        }
        printf("| method | seconds | MIPS sum | per triangle | excess over converged | flips | "
               "boundary self-intersections | note |\n|---|---|---|---|---|---|---|---|\n");
        for (int k = 0; k < nrows; ++k) {
            row *r = &rows[k];
            if (!r->ok) {
                printf("| %s | %s | | | | | | %s |\n", r->method, r->seconds > 0 ? "" : "-",
                       r->note);
                continue;
            }
            printf("| %s | %.3f | %.4f | %.6f | %.4f%% | %zu | %zu | %s |\n", r->method, r->seconds,
                   r->m.mips_sum, r->m.mips_sum / (double)nf,
                   100.0 * (r->m.mips_sum - best) / best, r->m.flipped,
                   r->m.boundary_self_intersections, r->note);
        }
        printf("\n");
        if (h->ok && (h->m.flipped || (h->m.mips_sum - best) > 1e-3 * best))
            rc = 1;
        free(uv);
        free(ref);
        sk_mesh_destroy(&m);
    }
    printf("libigl SLIM on lion-head (measured earlier, harmonic start): 200 iterations, 23 s, "
           "MIPS sum 33474.8, no flips\n");
    return rc;
}
