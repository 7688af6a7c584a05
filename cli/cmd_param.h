/* surfkit param: what cmd_param.c (argv, disks) and cmd_param_atlas.c (atlases) share. */
#ifndef SK_CLI_CMD_PARAM_H
#define SK_CLI_CMD_PARAM_H

#include "cli.h"

/* argv -> options, for both paths */
typedef struct param_args {
    const char *in, *out, *png, *svg, *checker, *report;
    bool quiet, json, atlas, split_seams;
    bool keep_polygons;      /* refuse quads and polygons instead of triangulating them */
    sk_triangulate_stats tri; /* what the input's reading split */
    bool atlas_possible;     /* no option that only the disk methods have */
    sk_parametrize_opts po;  /* disk */
    sk_param_opts linear;    /* --solver: the linear methods' fine tuning (po.linear) */
    sk_atlas_opts ao;        /* atlas */
    sk_write_opts wo;
    sk_render_opts ro;
} param_args;

/* The atlas of mesh (read in read_seconds) written as a asks; the exit code. */
int param_run_atlas(const param_args *a, sk_mesh *mesh, double read_seconds);
/* --png, --svg and --checker of a: uv of mesh, titled. */
sk_status param_pictures(const param_args *a, const sk_mesh *mesh, const double *uv,
                         const char *title, unsigned checks, sk_error *err);
/* The end of both paths: the error of st, or the report (--report), the JSON (--json) or the
 * summary line (unless -q) through the given writers; the exit code. */
int param_finish(const param_args *a, sk_status st, const sk_error *err,
                 void (*json)(FILE *, const void *), void (*summary)(const void *),
                 const void *ctx);

#endif
