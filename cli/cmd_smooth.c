/* surfkit smooth: VC1 surface (Cottin & van Damme) or PN triangles, tessellated, with a continuity
 * report. */
#include "cli.h"

#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char help[] =
    "usage: surfkit smooth IN -o OUT.obj|OUT.ply|OUT.igs|OUT.step [--tess N] [--patches OUT.json]\n"
    "                      [--layout layout.png] [--render shaded.png] [--report report.json]\n"
    "                      [--json] [--normals angle|area|mean|quadric] [--estimate-normals]\n"
    "                      [--scheme vc1|pn] [--allow-split] [--obj-freeform] [--units U]\n"
    "                      [--iges-triangles split|degenerate] [--allow-fail] [-q]\n"
    "\n"
    "Builds a smooth surface that interpolates every vertex and normal of the triangle mesh IN.\n"
    "vc1 (default): Cottin & van Damme's construction: edge deletion makes a mesh of triangles\n"
    "and quads in which every interior vertex is odd, then quartic triangles and bicubic quads\n"
    "join with tangent-plane continuity across every edge, without splitting faces.\n"
    "pn: PN triangles (Vlachos et al. 2001), cubic and only C0 across edges: a baseline.\n"
    "\n"
    "Normals: the file's normals (OBJ vn, PLY nx ny nz) if present, else estimated with\n"
    "--normals (default angle); --estimate-normals ignores the file's normals.\n"
    "A closed mesh with an odd number of vertices has no edge deletion (every vertex odd is\n"
    "impossible by Euler's formula): it is refused unless --allow-split, which splits its\n"
    "longest edge at the midpoint of its wire frame curve.\n"
    "\n"
    "  -o OUT          by extension: .obj/.ply the tessellated surface with exact patch normals;\n"
    "                  .igs/.iges IGES 5.3 B-rep: B-spline faces (entity 128) sharing edges\n"
    "                  and vertices, a solid (186) when the surface is closed, else a shell;\n"
    "                  .step/.stp STEP AP214, faces sharing edges and vertices, a solid\n"
    "                  (MANIFOLD_SOLID_BREP) when the surface is closed, else a shell;\n"
    "                  .obj with --obj-freeform: OBJ free-form surfaces, each patch as a\n"
    "                  B-spline with clamped knots (cstype bspline).\n"
    "                  CAD formats write each quartic triangle as one biquartic face with a side\n"
    "                  collapsed to a corner (exact); --iges-triangles split writes three regular\n"
    "                  biquartic faces instead (STEP and IGES, 3x the size), degenerate writes\n"
    "                  the one-patch surfaces as loose IGES faces in one group\n"
    "  --units U       CAD length unit of the coordinates: mm (default), cm, m, um, in, ft\n"
    "  --tess N        grid of N x N per patch (default 4)\n"
    "  --patches F     control nets as JSON\n"
    "  --layout F      picture of the triangle/quad configuration, deleted edges in red,\n"
    "                  problem vertices in orange\n"
    "  --render F      flat-shaded picture of the tessellated surface\n"
    "  --report F      continuity report as JSON (--json prints it on stdout): gaps and normal\n"
    "                  jumps across patch boundaries, vertex and normal errors, singular patches\n"
    "                  (the normal vanishes or turns over somewhere: a cusp or a fold), uncertified\n"
    "                  patches (the normal-cone test cannot prove them regular; most are),\n"
    "                  self-intersecting patch pairs (patches sharing no corner that cross each\n"
    "                  other: what CAD checkers flag), pass/fail against 0.5 deg and 0.005\n"
    "  --allow-fail    write the surface even when the vc1 continuity report fails\n"
    "\n"
    "Exit status 4: the vc1 surface fails its own continuity report (a normal jump over\n"
    "0.5 degrees, a gap over 0.005, or a singular patch); the report (--report, --json) is\n"
    "still written, the surface files are not, unless --allow-fail (then the exit status is\n"
    "0). pn is C0 by construction: its report is information only.\n";


static void write_report(FILE *fp, const char *in, const sk_smooth *s, const sk_continuity_report *r,
                         const char *normals_src, double seconds, double report_seconds)
{
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", in);
    json_kstr(&j, "scheme", s->scheme == SK_SMOOTH_PN ? "pn" : "vc1");
    json_kstr(&j, "normals", normals_src);
    size_t tri = 0, quad = 0;
    for (size_t p = 0; p < s->surface.count; ++p)
        s->surface.patches[p].kind == SK_PATCH_TENSOR ? ++quad : ++tri;
    json_kuint(&j, "vertices", s->config->num_vertices);
    json_kuint(&j, "triangles", tri);
    json_kuint(&j, "quads", quad);
    json_kuint(&j, "even_vertices", s->stats.deletion.even_vertices);
    json_kuint(&j, "deleted_edges", s->stats.deletion.deleted_edges);
    json_kuint(&j, "deleted_edges_lower_bound", s->stats.deletion.lower_bound);
    json_kuint(&j, "split_edges", s->stats.split_edges);
    json_knum(&j, "max_gap", r->max_gap);
    json_knum(&j, "mean_gap", r->mean_gap);
    json_knum(&j, "max_normal_jump_deg", r->max_normal_jump_deg);
    json_knum(&j, "mean_normal_jump_deg", r->mean_normal_jump_deg);
    json_key(&j, "worst_edge");
    json_arr_open(&j);
    json_uint(&j, r->worst_edge_vertices[0]);
    json_uint(&j, r->worst_edge_vertices[1]);
    json_arr_close(&j);
    json_knum(&j, "max_vertex_error", r->max_vertex_error);
    json_knum(&j, "max_normal_error_deg", r->max_normal_error_deg);
    json_kuint(&j, "singular_patches", r->singular_patches);
    json_kuint(&j, "uncertified_patches", r->uncertified_patches);
    json_key(&j, "singular_patch_examples");
    json_arr_open(&j);
    for (size_t i = 0; i < r->num_singular_examples; ++i)
        json_uint(&j, r->singular_examples[i]);
    json_arr_close(&j);
    if (r->intersecting_pairs != SIZE_MAX) {
        json_kuint(&j, "self_intersecting_pairs", r->intersecting_pairs);
        json_kuint(&j, "self_intersecting_patches", r->intersecting_patches);
        json_key(&j, "self_intersection_examples");
        json_arr_open(&j);
        for (size_t i = 0; i < r->num_intersection_examples; ++i) {
            json_arr_open(&j);
            json_uint(&j, r->intersection_examples[2 * i]);
            json_uint(&j, r->intersection_examples[2 * i + 1]);
            json_arr_close(&j);
        }
        json_arr_close(&j);
    }
    json_kuint(&j, "relaxed_vertices", s->stats.relaxed_vertices);
    json_kuint(&j, "angle_violations", s->stats.angle_violations);
    json_kuint(&j, "singular_before_repair", s->stats.singular_before_repair);
    json_kuint(&j, "repaired_vertices", s->stats.repaired_vertices);
    json_kuint(&j, "failed_vertices", s->stats.failed_vertices);
    json_key(&j, "problem_vertices");
    json_arr_open(&j);
    for (size_t i = 0; i < s->num_problems && i < 100; ++i)
        json_uint(&j, s->problems[i]);
    json_arr_close(&j);
    json_kuint(&j, "max_iterations", s->stats.max_iterations);
    json_knum(&j, "max_constraint_residual", s->stats.max_residual);
    json_knum(&j, "mean_target_deviation", s->stats.mean_target_deviation);
    json_kbool(&j, "pass_g1", r->pass_g1); /* normal jumps within max_angle_deg (0.5) */
    json_kbool(&j, "pass_gap", r->pass_gap);   /* gaps within max_gap (0.005) */
    json_kbool(&j, "pass_intersections", r->pass_intersections);
    json_key(&j, "stage_seconds");
    json_obj_open(&j);
    json_knum(&j, "normals", s->stats.seconds_normals);
    json_knum(&j, "edge_deletion", s->stats.seconds_deletion);
    json_knum(&j, "vertex_systems", s->stats.seconds_systems);
    json_knum(&j, "patches", s->stats.seconds_patches);
    json_knum(&j, "report", report_seconds);
    json_obj_close(&j);
    json_knum(&j, "seconds", seconds);
    json_obj_close(&j);
    json_end(&j);
}


static void patches_json(FILE *fp, const void *ctx)
{
    const sk_smooth *s = ctx;
    fprintf(fp, "{\"scheme\": \"%s\", \"layout\": \"triangles: b_ijk by rows k = 0..n, j = "
                "0..n-k; quads: b[i + 4 j]\", \"patches\": [\n",
            s->scheme == SK_SMOOTH_PN ? "pn" : "vc1");
    const sk_patch_set *set = &s->surface;
    for (size_t p = 0; p < set->count; ++p) {
        const sk_patch *pa = &set->patches[p];
        bool quad = pa->kind == SK_PATCH_TENSOR;
        fprintf(fp, "{\"kind\": \"%s\", \"degree\": %d, \"corners\": [%u, %u, %u",
                quad ? "quad" : "triangle", pa->degree, pa->corner_ids[0], pa->corner_ids[1],
                pa->corner_ids[2]);
        if (quad)
            fprintf(fp, ", %u", pa->corner_ids[3]);
        fprintf(fp, "], \"points\": [");
        const double *cp = sk_patch_cp(set, p);
        for (size_t i = 0; i < sk_patch_num_points(pa); ++i) {
            const double *x = cp + 3 * i;
            fprintf(fp, "%s[%.17g, %.17g, %.17g]", i ? ", " : "", x[0], x[1], x[2]);
        }
        fprintf(fp, "]}%s\n", p + 1 < set->count ? "," : "");
    }
    fprintf(fp, "]}\n");
}

typedef struct report_ctx {
    const char *in;
    const sk_smooth *s;
    const sk_continuity_report *r;
    const char *normals_src;
    double seconds, report_seconds;
} report_ctx;

static void report_json(FILE *fp, const void *ctx)
{
    const report_ctx *c = ctx;
    write_report(fp, c->in, c->s, c->r, c->normals_src, c->seconds, c->report_seconds);
}

typedef enum { CAD_NONE, CAD_IGES, CAD_STEP, CAD_OBJ_FREEFORM } cad_kind;

static cad_kind cad_kind_of(const char *path, bool freeform)
{
    if (sk_path_has_ext(path, ".igs") || sk_path_has_ext(path, ".iges"))
        return CAD_IGES;
    if (sk_path_has_ext(path, ".step") || sk_path_has_ext(path, ".stp"))
        return CAD_STEP;
    if (freeform && sk_path_has_ext(path, ".obj"))
        return CAD_OBJ_FREEFORM;
    return CAD_NONE;
}

static int write_cad(const char *path, cad_kind cad, const sk_smooth *s, sk_export_opts *eo,
                     bool quiet)
{
    sk_error err = {0};
    sk_export_stats es = {0};
    sk_status st;
    cli_progress bar; /* drawn on stderr while writing when it is a terminal */
    cli_progress_init(&bar, "write", quiet);
    eo->progress = cli_progress_cb;
    eo->progress_user = &bar;
    if (cad == CAD_IGES)
        st = sk_export_iges(path, &s->surface, eo, &es, &err);
    else if (cad == CAD_STEP)
        st = sk_export_step(path, &s->surface, eo, &es, &err);
    else
        st = sk_export_obj_freeform(path, &s->surface, eo, &es, &err);
    cli_progress_done(&bar);
    if (st != SK_OK)
        return cli_fail(st, &err);
    if (!quiet) {
        printf("smooth: wrote %s: %zu surfaces", path, es.faces);
        if (es.edges)
            printf(", %zu edges, %zu vertices", es.edges, es.vertices);
        printf(", %.1f KiB\n", (double)es.bytes / 1024.0);
    }
    return EXIT_OK;
}

int cmd_smooth(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *patches = NULL, *layout = NULL, *render = NULL,
               *report = NULL, *val;
    unsigned long tess = 4;
    bool quiet = false, json = false, freeform = false, allow_fail = false;
    sk_smooth_opts so = {0};
    sk_export_opts eo = {0};
    const cli_path_opt paths[] = {{"-o", &out}, {"--patches", &patches}, {"--layout", &layout},
                                  {"--render", &render}, {"--report", &report}};
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
        } else if (!strcmp(a, "--allow-fail")) {
            allow_fail = true;
        } else if (!strcmp(a, "--allow-split")) {
            so.allow_split = true;
        } else if (!strcmp(a, "--estimate-normals")) {
            so.estimate_normals = true;
        } else if (!strcmp(a, "--obj-freeform")) {
            freeform = true;
        } else if ((took = cli_take_path(argc, argv, &i, "smooth", paths, 5)) != 0) {
            if (took < 0)
                return EXIT_USAGE;
        } else if (cli_opt_value(argc, argv, &i, "--units", &val)) {
            if (!val || !sk_export_units_known(val))
                return cli_usage("smooth", "--units takes mm, cm, m, um, in or ft");
            eo.units = val;
        } else if (cli_opt_value(argc, argv, &i, "--iges-triangles", &val)) {
            if (val && !strcmp(val, "split"))
                eo.split_triangles = true;
            else if (val && !strcmp(val, "degenerate"))
                eo.degenerate_triangles = true;
            else
                return cli_usage("smooth", "--iges-triangles takes split or degenerate");
        } else if (cli_opt_value(argc, argv, &i, "--tess", &val)) {
            if (!cli_parse_uint(val, &tess) || tess < 1 || tess > 64)
                return cli_usage("smooth", "--tess takes a whole number from 1 to 64");
        } else if (cli_opt_value(argc, argv, &i, "--normals", &val)) {
            int mth = sk_normal_method_from_name(val);
            if (mth < 0)
                return cli_usage("smooth", "--normals takes angle, area, mean or quadric");
            so.normals = (sk_normal_method)mth;
        } else if (cli_opt_value(argc, argv, &i, "--scheme", &val)) {
            if (val && !strcmp(val, "vc1"))
                so.scheme = SK_SMOOTH_VC1;
            else if (val && !strcmp(val, "pn"))
                so.scheme = SK_SMOOTH_PN;
            else
                return cli_usage("smooth", "--scheme takes vc1 or pn");
        } else if (a[0] == '-' && a[1]) {
            return cli_usage("smooth", "unknown option '%s'", a);
        } else if (!in) {
            in = a;
        } else {
            return cli_usage("smooth", "more than one input file");
        }
    }
    if (!in)
        return cli_usage("smooth", "needs an input file");
    if (!out && !patches && !layout && !render && !report && !json)
        return cli_usage("smooth", "nothing to write: give -o, --patches, --layout, --render, "
                                   "--report or --json");
    cad_kind cad = out ? cad_kind_of(out, freeform) : CAD_NONE;
    if (out && cad == CAD_NONE) {
        sk_format f = sk_format_from_path(out);
        if (f != SK_FORMAT_OBJ && f != SK_FORMAT_PLY)
            return cli_usage("smooth", "-o must name an .obj, .ply, .igs, .iges, .step or .stp "
                                       "file");
    }
    if (freeform && cad != CAD_OBJ_FREEFORM)
        return cli_usage("smooth", "--obj-freeform needs -o with an .obj file");
    double t0 = sk_seconds();
    cli_progress bar;
    cli_progress_init(&bar, "smooth", quiet);
    so.progress = cli_progress_cb;
    so.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    sk_smooth *s = NULL;
    sk_soup *tes = NULL;
    int rc = EXIT_OK;
    sk_status st = sk_mesh_read(in, NULL, &mesh, &err);
    const char *normals_src = "";
    if (st == SK_OK) {
        normals_src = mesh->normals && !so.estimate_normals ? "file"
                                                             : sk_normal_method_name(so.normals);
        st = sk_smooth_build(mesh, &so, &s, &err);
    }
    cli_progress_done(&bar);
    if (st != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    double t1 = sk_seconds();
    sk_continuity_report rep;
    if ((st = sk_smooth_continuity(s, NULL, &rep, &err)) != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    double t2 = sk_seconds();
    /* the surface fails its own report (a singular patch has no tangent plane somewhere, e.g.
     * every patch of a thin strip): the report is written, the surface only on request */
    bool failed = !(rep.pass_g1 && rep.pass_gap) || rep.singular_patches > 0;
    if (failed && s->scheme == SK_SMOOTH_VC1 && !allow_fail)
        goto report_only;
    if (cad != CAD_NONE && (rc = write_cad(out, cad, s, &eo, quiet)) != EXIT_OK)
        goto done;
    if ((out && cad == CAD_NONE) || render) {
        if ((st = sk_patch_set_tessellate(&s->surface, (unsigned)tess, &tes, &err)) != SK_OK) {
            rc = cli_fail(st, &err);
            goto done;
        }
    }
    if (out && cad == CAD_NONE && (st = sk_soup_write(out, tes, NULL, &err)) != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    if (render && (st = sk_render_shaded(tes, render, NULL, &err)) != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    if (layout && (st = sk_render_patch_layout(s, layout, NULL, &err)) != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    if (patches && (rc = cli_write_file(patches, patches_json, s)) != EXIT_OK)
        goto done;
report_only:;
    report_ctx rc_ctx = {in, s, &rep, normals_src, t1 - t0 + (t2 - t1), t2 - t1};
    if (report && (rc = cli_write_file(report, report_json, &rc_ctx)) != EXIT_OK)
        goto done;
    if (json)
        report_json(stdout, &rc_ctx);
    else if (!quiet)
        printf(
                "smooth: %zu patches (%s), %zu deleted edges (bound %zu), max normal jump %.3g deg, "
                "max gap %.3g, singular patches %zu, self-intersecting patch pairs %zu, problem "
                "vertices %zu, report %s\n",
                s->surface.count, s->scheme == SK_SMOOTH_PN ? "pn" : "vc1",
                s->stats.deletion.deleted_edges, s->stats.deletion.lower_bound,
                rep.max_normal_jump_deg, rep.max_gap, rep.singular_patches, rep.intersecting_pairs,
                s->num_problems, failed ? "FAIL" : "pass");
    if (failed && s->scheme == SK_SMOOTH_VC1 && !allow_fail) {
        cli_error("%s: the surface fails its continuity report (max normal jump %.3g deg, max gap "
                  "%.3g, singular patches %zu): no surface written (--allow-fail writes it anyway)",
                  in, rep.max_normal_jump_deg, rep.max_gap, rep.singular_patches);
        rc = EXIT_QUALITY;
    }
done:
    sk_soup_destroy(&tes);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
    return rc;
}
