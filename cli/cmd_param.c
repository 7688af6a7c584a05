/* surfkit param: parametrization of a disk (linear methods, or hierarchical / flat MIPS), metrics,
 * pictures. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static const char help[] =
    "usage: surfkit param IN -o OUT [--method tutte|floater|mvc|harmonic|lscm|mips]\n"
    "                     [--boundary circle|square|free] [--spacing chord|uniform]\n"
    "                     [--solver direct|hierarchical]\n"
    "                     [--hierarchical | --flat] [--steps N] [--seed S]\n"
    "                     [--png LAYOUT.png] [--svg LAYOUT.svg] [--checker VIEW.png]\n"
    "                     [--view X,Y,Z] [--report REPORT.json] [--json] [--ascii]\n"
    "                     [--no-normalize] [-q]\n"
    "\n"
    "Maps a triangulated disk (one boundary loop, Euler characteristic 1) to the plane.\n"
    "Fixed boundary (circle by default, or the unit square with corners at the four sharpest\n"
    "boundary turns, where an interior edge with both ends on one side is split at its midpoint,\n"
    "adding an interior vertex to the output, so that no triangle lies on one side; boundary\n"
    "spacing by chord length by default): tutte (uniform weights), floater\n"
    "(shape-preserving, the default), mvc (mean value), harmonic (cotangent weights; obtuse\n"
    "triangles give negative weights that can flip triangles). Free boundary: lscm (least\n"
    "squares conformal, two boundary vertices pinned). Tutte, floater and mvc never flip a\n"
    "triangle with a convex boundary. --solver direct (default: sparse Cholesky / LU) or\n"
    "hierarchical (multilevel CG / BiCGStab over the progressive mesh, the coarsest level solved\n"
    "directly; the same uv to 1e-8 of the layout, not faster today: docs/linear.md).\n"
    "\n"
    "mips: minimises the MIPS energy (sum of sigma1/sigma2 + sigma2/sigma1) by local steps that\n"
    "never flip a triangle. --hierarchical (default): Hormann, Greiner, Campagna: a progressive\n"
    "mesh, the coarsest level from Floater, then level by level the removed vertices inserted\n"
    "at their barycentric coordinates and optimised. --flat: the conventional method, Floater on\n"
    "the full mesh then local steps in random order. --boundary free (default for mips) lets\n"
    "the boundary move; circle/square keep it fixed. --steps N bounds the local steps.\n"
    "\n"
    "OUT: .obj (v + vt, faces v/vt) or .ply (with s t); formats without texture coordinates\n"
    "(.off, .stl) are refused. The uv are normalized to the unit square (one uniform scale and\n"
    "a translation, aspect kept: the larger side spans [0, 1]); --no-normalize writes each\n"
    "method's own scale (unit circle, unit square, LSCM's pins, MIPS's drifting scale).\n"
    "--png/--svg draw the uv layout coloured by conformal distortion sigma1/sigma2, flipped\n"
    "triangles in magenta; --checker draws the 3D mesh with a checkerboard texture seen along\n"
    "--view (default 0,0,-1). --report writes the metrics as JSON; --json prints them.\n"
    "\n"
    "Flipped triangles (harmonic and lscm can flip; the others never do): OUT and the pictures\n"
    "are still written, a warning saying how many goes to stderr, the summary and the report\n"
    "have 'flipped', and the exit code is 0. Exit codes: 0 done, 1 bad input (not a disk),\n"
    "2 usage error, 3 internal failure.\n"
    "\n"
    "examples:\n"
    "  surfkit param face.off -o face.obj --png layout.png\n"
    "  surfkit param face.off -o face.ply --method mips --report metrics.json\n"
    "  surfkit param face.off -o face.obj --method mips --flat --steps 100000\n";

/* What a run did, for the report. */
typedef struct run_info {
    const char *in;
    sk_parametrize_stats ps;
    sk_param_metrics pm;
} run_info;

static void write_json(FILE *fp, const void *ctx)
{
    const run_info *r = ctx;
    const sk_param_metrics *pm = &r->pm;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", r->in);
    json_kstr(&j, "method", r->ps.name);
    json_kstr(&j, "boundary", sk_boundary_shape_name(r->ps.boundary));
    json_kuint(&j, "faces", pm->faces);
    json_kuint(&j, "flipped", pm->flipped);
    json_kuint(&j, "degenerate", pm->degenerate);
    json_knum(&j, "mips_sum", pm->mips_sum);
    json_knum(&j, "mips_mean", pm->mips_mean);
    json_knum(&j, "conformal_mean", pm->conformal_mean);
    json_knum(&j, "conformal_max", pm->conformal_max);
    json_knum(&j, "area_log_mean", pm->area_log_mean);
    json_knum(&j, "stretch_max", pm->stretch_max);
    json_kuint(&j, "boundary_self_intersections", pm->boundary_self_intersections);
    json_knum(&j, "seconds", r->ps.seconds);
    if (r->ps.method != SK_PARAM_MIPS) {
        const sk_param_stats *ps = &r->ps.linear;
        json_kuint(&j, "vertices", ps->vertices);
        json_kuint(&j, "interior", ps->interior);
        json_key(&j, "timing");
        json_obj_open(&j);
        json_knum(&j, "check", ps->check_seconds);
        json_knum(&j, "boundary", ps->boundary_seconds);
        json_knum(&j, "weights_and_assembly", ps->weights_seconds);
        json_knum(&j, "analyse", ps->solve.analyse_seconds);
        json_knum(&j, "factor", ps->solve.factor_seconds);
        json_knum(&j, "solve", ps->solve.solve_seconds);
        json_obj_close(&j);
        json_key(&j, "solver");
        json_obj_open(&j);
        json_kstr(&j, "kind", ps->solve.kind == SK_SOLVER_CHOLESKY ? "cholmod" : "umfpack");
        json_kuint(&j, "n", ps->solve.n);
        json_kuint(&j, "nnz", ps->solve.nnz);
        json_kuint(&j, "factor_nnz", ps->solve.factor_nnz);
        json_obj_close(&j);
    } else if (r->ps.hierarchical) {
        const sk_hparam_stats *hs = &r->ps.hparam;
        json_kuint(&j, "steps", hs->steps);
        json_kuint(&j, "repaired_insertions", hs->repaired);
        json_kuint(&j, "fallbacks", hs->fallbacks);
        json_knum(&j, "hierarchy_seconds", hs->hierarchy_seconds);
        json_key(&j, "levels"); /* coarsest first */
        json_arr_open(&j);
        for (size_t l = 0; l < hs->num_levels; ++l) {
            const sk_hparam_level *lv = &hs->levels[l];
            json_obj_open(&j);
            json_kuint(&j, "vertices", lv->vertices);
            json_kuint(&j, "faces", lv->faces);
            json_kuint(&j, "sweeps", lv->sweeps);
            json_kuint(&j, "steps", lv->steps);
            json_kuint(&j, "repaired", lv->repaired);
            json_knum(&j, "energy", lv->energy);
            json_knum(&j, "seconds", lv->seconds);
            json_obj_close(&j);
        }
        json_arr_close(&j);
    } else {
        json_kuint(&j, "steps", r->ps.mips.steps);
        json_kuint(&j, "sweeps", r->ps.mips.sweeps);
        json_knum(&j, "energy_start", r->ps.mips.energy_start);
    }
    json_obj_close(&j);
    json_end(&j);
}

/* argv -> options; returns EXIT_OK to run, or the exit code (help printed, usage error). */
typedef struct param_args {
    const char *in, *out, *png, *svg, *checker, *report;
    bool quiet, json, hier_flag, solver_flag;
    sk_parametrize_opts po;
    sk_param_opts linear; /* --solver: the linear methods' fine tuning (po.linear) */
    sk_write_opts wo;
    sk_render_opts ro;
} param_args;

static int parse_args(int argc, char **argv, param_args *a)
{
    const char *val;
    unsigned long steps = 0, seed = 0;
    const cli_path_opt paths[] = {{"-o", &a->out}, {"--png", &a->png}, {"--svg", &a->svg},
                                  {"--checker", &a->checker}, {"--report", &a->report}};
    int took;
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i];
        if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
            fputs(help, stdout);
            fputs(cli_param_atlas_help, stdout);
            return -1;
        } else if (!strcmp(s, "-q")) {
            a->quiet = true;
        } else if (!strcmp(s, "--json")) {
            a->json = true;
        } else if (!strcmp(s, "--ascii")) {
            a->wo.ascii = true;
        } else if (!strcmp(s, "--no-normalize")) {
            a->po.raw = true;
        } else if (!strcmp(s, "--flat")) {
            a->po.flat = true;
        } else if (!strcmp(s, "--hierarchical")) {
            a->hier_flag = true;
        } else if ((took = cli_take_path(argc, argv, &i, "param", paths, 5)) != 0) {
            if (took < 0)
                return EXIT_USAGE;
        } else if (cli_opt_value(argc, argv, &i, "--method", &val)) {
            if (!sk_param_method_parse(val, &a->po.method))
                return cli_usage("param", "--method takes tutte, floater, mvc, harmonic, lscm or "
                                          "mips");
        } else if (cli_opt_value(argc, argv, &i, "--boundary", &val)) {
            if (!sk_boundary_shape_parse(val, &a->po.boundary.shape) ||
                a->po.boundary.shape == SK_BOUNDARY_GIVEN)
                return cli_usage("param", "--boundary takes circle, square or free");
        } else if (cli_opt_value(argc, argv, &i, "--solver", &val)) {
            if (val && !strcmp(val, "direct"))
                a->linear.solver = SK_LINEAR_DIRECT;
            else if (val && !strcmp(val, "hierarchical"))
                a->linear.solver = SK_LINEAR_HIERARCHICAL;
            else
                return cli_usage("param", "--solver takes direct or hierarchical");
            a->solver_flag = true;
            a->po.linear = &a->linear;
        } else if (cli_opt_value(argc, argv, &i, "--spacing", &val)) {
            if (val && !strcmp(val, "chord"))
                a->po.boundary.spacing = SK_SPACING_CHORD;
            else if (val && !strcmp(val, "uniform"))
                a->po.boundary.spacing = SK_SPACING_UNIFORM;
            else
                return cli_usage("param", "--spacing takes chord or uniform");
        } else if (cli_opt_value(argc, argv, &i, "--steps", &val)) {
            if (!cli_parse_uint(val, &steps) || steps == 0)
                return cli_usage("param", "--steps takes a positive whole number");
            a->po.max_steps = steps;
        } else if (cli_opt_value(argc, argv, &i, "--seed", &val)) {
            if (!cli_parse_uint(val, &seed))
                return cli_usage("param", "--seed takes a whole number");
            a->po.seed = seed;
        } else if (cli_opt_value(argc, argv, &i, "--view", &val)) {
            if (!cli_parse_vec3(val, a->ro.view))
                return cli_usage("param", "--view takes three numbers X,Y,Z");
        } else if (s[0] == '-' && s[1]) {
            return cli_usage("param", "unknown option '%s'", s);
        } else if (!a->in) {
            a->in = s;
        } else {
            return cli_usage("param", "more than one input file");
        }
    }
    if (!a->in || !a->out)
        return cli_usage("param", "needs an input file and -o OUT");
    sk_format ofmt = sk_format_from_path(a->out);
    if (ofmt == SK_FORMAT_UNKNOWN)
        return cli_usage("param", "cannot tell the output format of '%s'", a->out);
    if (ofmt != SK_FORMAT_OBJ && ofmt != SK_FORMAT_PLY)
        return cli_usage("param", "%s cannot hold texture coordinates ('%s'): write .obj or .ply",
                         sk_format_name(ofmt), a->out);
    if (a->po.flat && a->hier_flag)
        return cli_usage("param", "--flat and --hierarchical exclude each other");
    if (a->hier_flag && a->po.method != SK_PARAM_MIPS)
        return cli_usage("param", "--hierarchical goes with --method mips");
    if (a->solver_flag && a->po.method == SK_PARAM_MIPS)
        return cli_usage("param", "--solver goes with the linear methods");
    sk_error err;
    if (sk_parametrize_check(&a->po, &err))
        return cli_usage("param", "%s", err.message);
    return EXIT_OK;
}

int cmd_param(int argc, char **argv)
{
    bool atlas = false; /* not one disk, or --atlas: charts + packing (cmd_param_atlas.c) */
    int atlas_rc = cmd_param_atlas(argc, argv, &atlas);
    if (atlas)
        return atlas_rc;
    param_args a;
    memset(&a, 0, sizeof a);
    int rc = parse_args(argc, argv, &a);
    if (rc)
        return rc < 0 ? EXIT_OK : rc;
    cli_progress bar;
    cli_progress_init(&bar, "param", a.quiet);
    a.po.progress = cli_progress_cb;
    a.po.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    double *uv = NULL;
    run_info r;
    memset(&r, 0, sizeof r);
    r.in = a.in;
    sk_status st = sk_mesh_read(a.in, NULL, &mesh, &err);
    if (st == SK_OK) {
        uv = calloc(2 * mesh->num_vertices + 1, sizeof *uv);
        if (!uv)
            st = SK_ERR_NOMEM, snprintf(err.message, sizeof err.message, "out of memory");
    }
    if (st == SK_OK && a.po.boundary.shape == SK_BOUNDARY_SQUARE && !a.po.boundary.has_corners &&
        sk_param_check_disk(mesh, NULL) == SK_OK) {
        /* corners at the sharpest turns; dividing edges split (else their triangles flatten) */
        sk_mesh *split = NULL;
        size_t splits = 0;
        st = sk_param_square_corners(mesh, a.po.boundary.corners, &err);
        if (st == SK_OK)
            st = sk_param_split_side_edges(mesh, a.po.boundary.corners, &split, &splits, &err);
        if (st == SK_OK) {
            a.po.boundary.has_corners = true;
            if (splits && !a.quiet)
                fprintf(stderr, "surfkit param: %s: split %zu interior edges with both ends on one "
                        "side of the square (%zu vertices added)\n", a.in, splits, splits);
            sk_mesh_destroy(&mesh);
            mesh = split;
            double *grown = realloc(uv, (2 * mesh->num_vertices + 1) * sizeof *uv);
            if (!grown)
                st = SK_ERR_NOMEM, snprintf(err.message, sizeof err.message, "out of memory");
            else
                memset(uv = grown, 0, (2 * mesh->num_vertices + 1) * sizeof *uv);
        }
    }
    if (st == SK_OK)
        st = sk_parametrize(mesh, &a.po, uv, &r.ps, &err);
    cli_progress_done(&bar);
    if (st == SK_WARN_FLIPS) { /* the result is complete: write it and say so */
        fprintf(stderr, "surfkit param: warning: %s: %s\n", a.in, err.message);
        st = SK_OK;
    }
    if (st == SK_OK)
        st = sk_param_metrics_compute(mesh, uv, &r.pm, &err);
    if (st == SK_OK && !(st = sk_mesh_add_uvs(mesh, &err))) {
        memcpy(mesh->uvs, uv, 2 * mesh->num_vertices * sizeof *uv);
        st = sk_mesh_write(a.out, mesh, &a.wo, &err);
    }
    const char *boundary = sk_boundary_shape_name(r.ps.boundary);
    char title[256];
    if (st == SK_OK)
        snprintf(title, sizeof title, "%s: %s, %s boundary, MIPS mean %.4f, flipped %zu", a.in,
                 r.ps.name, boundary, r.pm.mips_mean, r.pm.flipped);
    a.ro.title = title;
    if (st == SK_OK && a.png)
        st = sk_render_uv(mesh, uv, a.png, &a.ro, &err);
    if (st == SK_OK && a.svg)
        st = sk_render_uv(mesh, uv, a.svg, &a.ro, &err);
    if (st == SK_OK && a.checker)
        st = sk_render_checker(mesh, uv, a.checker, &a.ro, &err);
    rc = st ? cli_fail(st, &err) : EXIT_OK;
    if (rc == EXIT_OK && a.report)
        rc = cli_write_file(a.report, write_json, &r);
    if (rc == EXIT_OK) {
        if (a.json)
            write_json(stdout, &r);
        else if (!a.quiet)
            printf("%s: %zu faces, %s, %s boundary, flipped %zu, MIPS sum %.6f (mean %.6f), "
                   "conformal %.4f, area log %.4f, boundary self-intersections %zu, %.3f s\n",
                   a.in, r.pm.faces, r.ps.name, boundary, r.pm.flipped, r.pm.mips_sum,
                   r.pm.mips_mean, r.pm.conformal_mean, r.pm.area_log_mean,
                   r.pm.boundary_self_intersections, r.ps.seconds);
    }
    sk_parametrize_stats_release(&r.ps);
    free(uv);
    sk_mesh_destroy(&mesh);
    return rc;
}
