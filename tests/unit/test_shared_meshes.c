/* Regression: the validation report agrees with every topology fact that ../shared/data/README.md
 * lists (computed independently of surfkit), and Gauss-Bonnet holds on every clean mesh. The
 * table is parsed from the README itself, so new rows are tested without code changes. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct fact {
    char file[128];
    long vertices, faces, edges, loops, components, chi;
    char even[8];
} fact;

static size_t read_facts(fact *out, size_t cap)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/data/README.md", SK_SHARED_DIR);
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("cannot open %s", path);
    char line[1024];
    size_t n = 0;
    while (fgets(line, sizeof line, f) && n < cap) {
        fact x;
        /* | file | vertices | faces | edges | boundary loops | components | chi | V even | notes | */
        if (sscanf(line, "| %127s | %ld | %ld | %ld | %ld | %ld | %ld | %7s |", x.file, &x.vertices,
                   &x.faces, &x.edges, &x.loops, &x.components, &x.chi, x.even) == 8 &&
            strstr(x.file, ".off"))
            out[n++] = x;
    }
    fclose(f);
    return n;
}

static void given_shared_readme_then_every_fact_matches(void **state)
{
    (void)state;
    fact facts[64];
    size_t n = read_facts(facts, 64);
    assert_true(n >= 28);
    for (size_t i = 0; i < n; ++i) {
        const fact *x = &facts[i];
        sk_soup *s = skt_read_soup(skt_shared_mesh(x->file));
        sk_validation r;
        assert_int_equal(sk_soup_validate(s, &r, NULL), SK_OK);
        if ((long)r.vertices != x->vertices || (long)r.faces != x->faces ||
            (long)r.edges != x->edges || (long)r.boundary_loops != x->loops ||
            (long)r.components != x->components || r.euler_characteristic != x->chi)
            fail_msg("%s: got V %zu F %zu E %zu loops %zu comps %zu chi %ld, README says "
                     "%ld %ld %ld %ld %ld %ld", x->file, r.vertices, r.faces, r.edges,
                     r.boundary_loops, r.components, r.euler_characteristic, x->vertices,
                     x->faces, x->edges, x->loops, x->components, x->chi);
        assert_int_equal(strcmp(x->even, "yes") == 0, r.vertices % 2 == 0);
        /* Gauss-Bonnet (Alboul & Echeverria): deficits sum to 2 pi chi on manifold meshes */
        if (sk_validation_is_manifold(&r))
            if (fabs(r.gauss_bonnet_error) > 1e-8 * (1.0 + fabs(r.angle_deficit_sum)))
                fail_msg("%s: Gauss-Bonnet error %g", x->file, r.gauss_bonnet_error);
        sk_soup_destroy(&s);
    }
}

static void given_named_genus_then_genus_matches(void **state)
{
    (void)state;
    const struct {
        const char *file;
        long genus;
    } g[] = {{"eight.off", 2}, {"elephant.off", 3}, {"knot1.off", 1}, {"bunny00.off", 0},
             {"holes.off", 0}, {"lion-head.off", 0}};
    for (size_t i = 0; i < sizeof g / sizeof g[0]; ++i) {
        sk_soup *s = skt_read_soup(skt_shared_mesh(g[i].file));
        sk_validation r;
        sk_soup_validate(s, &r, NULL);
        assert_true(r.genus_defined);
        if (r.genus != g[i].genus)
            fail_msg("%s: genus %ld, expected %ld", g[i].file, r.genus, g[i].genus);
        sk_soup_destroy(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_shared_readme_then_every_fact_matches),
        cmocka_unit_test(given_named_genus_then_genus_matches),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
