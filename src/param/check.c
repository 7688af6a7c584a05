/* Input check for disk parametrizations: says what the mesh is when it is not a disk. */
#include "surfkit/param.h"
#include "core/internal.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *sk_param_method_name(sk_param_method m)
{
    switch (m) {
    case SK_PARAM_DEFAULT: return "floater";
    case SK_PARAM_TUTTE: return "tutte";
    case SK_PARAM_FLOATER: return "floater";
    case SK_PARAM_MEAN_VALUE: return "mvc";
    case SK_PARAM_HARMONIC: return "harmonic";
    case SK_PARAM_LSCM: return "lscm";
    case SK_PARAM_MIPS: return "mips";
    }
    return "unknown";
}

bool sk_param_method_parse(const char *name, sk_param_method *m)
{
    static const struct { const char *name; sk_param_method m; } names[] = {
        {"tutte", SK_PARAM_TUTTE},        {"barycentric", SK_PARAM_TUTTE},
        {"floater", SK_PARAM_FLOATER},    {"shape-preserving", SK_PARAM_FLOATER},
        {"mvc", SK_PARAM_MEAN_VALUE},     {"mean-value", SK_PARAM_MEAN_VALUE},
        {"harmonic", SK_PARAM_HARMONIC},  {"cotangent", SK_PARAM_HARMONIC},
        {"lscm", SK_PARAM_LSCM},          {"mips", SK_PARAM_MIPS},
    };
    for (size_t i = 0; name && i < sizeof names / sizeof names[0]; ++i)
        if (!strcmp(name, names[i].name)) {
            *m = names[i].m;
            return true;
        }
    return false;
}

static const char *const boundary_names[] = {"default", "circle", "square", "free", "given"};

const char *sk_boundary_shape_name(sk_boundary_shape shape)
{
    return (unsigned)shape < sizeof boundary_names / sizeof boundary_names[0]
               ? boundary_names[shape] : "unknown";
}

bool sk_boundary_shape_parse(const char *name, sk_boundary_shape *shape)
{
    for (size_t i = 1; name && i < sizeof boundary_names / sizeof boundary_names[0]; ++i)
        if (!strcmp(name, boundary_names[i])) {
            *shape = (sk_boundary_shape)i;
            return true;
        }
    return false;
}

/* Twice the area below SK_DEGENERATE_REL * (longest edge)^2 counts as degenerate (as in
 * sk_soup_validate). */
static bool face_degenerate(const sk_mesh *m, uint32_t f)
{
    double n[3];
    double twice_area = sk_mesh_face_normal(m, f, n);
    uint32_t h = m->f_halfedge[f];
    double lmax = 0;
    for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
        double l = sk_mesh_edge_length(m, sk_edge(h));
        if (l > lmax)
            lmax = l;
    }
    return !(twice_area > SK_DEGENERATE_REL * lmax * lmax);
}

sk_status sk_param_check_disk(const sk_mesh *m, sk_error *err)
{
    size_t alive = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        alive++;
        size_t k = sk_mesh_face_size(m, (uint32_t)f);
        if (k != 3)
            return sk__fail(err, SK_ERR_TOPOLOGY, "face %zu has %zu vertices: parametrization "
                            "needs a triangle mesh (triangulate it first)", f, k);
    }
    if (alive == 0)
        return sk__fail(err, SK_ERR_TOPOLOGY, "the mesh has no faces");
    for (size_t v = 0; v < m->num_vertices; ++v) {
        if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        const double *p = m->positions + 3 * v;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return sk__fail(err, SK_ERR_TOPOLOGY, "vertex %zu has a NaN or infinite coordinate",
                            v);
    }
    sk_status st = sk_mesh_check_scale(m, err);
    if (st)
        return st;
    sk_topology top;
    st = sk_mesh_topology(m, &top, NULL, err);
    if (st)
        return st;
    if (top.components != 1)
        return sk__fail(err, SK_ERR_TOPOLOGY, "the mesh has %zu components: a disk "
                        "parametrization needs one (split it and parametrize each)",
                        top.components);
    if (top.boundary_loops == 0) {
        if (top.euler_characteristic == 2)
            return sk__fail(err, SK_ERR_TOPOLOGY, "closed surface of genus 0 (a sphere): cut it "
                            "open to a disk first");
        return sk__fail(err, SK_ERR_TOPOLOGY, "closed surface of genus %ld: cut it to a disk "
                        "first", (2 - top.euler_characteristic) / 2);
    }
    if (top.boundary_loops != 1 || top.euler_characteristic != 1) {
        long twice_genus = 2 - top.euler_characteristic - (long)top.boundary_loops;
        if (twice_genus >= 0 && twice_genus % 2 == 0)
            return sk__fail(err, SK_ERR_TOPOLOGY, "surface of genus %ld with %zu boundary loops "
                            "(Euler characteristic %ld), not a disk: cut it to a disk first",
                            twice_genus / 2, top.boundary_loops, top.euler_characteristic);
        return sk__fail(err, SK_ERR_TOPOLOGY, "surface with %zu boundary loops and Euler "
                        "characteristic %ld, not a disk: cut it to a disk first",
                        top.boundary_loops, top.euler_characteristic);
    }
    /* (in parallel: the count and the first such face are the same for any thread count) */
    size_t ndeg = 0;
    long first = LONG_MAX;
#if defined(SK_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(+ : ndeg) reduction(min : first) \
    if (m->num_faces > 50000)
#endif
    for (long f = 0; f < (long)m->num_faces; ++f)
        if (!m->f_deleted[f] && face_degenerate(m, (uint32_t)f)) {
            ndeg++;
            first = f < first ? f : first;
        }
    if (ndeg)
        return sk__fail(err, SK_ERR_TOPOLOGY, "the disk has %zu degenerate (zero-area) "
                        "triangles, e.g. face %ld: remove or repair them first", ndeg, first);
    return SK_OK;
}
