/* The parametrize pipeline: options resolved and checked per method, the square boundary's
 * corners and edge splits, one of the three drivers (linear / LSCM, hierarchical MIPS, flat
 * MIPS), the unit-square normalization, the flip count. */
#include "surfkit/parametrize.h"
#include "core/internal.h"

#include <string.h>

static bool is_fixed_method(sk_param_method m)
{
    return m == SK_PARAM_TUTTE || m == SK_PARAM_FLOATER || m == SK_PARAM_MEAN_VALUE ||
           m == SK_PARAM_HARMONIC;
}

/* The method and boundary shape that run, or SK_ERR_ARG for an illegal combination. */
static sk_status resolve(const sk_parametrize_opts *o, sk_param_method *method,
                         sk_boundary_shape *shape, sk_error *err)
{
    sk_param_method m = o->method == SK_PARAM_DEFAULT ? SK_PARAM_FLOATER : o->method;
    sk_boundary_shape b = o->boundary.shape;
    if (!is_fixed_method(m) && m != SK_PARAM_LSCM && m != SK_PARAM_MIPS)
        return sk__fail(err, SK_ERR_ARG, "unknown parametrization method %d", (int)o->method);
    if ((unsigned)b > SK_BOUNDARY_GIVEN)
        return sk__fail(err, SK_ERR_ARG, "unknown boundary shape %d", (int)b);
    if (b == SK_BOUNDARY_DEFAULT)
        b = is_fixed_method(m) ? SK_BOUNDARY_CIRCLE : SK_BOUNDARY_FREE;
    if (m != SK_PARAM_MIPS && (o->flat || o->max_steps))
        return sk__fail(err, SK_ERR_ARG, "flat and a step budget go with the MIPS method, not %s",
                        sk_param_method_name(m));
    if (m == SK_PARAM_LSCM && b != SK_BOUNDARY_FREE)
        return sk__fail(err, SK_ERR_ARG, "lscm has a free boundary, not %s",
                        sk_boundary_shape_name(b));
    if (is_fixed_method(m) && b == SK_BOUNDARY_FREE)
        return sk__fail(err, SK_ERR_ARG, "%s has a fixed boundary: a free boundary needs lscm or "
                        "mips", sk_param_method_name(m));
    if (m == SK_PARAM_MIPS && b == SK_BOUNDARY_GIVEN)
        return sk__fail(err, SK_ERR_ARG, "mips maps the boundary itself: circle, square or free, "
                        "not given");
    if (m == SK_PARAM_MIPS && o->linear)
        return sk__fail(err, SK_ERR_ARG, "the linear solver options go with the linear methods, "
                        "not mips");
    if (m != SK_PARAM_MIPS && o->hierarchical)
        return sk__fail(err, SK_ERR_ARG, "the hierarchical MIPS options go with the MIPS method, "
                        "not %s", sk_param_method_name(m));
    *method = m;
    *shape = b;
    return SK_OK;
}

sk_status sk_parametrize_check(const sk_parametrize_opts *opts, sk_error *err)
{
    sk_parametrize_opts o = {0};
    if (opts)
        o = *opts;
    sk_param_method m;
    sk_boundary_shape b;
    return resolve(&o, &m, &b, err);
}

/* Triangles whose uv are clockwise or collinear (exact test). */
static size_t count_flipped(const sk_mesh *m, const double *uv)
{
    size_t flipped = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h = m->f_halfedge[f], hb = m->h_next[h], hc = m->h_next[hb];
        if (sk_orient2d(uv + 2 * (size_t)sk_from(m, h), uv + 2 * (size_t)sk_from(m, hb),
                        uv + 2 * (size_t)sk_from(m, hc)) <= 0)
            flipped++;
    }
    return flipped;
}

/* The square boundary: the corners (given, or at the four sharpest boundary turns) and the
 * dividing edges split; a split mesh goes to s->split_mesh, its uv zeroed. A mesh that is not a
 * disk is left to the method, which says what it is. */
static sk_status square_step(const sk_mesh *mesh, sk_boundary_opts *bo, sk_parametrize_stats *s,
                             sk_error *err)
{
    sk_status st = sk_param_check_disk(mesh, err);
    if (st == SK_ERR_TOPOLOGY)
        return SK_OK;
    if (st)
        return st;
    if (!bo->has_corners && (st = sk_param_square_corners(mesh, bo->corners, err)))
        return st;
    bo->has_corners = true;
    sk_mesh *split = NULL;
    if ((st = sk_param_split_side_edges(mesh, bo->corners, &split, &s->split_edges, err)))
        return st;
    if (s->split_edges && (st = sk_mesh_add_uvs(split, err)) == SK_OK) {
        memset(split->uvs, 0, 2 * split->num_vertices * sizeof *split->uvs);
        s->split_mesh = split;
        split = NULL;
    }
    sk_mesh_destroy(&split);
    return st;
}

static sk_status run_method(const sk_mesh *mesh, const sk_parametrize_opts *o,
                            const sk_boundary_opts *bo, double *uv, sk_parametrize_stats *s,
                            sk_error *err)
{
    uint64_t seed = o->seed ? o->seed : 1;
    if (s->method != SK_PARAM_MIPS) {
        sk_param_opts po = {0};
        if (o->linear)
            po = *o->linear;
        po.method = s->method;
        po.boundary = *bo;
        po.progress = o->progress;
        po.progress_user = o->progress_user;
        return sk_param_linear(mesh, &po, uv, &s->linear, err);
    }
    if (s->hierarchical) {
        sk_hparam_opts ho = {0};
        if (o->hierarchical)
            ho = *o->hierarchical;
        ho.boundary = *bo;
        ho.max_steps = o->max_steps;
        ho.seed = seed;
        ho.progress = o->progress;
        ho.progress_user = o->progress_user;
        return sk_param_hierarchical(mesh, &ho, uv, &s->hparam, err);
    }
    sk_mips_flat_opts fo = {0};
    fo.boundary = *bo;
    fo.max_steps = o->max_steps;
    fo.seed = seed;
    fo.progress = o->progress;
    fo.progress_user = o->progress_user;
    return sk_param_mips_flat(mesh, &fo, uv, &s->mips, err);
}

sk_status sk_parametrize(const sk_mesh *mesh, const sk_parametrize_opts *opts, double *uv,
                         sk_parametrize_stats *stats, sk_error *err)
{
    sk_parametrize_opts o = {0};
    if (opts)
        o = *opts;
    double t0 = sk_seconds();
    sk_parametrize_stats s;
    memset(&s, 0, sizeof s);
    sk_boundary_opts bo = o.boundary;
    sk_status st = resolve(&o, &s.method, &bo.shape, err);
    if (st)
        goto done;
    s.boundary = bo.shape;
    s.hierarchical = s.method == SK_PARAM_MIPS && !o.flat;
    s.name = s.method != SK_PARAM_MIPS ? sk_param_method_name(s.method)
             : s.hierarchical          ? "mips-hierarchical"
                                       : "mips-flat";
    if (bo.shape == SK_BOUNDARY_SQUARE && (st = square_step(mesh, &bo, &s, err)))
        goto done;
    const sk_mesh *m = s.split_mesh ? s.split_mesh : mesh; /* the mesh parametrized */
    double *muv = s.split_mesh ? s.split_mesh->uvs : uv;
    st = run_method(m, &o, &bo, muv, &s, err);
    if (st == SK_WARN_FLIPS)
        st = SK_OK; /* counted below, with the pipeline's message */
    if (st == SK_OK && !o.raw)
        st = sk_param_normalize(m, muv, err);
    if (st == SK_OK && s.split_mesh)
        memcpy(uv, muv, 2 * mesh->num_vertices * sizeof *uv); /* vertices keep their ids */
    if (st == SK_OK) {
        s.flipped = count_flipped(m, muv);
        if (s.flipped)
            st = sk__fail(err, SK_WARN_FLIPS, "%zu of %zu triangles flipped (%s)", s.flipped,
                          m->num_faces - m->num_deleted_faces, s.name);
    }
done:
    s.seconds = sk_seconds() - t0;
    if (stats)
        *stats = s;
    else
        sk_parametrize_stats_release(&s);
    return st;
}

void sk_parametrize_stats_release(sk_parametrize_stats *stats)
{
    if (!stats)
        return;
    sk_hparam_stats_release(&stats->hparam);
    sk_mesh_destroy(&stats->split_mesh);
    memset(stats, 0, sizeof *stats);
}
