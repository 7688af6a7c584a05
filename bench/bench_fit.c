/* B-spline fits of disks for bench/approx.sh: per mesh the rounds, control points, parametric
 * max / rms error, the two-sided deviation of the 128 x 128 tessellation, seconds.
 *   bench_fit TOL_REL SMOOTHING MESH... */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_fit TOL_REL SMOOTHING MESH...\n");
        return 2;
    }
    double rel = atof(argv[1]), smooth = atof(argv[2]);
    printf("| mesh | vertices | met | rounds | control points | max | rms | tol | mesh->surface | surface->mesh | flips | s |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int a = 3; a < argc; ++a) {
        sk_error err;
        sk_mesh *m = NULL;
        if (sk_mesh_read(argv[a], NULL, &m, &err)) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        sk_soup *ms = NULL, *tess = NULL;
        sk_mesh_to_soup(m, &ms, NULL);
        double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
        for (size_t v = 0; v < m->num_vertices; ++v)
            for (int k = 0; k < 3; ++k) {
                double x = m->positions[3 * v + k];
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
        double d = 0;
        for (int k = 0; k < 3; ++k)
            d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
        sk_fit_opts o = {.tolerance = rel * sqrt(d), .smoothing = smooth};
        sk_fit_stats st;
        sk_bspline_surface *s = NULL;
        double t0 = sk_seconds();
        if (sk_fit_bspline(m, &o, &s, &st, &err)) {
            printf("| %s | fit failed: %s |\n", argv[a], err.message);
            continue;
        }
        double t1 = sk_seconds();
        sk_bspline_tessellate(s, 128, &tess, NULL);
        sk_deviation_report r;
        sk_deviation(tess, ms, NULL, &r, NULL, NULL);
        const char *name = argv[a];
        for (const char *c = argv[a]; *c; ++c)
            if (*c == '/')
                name = c + 1;
        printf("| %s | %zu | %s | %zu | %zu (%zu x %zu) | %.3g | %.3g | %.3g | %.3g | %.3g | %zu | %.2f |\n",
               name, m->num_vertices, st.met ? "yes" : "no", st.rounds, st.control_points, s->nu,
               s->nv, st.max_error, st.rms_error, st.tolerance, r.mesh_to_surface.max,
               r.surface_to_mesh.max, st.flipped, t1 - t0);
        fflush(stdout);
        sk_bspline_destroy(&s);
        sk_soup_destroy(&tess);
        sk_soup_destroy(&ms);
        sk_mesh_destroy(&m);
    }
    return 0;
}
