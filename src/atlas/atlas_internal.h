/* Internal pieces of the atlas module (src/atlas/). */
#ifndef SK_ATLAS_INTERNAL_H
#define SK_ATLAS_INTERNAL_H

#include "surfkit/atlas.h"

#include <stdbool.h>

/* ---- charts.c ---- */

/* Scratch shared by chart extraction and bisection, sized by the mesh. */
typedef struct sk__chart_work {
    uint32_t *label;     /* per face: stamp of the chart it was last processed in */
    uint32_t *parent;    /* per half-edge: union-find of corners (wedges) */
    uint32_t *local;     /* per half-edge root: local vertex index in the chart mesh */
    uint32_t *flocal;    /* per face: local face index in the chart being bisected */
    double *dist;        /* per local face: Dijkstra distance (bisection) */
    uint32_t *heap, *heap_pos; /* per local face */
    uint8_t *side;       /* per local face */
    uint32_t *tmp;       /* per face: partition buffer */
    double *centroid;    /* 3 per face */
    double *fnormal;     /* 4 per face: the normal times the area, the area (coherence) */
    uint32_t *vcount;    /* per vertex: faces of the growing disk around it (zero between uses) */
    uint8_t *cut;        /* per mesh edge: cut inside a chart (sk__chart_cut_holes); a chart's
                          * faces are not joined across it */
} sk__chart_work;

sk_status sk__chart_work_init(sk__chart_work *w, const sk_mesh *m, sk_error *err);
void sk__chart_work_free(sk__chart_work *w);

/* Component ids of the faces (edge-connected), written to comp; returns their number. */
size_t sk__face_components(const sk_mesh *m, uint32_t *comp, uint32_t *queue);

/* The chart mesh of faces[0..nf) (all labelled `stamp` in w->label): one vertex per wedge (fan
 * of chart faces around a mesh vertex), faces in the given order. vert_h (nv entries, allocated
 * here) receives, per chart vertex, one mesh half-edge whose corner it is; corner (h) of a chart
 * face maps to chart vertex w->local[sk__wedge_find(w, h)]. */
sk_status sk__chart_extract(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                            sk__chart_work *w, sk_mesh **chart, uint32_t **vert_h, sk_error *err);
uint32_t sk__wedge_find(sk__chart_work *w, uint32_t h);

/* Splits faces[0..nf) (labelled stamp, nf >= 2, edge-connected) in two edge-connected halves:
 * reorders faces so that the first *n0 faces are one half. */
sk_status sk__chart_bisect(const sk_mesh *m, uint32_t *faces, size_t nf, uint32_t stamp,
                           sk__chart_work *w, size_t *n0, sk_error *err);

/* Grows one disk from a seed inside the non-disk chart faces[0..nf) (labelled stamp) in
 * Dijkstra order, adding a face only when the region stays a disk without pinched vertices
 * (it shares one edge with the region and brings a new vertex, or shares two edges and closes
 * the fan of their common vertex): the complement is a band along a cut graph. Reorders faces so
 * the first *n0 are the disk (1 <= *n0 < nf unless the chart is itself a disk). */
sk_status sk__chart_grow_disk(const sk_mesh *m, uint32_t *faces, size_t nf, uint32_t stamp,
                              sk__chart_work *w, size_t *n0, sk_error *err);

/* Cuts the chart faces[0..nf) (labelled stamp, one piece, genus 0 with two or more boundary
 * loops: a disk with holes) into a disk: each hole joined by the shortest path along the chart's
 * edges to the longest boundary loop or to a path already cut, in w->cut. *ncut receives the
 * edges cut: 0 (nothing done) when the chart already holds cut edges, has more than
 * SK__ATLAS_MAX_HOLES holes, or no path was found. */
sk_status sk__chart_cut_holes(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                              sk__chart_work *w, size_t *ncut, sk_error *err);
#define SK__ATLAS_MAX_HOLES 64

/* A slit into the chart faces[0..nf) (labelled stamp, one piece with a boundary): the shortest
 * path along the chart's inner edges from its boundary to its inner vertex of the largest
 * score (per mesh vertex), cut in w->cut; the edges go to cut_edges (room for 3 nf), their
 * number to *ncut (0: no inner vertex of positive score, or none reached) and their 3D length
 * to *length. */
sk_status sk__chart_cut_slit(const sk_mesh *m, const uint32_t *faces, size_t nf, uint32_t stamp,
                             sk__chart_work *w, const double *score, uint32_t *cut_edges,
                             size_t *ncut, double *length, sk_error *err);

/* Reorders faces[0..nf) (labelled stamp) by edge-connected component; sizes (nf entries of room)
 * receives the component sizes in order; returns their number. */
size_t sk__chart_components(const sk_mesh *m, uint32_t *faces, size_t nf, uint32_t stamp,
                            sk__chart_work *w, uint32_t *sizes);

#define SK__ATLAS_MERGE_FACES 4000

/* ---- creases.c ---- */

/* The atlas's default sk_atlas_opts.crease_angle in degrees. Not the smooth pipeline's 40: the
 * icosahedron (41.8 degrees between face normals) then fell apart into 20 one-triangle charts
 * (seams 10.2 x sqrt(area) against Blender's 6.1 and xatlas's 4.8); at 60 it is one region, cut
 * into 4 charts (seams 4.1). Every other shared mesh (cube 90, fandisk, mech-holes-shark, the
 * scans) gets the same atlas for any angle from 42 to 70 (bench/atlas.sh rows, issue 11); 60
 * keeps the dodecahedron's faces (63.4) and the cube's, and is close to Blender's Smart UV
 * Project angle limit (66). */
#define SK__ATLAS_CREASE_ANGLE 60.0

/* Regions of the faces that touch across edges with a dihedral angle below angle_deg (degrees),
 * a region under min_frac of its component's area merged into the neighbour it shares the most
 * sharp edge length with: region[f] (nf entries) receives ids numbered by their first face, the
 * components' ids (comp, ncomp of them) when no crease cuts; *nregions their number. */
sk_status sk__crease_regions(const sk_mesh *m, double angle_deg, double min_frac,
                             const uint32_t *comp, size_t ncomp, uint32_t *region,
                             size_t *nregions, sk_error *err);

/* ---- atlas.c ---- */

/* Is the edge of half-edge h (a face on both sides) a seam of the layout corner_uv (per
 * half-edge: the uv point of its corner), i.e. are its ends different uv points on either side? */
static inline bool sk__uv_seam(const sk_mesh *m, const uint32_t *corner_uv, uint32_t h)
{
    uint32_t o = h ^ 1u;
    return corner_uv[h] != corner_uv[m->h_next[o]] || corner_uv[m->h_next[h]] != corner_uv[o];
}

/* The 3D length of the seams of corner_uv (interior mesh edges that are sk__uv_seam); *edges
 * (optional) receives their number. */
double sk__uv_seam_length(const sk_mesh *m, const uint32_t *corner_uv, size_t *edges);

/* ---- chart_param.c ---- */

typedef struct sk__chart_quality {
    size_t flipped;
    double conformal_mean; /* 3D-area weighted sigma1/sigma2 */
    double area_log_dev;   /* 3D-area weighted |log(area scale / mean area scale)| */
    double area3, area_uv; /* after scaling area_uv == area3 */
} sk__chart_quality;

/* Parametrizes a disk chart (free boundary, flip-free hierarchical MIPS) into uv, scaled so that
 * its uv area equals its 3D area, and measures it. */
sk_status sk__chart_param(const sk_mesh *chart, uint64_t seed, double *uv, sk__chart_quality *q,
                          sk_error *err);

/* The atlas's defaults: sk_atlas_opts.max_distortion, max_stretch, area_theta, merge_faces.
 * Chosen together with the merging (bench/atlas.sh, SK_ATLAS_BIG=0, issue 11): tight bounds
 * split the charts down to nearly flat pieces (cow without merging: 332 charts, MIPS mean
 * 2.0021, seams 28.1 x sqrt(area)) and the merging joins neighbours while the union stays within
 * them (40 charts, MIPS 2.0045, seams 17.1, area-log 0.066; xatlas 2.0049, 19.9, 0.337; the old
 * defaults 1.25 / 1.25 / 1 without merging 2.0134, 22.4, 0.037). A theta of 0.5 instead of 1
 * lowers MIPS where the stretch bound leaves room. merge_faces bounds the merging's solves:
 * 4000 triangles (2000 before) lets holes' plate merge to 3 charts (seams 3.84 -> 1.55 x
 * sqrt(area), xatlas 1.59; MIPS 2.000100 -> 2.000109, xatlas 2.000136); 3000 and 3500 leave 4
 * (seams 1.71), 4500 takes mech-holes-shark to 3 charts at utilization 0.503 (xatlas 0.527).
 * Larger charts on the scans too: lion, bunny00, armadillo seams down 8-12%, MIPS mean up
 * 2-5e-4, all still below both peers (docs/param.md). */
#define SK__ATLAS_MAX_DISTORTION 1.05
#define SK__ATLAS_MAX_STRETCH 1.15
#define SK__ATLAS_AREA_THETA 0.5
/* sk_atlas_opts.area_bound's default: see bound_area in atlas.c and docs/param.md. */
#define SK__ATLAS_AREA_BOUND 1.08
/* sk_atlas_opts.slit_price's default: see slit_charts in atlas.c and docs/param.md. */
#define SK__ATLAS_SLIT_PRICE 1e-3

/* MIPS with the area term (sk_mips_opts.area_theta = theta, free boundary) from the layout in uv,
 * scaled and measured into q; *ok false (uv then undefined) when it failed or flipped. Errors are
 * out of memory and cancellation only. */
sk_status sk__chart_area(const sk_mesh *chart, uint64_t seed, double theta, double *uv,
                         sk__chart_quality *q, bool *ok, sk_error *err);

/* The cheap prediction of sk__chart_param's quality: LSCM (one linear solve) into uv, scaled and
 * measured into q. *ok is false when LSCM failed or flipped (no prediction). Errors are out of
 * memory and cancellation only. */
sk_status sk__chart_predict(const sk_mesh *chart, double *uv, sk__chart_quality *q, bool *ok,
                            sk_error *err);

/* Per triangle: 3D area, signed uv area, MIPS value and sigma1/sigma2 of the map p -> q. */
void sk__tri_distortion(const double *p0, const double *p1, const double *p2, const double *q0,
                        const double *q1, const double *q2, double *area3, double *area_uv,
                        double *mips, double *conformal);

/* ---- pack.c ---- */

/* Packs the charts in place: chart c owns the uv points [off[c], off[c+1]) (already at a common
 * scale, in any position; uv_chart[u] the chart of point u), bounded by the ne edges edges[2i],
 * edges[2i+1] (uv indices; the chart's boundary and seams). The charts go into [0,1]^2 at the
 * largest common scale found, `pad` texels apart at `res` texels per side (half of it from the
 * square's border): chart-shaped (sk__raster_pack) when that wins, else each chart's smallest
 * bounding box on a skyline (shelves above 2000 charts). *scale receives the common factor. */
sk_status sk__pack_charts(size_t num_charts, const uint32_t *off, const uint32_t *uv_chart,
                          double *uv, size_t ne, const uint32_t *edges, double res, double pad,
                          double *scale, sk_error *err);

/* The area of the smallest bounding box (over the convex hull's edge directions) of the n points
 * pts (sorted in place); hull: 2n + 2 doubles of room. 0 below 3 points. */
double sk__min_box_area(double *pts, size_t n, double *hull);

/* ---- pack_split.c ---- */

/* The atlas's charts as sk__pack_atlas reads and rewrites them. */
typedef struct sk__atlas_layout {
    size_t nc, n;          /* charts, uv points */
    uint32_t *off;         /* nc + 1: chart c owns the uv points [off[c], off[c+1]) */
    uint32_t *chart;       /* n: the chart of each uv point */
    double *uv;            /* 2n: the charts at one scale, in any position */
    uint32_t *corner_uv;   /* per half-edge (sk_atlas.corner_uv) */
    uint32_t *face_chart;  /* per face */
    /* the charts' bounds (sk_atlas_opts.max_distortion, max_stretch; <= 0: none): a cut is
     * kept only when both pieces are within them */
    double max_conf, max_stretch;
} sk__atlas_layout;

/* Packs the charts of a into [0,1]^2 (sk__pack_charts, outlines from the corners). With may_cut
 * and 2..8 charts, also tries cutting charts in two where that packs at a larger scale (see
 * pack_split.c): then off, chart and uv are replaced (new allocations, the old freed), nc and n
 * grow and corner_uv, face_chart are rewritten; *cuts receives the cuts kept. */
sk_status sk__pack_atlas(const sk_mesh *m, sk__atlas_layout *a, bool may_cut, double res,
                         double pad, double *scale, size_t *cuts, sk_error *err);

/* ---- raster_pack.c ---- */

typedef struct sk__raster_in {
    size_t nc;
    const uint32_t *off;       /* chart c owns uv points [off[c], off[c+1]) */
    const double *uv[2];       /* two orientations of every chart's points (scale 1) */
    const double *area;        /* per chart: its uv area at scale 1 (largest placed first) */
    const uint32_t *edge_off;  /* per chart: its outline edges [edge_off[c], edge_off[c+1]) */
    const uint32_t *edge;      /* 2 uv indices per outline edge */
    uint32_t res, pad, margin; /* texels per side, gutter and border in texels */
} sk__raster_in;

/* Chart-shaped packing (see raster_pack.c) at the largest common scale found between s0 (tried
 * first, lowered by 5% steps while nothing fits) and s1 (an upper bound); on success (*ok) the
 * packed points go to uv (not one of in->uv) and the scale to *scale. */
sk_status sk__raster_pack(const sk__raster_in *in, double s0, double s1, double *uv,
                          double *scale, bool *ok, sk_error *err);

#endif
