/* Text writers on two threads (issue 15): sk__out_rows writes the same bytes as the plain loop,
 * and every text writer, given more rows than it formats on one thread, writes what formatting
 * each row by hand with sk_format_double gives, which reads back bit for bit. */
#include "io_test.h"

#include "core/internal.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>

/* More vertices and faces than sk__out_rows formats on one thread, and not a multiple of its
 * rounds: W x H grid vertices, two triangles per cell except every 7th cell, a quad. */
#define W 401
#define H 263

/* Awkward doubles: tenths, -0, the smallest normal and subnormal, huge, integers at and beyond
 * 2^53, thirds, values near powers of ten. */
static double awkward(size_t i, int k)
{
    static const double table[] = {-0.0, 1e-300, 5e-324, 2.2250738585072014e-308, 1e300,
                                   -1.7976931348623157e308, 9007199254740993.0, 1e15, 1e16,
                                   123456789012345678.0, 0.3, 1e-5, 9.999999999999999e22, 0};
    size_t nt = sizeof table / sizeof table[0];
    size_t j = i * 3 + (size_t)k;
    switch (j % 5) {
    case 0: return 0.1 * (double)j;
    case 1: return table[j / 5 % nt];
    case 2: return -(double)j / 3.0;
    case 3: return (double)(j % 1000) - 500.0;
    default: return sqrt((double)j) * 1e-7;
    }
}

static sk_soup *make_grid(void)
{
    sk_soup *s = NULL;
    assert_int_equal(sk_soup_create(W * H, 2 * W * H, 6 * W * H, true, true, &s, NULL), SK_OK);
    for (size_t v = 0; v < (size_t)W * H; ++v) {
        double p[3], n[3], uv[2];
        for (int k = 0; k < 3; ++k) {
            p[k] = awkward(v, k);
            n[k] = awkward(v + 7, k) / 7.0;
        }
        uv[0] = awkward(v + 11, 0) * 0.5;
        uv[1] = awkward(v + 13, 1);
        assert_int_equal(sk_soup_push_vertex(s, p, n, uv), SK_OK);
    }
    for (uint32_t y = 0; y + 1 < H; ++y)
        for (uint32_t x = 0; x + 1 < W; ++x) {
            uint32_t a = y * W + x, b = a + 1, c = a + W + 1, d = a + W;
            if ((y * W + x) % 7 == 0) {
                assert_int_equal(sk_soup_push_face(s, (uint32_t[]){a, b, c, d}, 4), SK_OK);
                continue;
            }
            assert_int_equal(sk_soup_push_face(s, (uint32_t[]){a, b, c}, 3), SK_OK);
            assert_int_equal(sk_soup_push_face(s, (uint32_t[]){a, c, d}, 3), SK_OK);
        }
    return s;
}

/* ---- the expected text, written one value at a time ---- */

typedef struct text {
    char *a;
    size_t n, cap;
} text;

static void put(text *t, const char *s, size_t n)
{
    if (t->n + n > t->cap) {
        t->cap = (t->n + n) * 2;
        t->a = realloc(t->a, t->cap);
        assert_non_null(t->a);
    }
    memcpy(t->a + t->n, s, n);
    t->n += n;
}

static void put_s(text *t, const char *s) { put(t, s, strlen(s)); }

static void put_u(text *t, uint64_t u)
{
    char b[24];
    put(t, b, (size_t)snprintf(b, sizeof b, "%llu", (unsigned long long)u));
}

/* sep, then each of the n values separated by one blank. */
static void put_d(text *t, const char *sep, const double *x, int n)
{
    for (int k = 0; k < n; ++k) {
        char b[32];
        put_s(t, k ? " " : sep);
        put(t, b, (size_t)sk_format_double(b, x[k]));
    }
}

static void expect_obj(const sk_soup *s, text *t)
{
    put_s(t, "# written by surfkit\n");
    const char *kw[3] = {"v", "vt", "vn"};
    const double *x[3] = {s->positions, s->uvs, s->normals};
    int dim[3] = {3, 2, 3};
    for (int a = 0; a < 3; ++a)
        for (size_t v = 0; v < s->num_vertices; ++v) {
            put_s(t, kw[a]);
            put_d(t, " ", x[a] + (size_t)dim[a] * v, dim[a]);
            put_s(t, "\n");
        }
    for (size_t f = 0; f < s->num_faces; ++f) {
        put_s(t, "f");
        for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; ++c)
            for (int a = 0; a < 3; ++a) {
                put_s(t, a ? "/" : " ");
                put_u(t, (uint64_t)s->face_indices[c] + 1);
            }
        put_s(t, "\n");
    }
}

/* OFF and ASCII PLY: the same vertex and face lines. */
static void expect_rows(const sk_soup *s, text *t)
{
    for (size_t v = 0; v < s->num_vertices; ++v) {
        put_d(t, "", s->positions + 3 * v, 3);
        put_d(t, " ", s->normals + 3 * v, 3);
        put_d(t, " ", s->uvs + 2 * v, 2);
        put_s(t, "\n");
    }
    for (size_t f = 0; f < s->num_faces; ++f) {
        put_u(t, s->face_offsets[f + 1] - s->face_offsets[f]);
        for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; ++c) {
            put_s(t, " ");
            put_u(t, s->face_indices[c]);
        }
        put_s(t, "\n");
    }
}

static void expect_off(const sk_soup *s, text *t)
{
    put_s(t, "STNOFF\n");
    put_u(t, s->num_vertices);
    put_s(t, " ");
    put_u(t, s->num_faces);
    put_s(t, " 0\n");
    expect_rows(s, t);
}

static void expect_ply(const sk_soup *s, text *t)
{
    put_s(t, "ply\nformat ascii 1.0\ncomment written by surfkit\nelement vertex ");
    put_u(t, s->num_vertices);
    put_s(t, "\nproperty double x\nproperty double y\nproperty double z\n"
             "property double nx\nproperty double ny\nproperty double nz\n"
             "property double s\nproperty double t\nelement face ");
    put_u(t, s->num_faces);
    put_s(t, "\nproperty list uchar int vertex_indices\nend_header\n");
    expect_rows(s, t);
}

/* ---- the checks ---- */

static void *write_text(const sk_soup *s, sk_format fmt, size_t *size)
{
    sk_write_opts o = {.format = fmt, .ascii = true};
    void *data = NULL;
    sk_error e = {0};
    if (sk_soup_write_memory(s, &o, &data, size, &e) != SK_OK)
        fail_msg("%s: %s", sk_format_name(fmt), e.message);
    return data;
}

/* The first differing byte, with the line around it, so that a failure shows which row. */
static void assert_same_text(const char *got, size_t ng, const text *want, const char *what)
{
    size_t n = ng < want->n ? ng : want->n, i = 0;
    while (i < n && got[i] == want->a[i])
        ++i;
    if (i == n && ng == want->n)
        return;
    size_t from = i;
    while (from > 0 && want->a[from - 1] != '\n')
        --from;
    fail_msg("%s: %zu bytes, expected %zu; first difference at byte %zu, line '%.60s' "
             "expected '%.60s'", what, ng, want->n, i, got + from, want->a + from);
}

static void assert_bits(const double *a, const double *b, size_t n, const char *what)
{
    for (size_t i = 0; i < n; ++i)
        if (memcmp(&a[i], &b[i], sizeof a[i]) != 0)
            fail_msg("%s: value %zu read back as %.17g, written %.17g", what, i, b[i], a[i]);
}

static void assert_reads_back(const sk_soup *s, const void *data, size_t size, sk_format fmt)
{
    sk_soup *r = iot_parse_n(data, size, sk_format_name(fmt), fmt);
    assert_int_equal(r->num_vertices, s->num_vertices);
    assert_int_equal(r->num_faces, s->num_faces);
    assert_non_null(r->normals);
    assert_non_null(r->uvs);
    assert_bits(s->positions, r->positions, 3 * s->num_vertices, "positions");
    assert_bits(s->normals, r->normals, 3 * s->num_vertices, "normals");
    assert_bits(s->uvs, r->uvs, 2 * s->num_vertices, "uvs");
    assert_memory_equal(s->face_offsets, r->face_offsets, (s->num_faces + 1) * sizeof(uint32_t));
    assert_memory_equal(s->face_indices, r->face_indices,
                        s->face_offsets[s->num_faces] * sizeof(uint32_t));
    sk_soup_destroy(&r);
}

static void check_format(sk_format fmt, void (*expect)(const sk_soup *, text *))
{
    /* given a grid with more rows than one thread formats */
    sk_soup *s = make_grid();
    text want = {0};
    expect(s, &want);
    /* when it is written as text */
    size_t size = 0;
    char *got = write_text(s, fmt, &size);
    /* then it is the row-by-row text, and reads back bit for bit */
    assert_same_text(got, size, &want, sk_format_name(fmt));
    assert_reads_back(s, got, size, fmt);
    free(got);
    free(want.a);
    sk_soup_destroy(&s);
}

static void test_obj(void **state)
{
    (void)state;
    check_format(SK_FORMAT_OBJ, expect_obj);
}

static void test_off(void **state)
{
    (void)state;
    check_format(SK_FORMAT_OFF, expect_off);
}

static void test_ascii_ply(void **state)
{
    (void)state;
    check_format(SK_FORMAT_PLY, expect_ply);
}

/* ASCII STL: the reference is the mesh written in slices of faces, each below the one-thread
 * size, concatenated without their solid / endsolid lines. */
static void test_ascii_stl(void **state)
{
    (void)state;
    sk_soup *s = make_grid();
    text want = {0};
    put_s(&want, "solid surfkit\n");
    const size_t slice = 10000, head = strlen("solid surfkit\n");
    const size_t tail = strlen("endsolid surfkit\n");
    for (size_t f0 = 0; f0 < s->num_faces; f0 += slice) {
        size_t f1 = f0 + slice < s->num_faces ? f0 + slice : s->num_faces;
        sk_soup *part = NULL;
        assert_int_equal(sk_soup_create(s->num_vertices, f1 - f0, 0, false, false, &part, NULL),
                         SK_OK);
        for (size_t v = 0; v < s->num_vertices; ++v)
            assert_int_equal(sk_soup_push_vertex(part, s->positions + 3 * v, NULL, NULL), SK_OK);
        for (size_t f = f0; f < f1; ++f)
            assert_int_equal(sk_soup_push_face(part, s->face_indices + s->face_offsets[f],
                                               sk_soup_face_size(s, f)), SK_OK);
        size_t n = 0;
        char *d = write_text(part, SK_FORMAT_STL, &n);
        assert_true(n >= head + tail);
        put(&want, d + head, n - head - tail);
        free(d);
        sk_soup_destroy(&part);
    }
    put_s(&want, "endsolid surfkit\n");
    size_t size = 0;
    char *got = write_text(s, SK_FORMAT_STL, &size);
    assert_same_text(got, size, &want, "ascii STL");
    free(got);
    free(want.a);
    sk_soup_destroy(&s);
}

/* ---- sk__out_rows itself ---- */

/* Rows of varying length: "i:" and i % 9 copies of a formatted double. */
static void row(sk__out *o, size_t i, const void *ctx)
{
    const double *scale = ctx;
    sk__out_uint(o, i);
    sk__out_char(o, ':');
    for (size_t k = 0; k < i % 9; ++k) {
        sk__out_char(o, ' ');
        sk__out_double(o, (double)i * *scale + (double)k);
    }
    sk__out_char(o, '\n');
}

/* The helper against the plain loop, to memory and through a FILE (flushes in between). */
static void check_rows(size_t n)
{
    double scale = 0.1;
    sk__out loop = {0}, rows = {0}, file = {0};
    for (size_t i = 0; i < n; ++i)
        row(&loop, i, &scale);
    sk__out_rows(&rows, n, row, &scale);
    assert_int_equal(loop.failed, 0);
    assert_int_equal(rows.failed, 0);
    assert_int_equal(rows.len, loop.len);
    assert_memory_equal(rows.buf, loop.buf, loop.len);
    file.fp = tmpfile();
    assert_non_null(file.fp);
    sk__out_str(&file, "head\n");
    sk__out_rows(&file, n, row, &scale);
    sk__out_flush(&file);
    assert_int_equal(file.failed, 0);
    assert_int_equal(ftell(file.fp), (long)(loop.len + 5));
    rewind(file.fp);
    char *back = malloc(loop.len + 5);
    assert_non_null(back);
    assert_int_equal(fread(back, 1, loop.len + 5, file.fp), loop.len + 5);
    assert_memory_equal(back, "head\n", 5);
    assert_memory_equal(back + 5, loop.buf, loop.len);
    free(back);
    fclose(file.fp);
    sk__out_free(&loop);
    sk__out_free(&rows);
    sk__out_free(&file);
}

static void test_rows_sizes(void **state)
{
    (void)state;
    /* around the one-thread limit (1 << 15) and the rounds (1 << 16) */
    const size_t n[] = {0, 1, 1000, 32767, 32768, 32769, 65535, 65536, 65537, 200003};
    for (size_t i = 0; i < sizeof n / sizeof n[0]; ++i)
        check_rows(n[i]);
}

/* A buffer that has failed stays failed and gets no more rows. */
static void test_rows_after_failure(void **state)
{
    (void)state;
    double scale = 0.1;
    sk__out o = {0};
    o.failed = SK_ERR_NOMEM;
    sk__out_rows(&o, 100000, row, &scale);
    assert_int_equal(o.failed, SK_ERR_NOMEM);
    assert_int_equal(o.len, 0);
    sk__out_free(&o);
}

/* An allocator that fails every allocation of a thread other than the test's. */
static pthread_t test_thread;

static bool on_test_thread(void) { return pthread_equal(pthread_self(), test_thread); }

static void *main_only_malloc(void *user, size_t n)
{
    (void)user;
    return on_test_thread() ? malloc(n) : NULL;
}

static void *main_only_realloc(void *user, void *p, size_t n)
{
    (void)user;
    return on_test_thread() ? realloc(p, n) : NULL;
}

static void plain_free(void *user, void *p)
{
    (void)user;
    free(p);
}

/* The second thread's buffer cannot grow: the output fails with SK_ERR_NOMEM. */
static void test_rows_second_thread_nomem(void **state)
{
    (void)state;
    test_thread = pthread_self();
    sk_set_allocator(&(sk_allocator){main_only_malloc, main_only_realloc, plain_free, NULL});
    double scale = 0.1;
    sk__out o = {0};
    sk__out_rows(&o, 100000, row, &scale);
    int failed = o.failed;
    sk__out_free(&o);
    sk_set_allocator(NULL);
    assert_int_equal(failed, SK_ERR_NOMEM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_sizes), cmocka_unit_test(test_rows_after_failure),
        cmocka_unit_test(test_rows_second_thread_nomem),
        cmocka_unit_test(test_obj),        cmocka_unit_test(test_off),
        cmocka_unit_test(test_ascii_ply),  cmocka_unit_test(test_ascii_stl),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
