/* OBJ free-form geometry: every tensor Bezier patch as the B-spline surface with the same control
 * points and clamped knots (one span: du + 1 zeros and du + 1 ones, likewise in v), which is the
 * same surface: `cstype bspline`, `deg du dv`, `surf 0 1 0 1 v...` (control points with u varying
 * fastest), `parm u 0 ... 1`, `parm v 0 ... 1`, `end`. Importers that take only B-splines
 * (Blender's) refuse `cstype bezier`. Triangles are written as three degree 4 x 4 patches (OBJ
 * has no triangular patches). */
#include "export/export_internal.h"

#include <stdlib.h>

sk_status sk_export_obj_freeform(const char *path, const sk_patch_set *patches,
                                 const sk_export_opts *opts, sk_export_stats *stats,
                                 sk_error *err)
{
    sk_patch_set ts = {0};
    sk_status st = sk_patch_set_to_tensor(patches, opts && opts->degenerate_triangles, &ts, err);
    if (st) {
        sk_patch_set_free(&ts);
        return st;
    }
    size_t nt = ts.count;
    sk__out out = {0};
    sk__out_printf(&out, "# surfkit %s: %zu Bezier patches as clamped B-splines (OBJ free-form "
                         "geometry)\n",
                   opts && opts->name ? opts->name : "surface", nt);
    size_t base = 1;
    for (size_t i = 0; i < nt; ++i) {
        const sk_patch *p = &ts.patches[i];
        const double *cp = sk_patch_cp(&ts, i);
        unsigned du = p->degree, dv = p->degree_v, n = (du + 1) * (dv + 1);
        char x[32], y[32], z[32];
        for (unsigned k = 0; k < n; ++k)
            sk__out_printf(&out, "v %s %s %s\n", sk__fmt_real(x, cp[3 * k]),
                           sk__fmt_real(y, cp[3 * k + 1]), sk__fmt_real(z, cp[3 * k + 2]));
        sk__out_printf(&out, "cstype bspline\ndeg %u %u\nsurf 0.0 1.0 0.0 1.0", du, dv);
        for (unsigned k = 0; k < n; ++k)
            sk__out_printf(&out, " %zu", base + k);
        for (int dir = 0; dir < 2; ++dir) { /* clamped knots of one span */
            unsigned d = dir == 0 ? du : dv;
            sk__out_str(&out, dir == 0 ? "\nparm u" : "\nparm v");
            for (unsigned k = 0; k < 2 * (d + 1); ++k)
                sk__out_str(&out, k <= d ? " 0.0" : " 1.0");
        }
        sk__out_str(&out, "\nend\n");
        base += n;
    }
    st = sk__out_write_file(&out, path, err);
    if (st == SK_OK && stats) {
        stats->faces = nt;
        stats->edges = stats->vertices = 0;
        stats->bytes = out.len;
    }
    sk__out_free(&out);
    sk_patch_set_free(&ts);
    return st;
}
