/* The one shortest-decimal formatter: the shortest round-trip digits of a double, found once
 * (exact integer arithmetic for the usual range, glibc's correctly rounded conversions and strtod
 * otherwise), and the two styles written from them: mesh text ("%g"-like) and CAD reals (capital
 * E, always a point). */
#include "core/internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the fast path: exact integer arithmetic for the usual range ----
 *
 * x = m 2^e (m < 2^53). For a precision p, the nearest p-digit decimal is D 10^-k with
 * D = round(m 5^k 2^(e + k)), computed exactly in 128 bits for 0 <= k <= FAST_MAX_K (5^k < 2^63,
 * so m 5^k < 2^116), which covers |x| from about 1e-11 to 1e15. D reads back to x exactly when it
 * lies in x's rounding interval (m -+ 1/2 ulp, the lower half-width 1/4 ulp at a power of two;
 * ends included for even m: strtod rounds ties to even), also an exact 128-bit comparison. The
 * result is the one of the libc path, digit for digit (tests/unit/test_format.c compares both
 * styles with "%.<p>g" scans on millions of values). */
__extension__ typedef unsigned __int128 u128;

#define FAST_MAX_K 27

static const uint64_t pow10_u64[18] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL,
                                       1000000ULL, 10000000ULL, 100000000ULL, 1000000000ULL,
                                       10000000000ULL, 100000000000ULL, 1000000000000ULL,
                                       10000000000000ULL, 100000000000000ULL,
                                       1000000000000000ULL, 10000000000000000ULL,
                                       100000000000000000ULL};

/* 5^k for 0 <= k <= FAST_MAX_K (5^27 < 2^63). */
static uint64_t pow5_u64(int k)
{
    static const uint64_t t[FAST_MAX_K + 1] = {
        1ULL, 5ULL, 25ULL, 125ULL, 625ULL, 3125ULL, 15625ULL, 78125ULL, 390625ULL, 1953125ULL,
        9765625ULL, 48828125ULL, 244140625ULL, 1220703125ULL, 6103515625ULL, 30517578125ULL,
        152587890625ULL, 762939453125ULL, 3814697265625ULL, 19073486328125ULL,
        95367431640625ULL, 476837158203125ULL, 2384185791015625ULL, 11920928955078125ULL,
        59604644775390625ULL, 298023223876953125ULL, 1490116119384765625ULL,
        7450580596923828125ULL};
    return t[k];
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

static void strip_zeros(sk__digits *o)
{
    while (o->n > 1 && o->d % 10 == 0) {
        o->d /= 10;
        --o->n;
    }
}

/* Normal doubles only (the caller checks). */
static bool fast_digits(double x, uint64_t bits, sk__digits *o)
{
    int be = (int)((bits >> 52) & 0x7ff);
    uint64_t m = (bits & ((1ULL << 52) - 1)) | (1ULL << 52);
    int e = be - 1075;
    bool pow2 = m == (1ULL << 52) && be > 1;
    /* decimal exponent estimate: floor((be - 1023) log10 2) (78913 / 2^18 = 0.30103, exact over
     * the normal range), one below floor(log10 |x|) at most; nearest_digits corrects it */
    (void)x;
    int b2 = be - 1023;
    int x10 = b2 >= 0 ? (b2 * 78913) >> 18 : -((-b2 * 78913 + (1 << 18) - 1) >> 18);
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
        o->d = d;
        o->n = p;
        o->x10 = xp;
        o->prec = p;
        strip_zeros(o);
        return true;
    }
    return false;
}

/* Reads "[-]d.ddde[+-]X" as printf's %e writes it. */
static void parse_e(const char *s, sk__digits *o)
{
    o->d = 0;
    o->n = 0;
    for (; *s && *s != 'e'; ++s)
        if (*s >= '0' && *s <= '9') {
            o->d = o->d * 10 + (uint64_t)(*s - '0');
            ++o->n;
        }
    o->x10 = *s ? atoi(s + 1) : 0;
}

/* The slow path: glibc's correctly rounded "%.<p-1>e" and strtod. For a normal double the first
 * precision tried is 15: a double is within 2.3e-16 (relative) of any decimal that reads back to
 * it, less than half a unit of the 15th digit, so rounding it to 15 digits gives the shortest
 * such decimal padded with zeros. Subnormals have fewer bits: their scan starts at min_prec. */
static void libc_digits(double x, int min_prec, sk__digits *o)
{
    char buf[40];
    int p = fabs(x) < DBL_MIN ? min_prec : 15;
    for (;; ++p) {
        snprintf(buf, sizeof buf, "%.*e", p - 1, x);
        if (p >= 17 || strtod(buf, NULL) == x)
            break;
    }
    parse_e(buf, o);
    o->prec = p;
    strip_zeros(o);
}

bool sk__shortest_digits(double x, int min_prec, sk__digits *out)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    int be = (int)((bits >> 52) & 0x7ff);
    if (x == 0.0 || be == 0x7ff)
        return false;
    out->neg = bits >> 63;
    if (min_prec < 1)
        min_prec = 1;
    if (min_prec > 17)
        min_prec = 17;
    if (be != 0 && fast_digits(x, bits, out))
        return true;
    libc_digits(x, min_prec, out);
    return true;
}

/* ---- the two styles ---- */

static char *put_digits(char *o, const char dig[20], int from, int to)
{
    for (int i = from; i < to; ++i)
        *o++ = dig[i];
    return o;
}

static char *put_exp(char *o, char e, int x10)
{
    int ax = x10 < 0 ? -x10 : x10;
    *o++ = e;
    *o++ = x10 < 0 ? '-' : '+';
    if (ax >= 100)
        *o++ = (char)('0' + ax / 100);
    *o++ = (char)('0' + ax / 10 % 10);
    *o++ = (char)('0' + ax % 10);
    return o;
}

/* Digit characters of dg into dig, most significant first. */
static void digit_chars(const sk__digits *dg, char dig[20])
{
    uint64_t d = dg->d;
    for (int i = dg->n - 1; i >= 0; --i) {
        dig[i] = (char)('0' + d % 10);
        d /= 10;
    }
}

/* printf's "%.<P>g" of the digits, P the precision that read back: fixed when -4 <= X < P (zeros
 * padded up to the point, no point without a fraction), else d[.ddd]e+XX. */
static int write_mesh(char *buf, const sk__digits *dg)
{
    char dig[20], *o = buf;
    digit_chars(dg, dig);
    int n = dg->n, x = dg->x10;
    if (dg->neg)
        *o++ = '-';
    if (x < -4 || x >= dg->prec) {
        *o++ = dig[0];
        if (n > 1) {
            *o++ = '.';
            o = put_digits(o, dig, 1, n);
        }
        o = put_exp(o, 'e', x);
    } else if (x >= 0) {
        o = put_digits(o, dig, 0, n < x + 1 ? n : x + 1);
        for (int i = n; i < x + 1; ++i)
            *o++ = '0';
        if (n > x + 1) {
            *o++ = '.';
            o = put_digits(o, dig, x + 1, n);
        }
    } else {
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -x - 1; ++i)
            *o++ = '0';
        o = put_digits(o, dig, 0, n);
    }
    *o = '\0';
    return (int)(o - buf);
}

/* "%.<n>G" of the n digits with a decimal point always: fixed when -4 <= X < n. */
static int write_cad(char *buf, const sk__digits *dg)
{
    char dig[20], *o = buf;
    digit_chars(dg, dig);
    int n = dg->n, x = dg->x10;
    if (dg->neg)
        *o++ = '-';
    if (x >= -4 && x < n) {
        if (x >= 0) {
            o = put_digits(o, dig, 0, x + 1);
            *o++ = '.';
            o = put_digits(o, dig, x + 1, n);
        } else {
            *o++ = '0';
            *o++ = '.';
            for (int i = 0; i < -x - 1; ++i)
                *o++ = '0';
            o = put_digits(o, dig, 0, n);
        }
    } else {
        *o++ = dig[0];
        *o++ = '.';
        o = put_digits(o, dig, 1, n);
        o = put_exp(o, 'E', x);
    }
    *o = '\0';
    return (int)(o - buf);
}

int sk__fmt_shortest(char buf[32], double v)
{
    sk__digits dg;
    if (sk__shortest_digits(v, 15, &dg))
        return write_mesh(buf, &dg);
    if (v == 0.0) {
        memcpy(buf, signbit(v) ? "-0" : "0", signbit(v) ? 3 : 2);
        return signbit(v) ? 2 : 1;
    }
    return snprintf(buf, 32, "%.17g", v); /* inf, nan */
}

int sk__fmt_cad(char buf[32], double v)
{
    sk__digits dg;
    if (sk__shortest_digits(v, 1, &dg))
        return write_cad(buf, &dg);
    if (v == 0.0) {
        memcpy(buf, "0.", 3); /* no "-0." */
        return 2;
    }
    int n = snprintf(buf, 31, "%.17G", v); /* "INF.", "NAN." */
    if (n > 0 && n < 30) {
        buf[n++] = '.';
        buf[n] = '\0';
    }
    return n;
}

int sk_format_double(char buf[32], double v)
{
    return sk__fmt_shortest(buf, v);
}
