/* surfkit view: the interactive HTML viewer of a mesh, its uv and its smooth surface. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Writes one self-contained HTML page (three.js inlined: it opens without a network) showing\n"
    "IN with its edges; with uv (IN's own vt / s t, or --uv, a parametrization of the same mesh\n"
    "as `surfkit param` writes it) a checkerboard and the conformal distortion sigma1/sigma2;\n"
    "with --smooth the VC1 surface of IN (as `surfkit smooth` builds it) shaded with its exact\n"
    "normals, zebra stripes (reflection lines: a kink in the stripes is a kink in the surface),\n"
    "its distance to IN (blue 0 ... red at --deviation-scale, default the largest) and the patch\n"
    "boundaries. Drag to orbit, right drag to pan, wheel to zoom, r to reset.\n";

static const char examples[] =
    "  surfkit view data/sphere.off --smooth -o sphere.html\n"
    "  surfkit param data/nefertiti.off -o uv.obj -q && surfkit view uv.obj -o uv.html\n";

/* The uv of `uvpath`, which must be a parametrization of mesh (same vertex count and
 * positions). */
static int read_uv(const char *uvpath, const char *in, const sk_mesh *mesh, sk_mesh **out)
{
    sk_error err = {0};
    sk_status st = sk_mesh_read(uvpath, NULL, out, &err);
    if (st)
        return cli_fail(st, &err);
    if (!(*out)->uvs) {
        cli_error("%s: has no uv", uvpath);
        return EXIT_BAD_INPUT;
    }
    if ((*out)->num_vertices != mesh->num_vertices ||
        memcmp((*out)->positions, mesh->positions, 3 * mesh->num_vertices * sizeof(double))) {
        cli_error("%s: is not a parametrization of %s (other vertices)", uvpath, in);
        return EXIT_BAD_INPUT;
    }
    return EXIT_OK;
}

int cmd_view(int argc, char **argv)
{
    const char *out = NULL, *uvpath = NULL;
    bool smooth = false, quiet = false;
    sk_view_opts vo = {0};
    const cli_opt opts[] = {
        OPT_OUTPUT(out, "VIEW.html", "the page"),
        OPT_FILE("--uv", uvpath, "UV.obj", "a parametrization of IN (OBJ vt or PLY s t)"),
        OPT_FLAG("--smooth", smooth, "add the VC1 surface, its zebra stripes and deviation"),
        OPT_INT("--tess", vo.tess, 1, 64, "N", "grid of N x N per patch of the smooth surface"),
        OPT_DOUBLE("--deviation-scale", vo.deviation_scale, 0, 0, CLI_LO_OPEN, "D",
                   "distance shown red (default the largest)"),
        OPT_FLAG("-q", quiet, "no progress bar"),
    };
    const cli_spec spec = {"view", "IN -o VIEW.html", about,
                           opts, CLI_COUNT(opts), 1, 1, examples, NULL};
    cli_args args;
    int rc = cli_parse(&spec, argc, argv, &args);
    if (rc)
        return rc == CLI_HELP ? EXIT_OK : rc;
    const char *in = cli_input(&args, 0);
    size_t n = strlen(out);
    if (n < 5 || strcmp(out + n - 5, ".html"))
        return cli_usage("view", "-o must name an .html file");
    if (!sk_view_available()) {
        cli_error("view: this surfkit was built without the viewer (three.js was not found; "
                  "scripts/setup.sh fetches it)");
        return EXIT_INTERNAL;
    }
    sk_error err = {0};
    sk_mesh *mesh = NULL, *uvmesh = NULL;
    sk_smooth *s = NULL;
    sk_status st = sk_mesh_read(in, NULL, &mesh, &err);
    if (st) {
        rc = cli_fail(st, &err);
        goto done;
    }
    if (uvpath && (rc = read_uv(uvpath, in, mesh, &uvmesh)) != EXIT_OK)
        goto done;
    char info[160] = "";
    if (smooth) {
        cli_progress bar;
        cli_progress_init(&bar, "smooth", quiet);
        sk_smooth_opts so = {.progress = cli_progress_cb, .progress_user = &bar};
        st = sk_smooth_build(mesh, &so, &s, &err);
        cli_progress_done(&bar);
        cli_name_input(in, st, &err);
        if (st) {
            rc = cli_fail(st, &err);
            goto done;
        }
        snprintf(info, sizeof info, "%zu faces, %zu VC1 patches (%zu deleted edges)",
                 mesh->num_faces, s->surface.count, s->num_deleted);
    } else {
        snprintf(info, sizeof info, "%zu vertices, %zu faces", mesh->num_vertices, mesh->num_faces);
    }
    vo.title = in;
    vo.info = info;
    const double *uv = uvmesh ? uvmesh->uvs : mesh->uvs;
    st = sk_view_write(mesh, uv, s, &vo, out, &err);
    if (st)
        rc = cli_fail(st, &err);
    else
        printf("view: wrote %s (%s%s%s)\n", out, uv ? "uv, " : "", s ? "smooth surface, " : "",
               info);
done:
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&uvmesh);
    sk_mesh_destroy(&mesh);
    return rc;
}
