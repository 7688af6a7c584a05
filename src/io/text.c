/* Shared parsing and output helpers of the mesh file formats: error messages with line numbers or
 * byte offsets, exact number parsing, and the output sink. */
#include "io/lexer.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>

sk_status sk__text_error(const sk__text *t, const char *fmt, ...)
{
    if (!t->err)
        return SK_ERR_PARSE;
    char msg[SK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return sk__fail(t->err, SK_ERR_PARSE, "%s:%zu: %s", t->name, t->line, msg);
}

sk_status sk__bin_error(sk_error *err, const char *name, size_t offset, const char *fmt, ...)
{
    if (!err)
        return SK_ERR_PARSE;
    char msg[SK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return sk__fail(err, SK_ERR_PARSE, "%s: byte %zu: %s", name, offset, msg);
}

const char *sk__token_str(const char *p, const char *end, char *buf, size_t size)
{
    size_t n = sk__token_len(p, end);
    size_t i = 0;
    bool cut = n > size - 4;
    size_t take = cut ? size - 4 : n;
    for (; i < take; ++i) {
        unsigned char c = (unsigned char)p[i];
        buf[i] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    if (cut) {
        memcpy(buf + i, "...", 3);
        i += 3;
    }
    buf[i] = '\0';
    return buf;
}

/* Powers of ten exactly representable as doubles. */
static const double pow10_exact[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                       1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                       1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

sk__num sk__parse_double(const char **pp, const char *end, double *out)
{
    const char *p = *pp, *start = p;
    bool neg = false;
    if (p < end && (*p == '-' || *p == '+')) {
        neg = *p == '-';
        ++p;
    }
    uint64_t mant = 0;
    int ndigits = 0;  /* significant digits kept in mant */
    bool exact = true; /* false when digits were dropped */
    long exp10 = 0;
    bool any = false;
    while (p < end && sk__is_digit(*p)) {
        any = true;
        if (ndigits < 19) {
            mant = mant * 10 + (uint64_t)(*p - '0');
            if (mant)
                ++ndigits;
        } else {
            exact = false;
        }
        ++p;
    }
    if (p < end && *p == '.') {
        ++p;
        while (p < end && sk__is_digit(*p)) {
            any = true;
            if (ndigits < 19) {
                mant = mant * 10 + (uint64_t)(*p - '0');
                if (mant)
                    ++ndigits;
                --exp10;
            } else if (*p != '0') {
                exact = false;
            }
            ++p;
        }
    }
    if (!any) {
        /* nan, inf, infinity (any case) are recognised so that they can be reported */
        if (p < end && (*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I')) {
            const char *q = p;
            while (q < end && (is_alpha(*q) || *q == '(' || *q == ')' || sk__is_digit(*q)))
                ++q;
            size_t n = (size_t)(q - p);
            char w[9] = {0};
            for (size_t i = 0; i < n && i < 8; ++i)
                w[i] = (char)(p[i] | 0x20);
            if ((n >= 3 && memcmp(w, "nan", 3) == 0) || (n == 3 && memcmp(w, "inf", 3) == 0) ||
                (n == 8 && memcmp(w, "infinity", 8) == 0)) {
                *pp = q;
                return SK__NUM_NONFINITE;
            }
        }
        return SK__NUM_NONE;
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        bool eneg = false;
        if (q < end && (*q == '-' || *q == '+')) {
            eneg = *q == '-';
            ++q;
        }
        if (q < end && sk__is_digit(*q)) {
            long e = 0;
            while (q < end && sk__is_digit(*q)) {
                if (e < 100000)
                    e = e * 10 + (*q - '0');
                ++q;
            }
            exp10 += eneg ? -e : e;
            p = q;
        }
    }
    *pp = p;
    if (mant == 0 && exact) {
        *out = neg ? -0.0 : 0.0;
        return SK__NUM_OK;
    }
    if (exact && mant <= ((uint64_t)1 << 53) && exp10 >= -22 && exp10 <= 22) {
        /* Clinger's fast path: both operands exact, one correctly rounded operation */
        double d = (double)mant;
        d = exp10 < 0 ? d / pow10_exact[-exp10] : d * pow10_exact[exp10];
        *out = neg ? -d : d;
        return SK__NUM_OK;
    }
    char buf[512];
    size_t n = (size_t)(p - start);
    if (n >= sizeof buf)
        return SK__NUM_NONE;
    memcpy(buf, start, n);
    buf[n] = '\0';
    char *stop = NULL;
    double d = strtod(buf, &stop);
    if (stop != buf + n)
        return SK__NUM_NONE;
    if (!isfinite(d))
        return SK__NUM_NONFINITE;
    *out = d;
    return SK__NUM_OK;
}

sk_status sk__check_soup_for_write(const sk_soup *s, sk_error *err)
{
    if (s->num_vertices && !s->positions)
        return sk__fail(err, SK_ERR_ARG, "the soup has vertices but no positions");
    for (size_t f = 0; f < s->num_faces; ++f) {
        uint32_t a = s->face_offsets[f], b = s->face_offsets[f + 1];
        if (b < a + 3)
            return sk__fail(err, SK_ERR_ARG, "face %zu has %u vertices; at least 3 are needed", f,
                            (unsigned)(b - a));
        for (uint32_t k = a; k < b; ++k)
            if (s->face_indices[k] >= s->num_vertices)
                return sk__fail(err, SK_ERR_ARG,
                                "face %zu has index %u but the soup has %zu vertices", f,
                                (unsigned)s->face_indices[k], s->num_vertices);
    }
    return SK_OK;
}
