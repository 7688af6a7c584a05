/* Self-intersections of a surface given as indexed faces: pairs of faces (or of groups of faces,
 * such as the patches of a smooth surface tessellated) that cross each other although they are
 * not neighbours. What Open CASCADE's BOPAlgo_ArgumentAnalyzer (FreeCAD's "check geometry")
 * reports as self-intersecting faces. */
#ifndef SURFKIT_INTERSECT_H
#define SURFKIT_INTERSECT_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { SK_INTERSECT_EXAMPLES = 16 };

typedef struct sk_intersection_report {
    size_t pairs;          /* group pairs that are not neighbours and whose triangles cross */
    size_t groups;         /* groups in at least one such pair */
    size_t num_examples;
    uint32_t examples[2 * SK_INTERSECT_EXAMPLES]; /* the first pairs (smaller id first, sorted) */
    size_t triangle_tests; /* triangle pairs tested exactly (after the box tests) */
    double seconds;
} sk_intersection_report;

/* Finds the crossings of surface (faces split into fans from their first corner). Faces belong to
 * groups: face f to group face_group[f], or to group f when face_group is NULL. Two groups are
 * neighbours when they share a vertex id: group g's vertices are the corners of face g of
 * `groups` (e.g. the patch network's config mesh, whose face g is patch g), or of `surface` itself
 * when groups is NULL. Faces of one group or of neighbouring groups are never tested against
 * each other; two triangles cross when an edge of one passes through the interior of the other
 * (touching and coplanar contacts do not count).
 * SK_ERR_TOPOLOGY for an index out of range (in surface, face_group or groups), a face with fewer
 * than 3 corners or a non-finite coordinate; SK_ERR_NOMEM. */
SK_API sk_status sk_self_intersections(const sk_soup *surface, const uint32_t *face_group,
                                       const sk_soup *groups, sk_intersection_report *rep,
                                       sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
