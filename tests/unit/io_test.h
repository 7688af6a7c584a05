/* Helpers of the io unit tests.
 *
 * These tests use only the soup functions: the testutil helpers also pull in sk_mesh_read, which
 * needs the half-edge builder (src/mesh/build.c) at link time. */
#ifndef SK_IO_TEST_H
#define SK_IO_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "surfkit/surfkit.h"

static inline const char *iot_path(const char *dir, const char *name)
{
    static char buf[4][1024];
    static int slot;
    char *b = buf[slot++ & 3];
    snprintf(b, sizeof buf[0], "%s/%s", dir, name);
    return b;
}

#define IOT_SHARED_MESHES SK_SHARED_DIR "/data/meshes"
#define IOT_DATA SK_TEST_DATA_DIR
#define IOT_TMP SK_TEST_TMP_DIR

/* Parses text (or bytes) that must be valid in the given format. */
static inline sk_soup *iot_parse_n(const void *data, size_t n, const char *name, sk_format fmt)
{
    sk_read_opts o = {fmt};
    sk_soup *s = NULL;
    sk_error e = {0};
    sk_status st = sk_soup_read_memory(data, n, name, &o, &s, &e);
    if (st != SK_OK)
        fail_msg("%s should parse but: %s", name, e.message);
    assert_non_null(s);
    return s;
}

static inline sk_soup *iot_parse(const char *text, const char *name, sk_format fmt)
{
    return iot_parse_n(text, strlen(text), name, fmt);
}

/* Parses data that must be rejected with SK_ERR_PARSE and a message that starts with
 * "name:" and contains want (may be NULL). */
static inline void iot_bad_n(const void *data, size_t n, const char *name, sk_format fmt,
                             const char *want)
{
    sk_read_opts o = {fmt};
    sk_soup *s = NULL;
    sk_error e = {0};
    sk_status st = sk_soup_read_memory(data, n, name, &o, &s, &e);
    if (st != SK_ERR_PARSE)
        fail_msg("%s should fail to parse (status %d, message '%s')", name, st, e.message);
    assert_null(s);
    size_t nl = strlen(name);
    if (strncmp(e.message, name, nl) != 0 || e.message[nl] != ':')
        fail_msg("%s: message does not start with the name: '%s'", name, e.message);
    if (strchr(e.message, '\n'))
        fail_msg("%s: message has a newline: '%s'", name, e.message);
    if (want && !strstr(e.message, want))
        fail_msg("%s: message '%s' does not contain '%s'", name, e.message, want);
}

static inline void iot_bad(const char *text, const char *name, sk_format fmt, const char *want)
{
    iot_bad_n(text, strlen(text), name, fmt, want);
}

static inline void iot_assert_vec(const double *got, const double *want, int n)
{
    for (int k = 0; k < n; ++k)
        if (got[k] != want[k])
            fail_msg("component %d: got %.17g, want %.17g", k, got[k], want[k]);
}

static inline void iot_assert_face(const sk_soup *s, size_t f, const uint32_t *want, size_t n)
{
    assert_int_equal(sk_soup_face_size(s, f), n);
    for (size_t k = 0; k < n; ++k)
        assert_int_equal(s->face_indices[s->face_offsets[f] + k], want[k]);
}

#endif
