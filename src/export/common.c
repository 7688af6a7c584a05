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

/* The shortest exact real, CAD style: the core's one formatter. */
const char *sk__fmt_real(char buf[32], double x)
{
    sk__fmt_cad(buf, x);
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
    return sk_patch_set_to_tensor(patches, sk__export_degenerate(opts), out, err);
}

void sk__export_progress_init(sk__export_progress *p, const sk_export_opts *opts, size_t total)
{
    p->opts = opts;
    p->total = total;
    p->next = 0;
}

bool sk__export_tick(sk__export_progress *p, size_t done)
{
    if (!p->opts || !p->opts->progress || (done < p->next && done < p->total))
        return false;
    p->next = done + (p->total / 100 > 0 ? p->total / 100 : 1);
    double f = p->total ? (double)done / (double)p->total : 1.0;
    return p->opts->progress(p->opts->progress_user, f > 1.0 ? 1.0 : f) != 0;
}

bool sk__export_degenerate(const sk_export_opts *opts)
{
    if (!opts)
        return true;
    return opts->degenerate_triangles || (!opts->split_triangles && !opts->iges_free_surfaces);
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
