/* Texture atlases of any manifold triangle mesh: automatic charts (every one a topological disk),
 * a flip-free, overlap-free hierarchical MIPS parametrization of each chart with a free boundary,
 * and a packing of all charts into [0,1]^2 with one uniform scale.
 *
 * Charts (src/atlas/charts.c): start from the edge-connected components; a chart that is not a
 * disk (closed, holed, with handles), whose parametrization overlaps itself, or whose distortion
 * exceeds a bound, or whose normals spread too far, is bisected: two seeds far apart (the face
 * farthest in space from an arbitrary one, then the farthest from that by a Dijkstra over face
 * centroids), every face goes to the nearer seed, so both halves stay edge-connected. Each disk
 * chart is laid out by LSCM, kept when flip-free, overlap-free and within both bounds, else by
 * the hierarchical MIPS; the disks of one round are parametrized in parallel.
 * A vertex where a chart's faces form several fans gets one uv per fan (wedges). Recursion ends at
 * the latest with single triangles, which are disks and never overlap.
 *
 * The result is per corner: a uv vertex ("wedge") per fan of a chart around a mesh vertex, shared
 * by the corners of that fan; corner_uv[h] is the uv vertex of the corner at sk_from(h) in face
 * sk_face(h) (the corner order of every face is its half-edge order from f_halfedge).
 */
#ifndef SURFKIT_ATLAS_H
#define SURFKIT_ATLAS_H

#include "surfkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_atlas_opts {
    /* Per-chart bounds; a chart above either is split (a single triangle never; below 8
     * triangles only for the angle bound). max_distortion: 3D-area-weighted mean of
     * sigma1/sigma2 over the chart; 0 = 1.05. max_stretch: exp of the 3D-area-weighted mean
     * |log(area scale / chart's mean area scale)|, i.e. how far a triangle's area scale
     * typically is from its chart's; 0 = 1.15. Tight, because the merging (merge_faces) joins
     * the pieces again where the union stays within them (bench/atlas.sh: cow MIPS mean 2.0045,
     * seams 17.1 x sqrt(area), against 2.0134 and 22.4 at 1.25 / 1.25 without merging).
     * Negative: no bound. */
    double max_distortion;
    double max_stretch;
    unsigned resolution;  /* texels per unit of the square; 0 = 1024 */
    double padding;       /* gutter between charts in texels; 0 = 2; negative = none */
    /* false (default): a chart keeps its LSCM layout when that is flip-free, overlap-free and
     * within both bounds, else it gets the hierarchical MIPS; true: hierarchical MIPS on every
     * chart. */
    bool mips_only;
    /* At most this many charts where the bounds allow: after the splitting, the cheapest
     * neighbouring charts (fewest triangles together) are merged while the union is a disk whose
     * layout is flip-free, overlap-free and within both bounds; stats.charts says whether the
     * target was met. 0 = no target. */
    unsigned max_charts;
    /* Without max_charts: after the splitting, neighbouring charts of one crease region and of
     * at most merge_faces triangles together are merged, smallest pairs first, while the union is
     * a disk whose layout is flip-free, overlap-free and within both bounds (shorter seams).
     * 0 = the default (4000). no_merge: none. */
    unsigned merge_faces;
    bool no_merge;
    /* With 2..8 charts (and at most 20000 triangles, no max_charts), a chart whose outline packs
     * badly (a bend, a deep notch) is cut in two along a straight line of its layout when that
     * packs at a higher utilization (by 1% or more; at most 2 cuts, each adding at most 10% to
     * the seams; the triangles' layouts unchanged). no_pack_cuts: never. */
    bool no_pack_cuts;
    /* Area term: every accepted chart layout is refined by MIPS with the area factor
     * (sk_mips_opts.area_theta), kept when it stays flip-free and overlap-free and lowers the
     * chart's area distortion. 0 = the default (0.5); negative = off (plain MIPS / LSCM). */
    double area_theta;
    /* Bound the area distortion, minimize the angle distortion: an accepted chart whose refined
     * layout (area_theta) is within area_bound, measured as max_stretch (exp of the 3D-area-
     * weighted mean |log(area scale / chart's mean)|), is laid out instead by the first of plain
     * MIPS and the area terms 1/8, 1/4 (below area_theta) that keeps it within area_bound,
     * flip-free and overlap-free, at a lower angle distortion; the decisions on the charts
     * (splits, merges) are those of the refined layout. 0 = the default (1.08); 1 or less (or
     * negative) = off (area_theta on every chart). */
    double area_bound;
    /* Slits (cuts from a chart's boundary into it, to its vertex of the largest MIPS excess among
     * those of positive curvature; up to 8 per chart, charts of 32..2000 triangles, after the
     * merging): a chart keeps the sequence of slits that maximizes (MIPS mean saved) -
     * slit_price * (seam_length_rel added), i.e. slit_price is what one unit of seam length /
     * sqrt(area) may cost in MIPS mean. 0 = the default (1e-3); negative = no slits. */
    double slit_price;
    /* Charts follow sharp edges: the first charts are the regions of faces joined across edges
     * whose dihedral angle (between the face normals) is below crease_angle degrees, a region
     * with less than 2% of its component's area (the scattered sharp edges of a scan) merged into
     * its neighbour; the cube gets its 6 squares. 0 = 60 (the icosahedron's 41.8 stays smooth);
     * negative = off (the components are the first charts). */
    double crease_angle;
    uint64_t seed; /* the charts' MIPS sweep orders; 0 = 1 (0 and 1 are the same; the CLI's
                      default) */
    sk_progress_fn progress;
    void *progress_user;
} sk_atlas_opts;

typedef struct sk_atlas {
    size_t num_charts;
    size_t num_uvs;        /* uv vertices (wedges) */
    double *uvs;           /* 2 * num_uvs, in [0,1]^2 */
    uint32_t *uv_chart;    /* num_uvs: chart of each uv vertex */
    uint32_t *face_chart;  /* mesh->num_faces (SK_INVALID for deleted faces) */
    uint32_t *corner_uv;   /* mesh->num_halfedges: uv vertex of the corner at sk_from(h) in face(h),
                              SK_INVALID for boundary half-edges */
    uint32_t *chart_faces; /* num_charts: triangles of each chart */
    double *chart_mips;    /* num_charts: mean MIPS energy of each chart's triangles */
} sk_atlas;

typedef struct sk_atlas_stats {
    size_t charts;
    size_t seam_edges;       /* mesh edges with different uv on the two sides (cut edges) */
    double seam_length_rel;  /* total 3D seam length / sqrt(3D area) */
    double mips_mean;        /* mean over triangles of sigma1/sigma2 + sigma2/sigma1 */
    double conformal_mean;   /* 3D-area-weighted mean of sigma1/sigma2 */
    double area_log_mean;    /* mean over triangles of |log((A_uv / sum A_uv) / (A / sum A))| */
    size_t flipped;          /* triangles with non-positive uv orientation (exact test) */
    size_t overlaps;         /* pairs of uv triangles whose interiors intersect (exact tests) */
    double utilization;      /* uv area of all charts / area of [0,1]^2 */
    double scale;            /* uv units per 3D unit (the same for every chart) */
    size_t splits_topology, splits_overlap, splits_distortion, splits_failed;
    size_t splits_predicted; /* of splits_distortion: decided by the LSCM predictor, no MIPS run */
    size_t lscm_charts;      /* charts laid out by LSCM (the others by hierarchical MIPS) */
    size_t merges;           /* pairs of charts merged for max_charts */
    size_t area_refinements; /* charts the area term refined (kept or not), final or split later */
    size_t area_bounded;     /* accepted chart layouts (final or merged later) that area_bound
                                gave a smaller area term */
    size_t crease_regions;   /* first charts: the crease regions (the components when no crease
                                cuts them) */
    size_t pack_cuts;        /* charts cut in two for a tighter packing (no_pack_cuts) */
    size_t slits;            /* slits kept (slit_price) */
    double charts_seconds, param_seconds, pack_seconds, check_seconds, total_seconds;
} sk_atlas_stats;

/* Builds an atlas of a manifold triangle mesh (any number of components, boundaries, genus).
 * Fails with SK_ERR_TOPOLOGY on non-triangle faces, deleted elements (compact first) and
 * degenerate (zero-area) triangles, naming the first. stats may be NULL. */
SK_API sk_status sk_atlas_build(const sk_mesh *mesh, const sk_atlas_opts *opts, sk_atlas **out,
                                sk_atlas_stats *stats, sk_error *err);
SK_API void sk_atlas_destroy(sk_atlas **atlas);

/* Counts pairs of triangles whose interiors intersect, triangles given as 6 doubles each
 * (u0 v0 u1 v1 u2 v2, any orientation; zero-area triangles have no interior). Grid buckets over
 * the bounding boxes, then an exact separating-axis test with sk_orient2d. If first is not NULL
 * it receives the first overlapping pair found (or SK_INVALID). */
SK_API sk_status sk_uv_overlaps(size_t num_triangles, const double *tri_uv, size_t *count,
                                uint32_t first[2], sk_error *err);

/* The atlas as a mesh split along the seams: one vertex per uv vertex (position copied, uvs set),
 * faces in the mesh's face order; for writers and readers that know only per-vertex uv (Blender's
 * PLY importer), and for the pictures (chart borders are its boundary). */
SK_API sk_status sk_atlas_split_mesh(const sk_mesh *mesh, const sk_atlas *atlas, sk_mesh **out,
                                     sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
