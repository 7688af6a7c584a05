/* Edge deletion (Cottin & van Damme section 3) on the shared meshes: every interior vertex odd,
 * faces triangles or quads, the mesh stays valid, the deleted count is near the lower bound. */
#include "testutil.h"
#include "surfkit/smooth.h"
#include "smooth/smooth_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void check_config(const sk_mesh *m)
{
    sk_error err = {0};
    assert_int_equal(sk_mesh_check(m, &err), SK_OK);
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        size_t n = sk_mesh_face_size(m, f);
        assert_true(n == 3 || n == 4);
    }
    for (uint32_t v = 0; v < m->num_vertices; ++v) {
        if (m->v_halfedge[v] == SK_INVALID || sk_is_boundary_v(m, v))
            continue;
        size_t faces = sk_mesh_valence(m, v);
        if ((faces & 1u) == 0)
            fail_msg("vertex %u has %zu faces", v, faces);
        assert_true(faces >= 3);
    }
}

static void run_mesh(const char *name, size_t expect_even)
{
    sk_mesh *m = skt_read_mesh(skt_shared_mesh(name)), *c = NULL;
    sk_edge_deletion_stats st;
    uint32_t *del = NULL;
    sk_error err = {0};
    sk_status s = sk_edge_deletion(m, &c, &del, &st, &err);
    if (s != SK_OK)
        fail_msg("%s: %s", name, err.message);
    check_config(c);
    print_message("%-20s even %6zu bound %6zu deleted %6zu (%.3f) adj %5zu aug %4zu pairs %5zu "
                  "bnd %4zu rounds %zu reductions %zu shared %zu fixes %zu tri %zu quad %zu\n",
                  name, st.even_vertices, st.lower_bound, st.deleted_edges,
                  st.lower_bound ? (double)st.deleted_edges / (double)st.lower_bound : 1.0,
                  st.adjacent_pairs, st.augmenting_paths, st.pairs,
                  st.boundary_paths, st.initialise_rounds, st.reductions, st.shared_edges,
                  st.triangle_fixes, st.triangles, st.quads);
    if (expect_even != (size_t)-1)
        assert_int_equal(st.even_vertices, expect_even);
    assert_true(st.deleted_edges >= st.lower_bound || st.boundary_paths > 0);
    /* near-optimal: the paper reports optimal counts; allow 35% over the bound */
    assert_true(st.deleted_edges <= st.lower_bound + st.lower_bound * 35 / 100 + 2);
    assert_int_equal(st.triangles + 2 * st.quads, m->num_faces);
    assert_int_equal(st.quads, st.deleted_edges);
    /* deleted edges were edges of the input */
    for (size_t i = 0; i < st.deleted_edges; ++i)
        assert_true(del[2 * i] != del[2 * i + 1]);
    free(del);
    sk_mesh_destroy(&c);
    sk_mesh_destroy(&m);
}

static void test_closed_even(void **state)
{
    (void)state;
    run_mesh("icosahedron.off", 0); /* all valence 5: nothing to delete */
    run_mesh("cube.off", (size_t)-1);
    run_mesh("sphere.off", (size_t)-1);
    run_mesh("cow.off", (size_t)-1);
    run_mesh("knot1.off", (size_t)-1);
    if (!getenv("SK_TEST_QUICK")) {
        run_mesh("bunny00.off", (size_t)-1);
        run_mesh("armadillo.off", (size_t)-1);
    }
}

static void test_disks(void **state)
{
    (void)state;
    const char *disks[] = {"lion-head.off", "mushroom.off", "nefertiti.off", "paraboloid-patch.off",
                           "patch-01.off", "three_peaks.off", "cylinder.off", "mask_cone.off",
                           "pig.off", "mech-holes-shark.off"};
    for (size_t i = 0; i < sizeof disks / sizeof disks[0]; ++i)
        run_mesh(disks[i], (size_t)-1);
}

/* Deleted edges against the lower bound #even / 2, per mesh (measured with the matching of
 * adjacent even vertices, Initialise's breadth-first 0-1 search and the cycle exchanges, plus about
 * 1% slack: cow 1.164, pig 1.188, lion-head 1.243, three_peaks 1.079, bunny00 1.080, armadillo
 * 1.159; with the depth-first search pig 1.222, lion-head 1.247, three_peaks 1.094, bunny00 1.084,
 * armadillo 1.161). On the scans the bound cannot be met: the exact minimum T-join of the input
 * (bench/tjoin_lemon.cpp, no forbidden edges) is already cow 899 (1.055 x the bound), pig 120
 * (1.026), lion-head 2460 (1.087), three_peaks 559 (1.029), bunny00 10460 (1.028), armadillo 6828
 * (1.049); keeping to the allowed edges (quad corner <= 160 degrees) costs more: an even vertex none
 * of whose even neighbours is free across an allowed edge costs an edge of its own. The second
 * check: within 8% of #even - (matched pairs), the size that bound has for the matching found.
 * The cycle exchanges apply on the scans marked (cow 63, lion-head 18, bunny00 15, armadillo 38
 * exchanges). (Until the breadth-first search the check was "above 1.1 x the bound, some
 * exchange applies", and the pig met it with 2; its breadth-first configuration, 4 edges fewer
 * before the exchanges than the depth-first one after them, leaves none to apply.) */
static void test_near_minimal(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        double max_ratio;
        bool exchanges; /* some cycle exchange applies */
    } cases[] = {
        {"sphere.off", 1.0, false},         {"knot1.off", 1.002, false},
        {"mushroom.off", 1.002, false},     {"cylinder.off", 1.0, false},
        {"mech-holes-shark.off", 1.0, false}, {"paraboloid-patch.off", 1.0, false},
        {"nefertiti.off", 1.06, false},     {"three_peaks.off", 1.09, false},
        {"cow.off", 1.175, true},           {"pig.off", 1.20, false},
        {"lion-head.off", 1.255, true},     {"bunny00.off", 1.09, true},
        {"armadillo.off", 1.17, true},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        if (getenv("SK_TEST_QUICK") && (strcmp(cases[i].name, "bunny00.off") == 0 ||
                                        strcmp(cases[i].name, "armadillo.off") == 0))
            continue;
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(cases[i].name)), *c = NULL;
        sk_edge_deletion_stats st;
        sk_error err = {0};
        if (sk_edge_deletion(m, &c, NULL, &st, &err) != SK_OK)
            fail_msg("%s: %s", cases[i].name, err.message);
        check_config(c);
        double ratio = (double)st.deleted_edges / (double)st.lower_bound;
        size_t matching_size = st.even_vertices - st.adjacent_pairs;
        if (ratio > cases[i].max_ratio)
            fail_msg("%s: %zu deleted, %.4f x the bound %zu (allowed %.3f)", cases[i].name,
                     st.deleted_edges, ratio, st.lower_bound, cases[i].max_ratio);
        if ((double)st.deleted_edges > 1.08 * (double)matching_size)
            fail_msg("%s: %zu deleted, more than 1.08 x %zu", cases[i].name, st.deleted_edges,
                     matching_size);
        assert_true(st.adjacent_pairs <= st.pairs);
        /* every exchange saves at least one edge; on the scans with paths some apply */
        assert_true(st.shortcut_savings >= st.shortcuts);
        if (cases[i].exchanges && st.shortcuts == 0)
            fail_msg("%s: %.4f x the bound and no cycle exchange", cases[i].name, ratio);
        sk_mesh_destroy(&c);
        sk_mesh_destroy(&m);
    }
}

/* Initialise on Loop-subdivided scans (once), where almost every vertex is even and matched, so
 * most of the mesh is at distance 0 from the sources through alternating paths: the search
 * finishes each distance level first in, first out, so every source gets a share of it and a
 * round pairs most of them. Measured: cow 3 rounds (5 depth first), lion-head 3 (7), three_peaks
 * 3 (8), and within 0.4% of the bound (cow 5218 / 5205, lion-head 14805 / 14760, three_peaks
 * 3265 / 3261); a valid configuration each. */
static void test_loop_rounds(void **state)
{
    (void)state;
    const char *names[] = {"cow.off", "lion-head.off", "three_peaks.off"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        sk_mesh *p = skt_read_mesh(skt_shared_mesh(names[i])), *m = NULL, *c = NULL;
        sk_error err = {0};
        assert_int_equal(sk_mesh_subdivide(p, NULL, &m, &err), SK_OK);
        sk_edge_deletion_stats st;
        if (sk_edge_deletion(m, &c, NULL, &st, &err) != SK_OK)
            fail_msg("%s Loop: %s", names[i], err.message);
        check_config(c);
        print_message("%s Loop x1: even %zu, %zu deleted (bound %zu), %zu rounds\n", names[i],
                      st.even_vertices, st.deleted_edges, st.lower_bound, st.initialise_rounds);
        assert_true(st.initialise_rounds <= 3);
        assert_true((double)st.deleted_edges <= 1.004 * (double)st.lower_bound);
        sk_mesh_destroy(&c);
        sk_mesh_destroy(&m);
        sk_mesh_destroy(&p);
    }
}

/* The cycle exchanges' parallel pre-pass selects the vertices the ordered pass tries: the same
 * exchanges at the same vertices in the same order as trying every even vertex (meshes where
 * exchanges apply, some of them only after an earlier one nearby; and a Loop-subdivided mesh,
 * almost every vertex even). */
static void test_shortcut_prepass_exact(void **state)
{
    (void)state;
    const char *names[] = {"cow.off", "lion-head.off", "pig.off", "three_peaks.off", "bunny00.off"};
    size_t n = getenv("SK_TEST_QUICK") ? 3 : 5, applied = 0;
    for (size_t i = 0; i <= n; ++i) {
        sk_mesh *m = NULL, *c[2] = {NULL, NULL};
        if (i < n) {
            m = skt_read_mesh(skt_shared_mesh(names[i]));
        } else {
            sk_mesh *p = skt_read_mesh(skt_shared_mesh("pig.off"));
            sk_error e0 = {0};
            assert_int_equal(sk_mesh_subdivide(p, NULL, &m, &e0), SK_OK);
            sk_mesh_destroy(&p);
        }
        uint32_t *trace[2];
        size_t nt[2];
        sk_edge_deletion_stats st[2];
        sk_error err = {0};
        for (int k = 0; k < 2; ++k)
            assert_int_equal(sk__edge_deletion_traced(m, k == 1, &trace[k], &nt[k], &c[k], &st[k], &err),
                             SK_OK);
        assert_int_equal(nt[0], nt[1]);
        assert_int_equal(nt[0], st[0].shortcuts);
        assert_int_equal(st[0].deleted_edges, st[1].deleted_edges);
        /* the screen by tight components: never more than the even vertices; none searched when
         * the deletion before the exchanges is at the lower bound (every component tight) */
        print_message("%s: %zu of %zu even vertices searched, %zu exchanges\n",
                      i < n ? names[i] : "pig Loop x1", st[0].shortcut_searched,
                      st[0].even_vertices, nt[0]);
        assert_true(st[0].shortcut_searched <= st[0].even_vertices);
        assert_int_equal(st[1].shortcut_searched, 0); /* try_all: no pre-pass */
        if (nt[0] == 0 && st[0].deleted_edges == st[0].lower_bound)
            assert_int_equal(st[0].shortcut_searched, 0);
        if (nt[0])
            assert_memory_equal(trace[0], trace[1], nt[0] * sizeof *trace[0]);
        applied += nt[0];
        for (int k = 0; k < 2; ++k) {
            free(trace[k]);
            sk_mesh_destroy(&c[k]);
        }
        sk_mesh_destroy(&m);
    }
    assert_true(applied > 0);
}

static void test_odd_closed_refused(void **state)
{
    (void)state;
    const char *odd[] = {"blobby.off", "eight.off", "elephant.off", "fandisk.off"};
    for (size_t i = 0; i < 4; ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(odd[i])), *c = NULL;
        sk_error err = {0};
        assert_int_equal(sk_edge_deletion(m, &c, NULL, NULL, &err), SK_ERR_TOPOLOGY);
        assert_null(c);
        assert_non_null(strstr(err.message, "odd"));
        sk_mesh_destroy(&m);
    }
}

static void test_quads_refused(void **state)
{
    (void)state;
    double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    uint32_t off[] = {0, 4}, idx[] = {0, 1, 2, 3};
    sk_mesh *m = NULL, *c = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces(4, pos, 1, off, idx, &m, &err), SK_OK);
    assert_int_equal(sk_edge_deletion(m, &c, NULL, NULL, &err), SK_ERR_TOPOLOGY);
    sk_mesh_destroy(&m);
}

/* the deleted edges as sorted (low, high) vertex pairs, packed in 64 bits */
static uint64_t *pair_set(const uint32_t *del, size_t n)
{
    uint64_t *p = malloc((n + 1) * sizeof *p);
    assert_non_null(p);
    for (size_t i = 0; i < n; ++i) {
        uint64_t a = del[2 * i], b = del[2 * i + 1];
        p[i] = a < b ? a << 32 | b : b << 32 | a;
    }
    for (size_t i = 1; i < n; ++i) /* insertion sort: a few thousand */
        for (size_t j = i; j > 0 && p[j - 1] > p[j]; --j) {
            uint64_t t = p[j];
            p[j] = p[j - 1];
            p[j - 1] = t;
        }
    return p;
}

/* |A symmetric difference B| of two sorted sets; *far := the largest ring distance dist[] of an
 * end of a differing edge */
static size_t sym_diff(const uint64_t *a, size_t na, const uint64_t *b, size_t nb,
                       const uint32_t *dist, uint32_t *far)
{
    size_t i = 0, j = 0, n = 0;
    *far = 0;
    while (i < na || j < nb) {
        uint64_t x;
        if (j >= nb || (i < na && a[i] < b[j]))
            x = a[i++];
        else if (i >= na || b[j] < a[i])
            x = b[j++];
        else {
            ++i, ++j;
            continue;
        }
        ++n;
        uint32_t d = dist[x >> 32] < dist[x & 0xffffffffu] ? dist[x >> 32] : dist[x & 0xffffffffu];
        *far = d > *far ? d : *far;
    }
    return n;
}

/* ring distances from the ns vertices seed (BFS over the mesh) */
static uint32_t *rings_from(const sk_mesh *m, const uint32_t *seed, size_t ns)
{
    uint32_t *dist = malloc(m->num_vertices * sizeof *dist);
    uint32_t *q = malloc(m->num_vertices * sizeof *q);
    assert_true(dist && q);
    size_t qh = 0, qt = 0;
    for (size_t v = 0; v < m->num_vertices; ++v)
        dist[v] = UINT32_MAX;
    for (size_t k = 0; k < ns; ++k)
        if (dist[seed[k]] == UINT32_MAX) {
            dist[seed[k]] = 0;
            q[qt++] = seed[k];
        }
    while (qh < qt) {
        uint32_t v = q[qh++], h0 = m->v_halfedge[v], h = h0;
        do {
            uint32_t w = m->h_vertex[h];
            if (dist[w] == UINT32_MAX) {
                dist[w] = dist[v] + 1;
                q[qt++] = w;
            }
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
    free(q);
    return dist;
}

/* The warm start (sk__edge_deletion_hinted): from its own deletion a mesh gets the same edges
 * back; after an edge flip the warm start changes the deleted set only within a few rings of the
 * flip, while the deletion from nothing changes it farther away (printed). */
static void test_hinted_local(void **state)
{
    (void)state;
    const char *names[] = {"knot1.off", "sphere.off", "mushroom.off"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(names[i])), *c = NULL;
        sk_edge_deletion_stats st0, st1, st2, st3;
        uint32_t *d0 = NULL, *d1 = NULL, *d2 = NULL, *d3 = NULL;
        assert_int_equal(sk_edge_deletion(m, &c, &d0, &st0, NULL), SK_OK);
        sk_mesh_destroy(&c);
        assert_int_equal(sk__edge_deletion_hinted(m, NULL, d0, st0.deleted_edges, NULL, &c, &d1, &st1,
                                                  NULL), SK_OK);
        check_config(c);
        sk_mesh_destroy(&c);
        uint64_t *p0 = pair_set(d0, st0.deleted_edges), *p1 = pair_set(d1, st1.deleted_edges);
        assert_int_equal(st1.deleted_edges, st0.deleted_edges);
        assert_memory_equal(p0, p1, st0.deleted_edges * sizeof *p0);
        /* the bound is the mesh's (ceil(#even / 2)), not what the hint leaves to pair */
        assert_int_equal(st1.even_vertices, st0.even_vertices);
        assert_int_equal(st1.lower_bound, st0.lower_bound);
        /* flip the first interior edge, away from the deleted ones, that keeps valences >= 4 */
        uint32_t h = SK_INVALID, ends[4] = {0, 0, 0, 0};
        for (uint32_t e = 0; e < sk_num_edges(m) && h == SK_INVALID; ++e) {
            uint32_t g = 2 * e, a = sk_from(m, g), b = sk_to(m, g);
            if (sk_is_boundary_e(m, e) || sk_mesh_valence(m, a) < 5 || sk_mesh_valence(m, b) < 5)
                continue;
            uint32_t x = m->h_vertex[m->h_next[g]], y = m->h_vertex[m->h_next[g ^ 1u]];
            if (sk__find_halfedge(m, x, y) != SK_INVALID)
                continue;
            h = g;
            ends[0] = a, ends[1] = b, ends[2] = x, ends[3] = y;
        }
        assert_true(h != SK_INVALID);
        sk__flip_edge(m, h);
        assert_int_equal(sk__edge_deletion_hinted(m, NULL, d0, st0.deleted_edges, NULL, &c, &d2, &st2,
                                                  NULL), SK_OK);
        check_config(c);
        sk_mesh_destroy(&c);
        assert_int_equal(sk_edge_deletion(m, &c, &d3, &st3, NULL), SK_OK);
        sk_mesh_destroy(&c);
        uint32_t *dist = rings_from(m, ends, 4), far2 = 0, far3 = 0;
        uint64_t *p2 = pair_set(d2, st2.deleted_edges), *p3 = pair_set(d3, st3.deleted_edges);
        size_t n2 = sym_diff(p0, st0.deleted_edges, p2, st2.deleted_edges, dist, &far2);
        size_t n3 = sym_diff(p0, st0.deleted_edges, p3, st3.deleted_edges, dist, &far3);
        print_message("%-14s %zu deleted; after a flip: warm start %zu deleted, %zu changed, "
                      "within %u rings; from nothing %zu deleted, %zu changed, within %u rings\n",
                      names[i], st0.deleted_edges, st2.deleted_edges, n2, far2, st3.deleted_edges,
                      n3, far3);
        assert_true(n2 <= 12 && far2 <= 4);
        assert_true(st2.deleted_edges <= st0.deleted_edges + 4);
        free(dist);
        free(p0);
        free(p1);
        free(p2);
        free(p3);
        free(d0);
        free(d1);
        free(d2);
        free(d3);
        sk_mesh_destroy(&m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_even),
        cmocka_unit_test(test_disks),
        cmocka_unit_test(test_near_minimal),
        cmocka_unit_test(test_loop_rounds),
        cmocka_unit_test(test_shortcut_prepass_exact),
        cmocka_unit_test(test_odd_closed_refused),
        cmocka_unit_test(test_quads_refused),
        cmocka_unit_test(test_hinted_local),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
