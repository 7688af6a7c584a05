/* Progressive mesh hierarchy (src/hierarchy): collapse legality, levels by random independent
 * sets, barycentric records, vertex split, prolongation. Given a mesh of ../shared/data/meshes,
 * when the hierarchy is built, then every level keeps the Euler characteristic, the boundary loops
 * and the components, passes sk_mesh_check, shrinks by a factor in [1.2, 1.6] while it has over
 * 1,000 faces, every barycentric record is valid, and the splits rebuild every level and the input
 * exactly. SK_TEST_QUICK=1 (the sanitizer run) keeps to the smaller meshes. */
#include "testutil.h"
#include "hierarchy/hierarchy_internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const all_meshes[] = {
    "armadillo.off", "blobby.off", "bunny00.off", "cow.off", "cube.off", "cylinder.off",
    "degtri_sliding.off", "eight.off", "elephant.off", "fandisk.off", "fold.off", "holes.off",
    "icosahedron.off", "in.off", "knot1.off", "lion-head.off", "lion.off", "mask_cone.off",
    "mech-holes-shark.off", "mushroom.off", "nefertiti.off", "paraboloid-patch.off",
    "patch-01.off", "pig.off", "sphere.off", "tetra_intersected_by_triangle.off",
    "three_peaks.off", "triangle.off",
};
#define NUM_MESHES (sizeof all_meshes / sizeof all_meshes[0])

static bool quick(void)
{
    const char *q = getenv("SK_TEST_QUICK");
    return q && *q && strcmp(q, "0") != 0;
}

/* ---- canonical face sets -------------------------------------------------------------------- */

typedef struct face_set {
    size_t n;
    uint64_t *keys; /* sorted; each face rotated so its smallest vertex comes first */
} face_set;

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static uint64_t face_key(uint32_t a, uint32_t b, uint32_t c)
{
    if (b < a && b < c) {
        uint32_t t = a;
        a = b, b = c, c = t;
    } else if (c < a && c < b) {
        uint32_t t = c;
        c = b, b = a, a = t;
    }
    return ((uint64_t)a << 42) | ((uint64_t)b << 21) | (uint64_t)c;
}

static face_set faces_of(const sk_mesh *m)
{
    face_set s = {0, malloc((m->num_faces + 1) * sizeof(uint64_t))};
    assert_non_null(s.keys);
    assert_true(m->num_vertices < (1u << 21));
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f];
        uint32_t a = m->h_vertex[m->h_prev[h]], b = m->h_vertex[h], c = m->h_vertex[m->h_next[h]];
        s.keys[s.n++] = face_key(a, b, c);
    }
    qsort(s.keys, s.n, sizeof(uint64_t), cmp_u64);
    return s;
}

static bool has_face(const face_set *s, uint32_t a, uint32_t b, uint32_t c)
{
    uint64_t k1 = face_key(a, b, c), k2 = face_key(a, c, b);
    return bsearch(&k1, s->keys, s->n, sizeof(uint64_t), cmp_u64) ||
           bsearch(&k2, s->keys, s->n, sizeof(uint64_t), cmp_u64);
}

/* A level as recorded during the build: faces and positions. */
typedef struct level_copy {
    face_set faces;
    size_t nv;
    double *pos;
} level_copy;

static level_copy copy_level(const sk_mesh *m)
{
    level_copy c;
    assert_int_equal(m->num_deleted_vertices, 0);
    c.faces = faces_of(m);
    c.nv = m->num_vertices;
    c.pos = malloc(3 * c.nv * sizeof(double) + 1);
    assert_non_null(c.pos);
    memcpy(c.pos, m->positions, 3 * c.nv * sizeof(double));
    return c;
}

static void free_level(level_copy *c)
{
    free(c->faces.keys);
    free(c->pos);
}

/* The mesh equals the recorded level exactly: same vertex count, positions bit for bit, same
 * oriented triangles on the same vertex numbers. */
static void assert_same_level(const sk_mesh *m, const level_copy *c, const char *what)
{
    if (m->num_vertices != c->nv)
        fail_msg("%s: %zu vertices, expected %zu", what, m->num_vertices, c->nv);
    if (memcmp(m->positions, c->pos, 3 * c->nv * sizeof(double)) != 0)
        fail_msg("%s: positions differ", what);
    face_set s = faces_of(m);
    if (s.n != c->faces.n || memcmp(s.keys, c->faces.keys, s.n * sizeof(uint64_t)) != 0)
        fail_msg("%s: faces differ (%zu vs %zu)", what, s.n, c->faces.n);
    free(s.keys);
}

/* ---- per-level checks during the build ------------------------------------------------------ */

typedef struct build_check {
    const char *name;
    sk_topology top0;
    size_t prev_faces;
    size_t steps;
    level_copy levels[128]; /* [0] input, [k] after step k */
    double worst_ratio_lo, worst_ratio_hi;
} build_check;

static int on_level(void *user, size_t step, const sk_mesh *m)
{
    build_check *bc = user;
    sk_error err;
    if (sk_mesh_check(m, &err) != SK_OK)
        fail_msg("%s level %zu: %s", bc->name, step, err.message);
    sk_topology top;
    assert_int_equal(sk_mesh_topology(m, &top, NULL, &err), SK_OK);
    if (top.euler_characteristic != bc->top0.euler_characteristic ||
        top.boundary_loops != bc->top0.boundary_loops || top.components != bc->top0.components)
        fail_msg("%s level %zu: chi %ld loops %zu components %zu, expected %ld %zu %zu", bc->name,
                 step, top.euler_characteristic, top.boundary_loops, top.components,
                 bc->top0.euler_characteristic, bc->top0.boundary_loops, bc->top0.components);
    assert_int_equal(m->num_deleted_faces, 0);
    double ratio = (double)bc->prev_faces / (double)m->num_faces;
    if (bc->prev_faces > 1000) {
        if (ratio < 1.2 || ratio > 1.6)
            fail_msg("%s level %zu: %zu -> %zu faces, ratio %.3f outside [1.2, 1.6]", bc->name,
                     step, bc->prev_faces, m->num_faces, ratio);
        if (ratio < bc->worst_ratio_lo)
            bc->worst_ratio_lo = ratio;
        if (ratio > bc->worst_ratio_hi)
            bc->worst_ratio_hi = ratio;
    }
    bc->prev_faces = m->num_faces;
    assert_true(step < 128);
    assert_int_equal(step, bc->steps + 1);
    bc->steps = step;
    bc->levels[step] = copy_level(m);
    return 0;
}

/* Every record: coordinates in [0, 1] summing to 1, parent[0] = w0, the parent triangle and the
 * record's vertices exist on the coarse level, the parent is a face of it, the vertex map is
 * consistent. */
static void check_records(const sk_hierarchy *h, size_t level, const level_copy *coarse,
                          const level_copy *fine, const char *name)
{
    size_t ns = 0;
    const sk_vertex_split *s = sk_hierarchy_splits(h, level, &ns);
    const uint32_t *map = sk_hierarchy_vertex_map(h, level);
    assert_non_null(map);
    size_t kept = 0;
    uint8_t *hit = calloc(coarse->nv + 1, 1);
    for (size_t f = 0; f < fine->nv; ++f) {
        if (map[f] != SK_INVALID) {
            assert_true(map[f] < coarse->nv && !hit[map[f]]); /* one to one */
            hit[map[f]] = 1;
            if (level + 2 < sk_hierarchy_num_levels(h))
                assert_int_equal(map[f], kept); /* below the input: relative order kept */
            ++kept;
            assert_memory_equal(fine->pos + 3 * f, coarse->pos + 3 * (size_t)map[f], 3 * sizeof(double));
        }
    }
    free(hit);
    assert_int_equal(kept, coarse->nv);
    assert_int_equal(kept + ns, fine->nv);
    for (size_t j = 0; j < ns; ++j) {
        const double *l = s[j].bary;
        if (!(l[0] >= 0 && l[1] >= 0 && l[2] >= 0 && l[0] <= 1 && l[1] <= 1 && l[2] <= 1) ||
            fabs(l[0] + l[1] + l[2] - 1.0) > 1e-12)
            fail_msg("%s level %zu split %zu: bad coordinates %g %g %g", name, level, j, l[0], l[1], l[2]);
        assert_true(s[j].v < fine->nv);
        assert_int_equal(map[s[j].v], SK_INVALID);
        assert_memory_equal(s[j].position, fine->pos + 3 * (size_t)s[j].v, 3 * sizeof(double));
        assert_int_equal(s[j].parent[0], s[j].w0);
        for (int k = 0; k < 3; ++k)
            assert_true(s[j].parent[k] < coarse->nv);
        assert_true(s[j].parent[0] != s[j].parent[1] && s[j].parent[1] != s[j].parent[2] &&
                    s[j].parent[0] != s[j].parent[2]);
        if (!has_face(&coarse->faces, s[j].parent[0], s[j].parent[1], s[j].parent[2]))
            fail_msg("%s level %zu split %zu: parent triangle is not a face", name, level, j);
    }
}

static void check_mesh(const char *name, bool print)
{
    sk_error err;
    sk_mesh *mesh = NULL;
    sk_status st = sk_mesh_read(skt_shared_mesh(name), NULL, &mesh, &err);
    if (st != SK_OK) { /* defective input is refused with a message */
        assert_true(st < 0);
        assert_true(strlen(err.message) > 0);
        if (print)
            printf("%-36s refused: %s\n", name, err.message);
        return;
    }
    build_check *bc = calloc(1, sizeof *bc);
    assert_non_null(bc);
    bc->name = name;
    bc->worst_ratio_lo = 1e9;
    bc->worst_ratio_hi = 0;
    assert_int_equal(sk_mesh_topology(mesh, &bc->top0, NULL, &err), SK_OK);
    bc->prev_faces = mesh->num_faces;
    bc->levels[0] = copy_level(mesh);

    sk_hierarchy_opts opts = {0};
    opts.seed = 7;
    opts.on_level = on_level;
    opts.on_level_user = bc;
    sk_hierarchy *h = NULL;
    st = sk_hierarchy_build(mesh, &opts, &h, &err);
    if (st != SK_OK)
        fail_msg("%s: %s", name, err.message);
    size_t L = sk_hierarchy_num_levels(h);
    assert_int_equal(L, bc->steps + 1);
    /* level i of the hierarchy is bc->levels[L - 1 - i] */
    for (size_t i = 0; i < L; ++i) {
        sk_level_info info = sk_hierarchy_level_info(h, i);
        const level_copy *c = &bc->levels[L - 1 - i];
        assert_int_equal(info.vertices, c->nv);
        assert_int_equal(info.faces, c->faces.n);
    }
    for (size_t i = 0; i + 1 < L; ++i)
        check_records(h, i, &bc->levels[L - 1 - i], &bc->levels[L - 2 - i], name);

    /* walk up from the coarsest level: every split reproduces the next level exactly */
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_copy(sk_hierarchy_coarsest(h), &m, &err), SK_OK);
    assert_same_level(m, &bc->levels[L - 1], name);
    char what[128];
    for (size_t i = 0; i + 1 < L; ++i) {
        if (sk_hierarchy_split(h, i, m, &err) != SK_OK)
            fail_msg("%s split %zu: %s", name, i, err.message);
        if (sk_mesh_check(m, &err) != SK_OK)
            fail_msg("%s after split %zu: %s", name, i, err.message);
        snprintf(what, sizeof what, "%s level %zu from splits", name, i + 1);
        assert_same_level(m, &bc->levels[L - 2 - i], what);
    }
    /* the finest level is the input */
    snprintf(what, sizeof what, "%s input from splits", name);
    assert_same_level(m, &bc->levels[0], what);

    /* prolongation of positions: kept vertices copy, inserted ones are convex combinations */
    const sk_mesh *c0 = sk_hierarchy_coarsest(h);
    double *a = malloc(3 * c0->num_vertices * sizeof(double) + 8);
    memcpy(a, c0->positions, 3 * c0->num_vertices * sizeof(double));
    for (size_t i = 0; i + 1 < L; ++i) {
        size_t nf = sk_hierarchy_level_info(h, i + 1).vertices;
        double *b = malloc(3 * nf * sizeof(double) + 8);
        assert_int_equal(sk_hierarchy_prolong(h, i, a, 3, b, &err), SK_OK);
        for (size_t k = 0; k < 3 * nf; ++k)
            assert_true(isfinite(b[k]));
        free(a);
        a = b;
    }
    free(a);

    if (print) {
        printf("%-36s %zu levels: faces", name, L);
        for (size_t i = L; i-- > 0;)
            printf(" %zu", sk_hierarchy_level_info(h, i).faces);
        if (bc->worst_ratio_hi > 0)
            printf("  (ratios %.3f..%.3f)", bc->worst_ratio_lo, bc->worst_ratio_hi);
        printf("\n");
    }
    sk_mesh_destroy(&m);
    for (size_t k = 0; k <= bc->steps; ++k)
        free_level(&bc->levels[k]);
    free(bc);
    sk_hierarchy_destroy(&h);
    sk_mesh_destroy(&mesh);
}

/* Given every shared mesh, when its hierarchy is built, then all the properties hold. */
static void test_all_shared_meshes(void **state)
{
    (void)state;
    for (size_t i = 0; i < NUM_MESHES; ++i) {
        const char *name = all_meshes[i];
        if (quick() && (!strcmp(name, "armadillo.off") || !strcmp(name, "bunny00.off") ||
                        !strcmp(name, "lion-head.off") || !strcmp(name, "fandisk.off")))
            continue;
        check_mesh(name, true);
    }
}

/* ---- small hand-made meshes ---------------------------------------------------------------- */

static sk_mesh *make_mesh(size_t nv, const double *pos, size_t nf, const uint32_t *tri)
{
    uint32_t *off = malloc((nf + 1) * sizeof(uint32_t));
    for (size_t f = 0; f <= nf; ++f)
        off[f] = (uint32_t)(3 * f);
    sk_mesh *m = NULL;
    sk_error err;
    if (sk_mesh_from_faces(nv, pos, nf, off, tri, &m, &err) != SK_OK)
        fail_msg("%s", err.message);
    free(off);
    return m;
}

static uint32_t find_halfedge(const sk_mesh *m, uint32_t a, uint32_t b)
{
    for (uint32_t h = 0; h < m->num_halfedges; ++h)
        if (!m->e_deleted[h >> 1] && sk_from(m, h) == a && sk_to(m, h) == b)
            return h;
    return SK_INVALID;
}

static const double tet_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const uint32_t tet_tri[] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};

/* Given a tetrahedron, no collapse is legal (it would leave two triangles back to back). */
static void test_tetrahedron_no_collapse(void **state)
{
    (void)state;
    sk_mesh *m = make_mesh(4, tet_pos, 4, tet_tri);
    for (uint32_t h = 0; h < m->num_halfedges; ++h)
        assert_false(sk_mesh_collapse_ok(m, h, NULL));
    sk_hierarchy *hier = NULL;
    sk_error err;
    assert_int_equal(sk_hierarchy_build(m, NULL, &hier, &err), SK_OK);
    assert_int_equal(sk_hierarchy_num_levels(hier), 1);
    sk_hierarchy_destroy(&hier);
    sk_mesh_destroy(&m);
}

/* A 3x3 grid of vertices (2x2 squares, 8 triangles) in the plane z = 0:
 *   6 7 8
 *   3 4 5
 *   0 1 2      centre 4 is interior, all others are boundary. */
static sk_mesh *grid(void)
{
    double pos[27];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            pos[3 * (3 * j + i)] = i;
            pos[3 * (3 * j + i) + 1] = j;
            pos[3 * (3 * j + i) + 2] = 0;
        }
    static const uint32_t tri[] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4,
                                   3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7};
    return make_mesh(9, pos, 8, tri);
}

/* Given the grid, then the boundary rules hold: the boundary vertex 1 collapses along the boundary
 * to 0 or 2 but not inward to 4; the interior edge 1-5 joins two boundary vertices and never
 * collapses; the interior vertex 4 may collapse onto a boundary vertex. */
static void test_boundary_rules(void **state)
{
    (void)state;
    sk_mesh *m = grid();
    assert_true(sk_mesh_collapse_ok(m, find_halfedge(m, 1, 0), NULL));
    assert_true(sk_mesh_collapse_ok(m, find_halfedge(m, 1, 2), NULL));
    assert_false(sk_mesh_collapse_ok(m, find_halfedge(m, 1, 4), NULL));
    assert_false(sk_mesh_collapse_ok(m, find_halfedge(m, 5, 1), NULL)); /* interior edge, both ends boundary */
    assert_false(sk_mesh_collapse_ok(m, find_halfedge(m, 1, 5), NULL));
    assert_true(sk_mesh_collapse_ok(m, find_halfedge(m, 4, 0), NULL));
    /* a corner with one triangle stays (no parent triangle for it) */
    assert_false(sk_mesh_collapse_ok(m, find_halfedge(m, 2, 1), NULL));

    /* collapse 4 -> 0, then the mesh is valid, chi and the loop stay */
    sk_error err;
    sk_topology t0, t1;
    assert_int_equal(sk_mesh_topology(m, &t0, NULL, &err), SK_OK);
    sk_mesh_collapse(m, find_halfedge(m, 4, 0));
    assert_int_equal(sk_mesh_check(m, &err), SK_OK);
    assert_int_equal(sk_mesh_topology(m, &t1, NULL, &err), SK_OK);
    assert_int_equal(t1.euler_characteristic, t0.euler_characteristic);
    assert_int_equal(t1.boundary_loops, 1);
    assert_int_equal(t1.faces, 6);
    /* then boundary vertex 1 -> 0 along the boundary */
    assert_true(sk_mesh_collapse_ok(m, find_halfedge(m, 1, 0), NULL));
    sk_mesh_collapse(m, find_halfedge(m, 1, 0));
    assert_int_equal(sk_mesh_check(m, &err), SK_OK);
    assert_int_equal(sk_mesh_topology(m, &t1, NULL, &err), SK_OK);
    assert_int_equal(t1.euler_characteristic, 1);
    assert_int_equal(t1.boundary_loops, 1);
    assert_int_equal(t1.faces, 5);
    assert_int_equal(sk_mesh_compact(m, NULL, NULL, &err), SK_OK);
    assert_int_equal(sk_mesh_check(m, &err), SK_OK);
    sk_mesh_destroy(&m);
}

/* Given the grid with its centre lifted so that moving it onto a corner flips a face, then the
 * normal test refuses that collapse with the default 90 degrees and allows it at 179 degrees. */
static void test_normal_threshold(void **state)
{
    (void)state;
    sk_mesh *m = grid();
    /* vertex 0 at (2.5, 2.5, 1): moving 4 onto it turns the normals of (4, 5, 8) and (4, 8, 7) by
       116.6 degrees, those of (1, 5, 4) and (3, 4, 7) by 54.7 degrees */
    m->positions[0] = 2.5;
    m->positions[1] = 2.5;
    m->positions[2] = 1.0;
    uint32_t h = find_halfedge(m, 4, 0);
    assert_false(sk_mesh_collapse_ok(m, h, NULL));
    sk_collapse_opts o = {116.0, 0};
    assert_false(sk_mesh_collapse_ok(m, h, &o));
    o.max_normal_deviation_deg = 117.0;
    assert_true(sk_mesh_collapse_ok(m, h, &o));
    sk_mesh_destroy(&m);
}

/* Given a mesh with a quad, the hierarchy refuses it with SK_ERR_TOPOLOGY; non-finite
 * coordinates give SK_ERR_NUMERIC. */
static void test_bad_input(void **state)
{
    (void)state;
    double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    uint32_t off[] = {0, 4};
    uint32_t idx[] = {0, 1, 2, 3};
    sk_mesh *m = NULL;
    sk_error err;
    assert_int_equal(sk_mesh_from_faces(4, pos, 1, off, idx, &m, &err), SK_OK);
    sk_hierarchy *h = NULL;
    assert_int_equal(sk_hierarchy_build(m, NULL, &h, &err), SK_ERR_TOPOLOGY);
    assert_null(h);
    assert_non_null(strstr(err.message, "triangle"));
    sk_mesh_destroy(&m);

    m = make_mesh(4, tet_pos, 4, tet_tri);
    m->positions[4] = NAN;
    assert_int_equal(sk_hierarchy_build(m, NULL, &h, &err), SK_ERR_NUMERIC);
    assert_null(h);
    sk_mesh_destroy(&m);
}

static void faces_per_level(const sk_mesh *mesh, const sk_hierarchy_opts *o, size_t *out, size_t *n)
{
    sk_hierarchy *h = NULL;
    sk_error err;
    assert_int_equal(sk_hierarchy_build(mesh, o, &h, &err), SK_OK);
    *n = sk_hierarchy_num_levels(h);
    for (size_t i = 0; i < *n && i < 64; ++i)
        out[i] = sk_hierarchy_level_info(h, i).faces;
    sk_hierarchy_destroy(&h);
}

/* Given a seed, the hierarchy is the same on every run; another seed gives another one; the level
 * and face limits stop the build. */
static void test_seed_and_stop_rules(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("cow.off"));
    size_t a[64], b[64], c[64], na, nb, nc;
    sk_hierarchy_opts o = {0};
    o.seed = 42;
    faces_per_level(mesh, &o, a, &na);
    faces_per_level(mesh, &o, b, &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, na * sizeof(size_t));
    o.seed = 43;
    faces_per_level(mesh, &o, c, &nc);
    assert_true(nc != na || memcmp(a, c, na * sizeof(size_t)) != 0);

    o.seed = 42;
    o.max_levels = 3;
    faces_per_level(mesh, &o, c, &nc);
    assert_int_equal(nc, 3);
    assert_memory_equal(c, a + na - 3, 3 * sizeof(size_t));

    o.max_levels = 0;
    o.target_faces = 2000;
    faces_per_level(mesh, &o, c, &nc);
    assert_true(c[0] <= 2000);
    assert_true(c[1] > 2000);
    sk_mesh_destroy(&mesh);
}

/* Given a level mesh from sk_hierarchy_level_mesh, it is the same as walking with splits, and uvs
 * carried by the split equal sk_hierarchy_prolong. */
static void test_level_mesh_and_uv(void **state)
{
    (void)state;
    sk_mesh *mesh = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    sk_hierarchy *h = NULL;
    sk_error err;
    sk_hierarchy_opts o = {0};
    assert_int_equal(sk_hierarchy_build(mesh, &o, &h, &err), SK_OK);
    size_t L = sk_hierarchy_num_levels(h);
    assert_true(L >= 4);
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_copy(sk_hierarchy_coarsest(h), &m, &err), SK_OK);
    assert_int_equal(sk_mesh_add_uvs(m, &err), SK_OK);
    for (size_t v = 0; v < m->num_vertices; ++v) {
        m->uvs[2 * v] = m->positions[3 * v];
        m->uvs[2 * v + 1] = m->positions[3 * v + 1];
    }
    double *uv = malloc(2 * m->num_vertices * sizeof(double));
    memcpy(uv, m->uvs, 2 * m->num_vertices * sizeof(double));
    for (size_t i = 0; i + 1 < L; ++i) {
        size_t nf = sk_hierarchy_level_info(h, i + 1).vertices;
        double *fine = malloc(2 * nf * sizeof(double));
        assert_int_equal(sk_hierarchy_prolong(h, i, uv, 2, fine, &err), SK_OK);
        free(uv);
        uv = fine;
        assert_int_equal(sk_hierarchy_split(h, i, m, &err), SK_OK);
        assert_memory_equal(m->uvs, uv, 2 * nf * sizeof(double));
        sk_mesh *lm = NULL;
        assert_int_equal(sk_hierarchy_level_mesh(h, i + 1, &lm, &err), SK_OK);
        assert_memory_equal(lm->positions, m->positions, 3 * nf * sizeof(double));
        sk_mesh_destroy(&lm);
    }
    /* wrong level: refused */
    assert_int_equal(sk_hierarchy_split(h, 0, m, &err), SK_ERR_ARG);
    free(uv);
    sk_mesh_destroy(&m);
    sk_hierarchy_destroy(&h);
    sk_mesh_destroy(&mesh);
}

/* Given a flat fan (hexagon with its centre off the middle), the exponential map is an isometry,
 * so the parent triangle and coordinates give back the centre's position to rounding; the same
 * for an open (boundary) fan, where v lands on the chord (w0, wn). */
static void test_flat_barycentric(void **state)
{
    (void)state;
    double pos[21] = {0.1, 0.05, 0};
    for (int k = 0; k < 6; ++k) {
        pos[3 * (k + 1)] = cos(k * M_PI / 3);
        pos[3 * (k + 1) + 1] = sin(k * M_PI / 3);
        pos[3 * (k + 1) + 2] = 0;
    }
    uint32_t tri[18];
    for (uint32_t k = 0; k < 6; ++k) {
        tri[3 * k] = 0;
        tri[3 * k + 1] = 1 + k;
        tri[3 * k + 2] = 1 + (k + 1) % 6;
    }
    for (int open = 0; open < 2; ++open) {
        sk_mesh *m = make_mesh(7, pos, open ? 3 : 6, tri); /* open: faces 0-1-2, 0-2-3, 0-3-4 */
        for (uint32_t w = 1; w <= (open ? 4u : 6u); ++w) {
            uint32_t h = find_halfedge(m, 0, w), ring[8], parent[3];
            if (open && w != 1 && w != 4)
                continue;
            bool closed;
            double scratch[40], l[3];
            size_t count = sk__collapse_ring(m, h, ring, &closed);
            assert_int_equal(closed, !open);
            assert_int_equal(count, open ? 4 : 6);
            assert_int_equal(ring[0], w);
            sk__barycentric(m, 0, ring, count, closed, scratch, parent, l);
            assert_int_equal(parent[0], w);
            double p[3] = {0, 0, 0};
            for (int k = 0; k < 3; ++k)
                for (int d = 0; d < 3; ++d)
                    p[d] += l[k] * m->positions[3 * (size_t)parent[k] + d];
            assert_true(l[0] >= 0 && l[1] >= 0 && l[2] >= 0);
            assert_true(fabs(l[0] + l[1] + l[2] - 1) < 1e-15);
            if (!open) {
                assert_true(fabs(p[0] - 0.1) < 1e-12 && fabs(p[1] - 0.05) < 1e-12);
            } else {
                /* on the chord between vertex 1 (1, 0) and vertex 4 (-1, 0), at the distance
                   ratio */
                double r0 = hypot(pos[3 * w] - 0.1, pos[3 * w + 1] - 0.05);
                uint32_t wn = w == 1 ? 4 : 1;
                double rn = hypot(pos[3 * wn] - 0.1, pos[3 * wn + 1] - 0.05);
                assert_int_equal(parent[2], wn);
                assert_true(l[1] == 0.0 && fabs(l[0] - rn / (r0 + rn)) < 1e-15);
            }
        }
        sk_mesh_destroy(&m);
    }
}

/* Given a mesh with an isolated vertex, the vertex stays on every level and the splits still give
 * back the input exactly. */
static void test_isolated_vertex(void **state)
{
    (void)state;
    double pos[3 * 26];
    uint32_t tri[3 * 32];
    size_t nf = 0;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            pos[3 * (5 * j + i)] = i;
            pos[3 * (5 * j + i) + 1] = j;
            pos[3 * (5 * j + i) + 2] = 0.1 * ((i * 7 + j * 3) % 5);
        }
    pos[75] = 9, pos[76] = 9, pos[77] = 9; /* vertex 25: isolated */
    for (uint32_t j = 0; j < 4; ++j)
        for (uint32_t i = 0; i < 4; ++i) {
            uint32_t a = 5 * j + i, b = a + 1, c = a + 6, d = a + 5;
            tri[3 * nf] = a, tri[3 * nf + 1] = b, tri[3 * nf + 2] = c, ++nf;
            tri[3 * nf] = a, tri[3 * nf + 1] = c, tri[3 * nf + 2] = d, ++nf;
        }
    sk_mesh *m = make_mesh(26, pos, nf, tri);
    sk_hierarchy *h = NULL;
    sk_error err;
    assert_int_equal(sk_hierarchy_build(m, NULL, &h, &err), SK_OK);
    size_t L = sk_hierarchy_num_levels(h);
    assert_true(L >= 3);
    const sk_mesh *c = sk_hierarchy_coarsest(h);
    size_t isolated = 0;
    for (size_t v = 0; v < c->num_vertices; ++v)
        isolated += c->v_halfedge[v] == SK_INVALID;
    assert_int_equal(isolated, 1);
    sk_mesh *top = NULL;
    assert_int_equal(sk_hierarchy_level_mesh(h, L - 1, &top, &err), SK_OK);
    assert_int_equal(top->num_vertices, 26);
    assert_memory_equal(top->positions, m->positions, 26 * 3 * sizeof(double));
    assert_int_equal(top->v_halfedge[25], SK_INVALID);
    face_set a = faces_of(top), b = faces_of(m);
    assert_int_equal(a.n, b.n);
    assert_memory_equal(a.keys, b.keys, a.n * sizeof(uint64_t));
    free(a.keys);
    free(b.keys);
    sk_mesh_destroy(&top);
    sk_hierarchy_destroy(&h);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetrahedron_no_collapse),
        cmocka_unit_test(test_boundary_rules),
        cmocka_unit_test(test_normal_threshold),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_flat_barycentric),
        cmocka_unit_test(test_isolated_vertex),
        cmocka_unit_test(test_seed_and_stop_rules),
        cmocka_unit_test(test_level_mesh_and_uv),
        cmocka_unit_test(test_all_shared_meshes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
