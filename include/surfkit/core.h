/* surfkit core: status codes, error reports, progress callbacks.
 *
 * Every fallible call returns an sk_status (0 ok, negative error, positive warning) and takes an
 * optional sk_error * that receives a one-line message. The library never prints and never exits.
 *
 * Conventions of every public declaration unless it says otherwise:
 *  - `err` may be NULL; an `opts` pointer may be NULL (all defaults), and a zero field means its
 *    default; `stats` / report outputs may be NULL.
 *  - Objects returned through `**out` belong to the caller and are freed with the matching
 *    sk_x_destroy(&x) (NULL-safe, sets the pointer to NULL); on failure *out is NULL. Arrays the
 *    caller passes in (positions, uv) stay the caller's; the library copies what it keeps.
 *  - Lengths and coordinates are in model units (whatever the input file used); angles in
 *    degrees where the name says _deg, radians otherwise; times in seconds. */
#ifndef SURFKIT_CORE_H
#define SURFKIT_CORE_H

#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>
#include <stdio.h>

/* Library version (CMakeLists.txt reads it from here; sk_version() returns the same string). */
#define SK_VERSION_MAJOR 0
#define SK_VERSION_MINOR 1
#define SK_VERSION_PATCH 0
#define SK_VERSION_STRING "0.1.0"

/* Marks the public functions: the shared library is built with hidden visibility and exports
 * exactly these (tests/api/exports.sh checks that every function declared in these headers is
 * exported, and nothing else is). */
#if defined(__GNUC__) && __GNUC__ >= 4
#  define SK_API __attribute__((visibility("default")))
#else
#  define SK_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SK_OK = 0,
    SK_ERR_IO = -1,       /* cannot open, read or write a file */
    SK_ERR_PARSE = -2,    /* malformed input file */
    SK_ERR_TOPOLOGY = -3, /* the mesh is not what the algorithm needs (non-manifold, not a disk...) */
    SK_ERR_NUMERIC = -4,  /* a numerical failure (singular system, no convergence) */
    SK_ERR_NOMEM = -5,    /* an allocation failed */
    SK_ERR_ARG = -6,      /* invalid argument (programmer or user option error) */
    SK_ERR_CANCELLED = -7,/* the progress callback asked to stop */
    SK_WARN_FLIPS = 1,    /* finished, but some triangles are flipped */
    SK_WARN_TOLERANCE = 2 /* finished, but the result does not meet the tolerance asked for */
} sk_status;

#define SK_ERROR_MESSAGE_SIZE 256

typedef struct sk_error {
    sk_status status;
    char message[SK_ERROR_MESSAGE_SIZE];
} sk_error;

/* Element index type and its "none" value. */
#define SK_INVALID UINT32_MAX

/* Progress callback: fraction in [0, 1]; return non-zero to cancel the operation. */
typedef int (*sk_progress_fn)(void *user, double fraction);

/* A short English name of a status ("parse error", ...). */
SK_API const char *sk_status_string(sk_status status);

/* Monotonic clock in seconds (for timings in reports and benchmarks). */
SK_API double sk_seconds(void);

/* CPU seconds of the whole process, all threads (CLOCK_PROCESS_CPUTIME_ID): the timings that stay
 * meaningful on a loaded machine. */
SK_API double sk_cpu_seconds(void);

/* Library version string, "MAJOR.MINOR.PATCH": SK_VERSION_STRING of the library linked, which may
 * differ from the header a program was compiled with. */
SK_API const char *sk_version(void);

/* The library's allocator (cgltf, CHOLMOD style): every allocation of libsurfkit goes through it
 * (not those inside CHOLMOD, LAPACK, cairo or the C library). All zero = malloc/realloc/free.
 * Process-wide: install it before any other call, or between calls when no object the library
 * allocated is alive. Memory the library hands over (sk_soup_write_memory's buffer) is freed
 * with its free. */
typedef struct sk_allocator {
    void *(*malloc)(void *user, size_t size);
    void *(*realloc)(void *user, void *p, size_t size);
    void (*free)(void *user, void *p);
    void *user;
} sk_allocator;
/* NULL (or an incomplete one) restores the C library's. */
SK_API void sk_set_allocator(const sk_allocator *alloc);

/* The shortest decimal of v that reads back (strtod) to exactly v (the shortest of %.15g, %.16g,
 * %.17g; "inf", "nan" as printf writes them) into buf; returns its length. The library's own
 * formatter, for callers that print numbers the way the writers do. */
SK_API int sk_format_double(char buf[32], double v);

/* True when path ends with ext (".step"), ignoring ASCII case: the one extension matcher. */
SK_API bool sk_path_has_ext(const char *path, const char *ext);

/* Output files. Every file the library writes goes through one writer: symlinks are followed and
 * the file is written beside their target; an existing file keeps its mode, a new one gets 0666
 * minus the umask; devices and pipes are written directly; regular files appear complete or not
 * at all (an anonymous temporary, named and renamed into place when complete).
 *
 * sk_write_file writes path through fn (which returns SK_OK or an error status) that way. */
SK_API sk_status sk_write_file(const char *path, sk_status (*fn)(FILE *fp, void *user), void *user,
                               sk_error *err);
/* One command, several outputs, all or none: after sk_outputs_begin, finished outputs wait as
 * named temporaries; sk_outputs_commit renames them all into place, sk_outputs_abort removes them
 * all. Not thread-safe: one batch per process, begun and ended by the application. */
SK_API void sk_outputs_begin(void);
SK_API sk_status sk_outputs_commit(sk_error *err);
SK_API void sk_outputs_abort(void);
/* Removes every named temporary still pending (async-signal-safe: for a SIGINT/SIGTERM handler,
 * which should then re-raise the signal). */
SK_API void sk_outputs_remove_pending(void);

#ifdef __cplusplus
}
#endif
#endif
