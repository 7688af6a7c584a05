/* surfkit deviation: two-sided distance between a surface (a tessellation) and a mesh. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Distances between SURFACE and MESH in both directions: from every vertex of MESH and from\n"
    "N x N samples of each of its triangles (default N = 2) to SURFACE, and from the same samples\n"
    "of SURFACE to MESH, through a bounding-volume hierarchy. Prints max, mean and RMS of each\n"
    "direction and the two-sided (Hausdorff) distance, in model units and relative to MESH's\n"
    "bounding-box diagonal. SURFACE and MESH are any mesh files (OFF, OBJ, PLY, STL; polygons are\n"
    "split into triangles), e.g. the tessellation `surfkit smooth IN -o S.obj` writes.\n"
    "\n"
    "--tolerance T (model units) or --tolerance-rel R (times the diagonal) says whether the\n"
    "Hausdorff distance is within it and sets the top of the colour scale (else the largest\n"
    "distance drawn). --png draws MESH coloured per pixel by its distance to SURFACE (blue 0, red\n"
    "at the scale, magenta beyond), --png-surface draws SURFACE coloured by its distance to MESH\n"
    "(where spikes and bulges of a smooth surface show), both seen along --view (default\n"
    "0,0,-1). --report writes the figures as JSON; --json prints them instead of the summary.\n";

static const char examples[] =
    "  surfkit smooth data/sphere.off -o sphere-s.obj -q && surfkit deviation "
    "sphere-s.obj data/sphere.off --png dev.png\n"
    "  surfkit deviation data/sphere.off data/sphere.off --tolerance-rel 1e-3 "
    "--json\n";

typedef struct run {
    const char *surface, *mesh;
    sk_deviation_report r;
    double tolerance; /* 0: none */
} run;

static void json_side(cli_json *j, const char *key, const sk_distance_stats *d, double diag)
{
    json_key(j, key);
    json_obj_open(j);
    json_kuint(j, "samples", d->samples);
    json_knum(j, "max", d->max);
    json_knum(j, "mean", d->mean);
    json_knum(j, "rms", d->rms);
    json_knum(j, "max_rel", diag > 0 ? d->max / diag : 0);
    json_key(j, "max_at");
    json_arr_open(j);
    for (int k = 0; k < 3; ++k)
        json_num(j, d->max_at[k]);
    json_arr_close(j);
    if (d->max_face != SK_INVALID)
        json_kuint(j, "max_face", d->max_face);
    json_key(j, "histogram");
    json_arr_open(j);
    for (int b = 0; b < SK_DEVIATION_BINS; ++b)
        json_uint(j, d->histogram[b]);
    json_arr_close(j);
    json_obj_close(j);
}

static void write_json(FILE *fp, const void *ctx)
{
    const run *x = ctx;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "surface", x->surface);
    json_kstr(&j, "input", x->mesh);
    json_knum(&j, "hausdorff", x->r.hausdorff);
    json_knum(&j, "hausdorff_rel", x->r.diagonal > 0 ? x->r.hausdorff / x->r.diagonal : 0);
    json_knum(&j, "diagonal", x->r.diagonal);
    json_knum(&j, "histogram_top", x->r.hausdorff);
    if (x->tolerance > 0) {
        json_knum(&j, "tolerance", x->tolerance);
        json_kbool(&j, "within_tolerance", x->r.hausdorff <= x->tolerance);
    }
    json_side(&j, "mesh_to_surface", &x->r.mesh_to_surface, x->r.diagonal);
    json_side(&j, "surface_to_mesh", &x->r.surface_to_mesh, x->r.diagonal);
    json_knum(&j, "seconds", x->r.seconds);
    json_obj_close(&j);
    json_end(&j);
}

static void print_summary(const run *x)
{
    const sk_deviation_report *r = &x->r;
    double d = r->diagonal > 0 ? r->diagonal : 1;
    printf("%s vs %s: hausdorff %.6g (%.3g of the diagonal)", x->surface, x->mesh, r->hausdorff,
           r->hausdorff / d);
    if (x->tolerance > 0)
        printf(", tolerance %.6g: %s", x->tolerance,
               r->hausdorff <= x->tolerance ? "within" : "EXCEEDED");
    printf("\n  mesh to surface  max %.6g  mean %.6g  rms %.6g  (%zu samples)\n",
           r->mesh_to_surface.max, r->mesh_to_surface.mean, r->mesh_to_surface.rms,
           r->mesh_to_surface.samples);
    printf("  surface to mesh  max %.6g  mean %.6g  rms %.6g  (%zu samples)\n",
           r->surface_to_mesh.max, r->surface_to_mesh.mean, r->surface_to_mesh.rms,
           r->surface_to_mesh.samples);
}

/* Picture of `shown` coloured by its distance to `other`. */
static sk_status draw_map(const sk_soup *shown, const char *name, sk_bvh *other,
                          const char *label, double scale, sk_render_opts *ro, const char *path,
                          sk_error *err)
{
    ro->title = name;
    return sk_render_field(shown, sk_bvh_distance, other, scale, label, path, ro, err);
}

int cmd_deviation(int argc, char **argv)
{
    const char *png = NULL, *png_surface = NULL, *report = NULL;
    run x = {0};
    sk_deviation_opts opts = {0};
    sk_render_opts ro = {0};
    double tol_rel = 0;
    bool json = false, quiet = false;
    const cli_opt table[] = {
        OPT_INT("--samples", opts.face_samples, 1, 64, "N",
                "N x N samples per triangle (default 2)"),
        OPT_DOUBLE("--tolerance", x.tolerance, 0, 0, CLI_LO_OPEN, "T", "tolerance in model units"),
        OPT_DOUBLE("--tolerance-rel", tol_rel, 0, 0, CLI_LO_OPEN, "R",
                   "tolerance as a fraction of MESH's bounding-box diagonal"),
        OPT_FILE("--png", png, "MAP.png", "MESH coloured by its distance to SURFACE"),
        OPT_FILE("--png-surface", png_surface, "MAP.png",
                 "SURFACE coloured by its distance to MESH"),
        OPT_VEC3("--view", ro.view, "viewing direction of the pictures (default 0,0,-1)"),
        OPT_FILE("--report", report, "REPORT.json", "the figures as JSON"),
        OPT_FLAG("--json", json, "print the JSON instead of the summary"),
        OPT_FLAG("-q", quiet, "no progress bar"),
    };
    const cli_spec spec = {"deviation", "SURFACE MESH", about,
                           table, CLI_COUNT(table), 2, 2, examples, NULL};
    cli_args args;
    int prc = cli_parse(&spec, argc, argv, &args);
    if (prc)
        return prc == CLI_HELP ? EXIT_OK : prc;
    x.surface = cli_input(&args, 0);
    x.mesh = cli_input(&args, 1);
    if (x.tolerance > 0 && tol_rel > 0)
        return cli_usage("deviation", "give --tolerance or --tolerance-rel, not both");
    cli_progress bar;
    cli_progress_init(&bar, "deviation", quiet);
    opts.progress = cli_progress_cb;
    opts.progress_user = &bar;
    sk_error err = {0};
    sk_soup *surface = NULL, *mesh = NULL;
    sk_status st = sk_soup_read(x.surface, NULL, &surface, &err);
    if (!st)
        st = sk_soup_read(x.mesh, NULL, &mesh, &err);
    bool named = false;
    sk_bvh *bvh_s = NULL, *bvh_m = NULL; /* kept from sk_deviation for the maps */
    opts.surface_bvh = png ? &bvh_s : NULL;
    opts.mesh_bvh = png_surface ? &bvh_m : NULL;
    if (!st && (st = sk_deviation(surface, mesh, &opts, &x.r, NULL, &err)) != SK_OK) {
        cli_progress_done(&bar); /* the library names the side; the files are named here */
        cli_error("%s vs %s: %s", x.surface, x.mesh, err.message);
        named = true;
    }
    cli_progress_done(&bar);
    if (!st && tol_rel > 0)
        x.tolerance = tol_rel * x.r.diagonal;
    if (!st && png)
        st = draw_map(mesh, x.mesh, bvh_s, "distance to the surface", x.tolerance, &ro, png, &err);
    if (!st && png_surface)
        st = draw_map(surface, x.surface, bvh_m, "distance to the mesh", x.tolerance, &ro,
                      png_surface, &err);
    sk_bvh_destroy(&bvh_s);
    sk_bvh_destroy(&bvh_m);
    int rc = named ? cli_exit_code(st) : st ? cli_fail(st, &err) : EXIT_OK;
    if (!st && report)
        rc = cli_write_file(report, write_json, &x);
    if (rc == EXIT_OK) {
        if (json)
            write_json(stdout, &x);
        else
            print_summary(&x);
    }
    sk_soup_destroy(&surface);
    sk_soup_destroy(&mesh);
    return rc;
}
