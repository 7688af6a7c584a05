/* surfkit simplify: progressive-mesh hierarchy (random independent sets of half-edge collapses,
 * Hormann/Greiner/Campagna section 3); writes the coarsest level, optionally every level and a JSON
 * report. */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char help[] =
    "usage: surfkit simplify IN -o OUT [--levels K | --faces N] [--seed S] [--max-angle DEG]\n"
    "                        [--all-levels DIR] [--report report.json] [-q]\n"
    "\n"
    "Builds the progressive-mesh hierarchy of a triangle mesh by half-edge collapses in random\n"
    "independent sets (about 25% fewer triangles per level) and writes the coarsest level M^0 to OUT.\n"
    "Collapses keep the Euler characteristic, the boundary loops and manifoldness; no face normal\n"
    "turns by more than --max-angle (default 90 degrees).\n"
    "\n"
    "  --levels K        stop when the hierarchy has K levels, the input included\n"
    "  --faces N         stop once a level has at most N faces\n"
    "                    (without either: until a level removes less than 3% of the faces)\n"
    "  --seed S          random order of the vertices (default 1); the same seed gives the same result\n"
    "  --all-levels DIR  also write every level as DIR/level_<i>.<ext of OUT>, i = 0 the coarsest,\n"
    "                    rebuilt from the coarsest level by the stored vertex splits\n"
    "  --report FILE     JSON: {\"levels\": [{vertices, faces, seconds}, ...]} from the finest\n"
    "                    (the input) to the coarsest, and the totals\n"
    "  -q                no progress bar, no summary line\n";

typedef struct report_ctx {
    const char *in;
    const sk_hierarchy *h;
    unsigned long seed;
    double total;
} report_ctx;

static void report_json(FILE *fp, const void *user)
{
    const report_ctx *c = user;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", c->in);
    json_kuint(&j, "seed", c->seed);
    size_t L = sk_hierarchy_num_levels(c->h);
    json_kuint(&j, "num_levels", L);
    json_knum(&j, "seconds", c->total);
    json_key(&j, "levels");
    json_arr_open(&j);
    for (size_t i = L; i-- > 0;) {
        sk_level_info li = sk_hierarchy_level_info(c->h, i);
        json_obj_open(&j);
        json_kuint(&j, "level", i);
        json_kuint(&j, "vertices", li.vertices);
        json_kuint(&j, "faces", li.faces);
        json_knum(&j, "seconds", li.seconds);
        json_obj_close(&j);
    }
    json_arr_close(&j);
    json_obj_close(&j);
    json_end(&j);
}

/* through the one atomic writer (this had its own, with a temporary name shared by every process) */
static int write_report(const char *path, const char *in, const sk_hierarchy *h, unsigned long seed,
                        double total)
{
    report_ctx c = {in, h, seed, total};
    return cli_write_file(path, report_json, &c);
}

static int write_all_levels(const char *dir, const char *out, const sk_hierarchy *h,
                            const sk_write_opts *wo)
{
    const char *ext = strrchr(out, '.');
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot create the folder: %s", dir, strerror(errno));
        return EXIT_BAD_INPUT;
    }
    sk_error err = {0};
    sk_mesh *m = NULL;
    sk_status st = sk_mesh_copy(sk_hierarchy_coarsest(h), &m, &err);
    size_t L = sk_hierarchy_num_levels(h);
    char *path = malloc(strlen(dir) + strlen(ext) + 32);
    if (!path) {
        sk_mesh_destroy(&m);
        cli_error("out of memory");
        return EXIT_INTERNAL;
    }
    for (size_t i = 0; st == SK_OK && i < L; ++i) {
        if (i > 0)
            st = sk_hierarchy_split(h, i - 1, m, &err);
        if (st == SK_OK) {
            sprintf(path, "%s/level_%02zu%s", dir, i, ext);
            st = sk_mesh_write(path, m, wo, &err);
        }
    }
    free(path);
    sk_mesh_destroy(&m);
    return st ? cli_fail(st, &err) : EXIT_OK;
}

int cmd_simplify(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *val, *all_dir = NULL, *report = NULL;
    sk_hierarchy_opts ho = {0};
    sk_write_opts wo = {0};
    bool quiet = false, have_levels = false, have_faces = false;
    unsigned long seed = 1;
    const cli_path_opt paths[] = {{"-o", &out}, {"--all-levels", &all_dir}, {"--report", &report}};
    int took;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        unsigned long n;
        double d;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(help, stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "-q")) {
            quiet = true;
        } else if ((took = cli_take_path(argc, argv, &i, "simplify", paths, 3)) != 0) {
            if (took < 0)
                return EXIT_USAGE;
        } else if (cli_opt_value(argc, argv, &i, "--levels", &val)) {
            if (!cli_parse_uint(val, &n) || n < 1 || n > 1000)
                return cli_usage("simplify", "--levels takes a whole number from 1 to 1000");
            ho.max_levels = (unsigned)n;
            have_levels = true;
        } else if (cli_opt_value(argc, argv, &i, "--faces", &val)) {
            if (!cli_parse_uint(val, &n) || n < 1)
                return cli_usage("simplify", "--faces takes a positive whole number");
            ho.target_faces = n;
            have_faces = true;
        } else if (cli_opt_value(argc, argv, &i, "--seed", &val)) {
            if (!cli_parse_uint(val, &n))
                return cli_usage("simplify", "--seed takes a whole number");
            seed = n;
        } else if (cli_opt_value(argc, argv, &i, "--max-angle", &val)) {
            if (!cli_parse_double(val, &d) || !(d > 0.0 && d <= 180.0))
                return cli_usage("simplify", "--max-angle takes degrees in (0, 180]");
            ho.collapse.max_normal_deviation_deg = d;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage("simplify", "unknown option '%s'", a);
        } else if (!in) {
            in = a;
        } else {
            return cli_usage("simplify", "more than one input file");
        }
    }
    if (!in || !out)
        return cli_usage("simplify", "needs an input file and -o OUT");
    if (have_levels && have_faces)
        return cli_usage("simplify", "--levels and --faces exclude each other");
    if (sk_format_from_path(out) == SK_FORMAT_UNKNOWN)
        return cli_usage("simplify", "cannot tell the output format of '%s'", out);
    ho.seed = seed;

    sk_error err = {0};
    sk_mesh *mesh = NULL;
    sk_hierarchy *h = NULL;
    sk_status st = sk_mesh_read(in, NULL, &mesh, &err);
    if (st)
        return cli_fail(st, &err);
    cli_progress bar;
    cli_progress_init(&bar, "simplify", quiet);
    ho.progress = cli_progress_cb;
    ho.progress_user = &bar;
    st = sk_hierarchy_build(mesh, &ho, &h, &err);
    cli_progress_done(&bar);
    if (st) {
        sk_mesh_destroy(&mesh);
        return cli_fail(st, &err);
    }
    double total = 0.0;
    size_t L = sk_hierarchy_num_levels(h);
    for (size_t i = 0; i < L; ++i)
        total += sk_hierarchy_level_info(h, i).seconds;
    int rc = EXIT_OK;
    st = sk_mesh_write(out, sk_hierarchy_coarsest(h), &wo, &err);
    if (st)
        rc = cli_fail(st, &err);
    if (rc == EXIT_OK && all_dir)
        rc = write_all_levels(all_dir, out, h, &wo);
    if (rc == EXIT_OK && report)
        rc = write_report(report, in, h, seed, total);
    if (rc == EXIT_OK && !quiet)
        printf("%s: %zu levels, %zu -> %zu faces (%zu -> %zu vertices) in %.3f s\n", in, L,
               sk_hierarchy_level_info(h, L - 1).faces, sk_hierarchy_level_info(h, 0).faces,
               sk_hierarchy_level_info(h, L - 1).vertices, sk_hierarchy_level_info(h, 0).vertices,
               total);
    sk_hierarchy_destroy(&h);
    sk_mesh_destroy(&mesh);
    return rc;
}
