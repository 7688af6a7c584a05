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
static void fmt_g(char buf[32], int prec, double x)
{
    switch (prec) {
    case 1: snprintf(buf, 32, "%.1G", x); break;
    case 2: snprintf(buf, 32, "%.2G", x); break;
    case 3: snprintf(buf, 32, "%.3G", x); break;
    case 4: snprintf(buf, 32, "%.4G", x); break;
    case 5: snprintf(buf, 32, "%.5G", x); break;
    case 6: snprintf(buf, 32, "%.6G", x); break;
    case 7: snprintf(buf, 32, "%.7G", x); break;
    case 8: snprintf(buf, 32, "%.8G", x); break;
    case 9: snprintf(buf, 32, "%.9G", x); break;
    case 10: snprintf(buf, 32, "%.10G", x); break;
    case 11: snprintf(buf, 32, "%.11G", x); break;
    case 12: snprintf(buf, 32, "%.12G", x); break;
    case 13: snprintf(buf, 32, "%.13G", x); break;
    case 14: snprintf(buf, 32, "%.14G", x); break;
    case 15: snprintf(buf, 32, "%.15G", x); break;
    case 16: snprintf(buf, 32, "%.16G", x); break;
    default: snprintf(buf, 32, "%.17G", x); break;
    }
}

const char *sk__fmt_real(char buf[32], double x)
{
    if (x == 0.0)
        x = 0.0; /* no "-0." */
    /* The shortest "%.<p>G" that reads back exactly. If 15 digits read back, the shortest p is the
     * number of significant digits of that string: a double is within 2.3e-16 (relative) of any
     * decimal that reads back to it, less than half a unit of the 15th digit, so rounding it to
     * 15 digits gives that decimal padded with zeros. This takes 2 formats instead of up to 17. */
    snprintf(buf, 32, "%.15G", x);
    if (x != 0.0 && fabs(x) < DBL_MIN) { /* subnormal: fewer bits, the argument fails; scan */
        for (int prec = 1; prec <= 17; ++prec) {
            fmt_g(buf, prec, x);
            if (strtod(buf, NULL) == x)
                break;
        }
    } else if (strtod(buf, NULL) == x) {
        int digits = 0, trailing = 0;
        bool leading = true;
        for (const char *c = buf; *c && *c != 'E'; ++c) {
            if (*c < '0' || *c > '9')
                continue;
            if (leading && *c == '0')
                continue;
            leading = false;
            ++digits;
            trailing = *c == '0' ? trailing + 1 : 0;
        }
        digits -= trailing;
        fmt_g(buf, digits > 0 ? digits : 1, x);
    } else {
        snprintf(buf, 32, "%.16G", x);
        if (strtod(buf, NULL) != x)
            snprintf(buf, 32, "%.17G", x);
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

void sk__bezier_halve(const double *cp, unsigned n, double *left, double *right)
{
    double w[3 * (SK_PATCH_MAX_DEGREE + 1)];
    memcpy(w, cp, 3 * (n + 1) * sizeof(double));
    for (unsigned r = 0; r <= n; ++r) {
        memcpy(left + 3 * r, w, 3 * sizeof(double));
        memcpy(right + 3 * (n - r), w + 3 * (n - r), 3 * sizeof(double));
        for (unsigned i = 0; i + r < n; ++i)
            for (int x = 0; x < 3; ++x)
                w[3 * i + (unsigned)x] = 0.5 * (w[3 * i + (unsigned)x] + w[3 * (i + 1) + (unsigned)x]);
    }
}
