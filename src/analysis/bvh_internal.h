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

#endif
