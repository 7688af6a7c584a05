/* STL reader: ascii and binary, vertex merging, binary files whose header says "solid". */
#include "io_test.h"

static const char *ascii_stl =
    "solid two\n"
    "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n"
    " endloop\nendfacet\n"
    "facet normal 0 0 1\n outer loop\n  vertex 1 0 0\n  vertex 1 1 0\n  vertex -0 1 0\n"
    " endloop\nendfacet\n"
    "endsolid two\n";

static void test_ascii_merges_vertices(void **state)
{
    (void)state;
    sk_soup *s = iot_parse(ascii_stl, "a.stl", SK_FORMAT_STL);
    assert_int_equal(s->num_faces, 2);
    assert_int_equal(s->num_vertices, 4); /* -0 equals 0 */
    iot_assert_face(s, 0, (uint32_t[]){0, 1, 2}, 3);
    iot_assert_face(s, 1, (uint32_t[]){1, 3, 2}, 3);
    iot_assert_vec(s->positions + 9, (double[]){1, 1, 0}, 3);
    sk_soup_destroy(&s);
}

static size_t make_binary(unsigned char *b, const char *header, uint32_t n)
{
    memset(b, ' ', 80);
    memcpy(b, header, strlen(header));
    memcpy(b + 80, &n, 4);
    const float tri[2][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}};
    for (uint32_t t = 0; t < n; ++t) {
        unsigned char *r = b + 84 + 50 * t;
        memset(r, 0, 50);
        memcpy(r + 12, tri[t % 2], 36);
    }
    return 84 + 50 * (size_t)n;
}

static void test_binary(void **state)
{
    (void)state;
    unsigned char b[84 + 50 * 2];
    size_t n = make_binary(b, "solid but binary", 2);
    sk_soup *s = iot_parse_n(b, n, "b.stl", SK_FORMAT_STL);
    assert_int_equal(s->num_faces, 2);
    assert_int_equal(s->num_vertices, 4);
    sk_soup_destroy(&s);
    /* detected by content alone too */
    s = iot_parse_n(b, n, "noext", SK_FORMAT_AUTO);
    assert_int_equal(s->num_faces, 2);
    sk_soup_destroy(&s);
    iot_bad_n(b, n - 1, "t.stl", SK_FORMAT_STL, "t.stl: byte 80:");
    iot_bad_n(b, 60, "h.stl", SK_FORMAT_STL, "h.stl:"); /* ambiguous: read as ascii */
}

static void test_ascii_errors(void **state)
{
    (void)state;
    iot_bad("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"
            "endfacet\nendsolid\n", "two.stl", SK_FORMAT_STL, "two.stl:6: facet 0 has only 2");
    iot_bad("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 inf 0\n",
            "inf.stl", SK_FORMAT_STL, "inf.stl:5: facet 0 has a non-finite coordinate");
    iot_bad("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "t.stl", SK_FORMAT_STL,
            "t.stl:");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ascii_merges_vertices),
        cmocka_unit_test(test_binary),
        cmocka_unit_test(test_ascii_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
