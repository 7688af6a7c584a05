/* surfkit convert: reads one mesh format and writes another (format from the extensions). */
#include "cli.h"

#include <string.h>

static const char about[] =
    "Converts between OFF, OBJ, PLY and STL; the formats come from the file extensions.\n"
    "PLY and STL are written binary unless --ascii is given. Normals and texture coordinates are\n"
    "kept where the output format can hold them. The input is copied as it is (no validation);\n"
    "use 'surfkit info' for defects.\n";

static const char examples[] =
    "  surfkit convert data/nefertiti.off nefertiti.ply\n"
    "  surfkit convert data/sphere.off sphere.stl --ascii\n";

int cmd_convert(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    sk_write_opts wo = {0};
    bool quiet = false;
    const cli_opt opts[] = {
        OPT_FILE("-o", out, "OUT", "the output file (or give it as the second file name)"),
        OPT_FLAG("--ascii", wo.ascii, "PLY and STL as text (default binary)"),
        OPT_FLAG("--no-normals", wo.no_normals, "do not write the normals"),
        OPT_FLAG("--no-uvs", wo.no_uvs, "do not write the texture coordinates"),
        OPT_FLAG("-q", quiet, "quiet (convert prints nothing anyway)"),
    };
    const cli_spec spec = {"convert", "IN OUT", about, opts, CLI_COUNT(opts), 1, 2, examples, NULL};
    cli_args args;
    int rc = cli_parse(&spec, argc, argv, &args);
    if (rc)
        return rc == CLI_HELP ? EXIT_OK : rc;
    in = cli_input(&args, 0);
    if (args.num_inputs > 1) {
        if (out)
            return cli_usage("convert", "too many file names");
        out = args.inputs[1];
    }
    if (!in || !out)
        return cli_usage("convert", "needs an input and an output file");
    if (sk_format_from_path(out) == SK_FORMAT_UNKNOWN)
        return cli_usage("convert", "cannot tell the output format of '%s' (use .off .obj .ply .stl)",
                         out);
    sk_error err = {0};
    sk_soup *soup = NULL;
    sk_status st = sk_soup_read(in, NULL, &soup, &err);
    if (st == SK_OK)
        st = sk_soup_write(out, soup, &wo, &err);
    sk_soup_destroy(&soup);
    return st ? cli_fail(st, &err) : EXIT_OK;
}
