/* Progressive mesh hierarchy (Hormann, Greiner, Campagna, "Hierarchical Parametrization of
 * Triangulated Surfaces", sections 2 and 3).
 *
 * Half-edge collapses V -> W0 (W0 keeps its position) grouped into levels by the paper's random
 * independent-set rule: unlock all vertices; repeat: pick an unlocked vertex V at random, collapse
 * it to a neighbour W0, lock V's one-ring W0..Wn; until no unlocked vertex is left. Every removed
 * vertex keeps its barycentric coordinates (rho, sigma, tau) in a parent triangle (w0, wi, wi+1)
 * of the next coarser level, found through the exponential map of its one-ring.
 *
 * Levels are numbered as in the paper: level 0 is the coarsest mesh M^0, level L-1 the input.
 * Storage is OpenSubdiv-like: the coarsest mesh plus, for each pair of consecutive levels, a
 * fine -> coarse vertex map and the vertex-split records (memory O(n)). Applying the splits of
 * level i to level i reproduces level i+1 exactly (positions bit for bit, the same triangles with
 * the same vertex numbers). */
#ifndef SURFKIT_HIERARCHY_H
#define SURFKIT_HIERARCHY_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Half-edge collapse
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_collapse_opts {
    double max_normal_deviation_deg; /* largest turn of a face normal; 0 = 90 degrees */
    unsigned min_valence;            /* smallest valence of an interior vertex after; 0 = 3
                                        (boundary vertices keep at least 2 edges = one face) */
} sk_collapse_opts;

/* True when the half-edge collapse of h (from(h) = V is removed, to(h) = W0 stays where it is) is
 * legal on a triangle mesh: the link condition holds (the common neighbours of V and W0 are exactly
 * the tips of the one or two triangles at the edge); a boundary V only collapses along a boundary
 * edge; an interior edge between two boundary vertices never collapses; no triangle would lose its
 * last interior edge; no face normal of V's remaining one-ring turns by more than the threshold; no
 * face becomes degenerate (SK_DEGENERATE_REL); the valences stay at or above the minimum. Such a
 * collapse keeps the Euler characteristic and the number of boundary loops. opts may be NULL. */
SK_API bool sk_mesh_collapse_ok(const sk_mesh *mesh, uint32_t h, const sk_collapse_opts *opts);

/* Performs the collapse of h (call sk_mesh_collapse_ok first): marks V, one or two faces and two or
 * three edges deleted (sk_mesh_compact removes them). */
SK_API void sk_mesh_collapse(sk_mesh *mesh, uint32_t h);

/* ---------------------------------------------------------------------------------------------
 * Hierarchy
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_hierarchy sk_hierarchy;

/* Called after each simplification step with the new (compacted) level; step 1 is the first level
 * below the input. Return non-zero to cancel. */
typedef int (*sk_level_fn)(void *user, size_t step, const sk_mesh *level);

typedef struct sk_hierarchy_opts {
    unsigned max_levels;    /* stop when the hierarchy has this many levels (input included);
                               0 = no limit */
    size_t target_faces;    /* stop once a level has at most this many faces; 0 = no target */
    double min_reduction;   /* stop after a level that removes less than this fraction of the
                               faces; 0 = 0.03 */
    uint64_t seed;          /* random order of the vertices; same seed, same hierarchy */
    sk_collapse_opts collapse;
    sk_progress_fn progress;
    void *progress_user;
    sk_level_fn on_level;   /* may be NULL */
    void *on_level_user;
} sk_hierarchy_opts;

/* Builds the hierarchy of a triangle mesh (SK_ERR_TOPOLOGY for other faces, SK_ERR_NUMERIC for
 * non-finite coordinates). Deleted elements of the input are ignored: level L-1 is the compacted
 * input. Isolated vertices are kept on every level. opts may be NULL. */
SK_API sk_status sk_hierarchy_build(const sk_mesh *mesh, const sk_hierarchy_opts *opts,
                                    sk_hierarchy **out, sk_error *err);
SK_API void sk_hierarchy_destroy(sk_hierarchy **h);

typedef struct sk_level_info {
    size_t vertices, faces;
    double seconds; /* time spent building this level from the next finer one; for the input: the
                       setup (checks, working copy) */
} sk_level_info;

/* Number of levels L (at least 1: the input itself). */
SK_API size_t sk_hierarchy_num_levels(const sk_hierarchy *h);
SK_API sk_level_info sk_hierarchy_level_info(const sk_hierarchy *h, size_t level);
/* The coarsest mesh M^0 (compacted; owned by the hierarchy). */
SK_API const sk_mesh *sk_hierarchy_coarsest(const sk_hierarchy *h);

/* One vertex split: undoes the collapse of v (level i+1 numbering) onto w0. All other vertex ids are
 * level i numbers. The split takes the faces of w0 from the edge (w0, first) around to the edge
 * (w0, last), turning counter-clockwise around the (reinserted) v, and gives them to v; it recreates
 * the triangle (v, w0, first) when left_face and (w0, v, last) when right_face (an interior collapse
 * has both; a boundary one has one of them and first or last is then v's other boundary neighbour).
 * The parent triangle (w0, parent[1], parent[2]) holds v at bary = (rho, sigma, tau) (section 3). */
typedef struct sk_vertex_split {
    uint32_t v;
    uint32_t w0, first, last;
    uint32_t parent[3]; /* parent[0] == w0 */
    uint8_t left_face, right_face;
    double bary[3];     /* rho, sigma, tau >= 0, sum 1 */
    double position[3]; /* v's position, exact */
} sk_vertex_split;

/* Splits taking level to level + 1 (level < L - 1) and their count. They commute (the removed
 * vertices of a level are pairwise non-adjacent); they are stored sorted by w0. */
SK_API const sk_vertex_split *sk_hierarchy_splits(const sk_hierarchy *h, size_t level, size_t *count);
/* Vertex map of level + 1 -> level: the level number of a kept vertex, SK_INVALID for a removed one.
 * Its length is the vertex count of level + 1. Coarser levels are numbered in a spatial (Morton)
 * order of the vertices, and keep the relative order from there on. */
SK_API const uint32_t *sk_hierarchy_vertex_map(const sk_hierarchy *h, size_t level);

/* Turns mesh, which must be level `level` (as from sk_hierarchy_coarsest or an earlier call), into
 * level + 1 in place: applies the splits, then renumbers the vertices as level + 1 numbers them.
 * uvs (when the mesh has them) of inserted vertices are interpolated with the barycentric
 * coordinates; normals are interpolated and normalised. */
SK_API sk_status sk_hierarchy_split(const sk_hierarchy *h, size_t level, sk_mesh *mesh, sk_error *err);

/* A copy of level `level` (coarsest mesh plus splits). */
SK_API sk_status sk_hierarchy_level_mesh(const sk_hierarchy *h, size_t level, sk_mesh **out,
                                         sk_error *err);

/* Section 3, "Triangle Insertion": carries a per-vertex attribute of `dim` doubles (uv: dim = 2)
 * from level to level + 1: kept vertices copy theirs, inserted ones get
 * rho * a(w0) + sigma * a(wi) + tau * a(wi+1). coarse has dim * V(level) values, fine dim *
 * V(level + 1); they must not overlap. */
SK_API sk_status sk_hierarchy_prolong(const sk_hierarchy *h, size_t level, const double *coarse,
                                      size_t dim, double *fine, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
