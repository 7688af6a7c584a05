/* surfkit param: linear parametrization of a disk, metrics, pictures. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static const char help[] =
    "usage: surfkit param IN -o OUT [--method tutte|floater|mvc|harmonic|lscm]\n"
    "                     [--boundary circle|square] [--spacing chord|uniform]\n"
    "                     [--png LAYOUT.png] [--svg LAYOUT.svg] [--checker VIEW.png]\n"
    "                     [--view X,Y,Z] [--report REPORT.json] [--json] [--ascii] [-q]\n"
    "\n"
    "Maps a triangulated disk (one boundary loop, Euler characteristic 1) to the plane.\n"
    "Fixed boundary (circle by default, or the unit square with corners at quarter arc length;\n"
    "boundary spacing by chord length by default): tutte (uniform weights), floater\n"
    "(shape-preserving, the default), mvc (mean value), harmonic (cotangent weights; obtuse\n"
    "triangles give negative weights that can flip triangles). Free boundary: lscm (least\n"
    "squares conformal, two boundary vertices pinned). Tutte, floater and mvc never flip a\n"
    "triangle with a convex boundary.\n"
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

static void write_json(FILE *fp, const char *in, sk_param_method method, const char *boundary,
                       const sk_param_stats *ps, const sk_param_metrics *pm)
{
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "file", in);
    json_kstr(&j, "method", sk_param_method_name(method));
    json_kstr(&j, "boundary", method == SK_PARAM_LSCM ? "free" : boundary);
    json_kuint(&j, "vertices", ps->vertices);
    json_kuint(&j, "faces", pm->faces);
    json_kuint(&j, "interior", ps->interior);
    json_kuint(&j, "flipped", pm->flipped);
    json_kuint(&j, "degenerate", pm->degenerate);
    json_knum(&j, "mips_sum", pm->mips_sum);
    json_knum(&j, "mips_mean", pm->mips_mean);
    json_knum(&j, "conformal_mean", pm->conformal_mean);
    json_knum(&j, "conformal_max", pm->conformal_max);
    json_knum(&j, "area_log_mean", pm->area_log_mean);
    json_knum(&j, "stretch_max", pm->stretch_max);
    json_kuint(&j, "boundary_self_intersections", pm->boundary_self_intersections);
    json_knum(&j, "seconds", ps->total_seconds);
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
    json_obj_close(&j);
    json_end(&j);
}

int cmd_param(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *png = NULL, *svg = NULL, *checker = NULL, *report = NULL;
    const char *val, *boundary = "circle";
    bool quiet = false, json = false;
    sk_param_opts po = {0};
    sk_write_opts wo = {0};
    sk_render_opts ro = {0};
    po.method = SK_PARAM_FLOATER;
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
        } else if (cli_opt_value(argc, argv, &i, "-o", &val)) {
            if (!val)
                return cli_usage("param", "-o needs a file name");
            out = val;
        } else if (cli_opt_value(argc, argv, &i, "--method", &val)) {
            if (!sk_param_method_parse(val, &po.method))
                return cli_usage("param", "--method takes tutte, floater, mvc, harmonic or lscm");
        } else if (cli_opt_value(argc, argv, &i, "--boundary", &val)) {
            if (val && !strcmp(val, "circle"))
                po.boundary.shape = SK_BOUNDARY_CIRCLE;
            else if (val && !strcmp(val, "square"))
                po.boundary.shape = SK_BOUNDARY_SQUARE;
            else
                return cli_usage("param", "--boundary takes circle or square");
            boundary = val;
        } else if (cli_opt_value(argc, argv, &i, "--spacing", &val)) {
            if (val && !strcmp(val, "chord"))
                po.boundary.spacing = SK_SPACING_CHORD;
            else if (val && !strcmp(val, "uniform"))
                po.boundary.spacing = SK_SPACING_UNIFORM;
            else
                return cli_usage("param", "--spacing takes chord or uniform");
        } else if (cli_opt_value(argc, argv, &i, "--png", &val)) {
            if (!val)
                return cli_usage("param", "--png needs a file name");
            png = val;
        } else if (cli_opt_value(argc, argv, &i, "--svg", &val)) {
            if (!val)
                return cli_usage("param", "--svg needs a file name");
            svg = val;
        } else if (cli_opt_value(argc, argv, &i, "--checker", &val)) {
            if (!val)
                return cli_usage("param", "--checker needs a file name");
            checker = val;
        } else if (cli_opt_value(argc, argv, &i, "--view", &val)) {
            if (!parse_view(val, ro.view))
                return cli_usage("param", "--view takes three numbers X,Y,Z");
        } else if (cli_opt_value(argc, argv, &i, "--report", &val)) {
            if (!val)
                return cli_usage("param", "--report needs a file name");
            report = val;
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
    cli_progress bar;
    cli_progress_init(&bar, "param", quiet);
    po.progress = cli_progress_cb;
    po.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    double *uv = NULL;
    sk_param_stats ps;
    sk_param_metrics pm;
    sk_status st = sk_mesh_read(in, NULL, &mesh, &err);
    if (st == SK_OK) {
        uv = calloc(2 * mesh->num_vertices + 1, sizeof *uv);
        if (!uv)
            st = SK_ERR_NOMEM;
    }
    if (st == SK_OK)
        st = sk_param_linear(mesh, &po, uv, &ps, &err);
    cli_progress_done(&bar);
    if (st == SK_OK)
        st = sk_param_metrics_compute(mesh, uv, &pm, &err);
    if (st == SK_OK && !(st = sk_mesh_add_uvs(mesh, &err))) {
        memcpy(mesh->uvs, uv, 2 * mesh->num_vertices * sizeof *uv);
        st = sk_mesh_write(out, mesh, &wo, &err);
    }
    char title[256];
    if (st == SK_OK)
        snprintf(title, sizeof title, "%s: %s, %s boundary, MIPS mean %.4f, flipped %zu",
                 in, sk_param_method_name(po.method),
                 po.method == SK_PARAM_LSCM ? "free" : boundary, pm.mips_mean, pm.flipped);
    ro.title = title;
    if (st == SK_OK && png)
        st = sk_render_uv(mesh, uv, &ro, png, &err);
    if (st == SK_OK && svg)
        st = sk_render_uv(mesh, uv, &ro, svg, &err);
    if (st == SK_OK && checker)
        st = sk_render_checker(mesh, uv, &ro, checker, &err);
    if (st == SK_OK && report) {
        size_t n = strlen(report);
        char *tmp = malloc(n + 8);
        FILE *fp = tmp ? (snprintf(tmp, n + 8, "%s.tmp", report), fopen(tmp, "w")) : NULL;
        if (!fp) {
            cli_error("%s: cannot write the report", report);
            free(tmp);
            free(uv);
            sk_mesh_destroy(&mesh);
            return EXIT_BAD_INPUT;
        }
        write_json(fp, in, po.method, boundary, &ps, &pm);
        bool ok = !ferror(fp);
        ok = (fclose(fp) == 0) && ok && rename(tmp, report) == 0;
        if (!ok) {
            remove(tmp);
            cli_error("%s: cannot write the report", report);
        }
        free(tmp);
        if (!ok) {
            free(uv);
            sk_mesh_destroy(&mesh);
            return EXIT_BAD_INPUT;
        }
    }
    if (st == SK_OK) {
        if (json)
            write_json(stdout, in, po.method, boundary, &ps, &pm);
        else if (!quiet)
            printf("%s: %zu faces, %s, flipped %zu, MIPS sum %.6g (mean %.6f), conformal %.4f, "
                   "area log %.4f, boundary self-intersections %zu, %.3f s\n",
                   in, pm.faces, sk_param_method_name(po.method), pm.flipped, pm.mips_sum,
                   pm.mips_mean, pm.conformal_mean, pm.area_log_mean,
                   pm.boundary_self_intersections, ps.total_seconds);
    }
    free(uv);
    sk_mesh_destroy(&mesh);
    if (st == SK_ERR_NOMEM && err.message[0] == '\0')
        snprintf(err.message, sizeof err.message, "out of memory");
    return st ? cli_fail(st, &err) : EXIT_OK;
}
