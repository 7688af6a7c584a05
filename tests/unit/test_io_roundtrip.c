/* Round trips: every shared mesh, read from OFF, written in every format, read back, compared
 * exactly (text formats write enough digits, binary PLY stores doubles; binary STL stores floats,
 * so its coordinates are compared with the float-rounded originals). */
#define _POSIX_C_SOURCE 200809L
#include "io_test.h"

#include <dirent.h>
#include <math.h>
#include <unistd.h>

typedef struct cfg {
    const char *label;
    sk_format format;
    bool ascii;
} cfg;

static const cfg configs[] = {
    {"OFF", SK_FORMAT_OFF, false},        {"OBJ", SK_FORMAT_OBJ, false},
    {"binary PLY", SK_FORMAT_PLY, false}, {"ascii PLY", SK_FORMAT_PLY, true},
    {"binary STL", SK_FORMAT_STL, false}, {"ascii STL", SK_FORMAT_STL, true},
};

/* Gives the soup normals and uvs that are awkward decimals (non-terminating in binary). */
static void add_attributes(sk_soup *s)
{
    assert_int_equal(sk_soup_add_normals(s), SK_OK);
    assert_int_equal(sk_soup_add_uvs(s), SK_OK);
    for (size_t v = 0; v < s->num_vertices; ++v) {
        const double *p = s->positions + 3 * v;
        s->normals[3 * v] = p[0] / 3.0;
        s->normals[3 * v + 1] = -p[1] / 7.0;
        s->normals[3 * v + 2] = sqrt(fabs(p[2])) + 1e-300;
        s->uvs[2 * v] = p[0] * 0.1 + 1.0 / 3.0;
        s->uvs[2 * v + 1] = (double)v / 9.0;
    }
}

static void compare_indexed(const sk_soup *a, const sk_soup *b, bool attrs, const char *what)
{
    if (a->num_vertices != b->num_vertices || a->num_faces != b->num_faces)
        fail_msg("%s: counts %zu/%zu became %zu/%zu", what, a->num_vertices, a->num_faces,
                 b->num_vertices, b->num_faces);
    assert_memory_equal(a->positions, b->positions, 3 * a->num_vertices * sizeof(double));
    assert_memory_equal(a->face_offsets, b->face_offsets, (a->num_faces + 1) * sizeof(uint32_t));
    assert_memory_equal(a->face_indices, b->face_indices,
                        a->face_offsets[a->num_faces] * sizeof(uint32_t));
    if (attrs) {
        assert_non_null(b->normals);
        assert_non_null(b->uvs);
        assert_memory_equal(a->normals, b->normals, 3 * a->num_vertices * sizeof(double));
        assert_memory_equal(a->uvs, b->uvs, 2 * a->num_vertices * sizeof(double));
    }
}

/* STL: one triangle per face (the meshes are triangles), corners compared by position. */
static void compare_stl(const sk_soup *a, const sk_soup *b, bool as_float, const char *what)
{
    if (a->num_faces != b->num_faces)
        fail_msg("%s: %zu faces became %zu", what, a->num_faces, b->num_faces);
    assert_true(b->num_vertices <= a->num_vertices);
    for (size_t f = 0; f < a->num_faces; ++f) {
        assert_int_equal(sk_soup_face_size(b, f), 3);
        for (int c = 0; c < 3; ++c) {
            const double *pa = a->positions + 3 * a->face_indices[a->face_offsets[f] + c];
            const double *pb = b->positions + 3 * b->face_indices[b->face_offsets[f] + c];
            for (int k = 0; k < 3; ++k) {
                double want = as_float ? (double)(float)pa[k] : pa[k];
                if (pb[k] != want + 0.0)
                    fail_msg("%s: face %zu corner %d: %.17g != %.17g", what, f, c, pb[k], want);
            }
        }
    }
}

static void roundtrip_one(const sk_soup *orig, const char *name, bool attrs)
{
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; ++i) {
        const cfg *c = &configs[i];
        char what[256];
        snprintf(what, sizeof what, "%s as %s%s", name, c->label, attrs ? " with attributes" : "");
        sk_write_opts wo = {.format = c->format, .ascii = c->ascii};
        void *data = NULL;
        size_t size = 0;
        sk_error e = {0};
        if (sk_soup_write_memory(orig, &wo, &data, &size, &e) != SK_OK)
            fail_msg("%s: write: %s", what, e.message);
        sk_soup *back = iot_parse_n(data, size, name, c->format);
        if (c->format == SK_FORMAT_STL)
            compare_stl(orig, back, !c->ascii, what);
        else
            compare_indexed(orig, back, attrs, what);
        sk_soup_destroy(&back);
        /* the same bytes are recognised by content alone */
        sk_read_opts ro = {SK_FORMAT_AUTO};
        assert_int_equal(sk_soup_read_memory(data, size, "noext", &ro, &back, &e), SK_OK);
        sk_soup_destroy(&back);
        free(data);
    }
}

static void test_roundtrip_shared_meshes(void **state)
{
    (void)state;
    DIR *d = opendir(IOT_SHARED_MESHES);
    assert_non_null(d);
    int count = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        size_t n = strlen(de->d_name);
        if (n < 5 || strcmp(de->d_name + n - 4, ".off") != 0)
            continue;
        sk_soup *s = NULL;
        sk_error e = {0};
        if (sk_soup_read(iot_path(IOT_SHARED_MESHES, de->d_name), NULL, &s, &e) != SK_OK)
            fail_msg("%s: %s", de->d_name, e.message);
        roundtrip_one(s, de->d_name, false);
        add_attributes(s);
        roundtrip_one(s, de->d_name, true);
        sk_soup_destroy(&s);
        ++count;
    }
    closedir(d);
    assert_true(count >= 20);
}

/* File round trip through the extension: write lion.off as every format to a file, read back. */
static void test_roundtrip_files(void **state)
{
    (void)state;
    sk_soup *s = NULL;
    sk_error e = {0};
    assert_int_equal(sk_soup_read(iot_path(IOT_SHARED_MESHES, "lion.off"), NULL, &s, &e), SK_OK);
    assert_int_equal(s->num_vertices, 7529);
    assert_int_equal(s->num_faces, 14859);
    const char *names[] = {"rt_lion.off", "rt_lion.obj", "rt_lion.ply", "rt_lion.stl"};
    for (int i = 0; i < 4; ++i) {
        const char *path = iot_path(IOT_TMP, names[i]);
        if (sk_soup_write(path, s, NULL, &e) != SK_OK)
            fail_msg("%s: %s", path, e.message);
        sk_soup *b = NULL;
        if (sk_soup_read(path, NULL, &b, &e) != SK_OK)
            fail_msg("%s: %s", path, e.message);
        assert_int_equal(b->num_faces, s->num_faces);
        if (i < 3)
            compare_indexed(s, b, false, path);
        else
            compare_stl(s, b, true, path);
        sk_soup_destroy(&b);
        remove(path);
    }
    sk_soup_destroy(&s);
}

/* A failed write leaves no file behind (neither the target nor a temporary). */
static void test_failed_write_leaves_no_file(void **state)
{
    (void)state;
    sk_soup *s = NULL;
    assert_int_equal(sk_soup_create(3, 1, 3, false, false, &s, NULL), SK_OK);
    double p[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
        assert_int_equal(sk_soup_push_vertex(s, p, NULL, NULL), SK_OK);
    uint32_t bad[3] = {0, 1, 7};
    assert_int_equal(sk_soup_push_face(s, bad, 3), SK_OK);
    const char *path = iot_path(IOT_TMP, "must_not_exist.ply");
    remove(path);
    sk_error e = {0};
    assert_int_equal(sk_soup_write(path, s, NULL, &e), SK_ERR_ARG);
    assert_non_null(strstr(e.message, "index 7"));
    assert_int_not_equal(access(path, F_OK), 0);

    /* an unwritable location: the i/o error names the path and nothing appears */
    const char *nodir = iot_path(IOT_TMP, "no/such/dir/out.off");
    s->face_indices[2] = 2;
    assert_int_equal(sk_soup_write(nodir, s, NULL, &e), SK_ERR_IO);
    assert_int_not_equal(access(nodir, F_OK), 0);

    /* no format */
    assert_int_equal(sk_soup_write(iot_path(IOT_TMP, "out.xyz"), s, NULL, &e), SK_ERR_ARG);
    assert_int_not_equal(access(iot_path(IOT_TMP, "out.xyz"), F_OK), 0);

    /* no temporary left in the folder */
    DIR *d = opendir(IOT_TMP);
    assert_non_null(d);
    struct dirent *de;
    while ((de = readdir(d)) != NULL)
        if (strstr(de->d_name, "must_not_exist") || strstr(de->d_name, "out.xyz"))
            fail_msg("left behind: %s", de->d_name);
    closedir(d);
    sk_soup_destroy(&s);
}

/* Polygons: STL fan-triangulates them, the others keep them. */
static void test_polygons(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("OFF\n6 2 0\n0 0 0\n1 0 0\n2 0.5 0\n1 1 0\n0 1 0\n0.5 0.5 1\n"
                           "5 0 1 2 3 4\n3 0 1 5\n", "poly.off", SK_FORMAT_OFF);
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; ++i) {
        sk_write_opts wo = {.format = configs[i].format, .ascii = configs[i].ascii};
        void *data;
        size_t size;
        assert_int_equal(sk_soup_write_memory(s, &wo, &data, &size, NULL), SK_OK);
        sk_soup *b = iot_parse_n(data, size, "poly", configs[i].format);
        if (configs[i].format == SK_FORMAT_STL) {
            assert_int_equal(b->num_faces, 4);
            assert_int_equal(b->num_vertices, 6);
        } else {
            compare_indexed(s, b, false, configs[i].label);
        }
        sk_soup_destroy(&b);
        free(data);
    }
    sk_soup_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roundtrip_shared_meshes),
        cmocka_unit_test(test_roundtrip_files),
        cmocka_unit_test(test_failed_write_leaves_no_file),
        cmocka_unit_test(test_polygons),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
