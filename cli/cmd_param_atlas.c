/* surfkit param on a mesh that is not one disk (or with --atlas): automatic charts, per-chart
 * hierarchical MIPS, packing (sk_atlas_build), per-corner uvs out, report and pictures.
 * cmd_param parses the options and reads the mesh; param_run_atlas takes it from there when the
 * atlas is wanted. */
#include "cmd_param.h"

#include <stdlib.h>
#include <string.h>

typedef struct atlas_run {
    const char *in;
    sk_triangulate_stats tri;
    const sk_atlas *atlas;
    sk_atlas_stats st;
    size_t faces;
    unsigned charts_target; /* --charts N, 0 = none */
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
    json_triangulated(&j, &r->tri);
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
    json_kuint(&j, "predicted", s->splits_predicted);
    json_obj_close(&j);
    json_kuint(&j, "lscm_charts", s->lscm_charts);
    json_kuint(&j, "crease_regions", s->crease_regions);
    json_kuint(&j, "area_refinements", s->area_refinements);
    json_kuint(&j, "area_bounded", s->area_bounded);
    json_kuint(&j, "slits", s->slits);
    json_kuint(&j, "merges", s->merges);
    json_kuint(&j, "pack_cuts", s->pack_cuts);
    if (r->charts_target) {
        json_kuint(&j, "charts_target", r->charts_target);
        json_kbool(&j, "charts_target_met", s->charts <= r->charts_target);
    }
    const struct {
        const char *key;
        double seconds;
    } stages[] = {{"read", r->read_seconds},       {"charts", s->charts_seconds},
                  {"parametrize", s->param_seconds}, {"pack", s->pack_seconds},
                  {"check", s->check_seconds},       {"write", r->write_seconds}};
    json_knum(&j, "seconds", s->total_seconds); /* the atlas, as "seconds" of the disk path */
    json_key(&j, "stage_seconds");
    json_obj_open(&j);
    for (size_t k = 0; k < CLI_COUNT(stages); ++k)
        json_knum(&j, stages[k].key, stages[k].seconds);
    json_obj_close(&j);
    json_obj_close(&j);
    json_end(&j);
}

static void print_summary(const void *ctx)
{
    const atlas_run *r = ctx;
    printf("%s: %zu faces, atlas of %zu charts, flipped %zu, overlaps %zu, MIPS mean %.6f, "
           "conformal %.4f, area log %.4f, seams %zu edges (%.2f x sqrt(area)), utilization "
           "%.3f, %.3f s\n",
           r->in, r->faces, r->st.charts, r->st.flipped, r->st.overlaps, r->st.mips_mean,
           r->st.conformal_mean, r->st.area_log_mean, r->st.seam_edges, r->st.seam_length_rel,
           r->st.utilization, r->st.total_seconds);
    if (r->charts_target && r->st.charts > r->charts_target)
        printf("%s: --charts %u cannot be met within the bounds: %zu charts after %zu merges\n",
               r->in, r->charts_target, r->st.charts, r->st.merges);
}

/* The output: one vertex per uv (--split-seams, the seams mesh), else per-corner uvs on mesh. */
static sk_status write_atlas(const param_args *a, sk_mesh *mesh, const sk_atlas *atlas,
                             const sk_mesh *seams, sk_error *err)
{
    if (a->split_seams)
        return sk_mesh_write(a->out, seams, &a->wo, err);
    sk_status st = sk_mesh_set_wedge_uvs(mesh, atlas->num_uvs, atlas->uvs, atlas->corner_uv, err);
    return st ? st : sk_mesh_write(a->out, mesh, &a->wo, err);
}

int param_run_atlas(const param_args *a, sk_mesh *mesh, double read_seconds)
{
    sk_atlas_opts ao = a->ao;
    cli_progress bar;
    cli_progress_init(&bar, "param", a->quiet);
    ao.progress = cli_progress_cb;
    ao.progress_user = &bar;
    atlas_run r;
    memset(&r, 0, sizeof r);
    r.in = a->in;
    r.tri = a->tri;
    r.faces = mesh->num_faces;
    r.charts_target = ao.max_charts;
    r.read_seconds = read_seconds;
    sk_error err = {0};
    sk_atlas *atlas = NULL;
    sk_mesh *seams = NULL;
    sk_status st = sk_atlas_build(mesh, &ao, &atlas, &r.st, &err);
    cli_progress_done(&bar);
    cli_name_input(a->in, st, &err);
    r.atlas = atlas;
    if (st == SK_OK)
        st = sk_atlas_split_mesh(mesh, atlas, &seams, &err);
    double tw = sk_seconds();
    if (st == SK_OK)
        st = write_atlas(a, mesh, atlas, seams, &err);
    r.write_seconds = sk_seconds() - tw;
    if (st == SK_OK) {
        char title[256];
        snprintf(title, sizeof title, "%s: atlas, %zu charts, MIPS mean %.4f, utilization %.2f",
                 a->in, r.st.charts, r.st.mips_mean, r.st.utilization);
        st = param_pictures(a, seams, seams->uvs, title, 64, &err);
    }
    int rc = param_finish(a, st, &err, write_json, print_summary, &r);
    sk_mesh_destroy(&seams);
    sk_atlas_destroy(&atlas);
    return rc;
}
