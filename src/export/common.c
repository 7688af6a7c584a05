/* Shared pieces of the CAD writers: units, number formatting, time stamps, tensor conversion. */
#define _POSIX_C_SOURCE 200809L
#include "export/export_internal.h"
#include "core/internal.h"

#include <float.h>
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

/* snprintf "%.<prec>G" with a literal format: glibc takes a much slower path for "%.*G". */
const char *sk__fmt_real(char buf[32], double x)
{
    if (x == 0.0)
        x = 0.0; /* no "-0." */
    /* shortest form that reads back exactly, in capitals, always with a decimal point */
    sk__fmt_shortest(buf, x);
    for (char *c = buf; *c; ++c)
        if (*c >= 'a' && *c <= 'z')
            *c = (char)(*c - 'a' + 'A');
    if (!strchr(buf, '.')) {
        char *e = strchr(buf, 'E');
        size_t n = strlen(buf);
        if (n + 2 > 32)
            return buf;
        if (e) {
            memmove(e + 1, e, strlen(e) + 1);
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
