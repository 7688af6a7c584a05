/* surfkit smooth: VC1 surface (Cottin & van Damme) or PN triangles, tessellated, with a continuity
 * report. */
#include "cli.h"

#include <limits.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Builds a smooth surface that interpolates every vertex and normal of the triangle mesh IN\n"
    "(quads and larger polygons are triangulated first; --keep-polygons refuses them).\n"
    "vc1 (default): Cottin & van Damme's construction: edge deletion makes a mesh of triangles\n"
    "and quads in which every interior vertex is odd, then quartic triangles and bicubic quads\n"
    "join with tangent-plane continuity across every edge, without splitting faces.\n"
    "pn: PN triangles (Vlachos et al. 2001), cubic and only C0 across edges: a baseline.\n"
    "\n"
    "Normals: the file's normals (OBJ vn, PLY nx ny nz) if present, else estimated with\n"
    "--normals (default angle); --estimate-normals ignores the file's normals.\n"
    "A closed mesh with an odd number of vertices has no edge deletion (every vertex odd is\n"
    "impossible by Euler's formula): it is refused unless --allow-split, which splits its\n"
    "longest edge at the midpoint of its wire frame curve.\n";

static const char examples[] =
    "  surfkit smooth data/sphere.off -o sphere.step\n"
    "  surfkit smooth data/sphere.off -o sphere.obj --tess 8 --report "
    "sphere.json -q\n"
    "  surfkit smooth data/sphere.off --scheme pn --json -q\n"
    "  surfkit smooth data/sphere.off -o sphere.step --tolerance-rel 1e-2\n";

static const char more[] =
    "\n"
    "Exit status 4: the vc1 surface fails its own continuity report (a normal jump over\n"
    "0.5 degrees, a gap over 0.005, or a singular patch); the report (--report, --json) is\n"
    "still written, the surface files are not, unless --allow-fail (then the exit status is\n"
    "0). pn is C0 by construction: its report is information only.\n"
    "\n"
    "--tolerance T / --tolerance-rel R: the surface is built over a coarse level of the\n"
    "progressive mesh (collapses that turn no face normal by more than 15 degrees), with the\n"
    "normals estimated on the input: a binary search over the levels finds the coarsest whose\n"
    "surface is within T of the mesh both ways (every vertex, 4 points per triangle, and the\n"
    "surface's tessellation against the mesh), then, from --refine-levels below it, only the\n"
    "collapses where the distance exceeds T (or a patch is singular) are split back, round by\n"
    "round. The summary gives patches, T, the deviation (max and RMS, both ways), normal jumps,\n"
    "levels tried, rounds and seconds per stage. Exit 4 when T is not met (the surface is\n"
    "still written).\n";

typedef struct report_ctx {
    const char *in;
    const sk_smooth *s;
    const sk_continuity_report *r;
    const char *normals_src;
    sk_triangulate_stats tri;
    double seconds, report_seconds, report_cpu_seconds;
} report_ctx;

static void write_report(FILE *fp, const report_ctx *c)
{
    const char *in = c->in;
    const sk_smooth *s = c->s;
    const sk_continuity_report *r = c->r;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", in);
    json_kstr(&j, "scheme", s->scheme == SK_SMOOTH_PN ? "pn" : "vc1");
    json_kstr(&j, "normals", c->normals_src);
    json_triangulated(&j, &c->tri);
    size_t tri = 0, quad = 0;
    for (size_t p = 0; p < s->surface.count; ++p)
        s->surface.patches[p].kind == SK_PATCH_TENSOR ? ++quad : ++tri;
    json_kuint(&j, "vertices", s->config->num_vertices);
    json_kuint(&j, "triangles", tri);
    json_kuint(&j, "quads", quad);
    json_kuint(&j, "even_vertices", s->stats.deletion.even_vertices);
    json_kuint(&j, "deleted_edges", s->stats.deletion.deleted_edges);
    json_kuint(&j, "crease_edges", s->num_creases);
    /* the G0 creases of the surface (vc1): vertex pairs; max_normal_jump_deg skips them */
    json_kuint(&j, "g0_crease_edges", r->crease_edges);
    json_knum(&j, "max_crease_gap", r->max_crease_gap);
    json_knum(&j, "max_crease_jump_deg", r->max_crease_jump_deg);
    json_knum(&j, "min_crease_jump_deg", r->min_crease_jump_deg);
    json_kuints(&j, "creases", s->creases, s->num_creases, 2);
    json_kuint(&j, "deleted_edges_lower_bound", s->stats.deletion.lower_bound);
    json_kuint(&j, "split_edges", s->stats.split_edges);
    json_kuint(&j, "flipped_edges", s->stats.flipped_edges);
    json_kuint(&j, "parity_flipped_edges", s->stats.parity_flipped_edges);
    json_kuint(&j, "deletion_flipped_edges", s->stats.deletion_flipped_edges);
    json_kuint(&j, "folded_normals", s->stats.folded_normals);
    json_knum(&j, "max_gap", r->max_gap);
    json_knum(&j, "mean_gap", r->mean_gap);
    json_knum(&j, "max_normal_jump_deg", r->max_normal_jump_deg);
    json_knum(&j, "mean_normal_jump_deg", r->mean_normal_jump_deg);
    json_kuints(&j, "worst_edge", r->worst_edge_vertices, 2, 1);
    json_knum(&j, "max_vertex_error", r->max_vertex_error);
    json_knum(&j, "max_normal_error_deg", r->max_normal_error_deg);
    json_kuint(&j, "singular_patches", r->singular_patches);
    json_knum(&j, "max_overshoot", r->max_overshoot);
    json_kuint(&j, "max_overshoot_patch", r->max_overshoot_patch);
    json_knum(&j, "mean_overshoot", r->mean_overshoot);
    json_kuint(&j, "overshoot_patches", r->overshoot_patches);
    json_kuints(&j, "overshoot_patch_examples", r->overshoot_examples,
                r->num_overshoot_examples, 1);
    json_knum(&j, "max_fairness_deg", r->max_fairness_deg);
    json_kuint(&j, "max_fairness_patch", r->max_fairness_patch);
    json_knum(&j, "mean_fairness_deg", r->mean_fairness_deg);
    json_kuint(&j, "uncertified_patches", r->uncertified_patches);
    json_kuints(&j, "singular_patch_examples", r->singular_examples, r->num_singular_examples, 1);
    if (r->intersecting_pairs != SIZE_MAX) {
        json_kuint(&j, "self_intersecting_pairs", r->intersecting_pairs);
        json_kuint(&j, "self_intersecting_patches", r->intersecting_patches);
        json_kuints(&j, "self_intersection_examples", r->intersection_examples,
                    r->num_intersection_examples, 2);
    }
    json_kuint(&j, "relaxed_vertices", s->stats.relaxed_vertices);
    json_kuint(&j, "angle_violations", s->stats.angle_violations);
    json_kuint(&j, "singular_before_repair", s->stats.singular_before_repair);
    json_kuint(&j, "repaired_vertices", s->stats.repaired_vertices);
    json_kuint(&j, "rerouted_rounds", s->stats.rerouted_rounds);
    json_kuint(&j, "fair_steps", s->stats.fair_steps);
    json_kuint(&j, "fit_points", s->stats.fit_points);
    json_kuint(&j, "fit_undone", s->stats.fit_undone);
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
    const sk_smooth_stats *t = &s->stats;
    const double wall[] = {t->seconds_normals, t->seconds_flips,   t->seconds_deletion,
                           t->seconds_systems, t->seconds_fair,    t->seconds_patches,
                           t->seconds_repair,  c->report_seconds};
    const double cpu[] = {t->cpu_normals, t->cpu_flips, t->cpu_deletion, t->cpu_systems,
                          t->cpu_fair,    t->cpu_patches, t->cpu_repair, c->report_cpu_seconds};
    static const char *const stage[] = {"normals",     "flips",   "edge_deletion", "vertex_systems",
                                        "fair_points", "patches", "repair",        "report"};
    for (int k = 0; k < 2; ++k) { /* CPU seconds: all threads, meaningful on a loaded machine */
        json_key(&j, k ? "stage_cpu_seconds" : "stage_seconds");
        json_obj_open(&j);
        for (size_t i = 0; i < sizeof stage / sizeof *stage; ++i)
            json_knum(&j, stage[i], k ? cpu[i] : wall[i]);
        json_obj_close(&j);
    }
    json_knum(&j, "seconds", c->seconds);
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
    sk_patch_shape *shape = malloc((set->count + 1) * sizeof *shape); /* per patch, if it can */
    if (shape && sk_smooth_patch_shapes(s, 0, shape, NULL) != SK_OK) {
        free(shape);
        shape = NULL;
    }
    for (size_t p = 0; p < set->count; ++p) {
        const sk_patch *pa = &set->patches[p];
        bool quad = pa->kind == SK_PATCH_TENSOR;
        fprintf(fp, "{\"kind\": \"%s\", \"degree\": %d, \"corners\": [%u, %u, %u",
                quad ? "quad" : "triangle", pa->degree, pa->corner_ids[0], pa->corner_ids[1],
                pa->corner_ids[2]);
        if (quad)
            fprintf(fp, ", %u", pa->corner_ids[3]);
        if (shape) {
            char ov[32], fa[32];
            sk_format_double(ov, shape[p].overshoot);
            sk_format_double(fa, shape[p].fairness_deg);
            fprintf(fp, "], \"overshoot\": %s, \"fairness_deg\": %s, \"singular\": %s", ov, fa,
                    shape[p].singular ? "true" : "false");
        }
        fprintf(fp, "%s\"points\": [", shape ? ", " : "], ");
        const double *cp = sk_patch_cp(set, p);
        for (size_t i = 0; i < sk_patch_num_points(pa); ++i) {
            char x[3][32];
            for (int k = 0; k < 3; ++k)
                sk_format_double(x[k], cp[3 * i + k]);
            fprintf(fp, "%s[%s, %s, %s]", i ? ", " : "", x[0], x[1], x[2]);
        }
        fprintf(fp, "]}%s\n", p + 1 < set->count ? "," : "");
    }
    fprintf(fp, "]}\n");
    free(shape);
}


static void report_json(FILE *fp, const void *ctx)
{
    const report_ctx *c = ctx;
    write_report(fp, c);
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

static const char *const unit_names[] = {"mm", "cm", "m", "um", "in", "ft"};

/* argv -> options */
typedef struct smooth_args {
    const char *in, *out, *patches, *layout, *render, *zebra, *patch_map, *report;
    unsigned tess;
    unsigned reroute_rounds;
    bool quiet, json, freeform, allow_fail, keep_polygons, no_creases;
    cad_kind cad;
    sk_tolerance_opts to; /* --tolerance / --tolerance-rel: the coarse-level route */
    bool tolerance;
    sk_smooth_opts so;
    sk_export_opts eo;
} smooth_args;

/* EXIT_OK to run, CLI_HELP, or the usage error's exit code */
static int parse_args(int argc, char **argv, smooth_args *a)
{
    unsigned units = 0, triangles = 0;
    a->tess = 4;
    a->reroute_rounds = UINT_MAX; /* not given: the library's default */
    const cli_opt opts[] = {
        OPT_FILE("-o", a->out, "OUT",
                 "by extension: .obj/.ply the tessellated surface with exact patch normals;\n"
                 ".igs/.iges IGES 5.3 B-rep: B-spline faces (entity 128) sharing edges\n"
                 "and vertices, a solid (186) when the surface is closed, else a shell;\n"
                 ".step/.stp STEP AP214, faces sharing edges and vertices, a solid\n"
                 "(MANIFOLD_SOLID_BREP) when the surface is closed, else a shell;\n"
                 ".obj with --obj-freeform: OBJ free-form surfaces, each patch as a\n"
                 "B-spline with clamped knots (cstype bspline).\n"
                 "CAD formats write each quartic triangle as one biquartic face with a side\n"
                 "collapsed to a corner (exact)"),
        OPT_CHOICE("--scheme", a->so.scheme, "vc1|pn", "vc1 (default) or PN triangles"),
        OPT_INT("--tess", a->tess, 1, 64, "N", "grid of N x N per patch (default 4)"),
        OPT_FILE("--patches", a->patches, "FILE", "control nets as JSON"),
        OPT_FILE("--layout", a->layout, "FILE",
                 "picture of the triangle/quad configuration, deleted edges in red,\n"
                 "problem vertices in orange"),
        OPT_FILE("--render", a->render, "FILE",
                 "picture of the surface shaded with its exact normals (per pixel)"),
        OPT_FILE("--zebra", a->zebra, "FILE",
                 "zebra stripes (reflection lines): a kink in the stripes is a kink in the\n"
                 "surface"),
        OPT_FILE("--patch-map", a->patch_map, "FILE",
                 "the patches, those with overshoot > 0.5 (orange) or a singular point\n"
                 "(magenta) highlighted"),
        OPT_FILE("--report", a->report, "FILE",
                 "continuity report as JSON (--json prints it on stdout): gaps and normal\n"
                 "jumps across patch boundaries, vertex and normal errors, singular patches\n"
                 "(the normal vanishes or turns over somewhere: a cusp or a fold), uncertified\n"
                 "patches (the normal-cone test cannot prove them regular; most are),\n"
                 "self-intersecting patch pairs (patches sharing no corner that cross each\n"
                 "other: what CAD checkers flag), shape: max_overshoot (distance from the\n"
                 "flat face / its longest edge; a spike is > 1) and fairness (angle between\n"
                 "the patch normal and the interpolated vertex normals), worst patch ids,\n"
                 "pass/fail against 0.5 deg and 0.005"),
        OPT_FLAG("--json", a->json, "print the continuity report as JSON"),
        OPT_CHOICE("--normals", a->so.normals, "angle|area|mean|quadric",
                   "normal estimate when the file has none (default angle)"),
        OPT_FLAG("--estimate-normals", a->so.estimate_normals, "ignore the file's normals"),
        OPT_FLAG("--allow-split", a->so.allow_split,
                 "split the longest edge of a closed mesh with an odd vertex count"),
        OPT_FLAG("--obj-freeform", a->freeform, "-o .obj writes OBJ free-form B-spline surfaces"),
        OPT_CHOICE("--units", units, "mm|cm|m|um|in|ft", "CAD length unit of the coordinates "
                   "(default mm)"),
        OPT_CHOICE("--iges-triangles", triangles, "face|split|degenerate",
                   "face (default): one collapsed-side face per triangle in the B-rep; split:\n"
                   "three regular biquartic faces (STEP and IGES, 3x the size); degenerate:\n"
                   "the one-patch surfaces as loose IGES faces in one group"),
        OPT_FLAG("--keep-triangulation", a->so.keep_triangulation,
                 "vc1: keep the input's edges (default: flip edges to remove slivers and\n"
                 "near-folds where the new edge bends under 10 degrees; same vertices)"),
        OPT_FLAG("--parity-flips", a->so.parity_flips,
                 "vc1: also flip edges that make even vertices odd where the shape and the\n"
                 "normal agreement are kept: fewer deleted edges (parity_flipped_edges)"),
        OPT_FLAG("--deletion-flips", a->so.deletion_flips,
                 "vc1: edge flips chosen for the edge deletion: fewer deleted edges on rough\n"
                 "scans (deletion_flipped_edges), about twice the build CPU there"),
        OPT_INT("--reroute-rounds", a->reroute_rounds, 0, 64, "K",
                "vc1: where patches stay singular after the regularity repair, build again\n"
                "up to K times (default 6, 12 with --refine-base; 0: never) with the edge\n"
                "deletion changed near them and their slivers flipped, keeping a build with\n"
                "fewer (rerouted_rounds; not in the --tolerance search, which refines at\n"
                "singular patches itself)"),
        OPT_INT("--refine-base", a->so.base_refinements, 0, 4, "N",
                "vc1: refine the input N times before the edge deletion (after the normals\n"
                "and the crease detection on it; no edge flips): every edge but the near-folds\n"
                "(facets over 120 degrees apart) split at its midpoint, on the input's facets\n"
                "with the facets' normal, the input's creases kept; the re-routed rounds may\n"
                "flip slivers of the refined base near singular patches (default 0; not with\n"
                "--tolerance)"),
        OPT_CHOICE("--free-points", a->so.free_points, "fair|lsq",
                   "vc1: free tangent control points by least squares to the wire frame\n"
                   "moved to lower the patches' bending energy (fair, default), or the\n"
                   "least-squares fit alone (lsq); both exactly VC1"),
        OPT_DOUBLE("--fit-weight", a->so.fit_weight, 0, 0, 0, "W",
                   "vc1: after the regularity repair, fit the free tangent control points to\n"
                   "the mesh: W times the squared distances of its vertices and 4 points per\n"
                   "triangle to their foot points on the surface (and of points inside each\n"
                   "patch to the mesh) added to the fair points' energy, every vertex swept,\n"
                   "3 rounds; still exactly VC1, no patch made singular (default 0: off; with\n"
                   "--tolerance every build fits to the input)"),
        OPT_DOUBLE("--crease-angle", a->so.crease_angle_deg, 0, 180, CLI_LO_OPEN, "DEG",
                   "sharp edges (dihedral angle >= DEG, default 40) become G0 creases: patch\n"
                   "boundaries with one normal per side, G1 elsewhere (crease_edges and\n"
                   "max_crease_gap in the report; the max normal jump skips them)"),
        OPT_FLAG("--no-creases", a->no_creases,
                 "no creases: G1 across every edge, sharp ones included (crease_edges 0)"),
        OPT_FLAG("--keep-polygons", a->keep_polygons, "refuse quads and polygons (default: split)"),
        OPT_FLAG("--allow-fail", a->allow_fail,
                 "write the surface even when the vc1 continuity report fails"),
        OPT_DOUBLE("--tolerance", a->to.tolerance, 0, 0, CLI_LO_OPEN, "T",
                   "vc1 over a coarse level of the progressive mesh: as few patches as keep\n"
                   "the surface within T (model units) of the mesh both ways (vertices and face\n"
                   "samples); exit 4 when not met (the surface is still written)"),
        OPT_DOUBLE("--tolerance-rel", a->to.tolerance_rel, 0, 1, CLI_LO_OPEN, "R",
                   "--tolerance as R times the bounding-box diagonal"),
        OPT_INT("--refine-levels", a->to.refine_levels, 1, 64, "K",
                "with a tolerance: the local refinement starts K levels below the coarsest\n"
                "level that meets it (default 6)"),
        OPT_INT("--stall-rounds", a->to.stall_rounds, 1, 1000, "K",
                "with a tolerance: the refinement stops after K rounds in a row that lower\n"
                "neither the offending vertices nor the max deviation (default 4)"),
        OPT_FLAG("--full-checks", a->to.full_checks,
                 "with a tolerance: every refinement round measures all distances again\n"
                 "(default: only what the patches' displacement since the last round\n"
                 "can have changed)"),
        OPT_FLAG("--full-search", a->to.full_search,
                 "with a tolerance: search the levels with VC1 builds until the coarsest one\n"
                 "within it is found (default: only 3 levels under the estimate; missed there,\n"
                 "the refinement starts from the estimate)"),
        OPT_FLAG("-q", a->quiet, "no progress bar, no summary"),
    };
    const cli_spec spec = {"smooth", "IN [-o OUT.obj|OUT.ply|OUT.igs|OUT.step]", about,
                           opts, CLI_COUNT(opts), 1, 1, examples, more};
    cli_args args;
    int rc = cli_parse(&spec, argc, argv, &args);
    if (rc)
        return rc;
    if (cli_given(&args, "--units"))
        a->eo.units = unit_names[units];
    a->eo.split_triangles = triangles == 1;
    a->eo.degenerate_triangles = triangles == 2;
    a->in = cli_input(&args, 0);
    if (!a->out && !a->patches && !a->layout && !a->render && !a->zebra && !a->patch_map &&
        !a->report && !a->json)
        return cli_usage("smooth", "nothing to write: give -o, --patches, --layout, --render, "
                                   "--zebra, --patch-map, --report or --json");
    a->cad = a->out ? cad_kind_of(a->out, a->freeform) : CAD_NONE;
    if (a->out && a->cad == CAD_NONE) {
        sk_format f = sk_format_from_path(a->out);
        if (f != SK_FORMAT_OBJ && f != SK_FORMAT_PLY)
            return cli_usage("smooth", "-o must name an .obj, .ply, .igs, .iges, .step or .stp "
                                       "file");
    }
    if (a->freeform && a->cad != CAD_OBJ_FREEFORM)
        return cli_usage("smooth", "--obj-freeform needs -o with an .obj file");
    if (a->to.tolerance > 0 && a->to.tolerance_rel > 0)
        return cli_usage("smooth", "give --tolerance or --tolerance-rel, not both");
    a->tolerance = a->to.tolerance > 0 || a->to.tolerance_rel > 0;
    if (a->tolerance && a->so.scheme != SK_SMOOTH_VC1)
        return cli_usage("smooth", "--tolerance builds vc1 surfaces (not --scheme pn)");
    if (cli_given(&args, "--refine-levels") && !a->tolerance)
        return cli_usage("smooth", "--refine-levels needs --tolerance or --tolerance-rel");
    if (cli_given(&args, "--stall-rounds") && !a->tolerance)
        return cli_usage("smooth", "--stall-rounds needs --tolerance or --tolerance-rel");
    if (a->to.full_checks && !a->tolerance)
        return cli_usage("smooth", "--full-checks needs --tolerance or --tolerance-rel");
    if (a->to.full_search && !a->tolerance)
        return cli_usage("smooth", "--full-search needs --tolerance or --tolerance-rel");
    return EXIT_OK;
}

/* The surface files and pictures (after the report has passed, or --allow-fail). */
static int write_surface(const smooth_args *a, const sk_smooth *s)
{
    sk_error err = {0};
    sk_soup *tes = NULL;
    sk_status st = SK_OK;
    int rc = EXIT_OK;
    sk_export_opts eo = a->eo;
    if (a->cad != CAD_NONE && (rc = write_cad(a->out, a->cad, s, &eo, a->quiet)) != EXIT_OK)
        return rc;
    if (a->out && a->cad == CAD_NONE)
        st = sk_patch_set_tessellate(&s->surface, a->tess, &tes, &err);
    if (!st && a->out && a->cad == CAD_NONE)
        st = sk_soup_write(a->out, tes, NULL, &err);
    const char *pics[3] = {a->render, a->zebra, a->patch_map}; /* sk_surface_picture order */
    for (int k = 0; k < 3 && !st; ++k)
        if (pics[k])
            st = sk_render_surface(s, (sk_surface_picture)k, pics[k], NULL, &err);
    if (!st && a->layout)
        st = sk_render_patch_layout(s, a->layout, NULL, &err);
    sk_soup_destroy(&tes);
    if (st)
        return cli_fail(st, &err);
    if (a->patches)
        rc = cli_write_file(a->patches, patches_json, s);
    return rc;
}

static void print_summary(const sk_smooth *s, const sk_continuity_report *rep, bool failed)
{
    char creases[160] = "";
    if (rep->crease_edges)
        snprintf(creases, sizeof creases,
                 " off %zu crease edges (G0 there: normal jump %.3g..%.3g deg, max gap %.3g)",
                 rep->crease_edges, rep->min_crease_jump_deg, rep->max_crease_jump_deg,
                 rep->max_crease_gap);
    printf("smooth: %zu patches (%s), %zu deleted edges (bound %zu), max normal jump %.3g deg%s, "
           "max gap %.3g, singular patches %zu, self-intersecting patch pairs %zu, problem "
           "vertices %zu, report %s\n",
           s->surface.count, s->scheme == SK_SMOOTH_PN ? "pn" : "vc1",
           s->stats.deletion.deleted_edges, s->stats.deletion.lower_bound,
           rep->max_normal_jump_deg, creases, rep->max_gap, rep->singular_patches,
           rep->intersecting_pairs, s->num_problems, failed ? "FAIL" : "pass");
}

static int smooth_tolerance(const smooth_args *a);

int cmd_smooth(int argc, char **argv)
{
    smooth_args a;
    memset(&a, 0, sizeof a);
    int rc = parse_args(argc, argv, &a);
    if (rc)
        return rc == CLI_HELP ? EXIT_OK : rc;
    if (a.no_creases)
        a.so.crease_angle_deg = -1.0; /* no detection, no G0 construction */
    a.so.reroute_rounds = a.reroute_rounds == UINT_MAX ? 0
                          : a.reroute_rounds          ? (int)a.reroute_rounds
                                                      : -1;
    if (a.tolerance)
        return smooth_tolerance(&a);
    double t0 = sk_seconds();
    cli_progress bar;
    cli_progress_init(&bar, "smooth", a.quiet);
    a.so.progress = cli_progress_cb;
    a.so.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    sk_smooth *s = NULL;
    sk_continuity_report rep;
    sk_triangulate_stats tri;
    sk_status st = cli_read_triangles(a.in, a.keep_polygons, &mesh, &tri, &err);
    if (st == SK_OK && !a.quiet && !a.json)
        cli_print_triangulated(a.in, &tri);
    const char *normals_src = "";
    if (st == SK_OK) {
        bool from_file = mesh->normals && !a.so.estimate_normals;
        normals_src = from_file ? "file" : sk_normal_method_name(a.so.normals);
        st = sk_smooth_build(mesh, &a.so, &s, &err);
    }
    cli_progress_done(&bar);
    double t1 = sk_seconds(), c1 = sk_cpu_seconds();
    if (st == SK_OK)
        st = sk_smooth_continuity(s, NULL, &rep, &err);
    cli_name_input(a.in, st, &err);
    if (st != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    double t2 = sk_seconds(), c2 = sk_cpu_seconds();
    /* the surface fails its own report (a singular patch has no tangent plane somewhere, e.g.
     * every patch of a thin strip): the report is written, the surface only on request */
    bool failed = !(rep.pass_g1 && rep.pass_gap) || rep.singular_patches > 0;
    bool refuse = failed && s->scheme == SK_SMOOTH_VC1 && !a.allow_fail;
    if (!refuse && (rc = write_surface(&a, s)) != EXIT_OK)
        goto done;
    report_ctx rc_ctx = {a.in, s, &rep, normals_src, tri, t2 - t0, t2 - t1, c2 - c1};
    if (a.report && (rc = cli_write_file(a.report, report_json, &rc_ctx)) != EXIT_OK)
        goto done;
    if (a.json)
        report_json(stdout, &rc_ctx);
    else if (!a.quiet)
        print_summary(s, &rep, failed);
    if (refuse) {
        cli_error("%s: the surface fails its continuity report (max normal jump %.3g deg, max gap "
                  "%.3g, singular patches %zu): no surface written (--allow-fail writes it anyway)",
                  a.in, rep.max_normal_jump_deg, rep.max_gap, rep.singular_patches);
        rc = EXIT_QUALITY;
    }
done:
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
    return rc;
}

/* ---------------------------------------------------------------------------------------------
 * --tolerance / --tolerance-rel: the coarse-level route (sk_smooth_tolerance)
 * ------------------------------------------------------------------------------------------- */

typedef struct tol_report {
    const char *in;
    const sk_smooth *s;
    const sk_tolerance_stats *t;
    const sk_continuity_report *r;
    const char *normals_src;
    sk_triangulate_stats tri;
    double seconds_report, seconds;
} tol_report;

static void write_tol_report(FILE *fp, const void *ctx)
{
    const tol_report *x = ctx;
    const sk_tolerance_stats *t = x->t;
    const sk_continuity_report *r = x->r;
    const sk_deviation_report *d = &t->deviation;
    double diag = t->diagonal > 0 ? t->diagonal : 1;
    size_t tri = 0, quad = 0;
    for (size_t p = 0; p < x->s->surface.count; ++p)
        x->s->surface.patches[p].kind == SK_PATCH_TENSOR ? ++quad : ++tri;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", x->in);
    json_kstr(&j, "scheme", "vc1");
    json_kstr(&j, "normals", x->normals_src);
    json_kuint(&j, "crease_edges", x->s->num_creases);
    json_kuint(&j, "g0_crease_edges", r->crease_edges);
    json_triangulated(&j, &x->tri);
    json_knum(&j, "tolerance", t->tolerance);
    json_knum(&j, "tolerance_rel", t->tolerance / diag);
    json_kbool(&j, "met", t->met);
    json_kuint(&j, "input_faces", t->input_faces);
    json_kuint(&j, "patches", t->patches);
    json_kuint(&j, "triangles", tri);
    json_kuint(&j, "quads", quad);
    json_kuint(&j, "vertices", t->vertices);
    json_knum(&j, "faces_per_patch", t->patches ? (double)t->input_faces / (double)t->patches : 0);
    json_key(&j, "deviation");
    json_obj_open(&j);
    json_knum(&j, "hausdorff", d->hausdorff);
    json_knum(&j, "hausdorff_rel", d->hausdorff / diag);
    json_knum(&j, "diagonal", d->diagonal);
    json_knum(&j, "mesh_to_surface_max", d->mesh_to_surface.max);
    json_knum(&j, "mesh_to_surface_rms", d->mesh_to_surface.rms);
    json_knum(&j, "mesh_to_surface_mean", d->mesh_to_surface.mean);
    json_knum(&j, "surface_to_mesh_max", d->surface_to_mesh.max);
    json_knum(&j, "surface_to_mesh_rms", d->surface_to_mesh.rms);
    json_knum(&j, "surface_to_mesh_mean", d->surface_to_mesh.mean);
    json_obj_close(&j);
    json_knum(&j, "max_normal_jump_deg", r->max_normal_jump_deg);
    json_knum(&j, "mean_normal_jump_deg", r->mean_normal_jump_deg);
    json_knum(&j, "max_gap", r->max_gap);
    json_kuint(&j, "singular_patches", r->singular_patches);
    json_kbool(&j, "pass_g1", r->pass_g1);
    json_kbool(&j, "pass_gap", r->pass_gap);
    json_kuint(&j, "hierarchy_levels", t->levels);
    json_kuint(&j, "estimate_level", t->estimate_level);
    json_kuint(&j, "linear_levels_tried", t->linear_tried);
    json_kuint(&j, "levels_tried", t->levels_tried);
    json_kuint(&j, "failed_levels", t->failed_levels);
    json_kuint(&j, "singular_levels", t->singular_levels);
    json_kbool(&j, "level_met", t->level_met);
    json_kbool(&j, "level_assumed", t->level_assumed);
    json_kuint(&j, "coarsest_level_met", t->coarsest_met);
    json_kuint(&j, "base_level", t->base_level);
    json_kuint(&j, "refinement_rounds", t->rounds);
    json_kuint(&j, "failed_rounds", t->failed_rounds);
    json_kuint(&j, "stalled_refinements", t->stalled);
    json_kuint(&j, "parity_splits", t->parity_splits);
    json_kuint(&j, "checked_patches", t->checked_patches);
    json_kuint(&j, "reused_patches", t->reused_patches);
    json_kbool(&j, "refined", t->refined);
    json_key(&j, "tried");
    json_arr_open(&j);
    for (size_t k = 0; k < t->num_tried && k < SK_TOLERANCE_MAX_TRIED; ++k) {
        const sk_tolerance_try *e = &t->tried[k];
        json_obj_open(&j);
        json_kstr(&j, "kind", e->refined ? "round" : "level");
        json_kuint(&j, "level", e->level);
        json_kuint(&j, "vertices", e->vertices);
        if (e->status) {
            json_kstr(&j, "vc1", sk_status_string(e->status));
        } else {
            json_kuint(&j, "patches", e->patches);
            json_knum(&j, "max_deviation", e->max_deviation);
            /* what the check measured (sk_tolerance_try.max_deviation): within T only bounded;
             * a level the search found beyond T: the first distances beyond T it met */
            json_kstr(&j, "max_deviation_is",
                      e->met ? "upper_bound" : e->refined ? "exact" : "lower_bound");
            json_kuint(&j, "singular_patches", e->singular);
            json_kbool(&j, "met", e->met);
            if (e->refined) {
                json_kuint(&j, "offending_vertices", e->offending);
                json_kuint(&j, "paired_patches", e->paired);
                json_kuint(&j, "unmoved_patches", e->unmoved);
                json_kuint(&j, "moved_far_patches", e->moved_far);
            }
        }
        json_obj_close(&j);
    }
    json_arr_close(&j);
    json_key(&j, "stage_seconds");
    json_obj_open(&j);
    json_knum(&j, "normals", t->seconds_normals);
    json_knum(&j, "hierarchy", t->seconds_hierarchy);
    json_knum(&j, "search", t->seconds_search);
    json_knum(&j, "estimate", t->seconds_estimate);
    json_knum(&j, "refine", t->seconds_refine);
    json_knum(&j, "vc1", t->seconds_vc1);
    json_knum(&j, "check", t->seconds_check);
    json_knum(&j, "deviation", t->seconds_deviation);
    json_knum(&j, "report", x->seconds_report);
    json_obj_close(&j);
    json_knum(&j, "seconds", x->seconds);
    json_obj_close(&j);
    json_end(&j);
}

static void print_tol_summary(const tol_report *x)
{
    const sk_tolerance_stats *t = x->t;
    const sk_deviation_report *d = &t->deviation;
    double diag = t->diagonal > 0 ? t->diagonal : 1;
    printf("smooth: %zu patches (vc1) for %zu triangles, tolerance %.6g (%.3g of the diagonal) %s; "
           "deviation max %.6g (%.3g): mesh to surface max %.6g rms %.6g, surface to mesh max "
           "%.6g rms %.6g\n",
           t->patches, t->input_faces, t->tolerance, t->tolerance / diag,
           t->met ? "met" : "NOT MET", d->hausdorff, d->hausdorff / diag, d->mesh_to_surface.max,
           d->mesh_to_surface.rms, d->surface_to_mesh.max, d->surface_to_mesh.rms);
    printf("smooth: max normal jump %.3g deg, max gap %.3g, singular patches %zu; %zu levels, %zu "
           "tried (%zu without a vc1 surface), ",
           x->r->max_normal_jump_deg, x->r->max_gap, x->r->singular_patches, t->levels,
           t->levels_tried, t->failed_levels);
    if (t->level_met)
        printf("coarsest within T: %zu", t->coarsest_met);
    else
        printf("none within T");
    if (t->rounds)
        printf(", %zu refinement rounds from level %zu (%s)", t->rounds, t->base_level,
               t->refined ? "kept" : "the full level kept: fewer patches");
    printf(", %.3f s\n", x->seconds);
}

static int smooth_tolerance(const smooth_args *a)
{
    double t0 = sk_seconds();
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    sk_smooth *s = NULL;
    sk_tolerance_stats ts;
    sk_continuity_report rep;
    sk_triangulate_stats tri;
    int rc = EXIT_OK;
    cli_progress bar;
    cli_progress_init(&bar, "smooth", a->quiet);
    sk_tolerance_opts to = a->to;
    to.smooth = a->so;
    to.tess = a->tess; /* the deviation is that of the tessellation -o writes */
    to.progress = cli_progress_cb;
    to.progress_user = &bar;
    sk_status st = cli_read_triangles(a->in, a->keep_polygons, &mesh, &tri, &err);
    if (st == SK_OK && !a->quiet && !a->json)
        cli_print_triangulated(a->in, &tri);
    const char *normals_src = "";
    if (st == SK_OK) {
        normals_src = mesh->normals && !a->so.estimate_normals ? "file"
                                                                : sk_normal_method_name(a->so.normals);
        st = sk_smooth_tolerance(mesh, &to, &s, NULL, &ts, &err);
    }
    cli_progress_done(&bar);
    bool missed = st == SK_WARN_TOLERANCE;
    char missed_msg[SK_ERROR_MESSAGE_SIZE] = "";
    if (missed) {
        memcpy(missed_msg, err.message, sizeof missed_msg);
        st = SK_OK;
    }
    double t1 = sk_seconds();
    if (st == SK_OK)
        st = sk_smooth_continuity(s, NULL, &rep, &err);
    cli_name_input(a->in, st, &err);
    if (st != SK_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    double t2 = sk_seconds();
    bool failed = !(rep.pass_g1 && rep.pass_gap) || rep.singular_patches > 0;
    if ((!failed || a->allow_fail) && (rc = write_surface(a, s)) != EXIT_OK)
        goto done;
    tol_report x = {a->in, s, &ts, &rep, normals_src, tri, t2 - t1, sk_seconds() - t0};
    if (a->report && (rc = cli_write_file(a->report, write_tol_report, &x)) != EXIT_OK)
        goto done;
    if (a->json)
        write_tol_report(stdout, &x);
    else if (!a->quiet)
        print_tol_summary(&x);
    if (failed) {
        cli_error("%s: the surface fails its continuity report (max normal jump %.3g deg, max gap "
                  "%.3g, singular patches %zu): %s", a->in, rep.max_normal_jump_deg, rep.max_gap,
                  rep.singular_patches, a->allow_fail ? "written anyway (--allow-fail)"
                  : "no surface written (--allow-fail writes it anyway)");
        rc = a->allow_fail ? rc : EXIT_QUALITY;
    }
    if (missed) {
        cli_error("%s: %s (%s)", a->in, missed_msg,
                  failed && !a->allow_fail ? "not written: it fails its continuity report"
                                           : "the surface is written");
        rc = EXIT_QUALITY;
    }
done:
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
    return rc;
}
