#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>

static char path_buf[4][1024];
static int path_slot;

static const char *join(const char *dir, const char *sub, const char *name)
{
    char *b = path_buf[path_slot++ & 3];
    snprintf(b, sizeof path_buf[0], "%s%s/%s", dir, sub, name);
    return b;
}

const char *skt_shared_mesh(const char *name) { return join(SK_SHARED_DIR, "/data/meshes", name); }
const char *skt_test_data(const char *name) { return join(SK_TEST_DATA_DIR, "", name); }
const char *skt_tmp_path(const char *name) { return join(SK_TEST_TMP_DIR, "", name); }

sk_soup *skt_read_soup(const char *path)
{
    sk_soup *s = NULL;
    sk_error err = {0};
    sk_status st = sk_soup_read(path, NULL, &s, &err);
    if (st != SK_OK)
        fail_msg("reading %s: %s", path, err.message);
    return s;
}

sk_mesh *skt_read_mesh(const char *path)
{
    sk_mesh *m = NULL;
    sk_error err = {0};
    sk_status st = sk_mesh_read(path, NULL, &m, &err);
    if (st != SK_OK)
        fail_msg("reading %s: %s", path, err.message);
    return m;
}

void *skt_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        fail_msg("cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *buf = malloc((size_t)n + 1);
    if (!buf || fread(buf, 1, (size_t)n, f) != (size_t)n)
        fail_msg("cannot read %s", path);
    fclose(f);
    ((char *)buf)[n] = 0;
    *size = (size_t)n;
    return buf;
}
