/* Every call the Python module makes into libsurfkit (see calls.h). */
#include "calls.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static sk_status fail(sk_error *err, sk_status st, const char *msg)
{
    if (err) {
        err->status = st;
        snprintf(err->message, sizeof err->message, "%s", msg);
    }
    return st;
}

void skpy_mesh_free(skpy_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->uvs);
    free(m->offsets);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

/* borrowed arrays -> sk_mesh (the soup only points at them) */
static sk_status to_mesh(const skpy_mesh *m, sk_mesh **out, sk_error *err)
{
    sk_soup s;
    memset(&s, 0, sizeof s);
    s.num_vertices = m->nv;
    s.num_faces = m->nf;
    s.positions = m->positions;
    s.normals = m->normals;
    s.uvs = m->uvs;
    s.face_offsets = m->offsets;
    s.face_indices = m->indices;
    return sk_mesh_from_soup(&s, out, err);
}

static void *dup(const void *p, size_t bytes)
{
    void *q = p ? malloc(bytes ? bytes : 1) : NULL;
    if (q)
        memcpy(q, p, bytes);
    return q;
}

sk_status skpy_read(const char *path, skpy_mesh *out, sk_error *err)
{
    memset(out, 0, sizeof *out);
    sk_mesh *mesh = NULL;
    sk_soup *soup = NULL;
    sk_status st = sk_mesh_read(path, NULL, &mesh, err);
    if (st == SK_OK)
        st = sk_mesh_to_soup(mesh, &soup, err);
    if (st == SK_OK) {
        size_t nv = soup->num_vertices, nf = soup->num_faces;
        out->nv = nv;
        out->nf = nf;
        out->positions = dup(soup->positions, 3 * nv * sizeof(double));
        out->normals = dup(soup->normals, 3 * nv * sizeof(double));
        out->uvs = dup(soup->uvs, 2 * nv * sizeof(double));
        out->offsets = dup(soup->face_offsets, (nf + 1) * sizeof(uint32_t));
        out->indices = dup(soup->face_indices, soup->face_offsets[nf] * sizeof(uint32_t));
        if (!out->positions || !out->offsets || !out->indices || (soup->normals && !out->normals) ||
            (soup->uvs && !out->uvs)) {
            skpy_mesh_free(out);
            st = fail(err, SK_ERR_NOMEM, "out of memory");
        }
    }
    sk_soup_destroy(&soup);
    sk_mesh_destroy(&mesh);
    return st;
}

sk_status skpy_write(const char *path, const skpy_mesh *m, sk_error *err)
{
    sk_mesh *mesh = NULL;
    sk_status st = to_mesh(m, &mesh, err);
    if (st == SK_OK)
        st = sk_mesh_write(path, mesh, NULL, err);
    sk_mesh_destroy(&mesh);
    return st;
}

sk_status skpy_info_compute(const skpy_mesh *m, skpy_info *info, sk_error *err)
{
    memset(info, 0, sizeof *info);
    sk_mesh *mesh = NULL;
    sk_status st = to_mesh(m, &mesh, err);
    if (st == SK_OK)
        st = sk_mesh_topology(mesh, &info->top, NULL, err);
    if (st == SK_OK) {
        for (uint32_t f = 0; f < mesh->num_faces; ++f) {
            size_t n = sk_mesh_face_size(mesh, f);
            info->triangles += n == 3;
            info->quads += n == 4;
            info->larger += n > 4;
        }
        for (uint32_t e = 0; e < sk_num_edges(mesh); ++e)
            info->boundary_edges += sk_is_boundary_e(mesh, e);
    }
    sk_mesh_destroy(&mesh);
    return st;
}

sk_status skpy_parametrize(const skpy_mesh *m, const skpy_param_args *a, double *uv,
                           sk_param_metrics *metrics, sk_error *err)
{
    const char *method = a->method ? a->method : "floater";
    sk_parametrize_opts po;
    memset(&po, 0, sizeof po);
    if (!strcmp(method, "mips") || !strcmp(method, "mips-flat")) {
        po.method = SK_PARAM_MIPS;
        po.flat = method[4] != 0;
    } else if (!sk_param_method_parse(method, &po.method)) {
        return fail(err, SK_ERR_ARG, "unknown method (tutte, floater, mvc, harmonic, lscm, mips, "
                                     "mips-flat)");
    }
    if (a->boundary && !sk_boundary_shape_parse(a->boundary, &po.boundary.shape))
        return fail(err, SK_ERR_ARG, "boundary must be circle, square or free");
    po.max_steps = a->steps;
    po.seed = a->seed;
    sk_status st = sk_parametrize_check(&po, err);
    sk_mesh *mesh = NULL;
    if (st == SK_OK)
        st = to_mesh(m, &mesh, err);
    if (st == SK_OK) {
        sk_parametrize_stats ps;
        st = sk_parametrize(mesh, &po, uv, &ps, err);
        sk_parametrize_stats_release(&ps);
        if (st == SK_WARN_FLIPS) /* the uv is complete; the metrics count the flips */
            st = SK_OK;
    }
    if (st == SK_OK && metrics)
        st = sk_param_metrics_compute(mesh, uv, metrics, err);
    sk_mesh_destroy(&mesh);
    return st;
}

void skpy_surface_free(skpy_surface *s)
{
    free(s->points);
    free(s->kind);
    free(s->degree);
    free(s->first);
    free(s->corners);
    free(s->deleted);
    free(s->problems);
    memset(s, 0, sizeof *s);
}

sk_status skpy_smooth(const skpy_mesh *m, const skpy_smooth_args *a, skpy_surface *out,
                      sk_error *err)
{
    memset(out, 0, sizeof *out);
    sk_smooth_opts so;
    memset(&so, 0, sizeof so);
    if (!a->scheme || !strcmp(a->scheme, "vc1"))
        so.scheme = SK_SMOOTH_VC1;
    else if (!strcmp(a->scheme, "pn"))
        so.scheme = SK_SMOOTH_PN;
    else
        return fail(err, SK_ERR_ARG, "scheme must be vc1 or pn");
    so.estimate_normals = a->estimate_normals != 0;
    so.allow_split = a->allow_split != 0;

    sk_mesh *mesh = NULL;
    sk_smooth *s = NULL;
    sk_status st = to_mesh(m, &mesh, err);
    if (st == SK_OK)
        st = sk_smooth_build(mesh, &so, &s, err);
    if (st == SK_OK)
        st = sk_smooth_continuity(s, NULL, &out->report, err);
    if (st == SK_OK) {
        const sk_patch_set *set = &s->surface;
        size_t np = set->count;
        out->num_patches = np;
        out->num_points = set->num_points;
        out->points = dup(set->points, 3 * set->num_points * sizeof(double));
        out->kind = malloc(np ? np : 1);
        out->degree = malloc(np ? np : 1);
        out->first = malloc((np ? np : 1) * sizeof(uint32_t));
        out->corners = malloc((np ? np : 1) * 4 * sizeof(uint32_t));
        out->num_deleted = s->num_deleted;
        out->deleted = malloc((2 * s->num_deleted + 1) * sizeof(uint32_t));
        out->num_problems = s->num_problems;
        out->problems = malloc((s->num_problems + 1) * sizeof(uint32_t));
        if (!out->points || !out->kind || !out->degree || !out->first || !out->corners ||
            !out->deleted || !out->problems) {
            skpy_surface_free(out);
            st = fail(err, SK_ERR_NOMEM, "out of memory");
        } else {
            for (size_t p = 0; p < np; ++p) {
                const sk_patch *pp = &set->patches[p];
                /* the Python vocabulary: kind 3 triangle, 4 quad (tensor) */
                out->kind[p] = pp->kind == SK_PATCH_TRIANGLE ? 3 : 4;
                out->degree[p] = pp->degree;
                out->first[p] = (uint32_t)pp->first;
                memcpy(out->corners + 4 * p, pp->corner_ids, 4 * sizeof(uint32_t));
            }
            if (s->num_deleted)
                memcpy(out->deleted, s->deleted, 2 * s->num_deleted * sizeof(uint32_t));
            if (s->num_problems)
                memcpy(out->problems, s->problems, s->num_problems * sizeof(uint32_t));
            out->stats = s->stats;
        }
    }
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&mesh);
    return st;
}

/* The patch set of the arrays, checked: kinds, degrees and point ranges. */
static sk_status surface_to_set(const skpy_surface *s, sk_patch_set *set, sk_error *err)
{
    for (size_t p = 0; p < s->num_patches; ++p) {
        unsigned n = s->degree[p];
        if ((s->kind[p] != 3 && s->kind[p] != 4) || n < 1 || n > SK_PATCH_MAX_DEGREE)
            return fail(err, SK_ERR_ARG, "patch has a bad kind or degree");
        sk_patch_kind kind = s->kind[p] == 3 ? SK_PATCH_TRIANGLE : SK_PATCH_TENSOR;
        size_t count = sk_bezier_num_points(kind, n, kind == SK_PATCH_TENSOR ? n : 0);
        if ((size_t)s->first[p] + count > s->num_points)
            return fail(err, SK_ERR_ARG, "patch control points beyond the point array");
        sk_status st = sk_patch_set_add(set, kind, n, kind == SK_PATCH_TENSOR ? n : 0,
                                        s->points + 3 * (size_t)s->first[p], s->corners + 4 * p,
                                        NULL, err);
        if (st)
            return st;
    }
    return SK_OK;
}

sk_status skpy_write_surface(const char *path, const skpy_surface *s, unsigned tess,
                             sk_error *err)
{
    sk_patch_set set = {0};
    sk_soup *soup = NULL;
    sk_export_opts eo;
    memset(&eo, 0, sizeof eo);
    sk_status st = surface_to_set(s, &set, err);
    if (st == SK_OK) {
        if (sk_path_has_ext(path, ".step") || sk_path_has_ext(path, ".stp"))
            st = sk_export_step(path, &set, &eo, NULL, err);
        else if (sk_path_has_ext(path, ".igs") || sk_path_has_ext(path, ".iges"))
            st = sk_export_iges(path, &set, &eo, NULL, err);
        else if (sk_format_from_path(path) != SK_FORMAT_UNKNOWN) {
            st = sk_patch_set_tessellate(&set, tess ? tess : 4, &soup, err);
            if (st == SK_OK)
                st = sk_soup_write(path, soup, NULL, err);
        } else
            st = fail(err, SK_ERR_ARG, "a surface is written as .step, .igs, or a tessellation "
                                       "(.obj, .ply, .off, .stl)");
    }
    sk_soup_destroy(&soup);
    sk_patch_set_free(&set);
    return st;
}
