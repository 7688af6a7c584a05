/* Internal entry of the self-intersection test (self_intersect.c) for callers that know the
 * group pairs that can cross (e.g. the patch pairs with overlapping control-point boxes). */
#ifndef SK_ANALYSIS_INTERSECT_INTERNAL_H
#define SK_ANALYSIS_INTERSECT_INTERNAL_H

#include "surfkit/intersect.h"

/* The crossings of surface among the given group pairs only: face f is in group face_group[f]
 * (< num_groups); cand_pairs[0 .. npairs) are keys (a << 32) | b, a < b, sorted, of pairs that are
 * not neighbours. The report is that of sk_self_intersections when every crossing group pair of
 * it is listed (its triangle_tests count the pairs' tests). *fallback is set, and the report left
 * empty, when a group's box is not finite (the caller then runs sk_self_intersections). */
sk_status sk__self_intersections_pairs(const sk_soup *surface, const uint32_t *face_group,
                                       size_t num_groups, const uint64_t *cand_pairs, size_t npairs,
                                       sk_intersection_report *rep, bool *fallback,
                                       sk_error *err);

#endif
