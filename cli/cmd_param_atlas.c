/* surfkit param on a mesh that is not one disk (or with --atlas): automatic charts, per-chart
 * hierarchical MIPS, packing (sk_atlas_build), per-corner uvs out, report and pictures.
 * cmd_param calls cmd_param_atlas first; it takes the run when the atlas is wanted and leaves
 * everything else (disks, usage errors, unreadable files) to cmd_param. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

const char cli_param_atlas_help[] =
    "\n"
    "Atlas (any manifold triangle mesh: closed, with holes or handles, several components; used\n"
    "when the input is not one disk, or with --atlas; --method mips only):\n"
    "  charts that are topological disks (components; holes and handles cut along where a grown\n"
    "  disk meets itself; closed pieces and charts above the distortion bounds bisected), each\n"
    "  parametrized by hierarchical MIPS with a free boundary, checked for flips and overlaps\n"
    "  (a chart that overlaps itself is split), packed into [0,1]^2 with one scale.\n"
    "  --max-distortion D  per chart, area-weighted mean sigma1/sigma2 (default 1.25)\n"
    "  --max-stretch S     per chart, exp of the area-weighted mean |log area scale / chart's\n"
    "                      mean| (default 1.25)\n"
    "  --resolution R --padding P  gutter of P texels at R texels across (defaults 1024, 2)\n"
    "  --split-seams       write one vertex per uv (per-vertex u v: what Blender's PLY reader\n"
    "                      takes); default: per-corner uvs (OBJ f v/vt with vt shared inside a\n"
    "                      chart; PLY face list texcoord, MeshLab's convention)\n"
    "  --png/--svg the atlas coloured by conformal distortion, chart borders in black;\n"
    "  --checker the checkerboard on the 3D mesh; --report adds charts, seams, overlaps,\n"
    "  utilization and seconds per stage.\n";

typedef struct atlas_run {
    const char *in;
    const sk_atlas *atlas;
    sk_atlas_stats st;
    size_t faces;
    double read_seconds, write_seconds;
} atlas_run;

static void write_json(FILE *fp, const void *ctx)
{
    const atlas_run *r = ctx;
    const sk_atlas_stats *s = &r->st;
    cli_json j;
    json_begin(&j, fp);
    json_obj_open(&j);
    json_kstr(&j, "input", r->in);
    json_kstr(&j, "method", "atlas-mips-hierarchical");
    json_kuint(&j, "faces", r->faces);
    json_kuint(&j, "charts", s->charts);
    json_kuint(&j, "seam_edges", s->seam_edges);
    json_knum(&j, "seam_length_rel", s->seam_length_rel);
    json_knum(&j, "mips_mean", s->mips_mean);
    json_knum(&j, "conformal_mean", s->conformal_mean);
    json_knum(&j, "area_log_mean", s->area_log_mean);
    json_key(&j, "chart_mips_mean"); /* per chart, in chart order */
    json_arr_open(&j);
    for (size_t c = 0; r->atlas && c < r->atlas->num_charts; ++c)
        json_num(&j, r->atlas->chart_mips[c]);
    json_arr_close(&j);
    json_key(&j, "chart_faces");
    json_arr_open(&j);
    for (size_t c = 0; r->atlas && c < r->atlas->num_charts; ++c)
        json_uint(&j, r->atlas->chart_faces[c]);
    json_arr_close(&j);
    json_kuint(&j, "flipped", s->flipped);
    json_kuint(&j, "overlaps", s->overlaps);
    json_knum(&j, "utilization", s->utilization);
    json_knum(&j, "scale", s->scale);
    json_key(&j, "splits");
    json_obj_open(&j);
    json_kuint(&j, "topology", s->splits_topology);
    json_kuint(&j, "overlap", s->splits_overlap);
    json_kuint(&j, "distortion", s->splits_distortion);
    json_kuint(&j, "failed", s->splits_failed);
    json_obj_close(&j);
    json_key(&j, "seconds");
    json_obj_open(&j);
    json_knum(&j, "read", r->read_seconds);
    json_knum(&j, "charts", s->charts_seconds);
    json_knum(&j, "parametrize", s->param_seconds);
    json_knum(&j, "pack", s->pack_seconds);
    json_knum(&j, "check", s->check_seconds);
    json_knum(&j, "atlas_total", s->total_seconds);
    json_knum(&j, "write", r->write_seconds);
    json_obj_close(&j);
    json_obj_close(&j);
    json_end(&j);
}

static bool parse_num(const char *s, double *out)
{
    if (!s || !*s)
        return false;
    char *end;
    *out = strtod(s, &end);
    return *end == '\0';
}

int cmd_param_atlas(int argc, char **argv, bool *handled)
{
    *handled = false;
    const char *in = NULL, *out = NULL, *png = NULL, *svg = NULL, *checker = NULL, *report = NULL;
    const char *val, *method = NULL, *view = NULL;
    bool quiet = false, json = false, forced = false, split = false, disk_only = false;
    sk_atlas_opts ao = {0};
    sk_write_opts wo = {0};
    sk_render_opts ro = {0};
    unsigned long seed = 1, res = 0;
    const cli_path_opt paths[] = {{"-o", &out}, {"--png", &png}, {"--svg", &svg},
                                  {"--checker", &checker}, {"--report", &report}};
    int took;
    /* a quiet first pass: anything unexpected is left to cmd_param */
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        double d;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            return EXIT_OK;
        } else if (!strcmp(a, "-q")) {
            quiet = true;
        } else if (!strcmp(a, "--json")) {
            json = true;
        } else if (!strcmp(a, "--ascii")) {
            wo.ascii = true;
        } else if (!strcmp(a, "--atlas")) {
            forced = true;
        } else if (!strcmp(a, "--split-seams")) {
            split = forced = true;
        } else if (!strcmp(a, "--flat") || !strcmp(a, "--hierarchical")) {
            disk_only = true;
        } else if ((took = cli_take_path(argc, argv, &i, "param", paths, 5)) != 0) {
            if (took < 0)
                return EXIT_USAGE; /* cmd_param would say the same */
        } else if (cli_opt_value(argc, argv, &i, "--method", &val)) {
            method = val;
        } else if (cli_opt_value(argc, argv, &i, "--boundary", &val) ||
                   cli_opt_value(argc, argv, &i, "--spacing", &val) ||
                   cli_opt_value(argc, argv, &i, "--steps", &val)) {
            disk_only = true;
        } else if (cli_opt_value(argc, argv, &i, "--seed", &val)) {
            if (!cli_parse_uint(val, &seed))
                return EXIT_OK; /* cmd_param reports it */
        } else if (cli_opt_value(argc, argv, &i, "--view", &val)) {
            view = val;
        } else if (cli_opt_value(argc, argv, &i, "--max-distortion", &val)) {
            if (!parse_num(val, &d) || !(d > 1.0))
                return *handled = true, cli_usage("param", "--max-distortion takes a number > 1");
            ao.max_distortion = d;
            forced = true;
        } else if (cli_opt_value(argc, argv, &i, "--max-stretch", &val)) {
            if (!parse_num(val, &d) || !(d > 1.0))
                return *handled = true, cli_usage("param", "--max-stretch takes a number > 1");
            ao.max_stretch = d;
            forced = true;
        } else if (cli_opt_value(argc, argv, &i, "--resolution", &val)) {
            if (!cli_parse_uint(val, &res) || res < 16 || res > 1u << 20)
                return *handled = true, cli_usage("param", "--resolution takes 16 .. 1048576");
            ao.resolution = (unsigned)res;
            forced = true;
        } else if (cli_opt_value(argc, argv, &i, "--padding", &val)) {
            if (!parse_num(val, &d) || !(d >= 0) || d > 64)
                return *handled = true, cli_usage("param", "--padding takes 0 .. 64 texels");
            ao.padding = d > 0 ? d : -1;
            forced = true;
        } else if (a[0] == '-' && a[1]) {
            if (forced)
                return *handled = true, cli_usage("param", "unknown option '%s'", a);
            return EXIT_OK;
        } else if (!in) {
            in = a;
        } else {
            return EXIT_OK;
        }
    }
    if (!in || !out)
        return EXIT_OK;
    bool mips = !method || !strcmp(method, "mips");
    if (forced && (!mips || disk_only)) {
        *handled = true;
        return cli_usage("param", "the atlas uses hierarchical MIPS with free boundaries: drop "
                                  "--method, --boundary, --spacing, --steps, --flat");
    }
    if (view && !forced)
        return EXIT_OK; /* parsed by cmd_param; with an atlas it is taken below */
    sk_error err = {0};
    sk_mesh *mesh = NULL;
    double t0 = sk_seconds();
    if (sk_mesh_read(in, NULL, &mesh, &err))
        return EXIT_OK; /* cmd_param names the problem */
    double t_read = sk_seconds() - t0;
    if (!forced) {
        sk_error derr;
        if (sk_param_check_disk(mesh, &derr) == SK_OK || !mips || disk_only) {
            sk_mesh_destroy(&mesh);
            return EXIT_OK; /* a disk, or options only the disk methods have */
        }
    }
    *handled = true;
    if (view) {
        char *end;
        const char *p = view;
        for (int k = 0; k < 3; ++k) {
            ro.view[k] = strtod(p, &end);
            p = end + (k < 2 && *end == ',');
        }
    }
    ao.seed = seed;
    cli_progress bar;
    cli_progress_init(&bar, "param", quiet);
    ao.progress = cli_progress_cb;
    ao.progress_user = &bar;
    atlas_run r;
    memset(&r, 0, sizeof r);
    r.in = in;
    r.faces = mesh->num_faces;
    r.read_seconds = t_read;
    sk_atlas *atlas = NULL;
    sk_mesh *seams = NULL;
    sk_status st = sk_atlas_build(mesh, &ao, &atlas, &r.st, &err);
    cli_progress_done(&bar);
    r.atlas = atlas;
    if (st == SK_OK)
        st = sk_atlas_split_mesh(mesh, atlas, &seams, &err);
    double tw = sk_seconds();
    if (st == SK_OK && split)
        st = sk_mesh_write(out, seams, &wo, &err);
    else if (st == SK_OK &&
             !(st = sk_mesh_set_wedge_uvs(mesh, atlas->num_uvs, atlas->uvs, atlas->corner_uv,
                                          &err)))
        st = sk_mesh_write(out, mesh, &wo, &err);
    r.write_seconds = sk_seconds() - tw;
    char title[256];
    if (st == SK_OK)
        snprintf(title, sizeof title, "%s: atlas, %zu charts, MIPS mean %.4f, utilization %.2f",
                 in, r.st.charts, r.st.mips_mean, r.st.utilization);
    ro.title = title;
    if (st == SK_OK && png)
        st = sk_render_uv(seams, seams->uvs, png, &ro, &err);
    if (st == SK_OK && svg)
        st = sk_render_uv(seams, seams->uvs, svg, &ro, &err);
    if (st == SK_OK && checker) {
        ro.checks = 64;
        st = sk_render_checker(seams, seams->uvs, checker, &ro, &err);
    }
    int rc = st ? cli_fail(st, &err) : EXIT_OK;
    if (rc == EXIT_OK && report)
        rc = cli_write_file(report, write_json, &r);
    if (rc == EXIT_OK) {
        if (json)
            write_json(stdout, &r);
        else if (!quiet)
            printf("%s: %zu faces, atlas of %zu charts, flipped %zu, overlaps %zu, MIPS mean "
                   "%.6f, conformal %.4f, area log %.4f, seams %zu edges (%.2f x sqrt(area)), "
                   "utilization %.3f, %.3f s\n",
                   in, r.faces, r.st.charts, r.st.flipped, r.st.overlaps, r.st.mips_mean,
                   r.st.conformal_mean, r.st.area_log_mean, r.st.seam_edges,
                   r.st.seam_length_rel, r.st.utilization, r.st.total_seconds);
    }
    sk_mesh_destroy(&seams);
    sk_atlas_destroy(&atlas);
    sk_mesh_destroy(&mesh);
    return rc;
}
