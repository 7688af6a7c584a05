/* surfkit info: prints the validation report of a mesh file (text or --json). */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Reads a mesh (OFF, OBJ, PLY, STL) and reports vertices, faces by size, edges, boundary loops\n"
    "(count and lengths), components, Euler characteristic, genus, every defect class (non-manifold\n"
    "edges and vertices, orientation conflicts, degenerate, duplicate and repeated-vertex faces,\n"
    "unreferenced vertices) with the first offending elements, self-intersections (pairs of faces\n"
    "that cross without sharing a vertex), bounding box, edge lengths, angles and the Gauss-Bonnet\n"
    "check (sum of angle deficits against 2 pi chi).\n";

static const char examples[] =
    "  surfkit info data/nefertiti.off\n"
    "  surfkit info data/sphere.off --json\n";

typedef struct defect_row {
    const char *key;
    const char *label;
    size_t offset;
    int kind; /* 0 vertex, 1 face, 2 edge (vertex pair), 3 face + index, 4 face + earlier face */
} defect_row;

#define ROW(key, label, field, kind) {key, label, offsetof(sk_validation, field), kind}
static const defect_row rows[] = {
    ROW("non_manifold_edges", "non-manifold edges", non_manifold_edges, 2),
    ROW("non_manifold_vertices", "non-manifold vertices", non_manifold_vertices, 0),
    ROW("orientation_conflicts", "orientation conflicts", orientation_conflicts, 2),
    ROW("degenerate_faces", "degenerate faces", degenerate_faces, 1),
    ROW("duplicate_faces", "duplicate faces", duplicate_faces, 4),
    ROW("repeated_vertex_faces", "faces with a repeated vertex", repeated_vertex_faces, 1),
    ROW("small_faces", "faces with < 3 vertices", small_faces, 1),
    ROW("out_of_range_indices", "out-of-range indices", out_of_range, 3),
    ROW("nonfinite_vertices", "NaN/inf vertices", nonfinite_vertices, 0),
    ROW("unreferenced_vertices", "unreferenced vertices", unreferenced_vertices, 0),
};
#undef ROW

static const sk_defect *defect_of(const sk_validation *r, const defect_row *row)
{
    return (const sk_defect *)((const char *)r + row->offset);
}

static void print_examples(FILE *fp, const sk_defect *d, int kind)
{
    for (size_t i = 0; i < d->num_examples; ++i) {
        fputs(i ? ", " : "", fp);
        switch (kind) {
        case 0: fprintf(fp, "v%u", d->a[i]); break;
        case 1: fprintf(fp, "f%u", d->a[i]); break;
        case 2: fprintf(fp, "(v%u, v%u)", d->a[i], d->b[i]); break;
        case 3: fprintf(fp, "f%u->%u", d->a[i], d->b[i]); break;
        default: fprintf(fp, "f%u=f%u", d->a[i], d->b[i]); break;
        }
    }
    if (d->count > d->num_examples)
        fputs(", ...", fp);
}

static void print_text(const char *path, sk_format fmt, const sk_validation *r, const sk_loops *lp)
{
    printf("%s (%s)\n", path, sk_format_name(fmt));
    printf("  vertices              %zu\n", r->vertices);
    printf("  faces                 %zu (%zu triangles, %zu quads, %zu larger)\n", r->faces,
           r->triangles, r->quads, r->polygons);
    printf("  edges                 %zu (%zu on the boundary)\n", r->edges, r->boundary_edges);
    printf("  boundary loops        %zu", r->boundary_loops);
    if (lp && lp->count) {
        printf(" (lengths");
        for (size_t i = 0; i < lp->count && i < 8; ++i)
            printf(" %.6g", lp->lengths[i]);
        printf("%s)", lp->count > 8 ? " ..." : "");
    }
    printf("\n  components            %zu\n", r->components);
    printf("  Euler characteristic  %ld\n", r->euler_characteristic);
    if (r->genus_defined)
        printf("  genus                 %ld\n", r->genus);
    else
        printf("  genus                 undefined (non-manifold or non-orientable)\n");
    printf("  orientation           %s\n",
           r->orientation_conflicts.count ? "inconsistent" : "consistent");
    printf("  manifold              %s\n", sk_validation_is_manifold(r) ? "yes" : "no");
    double dx = r->bbox_max[0] - r->bbox_min[0], dy = r->bbox_max[1] - r->bbox_min[1],
           dz = r->bbox_max[2] - r->bbox_min[2];
    printf("  bounding box          [%.6g %.6g %.6g] .. [%.6g %.6g %.6g], diagonal %.6g\n",
           r->bbox_min[0], r->bbox_min[1], r->bbox_min[2], r->bbox_max[0], r->bbox_max[1],
           r->bbox_max[2], sqrt(dx * dx + dy * dy + dz * dz));
    printf("  edge length           min %.6g, mean %.6g, max %.6g\n", r->edge_min, r->edge_mean,
           r->edge_max);
    printf("  triangle angles       min %.4g deg, max %.4g deg\n", r->min_angle_deg,
           r->max_angle_deg);
    printf("  area                  %.6g\n", r->area);
    printf("  Gauss-Bonnet          sum of angle deficits %.12g, 2 pi chi %.12g, error %.3g\n",
           r->angle_deficit_sum, r->angle_deficit_sum - r->gauss_bonnet_error,
           r->gauss_bonnet_error);
    size_t total = 0;
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i)
        total += defect_of(r, &rows[i])->count;
    printf("  defects               %s\n", total ? "" : "none");
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        const sk_defect *d = defect_of(r, &rows[i]);
        if (!d->count)
            continue;
        printf("    %-28s %zu: ", rows[i].label, d->count);
        print_examples(stdout, d, rows[i].kind);
        printf("\n");
    }
}

/* Self-intersections: NULL when they could not be checked (faces out of range, NaN...). */
static void print_crossings_text(const sk_intersection_report *x)
{
    if (!x) {
        printf("  self-intersections    not checked (defective faces or coordinates)\n");
        return;
    }
    printf("  self-intersections    ");
    if (!x->pairs) {
        printf("none\n");
        return;
    }
    printf("%zu face pairs:", x->pairs);
    for (size_t i = 0; i < x->num_examples && i < 8; ++i)
        printf(" %u-%u", x->examples[2 * i], x->examples[2 * i + 1]);
    printf("%s\n", x->pairs > 8 ? " ..." : "");
}

static void print_crossings_json(cli_json *j, const sk_intersection_report *x)
{
    json_key(j, "self_intersections");
    if (!x) {
        json_str(j, "not checked");
        return;
    }
    json_uint(j, x->pairs);
    json_key(j, "self_intersection_examples");
    json_arr_open(j);
    for (size_t i = 0; i < x->num_examples; ++i) {
        json_arr_open(j);
        json_uint(j, x->examples[2 * i]);
        json_uint(j, x->examples[2 * i + 1]);
        json_arr_close(j);
    }
    json_arr_close(j);
}

static void print_json(const char *path, sk_format fmt, const sk_validation *r, const sk_loops *lp,
                       const sk_intersection_report *x)
{
    cli_json j;
    json_begin(&j, stdout);
    json_obj_open(&j);
    json_kstr(&j, "input", path);
    json_kstr(&j, "format", sk_format_name(fmt));
    json_kuint(&j, "vertices", r->vertices);
    json_kuint(&j, "faces", r->faces);
    json_kuint(&j, "triangles", r->triangles);
    json_kuint(&j, "quads", r->quads);
    json_kuint(&j, "polygons", r->polygons);
    json_kuint(&j, "edges", r->edges);
    json_kuint(&j, "boundary_edges", r->boundary_edges);
    json_kuint(&j, "boundary_loops", r->boundary_loops);
    json_key(&j, "boundary_loop_lengths");
    json_arr_open(&j);
    for (size_t i = 0; lp && i < lp->count; ++i)
        json_num(&j, lp->lengths[i]);
    json_arr_close(&j);
    json_kuint(&j, "components", r->components);
    json_kint(&j, "euler_characteristic", r->euler_characteristic);
    json_key(&j, "genus");
    if (r->genus_defined)
        json_int(&j, r->genus);
    else
        json_str(&j, "undefined");
    json_kbool(&j, "manifold", sk_validation_is_manifold(r));
    json_kbool(&j, "orientation_consistent", r->orientation_conflicts.count == 0);
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i)
        json_kuint(&j, rows[i].key, defect_of(r, &rows[i])->count);
    json_key(&j, "defect_examples");
    json_obj_open(&j);
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        const sk_defect *d = defect_of(r, &rows[i]);
        if (!d->count)
            continue;
        json_key(&j, rows[i].key);
        json_arr_open(&j);
        for (size_t k = 0; k < d->num_examples; ++k) {
            if (rows[i].kind >= 2) {
                json_arr_open(&j);
                json_uint(&j, d->a[k]);
                json_uint(&j, d->b[k]);
                json_arr_close(&j);
            } else {
                json_uint(&j, d->a[k]);
            }
        }
        json_arr_close(&j);
    }
    json_obj_close(&j);
    print_crossings_json(&j, x);
    json_key(&j, "bbox_min");
    json_arr_open(&j);
    for (int k = 0; k < 3; ++k)
        json_num(&j, r->bbox_min[k]);
    json_arr_close(&j);
    json_key(&j, "bbox_max");
    json_arr_open(&j);
    for (int k = 0; k < 3; ++k)
        json_num(&j, r->bbox_max[k]);
    json_arr_close(&j);
    json_knum(&j, "edge_length_min", r->edge_min);
    json_knum(&j, "edge_length_mean", r->edge_mean);
    json_knum(&j, "edge_length_max", r->edge_max);
    json_knum(&j, "min_angle_deg", r->min_angle_deg);
    json_knum(&j, "max_angle_deg", r->max_angle_deg);
    json_knum(&j, "area", r->area);
    json_knum(&j, "angle_deficit_sum", r->angle_deficit_sum);
    json_knum(&j, "gauss_bonnet_error", r->gauss_bonnet_error);
    json_obj_close(&j);
    json_end(&j);
}

int cmd_info(int argc, char **argv)
{
    bool as_json = false, quiet = false;
    const cli_opt opts[] = {
        OPT_FLAG("--json", as_json, "machine-readable report on stdout"),
        OPT_FLAG("-q", quiet, "no progress output (info has none)"),
    };
    const cli_spec spec = {"info", "FILE", about, opts, CLI_COUNT(opts), 1, 1, examples, NULL};
    cli_args args;
    int rc = cli_parse(&spec, argc, argv, &args);
    if (rc)
        return rc == CLI_HELP ? EXIT_OK : rc;
    const char *path = args.inputs[0];

    sk_error err = {0};
    sk_soup *soup = NULL;
    sk_mesh *mesh = NULL;
    sk_loops loops = {0};
    bool have_loops = false;
    sk_validation rep;
    sk_status st = sk_soup_read(path, NULL, &soup, &err);
    if (st)
        return cli_fail(st, &err);
    st = sk_soup_validate(soup, &rep, &err);
    if (st) {
        sk_soup_destroy(&soup);
        return cli_fail(st, &err);
    }
    /* loop lengths need the half-edge mesh, which exists only for manifold input; there a failure
     * (out of memory) is an error, not a report without the lengths */
    if (sk_validation_is_manifold(&rep)) {
        if ((st = sk_mesh_from_soup(soup, &mesh, &err)) == SK_OK &&
            (st = sk_mesh_boundary_loops(mesh, &loops, &err)) == SK_OK)
            have_loops = true;
        if (st) {
            sk_mesh_destroy(&mesh);
            sk_soup_destroy(&soup);
            return cli_fail(st, &err);
        }
    }
    sk_format fmt = sk_format_from_path(path);
    sk_intersection_report crossings;
    sk_error xerr;
    st = sk_self_intersections(soup, NULL, NULL, &crossings, &xerr);
    if (st == SK_ERR_NOMEM) { /* not "not checked": out of memory is an error */
        if (have_loops)
            sk_loops_free(&loops);
        sk_mesh_destroy(&mesh);
        sk_soup_destroy(&soup);
        return cli_fail(st, &xerr);
    }
    bool have_crossings = st == SK_OK;
    if (as_json) {
        print_json(path, fmt, &rep, have_loops ? &loops : NULL, have_crossings ? &crossings : NULL);
    } else {
        print_text(path, fmt, &rep, have_loops ? &loops : NULL);
        print_crossings_text(have_crossings ? &crossings : NULL);
    }
    if (have_loops)
        sk_loops_free(&loops);
    sk_mesh_destroy(&mesh);
    sk_soup_destroy(&soup);
    return EXIT_OK;
}
