/* Status strings and error reporting. */
#include "core/internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const char *sk_status_string(sk_status status)
{
    switch (status) {
    case SK_OK: return "ok";
    case SK_ERR_IO: return "i/o error";
    case SK_ERR_PARSE: return "parse error";
    case SK_ERR_TOPOLOGY: return "topology error";
    case SK_ERR_NUMERIC: return "numerical failure";
    case SK_ERR_NOMEM: return "out of memory";
    case SK_ERR_ARG: return "invalid argument";
    case SK_ERR_CANCELLED: return "cancelled";
    case SK_WARN_FLIPS: return "flipped triangles";
    case SK_WARN_TOLERANCE: return "tolerance not met";
    }
    return "unknown status";
}

const char *sk_version(void)
{
    return SK_VERSION_STRING;
}

sk_status sk__fail(sk_error *err, sk_status status, const char *fmt, ...)
{
    if (err) {
        /* a message longer than the field (a long path) keeps its head and its tail, joined by
         * "...", so the reason at the end is never lost */
        char full[8192]; /* a PATH_MAX path and its reason */
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(full, sizeof full, fmt, ap);
        va_end(ap);
        size_t len = n < 0 ? 0 : (size_t)n < sizeof full ? (size_t)n : sizeof full - 1;
        full[len] = '\0';
        if (len < sizeof err->message) {
            memcpy(err->message, full, len + 1);
        } else {
            size_t head = sizeof err->message / 4, tail = sizeof err->message - head - 4;
            memcpy(err->message, full, head);
            memcpy(err->message + head, "...", 3);
            memcpy(err->message + head + 3, full + len - tail, tail + 1);
        }
        /* one line: replace any newline a caller's string may carry */
        for (char *p = err->message; *p; ++p)
            if (*p == '\n' || *p == '\r')
                *p = ' ';
        err->status = status;
    }
    return status;
}

void sk__ok(sk_error *err)
{
    if (err) {
        err->status = SK_OK;
        err->message[0] = '\0';
    }
}

sk_status sk__progress(sk_progress_fn fn, void *user, double fraction, sk_error *err)
{
    if (fn && fn(user, fraction) != 0)
        return sk__fail(err, SK_ERR_CANCELLED, "cancelled by the caller");
    return SK_OK;
}

const char *sk__basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}
