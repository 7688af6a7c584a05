#include "testutil.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* An irregular planar grid: n x n points jittered in the plane z = 0. */
sk_mesh *skt_planar_disk(int n, unsigned seed)
{
    size_t nv = (size_t)n * n, nf = 2 * (size_t)(n - 1) * (n - 1);
    double *p = malloc(3 * nv * sizeof(double));
    uint32_t *idx = malloc(3 * nf * sizeof(uint32_t)), *off = malloc((nf + 1) * sizeof(uint32_t));
    srand(seed);
    for (int j = 0, k = 0; j < n; ++j)
        for (int i = 0; i < n; ++i, ++k) {
            bool edge = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            p[3 * k] = i + (edge ? 0 : 0.3 * ((double)rand() / RAND_MAX - 0.5));
            p[3 * k + 1] = j + (edge ? 0 : 0.3 * ((double)rand() / RAND_MAX - 0.5));
            p[3 * k + 2] = 0;
        }
    size_t t = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            uint32_t a = (uint32_t)(j * n + i), b = a + 1, c = a + (uint32_t)n, d = c + 1;
            uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(idx + 3 * t, q, sizeof q);
            t += 2;
        }
    for (size_t f = 0; f <= nf; ++f)
        off[f] = (uint32_t)(3 * f);
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_from_faces(nv, p, nf, off, idx, &m, NULL), SK_OK);
    free(p);
    free(idx);
    free(off);
    return m;
}

/* The old CAD formatter: the shortest "%.<p>G" from one digit, with a point always. */
void skt_cad_real_ref(char out[32], double x)
{
    if (x == 0.0) {
        strcpy(out, "0.");
        return;
    }
    for (int p = 1; p <= 17; ++p) {
        snprintf(out, 32, "%.*G", p, x);
        if (strtod(out, NULL) == x)
            break;
    }
    if (!strchr(out, '.')) {
        char *e = strchr(out, 'E');
        size_t n = strlen(out);
        if (e) {
            memmove(e + 1, e, n - (size_t)(e - out) + 1);
            *e = '.';
        } else {
            out[n] = '.';
            out[n + 1] = '\0';
        }
    }
}

double skt_uv_difference(size_t nv, const double *a, const double *b)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, d = 0;
    for (size_t v = 0; v < nv; ++v)
        for (int c = 0; c < 2; ++c) {
            lo[c] = fmin(lo[c], a[2 * v + c]);
            hi[c] = fmax(hi[c], a[2 * v + c]);
            d = fmax(d, fabs(a[2 * v + c] - b[2 * v + c]));
        }
    return d / fmax(hi[0] - lo[0], hi[1] - lo[1]);
}
