/* surfkit param: parametrization of a disk (linear methods, or hierarchical / flat MIPS), metrics,
 * pictures. */
#include "cmd_param.h"

#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Quads and larger polygons are triangulated on the way in (--keep-polygons refuses them).\n"
    "Maps a triangulated disk (one boundary loop, Euler characteristic 1) to the plane.\n"
    "Fixed boundary (circle by default, or the unit square with corners at the four sharpest\n"
    "boundary turns, where an interior edge with both ends on one side is split at its midpoint,\n"
    "adding an interior vertex to the output, so that no triangle lies on one side; boundary\n"
    "spacing by chord length by default): tutte (uniform weights), floater\n"
    "(shape-preserving, the default), mvc (mean value), harmonic (cotangent weights; obtuse\n"
    "triangles give negative weights that can flip triangles). Free boundary: lscm (least\n"
    "squares conformal, two boundary vertices pinned). Tutte, floater and mvc never flip a\n"
    "triangle with a convex boundary. --solver direct (sparse Cholesky / LU) or hierarchical\n"
    "(multilevel CG / BiCGStab over the progressive mesh, the coarsest level solved directly;\n"
    "the same uv to 1e-8 of the layout, not faster today: docs/linear.md) or amg (the same\n"
    "Krylov methods over an algebraic multigrid of the matrix graph: no progressive mesh to\n"
    "build) or auto (the default: amg from --amg-from free vertices up, direct below and for\n"
    "lscm; an amg solve that does not converge is redone directly). --json says which ran\n"
    "(solver.route), its iterations and its relative residual.\n"
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
    "2 usage error, 3 internal failure.\n";

static const char examples[] =
    "  surfkit param data/nefertiti.off -o uv.obj --png layout.png\n"
    "  surfkit param data/nefertiti.off -o uv.ply --method mips --report "
    "metrics.json\n"
    "  surfkit param data/nefertiti.off -o uv.obj --method mips --flat "
    "--steps 100000\n"
    "  surfkit param data/sphere.off -o atlas.obj --png atlas.png\n";

/* What a run did, for the report. */
typedef struct run_info {
    const char *in;
    sk_triangulate_stats tri;
    sk_parametrize_stats ps;
    sk_param_metrics pm;
    double read_seconds, metrics_seconds, write_seconds; /* the process's own stages */
} run_info;

static void write_json(FILE *fp, const void *ctx)
{
    const run_info *r = ctx;
    const sk_param_metrics *pm = &r->pm;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", r->in);
    json_triangulated(&j, &r->tri);
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
        json_key(&j, "stage_seconds");
        json_obj_open(&j);
        json_knum(&j, "read", r->read_seconds);
        json_knum(&j, "check", ps->check_seconds);
        json_knum(&j, "boundary", ps->boundary_seconds);
        json_knum(&j, "weights_and_assembly", ps->weights_seconds);
        json_knum(&j, "analyse", ps->solve.analyse_seconds);
        json_knum(&j, "factor", ps->solve.factor_seconds);
        json_knum(&j, "solve", ps->solve.solve_seconds);
        json_knum(&j, "metrics", r->metrics_seconds);
        json_knum(&j, "write", r->write_seconds);
        json_obj_close(&j);
        json_key(&j, "solver");
        json_obj_open(&j);
        json_kstr(&j, "route", sk_linear_solver_name(ps->solver));
        json_kstr(&j, "kind", ps->solve.kind == SK_SOLVER_CHOLESKY ? "cholmod" : "umfpack");
        json_kuint(&j, "n", ps->solve.n);
        json_kuint(&j, "nnz", ps->solve.nnz);
        json_kuint(&j, "factor_nnz", ps->solve.factor_nnz);
        json_kuint(&j, "levels", ps->levels);
        json_kuint(&j, "iterations", ps->iterations);
        json_knum(&j, "residual", ps->residual);
        json_obj_close(&j);
    } else if (r->ps.hierarchical) {
        const sk_hparam_stats *hs = &r->ps.hparam;
        json_kuint(&j, "steps", hs->steps);
        json_kuint(&j, "repaired_insertions", hs->repaired);
        json_kuint(&j, "fallbacks", hs->fallbacks);
        json_knum(&j, "gap_bound", hs->gap_bound); /* above any converged energy, at most */
        json_kuint(&j, "gap_stopped_levels", hs->gap_stopped_levels);
        json_knum(&j, "hierarchy_seconds", hs->hierarchy_seconds);
        json_key(&j, "stage_seconds"); /* the whole process (the levels' own below) */
        json_obj_open(&j);
        json_knum(&j, "read", r->read_seconds);
        json_knum(&j, "check_and_hierarchy", hs->hierarchy_seconds);
        json_knum(&j, "levels", hs->total_seconds - hs->hierarchy_seconds);
        json_knum(&j, "metrics", r->metrics_seconds);
        json_knum(&j, "write", r->write_seconds);
        json_obj_close(&j);
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

static const char atlas_about[] =
    "\n"
    "Atlas (any manifold triangle mesh: closed, with holes or handles, several components; used\n"
    "when the input is not one disk, or with --atlas or any of --max-distortion, --max-stretch,\n"
    "--resolution, --padding, --split-seams; --method mips only):\n"
    "  charts that are topological disks (components; holes and handles cut along where a grown\n"
    "  disk meets itself; closed pieces and charts above the distortion bounds bisected), each\n"
    "  laid out by LSCM when that is flip-free and within the bounds, else by hierarchical\n"
    "  MIPS with a free boundary (--mips-charts: MIPS always), checked for flips and overlaps\n"
    "  (a chart that overlaps itself is split), packed into [0,1]^2 with one scale.\n"
    "  --png/--svg draw the atlas coloured by conformal distortion, chart borders in black;\n"
    "  --checker the checkerboard on the 3D mesh; --report adds charts, seams, overlaps,\n"
    "  utilization and seconds per stage.\n";

static const sk_param_method methods[] = {SK_PARAM_TUTTE,    SK_PARAM_FLOATER, SK_PARAM_MEAN_VALUE,
                                          SK_PARAM_HARMONIC, SK_PARAM_LSCM,    SK_PARAM_MIPS};
static const sk_linear_solver solvers[] = {SK_LINEAR_AUTO, SK_LINEAR_DIRECT,
                                          SK_LINEAR_HIERARCHICAL, SK_LINEAR_AMG};
static const sk_boundary_shape boundaries[] = {SK_BOUNDARY_CIRCLE, SK_BOUNDARY_SQUARE,
                                               SK_BOUNDARY_FREE};

/* The option table of param; the choices land in the indices, mapped by the caller. */
static int parse_table(int argc, char **argv, param_args *a, unsigned *method, unsigned *boundary,
                       unsigned *solver, cli_args *args)
{
    bool hierarchical = false;
    const cli_opt opts[] = {
        OPT_OUTPUT(a->out, "OUT", ".obj (v + vt) or .ply (s t)"),
        OPT_CHOICE("--method", *method, "tutte|floater|mvc|harmonic|lscm|mips",
                   "the parametrization (default floater; mips for the atlas)"),
        OPT_CHOICE("--boundary", *boundary, "circle|square|free",
                   "fixed on the circle (default) or the unit square, or free"),
        OPT_CHOICE("--spacing", a->po.boundary.spacing, "chord|uniform",
                   "fixed boundary vertices by chord length (default) or equal steps"),
        OPT_CHOICE("--solver", *solver, "auto|direct|hierarchical|amg",
                   "linear methods: amg from the method's crossover size up, direct below\n"
                   "(default), sparse Cholesky / LU, multilevel over the progressive mesh,\n"
                   "or algebraic multigrid"),
        OPT_INT("--amg-from", a->linear.auto_vertices, 1, 0, "N",
                "--solver auto: amg from N free vertices up (default: per method,\n"
                "docs/linear.md; lscm: never)"),
        OPT_FLAG("--hierarchical", hierarchical, "mips: over the progressive mesh (default)"),
        OPT_FLAG("--flat", a->po.flat, "mips: the conventional method on the full mesh"),
        OPT_INT("--steps", a->po.max_steps, 1, 0, "N", "mips: budget of local steps"),
        OPT_INT("--seed", a->po.seed, 0, 0, "S", "mips and atlas: random order (default 1)"),
        OPT_FILE("--png", a->png, "LAYOUT.png", "uv layout coloured by conformal distortion"),
        OPT_FILE("--svg", a->svg, "LAYOUT.svg", "the same as SVG"),
        OPT_FILE("--checker", a->checker, "VIEW.png", "the 3D mesh with a checkerboard texture"),
        OPT_VEC3("--view", a->ro.view, "viewing direction of --checker (default 0,0,-1)"),
        OPT_FILE("--report", a->report, "REPORT.json", "the metrics as JSON"),
        OPT_FLAG("--json", a->json, "print the metrics as JSON instead of the summary"),
        OPT_FLAG("--keep-polygons", a->keep_polygons, "refuse quads and polygons (default: split)"),
        OPT_FLAG("--ascii", a->wo.ascii, "PLY as text (default binary)"),
        OPT_FLAG("--no-normalize", a->po.raw, "keep each method's own uv scale"),
        OPT_FLAG("--atlas", a->atlas, "an atlas even for a disk"),
        OPT_DOUBLE("--max-distortion", a->ao.max_distortion, 1, 0, CLI_LO_OPEN, "D",
                   "atlas: per chart, area-weighted mean sigma1/sigma2 (default 1.05)"),
        OPT_DOUBLE("--max-stretch", a->ao.max_stretch, 1, 0, CLI_LO_OPEN, "S",
                   "atlas: per chart, exp of the area-weighted mean |log area scale / chart's\n"
                   "mean| (default 1.15)"),
        OPT_DOUBLE("--area-theta", a->ao.area_theta, -1, 8, 0, "T",
                   "atlas: each chart refined by MIPS times (area scale + 1/area scale)^T\n"
                   "(default 0.5; negative: off)"),
        OPT_DOUBLE("--area-bound", a->ao.area_bound, -1, 0, 0, "S",
                   "atlas: a chart within stretch S (as --max-stretch) at --area-theta takes\n"
                   "the least area term (plain MIPS, 1/8, 1/4) that stays within S: lower\n"
                   "angle distortion (default 1.08; 1 or less: off)"),
        OPT_DOUBLE("--slit-price", a->ao.slit_price, -1, 1, 0, "P",
                   "atlas: slits into the charts where the MIPS mean they save is at least P\n"
                   "per unit of seam length / sqrt(area) they add (default 0.001; 0 or\n"
                   "negative: none)"),
        OPT_DOUBLE("--crease-angle", a->ao.crease_angle, -1, 180, 0, "DEG",
                   "atlas: charts follow edges with a dihedral angle >= DEG (default 60;\n"
                   "negative: off), regions under 2% of the area aside"),
        OPT_INT("--resolution", a->ao.resolution, 16, 1u << 20, "R",
                "atlas: texels across, for --padding (default 1024)"),
        OPT_DOUBLE("--padding", a->ao.padding, 0, 64, 0, "P",
                   "atlas: gutter of P texels between charts (default 2)"),
        OPT_INT("--charts", a->ao.max_charts, 1, 0, "N",
                "atlas: at most N charts where the bounds allow (neighbours merged)"),
        OPT_INT("--merge-faces", a->ao.merge_faces, 1, 0, "N",
                "atlas: neighbouring charts of at most N triangles together merged\n"
                "while the bounds hold (default 4000)"),
        OPT_FLAG("--no-merge", a->ao.no_merge, "atlas: no merging of neighbouring charts"),
        OPT_FLAG("--no-pack-cuts", a->ao.no_pack_cuts,
                 "atlas: never cut one of 2..8 charts in two for a tighter packing"),
        OPT_FLAG("--mips-charts", a->ao.mips_only,
                 "atlas: hierarchical MIPS on every chart (default: a chart keeps its\n"
                 "LSCM layout when that is flip-free, overlap-free and within the bounds)"),
        OPT_FLAG("--split-seams", a->split_seams,
                 "atlas: one vertex per uv (per-vertex s t: what Blender's PLY reader\n"
                 "takes); default: per-corner uvs (OBJ f v/vt with vt shared inside a\n"
                 "chart; PLY face list texcoord, MeshLab's convention)"),
        OPT_FLAG("-q", a->quiet, "no progress bar, no summary"),
    };
    const cli_spec spec = {"param", "IN -o OUT", about,
                           opts, CLI_COUNT(opts), 1, 1, examples, atlas_about};
    return cli_parse(&spec, argc, argv, args);
}

/* argv -> options; EXIT_OK to run, CLI_HELP, or the usage error's exit code. */
static int parse_args(int argc, char **argv, param_args *a)
{
    unsigned method = 0, boundary = 0, solver = 0;
    cli_args args;
    int rc = parse_table(argc, argv, a, &method, &boundary, &solver, &args);
    if (rc)
        return rc;
    bool given_method = cli_given(&args, "--method");
    if (given_method)
        a->po.method = methods[method];
    if (cli_given(&args, "--boundary"))
        a->po.boundary.shape = boundaries[boundary];
    a->linear.solver = solvers[solver]; /* auto unless given */
    if (a->po.method != SK_PARAM_MIPS || cli_given(&args, "--solver") ||
        cli_given(&args, "--amg-from"))
        a->po.linear = &a->linear; /* with mips: refused below */
    if (cli_given(&args, "--padding") && !(a->ao.padding > 0))
        a->ao.padding = -1; /* 0 means the default in sk_atlas_opts */
    if (cli_given(&args, "--slit-price") && !(a->ao.slit_price > 0))
        a->ao.slit_price = -1; /* none; 0 means the default in sk_atlas_opts */
    if (cli_given(&args, "--area-bound") && !(a->ao.area_bound > 1))
        a->ao.area_bound = -1; /* off; 0 means the default in sk_atlas_opts */
    a->ao.seed = a->po.seed; /* 0 (not given) and 1 are the same */
    a->in = cli_input(&args, 0);
    sk_format ofmt = sk_format_from_path(a->out);
    if (ofmt == SK_FORMAT_UNKNOWN)
        return cli_usage("param", "cannot tell the output format of '%s'", a->out);
    if (ofmt != SK_FORMAT_OBJ && ofmt != SK_FORMAT_PLY)
        return cli_usage("param", "%s cannot hold texture coordinates ('%s'): write .obj or .ply",
                         sk_format_name(ofmt), a->out);
    /* the atlas: asked for by its options, else taken when the input is not one disk */
    static const char *const atlas_only[] = {"--max-distortion", "--max-stretch", "--area-theta",
                                             "--area-bound", "--slit-price",
                                             "--crease-angle", "--resolution", "--padding",
                                             "--split-seams",
                                             "--mips-charts", "--charts", "--merge-faces",
                                             "--no-merge", "--no-pack-cuts"};
    for (size_t k = 0; k < sizeof atlas_only / sizeof atlas_only[0]; ++k)
        a->atlas |= cli_given(&args, atlas_only[k]);
    static const char *const disk_only[] = {"--flat", "--hierarchical", "--boundary",
                                            "--spacing", "--steps", "--solver", "--amg-from"};
    bool disk = given_method && a->po.method != SK_PARAM_MIPS;
    for (size_t k = 0; k < sizeof disk_only / sizeof disk_only[0]; ++k)
        disk |= cli_given(&args, disk_only[k]);
    if (a->atlas && disk)
        return cli_usage("param", "the atlas uses hierarchical MIPS with free boundaries: drop "
                                  "--method, --boundary, --spacing, --steps, --solver, --flat");
    a->atlas_possible = !disk;
    if (a->atlas)
        return EXIT_OK;
    bool hier = cli_given(&args, "--hierarchical");
    if (a->po.flat && hier)
        return cli_usage("param", "--flat and --hierarchical exclude each other");
    if (hier && a->po.method != SK_PARAM_MIPS)
        return cli_usage("param", "--hierarchical goes with --method mips");
    sk_error err;
    if (sk_parametrize_check(&a->po, &err))
        return cli_usage("param", "%s", err.message);
    return EXIT_OK;
}

sk_status param_pictures(const param_args *a, const sk_mesh *mesh, const double *uv,
                         const char *title, unsigned checks, sk_error *err)
{
    sk_render_opts ro = a->ro;
    ro.title = title;
    sk_status st = SK_OK;
    if (st == SK_OK && a->png)
        st = sk_render_uv(mesh, uv, a->png, &ro, err);
    if (st == SK_OK && a->svg)
        st = sk_render_uv(mesh, uv, a->svg, &ro, err);
    if (checks)
        ro.checks = checks;
    if (st == SK_OK && a->checker)
        st = sk_render_checker(mesh, uv, a->checker, &ro, err);
    return st;
}

int param_finish(const param_args *a, sk_status st, const sk_error *err,
                 void (*json)(FILE *, const void *), void (*summary)(const void *),
                 const void *ctx)
{
    int rc = st ? cli_fail(st, err) : EXIT_OK;
    if (rc == EXIT_OK && a->report)
        rc = cli_write_file(a->report, json, ctx);
    if (rc == EXIT_OK) {
        if (a->json)
            json(stdout, ctx);
        else if (!a->quiet)
            summary(ctx);
    }
    return rc;
}

static void print_summary(const void *ctx)
{
    const run_info *r = ctx;
    printf("%s: %zu faces, %s, %s boundary, flipped %zu, MIPS sum %.6f (mean %.6f), "
           "conformal %.4f, area log %.4f, boundary self-intersections %zu, %.3f s\n",
           r->in, r->pm.faces, r->ps.name, sk_boundary_shape_name(r->ps.boundary), r->pm.flipped,
           r->pm.mips_sum, r->pm.mips_mean, r->pm.conformal_mean, r->pm.area_log_mean,
           r->pm.boundary_self_intersections, r->ps.seconds);
}

/* The disk path: one sk_parametrize call, metrics, output, pictures. */
static int run_disk(param_args *a, sk_mesh *input, double read_seconds)
{
    cli_progress bar;
    cli_progress_init(&bar, "param", a->quiet);
    a->po.progress = cli_progress_cb;
    a->po.progress_user = &bar;
    sk_error err = {0};
    run_info r;
    memset(&r, 0, sizeof r);
    r.in = a->in;
    r.tri = a->tri;
    r.read_seconds = read_seconds;
    double *uv = calloc(2 * input->num_vertices + 1, sizeof *uv);
    sk_status st = uv ? sk_parametrize(input, &a->po, uv, &r.ps, &err) : SK_ERR_NOMEM;
    if (!uv)
        snprintf(err.message, sizeof err.message, "out of memory");
    cli_progress_done(&bar);
    /* a square boundary splits the dividing edges: the output is the split mesh */
    sk_mesh *mesh = r.ps.split_mesh ? r.ps.split_mesh : input;
    if (r.ps.split_edges && !a->quiet)
        fprintf(stderr, "surfkit param: %s: split %zu interior edges with both ends on one side "
                "of the square (%zu vertices added)\n", a->in, r.ps.split_edges, r.ps.split_edges);
    cli_name_input(a->in, st, &err);
    if (st == SK_WARN_FLIPS) { /* the result is complete: write it and say so */
        fprintf(stderr, "surfkit param: warning: %s: %s\n", a->in, err.message);
        st = SK_OK;
    }
    if (st == SK_OK && !r.ps.split_mesh && !(st = sk_mesh_add_uvs(mesh, &err)))
        memcpy(mesh->uvs, uv, 2 * mesh->num_vertices * sizeof *uv);
    double t0 = sk_seconds();
    if (st == SK_OK)
        st = sk_param_metrics_compute(mesh, mesh->uvs, &r.pm, &err);
    double t1 = sk_seconds();
    if (st == SK_OK)
        st = sk_mesh_write(a->out, mesh, &a->wo, &err);
    r.metrics_seconds = t1 - t0;
    r.write_seconds = sk_seconds() - t1;
    char title[256];
    if (st == SK_OK) {
        snprintf(title, sizeof title, "%s: %s, %s boundary, MIPS mean %.4f, flipped %zu", a->in,
                 r.ps.name, sk_boundary_shape_name(r.ps.boundary), r.pm.mips_mean, r.pm.flipped);
        st = param_pictures(a, mesh, mesh->uvs, title, 0, &err);
    }
    int rc = param_finish(a, st, &err, write_json, print_summary, &r);
    sk_parametrize_stats_release(&r.ps);
    free(uv);
    return rc;
}

int cmd_param(int argc, char **argv)
{
    param_args a;
    memset(&a, 0, sizeof a);
    int rc = parse_args(argc, argv, &a);
    if (rc)
        return rc == CLI_HELP ? EXIT_OK : rc;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    double t0 = sk_seconds();
    sk_status st = cli_read_triangles(a.in, a.keep_polygons, &mesh, &a.tri, &err);
    if (st)
        return cli_fail(st, &err);
    double t_read = sk_seconds() - t0;
    if (!a.quiet && !a.json)
        cli_print_triangulated(a.in, &a.tri);
    /* not one disk (and no option only the disk methods have): the atlas */
    if (!a.atlas && a.atlas_possible) {
        sk_error derr;
        a.atlas = sk_param_check_disk(mesh, &derr) != SK_OK;
    }
    rc = a.atlas ? param_run_atlas(&a, mesh, t_read) : run_disk(&a, mesh, t_read);
    sk_mesh_destroy(&mesh);
    return rc;
}
