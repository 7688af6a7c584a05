/* Internal pieces shared by the files of src/hierarchy. */
#ifndef SK_HIERARCHY_INTERNAL_H
#define SK_HIERARCHY_INTERNAL_H

#include "surfkit/hierarchy.h"

/* Workspace of the collapse checks. stamp (per vertex, may be NULL) marks the one-ring of the
 * vertex about to be removed: stamp[w] == stamp_value for its neighbours (sk__collapse_mark_ring).
 * valence (per vertex, may be NULL) is kept up to date by sk__collapse; without it valences are
 * counted by walking the rings. */
typedef struct sk__collapse_ctx {
    uint32_t *stamp;
    uint32_t stamp_value;
    uint32_t *valence;
    double cos_max;        /* cos of the largest allowed normal turn */
    unsigned min_valence;
} sk__collapse_ctx;

void sk__collapse_ctx_init(sk__collapse_ctx *ctx, const sk_collapse_opts *opts);
/* Marks the neighbours of v with a fresh stamp value (ctx->stamp must be set). */
void sk__collapse_mark_ring(const sk_mesh *m, uint32_t v, sk__collapse_ctx *ctx);
/* Legality of the half-edge collapse of h (see sk_mesh_collapse_ok); with ctx->stamp the ring of
 * from(h) must be marked. */
bool sk__collapse_ok(const sk_mesh *m, uint32_t h, const sk__collapse_ctx *ctx);
/* Performs it; updates ctx->valence when set. */
void sk__collapse(sk_mesh *m, uint32_t h, uint32_t *valence);

/* Half-edge x takes the place of half-edge y in y's loop: x gets y's next, prev and face (and
 * becomes that face's half-edge); y is left unlinked. The one relinking step of collapses and
 * vertex splits (the half-edge kept of a removed triangle stands in for its outer neighbour). */
void sk__halfedge_take_place(sk_mesh *m, uint32_t x, uint32_t y);

/* The ring of from(h) for the exponential map: ring[0] = to(h) = W0, then the neighbours in the
 * order of the faces, so that (V, ring[k], ring[k+1]) are V's triangles; for a boundary vertex the
 * ring runs from W0 to the other boundary neighbour. Returns n + 1 (the number of ring vertices)
 * and sets *closed. ring needs room for the valence of from(h). */
size_t sk__collapse_ring(const sk_mesh *m, uint32_t h, uint32_t *ring, bool *closed);

/* Section 3: exponential map of V's one-ring (lengths kept, angles scaled to 2 pi, or to pi for a
 * boundary vertex), parent triangle (w0, w_i, w_i+1) containing v and its barycentric
 * coordinates. ring as from sk__collapse_ring (count = n + 1 >= 3). scratch needs 4 * count + 2
 * doubles. Writes parent[3] (vertex ids) and bary[3]. */
void sk__barycentric(const sk_mesh *m, uint32_t v, const uint32_t *ring, size_t count, bool closed,
                     double *scratch, uint32_t parent[3], double bary[3]);

/* Vertex split on a mesh in level-i numbering; appends the new vertex and returns its index. */
uint32_t sk__vertex_split(sk_mesh *m, const sk_vertex_split *s);

/* Transparent-huge-page hint for big arrays (memory.c); results never depend on it. */
void *sk__alloc_huge(size_t n, size_t size); /* sk__malloc_array + hint; sk__free() it */
void sk__mesh_huge_hint(sk_mesh *m);         /* hint on the whole capacity of every array */

/* Renumbers the vertices of a compacted mesh: vertex k becomes newid[k] (a permutation). */
sk_status sk__permute_vertices(sk_mesh *m, const uint32_t *newid, sk_error *err);

/* The levels, as built by levels.c and read by split.c. */
typedef struct sk__level {
    size_t vertices, faces, halfedges;
    double seconds;
    /* transition from this level + 1 (finer) to this level; empty for the finest level */
    uint32_t *fine_to_coarse; /* vertices of level + 1 entries */
    sk_vertex_split *splits;
    size_t num_splits;
} sk__level;

struct sk_hierarchy {
    size_t num_levels;
    sk_vertex_split *split_store; /* all records; levels[i].splits point into it */
    sk__level *levels; /* [0] coarsest ... [num_levels - 1] input */
    sk_mesh *coarsest;
};

#endif
