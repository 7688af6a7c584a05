/* surfkit subdivide: Loop or midpoint refinement, K times. */
#include "cli.h"

#include <string.h>

static const char about[] =
    "Splits every triangle into four, K times (default 1): Loop subdivision with boundary rules\n"
    "(default) or midpoint refinement (vertices stay, new ones at edge midpoints). Each step\n"
    "multiplies the face count by 4. The input must be a manifold triangle mesh.\n";

static const char examples[] =
    "  surfkit subdivide data/sphere.off -o sphere4.off -n 2\n"
    "  surfkit subdivide data/nefertiti.off -o fine.ply --scheme midpoint\n";

int cmd_subdivide(int argc, char **argv)
{
    const char *out = NULL;
    sk_subdiv_opts so = {0};
    sk_write_opts wo = {0};
    bool quiet = false;
    so.iterations = 1;
    const cli_opt opts[] = {
        OPT_OUTPUT(out, "OUT", "the subdivided mesh (OFF, OBJ, PLY, STL)"),
        OPT_CHOICE("--scheme", so.scheme, "loop|midpoint", "Loop (default) or midpoint refinement"),
        OPT_INT("-n", so.iterations, 1, 12, "K", "subdivision steps (default 1)"),
        OPT_FLAG("--ascii", wo.ascii, "PLY and STL as text (default binary)"),
        OPT_FLAG("-q", quiet, "no progress bar"),
    };
    const cli_spec spec = {"subdivide", "IN -o OUT", about,
                           opts, CLI_COUNT(opts), 1, 1, examples, NULL};
    cli_args args;
    int rc = cli_parse(&spec, argc, argv, &args);
    if (rc)
        return rc == CLI_HELP ? EXIT_OK : rc;
    const char *in = cli_input(&args, 0);
    if (sk_format_from_path(out) == SK_FORMAT_UNKNOWN)
        return cli_usage("subdivide", "cannot tell the output format of '%s'", out);
    cli_progress bar;
    cli_progress_init(&bar, "subdivide", quiet);
    so.progress = cli_progress_cb;
    so.progress_user = &bar;
    sk_error err = {0};
    sk_mesh *mesh = NULL, *fine = NULL;
    sk_status st = sk_mesh_read(in, NULL, &mesh, &err);
    if (st == SK_OK)
        st = sk_mesh_subdivide(mesh, &so, &fine, &err);
    cli_progress_done(&bar);
    cli_name_input(in, st, &err);
    if (st == SK_OK)
        st = sk_mesh_write(out, fine, &wo, &err);
    sk_mesh_destroy(&mesh);
    sk_mesh_destroy(&fine);
    return st ? cli_fail(st, &err) : EXIT_OK;
}
