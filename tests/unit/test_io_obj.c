/* OBJ reader: face forms, negative indices, attributes (first corner wins), ignored statements,
 * continuation lines; errors. */
#include "io_test.h"

static void test_faces_and_attributes(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("mtllib a.mtl\no x\ng y\ns off\nusemtl m\n"
                           "v 0 0 0\nv 1 0 0 1.0\nv 0 1 0 0.1 0.2 0.3\nv 0 0 1\n"
                           "vt 0.5 0.25\nvt 1\nvt 0 1 0\nvn 0 0 1\nvn 0 1 0\n"
                           "f 1 2 3\nf 1/1 2/2 4/3\nf 1//2 3//1 4//2\nf 2/3/1 3/2/2 4/1/1\n"
                           "f -4 -2 -1\nl 1 2\np 1\nunknown stuff\n", "a.obj", SK_FORMAT_OBJ);
    assert_int_equal(s->num_vertices, 4);
    assert_int_equal(s->num_faces, 5);
    iot_assert_face(s, 4, (uint32_t[]){0, 2, 3}, 3);
    assert_non_null(s->uvs);
    assert_non_null(s->normals);
    /* vertex 1 (index 0): first uv from face 1 corner vt 1, first normal from face 2 vn 2 */
    iot_assert_vec(s->uvs, (double[]){0.5, 0.25}, 2);
    iot_assert_vec(s->normals, (double[]){0, 1, 0}, 3);
    /* vertex 2: vt 2 = (1, 0) from face 1 (face 3's vt 3 is a seam: dropped) */
    iot_assert_vec(s->uvs + 2, (double[]){1, 0}, 2);
    iot_assert_vec(s->normals + 3, (double[]){0, 0, 1}, 3);
    /* vertex 3: first uv at face 3 (vt 2), first normal face 2 (vn 1) */
    iot_assert_vec(s->uvs + 4, (double[]){1, 0}, 2);
    iot_assert_vec(s->normals + 6, (double[]){0, 0, 1}, 3);
    iot_assert_vec(s->positions + 6, (double[]){0, 1, 0}, 3);
    sk_soup_destroy(&s);
}

static void test_plain_has_no_attributes(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1 2 3\n", "p.obj",
                           SK_FORMAT_OBJ);
    assert_null(s->normals);
    assert_null(s->uvs);
    sk_soup_destroy(&s);
}

static void test_continuation_and_line_ends(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("v 0 0 0\r\nv 1 \\\n 2 3\rv 0 1 0\nf 1 \\\r\n2 3 \\\n\n", "c.obj",
                           SK_FORMAT_OBJ);
    assert_int_equal(s->num_vertices, 3);
    iot_assert_vec(s->positions + 3, (double[]){1, 2, 3}, 3);
    iot_assert_face(s, 0, (uint32_t[]){0, 1, 2}, 3);
    sk_soup_destroy(&s);
    /* the line number after continuations is right */
    iot_bad("v 0 0 0\nv 1 \\\n0 0\nv 0 1 0\nf 1 2 7\n", "c.obj", SK_FORMAT_OBJ, "c.obj:5:");
}

static void test_polygon(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 2 0\nf 1 2 3 4 5\n", "p.obj",
                           SK_FORMAT_OBJ);
    iot_assert_face(s, 0, (uint32_t[]){0, 1, 2, 3, 4}, 5);
    sk_soup_destroy(&s);
}

static void test_errors(void **state)
{
    (void)state;
    iot_bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "two.obj", SK_FORMAT_OBJ,
            "two.obj:4: face 0 has only 2 vertices");
    iot_bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "r.obj", SK_FORMAT_OBJ,
            "r.obj:4: face 0 has index 9");
    iot_bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "n.obj", SK_FORMAT_OBJ, "index -4");
    iot_bad("v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", "i.obj", SK_FORMAT_OBJ,
            "i.obj:2: vertex 2 has a non-finite value");
    iot_bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n", "b.obj", SK_FORMAT_OBJ, "b.obj:4:");
    iot_bad("v 0 0\n", "s.obj", SK_FORMAT_OBJ, "s.obj:1: vertex 1 has 2 values");
    iot_bad("v 0 0 0\nvn 1 0\n", "vn.obj", SK_FORMAT_OBJ, "vn.obj:2: normal 1");
    iot_bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "vt.obj", SK_FORMAT_OBJ,
            "texture index 1");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_faces_and_attributes),
        cmocka_unit_test(test_plain_has_no_attributes),
        cmocka_unit_test(test_continuation_and_line_ends),
        cmocka_unit_test(test_polygon),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
