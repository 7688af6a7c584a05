/* surfkit subdivide: Loop or midpoint refinement, K times. */
#include "cli.h"

#include <string.h>

static const char help[] =
    "usage: surfkit subdivide IN -o OUT [--scheme loop|midpoint] [-n K] [--ascii] [-q]\n"
    "\n"
    "Splits every triangle into four, K times (default 1): Loop subdivision with boundary rules\n"
    "(default) or midpoint refinement (vertices stay, new ones at edge midpoints). Each step\n"
    "multiplies the face count by 4. The input must be a manifold triangle mesh.\n";

int cmd_subdivide(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *val;
    sk_subdiv_opts so = {0};
    sk_write_opts wo = {0};
    bool quiet = false;
    so.iterations = 1;
    const cli_path_opt paths[] = {{"-o", &out}};
    int took;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(help, stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "-q")) {
            quiet = true;
        } else if (!strcmp(a, "--ascii")) {
            wo.ascii = true;
        } else if ((took = cli_take_path(argc, argv, &i, "subdivide", paths, 1)) != 0) {
            if (took < 0)
                return EXIT_USAGE;
        } else if (cli_opt_value(argc, argv, &i, "--scheme", &val)) {
            if (val && !strcmp(val, "loop"))
                so.scheme = SK_SUBDIV_LOOP;
            else if (val && !strcmp(val, "midpoint"))
                so.scheme = SK_SUBDIV_MIDPOINT;
            else
                return cli_usage("subdivide", "--scheme takes loop or midpoint");
        } else if (cli_opt_value(argc, argv, &i, "-n", &val)) {
            unsigned long n;
            if (!cli_parse_uint(val, &n) || n < 1 || n > 12)
                return cli_usage("subdivide", "-n takes a whole number from 1 to 12");
            so.iterations = (unsigned)n;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage("subdivide", "unknown option '%s'", a);
        } else if (!in) {
            in = a;
        } else {
            return cli_usage("subdivide", "more than one input file");
        }
    }
    if (!in || !out)
        return cli_usage("subdivide", "needs an input file and -o OUT");
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
    if (st == SK_OK)
        st = sk_mesh_write(out, fine, &wo, &err);
    sk_mesh_destroy(&mesh);
    sk_mesh_destroy(&fine);
    return st ? cli_fail(st, &err) : EXIT_OK;
}
