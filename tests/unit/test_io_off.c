/* OFF reader: every header variant, comments, line endings, values; errors name line and what. */
#include "io_test.h"

static const char *tet = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                         "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

static void test_plain(void **state)
{
    (void)state;
    sk_soup *s = iot_parse(tet, "tet.off", SK_FORMAT_OFF);
    assert_int_equal(s->num_vertices, 4);
    assert_int_equal(s->num_faces, 4);
    assert_null(s->normals);
    assert_null(s->uvs);
    iot_assert_vec(s->positions + 3, (double[]){1, 0, 0}, 3);
    iot_assert_face(s, 2, (uint32_t[]){1, 2, 3}, 3);
    sk_soup_destroy(&s);
}

static void test_numbers(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("OFF\n3 1\n-0.129196 +1.5e3 .25\n1e-5 -2.5E+2 0.1\n"
                           "123456789012345678901234567890 4.9406564584124654e-324 -0\n3 0 1 2\n",
                           "n.off", SK_FORMAT_OFF);
    iot_assert_vec(s->positions, (double[]){-0.129196, 1500, 0.25, 1e-5, -250, 0.1,
                                           123456789012345678901234567890.0,
                                           4.9406564584124654e-324, 0}, 9);
    sk_soup_destroy(&s);
}

static void test_header_variants(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("OFF 4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n", "a.off",
                           SK_FORMAT_OFF);
    assert_int_equal(s->num_vertices, 4);
    sk_soup_destroy(&s);
    s = iot_parse("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "noheader.off", SK_FORMAT_OFF);
    assert_int_equal(s->num_faces, 1);
    sk_soup_destroy(&s);
    /* NOFF: normals after the position */
    s = iot_parse("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 1 0\n0 1 0 1 0 0\n3 0 1 2\n", "n.off",
                  SK_FORMAT_OFF);
    assert_non_null(s->normals);
    iot_assert_vec(s->normals + 3, (double[]){0, 1, 0}, 3);
    sk_soup_destroy(&s);
    /* STOFF: uvs; CNOFF: colours ignored; STCNOFF: uv are the last two values */
    s = iot_parse("STOFF\n3 1 0\n0 0 0 0.5 0.25\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", "st.off",
                  SK_FORMAT_OFF);
    assert_non_null(s->uvs);
    iot_assert_vec(s->uvs, (double[]){0.5, 0.25}, 2);
    sk_soup_destroy(&s);
    s = iot_parse("CNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1\n1 0 0 0 0 1 0.5 0.5 0.5\n"
                  "0 1 0 0 0 1 0 0 0 0\n3 0 1 2 255 0 0\n", "cn.off", SK_FORMAT_OFF);
    assert_non_null(s->normals);
    assert_null(s->uvs);
    iot_assert_vec(s->normals + 6, (double[]){0, 0, 1}, 3);
    sk_soup_destroy(&s);
    s = iot_parse("STCNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1 0.125 0.75\n1 0 0 0 0 1 1 1 1 0 0\n"
                  "0 1 0 0 0 1 1 1 1 0 1\n3 0 1 2\n", "stcn.off", SK_FORMAT_OFF);
    iot_assert_vec(s->uvs, (double[]){0.125, 0.75}, 2);
    sk_soup_destroy(&s);
}

static void test_comments_and_line_ends(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("# c\r\nOFF # x\r\n\r\n4 4 0 # counts\r0 0 0\r1 0 0 # v\n0 1 0\r\n"
                           "0 0 1\n# faces\n3 0 2 1\r3 0 1 3\r\n3 1 2 3\n3 0 3 2", "le.off",
                           SK_FORMAT_OFF);
    assert_int_equal(s->num_vertices, 4);
    assert_int_equal(s->num_faces, 4);
    iot_assert_face(s, 3, (uint32_t[]){0, 3, 2}, 3);
    sk_soup_destroy(&s);
}

static void test_polygons_any_size(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("OFF\n6 2 0\n0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 2 0\n-1 1 0\n"
                           "6 0 1 2 3 4 5\n4 0 1 2 3 0.1 0.2 0.3\n", "p.off", SK_FORMAT_OFF);
    iot_assert_face(s, 0, (uint32_t[]){0, 1, 2, 3, 4, 5}, 6);
    iot_assert_face(s, 1, (uint32_t[]){0, 1, 2, 3}, 4);
    sk_soup_destroy(&s);
}

static void test_errors(void **state)
{
    (void)state;
    iot_bad("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 9001\n3 0 3 2\n",
            "lion.off", SK_FORMAT_OFF, "lion.off:9: face 2 has index 9001 but the file has 4 "
            "vertices");
    iot_bad("OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "nan.off", SK_FORMAT_OFF,
            "nan.off:4: vertex 1");
    iot_bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "small.off", SK_FORMAT_OFF,
            "small.off:6: face 0 has only 2 vertices");
    iot_bad("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "short.off", SK_FORMAT_OFF,
            "short.off:7: the file ends after 1 of 2 faces");
    iot_bad("OFF\n999999999999 1 0\n0 0 0\n", "huge.off", SK_FORMAT_OFF, "huge.off:2:");
    iot_bad("OFF\n3 1 0\n0 0 0 1\n1 0 0\n0 1 0\n3 0 1 2\n", "extra.off", SK_FORMAT_OFF,
            "extra.off:3: vertex 0 has 4 values");
    iot_bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", "more.off", SK_FORMAT_OFF,
            "more.off:7:");
    iot_bad("", "empty.off", SK_FORMAT_OFF, "empty file");
    iot_bad("OFF\n3 1 0\n0 0 0\r1 0 0\r0 1 0\r3 0 1 x\r", "cr.off", SK_FORMAT_OFF,
            "cr.off:6: face 0");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plain),
        cmocka_unit_test(test_numbers),
        cmocka_unit_test(test_header_variants),
        cmocka_unit_test(test_comments_and_line_ends),
        cmocka_unit_test(test_polygons_any_size),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
