/* Half-edge mesh convenience wrappers: file <-> soup <-> mesh. Kept apart from io.c so that
 * programs using only the soup functions do not need the mesh builder. */
#include "io/lexer.h"

sk_status sk_mesh_read(const char *path, const sk_read_opts *opts, sk_mesh **out, sk_error *err)
{
    if (!out)
        return sk__fail(err, SK_ERR_ARG, "no output mesh");
    *out = NULL;
    sk_soup *soup = NULL;
    sk_status st = sk_soup_read(path, opts, &soup, err);
    if (st)
        return st;
    st = sk_mesh_from_soup(soup, out, err);
    if (st && err) {
        /* name the file: "NAME: what is wrong" */
        char msg[SK_ERROR_MESSAGE_SIZE];
        memcpy(msg, err->message, sizeof msg);
        sk__fail(err, st, "%s: %s", sk__basename(path), msg);
    }
    sk_soup_destroy(&soup);
    return st;
}

sk_status sk_mesh_write(const char *path, const sk_mesh *mesh, const sk_write_opts *opts,
                        sk_error *err)
{
    if (!mesh)
        return sk__fail(err, SK_ERR_ARG, "no mesh");
    sk_soup *soup = NULL;
    sk_status st = sk_mesh_to_soup(mesh, &soup, err);
    if (st)
        return st;
    st = sk_soup_write(path, soup, opts, err);
    sk_soup_destroy(&soup);
    return st;
}
