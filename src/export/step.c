/* STEP AP214 (ISO 10303-21) writer: every tensor Bezier patch is a B_SPLINE_SURFACE_WITH_KNOTS
 * (one Bezier span: knots 0 and 1 of multiplicity degree + 1) carried by an ADVANCED_FACE; all
 * faces form one OPEN_SHELL of a SHELL_BASED_SURFACE_MODEL, or, when every edge has two faces, a
 * CLOSED_SHELL bounding a MANIFOLD_SOLID_BREP (in an ADVANCED_BREP_SHAPE_REPRESENTATION).
 * Neighbouring faces share their EDGE_CURVEs and VERTEX_POINTs, so a CAD system sees one
 * connected surface; edges are plain 3D curves (no pcurves: importers compute them).
 *
 * Topology comes from the patches' corner ids (mesh vertices). By default a triangle is one face:
 * the biquartic of sk_patch_triangle_to_degenerate_tensor, whose side s = 0 is collapsed to
 * corner 0, bounded by a loop of its three real sides (importers add the degenerated edge, as
 * at the pole of a sphere). With opts->split_triangles a triangle is split into three tensor
 * patches at its centroid and edge midpoints; the mesh edges next to a triangle are then split
 * at their midpoints in every face that uses them (a quad next to a triangle has that side in two
 * edges), so faces always meet edge to edge.
 *
 * Size: every CARTESIAN_POINT is written once per distinct position (exact bits) and referenced
 * by every surface and edge curve that has that control point; an edge curve's control points
 * are the boundary row of the first face that uses it. */
#include "export/export_internal.h"

#include <stdlib.h>
#include <string.h>

typedef enum { K_VERTEX, K_MID, K_CENTROID, K_FULL, K_HALF, K_INNER } key_kind;

typedef struct key {
    uint32_t kind, a, b;
} key;

typedef struct entry {
    key k;
    size_t id;      /* entity id (VERTEX_POINT or EDGE_CURVE) */
    size_t start;   /* edges: start vertex entity */
    uint32_t uses;  /* edges: faces using it */
    bool used;
} entry;

typedef struct map {
    entry *e;
    size_t cap, n;
} map;

static uint64_t hash_key(key k)
{
    uint64_t h = ((uint64_t)k.kind * 0x9E3779B97F4A7C15ULL) ^ ((uint64_t)k.a << 32 | k.b);
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ULL;
    return h ^ (h >> 29);
}

static bool key_eq(key x, key y)
{
    return x.kind == y.kind && x.a == y.a && x.b == y.b;
}

/* Finds or inserts k; returns the slot (NULL on allocation failure). */
static entry *map_get(map *m, key k, bool *created)
{
    if (2 * (m->n + 1) > m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 1024;
        entry *ne = sk__calloc_array(cap, sizeof *ne);
        if (!ne)
            return NULL;
        for (size_t i = 0; i < m->cap; ++i) {
            if (!m->e[i].used)
                continue;
            size_t j = hash_key(m->e[i].k) & (cap - 1);
            while (ne[j].used)
                j = (j + 1) & (cap - 1);
            ne[j] = m->e[i];
        }
        sk__free(m->e);
        m->e = ne;
        m->cap = cap;
    }
    size_t j = hash_key(k) & (m->cap - 1);
    while (m->e[j].used) {
        if (key_eq(m->e[j].k, k)) {
            *created = false;
            return &m->e[j];
        }
        j = (j + 1) & (m->cap - 1);
    }
    m->e[j].used = true;
    m->e[j].k = k;
    m->n++;
    *created = true;
    return &m->e[j];
}

static bool map_find(const map *m, key k)
{
    if (!m->cap)
        return false;
    for (size_t j = hash_key(k) & (m->cap - 1); m->e[j].used; j = (j + 1) & (m->cap - 1))
        if (key_eq(m->e[j].k, k))
            return true;
    return false;
}

static key edge_key(key_kind kind, uint32_t a, uint32_t b)
{
    key k = {kind, a < b ? a : b, a < b ? b : a};
    return k;
}

/* CARTESIAN_POINT entities by the exact bits of their coordinates. */
typedef struct pentry {
    uint64_t x, y, z;
    size_t id; /* 0 = empty slot */
} pentry;

typedef struct pmap {
    pentry *e;
    size_t cap, n;
} pmap;

typedef struct writer {
    sk__out *b;
    size_t next; /* next entity id */
    map vertices, edges;
    pmap points;
    bool nomem;
} writer;

/* "#id" (an entity name or reference) */
static void ent_id(sk__out *b, size_t id)
{
    sk__out_char(b, '#');
    sk__out_uint(b, id);
}

static uint64_t hash_point(const uint64_t q[3])
{
    uint64_t h = q[0] * 0x9E3779B97F4A7C15ULL ^ (q[1] + 0x632BE59BD9B4E019ULL) * 0xC2B2AE3D27D4EB4FULL ^
                 q[2] * 0x165667B19E3779F9ULL;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ULL;
    return h ^ (h >> 29);
}

/* The slot of the point with bits q (empty if absent); the table has room. */
static pentry *pmap_slot(pmap *m, const uint64_t q[3])
{
    size_t j = hash_point(q) & (m->cap - 1);
    while (m->e[j].id && !(m->e[j].x == q[0] && m->e[j].y == q[1] && m->e[j].z == q[2]))
        j = (j + 1) & (m->cap - 1);
    return &m->e[j];
}

/* The CARTESIAN_POINT at p, written on first use. */
static size_t point(writer *w, const double p[3])
{
    pmap *m = &w->points;
    if (2 * (m->n + 1) > m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 4096;
        pentry *old = m->e, *ne = sk__calloc_array(cap, sizeof *ne);
        if (!ne) {
            w->nomem = true;
            return 0;
        }
        size_t ocap = m->cap;
        m->e = ne;
        m->cap = cap;
        for (size_t i = 0; i < ocap; ++i)
            if (old[i].id) {
                const uint64_t q[3] = {old[i].x, old[i].y, old[i].z};
                *pmap_slot(m, q) = old[i];
            }
        sk__free(old);
    }
    double c[3];
    for (int k = 0; k < 3; ++k)
        c[k] = p[k] == 0.0 ? 0.0 : p[k]; /* -0 and 0 are the same point */
    uint64_t q[3];
    memcpy(q, c, sizeof q);
    pentry *e = pmap_slot(m, q);
    if (e->id)
        return e->id;
    e->x = q[0], e->y = q[1], e->z = q[2];
    e->id = w->next++;
    m->n++;
    char x[32];
    ent_id(w->b, e->id);
    sk__out_str(w->b, "=CARTESIAN_POINT('',(");
    for (int k = 0; k < 3; ++k) {
        if (k)
            sk__out_char(w->b, ',');
        sk__out_str(w->b, sk__fmt_real(x, c[k]));
    }
    sk__out_str(w->b, "));\n");
    return e->id;
}

static size_t vertex(writer *w, key k, const double p[3])
{
    bool created;
    entry *e = map_get(&w->vertices, k, &created);
    if (!e) {
        w->nomem = true;
        return 0;
    }
    if (created) {
        size_t pt = point(w, p);
        e->id = w->next++;
        ent_id(w->b, e->id);
        sk__out_str(w->b, "=VERTEX_POINT('',");
        ent_id(w->b, pt);
        sk__out_str(w->b, ");\n");
    }
    return e->id;
}

/* The edge with key k from vertex entity `from` to `to` whose curve (from -> to) has the given
 * control points; returns the ORIENTED_EDGE entity for traversing it from -> to. */
static size_t oriented_edge(writer *w, key k, size_t from, size_t to, const double *cp,
                            unsigned deg)
{
    bool created;
    entry *e = map_get(&w->edges, k, &created);
    if (!e) {
        w->nomem = true;
        return 0;
    }
    if (created) {
        size_t ids[SK_PATCH_MAX_DEGREE + 1];
        for (unsigned i = 0; i <= deg; ++i)
            ids[i] = point(w, cp + 3 * i);
        size_t curve = w->next++;
        ent_id(w->b, curve);
        sk__out_str(w->b, "=B_SPLINE_CURVE_WITH_KNOTS('',");
        sk__out_uint(w->b, deg);
        sk__out_str(w->b, ",(");
        for (unsigned i = 0; i <= deg; ++i) {
            if (i)
                sk__out_char(w->b, ',');
            ent_id(w->b, ids[i]);
        }
        sk__out_str(w->b, "),.UNSPECIFIED.,.F.,.F.,(");
        sk__out_uint(w->b, deg + 1);
        sk__out_char(w->b, ',');
        sk__out_uint(w->b, deg + 1);
        sk__out_str(w->b, "),(0.,1.),.UNSPECIFIED.);\n");
        e->id = w->next++;
        e->start = from;
        ent_id(w->b, e->id);
        sk__out_str(w->b, "=EDGE_CURVE('',");
        ent_id(w->b, from);
        sk__out_char(w->b, ',');
        ent_id(w->b, to);
        sk__out_char(w->b, ',');
        ent_id(w->b, curve);
        sk__out_str(w->b, ",.T.);\n");
    }
    e->uses++;
    size_t id = w->next++;
    ent_id(w->b, id);
    sk__out_str(w->b, "=ORIENTED_EDGE('',*,*,");
    ent_id(w->b, e->id);
    sk__out_str(w->b, e->start == from ? ",.T.);\n" : ",.F.);\n");
    return id;
}

static void face(writer *w, const sk_patch_set *set, size_t pi, const size_t *loop, size_t nloop,
                 size_t *face_id)
{
    const sk_patch *p = &set->patches[pi];
    const double *cp = sk_patch_cp(set, pi);
    unsigned du = p->degree, dv = p->degree_v;
    size_t *ids = sk__malloc_array((du + 1) * (dv + 1) * sizeof(size_t), 1);
    if (!ids) {
        w->nomem = true;
        return;
    }
    for (unsigned k = 0; k < (du + 1) * (dv + 1); ++k)
        ids[k] = point(w, cp + 3 * k);
    size_t surf = w->next++;
    ent_id(w->b, surf);
    sk__out_str(w->b, "=B_SPLINE_SURFACE_WITH_KNOTS('',");
    sk__out_uint(w->b, du);
    sk__out_char(w->b, ',');
    sk__out_uint(w->b, dv);
    sk__out_str(w->b, ",(");
    for (unsigned i = 0; i <= du; ++i) { /* outer list along u (s), inner along v (t) */
        sk__out_str(w->b, i ? ",(" : "(");
        for (unsigned j = 0; j <= dv; ++j) {
            if (j)
                sk__out_char(w->b, ',');
            ent_id(w->b, ids[sk_tensor_index(du, i, j)]);
        }
        sk__out_char(w->b, ')');
    }
    sk__out_printf(w->b, "),.UNSPECIFIED.,.F.,.F.,.F.,(%u,%u),(%u,%u),(0.,1.),(0.,1.),"
                         ".UNSPECIFIED.);\n", du + 1, du + 1, dv + 1, dv + 1);
    sk__free(ids);
    size_t lp = w->next++;
    ent_id(w->b, lp);
    sk__out_str(w->b, "=EDGE_LOOP('',(");
    for (size_t i = 0; i < nloop; ++i) {
        if (i)
            sk__out_char(w->b, ',');
        ent_id(w->b, loop[i]);
    }
    sk__out_str(w->b, "));\n");
    size_t bound = w->next++;
    ent_id(w->b, bound);
    sk__out_str(w->b, "=FACE_OUTER_BOUND('',");
    ent_id(w->b, lp);
    sk__out_str(w->b, ",.T.);\n");
    *face_id = w->next++;
    ent_id(w->b, *face_id);
    sk__out_str(w->b, "=ADVANCED_FACE('',(");
    ent_id(w->b, bound);
    sk__out_str(w->b, "),");
    ent_id(w->b, surf);
    sk__out_str(w->b, ",.T.);\n");
}

/* The face of tensor patch i: its sides are the mesh edges between its corner ids, each in two
 * halves where a triangle uses it (split). */
static void tensor_face(writer *w, const map *split, const sk_patch_set *set, size_t i,
                        size_t *face_id)
{
    const uint32_t *c = set->patches[i].corner_ids;
    double cp[3 * (SK_PATCH_MAX_DEGREE + 1)], l[3 * (SK_PATCH_MAX_DEGREE + 1)],
        r[3 * (SK_PATCH_MAX_DEGREE + 1)], q[3];
    size_t loop[8], nl = 0, vid[4];
    for (unsigned k = 0; k < 4; ++k) {
        sk_patch_edge_point(set, i, k, 0.0, q);
        vid[k] = vertex(w, (key){K_VERTEX, c[k], 0}, q);
    }
    for (unsigned k = 0; k < 4; ++k) {
        uint32_t a = c[k], b = c[(k + 1) % 4];
        unsigned deg = sk_patch_edge_curve(set, i, k, cp);
        if (!map_find(split, edge_key(K_FULL, a, b))) {
            loop[nl++] = oriented_edge(w, edge_key(K_FULL, a, b), vid[k], vid[(k + 1) % 4], cp, deg);
        } else {
            sk__bezier_halve(cp, deg, l, r);
            size_t mid = vertex(w, edge_key(K_MID, a, b), r);
            loop[nl++] = oriented_edge(w, (key){K_HALF, a, b}, vid[k], mid, l, deg);
            loop[nl++] = oriented_edge(w, (key){K_HALF, b, a}, mid, vid[(k + 1) % 4], r, deg);
        }
    }
    if (!w->nomem)
        face(w, set, i, loop, nl, face_id);
}

/* The three faces of triangle i (split at its centroid and edge midpoints; scratch holds the
 * sub-patches). */
static sk_status triangle_faces(writer *w, const sk_patch_set *set, size_t i,
                                sk_patch_set *scratch, size_t face_ids[3], sk_error *err)
{
    const uint32_t *c = set->patches[i].corner_ids;
    double cp[3 * (SK_PATCH_MAX_DEGREE + 1)], q[3];
    size_t loop[4];
    sk_patch_set_clear(scratch);
    sk_status st = sk_patch_split_triangle(set, i, scratch, err);
    if (st)
        return st;
    size_t vc[3], vm[3];
    for (unsigned k = 0; k < 3; ++k) {
        sk_patch_edge_point(scratch, k, 0, 0.0, q);
        vc[k] = vertex(w, (key){K_VERTEX, c[k], 0}, q);
    }
    for (unsigned k = 0; k < 3; ++k) { /* midpoint of side k (corner k -> k+1) */
        sk_patch_edge_point(scratch, k, 1, 0.0, q);
        vm[k] = vertex(w, edge_key(K_MID, c[k], c[(k + 1) % 3]), q);
    }
    sk_patch_edge_point(scratch, 0, 2, 0.0, q);
    size_t vg = vertex(w, (key){K_CENTROID, (uint32_t)i, 0}, q);
    for (unsigned k = 0; k < 3 && !w->nomem; ++k) {
        unsigned kp = (k + 2) % 3;
        uint32_t A = c[k], B = c[(k + 1) % 3], C = c[kp];
        unsigned deg = sk_patch_edge_curve(scratch, k, 0, cp); /* A -> mid(A,B) */
        loop[0] = oriented_edge(w, (key){K_HALF, A, B}, vc[k], vm[k], cp, deg);
        deg = sk_patch_edge_curve(scratch, k, 1, cp); /* mid(A,B) -> centroid */
        loop[1] = oriented_edge(w, (key){K_INNER, (uint32_t)i, k}, vm[k], vg, cp, deg);
        deg = sk_patch_edge_curve(scratch, k, 2, cp); /* centroid -> mid(C,A) */
        loop[2] = oriented_edge(w, (key){K_INNER, (uint32_t)i, kp}, vg, vm[kp], cp, deg);
        deg = sk_patch_edge_curve(scratch, k, 3, cp); /* mid(C,A) -> A */
        loop[3] = oriented_edge(w, (key){K_HALF, A, C}, vm[kp], vc[k], cp, deg);
        face(w, scratch, k, loop, 4, &face_ids[k]);
    }
    return SK_OK;
}

/* The one face of triangle i: the degenerate biquartic (side s = 0 collapsed to corner 0) in
 * scratch, bounded by its sides 0, 1, 2 (corners 0 -> 1 -> 2 -> 0 of the triangle). */
static sk_status degenerate_face(writer *w, const sk_patch_set *set, size_t i,
                                 sk_patch_set *scratch, size_t *face_id, sk_error *err)
{
    const uint32_t *c = set->patches[i].corner_ids;
    double cp[3 * (SK_PATCH_MAX_DEGREE + 1)], q[3];
    size_t loop[3], vid[3];
    sk_patch_set_clear(scratch);
    sk_status st = sk_patch_triangle_to_degenerate_tensor(set, i, scratch, err);
    if (st)
        return st;
    for (unsigned k = 0; k < 3; ++k) {
        sk_patch_edge_point(scratch, 0, k, 0.0, q);
        vid[k] = vertex(w, (key){K_VERTEX, c[k], 0}, q);
    }
    for (unsigned k = 0; k < 3 && !w->nomem; ++k) {
        unsigned deg = sk_patch_edge_curve(scratch, 0, k, cp);
        loop[k] = oriented_edge(w, edge_key(K_FULL, c[k], c[(k + 1) % 3]), vid[k],
                                vid[(k + 1) % 3], cp, deg);
    }
    if (!w->nomem)
        face(w, scratch, 0, loop, 3, face_id);
    return SK_OK;
}

sk_status sk_export_step(const char *path, const sk_patch_set *patches,
                         const sk_export_opts *opts, sk_export_stats *stats, sk_error *err)
{
    const sk__unit *unit = sk__unit_lookup(opts ? opts->units : NULL);
    if (!unit)
        return sk__fail(err, SK_ERR_ARG, "unknown unit '%s'", opts->units);
    for (size_t i = 0; i < patches->count; ++i)
        for (unsigned c = 0; c < sk_patch_num_corners(&patches->patches[i]); ++c)
            if (patches->patches[i].corner_ids[c] == SK_INVALID)
                return sk__fail(err, SK_ERR_ARG, "patch %zu has no corner ids: STEP export needs "
                                "them to share edges", i);
    const char *name = opts && opts->name ? opts->name : "surfkit";
    char when[32];
    sk__export_time(opts, when);
    sk__out out = {0};
    writer w = {.b = &out, .next = 1};
    map split = {0};
    sk_patch_set sub = {0};
    size_t *faces = NULL, nfaces = 0;
    sk_status st = SK_OK;

    bool split_tri = !sk__export_degenerate(opts);
    /* split layout: sides next to a triangle are split at their midpoints */
    for (size_t i = 0; i < patches->count && split_tri && !w.nomem; ++i) {
        const sk_patch *p = &patches->patches[i];
        if (p->kind != SK_PATCH_TRIANGLE)
            continue;
        for (unsigned c = 0; c < 3; ++c) {
            bool created;
            if (!map_get(&split, edge_key(K_FULL, p->corner_ids[c], p->corner_ids[(c + 1) % 3]),
                         &created))
                w.nomem = true;
        }
    }
    size_t nt = 0;
    for (size_t i = 0; i < patches->count; ++i)
        nt += patches->patches[i].kind == SK_PATCH_TRIANGLE && split_tri ? 3 : 1;
    faces = sk__malloc_array((nt ? nt : 1) * sizeof *faces, 1);
    if (!faces || w.nomem) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }

    sk__step_header(&out, "surfkit VC1 surface: Bezier patches as B-spline surfaces", path, name,
                    when, "surfkit 0.1.0", unit);
    w.next = 30;

    sk__export_progress prog;
    sk__export_progress_init(&prog, opts, patches->count);
    for (size_t i = 0; i < patches->count && !w.nomem && st == SK_OK; ++i) {
        if (sk__export_tick(&prog, i)) {
            st = sk__fail(err, SK_ERR_CANCELLED, "cancelled");
            break;
        }
        if (patches->patches[i].kind == SK_PATCH_TENSOR)
            tensor_face(&w, &split, patches, i, &faces[nfaces++]);
        else if (!split_tri)
            st = degenerate_face(&w, patches, i, &sub, &faces[nfaces++], err);
        else if ((st = triangle_faces(&w, patches, i, &sub, &faces[nfaces], err)) == SK_OK)
            nfaces += 3;
    }
    if (st)
        goto done;
    if (w.nomem) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    bool closed = w.edges.n > 0;
    for (size_t i = 0; i < w.edges.cap; ++i)
        if (w.edges.e[i].used && w.edges.e[i].uses != 2)
            closed = false;
    size_t shell = w.next++;
    sk__out_printf(&out, "#%zu=%s('',(", shell, closed ? "CLOSED_SHELL" : "OPEN_SHELL");
    for (size_t i = 0; i < nfaces; ++i)
        sk__out_printf(&out, "%s#%zu", i ? "," : "", faces[i]);
    sk__out_str(&out, "));\n");
    size_t model = w.next++, rep = w.next++, sdr = w.next++;
    if (closed) { /* a closed shell bounds a solid: importers get a solid for booleans, offsets */
        sk__out_printf(&out, "#%zu=MANIFOLD_SOLID_BREP('',#%zu);\n", model, shell);
        sk__out_printf(&out, "#%zu=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#18,#%zu),#14);\n",
                       rep, model);
    } else {
        sk__out_printf(&out, "#%zu=SHELL_BASED_SURFACE_MODEL('',(#%zu));\n", model, shell);
        sk__out_printf(&out, "#%zu=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#18,#%zu),#14);\n",
                       rep, model);
    }
    sk__out_printf(&out, "#%zu=SHAPE_DEFINITION_REPRESENTATION(#9,#%zu);\n", sdr, rep);
    sk__out_str(&out, "ENDSEC;\nEND-ISO-10303-21;\n");
    if (sk__export_tick(&prog, patches->count)) {
        st = sk__fail(err, SK_ERR_CANCELLED, "cancelled");
        goto done;
    }
    st = sk__out_write_file(&out, path, err);
    if (st == SK_OK && stats) {
        stats->faces = nfaces;
        stats->edges = w.edges.n;
        stats->vertices = w.vertices.n;
        stats->bytes = out.len;
        stats->solid = closed;
    }
done:
    sk__free(faces);
    sk_patch_set_free(&sub);
    sk__free(split.e);
    sk__free(w.vertices.e);
    sk__free(w.edges.e);
    sk__free(w.points.e);
    sk__out_free(&out);
    return st;
}
