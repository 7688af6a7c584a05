/* Shared pieces of the CAD writers: units, number formatting, time stamps, tensor conversion. */
#define _POSIX_C_SOURCE 200809L
#include "export/export_internal.h"
#include "core/internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const sk__unit units[] = {
    {"mm", 2, "MM", ".MILLI.", ".METRE.", 1e-3},
    {"cm", 10, "CM", ".CENTI.", ".METRE.", 1e-2},
    {"m", 6, "M", NULL, ".METRE.", 1.0},
    {"um", 9, "UM", ".MICRO.", ".METRE.", 1e-6},
    {"in", 1, "IN", NULL, NULL, 0.0254},
    {"ft", 4, "FT", NULL, NULL, 0.3048},
};

const sk__unit *sk__unit_lookup(const char *name)
{
    if (!name)
        name = "mm";
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i)
        if (!strcmp(units[i].name, name))
            return &units[i];
    return NULL;
}

bool sk_export_units_known(const char *name)
{
    return sk__unit_lookup(name) != NULL;
}

const char *sk__fmt_real(char buf[32], double x)
{
    if (x == 0.0)
        x = 0.0; /* no "-0." */
    snprintf(buf, 32, "%.17G", x);
    /* shortest form that reads back exactly */
    for (int prec = 1; prec < 17; ++prec) {
        char t[32];
        snprintf(t, sizeof t, "%.*G", prec, x);
        if (strtod(t, NULL) == x) {
            memcpy(buf, t, sizeof t);
            break;
        }
    }
    if (!strchr(buf, '.')) {
        char *e = strchr(buf, 'E');
        size_t n = strlen(buf);
        if (e) {
            memmove(e + 1, e, n - (size_t)(e - buf) + 1);
            *e = '.';
        } else {
            buf[n] = '.';
            buf[n + 1] = '\0';
        }
    }
    return buf;
}

void sk__export_time(const sk_export_opts *opts, char out[32])
{
    if (opts && opts->timestamp) {
        snprintf(out, 32, "%s", opts->timestamp);
        return;
    }
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(out, 32, "%Y-%m-%dT%H:%M:%S", &tm);
}

double sk__patches_max_coord(const sk_patch_set *patches)
{
    double m = 0.0;
    for (size_t i = 0; i < patches->count; ++i) {
        const double *cp = sk_patch_cp(patches, i);
        for (unsigned k = 0; k < 3 * sk_patch_num_points(&patches->patches[i]); ++k)
            m = fmax(m, fabs(cp[k]));
    }
    return m;
}

sk_status sk_export_tensor_patches(const sk_patch_set *patches, const sk_export_opts *opts,
                                   sk_patch_set *out, sk_error *err)
{
    if (!patches || !out)
        return sk__fail(err, SK_ERR_ARG, "sk_export_tensor_patches: NULL argument");
    return sk_patch_set_to_tensor(patches, opts && opts->degenerate_triangles, out, err);
}

void sk__buf_put(sk__buf *b, const char *s, size_t n)
{
    if (b->failed)
        return;
    if (b->n + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->n + n + 1)
            cap *= 2;
        char *p = realloc(b->s, cap);
        if (!p) {
            b->failed = true;
            return;
        }
        b->s = p;
        b->cap = cap;
    }
    memcpy(b->s + b->n, s, n);
    b->n += n;
    b->s[b->n] = '\0';
}

void sk__buf_puts(sk__buf *b, const char *s)
{
    sk__buf_put(b, s, strlen(s));
}

void sk__buf_printf(sk__buf *b, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->failed = true;
        return;
    }
    if ((size_t)n < sizeof tmp) {
        sk__buf_put(b, tmp, (size_t)n);
        return;
    }
    char *big = malloc((size_t)n + 1);
    if (!big) {
        b->failed = true;
        return;
    }
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    sk__buf_put(b, big, (size_t)n);
    free(big);
}

void sk__buf_free(sk__buf *b)
{
    free(b->s);
    b->s = NULL;
    b->n = b->cap = 0;
}

sk_status sk__buf_write_file(const sk__buf *b, const char *path, sk_error *err)
{
    if (b->failed)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory building %s", path);
    sk__atomic_file af;
    sk_status st = sk__atomic_open(&af, path, err);
    if (st)
        return st;
    if (b->n && fwrite(b->s, 1, b->n, af.fp) != b->n) {
        sk__atomic_abort(&af);
        return sk__fail(err, SK_ERR_IO, "%s: write failed", path);
    }
    return sk__atomic_commit(&af, err);
}
