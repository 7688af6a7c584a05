/* OBJ free-form geometry: every tensor Bezier patch as `cstype bezier`, `deg du dv`,
 * `surf 0 1 0 1 v...` (control points with u varying fastest), `parm u 0 1`, `parm v 0 1`,
 * `end`. Triangles are written as three degree 4 x 4 patches (OBJ has no triangular Bezier). */
#include "export/export_internal.h"

#include <stdlib.h>

sk_status sk_export_obj_freeform(const char *path, const sk_patch *patches, size_t count,
                                 const sk_export_opts *opts, sk_export_stats *stats,
                                 sk_error *err)
{
    sk_patch *t = NULL;
    size_t nt = 0;
    sk_status st = sk_export_tensor_patches(patches, count, opts, &t, &nt, err);
    if (st)
        return st;
    sk__out out = {0};
    sk__out_printf(&out, "# surfkit %s: %zu Bezier patches (OBJ free-form geometry)\n",
                   opts && opts->name ? opts->name : "surface", nt);
    size_t base = 1;
    for (size_t i = 0; i < nt; ++i) {
        const sk_patch *p = &t[i];
        unsigned du = p->degree, dv = p->degree_v, n = (du + 1) * (dv + 1);
        char x[32], y[32], z[32];
        for (unsigned k = 0; k < n; ++k)
            sk__out_printf(&out, "v %s %s %s\n", sk__fmt_real(x, p->cp[3 * k]),
                           sk__fmt_real(y, p->cp[3 * k + 1]), sk__fmt_real(z, p->cp[3 * k + 2]));
        sk__out_printf(&out, "cstype bezier\ndeg %u %u\nsurf 0.0 1.0 0.0 1.0", du, dv);
        for (unsigned k = 0; k < n; ++k)
            sk__out_printf(&out, " %zu", base + k);
        sk__out_str(&out, "\nparm u 0.0 1.0\nparm v 0.0 1.0\nend\n");
        base += n;
    }
    st = sk__out_write_file(&out, path, err);
    if (st == SK_OK && stats) {
        stats->faces = nt;
        stats->edges = stats->vertices = 0;
        stats->bytes = out.len;
    }
    sk__out_free(&out);
    sk__free(t);
    return st;
}
