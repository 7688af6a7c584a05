/* Refinement of triangle meshes: Loop subdivision (with boundary rules) and 1-to-4 midpoint
 * refinement. Used to make large test meshes from the real ones (benchmarks). */
#ifndef SURFKIT_SUBDIVIDE_H
#define SURFKIT_SUBDIVIDE_H

#include "surfkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { SK_SUBDIV_LOOP = 0, SK_SUBDIV_MIDPOINT = 1 } sk_subdiv_scheme;

typedef struct sk_subdiv_opts {
    sk_subdiv_scheme scheme; /* 0 = Loop */
    unsigned iterations;     /* 0 = 1 */
    sk_progress_fn progress;
    void *progress_user;
} sk_subdiv_opts;

/* Refines a triangle mesh (SK_ERR_TOPOLOGY if it has other faces): each step splits every
 * triangle into four; the result has V + E vertices and 4F faces per step. Loop's rules: interior
 * even vertices (1 - n beta) v + beta sum(neighbours) with beta = (5/8 - (3/8 + cos(2 pi / n) / 4)^2)
 * / n; interior odd vertices 3/8 (a + b) + 1/8 (c + d); boundary even 3/4 v + 1/8 (b0 + b1);
 * boundary odd (a + b) / 2. Midpoint: old vertices stay, new ones at edge midpoints. Normals and
 * uvs, when present, are carried linearly (midpoints) in both schemes. */
SK_API sk_status sk_mesh_subdivide(const sk_mesh *mesh, const sk_subdiv_opts *opts, sk_mesh **out,
                                   sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
