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

/* The STEP AP214 header, product, units and geometric context (#14) with its placement (#18),
 * shared by the patch and the B-spline writers; entity ids from 30 on are free. `description`
 * goes in FILE_DESCRIPTION, `system` is the originating system of FILE_NAME. */
void sk__step_header(sk__out *o, const char *description, const char *path, const char *name,
                     const char *when, const char *system, const sk__unit *unit);

/* A STEP string: quoted, quotes doubled, characters outside printable ASCII left out. */
void sk__step_string(sk__out *o, const char *s);

/* One IGES 80-column record: 72 columns of text (the first n chars of text, padded), the section
 * letter, the sequence number right-aligned in columns 74-80. */
void sk__iges_record_n(sk__out *b, const char *text, size_t n, char section, size_t seq);
void sk__iges_record(sk__out *b, const char *text, char section, size_t seq);

/* x right-aligned in a field of `width` columns at o (x fits). */
void sk__iges_field(char *o, int width, size_t x);

/* Packs IGES free-format tokens into records of `width` columns. Every token but the last of the
 * section or entity is followed by ',', the last by ';' (sk__iges_pack_end). For the P section,
 * each record carries the DE pointer in columns 66-72. */
typedef struct sk__iges_packer {
    sk__out *b;
    char section;
    size_t *seq;  /* sequence number of the section's last record */
    size_t width;
    size_t de;    /* P section: directory entry pointer */
    size_t first; /* P section: sequence number of the entity's first record */
    bool zero_before_point; /* reals of |x| < 1 as "0.25" rather than ".25" */
    char line[81];
    size_t len;
    char pending[96]; /* the last token, written once the next delimiter is known */
    bool has_pending;
} sk__iges_packer;

void sk__iges_pack(sk__iges_packer *p, const char *token);
void sk__iges_pack_end(sk__iges_packer *p);
/* The shortest exact real (sk__fmt_real), without the zero before the point of |x| < 1 (".25",
 * "-.5"; zero stays "0.") unless p->zero_before_point. */
void sk__iges_pack_real(sk__iges_packer *p, double x);
void sk__iges_pack_size(sk__iges_packer *p, size_t x);
void sk__iges_pack_int(sk__iges_packer *p, long x);
/* A Hollerith string "nHtext" of at most 60 characters. */
void sk__iges_pack_string(sk__iges_packer *p, const char *s);

/* The parameters of the IGES Global section (IGES 5.3 section 2.2.4): delimiters, product `name`,
 * the base name of `path`, originating `system`, 64-bit number ranges, unit, the time stamp
 * ("YYYYMMDD.HHNNSS"), the minimum `resolution` and the largest coordinate, version 5.3. */
void sk__iges_global(sk__iges_packer *g, const char *name, const char *path, const char *system,
                     const sk__unit *unit, const char *stamp, double resolution, double maxc);

#endif
