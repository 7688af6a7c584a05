/* The one shortest-decimal formatter (src/core/fmt.c): its digits against printf's correctly
 * rounded conversions scanned up from few digits, and both styles against what the mesh writers
 * ("%.15g" .. "%.17g") and the CAD writers ("%.1G" .. "%.17G" with a point) wrote before. */
#include "testutil.h"

#include "core/internal.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The old mesh formatter: the shortest of %.15g, %.16g, %.17g that reads back. */
static void mesh_ref(char out[32], double v)
{
    for (int prec = 15; prec <= 17; ++prec) {
        snprintf(out, 32, "%.*g", prec, v);
        if (prec == 17 || strtod(out, NULL) == v)
            break;
    }
}

/* The digits of "%.17e" cut to the fewest "%.<p-1>e" (p from min_prec) that read back, trailing
 * zeros dropped: the reference for sk__shortest_digits. */
static void digits_ref(double x, int min_prec, sk__digits *o)
{
    char buf[40];
    snprintf(buf, sizeof buf, "%.17e", x);
    assert_true(strtod(buf, NULL) == x);
    int p = min_prec;
    for (; p < 17; ++p) {
        snprintf(buf, sizeof buf, "%.*e", p - 1, x);
        if (strtod(buf, NULL) == x)
            break;
    }
    if (p == 17)
        snprintf(buf, sizeof buf, "%.16e", x);
    o->neg = buf[0] == '-';
    o->d = 0;
    o->n = 0;
    const char *s = buf;
    for (; *s != 'e'; ++s)
        if (*s >= '0' && *s <= '9') {
            o->d = o->d * 10 + (uint64_t)(*s - '0');
            ++o->n;
        }
    o->x10 = atoi(s + 1);
    /* the precision reported: the first from 15 that reads back for a normal double */
    o->prec = p;
    if (fabs(x) >= DBL_MIN)
        for (o->prec = 15; o->prec < 17; ++o->prec) {
            snprintf(buf, sizeof buf, "%.*e", o->prec - 1, x);
            if (strtod(buf, NULL) == x)
                break;
        }
    while (o->n > 1 && o->d % 10 == 0) {
        o->d /= 10;
        --o->n;
    }
}

static uint64_t next(uint64_t *s)
{
    *s += 0x9E3779B97F4A7C15ULL; /* splitmix64 */
    uint64_t z = *s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* Value i of the sample: every kind in turn (raw bit patterns cover all magnitudes). */
static double sample(uint64_t *s, long i)
{
    uint64_t r = next(s);
    double x;
    switch (i % 8) {
    case 0: /* any finite bit pattern: all binades, subnormals among them */
        memcpy(&x, &r, sizeof x);
        if (!isfinite(x))
            x = 1.0 / 3.0;
        return x;
    case 1: /* subnormals */
        r &= (1ULL << 52) - 1;
        r |= (uint64_t)(i & 16) << 59;
        memcpy(&x, &r, sizeof x);
        return x;
    case 2: /* integers, also beyond 2^53 */
        return (double)(int64_t)(r >> (r % 40)) * ((r & 1) ? -1.0 : 1.0);
    case 3: /* powers of ten and their neighbours */
    {
        double p = pow(10.0, (double)((int)(r % 617) - 308));
        int step = (int)((r >> 20) % 3) - 1;
        return step ? nextafter(p, step * INFINITY) : p;
    }
    case 4: /* short decimals */
        return (double)(r % 1000000) / pow(10.0, (double)((r >> 32) % 20));
    case 5: /* the fast path's range and beyond */
        return ldexp((double)(r >> 11) / 9007199254740992.0 * 3.0 - 1.5, (int)(r % 140) - 70);
    default: /* mesh coordinates */
        return ((double)(r >> 11) / 9007199254740992.0 - 0.5) * 200.0;
    }
}

static void given_doubles_of_all_kinds_when_digits_found_then_printf_shortest(void **state)
{
    (void)state;
    const double special[] = {0.0, -0.0, 1.0, -1.0, 0.1, 0.3, 0.30000000000000004, 100.0, 1e15,
                              1e16, 1e17, 1e22, 1e23, 999999999999999.0, 123456789012345678.0,
                              DBL_MAX, -DBL_MAX, DBL_MIN, DBL_TRUE_MIN, -DBL_TRUE_MIN, 5e-324,
                              2.2250738585072009e-308, 9007199254740993.0, 2.0 / 3.0,
                              INFINITY, -INFINITY, NAN, 1e-5, 1e-4, 1.5e-5, 123456.7};
    long count = getenv("SK_TEST_QUICK") ? 200000 : 2000000;
    uint64_t seed = 20261201;
    char a[32], b[32];
    long fast_range = 0;
    for (long i = 0; i < count; ++i) {
        double x = i < (long)(sizeof special / sizeof special[0]) ? special[i] : sample(&seed, i);
        mesh_ref(b, x);
        int n = sk__fmt_shortest(a, x);
        if (strcmp(a, b))
            fail_msg("mesh %a: %s, before %s", x, a, b);
        assert_int_equal(n, (int)strlen(b));
        if (!isfinite(x) || x == 0.0) {
            sk__digits dg;
            assert_false(sk__shortest_digits(x, 1, &dg));
            continue;
        }
        sk__digits ref1;
        digits_ref(x, 1, &ref1);
        for (int min_prec = 1; min_prec <= 15; min_prec += 14) {
            sk__digits dg, ref = ref1;
            assert_true(sk__shortest_digits(x, min_prec, &dg));
            if (min_prec > 1 && fabs(x) < DBL_MIN) /* normal doubles: the same digits */
                digits_ref(x, min_prec, &ref);
            if (dg.d != ref.d || dg.n != ref.n || dg.x10 != ref.x10 || dg.neg != ref.neg ||
                dg.prec != ref.prec)
                fail_msg("digits %a (from %d): %llu/%d e%d p%d, printf %llu/%d e%d p%d", x,
                         min_prec, (unsigned long long)dg.d, dg.n, dg.x10, dg.prec,
                         (unsigned long long)ref.d, ref.n, ref.x10, ref.prec);
        }
        fast_range += fabs(x) > 1e-11 && fabs(x) < 1e15;
        if (i % 8 < 2 || i % 16 == 3) { /* the CAD scan costs up to 17 conversions: a part */
            skt_cad_real_ref(b, x);
            sk__fmt_cad(a, x);
            if (strcmp(a, b))
                fail_msg("cad %a: %s, before %s", x, a, b);
        }
    }
    assert_true(fast_range > count / 3); /* the fast path was exercised, not only the libc one */
}

static void given_special_values_then_both_styles_as_before(void **state)
{
    (void)state;
    char a[32];
    assert_int_equal(sk__fmt_shortest(a, -0.0), 2);
    assert_string_equal(a, "-0");
    sk__fmt_shortest(a, 0.0);
    assert_string_equal(a, "0");
    sk__fmt_shortest(a, 1e15);
    assert_string_equal(a, "1e+15");
    sk__fmt_shortest(a, 5e-324);
    assert_string_equal(a, "4.94065645841247e-324");
    sk__fmt_shortest(a, 0.1 + 0.2);
    assert_string_equal(a, "0.30000000000000004");
    sk__fmt_shortest(a, -1.5e-5);
    assert_string_equal(a, "-1.5e-05");
    sk__fmt_cad(a, 5e-324);
    assert_string_equal(a, "5.E-324");
    sk__fmt_cad(a, -0.0);
    assert_string_equal(a, "0.");
    sk__fmt_cad(a, 100.0);
    assert_string_equal(a, "1.E+02");
    sk__fmt_cad(a, 1e-4);
    assert_string_equal(a, "0.0001");
    sk__fmt_cad(a, INFINITY);
    assert_string_equal(a, "INF.");
    assert_int_equal(sk_format_double(a, 1234.5), 6);
    assert_string_equal(a, "1234.5");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_doubles_of_all_kinds_when_digits_found_then_printf_shortest),
        cmocka_unit_test(given_special_values_then_both_styles_as_before),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
