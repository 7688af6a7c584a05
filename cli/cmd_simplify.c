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

static const char about[] =
    "Builds the progressive-mesh hierarchy of a triangle mesh by half-edge collapses in random\n"
    "independent sets (about 25% fewer triangles per level) and writes the coarsest level M^0 to OUT.\n"
    "Collapses keep the Euler characteristic, the boundary loops and manifoldness; no face normal\n"
    "turns by more than --max-angle (default 90 degrees).\n"
    "Without --levels or --faces the target is half the input's faces (two or three levels);\n"
    "--faces 1 builds the whole hierarchy (until a level removes less than 3% of the faces).\n"
    "Quads and larger polygons are triangulated first (--keep-polygons refuses them).\n";

static const char examples[] =
    "  surfkit simplify data/nefertiti.off -o coarse.off\n"
    "  surfkit simplify data/sphere.off -o coarse.ply --faces 100 --seed 7\n"
    "  surfkit simplify data/nefertiti.off -o c.obj --all-levels levels "
    "--report levels.json\n";

typedef struct report_ctx {
    const char *in;
    const sk_triangulate_stats *tri;
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
    json_triangulated(&j, c->tri);
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
static int write_report(const char *path, const char *in, const sk_triangulate_stats *tri,
                        const sk_hierarchy *h, unsigned long seed, double total)
{
    report_ctx c = {in, tri, h, seed, total};
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

/* target: the default target (half the faces) when it was used, else 0 */
static void print_summary(const char *in, const sk_hierarchy *h, double total, size_t target)
{
    size_t L = sk_hierarchy_num_levels(h);
    sk_level_info fine = sk_hierarchy_level_info(h, L - 1), coarse = sk_hierarchy_level_info(h, 0);
    printf("%s: %zu levels, %zu -> %zu faces (%zu -> %zu vertices) in %.3f s", in, L, fine.faces,
           coarse.faces, fine.vertices, coarse.vertices, total);
    if (target)
        printf(" (default target: half the faces, %zu; --faces N or --levels K to choose)", target);
    printf("\n");
}

int cmd_simplify(int argc, char **argv)
{
    const char *out = NULL, *all_dir = NULL, *report = NULL;
    sk_hierarchy_opts ho = {0};
    sk_write_opts wo = {0};
    bool quiet = false, keep_polygons = false;
    unsigned long seed = 1;
    const cli_opt opts[] = {
        OPT_OUTPUT(out, "OUT", "the coarsest level (OFF, OBJ, PLY, STL)"),
        OPT_INT("--levels", ho.max_levels, 1, 1000, "K",
                "stop when the hierarchy has K levels, the input included"),
        OPT_INT("--faces", ho.target_faces, 1, 0, "N", "stop once a level has at most N faces\n"
                "(without either: half the input's faces)"),
        OPT_INT("--seed", seed, 0, 0, "S",
                "random order of the vertices (default 1); the same seed gives the same result"),
        OPT_DOUBLE("--max-angle", ho.collapse.max_normal_deviation_deg, 0, 180, CLI_LO_OPEN, "DEG",
                   "largest turn of a face normal by a collapse (default 90)"),
        OPT_FILE("--all-levels", all_dir, "DIR",
                 "also write every level as DIR/level_<i>.<ext of OUT>, i = 0 the coarsest,\n"
                 "rebuilt from the coarsest level by the stored vertex splits"),
        OPT_FILE("--report", report, "FILE",
                 "JSON: {\"levels\": [{vertices, faces, seconds}, ...]} from the finest\n"
                 "(the input) to the coarsest, and the totals"),
        OPT_FLAG("--keep-polygons", keep_polygons, "refuse quads and polygons (default: split)"),
        OPT_FLAG("--ascii", wo.ascii, "PLY and STL as text (default binary)"),
        OPT_FLAG("-q", quiet, "no progress bar, no summary line"),
    };
    const cli_spec spec = {"simplify", "IN -o OUT", about,
                           opts, CLI_COUNT(opts), 1, 1, examples, NULL};
    cli_args args;
    int prc = cli_parse(&spec, argc, argv, &args);
    if (prc)
        return prc == CLI_HELP ? EXIT_OK : prc;
    const char *in = cli_input(&args, 0);
    bool have_levels = cli_given(&args, "--levels"), have_faces = cli_given(&args, "--faces");
    if (have_levels && have_faces)
        return cli_usage("simplify", "--levels and --faces exclude each other");
    if (sk_format_from_path(out) == SK_FORMAT_UNKNOWN)
        return cli_usage("simplify", "cannot tell the output format of '%s'", out);
    ho.seed = seed;

    sk_error err = {0};
    sk_mesh *mesh = NULL;
    sk_hierarchy *h = NULL;
    sk_triangulate_stats tri;
    sk_status st = cli_read_triangles(in, keep_polygons, &mesh, &tri, &err);
    if (st)
        return cli_fail(st, &err);
    bool half = !have_levels && !have_faces; /* the default: half the faces */
    if (half)
        ho.target_faces = (mesh->num_faces + 1) / 2;
    cli_progress bar;
    cli_progress_init(&bar, "simplify", quiet);
    ho.progress = cli_progress_cb;
    ho.progress_user = &bar;
    st = sk_hierarchy_build(mesh, &ho, &h, &err);
    cli_progress_done(&bar);
    cli_name_input(in, st, &err);
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
        rc = write_report(report, in, &tri, h, seed, total);
    if (rc == EXIT_OK && !quiet) {
        cli_print_triangulated(in, &tri);
        print_summary(in, h, total, half ? ho.target_faces : 0);
    }
    sk_hierarchy_destroy(&h);
    sk_mesh_destroy(&mesh);
    return rc;
}
