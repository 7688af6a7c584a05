/* surfkit convert: reads one mesh format and writes another (format from the extensions). */
#include "cli.h"

#include <string.h>

static const char help[] =
    "usage: surfkit convert IN OUT [--ascii] [--no-normals] [--no-uvs]\n"
    "\n"
    "Converts between OFF, OBJ, PLY and STL; the formats come from the file extensions.\n"
    "PLY and STL are written binary unless --ascii is given. Normals and texture coordinates are\n"
    "kept where the output format can hold them. The input is copied as it is (no validation);\n"
    "use 'surfkit info' for defects.\n";

int cmd_convert(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    sk_write_opts wo = {0};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(help, stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "--ascii")) {
            wo.ascii = true;
        } else if (!strcmp(a, "--no-normals")) {
            wo.no_normals = true;
        } else if (!strcmp(a, "--no-uvs")) {
            wo.no_uvs = true;
        } else if (!strcmp(a, "-q")) {
        } else if (!strcmp(a, "-o")) {
            if (++i >= argc)
                return cli_usage("convert", "-o needs a file name");
            out = argv[i];
        } else if (a[0] == '-' && a[1]) {
            return cli_usage("convert", "unknown option '%s'", a);
        } else if (!in) {
            in = a;
        } else if (!out) {
            out = a;
        } else {
            return cli_usage("convert", "too many file names");
        }
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
