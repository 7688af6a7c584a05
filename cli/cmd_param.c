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
    "                     [--view X,Y,Z] [--report REPORT.json] [--json] [--ascii] [-q]\n"
    "\n"
    "Maps a triangulated disk (one boundary loop, Euler characteristic 1) to the plane.\n"
    "Fixed boundary (circle by default, or the unit square with corners at quarter arc length;\n"
    "boundary spacing by chord length by default): tutte (uniform weights), floater\n"
    "(shape-preserving, the default), mvc (mean value), harmonic (cotangent weights; obtuse\n"
    "triangles give negative weights that can flip triangles). Free boundary: lscm (least\n"
    "squares conformal, two boundary vertices pinned). Tutte, floater and mvc never flip a\n"
    "triangle with a convex boundary. --solver: direct (sparse Cholesky / LU, the default) or\n"
    "hierarchical (multilevel over the progressive mesh, Krylov iterations to a relative residual\n"
    "of 1e-12; the same system).\n"
    "\n"
    "mips: minimises the MIPS energy (sum of sigma1/sigma2 + sigma2/sigma1) by local steps that\n"
    "never flip a triangle. --hierarchical (default): Hormann, Greiner, Campagna: a progressive\n"
    "mesh, the coarsest level from Floater, then level by level the removed vertices inserted\n"
    "at their barycentric coordinates and optimised. --flat: the conventional method, Floater on\n"
    "the full mesh then local steps in random order. --boundary free (default for mips) lets\n"
    "the boundary move; circle/square keep it fixed. --steps N bounds the local steps.\n"
    "\n"
    "OUT: .obj (v + vt, faces v/vt) or .ply (with u v), also .off (positions only).\n"
    "--png/--svg draw the uv layout coloured by conformal distortion sigma1/sigma2, flipped\n"
    "triangles in magenta; --checker draws the 3D mesh with a checkerboard texture seen along\n"
    "--view (default 0,0,-1). --report writes the metrics as JSON; --json prints them.\n";

static bool parse_view(const char *s, double v[3])
{
    if (!s)
        return false;
    char *end;
    for (int k = 0; k < 3; ++k) {
        v[k] = strtod(s, &end);
        if (end == s)
            return false;
        s = end;
        if (k < 2) {
            if (*s != ',')
                return false;
            ++s;
        }
    }
    return *s == '\0';
}

/* What a run did, for the report. */
typedef struct run_info {
    const char *in, *method, *boundary;
    bool linear, hierarchical;
    sk_param_stats ps;   /* linear methods */
    sk_hparam_stats hs;  /* hierarchical MIPS */
    sk_mips_stats ms;    /* flat MIPS */
    sk_param_metrics pm;
    double seconds;
} run_info;

static void write_json(FILE *fp, const void *ctx)
{
    const run_info *r = ctx;
    const sk_param_metrics *pm = &r->pm;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "file", r->in);
    json_kstr(&j, "method", r->method);
    json_kstr(&j, "boundary", r->boundary);
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
    json_knum(&j, "seconds", r->seconds);
    if (r->linear) {
        const sk_param_stats *ps = &r->ps;
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
        if (ps->levels > 1) {
            json_kuint(&j, "levels", ps->levels);
            json_kuint(&j, "iterations", ps->iterations);
            json_knum(&j, "residual", ps->residual);
        }
        json_obj_close(&j);
    } else if (r->hierarchical) {
        const sk_hparam_stats *hs = &r->hs;
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
        json_kuint(&j, "steps", r->ms.steps);
        json_kuint(&j, "sweeps", r->ms.sweeps);
        json_knum(&j, "energy_start", r->ms.energy_start);
    }
    json_obj_close(&j);
    json_end(&j);
}


int cmd_param(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *png = NULL, *svg = NULL, *checker = NULL, *report = NULL;
    const char *val, *boundary = NULL;
    bool quiet = false, json = false, mips = false, flat = false, hier_flag = false, solver_flag = false;
    unsigned long steps = 0, seed = 1;
    sk_param_opts po = {0};
    sk_write_opts wo = {0};
    sk_render_opts ro = {0};
    po.method = SK_PARAM_FLOATER;
    const cli_path_opt paths[] = {{"-o", &out}, {"--png", &png}, {"--svg", &svg},
                                  {"--checker", &checker}, {"--report", &report}};
    int took;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(help, stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "-q")) {
            quiet = true;
        } else if (!strcmp(a, "--json")) {
            json = true;
        } else if (!strcmp(a, "--ascii")) {
            wo.ascii = true;
        } else if (!strcmp(a, "--flat")) {
            flat = true;
        } else if (!strcmp(a, "--hierarchical")) {
            hier_flag = true;
        } else if ((took = cli_take_path(argc, argv, &i, "param", paths, 5)) != 0) {
            if (took < 0)
                return EXIT_USAGE;
        } else if (cli_opt_value(argc, argv, &i, "--method", &val)) {
            if (val && !strcmp(val, "mips"))
                mips = true;
            else if (!sk_param_method_parse(val, &po.method))
                return cli_usage("param", "--method takes tutte, floater, mvc, harmonic, lscm or "
                                          "mips");
        } else if (cli_opt_value(argc, argv, &i, "--boundary", &val)) {
            if (!val || (strcmp(val, "circle") && strcmp(val, "square") && strcmp(val, "free")))
                return cli_usage("param", "--boundary takes circle, square or free");
            boundary = val;
        } else if (cli_opt_value(argc, argv, &i, "--spacing", &val)) {
            if (val && !strcmp(val, "chord"))
                po.boundary.spacing = SK_SPACING_CHORD;
            else if (val && !strcmp(val, "uniform"))
                po.boundary.spacing = SK_SPACING_UNIFORM;
            else
                return cli_usage("param", "--spacing takes chord or uniform");
        } else if (cli_opt_value(argc, argv, &i, "--solver", &val)) {
            if (val && !strcmp(val, "direct"))
                po.solver = SK_LINEAR_DIRECT;
            else if (val && !strcmp(val, "hierarchical"))
                po.solver = SK_LINEAR_HIERARCHICAL;
            else
                return cli_usage("param", "--solver takes direct or hierarchical");
            solver_flag = true;
        } else if (cli_opt_value(argc, argv, &i, "--steps", &val)) {
            if (!cli_parse_uint(val, &steps) || steps == 0)
                return cli_usage("param", "--steps takes a positive whole number");
        } else if (cli_opt_value(argc, argv, &i, "--seed", &val)) {
            if (!cli_parse_uint(val, &seed))
                return cli_usage("param", "--seed takes a whole number");
        } else if (cli_opt_value(argc, argv, &i, "--view", &val)) {
            if (!parse_view(val, ro.view))
                return cli_usage("param", "--view takes three numbers X,Y,Z");
        } else if (a[0] == '-' && a[1]) {
            return cli_usage("param", "unknown option '%s'", a);
        } else if (!in) {
            in = a;
        } else {
            return cli_usage("param", "more than one input file");
        }
    }
    if (!in || !out)
        return cli_usage("param", "needs an input file and -o OUT");
    if (sk_format_from_path(out) == SK_FORMAT_UNKNOWN)
        return cli_usage("param", "cannot tell the output format of '%s'", out);
    if ((flat || hier_flag || steps) && !mips)
        return cli_usage("param", "--flat, --hierarchical and --steps go with --method mips");
    if (solver_flag && mips)
        return cli_usage("param", "--solver goes with the linear methods");
    if (flat && hier_flag)
        return cli_usage("param", "--flat and --hierarchical exclude each other");
    if (!boundary)
        boundary = mips || po.method == SK_PARAM_LSCM ? "free" : "circle";
    if (!mips && ((po.method == SK_PARAM_LSCM) != !strcmp(boundary, "free")))
        return cli_usage("param", "%s", po.method == SK_PARAM_LSCM
                                            ? "lscm has a free boundary"
                                            : "a free boundary needs --method lscm or mips");
    po.boundary.shape = !strcmp(boundary, "square") ? SK_BOUNDARY_SQUARE : SK_BOUNDARY_CIRCLE;
    sk_mips_boundary mb = !strcmp(boundary, "free")     ? SK_MIPS_BOUNDARY_FREE
                          : !strcmp(boundary, "square") ? SK_MIPS_BOUNDARY_SQUARE
                                                        : SK_MIPS_BOUNDARY_CIRCLE;

    cli_progress bar;
    cli_progress_init(&bar, "param", quiet);
    po.progress = cli_progress_cb;
    po.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    double *uv = NULL;
    run_info r;
    memset(&r, 0, sizeof r);
    r.in = in;
    r.boundary = boundary;
    r.method = mips ? (flat ? "mips-flat" : "mips-hierarchical") : sk_param_method_name(po.method);
    r.linear = !mips;
    r.hierarchical = mips && !flat;
    sk_status st = sk_mesh_read(in, NULL, &mesh, &err);
    if (st == SK_OK) {
        uv = calloc(2 * mesh->num_vertices + 1, sizeof *uv);
        if (!uv)
            st = SK_ERR_NOMEM, snprintf(err.message, sizeof err.message, "out of memory");
    }
    double t0 = sk_seconds(); /* time the method, not the reading */
    if (st == SK_OK && r.linear) {
        st = sk_param_linear(mesh, &po, uv, &r.ps, &err);
    } else if (st == SK_OK && r.hierarchical) {
        sk_hparam_opts ho = {0};
        ho.boundary = mb;
        ho.max_steps = steps;
        ho.seed = seed;
        ho.progress = cli_progress_cb;
        ho.progress_user = &bar;
        st = sk_param_hierarchical(mesh, &ho, uv, &r.hs, &err);
    } else if (st == SK_OK) {
        st = sk_param_mips_flat(mesh, mb, steps, 0.0, seed, uv, &r.ms, &err);
    }
    r.seconds = sk_seconds() - t0;
    cli_progress_done(&bar);
    if (st == SK_OK)
        st = sk_param_metrics_compute(mesh, uv, &r.pm, &err);
    if (st == SK_OK && !(st = sk_mesh_add_uvs(mesh, &err))) {
        memcpy(mesh->uvs, uv, 2 * mesh->num_vertices * sizeof *uv);
        st = sk_mesh_write(out, mesh, &wo, &err);
    }
    char title[256];
    if (st == SK_OK)
        snprintf(title, sizeof title, "%s: %s, %s boundary, MIPS mean %.4f, flipped %zu", in,
                 r.method, boundary, r.pm.mips_mean, r.pm.flipped);
    ro.title = title;
    if (st == SK_OK && png)
        st = sk_render_uv(mesh, uv, &ro, png, &err);
    if (st == SK_OK && svg)
        st = sk_render_uv(mesh, uv, &ro, svg, &err);
    if (st == SK_OK && checker)
        st = sk_render_checker(mesh, uv, &ro, checker, &err);
    int rc = st ? cli_fail(st, &err) : EXIT_OK;
    if (rc == EXIT_OK && report)
        rc = cli_write_file(report, write_json, &r);
    if (rc == EXIT_OK) {
        if (json)
            write_json(stdout, &r);
        else if (!quiet)
            printf("%s: %zu faces, %s, %s boundary, flipped %zu, MIPS sum %.6f (mean %.6f), "
                   "conformal %.4f, area log %.4f, boundary self-intersections %zu, %.3f s\n",
                   in, r.pm.faces, r.method, boundary, r.pm.flipped, r.pm.mips_sum, r.pm.mips_mean,
                   r.pm.conformal_mean, r.pm.area_log_mean, r.pm.boundary_self_intersections,
                   r.seconds);
    }
    free(uv);
    sk_mesh_destroy(&mesh);
    return rc;
}
