/* Vertex normals: angle-, area-weighted and mean averages of face normals, and a local quadratic
 * fit. See include/surfkit/analysis.h and Xu, Xu, Sun (Mathematics of Surfaces XI) for when each
 * converges at O(h^2). */
#include "surfkit/analysis.h"
#include "core/internal.h"
#include "core/vec.h"

#include <lapacke.h>
#include <math.h>
#include <string.h>

int sk_normal_method_from_name(const char *name)
{
    static const char *names[] = {"angle", "area", "mean", "quadric"};
    for (int i = 0; i < 4; ++i)
        if (name && !strcmp(name, names[i]))
            return i;
    return -1;
}

const char *sk_normal_method_name(sk_normal_method method)
{
    switch (method) {
    case SK_NORMALS_ANGLE: return "angle";
    case SK_NORMALS_AREA: return "area";
    case SK_NORMALS_MEAN: return "mean";
    case SK_NORMALS_QUADRIC: return "quadric";
    }
    return "unknown";
}

/* Weighted sum of the face-corner normals around v (eq. (3) of Xu, Xu, Sun: sum lambda_i n_i). */
static void average_normal(const sk_mesh *m, uint32_t v, sk_normal_method method, double n[3])
{
    const double *p = m->positions + 3 * (size_t)v;
    n[0] = n[1] = n[2] = 0.0;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    if (h0 == SK_INVALID)
        return;
    do {
        if (m->h_face[h] != SK_INVALID) {
            double e1[3], e2[3], c[3];
            sk__sub3(e1, m->positions + 3 * (size_t)sk_to(m, h), p);
            sk__sub3(e2, m->positions + 3 * (size_t)sk_from(m, m->h_prev[h]), p);
            sk__cross3(c, e1, e2);
            double len = sk__norm3(c), w;
            if (len > 0.0) {
                switch (method) {
                case SK_NORMALS_AREA: w = 1.0; break; /* |c| = twice the area */
                case SK_NORMALS_MEAN: w = 1.0 / len; break;
                default: w = sk__angle3(e1, e2) / len; break;
                }
                sk__axpy3(n, n, w, c);
            }
        }
        h = sk_cw_out(m, h);
    } while (h != h0);
}

/* Solves the small dense symmetric system A x = b (n <= 8) with LAPACK's LU with partial
 * pivoting; returns 0 when singular relative to the largest entry (a pivot below 1e-13 of it).
 * A is symmetric, so it is its own column-major form: the column-major call allocates nothing
 * (LAPACKE's row-major path mallocs transposed copies and reports a failed malloc as info
 * -1011, which would have been taken for "singular" here), so 0 always means singular. */
static int solve_small(int n, double *A, double *b)
{
    double scale = 0.0;
    for (int i = 0; i < n * n; ++i)
        scale = fmax(scale, fabs(A[i]));
    lapack_int ipiv[8];
    if (scale == 0.0 || n > 8 || LAPACKE_dgesv_work(LAPACK_COL_MAJOR, n, 1, A, n, ipiv, b, n) != 0)
        return 0;
    for (int k = 0; k < n; ++k) /* A now holds L\U: the pivots are U's diagonal */
        if (fabs(A[k * n + k]) < 1e-13 * scale)
            return 0;
    return 1;
}

#define QUADRIC_MAX_NB 64

/* Collects the 1-ring (and the 2-ring when the 1-ring has fewer than 5 vertices). */
static int quadric_neighbours(const sk_mesh *m, uint32_t v, uint32_t *nb)
{
    int count = 0;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        if (count < QUADRIC_MAX_NB)
            nb[count++] = sk_to(m, h);
        h = sk_cw_out(m, h);
    } while (h != h0);
    if (count >= 5)
        return count;
    int ring1 = count;
    for (int i = 0; i < ring1; ++i) {
        uint32_t g0 = m->v_halfedge[nb[i]], g = g0;
        do {
            uint32_t w = sk_to(m, g);
            int seen = (w == v);
            for (int j = 0; j < count && !seen; ++j)
                seen = (nb[j] == w);
            if (!seen && count < QUADRIC_MAX_NB)
                nb[count++] = w;
            g = sk_cw_out(m, g);
        } while (g != g0);
    }
    return count;
}

/* Local quadratic fit z = a x^2 + b xy + c y^2 + d x + e y through the vertex, in the frame of the
 * angle-weighted normal; the normal is (-d, -e, 1) in that frame. */
static void quadric_normal(const sk_mesh *m, uint32_t v, double n[3])
{
    average_normal(m, v, SK_NORMALS_ANGLE, n);
    if (sk__normalize3(n) == 0.0)
        return;
    double e1[3], e2[3], a[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.6)
        a[0] = 0, a[1] = 1;
    sk__cross3(e1, n, a);
    sk__normalize3(e1);
    sk__cross3(e2, n, e1);
    uint32_t nb[QUADRIC_MAX_NB];
    int count = quadric_neighbours(m, v, nb);
    if (count < 5)
        return;
    const double *p = m->positions + 3 * (size_t)v;
    double A[25] = {0}, b[5] = {0}, scale = 0.0;
    for (int i = 0; i < count; ++i)
        scale += sk__dist3(m->positions + 3 * (size_t)nb[i], p);
    scale = count / scale; /* fit in units of the mean neighbour distance */
    for (int i = 0; i < count; ++i) {
        double d[3];
        sk__sub3(d, m->positions + 3 * (size_t)nb[i], p);
        double x = sk__dot3(d, e1) * scale, y = sk__dot3(d, e2) * scale, z = sk__dot3(d, n) * scale;
        double row[5] = {x * x, x * y, y * y, x, y};
        for (int r = 0; r < 5; ++r) {
            for (int c = 0; c < 5; ++c)
                A[r * 5 + c] += row[r] * row[c];
            b[r] += row[r] * z;
        }
    }
    if (!solve_small(5, A, b))
        return; /* the fit is singular (documented in analysis.h): keep the angle-weighted normal */
    double q[3];
    sk__axpy3(q, n, -b[3], e1);
    sk__axpy3(q, q, -b[4], e2);
    sk__normalize3(q);
    n[0] = q[0], n[1] = q[1], n[2] = q[2];
}

sk_status sk_mesh_vertex_normals(const sk_mesh *mesh, sk_normal_method method, double *out,
                                 sk_error *err)
{
    if (!mesh || !out)
        return sk__fail(err, SK_ERR_ARG, "sk_mesh_vertex_normals: NULL argument");
    if ((int)method < 0 || method > SK_NORMALS_QUADRIC)
        return sk__fail(err, SK_ERR_ARG, "unknown normal estimation method %d", (int)method);
    uint32_t bad = SK_INVALID;
    long nv = (long)mesh->num_vertices;
    int blas_threads = sk__blas_serial_begin(); /* one tiny dgesv per vertex */
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nv > 20000)
#endif
    for (long i = 0; i < nv; ++i) {
        uint32_t v = (uint32_t)i;
        double *n = out + 3 * (size_t)v;
        if (mesh->v_deleted[v] || mesh->v_halfedge[v] == SK_INVALID) {
            n[0] = n[1] = n[2] = 0.0;
            continue;
        }
        if (method == SK_NORMALS_QUADRIC)
            quadric_normal(mesh, v, n);
        else
            average_normal(mesh, v, method, n);
        if (sk__normalize3(n) == 0.0 || !isfinite(n[0] + n[1] + n[2])) {
            n[0] = n[1] = n[2] = 0.0;
#ifdef SK_HAVE_OPENMP
#pragma omp critical(sk_normals_bad)
#endif
            if (bad == SK_INVALID || v < bad)
                bad = v;
        }
    }
    sk__blas_serial_end(blas_threads);
    if (bad != SK_INVALID)
        return sk__fail(err, SK_ERR_NUMERIC,
                        "vertex %u: the faces around it cancel out, no normal can be estimated",
                        bad);
    sk__ok(err);
    return SK_OK;
}
