/* The lexer and byte helpers the mesh file readers and writers share (not installed); the format
 * entry points are in io/formats.h, which only the dispatcher (io.c) and the formats include.
 *
 * Text readers walk the input with an sk__text cursor that knows the current line number, so every
 * error can say "NAME:LINE: what is wrong". Input buffers are never NUL-terminated: every scan is
 * bounded by the end pointer. Binary readers report "NAME: byte OFFSET: what is wrong". */
#ifndef SK_IO_LEXER_H
#define SK_IO_LEXER_H

#include "surfkit/io.h"
#include "core/internal.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Text cursor
 * ------------------------------------------------------------------------------------------- */

typedef struct sk__text {
    const char *p;   /* current position */
    const char *end; /* one past the last byte */
    size_t line;     /* 1-based line number of p */
    const char *name;
    sk_error *err;
} sk__text;

static inline void sk__text_init(sk__text *t, const void *data, size_t size, const char *name,
                                 sk_error *err)
{
    t->p = (const char *)data;
    t->end = t->p + size;
    t->line = 1;
    t->name = name;
    t->err = err;
}

static inline bool sk__is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}

static inline bool sk__is_eol(char c) { return c == '\n' || c == '\r'; }

static inline bool sk__is_space(char c) { return sk__is_blank(c) || sk__is_eol(c); }

static inline bool sk__is_digit(char c) { return c >= '0' && c <= '9'; }

/* Skips spaces and tabs, not line ends. */
static inline void sk__skip_blank(sk__text *t)
{
    while (t->p < t->end && sk__is_blank(*t->p))
        ++t->p;
}

static inline bool sk__at_eof(const sk__text *t) { return t->p >= t->end; }

/* At a line end or at the end of the input. */
static inline bool sk__at_eol(const sk__text *t) { return t->p >= t->end || sk__is_eol(*t->p); }

/* Consumes one line end ("\n", "\r\n" or "\r") if the cursor is at one. */
static inline void sk__eat_eol(sk__text *t)
{
    if (t->p < t->end && *t->p == '\r') {
        ++t->p;
        if (t->p < t->end && *t->p == '\n')
            ++t->p;
        ++t->line;
    } else if (t->p < t->end && *t->p == '\n') {
        ++t->p;
        ++t->line;
    }
}

/* Skips the rest of the line and its line end. */
static inline void sk__skip_line(sk__text *t)
{
    const char *p = t->p;
    while (p < t->end && !sk__is_eol(*p))
        ++p;
    t->p = p;
    sk__eat_eol(t);
}

/* Skips spaces, tabs and line ends (counting lines). */
static inline void sk__skip_space(sk__text *t)
{
    while (t->p < t->end) {
        char c = *t->p;
        if (sk__is_blank(c))
            ++t->p;
        else if (sk__is_eol(c))
            sk__eat_eol(t);
        else
            break;
    }
}

/* True if the bytes at the cursor start with the keyword kw followed by a space, a line end or
 * the end of the input. */
static inline bool sk__at_keyword(const sk__text *t, const char *kw)
{
    size_t n = strlen(kw);
    if ((size_t)(t->end - t->p) < n || memcmp(t->p, kw, n) != 0)
        return false;
    return t->p + n == t->end || sk__is_space(t->p[n]);
}

/* Length of the token at p (up to a space, a line end or the end). */
static inline size_t sk__token_len(const char *p, const char *end)
{
    const char *q = p;
    while (q < end && !sk__is_space(*q))
        ++q;
    return (size_t)(q - p);
}

/* "NAME:LINE: message" with status SK_ERR_PARSE. */
sk_status sk__text_error(const sk__text *t, const char *fmt, ...) SK__PRINTF(2, 3);
/* "NAME: byte OFFSET: message" with status SK_ERR_PARSE. */
sk_status sk__bin_error(sk_error *err, const char *name, size_t offset, const char *fmt, ...)
    SK__PRINTF(4, 5);

/* Writes a token into buf (at most size - 1 characters, "..." appended when cut) for messages. */
const char *sk__token_str(const char *p, const char *end, char *buf, size_t size);

/* ---------------------------------------------------------------------------------------------
 * Numbers
 * ------------------------------------------------------------------------------------------- */

typedef enum {
    SK__NUM_OK = 0,
    SK__NUM_NONE,     /* not a number */
    SK__NUM_NONFINITE /* nan, inf, or a value that overflows a double */
} sk__num;

/* Parses a decimal floating-point number at *pp (optional sign, digits, fraction, exponent; also
 * recognises nan/inf spellings to report them). Exact: uses the Clinger fast path when the
 * mantissa and exponent allow it and strtod otherwise. On success *pp points after the number;
 * the caller checks what follows. */
sk__num sk__parse_double(const char **pp, const char *end, double *out);

/* Parses an unsigned decimal integer (no sign). Values above SK__INT_SAT saturate to it. Returns
 * false when there is no digit. */
#define SK__INT_SAT ((uint64_t)1 << 62)
static inline bool sk__parse_uint(const char **pp, const char *end, uint64_t *out)
{
    const char *p = *pp;
    uint64_t v = 0;
    if (p >= end || !sk__is_digit(*p))
        return false;
    do {
        v = v * 10 + (uint64_t)(*p - '0');
        if (v > SK__INT_SAT)
            v = SK__INT_SAT;
        ++p;
    } while (p < end && sk__is_digit(*p));
    *pp = p;
    *out = v;
    return true;
}

/* Signed variant ('+' or '-' allowed), saturating at +-SK__INT_SAT. */
static inline bool sk__parse_int(const char **pp, const char *end, int64_t *out)
{
    const char *p = *pp;
    bool neg = false;
    if (p < end && (*p == '-' || *p == '+')) {
        neg = *p == '-';
        ++p;
    }
    uint64_t v;
    if (!sk__parse_uint(&p, end, &v))
        return false;
    *pp = p;
    *out = neg ? -(int64_t)v : (int64_t)v;
    return true;
}

static inline void sk__put_le32(unsigned char *b, uint32_t v)
{
    b[0] = (unsigned char)v;
    b[1] = (unsigned char)(v >> 8);
    b[2] = (unsigned char)(v >> 16);
    b[3] = (unsigned char)(v >> 24);
}

static inline void sk__put_le64(unsigned char *b, uint64_t v)
{
    sk__put_le32(b, (uint32_t)v);
    sk__put_le32(b + 4, (uint32_t)(v >> 32));
}

static inline uint32_t sk__get_le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static inline uint64_t sk__get_le64(const unsigned char *b)
{
    return (uint64_t)sk__get_le32(b) | (uint64_t)sk__get_le32(b + 4) << 32;
}

/* Checks that the soup can be written: indices in range, every face at least 3 vertices. */
sk_status sk__check_soup_for_write(const sk_soup *s, sk_error *err);

#endif
