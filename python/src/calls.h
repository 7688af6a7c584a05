/* Every call the Python module makes into libsurfkit, in one place: plain C over plain arrays, no
 * Python API here, so module.c can run these with the GIL released. When the library's entry
 * points change (one sk_parametrize, the patch set), only calls.c changes. */
#ifndef SKPY_CALLS_H
#define SKPY_CALLS_H

#include <surfkit/surfkit.h>

/* A mesh as flat arrays (borrowed or malloc'ed, as said at each use). */
typedef struct skpy_mesh {
    size_t nv, nf;
    double *positions;  /* 3 * nv */
    double *normals;    /* 3 * nv or NULL */
    double *uvs;        /* 2 * nv or NULL */
    uint32_t *offsets;  /* nf + 1 */
    uint32_t *indices;  /* offsets[nf] */
} skpy_mesh;

void skpy_mesh_free(skpy_mesh *m);

/* sk_mesh_read, then the mesh as arrays (malloc'ed into *out; skpy_mesh_free). */
sk_status skpy_read(const char *path, skpy_mesh *out, sk_error *err);

/* sk_mesh_write of the (borrowed) arrays; format from the extension. */
sk_status skpy_write(const char *path, const skpy_mesh *m, sk_error *err);

typedef struct skpy_info {
    sk_topology top;
    size_t triangles, quads, larger;
    size_t boundary_edges;
} skpy_info;

sk_status skpy_info_compute(const skpy_mesh *m, skpy_info *info, sk_error *err);

/* Parametrization of a disk into uv (2 * nv, caller's). method: tutte, floater, mvc, harmonic,
 * lscm, mips (hierarchical) or mips-flat; boundary: circle, square, free or NULL (the CLI's
 * default: free for lscm and mips, else circle); seed and steps as the CLI's --seed, --steps. */
typedef struct skpy_param_args {
    const char *method, *boundary;
    uint64_t seed;
    size_t steps;
} skpy_param_args;

sk_status skpy_parametrize(const skpy_mesh *m, const skpy_param_args *args, double *uv,
                           sk_param_metrics *metrics, sk_error *err);

/* The smooth surface as arrays (malloc'ed; skpy_surface_free). */
typedef struct skpy_surface {
    size_t num_patches, num_points;
    double *points;      /* 3 * num_points */
    uint8_t *kind;       /* 3 triangle, 4 quad */
    uint8_t *degree;
    uint32_t *first;     /* first control point of each patch */
    uint32_t *corners;   /* 4 per patch, SK_INVALID for a triangle's fourth */
    size_t num_deleted;
    uint32_t *deleted;   /* 2 per deleted edge */
    size_t num_problems;
    uint32_t *problems;
    sk_continuity_report report;
    sk_smooth_stats stats;
} skpy_surface;

typedef struct skpy_smooth_args {
    const char *scheme; /* vc1 (NULL) or pn */
    int estimate_normals, allow_split;
} skpy_smooth_args;

sk_status skpy_smooth(const skpy_mesh *m, const skpy_smooth_args *args, skpy_surface *out,
                      sk_error *err);
void skpy_surface_free(skpy_surface *s);

/* Writes a surface given as arrays (kind/degree/first/corners per patch, points) by the path's
 * extension: .step/.stp (STEP), .igs/.iges (IGES), .obj/.ply/.off/.stl (the watertight
 * tessellation, tess segments per patch side). */
sk_status skpy_write_surface(const char *path, const skpy_surface *s, unsigned tess,
                             sk_error *err);

#endif
