/* A program outside the project: built against an installed surfkit through pkg-config. Reads a
 * mesh, prints its topology, and parametrizes it (Floater, circle boundary: CHOLMOD is linked).
 * Output: "VERSION V E F genus N uvmax U". */
#include <surfkit/surfkit.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    sk_error err;
    sk_mesh *mesh = NULL;
    double *uv = NULL;
    int rc = 1;
    if (argc != 2) {
        fprintf(stderr, "usage: consumer MESH\n");
        return 2;
    }
    if (sk_mesh_read(argv[1], NULL, &mesh, &err) != SK_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    sk_topology top;
    if (sk_mesh_topology(mesh, &top, NULL, &err) != SK_OK)
        goto done;
    uv = calloc(2 * mesh->num_vertices, sizeof *uv);
    if (!uv)
        goto done;
    sk_param_opts opts = {0};
    opts.method = SK_PARAM_FLOATER;
    if (sk_param_linear(mesh, &opts, uv, NULL, &err) != SK_OK)
        goto done;
    double uvmax = 0.0;
    for (size_t i = 0; i < 2 * mesh->num_vertices; ++i)
        uvmax = fmax(uvmax, fabs(uv[i]));
    printf("%s V %zu E %zu F %zu genus %ld uvmax %.6f\n", sk_version(), top.vertices, top.edges,
           top.faces, top.genus, uvmax);
    rc = 0;
done:
    if (rc)
        fprintf(stderr, "%s\n", err.message);
    free(uv);
    sk_mesh_destroy(&mesh);
    return rc;
}
