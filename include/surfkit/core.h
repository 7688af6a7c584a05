/* surfkit core: status codes, error reports, progress callbacks.
 *
 * Every fallible call returns an sk_status (0 ok, negative error, positive warning) and takes an
 * optional sk_error * that receives a one-line message. The library never prints and never exits. */
#ifndef SURFKIT_CORE_H
#define SURFKIT_CORE_H

#include <stddef.h>
#include <stdint.h>

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
    SK_WARN_FLIPS = 1     /* finished, but some triangles are flipped */
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

/* Library version string, "MAJOR.MINOR.PATCH": SK_VERSION_STRING of the library linked, which may
 * differ from the header a program was compiled with. */
SK_API const char *sk_version(void);

#ifdef __cplusplus
}
#endif
#endif
