/* PLY reader: ascii and both binary byte orders, every scalar type, optional attributes, skipped
 * properties and elements; errors with lines or byte offsets. */
#include "io_test.h"

/* A binary file built in memory. */
typedef struct buf {
    unsigned char b[4096];
    size_t n;
    bool be;
} buf;

static void put(buf *w, const void *x, size_t k)
{
    const unsigned char *c = x;
    for (size_t i = 0; i < k; ++i)
        w->b[w->n + i] = c[w->be ? k - 1 - i : i]; /* host is little endian (x86) */
    w->n += k;
}

static void put_str(buf *w, const char *s)
{
    memcpy(w->b + w->n, s, strlen(s));
    w->n += strlen(s);
}

static void test_ascii(void **state)
{
    (void)state;
    sk_soup *s = iot_parse("ply\r\nformat ascii 1.0\r\ncomment c\r\nobj_info o\r\n"
                           "element vertex 3\r\nproperty float x\r\nproperty float y\r\n"
                           "property float z\r\nproperty float nx\r\nproperty float ny\r\n"
                           "property float nz\r\nproperty float texture_u\r\n"
                           "property float texture_v\r\nelement face 1\r\n"
                           "property list uchar int vertex_indices\r\nend_header\r\n"
                           "0 0 0 0 0 1 0.5 0.25\r\n1 0 0 0 0 1 1 0\r\n0 1 0 0 0 1 0 1\r\n"
                           "3 0 1 2\r\n", "a.ply", SK_FORMAT_PLY);
    assert_int_equal(s->num_vertices, 3);
    assert_int_equal(s->num_faces, 1);
    iot_assert_vec(s->positions + 3, (double[]){1, 0, 0}, 3);
    iot_assert_vec(s->normals, (double[]){0, 0, 1}, 3);
    iot_assert_vec(s->uvs, (double[]){0.5, 0.25}, 2);
    sk_soup_destroy(&s);
}

/* Vertex with every scalar type (x as char ... ), an ignored list property, an unknown element
 * before and after, faces with ushort counts and uint16 indices. */
static void binary_all_types(bool be)
{
    buf w = {.be = be};
    put_str(&w, be ? "ply\nformat binary_big_endian 1.0\n"
                   : "ply\nformat binary_little_endian 1.0\n");
    put_str(&w, "element header_stuff 2\nproperty int a\nproperty list uchar double b\n"
                "element vertex 3\nproperty char x\nproperty ushort y\nproperty float64 z\n"
                "property uint8 red\nproperty list int16 float junk\n"
                "property int nx\nproperty uint ny\nproperty short nz\nproperty float u\n"
                "property double v\n"
                "element face 2\nproperty uchar flag\nproperty list ushort uint16 vertex_index\n"
                "element tail 1\nproperty float q\nend_header\n");
    for (int i = 0; i < 2; ++i) {
        int32_t a = i;
        uint8_t c = 2;
        double d[2] = {1.5, -2.5};
        put(&w, &a, 4);
        put(&w, &c, 1);
        put(&w, &d[0], 8);
        put(&w, &d[1], 8);
    }
    for (int v = 0; v < 3; ++v) {
        int8_t x = (int8_t)(-v);
        uint16_t y = (uint16_t)(60000 + v);
        double z = 0.1 * v;
        uint8_t red = 9;
        int16_t nj = (int16_t)v;
        int32_t nx = -v;
        uint32_t ny = 4000000000u;
        int16_t nz = -300;
        float u = 0.25f * (float)v;
        double vv = 1.0 / 3.0;
        put(&w, &x, 1);
        put(&w, &y, 2);
        put(&w, &z, 8);
        put(&w, &red, 1);
        put(&w, &nj, 2);
        for (int k = 0; k < nj; ++k) {
            float f = 7;
            put(&w, &f, 4);
        }
        put(&w, &nx, 4);
        put(&w, &ny, 4);
        put(&w, &nz, 2);
        put(&w, &u, 4);
        put(&w, &vv, 8);
    }
    for (int f = 0; f < 2; ++f) {
        uint8_t flag = 1;
        uint16_t n = (uint16_t)(f == 0 ? 3 : 4), idx[4] = {0, 1, 2, 0};
        put(&w, &flag, 1);
        put(&w, &n, 2);
        for (int k = 0; k < n; ++k)
            put(&w, &idx[k], 2);
    }
    float q = 1;
    put(&w, &q, 4);

    sk_soup *s = iot_parse_n(w.b, w.n, "t.ply", SK_FORMAT_PLY);
    assert_int_equal(s->num_vertices, 3);
    assert_int_equal(s->num_faces, 2);
    iot_assert_vec(s->positions + 6, (double[]){-2, 60002, 0.1 * 2}, 3);
    iot_assert_vec(s->normals + 3, (double[]){-1, 4000000000.0, -300}, 3);
    iot_assert_vec(s->uvs + 4, (double[]){0.5, 1.0 / 3.0}, 2);
    iot_assert_face(s, 1, (uint32_t[]){0, 1, 2, 0}, 4);
    sk_soup_destroy(&s);

    /* every truncation is an error naming a byte offset */
    for (size_t n = 0; n < w.n; n += 7) {
        sk_read_opts o = {SK_FORMAT_PLY};
        sk_error e = {0};
        assert_int_equal(sk_soup_read_memory(w.b, n, "t.ply", &o, &s, &e), SK_ERR_PARSE);
        assert_int_equal(strncmp(e.message, "t.ply:", 6), 0);
    }
}

static void test_binary_le(void **state)
{
    (void)state;
    binary_all_types(false);
}

static void test_binary_be(void **state)
{
    (void)state;
    binary_all_types(true);
}

static void test_errors(void **state)
{
    (void)state;
    const char *head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\n"
                       "property list uchar int vertex_indices\nend_header\n";
    char text[1024];
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", head);
    iot_bad(text, "r.ply", SK_FORMAT_PLY, "r.ply:13: face 0 has index 3 but the file has 3 "
            "vertices");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n0 1 0\n2 0 1\n", head);
    iot_bad(text, "s.ply", SK_FORMAT_PLY, "s.ply:13: face 0 has only 2 vertices");
    snprintf(text, sizeof text, "%s0 0 0\n1 -nan 0\n0 1 0\n3 0 1 2\n", head);
    iot_bad(text, "n.ply", SK_FORMAT_PLY, "n.ply:11: vertex 1 has a non-finite value");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n", head);
    iot_bad(text, "t.ply", SK_FORMAT_PLY, "t.ply:");
    iot_bad("ply\nformat binary_little_endian 1.0\nelement vertex 100000000\n"
            "property double x\nproperty double y\nproperty double z\nend_header\n0123",
            "h.ply", SK_FORMAT_PLY, "h.ply: byte 126: the header declares 100000000 'vertex'");
    iot_bad("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n3 0 1 2\n", "nv.ply", SK_FORMAT_PLY, "index 0 but the file has 0");
    iot_bad("plyx\n", "m.ply", SK_FORMAT_PLY, "m.ply:1:");
}

/* Given each spelling of the texture coordinates (s t as Blender and MeshLab write, u v,
 * texture_u texture_v), when read, then the uvs are the file's; and a soup with uvs is written
 * with s t and reads back the same. */
static void test_uv_spellings(void **state)
{
    (void)state;
    const char *names[][2] = {{"s", "t"}, {"u", "v"}, {"texture_u", "texture_v"}};
    for (int k = 0; k < 3; ++k) {
        char text[512];
        snprintf(text, sizeof text,
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nproperty float %s\nproperty float %s\nelement face 1\n"
                 "property list uchar int vertex_indices\nend_header\n"
                 "0 0 0 0.25 0.5\n1 0 0 1 0.125\n0 1 0 0 1\n3 0 1 2\n",
                 names[k][0], names[k][1]);
        sk_soup *s = iot_parse(text, "uv.ply", SK_FORMAT_PLY);
        assert_non_null(s->uvs);
        iot_assert_vec(s->uvs, (double[]){0.25, 0.5, 1, 0.125, 0, 1}, 6);
        sk_write_opts wo = {.format = SK_FORMAT_PLY, .ascii = k == 0};
        void *data = NULL;
        size_t size = 0;
        assert_int_equal(sk_soup_write_memory(s, &wo, &data, &size, NULL), SK_OK);
        char hdr[512] = {0}; /* the header, NUL-terminated */
        memcpy(hdr, data, size < sizeof hdr - 1 ? size : sizeof hdr - 1);
        char *hdr_end = strstr(hdr, "end_header");
        assert_non_null(hdr_end);
        *hdr_end = '\0';
        assert_non_null(strstr(hdr, "property double s\nproperty double t\n"));
        assert_null(strstr(hdr, "property double u\n"));
        sk_soup *r = iot_parse_n(data, size, "back.ply", SK_FORMAT_PLY);
        iot_assert_vec(r->uvs, s->uvs, 6);
        sk_soup_destroy(&r);
        free(data);
        sk_soup_destroy(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ascii),
        cmocka_unit_test(test_binary_le),
        cmocka_unit_test(test_binary_be),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_uv_spellings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
