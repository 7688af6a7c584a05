/* surfkit fit: one tensor-product B-spline surface fitted to a triangulated disk within a
 * tolerance, written as STEP or IGES (or tessellated), with its deviation from the mesh. */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Fits one tensor-product B-spline surface to the triangulated disk DISK: parametrizes it over\n"
    "the unit square (Floater's shape-preserving map; the four corners are the four sharpest\n"
    "turns of the boundary, spread apart, or --corners), balanced by MIPS with an area term at\n"
    "theta 1 and 0.5 and not at all (the fit with the fewest control points within the\n"
    "tolerance kept; --area-theta picks one), fits the control points to the vertices\n"
    "and to points of every face by least squares with a thin-plate smoothing term, corrects the\n"
    "parameters towards the foot points, and inserts knots in the worst of the spans where the\n"
    "surface is farther than the tolerance from the mesh (--refine-share of them per round and\n"
    "direction), until it holds both ways or the data runs out.\n";

static const char more[] =
    "The summary gives the control points, the tolerance, and the deviation between the surface\n"
    "(tessellated) and the mesh measured both ways (surfkit deviation's figures: vertices and face\n"
    "samples of each to the other). Exit 4 when the tolerance is not met (the surface is still\n"
    "written). A closed surface or one with several boundary loops is not a disk: cut it into\n"
    "disks with `surfkit param --atlas`, or build G1 patches with `surfkit smooth`.\n";

static const char examples[] =
    "  surfkit fit data/nefertiti.off -o nefertiti.step --tolerance-rel 0.05\n"
    "  surfkit fit data/nefertiti.off -o nefertiti.igs --tolerance-rel 0.05 --degree 4 --json\n";

/* Cells per side of the tessellation at most (sk_fit_tessellate): the deviation's cost. */
#define TESS_SIDE 1024

typedef struct fit_run {
    const char *in, *out, *method;
    sk_fit_stats fs;
    sk_deviation_report dev;
    size_t nu, nv;
    int degree;
    size_t bytes;
    double chord;    /* bound on the tessellation's chord error */
    size_t tess_nu, tess_nv; /* cells of the tessellation (deviation, mesh output) */
    bool area_auto;
    double seconds_write, seconds_deviation, seconds;
} fit_run;

static void write_json(FILE *fp, const void *ctx)
{
    const fit_run *x = ctx;
    double diag = x->dev.diagonal > 0 ? x->dev.diagonal : 1;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", x->in);
    json_kstr(&j, "output", x->out);
    json_kint(&j, "degree", x->degree);
    json_kstr(&j, "method", x->method);
    json_knum(&j, "area_theta", x->fs.area_theta);
    json_kbool(&j, "area_theta_auto", x->area_auto);
    json_kuint(&j, "control_points", x->fs.control_points);
    json_kuint(&j, "nu", x->nu);
    json_kuint(&j, "nv", x->nv);
    json_key(&j, "corners");
    json_arr_open(&j);
    for (int k = 0; k < 4; ++k)
        json_uint(&j, x->fs.corners[k]);
    json_arr_close(&j);
    json_kuint(&j, "rounds", x->fs.rounds);
    json_kuint(&j, "samples", x->fs.samples);
    json_kuint(&j, "split_edges", x->fs.split_edges);
    json_kuint(&j, "flipped", x->fs.flipped);
    json_knum(&j, "tolerance", x->fs.tolerance);
    json_knum(&j, "tolerance_rel", x->fs.tolerance / diag);
    json_kbool(&j, "met", x->fs.met);
    json_knum(&j, "fit_max", x->fs.max_error);
    json_knum(&j, "fit_rms", x->fs.rms_error);
    json_knum(&j, "fit_surface_to_mesh", x->fs.surface_to_mesh);
    json_key(&j, "deviation");
    json_obj_open(&j);
    json_knum(&j, "hausdorff", x->dev.hausdorff);
    json_knum(&j, "hausdorff_rel", x->dev.hausdorff / diag);
    json_knum(&j, "diagonal", x->dev.diagonal);
    json_knum(&j, "mesh_to_surface_max", x->dev.mesh_to_surface.max);
    json_knum(&j, "mesh_to_surface_rms", x->dev.mesh_to_surface.rms);
    json_knum(&j, "surface_to_mesh_max", x->dev.surface_to_mesh.max);
    json_knum(&j, "surface_to_mesh_rms", x->dev.surface_to_mesh.rms);
    json_obj_close(&j);
    json_kuint(&j, "bytes", x->bytes);
    json_kuint(&j, "tessellation", x->tess_nu > x->tess_nv ? x->tess_nu : x->tess_nv);
    json_kuint(&j, "tessellation_nu", x->tess_nu);
    json_kuint(&j, "tessellation_nv", x->tess_nv);
    json_knum(&j, "tessellation_chord_bound", x->chord);
    json_knum(&j, "seconds_param", x->fs.seconds_param);
    json_knum(&j, "seconds_fit", x->fs.seconds_fit);
    json_knum(&j, "seconds_write", x->seconds_write);
    json_knum(&j, "seconds_deviation", x->seconds_deviation);
    json_knum(&j, "seconds", x->seconds);
    /* last: its entries' keys repeat the summary's (the tests grep the first) */
    json_key(&j, "maps_tried");
    json_arr_open(&j);
    for (size_t k = 0; k < x->fs.tries; ++k) {
        const sk_fit_try *t = &x->fs.tried[k];
        json_obj_open(&j);
        json_knum(&j, "area_theta", t->area_theta);
        json_kuint(&j, "control_points", t->control_points);
        json_knum(&j, "deviation", t->deviation);
        json_kbool(&j, "met", t->met);
        json_kbool(&j, "capped", t->capped);
        json_knum(&j, "seconds", t->seconds);
        json_obj_close(&j);
    }
    json_arr_close(&j);
    json_obj_close(&j);
    json_end(&j);
}

static void print_summary(const fit_run *x)
{
    double diag = x->dev.diagonal > 0 ? x->dev.diagonal : 1;
    printf("fit: wrote %s: degree %d, %zu x %zu = %zu control points, %zu rounds, %.3f s\n", x->out,
           x->degree, x->nu, x->nv, x->fs.control_points, x->fs.rounds, x->seconds);
    printf("fit: tolerance %.6g (%.3g of the diagonal) %s; deviation max %.6g (%.3g), "
           "rms %.6g: mesh to surface max %.6g rms %.6g, surface to mesh max %.6g rms %.6g\n",
           x->fs.tolerance, x->fs.tolerance / diag, x->fs.met ? "met" : "NOT MET",
           x->dev.hausdorff, x->dev.hausdorff / diag, x->dev.mesh_to_surface.rms,
           x->dev.mesh_to_surface.max, x->dev.mesh_to_surface.rms, x->dev.surface_to_mesh.max,
           x->dev.surface_to_mesh.rms);
}

static bool parse_corners(const char *s, uint32_t c[4])
{
    for (int k = 0; k < 4; ++k) {
        char *end = NULL;
        if (!s || *s < '0' || *s > '9')
            return false;
        unsigned long v = strtoul(s, &end, 10);
        if (v >= UINT32_MAX || end == s || (k < 3 && *end != ',') || (k == 3 && *end))
            return false;
        c[k] = (uint32_t)v;
        s = end + 1;
    }
    return true;
}

typedef enum { OUT_STEP, OUT_IGES, OUT_MESH } out_kind;

static bool out_kind_of(const char *path, out_kind *k)
{
    if (sk_path_has_ext(path, ".step") || sk_path_has_ext(path, ".stp"))
        *k = OUT_STEP;
    else if (sk_path_has_ext(path, ".igs") || sk_path_has_ext(path, ".iges"))
        *k = OUT_IGES;
    else if (sk_path_has_ext(path, ".obj") || sk_path_has_ext(path, ".ply") ||
             sk_path_has_ext(path, ".off") || sk_path_has_ext(path, ".stl"))
        *k = OUT_MESH;
    else
        return false;
    return true;
}

static const char *const unit_names[] = {"mm", "cm", "m", "um", "in", "ft"};

/* argv -> options */
typedef struct fit_args {
    const char *report, *tess_path, *corners;
    bool json, quiet;
    out_kind kind;
    sk_fit_opts fo;
    sk_export_opts eo;
} fit_args;

/* EXIT_OK to run, CLI_HELP, or the usage error's exit code */
static int parse_args(int argc, char **argv, fit_run *x, fit_args *a)
{
    unsigned units = 0, method = 0;
    int degree = 3, max_cp = 0;
    const cli_opt opts[] = {
        OPT_OUTPUT(x->out, "OUT",
                   ".step/.stp: STEP AP214, one B_SPLINE_SURFACE_WITH_KNOTS as the face of an\n"
                   "open shell; .igs/.iges: IGES 5.3, one entity 128; .obj/.ply/.off/.stl: a\n"
                   "tessellation of the surface (each knot span split as finely as a bound on\n"
                   "its chord error below 1/20 of the tolerance needs, 64 to 1024 per side)"),
        OPT_DOUBLE("--tolerance", a->fo.tolerance, 0, 0, CLI_LO_OPEN, "T",
                   "largest distance between surface and mesh, model units"),
        OPT_DOUBLE("--tolerance-rel", a->fo.tolerance_rel, 0, 1, CLI_LO_OPEN, "R",
                   "the tolerance as R times the bounding-box diagonal (default 1e-3)"),
        OPT_DOUBLE("--refine-share", a->fo.refine_share, 0, 1, CLI_LO_OPEN, "S",
                   "share of the knot spans above the tolerance split per round and direction,\n"
                   "the worst first (default 0.1; 1 bisects all of them)"),
        OPT_DOUBLE("--smoothing", a->fo.smoothing, 0, 0, CLI_LO_OPEN, "W",
                   "weight of the thin-plate term (default: each round tries 1e-6 and 1e-3\n"
                   "and keeps the closer fit)"),
        OPT_INT("--degree", degree, 2, 5, "D", "degree in both directions (default 3, bicubic)"),
        OPT_INT("--max-control-points", max_cp, 16, 1048576, "N",
                "stop refining before the grid passes N control points (default: twice\n"
                "the disk's vertex count)"),
        OPT_STRING("--corners", a->corners, "I,J,K,L",
                   "the boundary vertices mapped to (0,0), (1,0), (1,1), (0,1), in\n"
                   "counter-clockwise order around the surface (0-based vertex ids)"),
        OPT_CHOICE("--method", method, "floater|mips",
                   "the square map: floater (default) or mips (hierarchical MIPS with the\n"
                   "square boundary fixed)"),
        OPT_DOUBLE("--area-theta", a->fo.area_theta, 0, 0, 0, "A",
                   "balance the square map's areas by MIPS times (area scale + 1/area scale)^A,\n"
                   "the sides kept; 0: no balance (default: A = 1, 0.5 and none tried, the fit\n"
                   "with the fewest control points within the tolerance kept)"),
        OPT_CHOICE("--units", units, "mm|cm|m|um|in|ft",
                   "CAD length unit of the coordinates (default mm)"),
        OPT_FILE("--tessellation", a->tess_path, "MESH",
                 "also writes the tessellation (as -o does for a mesh file): vertex (i, j) is\n"
                 "the surface point at (u_i, v_j), the lines dividing each knot span evenly"),
        OPT_FILE("--report", a->report, "FILE", "the summary as JSON in FILE"),
        OPT_FLAG("--json", a->json, "print the summary as JSON instead"),
        OPT_FLAG("-q", a->quiet, "no progress bar, no summary"),
    };
    const cli_spec spec = {"fit", "DISK -o OUT.step|OUT.igs|OUT.obj|OUT.ply", about,
                           opts, CLI_COUNT(opts), 1, 1, examples, more};
    cli_args args;
    int rc = cli_parse(&spec, argc, argv, &args);
    if (rc)
        return rc;
    x->in = cli_input(&args, 0);
    a->fo.degree = degree;
    a->fo.max_control_points = (size_t)max_cp;
    a->fo.method = method ? SK_PARAM_MIPS : SK_PARAM_FLOATER;
    if (cli_given(&args, "--units"))
        a->eo.units = unit_names[units];
    if (a->corners && !parse_corners(a->corners, a->fo.corners))
        return cli_usage("fit", "--corners takes four vertex ids I,J,K,L, not '%s'", a->corners);
    a->fo.has_corners = a->corners != NULL;
    x->area_auto = !cli_given(&args, "--area-theta");
    if (!x->area_auto && a->fo.area_theta == 0)
        a->fo.area_theta = -1; /* the library's "no balance"; its 0 is the automatic choice */
    if (!out_kind_of(x->out, &a->kind))
        return cli_usage("fit", "-o must name a .step, .stp, .igs, .iges, .obj, .ply, .off or "
                         ".stl file");
    if (a->fo.tolerance > 0 && a->fo.tolerance_rel > 0)
        return cli_usage("fit", "give --tolerance or --tolerance-rel, not both");
    return EXIT_OK;
}

int cmd_fit(int argc, char **argv)
{
    fit_run x = {0};
    fit_args a;
    memset(&a, 0, sizeof a);
    int prc = parse_args(argc, argv, &x, &a);
    if (prc)
        return prc == CLI_HELP ? EXIT_OK : prc;
    sk_fit_opts fo = a.fo;
    sk_export_opts eo = a.eo;
    const char *report = a.report, *tess_path = a.tess_path;
    bool json = a.json, quiet = a.quiet;
    out_kind kind = a.kind;

    x.method = fo.method == SK_PARAM_MIPS ? "mips" : "floater";
    double t0 = sk_seconds();
    cli_progress bar;
    cli_progress_init(&bar, "fit", quiet);
    fo.progress = cli_progress_cb;
    fo.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    sk_bspline_surface *s = NULL;
    sk_soup *tess = NULL, *ms = NULL;
    int rc = EXIT_OK;
    sk_status st = sk_mesh_read(x.in, NULL, &mesh, &err);
    if (!st)
        st = sk_mesh_to_soup(mesh, &ms, &err);
    if (!st) {
        st = sk_fit_bspline(mesh, &fo, &s, &x.fs, &err);
        if (st == SK_ERR_TOPOLOGY) { /* not a disk: say what to do instead, on one line */
            cli_progress_done(&bar);
            cli_error("%s: %s; `surfkit fit` fits one disk: cut the surface into disks with "
                      "`surfkit param --atlas`, or build G1 patches with `surfkit smooth`",
                      x.in, err.message);
            rc = EXIT_BAD_INPUT;
            goto done;
        }
    }
    cli_progress_done(&bar);
    if (!st) {
        x.nu = s->nu, x.nv = s->nv, x.degree = s->degree_u;
        /* the chord error a twentieth of the deviation to measure: of T when the fit is within
         * it, of the fit's own error when it is not (T may be far out of reach, e.g. 1e-6 of
         * the diagonal: a 1024-a-side grid would measure a miss 10^4 times larger) */
        double scale = x.fs.met ? x.fs.tolerance : fmax(x.fs.tolerance, x.fs.max_error);
        sk_fit_tessellation ti = {0};
        st = sk_fit_tessellate(s, scale, TESS_SIDE, &tess, &ti, &err);
        x.tess_nu = ti.nu, x.tess_nv = ti.nv, x.chord = ti.chord;
        double tw = sk_seconds();
        sk_export_stats es = {0};
        if (!st && kind == OUT_STEP)
            st = sk_export_bspline_step(x.out, s, &eo, &es, &err);
        else if (!st && kind == OUT_IGES)
            st = sk_export_bspline_iges(x.out, s, &eo, &es, &err);
        else if (!st)
            st = sk_soup_write(x.out, tess, NULL, &err);
        if (!st && tess_path)
            st = sk_soup_write(tess_path, tess, NULL, &err);
        x.bytes = es.bytes;
        x.seconds_write = sk_seconds() - tw;
    }
    if (!st) {
        double td = sk_seconds();
        st = sk_deviation(tess, ms, NULL, &x.dev, NULL, &err);
        x.seconds_deviation = sk_seconds() - td;
        if (x.dev.hausdorff > x.fs.tolerance)
            x.fs.met = false; /* what the summary shows decides, not the fit's own grid */
    }
    x.seconds = sk_seconds() - t0;
    if (st) {
        rc = cli_fail(st, &err);
        goto done;
    }
    if (report)
        rc = cli_write_file(report, write_json, &x);
    if (rc == EXIT_OK) {
        if (json)
            write_json(stdout, &x);
        else if (!quiet)
            print_summary(&x);
        if (!x.fs.met) {
            fprintf(stderr, "surfkit fit: %s: tolerance %.6g not met (Hausdorff %.6g; the fit's "
                    "max %.6g, surface to mesh %.6g) with %zu control points after %zu rounds\n",
                    x.in, x.fs.tolerance, x.dev.hausdorff, x.fs.max_error, x.fs.surface_to_mesh,
                    x.fs.control_points, x.fs.rounds);
            rc = EXIT_QUALITY;
        }
    }
done:
    sk_bspline_destroy(&s);
    sk_soup_destroy(&tess);
    sk_soup_destroy(&ms);
    sk_mesh_destroy(&mesh);
    return rc;
}
