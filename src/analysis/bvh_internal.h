/* Box queries on the BVH (bvh.c), for the other analysis modules. */
#ifndef SK_BVH_INTERNAL_H
#define SK_BVH_INTERNAL_H

#include "surfkit/deviation.h"

/* Called with the three corners (9 doubles) and the soup face of a triangle; non-zero stops. */
typedef int (*sk__bvh_visit)(void *user, const double corners[9], uint32_t face);

/* Visits every triangle whose bounding box overlaps the box [lo, hi]; returns non-zero when fn
 * stopped the walk. */
int sk__bvh_overlaps(const sk_bvh *bvh, const double lo[3], const double hi[3], sk__bvh_visit fn,
                     void *user);

/* The distance from p to the triangles of bvh by a walk that stops at the first triangle within
 * cap: the exact distance when it exceeds cap, else the distance to some triangle within cap (at
 * most cap, at least the exact distance). *hint: a triangle to try first (a value this function
 * set before, e.g. for a nearby point; SK_INVALID for none), set to the triangle found; *face
 * (may be NULL): that triangle's soup face. cap = 0 gives the exact distance. */
double sk__bvh_distance_capped(const sk_bvh *bvh, const double p[3], double cap, uint32_t *hint,
                               uint32_t *face);

/* sk_deviation (no vertex distances) over mesh_bvh, the caller's BVH of the soup mesh (not
 * built again, not handed over: opts->mesh_bvh, if set, gets NULL). */
sk_status sk__deviation_over(const sk_soup *surface, const sk_soup *mesh, const sk_bvh *mesh_bvh,
                             const sk_deviation_opts *opts, sk_deviation_report *report,
                             sk_error *err);

#endif
