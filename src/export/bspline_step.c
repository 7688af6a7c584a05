/* STEP AP214 (ISO 10303-21) of one B-spline surface (bspline_export.h): the surface as a
 * B_SPLINE_SURFACE_WITH_KNOTS, its four sides as B_SPLINE_CURVE_WITH_KNOTS edges of one
 * ADVANCED_FACE, in an OPEN_SHELL of a SHELL_BASED_SURFACE_MODEL. */
#include "surfkit/bspline_export.h"
#include "export/export_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* "(m1,m2,...)" or "(k1,k2,...)": the multiplicities or the distinct values of a clamped knot
 * vector (STEP lists a surface's u and v multiplicities first, then its u and v knots). */
static void knot_list(sk__out *o, const double *k, size_t m, bool multiplicities)
{
    char buf[32];
    sk__out_char(o, '(');
    for (size_t i = 0; i < m;) {
        size_t j = i;
        while (j < m && k[j] == k[i])
            ++j;
        if (multiplicities)
            sk__out_printf(o, "%s%zu", i ? "," : "", j - i);
        else
            sk__out_printf(o, "%s%s", i ? "," : "", sk__fmt_real(buf, k[i]));
        i = j;
    }
    sk__out_char(o, ')');
}

static void write_point(sk__out *o, size_t id, const double *p)
{
    char x[32], y[32], z[32];
    sk__out_printf(o, "#%zu=CARTESIAN_POINT('',(%s,%s,%s));\n", id, sk__fmt_real(x, p[0]),
                   sk__fmt_real(y, p[1]), sk__fmt_real(z, p[2]));
}

/* The B-spline curve through control points ids[0..n-1] (entity ids) with knots k. */
static void write_curve(sk__out *o, size_t id, int degree, const size_t *ids, size_t n,
                        const double *k)
{
    sk__out_printf(o, "#%zu=B_SPLINE_CURVE_WITH_KNOTS('',%d,(", id, degree);
    for (size_t i = 0; i < n; ++i)
        sk__out_printf(o, "%s#%zu", i ? "," : "", ids[i]);
    sk__out_str(o, "),.UNSPECIFIED.,.F.,.F.,");
    knot_list(o, k, n + (size_t)degree + 1, true);
    sk__out_char(o, ',');
    knot_list(o, k, n + (size_t)degree + 1, false);
    sk__out_str(o, ",.UNSPECIFIED.);\n");
}

static bool finite_surface(const sk_bspline_surface *s)
{
    for (size_t i = 0; i < 3 * s->nu * s->nv; ++i)
        if (!isfinite(s->points[i]))
            return false;
    return true;
}

sk_status sk_export_bspline_step(const char *path, const sk_bspline_surface *s,
                                 const sk_export_opts *opts, sk_export_stats *stats, sk_error *err)
{
    if (!path || !s)
        return sk__fail(err, SK_ERR_ARG, "sk_export_bspline_step: NULL argument");
    if (s->nu <= (size_t)s->degree_u || s->nv <= (size_t)s->degree_v || !finite_surface(s))
        return sk__fail(err, SK_ERR_ARG, "the B-spline surface is malformed (grid %zu x %zu, "
                        "degrees %d x %d, or a coordinate that is not finite)", s->nu, s->nv,
                        s->degree_u, s->degree_v);
    const sk__unit *unit = sk__unit_lookup(opts ? opts->units : NULL);
    if (!unit)
        return sk__fail(err, SK_ERR_ARG, "unknown unit '%s'", opts->units);
    const char *name = opts && opts->name ? opts->name : "surfkit";
    char when[32];
    sk__export_time(opts, when);
    size_t nu = s->nu, nv = s->nv, N = nu * nv;
    size_t *ids = sk__malloc_array(N + (nu > nv ? nu : nv), sizeof *ids), *row = ids ? ids + N : NULL;
    sk__out o = {0};
    sk_status st = SK_OK;
    if (!ids) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    char system[48];
    snprintf(system, sizeof system, "surfkit %s", sk_version());
    sk__step_header(&o, "surfkit B-spline fit of a disk", path, name, when, system, unit);
    size_t next = 30;
    for (size_t j = 0; j < nv; ++j)
        for (size_t i = 0; i < nu; ++i) {
            ids[i + nu * j] = next++;
            write_point(&o, ids[i + nu * j], s->points + 3 * (i + nu * j));
        }
    size_t surf = next++;
    sk__out_printf(&o, "#%zu=B_SPLINE_SURFACE_WITH_KNOTS('',%d,%d,(", surf, s->degree_u,
                   s->degree_v);
    for (size_t i = 0; i < nu; ++i) { /* outer list along u, inner along v */
        sk__out_str(&o, i ? ",(" : "(");
        for (size_t j = 0; j < nv; ++j)
            sk__out_printf(&o, "%s#%zu", j ? "," : "", ids[i + nu * j]);
        sk__out_char(&o, ')');
    }
    sk__out_str(&o, "),.UNSPECIFIED.,.F.,.F.,.F.,");
    size_t mu = nu + (size_t)s->degree_u + 1, mv = nv + (size_t)s->degree_v + 1;
    knot_list(&o, s->knots_u, mu, true);
    sk__out_char(&o, ',');
    knot_list(&o, s->knots_v, mv, true);
    sk__out_char(&o, ',');
    knot_list(&o, s->knots_u, mu, false);
    sk__out_char(&o, ',');
    knot_list(&o, s->knots_v, mv, false);
    sk__out_str(&o, ",.UNSPECIFIED.);\n");

    /* corners (0,0), (1,0), (1,1), (0,1): the corner control points of the clamped grid */
    const size_t corner_cp[4] = {0, nu - 1, N - 1, nu * (nv - 1)};
    size_t vtx[4];
    for (int c = 0; c < 4; ++c) {
        vtx[c] = next++;
        sk__out_printf(&o, "#%zu=VERTEX_POINT('',#%zu);\n", vtx[c], ids[corner_cp[c]]);
    }
    /* sides in their parameter direction: v = 0 and v = 1 along u, u = 0 and u = 1 along v; the
     * loop (0,0) -> (1,0) -> (1,1) -> (0,1) runs counter-clockwise in (u, v), around the normal
     * S_u x S_v, and uses the v = 1 and u = 0 sides backwards */
    size_t oriented[4];
    for (int side = 0; side < 4; ++side) {
        bool along_u = side == 0 || side == 2;
        size_t n = along_u ? nu : nv;
        for (size_t k = 0; k < n; ++k)
            row[k] = side == 0 ? ids[k] : side == 1 ? ids[nu - 1 + nu * k]
                   : side == 2 ? ids[k + nu * (nv - 1)] : ids[nu * k];
        size_t curve = next++, edge = next++;
        write_curve(&o, curve, along_u ? s->degree_u : s->degree_v, row, n,
                    along_u ? s->knots_u : s->knots_v);
        /* start and end vertex of the curve in its own direction */
        size_t from = side == 0 ? vtx[0] : side == 1 ? vtx[1] : side == 2 ? vtx[3] : vtx[0];
        size_t to = side == 0 ? vtx[1] : side == 1 ? vtx[2] : side == 2 ? vtx[2] : vtx[3];
        sk__out_printf(&o, "#%zu=EDGE_CURVE('',#%zu,#%zu,#%zu,.T.);\n", edge, from, to, curve);
        oriented[side] = next++;
        sk__out_printf(&o, "#%zu=ORIENTED_EDGE('',*,*,#%zu,%s);\n", oriented[side], edge,
                       side < 2 ? ".T." : ".F.");
    }
    size_t loop = next++, bound = next++, face = next++, shell = next++, model = next++,
           rep = next++, sdr = next++;
    sk__out_printf(&o, "#%zu=EDGE_LOOP('',(#%zu,#%zu,#%zu,#%zu));\n", loop, oriented[0],
                   oriented[1], oriented[2], oriented[3]);
    sk__out_printf(&o, "#%zu=FACE_OUTER_BOUND('',#%zu,.T.);\n", bound, loop);
    sk__out_printf(&o, "#%zu=ADVANCED_FACE('',(#%zu),#%zu,.T.);\n", face, bound, surf);
    sk__out_printf(&o, "#%zu=OPEN_SHELL('',(#%zu));\n", shell, face);
    sk__out_printf(&o, "#%zu=SHELL_BASED_SURFACE_MODEL('',(#%zu));\n", model, shell);
    sk__out_printf(&o, "#%zu=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#18,#%zu),#14);\n", rep,
                   model);
    sk__out_printf(&o, "#%zu=SHAPE_DEFINITION_REPRESENTATION(#9,#%zu);\n", sdr, rep);
    sk__out_str(&o, "ENDSEC;\nEND-ISO-10303-21;\n");
    st = sk__out_write_file(&o, path, err);
    if (!st && stats) {
        memset(stats, 0, sizeof *stats);
        stats->faces = 1;
        stats->edges = 4;
        stats->vertices = 4;
        stats->bytes = o.len;
    }
done:
    sk__free(ids);
    sk__out_free(&o);
    return st;
}
