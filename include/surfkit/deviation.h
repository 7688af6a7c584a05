/* Distances between two surfaces given as indexed faces: closest points through a bounding-volume
 * hierarchy, and the two-sided (Hausdorff) deviation of a surface from a mesh, with the figures a
 * reverse-engineering report carries (Varady & Facello; Albat & Mueller: max, mean, RMS, and a
 * histogram, in model units).
 *
 * Faces of any size are split into triangles as fans from their first corner. */
#ifndef SURFKIT_DEVIATION_H
#define SURFKIT_DEVIATION_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Closest points
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_bvh sk_bvh;

/* Builds a hierarchy of axis-aligned boxes over the triangles of soup (binned surface-area
 * heuristic, at most 4 triangles per leaf). The soup is copied: it may be freed afterwards.
 * SK_ERR_TOPOLOGY when a face index is out of range, a face has fewer than 3 corners, a coordinate is
 * not finite, or there is no face; SK_ERR_NOMEM when out of memory. */
SK_API sk_status sk_bvh_build(const sk_soup *soup, sk_bvh **out, sk_error *err);
SK_API void sk_bvh_destroy(sk_bvh **bvh);
/* Number of triangles (after fan splitting) */
SK_API size_t sk_bvh_triangles(const sk_bvh *bvh);

typedef struct sk_closest {
    double distance;  /* Euclidean distance from the query to point */
    double point[3];  /* the closest point on the surface */
    uint32_t face;    /* the soup face that holds it */
    uint32_t triangle;/* the fan triangle that holds it (index into the bvh's triangles) */
} sk_closest;

/* The point of the surface nearest to p (ties: any of the nearest). Never fails for finite p. */
SK_API void sk_bvh_closest(const sk_bvh *bvh, const double p[3], sk_closest *out);

/* Distance from p to the surface of bvh (a const sk_bvh * passed as user): the shape of
 * sk_field_fn in render.h, to colour one surface by its distance to another. */
SK_API double sk_bvh_distance(void *bvh, const double p[3]);

/* ---------------------------------------------------------------------------------------------
 * Deviation
 * ------------------------------------------------------------------------------------------- */

enum { SK_DEVIATION_BINS = 16 };

typedef struct sk_deviation_opts {
    /* samples per triangle edge: every triangle is cut into n x n congruent triangles and their
     * centroids are sampled, besides every vertex; 0 = 2 (4 samples per triangle) */
    int face_samples;
    sk_progress_fn progress; /* may be NULL; returning non-zero cancels (SK_ERR_CANCELLED) */
    void *progress_user;
    /* When not NULL, the hierarchies sk_deviation builds over the surface and over the mesh are
     * handed over here on success (the caller destroys them with sk_bvh_destroy; NULL after a
     * failure): a colour map of either side's distance to the other (sk_render_field with
     * sk_bvh_distance) then needs no second build. */
    sk_bvh **surface_bvh;
    sk_bvh **mesh_bvh;
} sk_deviation_opts;

/* Distances from the samples (vertices and face samples) of one surface to the other. */
typedef struct sk_distance_stats {
    size_t samples;
    double max, mean, rms;  /* model units */
    double max_at[3];       /* the sample with the largest distance */
    uint32_t max_face;      /* the face of the sampled surface it lies on (a face of that vertex
                               when the sample is a vertex) */
    /* histogram of the distances over [0, hausdorff] of the report in SK_DEVIATION_BINS equal
     * bins (the last bin includes its upper end) */
    size_t histogram[SK_DEVIATION_BINS];
} sk_distance_stats;

typedef struct sk_deviation_report {
    sk_distance_stats mesh_to_surface; /* from the mesh's samples to the surface */
    sk_distance_stats surface_to_mesh; /* from the surface's samples to the mesh */
    double hausdorff;                  /* max of the two maxima (the two-sided distance) */
    double diagonal;                   /* bounding-box diagonal of the mesh, for relative figures */
    double seconds;                    /* wall time of the whole computation */
} sk_deviation_report;

/* Two-sided deviation between surface and mesh (both as indexed faces: a tessellation of a smooth
 * surface and the scan it approximates, or any two meshes). vertex_distance, when not NULL, gets
 * one distance per mesh vertex (num_vertices entries; unreferenced vertices get their distance
 * too). Errors as sk_bvh_build, naming which of the two inputs is wrong. */
SK_API sk_status sk_deviation(const sk_soup *surface, const sk_soup *mesh, const sk_deviation_opts *opts,
                              sk_deviation_report *report, double *vertex_distance, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
