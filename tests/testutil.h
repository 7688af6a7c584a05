/* Helpers shared by the unit tests. */
#ifndef SK_TESTUTIL_H
#define SK_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "surfkit/surfkit.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Path of a file in ../shared/data/meshes (static buffer, valid until the next call). */
const char *skt_shared_mesh(const char *name);
/* Path of a file in tests/data. */
const char *skt_test_data(const char *name);
/* A fresh path in the build's test temp folder. */
const char *skt_tmp_path(const char *name);
/* Reads a mesh file into a soup / a half-edge mesh; fails the test with the error message. */
sk_soup *skt_read_soup(const char *path);
sk_mesh *skt_read_mesh(const char *path);
/* An irregular planar disk: an n x n grid in z = 0, interior points jittered by up to 0.15,
 * two triangles per cell (srand(seed)). */
sk_mesh *skt_planar_disk(int n, unsigned seed);
/* The largest |a - b| over nv uv pairs, relative to the larger side of a's uv bounding box. */
double skt_uv_difference(size_t nv, const double *a, const double *b);
/* Reads a whole file into memory (fails the test if it cannot). */
void *skt_read_file(const char *path, size_t *size);

/* The reference CAD real (the old formatter): the shortest "%.<p>G", p = 1..17, that reads back,
 * with a decimal point always; "0." for either zero. */
void skt_cad_real_ref(char out[32], double x);

#endif
