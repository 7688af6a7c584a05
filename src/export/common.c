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

void sk__step_string(sk__out *o, const char *s)
{
    sk__out_char(o, '\'');
    for (; *s; ++s) {
        if (*s == '\'')
            sk__out_str(o, "''");
        else if ((unsigned char)*s >= 0x20 && (unsigned char)*s < 0x7f)
            sk__out_bytes(o, s, 1);
    }
    sk__out_char(o, '\'');
}

void sk__step_header(sk__out *o, const char *description, const char *path, const char *name,
                     const char *when, const char *system, const sk__unit *unit)
{
    sk__out_str(o, "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((");
    sk__step_string(o, description);
    sk__out_str(o, "),'2;1');\nFILE_NAME(");
    sk__step_string(o, sk__basename(path));
    sk__out_printf(o, ",'%s',('surfkit'),('surfkit'),", when);
    sk__step_string(o, system);
    sk__out_str(o, ",'surfkit','');\n");
    sk__out_str(o, "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
                   "#1=APPLICATION_CONTEXT('core data for automotive mechanical design processes');\n"
                   "#2=APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',"
                   "2000,#1);\n#3=PRODUCT_CONTEXT('',#1,'mechanical');\n#4=PRODUCT(");
    sk__step_string(o, name);
    sk__out_char(o, ',');
    sk__step_string(o, name);
    sk__out_str(o, ",'',(#3));\n#5=PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#4));\n"
                   "#6=PRODUCT_DEFINITION_FORMATION('','',#4);\n"
                   "#7=PRODUCT_DEFINITION_CONTEXT('part definition',#1,'design');\n"
                   "#8=PRODUCT_DEFINITION('design','',#6,#7);\n"
                   "#9=PRODUCT_DEFINITION_SHAPE('','',#8);\n");
    if (unit->step_unit)
        sk__out_printf(o, "#10=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(%s,%s));\n",
                       unit->step_prefix ? unit->step_prefix : "$", unit->step_unit);
    else
        sk__out_printf(o, "#20=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.));\n"
                          "#21=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(%.6g),#20);\n"
                          "#22=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n"
                          "#10=(CONVERSION_BASED_UNIT('%s',#21)LENGTH_UNIT()NAMED_UNIT(#22));\n",
                       unit->metres, unit->iges_name);
    sk__out_str(o, "#11=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));\n"
                   "#12=(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT());\n"
                   "#13=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#10,"
                   "'distance_accuracy_value','confusion accuracy');\n"
                   "#14=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#13))"
                   "GLOBAL_UNIT_ASSIGNED_CONTEXT((#10,#11,#12))REPRESENTATION_CONTEXT('',''));\n"
                   "#15=CARTESIAN_POINT('',(0.,0.,0.));\n#16=DIRECTION('',(0.,0.,1.));\n"
                   "#17=DIRECTION('',(1.,0.,0.));\n#18=AXIS2_PLACEMENT_3D('',#15,#16,#17);\n");
}

void sk__iges_record_n(sk__out *b, const char *text, size_t n, char section, size_t seq)
{
    if (!sk__out_room(b, 81))
        return;
    char *o = b->buf + b->len;
    if (n > 72)
        n = 72;
    memcpy(o, text, n);
    memset(o + n, ' ', 72 - n);
    o[72] = section;
    for (int i = 79; i >= 73; --i) { /* sequence number, right-aligned in columns 74-80 */
        o[i] = seq || i == 79 ? (char)('0' + seq % 10) : ' ';
        seq /= 10;
    }
    o[80] = '\n';
    b->len += 81;
}

void sk__iges_record(sk__out *b, const char *text, char section, size_t seq)
{
    sk__iges_record_n(b, text, strlen(text), section, seq);
}

void sk__iges_field(char *o, int width, size_t x)
{
    for (int i = width - 1; i >= 0; --i) {
        o[i] = x || i == width - 1 ? (char)('0' + x % 10) : ' ';
        x /= 10;
    }
}

static void iges_flush(sk__iges_packer *p)
{
    if (!p->len)
        return;
    if (p->section == 'P') { /* 64 columns of data, a blank, the DE pointer in 66-72 */
        char text[72];
        memcpy(text, p->line, p->len);
        memset(text + p->len, ' ', 65 - p->len);
        sk__iges_field(text + 65, 7, p->de);
        sk__iges_record_n(p->b, text, 72, 'P', ++*p->seq);
    } else {
        sk__iges_record_n(p->b, p->line, p->len, p->section, ++*p->seq);
    }
    p->len = 0;
}

static void iges_emit(sk__iges_packer *p, char delim)
{
    size_t n = strlen(p->pending);
    if (p->len + n + 1 > p->width)
        iges_flush(p);
    if (n + 1 > p->width) /* cannot happen for our tokens (numbers, short strings) */
        n = p->width - 1;
    memcpy(p->line + p->len, p->pending, n);
    p->len += n;
    p->line[p->len++] = delim;
    p->has_pending = false;
}

void sk__iges_pack(sk__iges_packer *p, const char *token)
{
    if (p->has_pending)
        iges_emit(p, ',');
    size_t n = strlen(token);
    if (n >= sizeof p->pending)
        n = sizeof p->pending - 1;
    memcpy(p->pending, token, n);
    p->pending[n] = '\0';
    p->has_pending = true;
}

void sk__iges_pack_end(sk__iges_packer *p)
{
    if (p->has_pending)
        iges_emit(p, ';');
    iges_flush(p);
}

void sk__iges_pack_real(sk__iges_packer *p, double x)
{
    char buf[32];
    char *r = (char *)sk__fmt_real(buf, x);
    if (p->zero_before_point) {
        /* as sk__fmt_real wrote it */
    } else if (r[0] == '0' && r[1] == '.' && r[2]) {
        r += 1;
    } else if (r[0] == '-' && r[1] == '0' && r[2] == '.') {
        r[1] = '-';
        r += 1;
    }
    sk__iges_pack(p, r);
}

void sk__iges_pack_size(sk__iges_packer *p, size_t x)
{
    char buf[24], *o = buf + sizeof buf - 1;
    *o = '\0';
    do {
        *--o = (char)('0' + x % 10);
        x /= 10;
    } while (x);
    sk__iges_pack(p, o);
}

void sk__iges_pack_int(sk__iges_packer *p, long x)
{
    if (x >= 0) {
        sk__iges_pack_size(p, (size_t)x);
        return;
    }
    char buf[32];
    snprintf(buf, sizeof buf, "%ld", x);
    sk__iges_pack(p, buf);
}

void sk__iges_pack_string(sk__iges_packer *p, const char *s)
{
    char buf[96];
    snprintf(buf, sizeof buf, "%zuH%.60s", strlen(s) > 60 ? (size_t)60 : strlen(s), s);
    sk__iges_pack(p, buf);
}

void sk__iges_global(sk__iges_packer *g, const char *name, const char *path, const char *system,
                     const sk__unit *unit, const char *stamp, double resolution, double maxc)
{
    char file_name[128];
    snprintf(file_name, sizeof file_name, "%s", sk__basename(path));
    sk__iges_pack(g, "1H,");
    sk__iges_pack(g, "1H;");
    sk__iges_pack_string(g, name);
    sk__iges_pack_string(g, file_name);
    sk__iges_pack_string(g, "surfkit");
    sk__iges_pack_string(g, system);
    sk__iges_pack_int(g, 32);
    sk__iges_pack_int(g, 38);
    sk__iges_pack_int(g, 6);
    sk__iges_pack_int(g, 308);
    sk__iges_pack_int(g, 15);
    sk__iges_pack_string(g, name);
    sk__iges_pack_real(g, 1.0);
    sk__iges_pack_int(g, unit->iges_flag);
    sk__iges_pack_string(g, unit->iges_name);
    sk__iges_pack_int(g, 1);
    sk__iges_pack_real(g, 1.0);
    sk__iges_pack_string(g, stamp);
    sk__iges_pack_real(g, resolution);
    sk__iges_pack_real(g, maxc);
    sk__iges_pack_string(g, "surfkit");
    sk__iges_pack_string(g, "surfkit");
    sk__iges_pack_int(g, 11); /* version 5.3 */
    sk__iges_pack_int(g, 0);
    sk__iges_pack_string(g, stamp);
    sk__iges_pack_end(g);
}
