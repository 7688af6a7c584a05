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

/* The slow path of sk__fmt_real: glibc's correctly rounded conversions and strtod. */
static const char *fmt_real_libc(char buf[32], double x)
{
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

/* ---- the fast path: exact integer arithmetic for the usual range ----
 *
 * x = m 2^e (m < 2^53). For a precision p, the nearest p-digit decimal is D 10^-k with
 * D = round(m 5^k 2^(e + k)), computed exactly in 128 bits for 0 <= k <= FAST_MAX_K (5^k < 2^63,
 * so m 5^k < 2^116), which covers |x| from about 1e-11 to 1e15. D reads back to x exactly when it
 * lies in x's rounding interval (m -+ 1/2 ulp, the lower half-width 1/4 ulp at a power of two;
 * ends included for even m: strtod rounds ties to even), also an exact 128-bit comparison. The
 * result is the one of the libc path, digit for digit (tests/unit/test_export.c compares it with a
 * scan of "%.1G" .. "%.17G" on 200k values). */
__extension__ typedef unsigned __int128 u128;

#define FAST_MAX_K 27

static const uint64_t pow10_u64[18] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL,
                                       1000000ULL, 10000000ULL, 100000000ULL, 1000000000ULL,
                                       10000000000ULL, 100000000000ULL, 1000000000000ULL,
                                       10000000000000ULL, 100000000000000ULL,
                                       1000000000000000ULL, 10000000000000000ULL,
                                       100000000000000000ULL};

static uint64_t pow5_u64(int k)
{
    uint64_t r = 1;
    for (int i = 0; i < k; ++i)
        r *= 5;
    return r;
}

/* a 2^s, truncated (*t) and rounded to nearest, ties to even (*r); false if out of the range
 * handled here (|s| small enough for 128 bits, results below 2^64). */
static bool scale_pow2(u128 a, int s, uint64_t *t, uint64_t *r)
{
    if (s >= 0) {
        if (s > 8)
            return false;
        u128 v = a << s;
        if (v >> 64)
            return false;
        *t = *r = (uint64_t)v;
        return true;
    }
    if (s < -120)
        return false;
    unsigned sh = (unsigned)-s;
    u128 v = a >> sh, rem = a - (v << sh), half = (u128)1 << (sh - 1);
    if (v >> 64)
        return false;
    *t = (uint64_t)v;
    if (rem > half || (rem == half && (v & 1)))
        ++v;
    if (v >> 64)
        return false;
    *r = (uint64_t)v;
    return true;
}

/* Whether D 10^-k reads back to m 2^e (pow2: m is the smallest mantissa of its binade, so the
 * gap below is half the gap above): 1 yes, 0 no, -1 out of the range handled here. */
static int reads_back(uint64_t d, int k, uint64_t m, int e, bool pow2)
{
    /* D 10^-k against (4m -+ c) 2^(e-2), that is D 2^-(e-2+k) against (4m -+ c) 5^k */
    if (k < 0 || k > FAST_MAX_K)
        return -1;
    u128 p5 = pow5_u64(k);
    u128 lo = ((u128)4 * m - (pow2 ? 1 : 2)) * p5, hi = ((u128)4 * m + 2) * p5, v = d;
    int t = e - 2 + k;
    if (t < 0) {
        if (-t > 62)
            return -1;
        v <<= -t;
    } else {
        if (t > 8)
            return -1;
        lo <<= t;
        hi <<= t;
    }
    bool even = (m & 1) == 0;
    return (v > lo && v < hi) || (even && (v == lo || v == hi));
}

/* The nearest p-digit decimal of m 2^e as D (10^(p-1) <= D < 10^p) and its decimal exponent X
 * (m 2^e ~ D 10^(X-p+1)); x10 is an estimate of floor(log10 (m 2^e)), off by at most one. False
 * when outside the fast range. */
static bool nearest_digits(uint64_t m, int e, int p, int x10, uint64_t *d, int *xout)
{
    for (int tries = 0; tries < 3; ++tries) {
        int k = p - 1 - x10;
        if (k < 0 || k > FAST_MAX_K)
            return false;
        uint64_t t, r;
        if (!scale_pow2((u128)m * pow5_u64(k), e + k, &t, &r))
            return false;
        if (t >= pow10_u64[p]) {
            ++x10; /* the estimate was one too low */
            continue;
        }
        if (t < pow10_u64[p - 1]) {
            --x10; /* one too high */
            continue;
        }
        if (r == pow10_u64[p]) { /* rounds up to the next power of ten */
            *d = pow10_u64[p - 1];
            *xout = x10 + 1;
        } else {
            *d = r;
            *xout = x10;
        }
        return true;
    }
    return false;
}

/* Writes the %.<digits>G form of D (digits significant digits, no trailing zeros) with decimal
 * exponent X, with a decimal point always, as fmt_real_libc does. */
static void write_g(char *o, bool neg, uint64_t d, int digits, int x10)
{
    char dig[20];
    for (int i = digits - 1; i >= 0; --i) {
        dig[i] = (char)('0' + d % 10);
        d /= 10;
    }
    if (neg)
        *o++ = '-';
    if (x10 >= -4 && x10 < digits) {
        if (x10 >= 0) {
            for (int i = 0; i <= x10; ++i)
                *o++ = dig[i];
            *o++ = '.';
            for (int i = x10 + 1; i < digits; ++i)
                *o++ = dig[i];
        } else {
            *o++ = '0';
            *o++ = '.';
            for (int i = 0; i < -x10 - 1; ++i)
                *o++ = '0';
            for (int i = 0; i < digits; ++i)
                *o++ = dig[i];
        }
    } else {
        *o++ = dig[0];
        *o++ = '.';
        for (int i = 1; i < digits; ++i)
            *o++ = dig[i];
        *o++ = 'E';
        int ax = x10 < 0 ? -x10 : x10;
        *o++ = x10 < 0 ? '-' : '+';
        if (ax >= 100)
            *o++ = (char)('0' + ax / 100);
        *o++ = (char)('0' + ax / 10 % 10);
        *o++ = (char)('0' + ax % 10);
    }
    *o = '\0';
}

static bool fmt_real_fast(char buf[32], double x)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    bool neg = bits >> 63;
    int be = (int)((bits >> 52) & 0x7ff);
    if (be == 0 || be == 0x7ff)
        return false; /* subnormal, inf, nan (zero is handled by the caller) */
    uint64_t m = (bits & ((1ULL << 52) - 1)) | (1ULL << 52);
    int e = be - 1075;
    bool pow2 = m == (1ULL << 52) && be > 1;
    /* decimal exponent estimate: floor(log10 |x|), corrected by nearest_digits */
    int x10 = (int)floor(log10(fabs(x)));
    for (int p = 15; p <= 17; ++p) {
        uint64_t d;
        int xp;
        if (!nearest_digits(m, e, p, x10, &d, &xp))
            return false;
        if (p < 17) {
            /* exponent of D: the power of ten is X - p + 1 (after a carry, D = 10^(p-1)) */
            int ok = reads_back(d, p - 1 - xp, m, e, pow2);
            if (ok < 0)
                return false;
            if (!ok)
                continue;
        }
        int digits = p;
        if (p == 15)
            while (digits > 1 && d % 10 == 0) {
                d /= 10;
                --digits;
            }
        write_g(buf, neg, d, digits, xp);
        return true;
    }
    return false;
}

const char *sk__fmt_real(char buf[32], double x)
{
    if (x == 0.0) {
        memcpy(buf, "0.", 3); /* no "-0." */
        return buf;
    }
    if (fmt_real_fast(buf, x))
        return buf;
    return fmt_real_libc(buf, x);
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
