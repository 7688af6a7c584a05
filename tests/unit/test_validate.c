/* Soup validation: every defect class on hand-made input, Gauss-Bonnet on exact cases. */
#include "testutil.h"

#include <math.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <string.h>

static sk_soup *make(size_t nv, const double *p, size_t nf, const uint32_t *sizes,
                     const uint32_t *idx)
{
    sk_soup *s = NULL;
    assert_int_equal(sk_soup_create(nv, nf, 0, false, false, &s, NULL), SK_OK);
    for (size_t v = 0; v < nv; ++v)
        assert_int_equal(sk_soup_push_vertex(s, p + 3 * v, NULL, NULL), SK_OK);
    for (size_t f = 0, k = 0; f < nf; k += sizes[f], ++f)
        assert_int_equal(sk_soup_push_face(s, idx + k, sizes[f]), SK_OK);
    return s;
}

static const uint32_t three[16] = {3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3};

static void given_tetrahedron_then_closed_genus0_and_gauss_bonnet_exact(void **state)
{
    (void)state;
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t idx[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    sk_soup *s = make(4, p, 4, three, idx);
    sk_validation r;
    assert_int_equal(sk_soup_validate(s, &r, NULL), SK_OK);
    assert_int_equal(r.edges, 6);
    assert_int_equal(r.boundary_loops, 0);
    assert_int_equal(r.euler_characteristic, 2);
    assert_true(r.genus_defined);
    assert_int_equal(r.genus, 0);
    assert_true(sk_validation_is_manifold(&r));
    assert_true(fabs(r.angle_deficit_sum - 4 * M_PI) < 1e-12);
    assert_true(fabs(r.gauss_bonnet_error) < 1e-12);
    /* angles: right angles at the origin, 45 and 60 degrees elsewhere */
    assert_true(fabs(r.max_angle_deg - 90.0) < 1e-12);
    assert_true(fabs(r.min_angle_deg - 45.0) < 1e-12);
    assert_true(fabs(r.area - (1.5 + sqrt(3.0) / 2)) < 1e-12);
    sk_soup_destroy(&s);
}

static void given_flat_square_then_boundary_deficits_sum_to_2pi(void **state)
{
    (void)state;
    /* 3x3 grid of points, 8 triangles: a disk, chi 1, deficit sum 2 pi */
    double p[27];
    for (int j = 0, k = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i, ++k) {
            p[3 * k] = i;
            p[3 * k + 1] = j;
            p[3 * k + 2] = 0;
        }
    uint32_t idx[24], n = 0;
    for (uint32_t j = 0; j < 2; ++j)
        for (uint32_t i = 0; i < 2; ++i) {
            uint32_t a = 3 * j + i, b = a + 1, c = a + 3, d = a + 4;
            uint32_t t[6] = {a, b, d, a, d, c};
            memcpy(idx + n, t, sizeof t);
            n += 6;
        }
    sk_soup *s = make(9, p, 8, three, idx);
    sk_validation r;
    sk_soup_validate(s, &r, NULL);
    assert_int_equal(r.euler_characteristic, 1);
    assert_int_equal(r.boundary_loops, 1);
    assert_int_equal(r.boundary_edges, 8);
    assert_int_equal(r.genus, 0);
    assert_true(fabs(r.angle_deficit_sum - 2 * M_PI) < 1e-12);
    assert_true(fabs(r.gauss_bonnet_error) < 1e-12);
    assert_true(fabs(r.edge_min - 1.0) < 1e-15);
    assert_true(fabs(r.edge_max - sqrt(2.0)) < 1e-15);
    sk_soup_destroy(&s);
}

static void given_every_defect_then_each_is_counted_and_named(void **state)
{
    (void)state;
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0,        /* 0-2: face 0 and its duplicate */
                        5, 0, 0, 6, 0, 0, 7, 0, 0,        /* 3-5: collinear */
                        10, 0, 0, 11, 0, 0, 10, 1, 0, 10, 0, 1, 10, -1, 0, /* 6-10: fin */
                        NAN, 0, 0, 9, 9, 9};              /* 11 NaN, 12 unreferenced */
    /* face 1 duplicates face 0 (reversed); face 2 degenerate; face 3 has 2 indices; face 4 out of
     * range; face 5 repeats a vertex; faces 6-8 share edge (6,7): non-manifold; face 9 uses the
     * NaN vertex */
    const uint32_t sizes[] = {3, 3, 3, 2, 3, 3, 3, 3, 3, 3};
    const uint32_t idx[] = {0, 1, 2, 2, 1, 0, 3, 4, 5, 0, 1, 0, 1, 99, 0, 0, 2,
                            6, 7, 8, 7, 6, 9, 6, 7, 10, 6, 8, 11};
    sk_soup *s = make(13, p, 10, sizes, idx);
    sk_validation r;
    assert_int_equal(sk_soup_validate(s, &r, NULL), SK_OK);
    assert_int_equal(r.nonfinite_vertices.count, 1);
    assert_int_equal(r.nonfinite_vertices.a[0], 11);
    assert_int_equal(r.unreferenced_vertices.count, 1);
    assert_int_equal(r.unreferenced_vertices.a[0], 12);
    assert_int_equal(r.duplicate_faces.count, 1);
    assert_int_equal(r.duplicate_faces.a[0], 1);
    assert_int_equal(r.duplicate_faces.b[0], 0);
    assert_int_equal(r.degenerate_faces.count, 1);
    assert_int_equal(r.degenerate_faces.a[0], 2);
    assert_int_equal(r.small_faces.count, 1);
    assert_int_equal(r.small_faces.a[0], 3);
    assert_int_equal(r.out_of_range.count, 1);
    assert_int_equal(r.out_of_range.a[0], 4);
    assert_int_equal(r.out_of_range.b[0], 99);
    assert_int_equal(r.repeated_vertex_faces.count, 1);
    assert_int_equal(r.repeated_vertex_faces.a[0], 5);
    assert_int_equal(r.non_manifold_edges.count, 1);
    assert_int_equal(r.non_manifold_edges.a[0], 6);
    assert_int_equal(r.non_manifold_edges.b[0], 7);
    assert_int_equal(r.orientation_conflicts.count, 0);
    assert_false(sk_validation_is_manifold(&r));
    assert_int_equal(r.faces, 10);
    assert_int_equal(r.triangles, 9);
    sk_soup_destroy(&s);
}

static void given_orientation_conflict_and_bowtie_then_both_reported(void **state)
{
    (void)state;
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0};
    const uint32_t idx[] = {0, 1, 2, 0, 1, 3, 0, 4, 5};
    sk_soup *s = make(6, p, 3, three, idx);
    sk_validation r;
    sk_soup_validate(s, &r, NULL);
    assert_int_equal(r.orientation_conflicts.count, 1);
    assert_int_equal(r.orientation_conflicts.a[0], 0);
    assert_int_equal(r.orientation_conflicts.b[0], 1);
    /* vertex 0: fan {0,1} and fan {2} */
    assert_int_equal(r.non_manifold_vertices.count, 1);
    assert_int_equal(r.non_manifold_vertices.a[0], 0);
    assert_int_equal(r.components, 1);
    assert_false(r.genus_defined);
    sk_soup_destroy(&s);
}

static void given_degtri_sliding_then_four_degenerate_faces(void **state)
{
    (void)state;
    sk_soup *s = skt_read_soup(skt_shared_mesh("degtri_sliding.off"));
    sk_validation r;
    sk_soup_validate(s, &r, NULL);
    assert_int_equal(r.degenerate_faces.count, 4);
    sk_soup_destroy(&s);
}

/* Uninitialised-memory regression (walk_boundary read the edge table past its filled part): glibc's
 * M_PERTURB fills every fresh allocation with garbage, so a read of unfilled slots indexes far out of
 * the arrays instead of silently seeing zeros. */
static void perturb_malloc(void)
{
#ifdef __GLIBC__
    mallopt(M_PERTURB, 0xA5);
#endif
}

static void given_only_face_repeats_a_vertex_then_no_loop_and_no_crash(void **state)
{
    (void)state;
    perturb_malloc();
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t sizes[] = {4};
    const uint32_t idx[] = {0, 1, 2, 0};
    sk_soup *s = make(3, p, 1, sizes, idx);
    sk_validation r;
    assert_int_equal(sk_soup_validate(s, &r, NULL), SK_OK);
    assert_int_equal(r.repeated_vertex_faces.count, 1);
    assert_int_equal(r.edges, 0);
    assert_int_equal(r.boundary_edges, 0);
    assert_int_equal(r.boundary_loops, 0);
    assert_int_equal(r.components, 0);
    sk_soup_destroy(&s);
}

static void given_disk_plus_repeated_vertex_face_then_one_loop_of_the_disk(void **state)
{
    (void)state;
    perturb_malloc();
    /* a square of two triangles, then a face 3 0 0 1 */
    const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t sizes[] = {3, 3, 3};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3, 0, 0, 1};
    sk_soup *s = make(4, p, 3, sizes, idx);
    sk_validation r;
    assert_int_equal(sk_soup_validate(s, &r, NULL), SK_OK);
    assert_int_equal(r.repeated_vertex_faces.count, 1);
    assert_int_equal(r.repeated_vertex_faces.a[0], 2);
    assert_int_equal(r.edges, 5);
    assert_int_equal(r.boundary_edges, 4);
    assert_int_equal(r.boundary_loops, 1);
    assert_int_equal(r.euler_characteristic, 1);
    assert_true(r.genus_defined);
    assert_int_equal(r.genus, 0);
    sk_soup_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_tetrahedron_then_closed_genus0_and_gauss_bonnet_exact),
        cmocka_unit_test(given_flat_square_then_boundary_deficits_sum_to_2pi),
        cmocka_unit_test(given_every_defect_then_each_is_counted_and_named),
        cmocka_unit_test(given_orientation_conflict_and_bowtie_then_both_reported),
        cmocka_unit_test(given_degtri_sliding_then_four_degenerate_faces),
        cmocka_unit_test(given_only_face_repeats_a_vertex_then_no_loop_and_no_crash),
        cmocka_unit_test(given_disk_plus_repeated_vertex_face_then_one_loop_of_the_disk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
