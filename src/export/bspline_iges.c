/* IGES 5.3 of one B-spline surface (bspline_export.h): a single independent entity 128
 * (rational B-spline surface, polynomial: PROP3 = 1, all weights 1) in fixed 80-column records
 * of the Start, Global, Directory Entry, Parameter Data and Terminate sections. */
#include "surfkit/bspline_export.h"
#include "export/export_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sk_status sk_export_bspline_iges(const char *path, const sk_bspline_surface *s,
                                 const sk_export_opts *opts, sk_export_stats *stats, sk_error *err)
{
    if (!path || !s)
        return sk__fail(err, SK_ERR_ARG, "sk_export_bspline_iges: NULL argument");
    double maxc = 0;
    for (size_t i = 0; i < 3 * s->nu * s->nv; ++i) {
        if (!isfinite(s->points[i]))
            return sk__fail(err, SK_ERR_ARG, "the B-spline surface has a coordinate that is not "
                            "finite");
        maxc = fmax(maxc, fabs(s->points[i]));
    }
    if (s->nu <= (size_t)s->degree_u || s->nv <= (size_t)s->degree_v)
        return sk__fail(err, SK_ERR_ARG, "the B-spline surface is malformed (grid %zu x %zu, "
                        "degrees %d x %d)", s->nu, s->nv, s->degree_u, s->degree_v);
    const sk__unit *unit = sk__unit_lookup(opts ? opts->units : NULL);
    if (!unit)
        return sk__fail(err, SK_ERR_ARG, "unknown unit '%s'", opts->units);
    const char *name = opts && opts->name ? opts->name : "surfkit";
    char when[32], stamp[32], version[48];
    sk__export_time(opts, when);
    snprintf(stamp, sizeof stamp, "%.4s%.2s%.2s.%.2s%.2s%.2s", when, when + 5, when + 8, when + 11,
             when + 14, when + 17); /* IGES dates: YYYYMMDD.HHNNSS */
    snprintf(version, sizeof version, "surfkit %s", sk_version());

    sk__out o = {0}, d = {0}, pd = {0};
    sk__iges_record(&o, "surfkit: B-spline fit of a disk as IGES entity 128", 'S', 1);
    size_t g_seq = 0, p_seq = 0;
    sk__iges_packer g = {.b = &o, .section = 'G', .seq = &g_seq, .width = 72,
                         .zero_before_point = true};
    /* minimum resolution as the patch writer's */
    sk__iges_global(&g, name, path, version, unit, stamp, fmax(1e-7, 1e-9 * maxc), maxc);

    /* entity 128, DE pointer 1 */
    sk__iges_packer p = {.b = &pd, .section = 'P', .seq = &p_seq, .width = 64, .de = 1,
                         .zero_before_point = true};
    sk__iges_pack_int(&p, 128);
    sk__iges_pack_int(&p, (long)s->nu - 1); /* K1: upper index of the u sum */
    sk__iges_pack_int(&p, (long)s->nv - 1); /* K2 */
    sk__iges_pack_int(&p, s->degree_u);     /* M1 */
    sk__iges_pack_int(&p, s->degree_v);     /* M2 */
    sk__iges_pack_int(&p, 0);               /* PROP1: not closed in u */
    sk__iges_pack_int(&p, 0);               /* PROP2: not closed in v */
    sk__iges_pack_int(&p, 1);               /* PROP3: polynomial */
    sk__iges_pack_int(&p, 0);               /* PROP4: not periodic in u */
    sk__iges_pack_int(&p, 0);               /* PROP5: not periodic in v */
    for (size_t k = 0; k < s->nu + (size_t)s->degree_u + 1; ++k)
        sk__iges_pack_real(&p, s->knots_u[k]);
    for (size_t k = 0; k < s->nv + (size_t)s->degree_v + 1; ++k)
        sk__iges_pack_real(&p, s->knots_v[k]);
    for (size_t k = 0; k < s->nu * s->nv; ++k)
        sk__iges_pack_real(&p, 1.0);
    for (size_t k = 0; k < 3 * s->nu * s->nv; ++k) /* point (i, j) at i + nu j: u fastest */
        sk__iges_pack_real(&p, s->points[k]);
    sk__iges_pack_real(&p, 0.0);
    sk__iges_pack_real(&p, 1.0);
    sk__iges_pack_real(&p, 0.0);
    sk__iges_pack_real(&p, 1.0);
    sk__iges_pack_end(&p);
    char l1[96], l2[96];
    snprintf(l1, sizeof l1, "%8d%8d%8d%8d%8d%8d%8d%8d%8s", 128, 1, 0, 0, 0, 0, 0, 0, "00000000");
    snprintf(l2, sizeof l2, "%8d%8d%8d%8zu%8d%8s%8s%8s%8d", 128, 0, 0, p_seq, 0, "", "", "", 0);
    sk__iges_record(&d, l1, 'D', 1);
    sk__iges_record(&d, l2, 'D', 2);

    sk__out_bytes(&o, d.buf ? d.buf : "", d.len);
    sk__out_bytes(&o, pd.buf ? pd.buf : "", pd.len);
    char term[64];
    snprintf(term, sizeof term, "S%07dG%07zuD%07dP%07zu", 1, g_seq, 2, p_seq);
    sk__iges_record(&o, term, 'T', 1);
    if (d.failed || pd.failed)
        o.failed = SK_ERR_NOMEM;
    sk_status st = sk__out_write_file(&o, path, err);
    if (!st && stats) {
        memset(stats, 0, sizeof *stats);
        stats->faces = 1;
        stats->bytes = o.len;
    }
    sk__out_free(&o);
    sk__out_free(&d);
    sk__out_free(&pd);
    return st;
}
