/* Internal helpers shared across the library (not installed). */
#ifndef SK_CORE_INTERNAL_H
#define SK_CORE_INTERNAL_H

#include "surfkit/core.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#if defined(__GNUC__)
#define SK__PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define SK__PRINTF(a, b)
#endif

/* Fill err (may be NULL) with a formatted one-line message and return status. */
sk_status sk__fail(sk_error *err, sk_status status, const char *fmt, ...) SK__PRINTF(3, 4);

/* Set err to SK_OK with an empty message. */
void sk__ok(sk_error *err);

/* Calls the progress callback if any; returns SK_ERR_CANCELLED (with message) when it asks to stop. */
sk_status sk__progress(sk_progress_fn fn, void *user, double fraction, sk_error *err);

/* Overflow-checked allocation of n elements of the given size (NULL on overflow or failure). */
void *sk__malloc_array(size_t n, size_t size);
void *sk__calloc_array(size_t n, size_t size);
void *sk__realloc_array(void *p, size_t n, size_t size);
/* Frees what the wrappers above (and sk__strdup) allocated; NULL is fine. */
void sk__free(void *p);
char *sk__strdup(const char *s);
char *sk__strndup(const char *s, size_t n);

/* Atomic output file (core/atomic_file.c has the rules): written to a temporary beside the
 * (symlink-resolved) target and renamed into place by sk__atomic_commit, or at sk_outputs_commit
 * inside a batch; devices and pipes are written directly; sk__atomic_abort removes the
 * temporary. */
typedef struct sk__atomic_file {
    FILE *fp;
    int fd;
    int direct;       /* not a regular file: written in place */
    int in_place;     /* a hard-linked regular file: the finished temporary is copied into it */
    char *shown_path; /* as the caller named it, for messages */
    char *final_path; /* symlinks resolved */
    char *tmp_path;   /* named temporary, or NULL (anonymous O_TMPFILE until commit) */
} sk__atomic_file;

sk_status sk__atomic_open(sk__atomic_file *af, const char *path, sk_error *err);
sk_status sk__atomic_commit(sk__atomic_file *af, sk_error *err);
void sk__atomic_abort(sk__atomic_file *af);

/* One BLAS thread for a stretch of small dense LAPACK calls: begin returns the caller's thread
 * count, end restores it. Not for code that also runs large sparse factorizations. */
int sk__blas_serial_begin(void);
void sk__blas_serial_end(int saved);

/* ---------------------------------------------------------------------------------------------
 * Output buffer: a growing memory buffer, flushed to a FILE when one is attached
 * ------------------------------------------------------------------------------------------- */

typedef struct sk__out {
    char *buf;
    size_t len, cap;
    FILE *fp;   /* NULL: everything stays in buf */
    int failed; /* 0, or SK_ERR_NOMEM / SK_ERR_IO after the first failure */
    int io_errno; /* with SK_ERR_IO from a flush: the errno of the failed write (the reason) */
} sk__out;

/* Makes room for n more bytes; returns false (and sets failed) on failure. */
bool sk__out_room(sk__out *o, size_t n);
void sk__out_bytes(sk__out *o, const void *data, size_t n);
void sk__out_str(sk__out *o, const char *s);
void sk__out_char(sk__out *o, char c);
/* The shortest of %.15g, %.16g, %.17g that reads back to the same double. */
void sk__out_double(sk__out *o, double v);
void sk__out_uint(sk__out *o, uint64_t v);
/* Writes any buffered bytes to the attached FILE. */
void sk__out_flush(sk__out *o);
void sk__out_printf(sk__out *o, const char *fmt, ...) SK__PRINTF(2, 3);
void sk__out_free(sk__out *o);
/* Writes rows 0..n-1 in order, row(o, i, ctx) writing row i: the same bytes as that loop (which
 * it is below 32768 rows, or when no thread can be started). Above, the rows go in rounds whose
 * second half a second thread formats into a private memory buffer, appended after the first
 * half; its SK_ERR_NOMEM becomes o's. row may only read ctx and what it points to, and write to
 * the o it is given. Stops at the first failure of o. */
typedef void (*sk__row_fn)(sk__out *o, size_t i, const void *ctx);
void sk__out_rows(sk__out *o, size_t n, sk__row_fn row, const void *ctx);
/* Writes the whole (unattached) buffer to path through the atomic writer. */
sk_status sk__out_write_file(const sk__out *o, const char *path, sk_error *err);

/* The shortest decimal digits that read back (strtod) to a finite nonzero double:
 * |x| ~ d1.d2..dn 10^x10, d holding the n digits without trailing zeros; prec is the precision of
 * the first "%.<prec>g" (from 15 for normal doubles, from min_prec for subnormals, up to 17) that
 * reads back, so n <= prec. For normal doubles the digits are the shortest of all. False for zero,
 * inf and nan. */
typedef struct sk__digits {
    uint64_t d;
    int n, x10, prec;
    bool neg;
} sk__digits;
bool sk__shortest_digits(double x, int min_prec, sk__digits *out);

/* Mesh text style: the shortest of %.15g, %.16g, %.17g that reads back to v exactly ("-0", "inf"
 * and "nan" as printf writes them), into buf; returns its length. */
int sk__fmt_shortest(char buf[32], double v);
/* CAD style (STEP/IGES reals): the shortest "%.<p>G" (p from 1) that reads back, with a decimal
 * point always ("1.E+02", "0.5"); zero, also -0, is "0."; returns the length. */
int sk__fmt_cad(char buf[32], double v);

/* Asks the kernel for transparent huge pages on a large fresh buffer (Linux; else nothing). */
void sk__huge_hint(void *p, size_t bytes);

/* The first touch of a fresh buffer's pages on a second thread, beside a serial stage (begin:
 * nothing when no thread can be started; end: waits for it; the buffer is not used between). */
typedef struct sk__prefault {
    void *p;
    size_t bytes;
    bool running;
    _Alignas(16) unsigned char thread[64]; /* a pthread_t */
} sk__prefault;
void sk__prefault_begin(sk__prefault *pf, void *p, size_t bytes);
void sk__prefault_end(sk__prefault *pf);

/* Base name of a path (pointer into path), for error messages. */
const char *sk__basename(const char *path);

/* Deterministic random numbers (splitmix64 seeding a xoshiro256** state). */
typedef struct sk__rng {
    uint64_t s[4];
} sk__rng;

void sk__rng_seed(sk__rng *rng, uint64_t seed);
uint64_t sk__rng_next(sk__rng *rng);
/* Uniform integer in [0, n), n > 0. */
uint32_t sk__rng_below(sk__rng *rng, uint32_t n);
/* Uniform double in [0, 1). */
double sk__rng_unit(sk__rng *rng);

/* Radix sort of 64-bit keys with a 32-bit payload, ascending by key; tmp buffers of n elements
 * are allocated internally. Returns SK_ERR_NOMEM on allocation failure. */
sk_status sk__sort_u64_u32(uint64_t *keys, uint32_t *vals, size_t n);

#endif
