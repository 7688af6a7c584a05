/* bench_export MESH OUT_DIR [REPEATS]: VC1 surface of a mesh (not timed), then the STEP and IGES
 * writers alone, best of REPEATS (default 3) runs each: size, size per input triangle, seconds
 * (process CPU and wall) and MB/s (by CPU time: the machine is shared). One table row per format;
 * the files stay in OUT_DIR as MESH.step and MESH.igs. */
#define _POSIX_C_SOURCE 200809L
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_export MESH OUT_DIR [REPEATS]\n");
        return 2;
    }
    int repeats = argc > 3 ? atoi(argv[3]) : 3;
    if (repeats < 1)
        repeats = 1;
    sk_mesh *m = NULL;
    sk_smooth *s = NULL;
    sk_error err = {0};
    if (sk_mesh_read(argv[1], NULL, &m, &err) != SK_OK ||
        sk_smooth_build(m, NULL, &s, &err) != SK_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const char *base = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
    char name[256];
    snprintf(name, sizeof name, "%.*s", (int)(strcspn(base, ".")), base);
    for (int f = 0; f < 2; ++f) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s.%s", argv[2], name, f ? "igs" : "step");
        double best_cpu = 1e300, best_wall = 1e300;
        sk_export_stats es = {0};
        for (int r = 0; r < repeats; ++r) {
            double c0 = cpu_seconds(), w0 = sk_seconds();
            sk_export_opts eo = {0};
            eo.timestamp = "2026-01-01T00:00:00";
            sk_status st = f ? sk_export_iges(path, &s->surface, &eo, &es, &err)
                             : sk_export_step(path, &s->surface, &eo, &es, &err);
            double c1 = cpu_seconds(), w1 = sk_seconds();
            if (st != SK_OK) {
                fprintf(stderr, "%s\n", err.message);
                return 1;
            }
            if (c1 - c0 < best_cpu)
                best_cpu = c1 - c0;
            if (w1 - w0 < best_wall)
                best_wall = w1 - w0;
        }
        double kb = (double)es.bytes / 1000.0;
        printf("| %-10s | %-4s | %9zu | %7zu | %10.1f | %6.2f | %7.3f | %7.3f | %6.1f |\n", name,
               f ? "igs" : "step", m->num_faces, es.faces, kb, kb / (double)m->num_faces,
               best_cpu, best_wall, (double)es.bytes / 1e6 / best_cpu);
    }
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&m);
    return 0;
}
