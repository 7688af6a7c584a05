/* Closest-point queries for bench/deviation.sh: sk_bvh build and queries of every vertex of
 * QUERY and the centroid of each of its faces against SURFACE, single-threaded (as the CGAL
 * peer) and with the library's OpenMP loop (sk_deviation's), then the whole sk_deviation.
 * Prints "surfkit_bvh build_s query_s queries max_distance sum_distance" and a deviation row.
 *   bench_deviation SURFACE QUERY */
#include "surfkit/surfkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: bench_deviation SURFACE QUERY\n");
        return 2;
    }
    sk_error err;
    sk_soup *s = NULL, *q = NULL;
    if (sk_soup_read(argv[1], NULL, &s, &err) || sk_soup_read(argv[2], NULL, &q, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    size_t nq = q->num_vertices + q->num_faces;
    double *pts = malloc(3 * nq * sizeof *pts);
    if (!pts)
        return 3;
    for (size_t v = 0; v < q->num_vertices; ++v)
        for (int k = 0; k < 3; ++k)
            pts[3 * v + k] = q->positions[3 * v + k];
    for (size_t f = 0; f < q->num_faces; ++f) {
        size_t n = sk_soup_face_size(q, f);
        double *c = pts + 3 * (q->num_vertices + f);
        c[0] = c[1] = c[2] = 0;
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k)
                c[k] += q->positions[3 * (size_t)q->face_indices[q->face_offsets[f] + i] + k] / (double)n;
    }
    double t0 = sk_seconds();
    sk_bvh *bvh = NULL;
    if (sk_bvh_build(s, &bvh, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    double t1 = sk_seconds(), mx = 0, sum = 0;
    for (size_t i = 0; i < nq; ++i) {
        sk_closest c;
        sk_bvh_closest(bvh, pts + 3 * i, &c);
        mx = fmax(mx, c.distance);
        sum += c.distance;
    }
    double t2 = sk_seconds();
    printf("surfkit_bvh %.3f %.3f %zu %.17g %.17g\n", t1 - t0, t2 - t1, nq, mx, sum);
    sk_deviation_report r;
    sk_deviation_opts o = {0};
    if (sk_deviation(s, q, &o, &r, NULL, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    printf("surfkit_deviation %.3f %zu %.17g\n", r.seconds,
           r.mesh_to_surface.samples + r.surface_to_mesh.samples, r.hausdorff);
    sk_bvh_destroy(&bvh);
    free(pts);
    sk_soup_destroy(&s);
    sk_soup_destroy(&q);
    return 0;
}
