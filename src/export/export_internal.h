/* Shared pieces of the CAD writers. */
#ifndef SK_EXPORT_INTERNAL_H
#define SK_EXPORT_INTERNAL_H

#include "surfkit/export.h"

#include <stdio.h>

#include "core/internal.h"

typedef struct sk__unit {
    const char *name;
    int iges_flag;           /* IGES global parameter 14 */
    const char *iges_name;   /* IGES global parameter 15 */
    const char *step_prefix; /* SI prefix for STEP (NULL = none) */
    const char *step_unit;   /* STEP SI unit name, or NULL for a conversion-based unit */
    double metres;           /* size of the unit in metres */
} sk__unit;

const sk__unit *sk__unit_lookup(const char *name);

/* A real number that reads back to the same double, always with a decimal point ("1.", "2.5E-07"),
 * as IGES and STEP want; buf must hold 32 chars. */
const char *sk__fmt_real(char buf[32], double x);

/* "YYYY-MM-DDTHH:MM:SS" of opts->timestamp or now (UTC). */
void sk__export_time(const sk_export_opts *opts, char out[32]);

/* Splits a Bezier curve of degree n (3 doubles per control point) at t = 1/2 (de Casteljau):
 * left and right halves, same direction. */
void sk__bezier_halve(const double *cp, unsigned n, double *left, double *right);

/* Whether triangles are written as one tensor patch with a collapsed side (the default, and
 * degenerate_triangles) or split in three (split_triangles, and the free-surface layout of
 * iges_free_surfaces alone). */
bool sk__export_degenerate(const sk_export_opts *opts);

/* Progress of a writer: reports done / total to opts->progress about every 1% (and at the end);
 * returns true when the callback asks to stop. */
typedef struct sk__export_progress {
    const sk_export_opts *opts;
    size_t total, next;
} sk__export_progress;

void sk__export_progress_init(sk__export_progress *p, const sk_export_opts *opts, size_t total);
bool sk__export_tick(sk__export_progress *p, size_t done);

/* Largest absolute coordinate of the control points. */
double sk__patches_max_coord(const sk_patch_set *patches);

#endif
