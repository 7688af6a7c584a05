/* The B-spline fit's internals shared by bspline_fit.c (the fit's own dense check) and
 * bspline_tess.c (the knot-adaptive lines and tessellation). */
#ifndef SK_FIT_BSPLINE_INTERNAL_H
#define SK_FIT_BSPLINE_INTERNAL_H

#include "surfkit/fit.h"

#include <stddef.h>

/* Parameter lines of a knot-adaptive grid: u[0..nu], v[0..nv] from 0 to 1, each knot span
 * subdivided evenly; chord bounds the distance between the surface and the grid's triangles. */
typedef struct sk__fit_lines {
    size_t nu, nv;
    double *u, *v;
    double chord;
} sk__fit_lines;

/* The lines for chord error tol / 20 (bounds from the second- and mixed-derivative control
 * points of each cell), at least 4 per span and 64 per side, at most max_side per side (the
 * spans' counts scaled down in proportion when more would be needed: chord then says so). */
sk_status sk__fit_lines_make(const sk_bspline_surface *s, double tol, size_t max_side,
                             sk__fit_lines *out, sk_error *err);
void sk__fit_lines_free(sk__fit_lines *l);

#endif
