/* Self-intersections: hand-made crossings, touching and neighbouring faces that do not count,
 * groups, the shared self-intersecting mesh, clean shared meshes, bad input. */
#include "testutil.h"
#include "surfkit/intersect.h"

#include <string.h>

static sk_soup *soup_of(const double *pos, size_t nv, const uint32_t *tri, size_t nt)
{
    sk_soup *s = NULL;
    assert_int_equal(sk_soup_create(nv, nt, 3 * nt, false, false, &s, NULL), SK_OK);
    for (size_t v = 0; v < nv; ++v)
        assert_int_equal(sk_soup_push_vertex(s, pos + 3 * v, NULL, NULL), SK_OK);
    for (size_t t = 0; t < nt; ++t)
        assert_int_equal(sk_soup_push_face(s, tri + 3 * t, 3), SK_OK);
    return s;
}

static size_t crossings(const double *pos, size_t nv, const uint32_t *tri, size_t nt)
{
    sk_soup *s = soup_of(pos, nv, tri, nt);
    sk_intersection_report r;
    assert_int_equal(sk_self_intersections(s, NULL, NULL, &r, NULL), SK_OK);
    sk_soup_destroy(&s);
    return r.pairs;
}

/* a horizontal triangle and a vertical one whose edge pierces it at (0.5, 0.5, 0) */
static const double X[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, -1, 0.5, 0.5, 1, 3, 3, 0};

static void crossing_pair(void **state)
{
    (void)state;
    const uint32_t t[] = {0, 1, 2, 3, 4, 5};
    assert_int_equal(crossings(X, 6, t, 2), 1);
    double far[18];
    memcpy(far, X, sizeof far);
    for (int v = 3; v < 6; ++v)
        far[3 * v] += 10; /* moved away */
    assert_int_equal(crossings(far, 6, t, 2), 0);
    /* the second triangle lifted so that its lower end touches the first one's plane: no
     * crossing (touching does not count) */
    double touch[18];
    memcpy(touch, X, sizeof touch);
    touch[3 * 3 + 2] = 0;
    assert_int_equal(crossings(touch, 6, t, 2), 0);
    /* a vertex shared by index: neighbours, not tested */
    const uint32_t shared[] = {0, 1, 2, 3, 4, 0};
    assert_int_equal(crossings(X, 6, shared, 2), 0);
}

static void groups_and_neighbours(void **state)
{
    (void)state;
    /* four faces: 0, 1 crossing 2, 3 (1 and 2 cross); groups {0, 1} -> 0, {2, 3} -> 1 */
    const double pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, -1, 0.5, 0.5, 1, 3, 3, 0,
                          -5, -5, 0, -4, -5, 0, -5, -4, 0};
    const uint32_t tri[] = {6, 7, 8, 0, 1, 2, 3, 4, 5, 6, 8, 7};
    sk_soup *s = soup_of(pos, 9, tri, 4);
    const uint32_t group[] = {0, 0, 1, 1};
    /* group corners: disjoint ids -> not neighbours */
    const double gp[] = {0, 0, 0};
    const uint32_t gt[] = {0, 1, 2, 3, 4, 5};
    sk_soup *g = soup_of(gp, 1, gt, 2);
    g->num_vertices = 6; /* ids only: positions are not used */
    sk_intersection_report r;
    sk_error err;
    assert_int_equal(sk_self_intersections(s, group, g, &r, &err), SK_OK);
    assert_int_equal(r.pairs, 1);
    assert_int_equal(r.groups, 2);
    assert_int_equal(r.examples[0], 0);
    assert_int_equal(r.examples[1], 1);
    /* groups sharing a corner id are neighbours */
    g->face_indices[5] = 0;
    assert_int_equal(sk_self_intersections(s, group, g, &r, &err), SK_OK);
    assert_int_equal(r.pairs, 0);
    /* a group id out of range */
    const uint32_t bad[] = {0, 0, 7, 1};
    assert_int_equal(sk_self_intersections(s, bad, g, &r, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "face 2 is in group 7"));
    sk_soup_destroy(&g);
    sk_soup_destroy(&s);
}

static void shared_meshes(void **state)
{
    (void)state;
    /* the intruding triangle (face 4) crosses the tetrahedron; nothing else crosses */
    sk_soup *s = skt_read_soup(skt_shared_mesh("tetra_intersected_by_triangle.off"));
    sk_intersection_report r;
    assert_int_equal(sk_self_intersections(s, NULL, NULL, &r, NULL), SK_OK);
    assert_true(r.pairs >= 1);
    for (size_t i = 0; i < r.num_examples; ++i)
        assert_int_equal(r.examples[2 * i + 1], 4);
    sk_soup_destroy(&s);
    /* the cow scan crosses itself: CGAL 5.5's PMP::self_intersections finds 101 face pairs
     * (touching and neighbouring faces included), all in a few places (e.g. faces 4713 and
     * 264-266); the strict crossings of non-neighbours are a subset */
    s = skt_read_soup(skt_shared_mesh("cow.off"));
    assert_int_equal(sk_self_intersections(s, NULL, NULL, &r, NULL), SK_OK);
    assert_true(r.pairs >= 50 && r.pairs <= 101);
    sk_soup_destroy(&s);
    /* CGAL finds none in these */
    const char *clean[] = {"sphere.off", "bunny00.off", "lion-head.off", "fandisk.off"};
    for (size_t i = 0; i < sizeof clean / sizeof *clean; ++i) {
        s = skt_read_soup(skt_shared_mesh(clean[i]));
        assert_int_equal(sk_self_intersections(s, NULL, NULL, &r, NULL), SK_OK);
        if (r.pairs)
            print_message("%s: %zu crossing pairs, e.g. faces %u and %u\n", clean[i], r.pairs,
                          r.examples[0], r.examples[1]);
        assert_int_equal(r.pairs, 0);
        assert_true(r.triangle_tests > 0);
        sk_soup_destroy(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(crossing_pair),
        cmocka_unit_test(groups_and_neighbours),
        cmocka_unit_test(shared_meshes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
