/* IGES 5.3 writer; fixed 80-column records in the Start, Global, Directory Entry, Parameter Data
 * and Terminate sections.
 *
 * Default layout: a boundary representation (IGES 5.3 section 4.7 "B-rep solid model" entities)
 * that CAD importers read as one connected shell or solid, not as loose faces to be sewn:
 *
 *   186 manifold solid B-rep object (closed surfaces only)
 *    `- 514 shell (form 1 closed, form 2 open)
 *        `- 510 face (form 1) per tensor patch
 *            |- 128 rational B-spline surface (one Bezier span, polynomial)
 *            `- 508 loop (form 1): its 4 sides (or more where a side meets two faces), each an
 *                   edge of the 504 list with its parameter-space curve (110 line in (s, t))
 *   504 edge list (form 1): every edge once, with its 126 model-space curve and the indices of
 *       its end vertices in the 502 vertex list (form 1)
 *
 * Topology comes from the geometry of the tensor patches themselves (the output of
 * sk_export_tensor_patches), so it does not depend on how the patches were built: corners are
 * welded within IGES_WELD_REL of the model size, an edge is identified by its two end vertices and
 * its midpoint, and a side whose midpoint is another face's corner (a quad next to a split
 * triangle) is split there, so faces meet edge to edge.
 *
 * With opts->degenerate_triangles or opts->iges_free_surfaces, or when a patch has a side
 * collapsed to a point, the file holds only the 128 surfaces, gathered in one 402 associativity
 * (form 1, unordered group): importers get untrimmed faces that they must sew themselves. (One
 * group, not independent surfaces: FreeCAD 0.20's Import.insert segfaults on a file of many
 * independent surfaces, what this writer wrote before, and opens the same surfaces grouped.) */
#include "export/export_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Corners, edge midpoints: points closer than this times the model size are the same point (the
 * VC1 patches meet to about 1e-16 of the model size). */
#define IGES_WELD_REL 1e-9
/* Hash grid cell, relative to the model size: much larger than the weld distance, so that the
 * 27 cells around a point hold every point within the weld distance. */
#define IGES_CELL_REL 1e-6

/* The D and P sections being written: entity k (0-based) has DE pointer 2k + 1. */
typedef struct sections {
    sk__out d, p;
    size_t d_seq, p_seq;
} sections;

static size_t de_of(size_t k)
{
    return 2 * k + 1;
}

static sk__iges_packer entity_begin(sections *s, int type)
{
    sk__iges_packer pp = {.b = &s->p, .section = 'P', .seq = &s->p_seq, .width = 64,
                          .de = s->d_seq + 1, .first = s->p_seq + 1};
    sk__iges_pack_int(&pp, type);
    return pp;
}

/* Ends the entity's parameter data and writes its two directory entry records. status is the
 * 8-digit status number (blank, subordinate, use, hierarchy). */
static void entity_end(sections *s, sk__iges_packer *pp, int type, int form, const char *status)
{
    sk__iges_pack_end(pp);
    size_t lines = s->p_seq - pp->first + 1;
    char l1[128], l2[128];
    snprintf(l1, sizeof l1, "%8d%8zu%8d%8d%8d%8d%8d%8d%8s", type, pp->first, 0, 0, 0, 0, 0, 0,
             status);
    snprintf(l2, sizeof l2, "%8d%8d%8d%8zu%8d%8s%8s%8s%8d", type, 0, 0, lines, form, "", "", "",
             0);
    sk__iges_record(&s->d, l1, 'D', ++s->d_seq);
    sk__iges_record(&s->d, l2, 'D', ++s->d_seq);
}

#define ST_INDEPENDENT "00000000"
#define ST_DEPENDENT "00010000"    /* physically dependent */
#define ST_PARAMETRIC "00010500"   /* physically dependent, 2D parametric */

/* Entity 128: one Bezier span as a polynomial B-spline surface on [0,1]^2. */
static void write_surface(sections *s, const sk_patch_set *t, size_t i, const char *status)
{
    const sk_patch *p = &t->patches[i];
    const double *cp = sk_patch_cp(t, i);
    unsigned du = p->degree, dv = p->degree_v;
    sk__iges_packer pp = entity_begin(s, 128);
    sk__iges_pack_int(&pp, (long)du); /* K1: upper index of the u sum */
    sk__iges_pack_int(&pp, (long)dv); /* K2 */
    sk__iges_pack_int(&pp, (long)du); /* M1: degree */
    sk__iges_pack_int(&pp, (long)dv); /* M2 */
    sk__iges_pack_int(&pp, 0);        /* PROP1: not closed in u */
    sk__iges_pack_int(&pp, 0);        /* PROP2: not closed in v */
    sk__iges_pack_int(&pp, 1);        /* PROP3: polynomial */
    sk__iges_pack_int(&pp, 0);        /* PROP4: not periodic in u */
    sk__iges_pack_int(&pp, 0);        /* PROP5: not periodic in v */
    for (unsigned k = 0; k < 2 * (du + 1); ++k)
        sk__iges_pack_real(&pp, k <= du ? 0.0 : 1.0);
    for (unsigned k = 0; k < 2 * (dv + 1); ++k)
        sk__iges_pack_real(&pp, k <= dv ? 0.0 : 1.0);
    for (unsigned k = 0; k < (du + 1) * (dv + 1); ++k)
        sk__iges_pack_real(&pp, 1.0);
    for (unsigned j = 0; j <= dv; ++j) /* first index (u) varies fastest */
        for (unsigned a = 0; a <= du; ++a)
            for (int x = 0; x < 3; ++x)
                sk__iges_pack_real(&pp, cp[3 * sk_tensor_index(du, a, j) + (unsigned)x]);
    sk__iges_pack_real(&pp, 0.0);
    sk__iges_pack_real(&pp, 1.0);
    sk__iges_pack_real(&pp, 0.0);
    sk__iges_pack_real(&pp, 1.0);
    entity_end(s, &pp, 128, 0, status);
}

/* ---- topology from geometry ---- */

/* Points welded within `tol`, hashed by grid cell. */
typedef struct pool {
    double *xyz;
    size_t n, cap;
    size_t *slot; /* index + 1, 0 = empty */
    size_t scap;
    double cell, tol;
} pool;

static uint64_t cell_hash(int64_t x, int64_t y, int64_t z)
{
    uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15ULL ^ (uint64_t)y * 0xC2B2AE3D27D4EB4FULL ^
                 (uint64_t)z * 0x165667B19E3779F9ULL;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ULL;
    return h ^ (h >> 29);
}

static void cell_of(const pool *pl, const double *p, int64_t c[3])
{
    for (int k = 0; k < 3; ++k)
        c[k] = (int64_t)floor(p[k] / pl->cell);
}

static void pool_slot_insert(size_t *slot, size_t scap, const pool *pl, size_t idx)
{
    int64_t c[3];
    cell_of(pl, pl->xyz + 3 * idx, c);
    size_t j = cell_hash(c[0], c[1], c[2]) & (scap - 1);
    while (slot[j])
        j = (j + 1) & (scap - 1);
    slot[j] = idx + 1;
}

/* Index of a point within tol of p, or SIZE_MAX. */
static size_t pool_find(const pool *pl, const double *p)
{
    if (!pl->scap)
        return SIZE_MAX;
    int64_t c[3];
    cell_of(pl, p, c);
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                int64_t q[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                for (size_t j = cell_hash(q[0], q[1], q[2]) & (pl->scap - 1); pl->slot[j];
                     j = (j + 1) & (pl->scap - 1)) {
                    const double *o = pl->xyz + 3 * (pl->slot[j] - 1);
                    double d2 = 0.0;
                    for (int k = 0; k < 3; ++k)
                        d2 += (o[k] - p[k]) * (o[k] - p[k]);
                    if (d2 <= pl->tol * pl->tol)
                        return pl->slot[j] - 1;
                }
            }
    return SIZE_MAX;
}

/* Finds or adds p; SIZE_MAX on allocation failure. */
static size_t pool_add(pool *pl, const double *p)
{
    size_t i = pool_find(pl, p);
    if (i != SIZE_MAX)
        return i;
    if (pl->n == pl->cap) {
        size_t cap = pl->cap ? 2 * pl->cap : 256;
        double *x = sk__realloc_array(pl->xyz, 3 * cap * sizeof *x, 1);
        if (!x)
            return SIZE_MAX;
        pl->xyz = x;
        pl->cap = cap;
    }
    if (2 * (pl->n + 1) > pl->scap) {
        size_t scap = pl->scap ? 2 * pl->scap : 1024;
        size_t *slot = sk__calloc_array(scap, sizeof *slot);
        if (!slot)
            return SIZE_MAX;
        for (size_t k = 0; k < pl->n; ++k)
            pool_slot_insert(slot, scap, pl, k);
        sk__free(pl->slot);
        pl->slot = slot;
        pl->scap = scap;
    }
    memcpy(pl->xyz + 3 * pl->n, p, 3 * sizeof(double));
    pool_slot_insert(pl->slot, pl->scap, pl, pl->n);
    return pl->n++;
}

static void pool_free(pool *pl)
{
    sk__free(pl->xyz);
    sk__free(pl->slot);
}

typedef struct bedge {
    size_t v0, v1, mid; /* end vertices, midpoint (in the midpoint pool) */
    unsigned deg;
    unsigned uses;
    double cp[3 * (SK_PATCH_MAX_DEGREE + 1)]; /* v0 -> v1 */
} bedge;

/* One side piece of a face's loop, in loop order. */
typedef struct use {
    size_t edge;
    bool same;          /* traversed from the edge's v0 to v1 */
    double uv0[2], uv1[2]; /* parameter-space ends, in loop direction */
} use;

typedef struct brep {
    pool verts, mids;
    bedge *edges;
    size_t ne, ecap;
    size_t *eslot; /* edge index + 1 by (min vertex, max vertex, midpoint) */
    size_t escap;
    use *uses;
    size_t nu, ucap;
    size_t *face_first; /* nfaces + 1 offsets into uses */
} brep;

static uint64_t edge_hash(size_t a, size_t b, size_t m)
{
    size_t lo = a < b ? a : b, hi = a < b ? b : a;
    return cell_hash((int64_t)lo, (int64_t)hi, (int64_t)m);
}

static bool edge_match(const bedge *e, size_t a, size_t b, size_t m)
{
    return e->mid == m && ((e->v0 == a && e->v1 == b) || (e->v0 == b && e->v1 == a));
}

/* Adds a loop piece: the curve cp (degree deg) from vertex a to vertex b, parameter-space ends
 * uv0 -> uv1. Returns false on allocation failure. */
static bool add_use(brep *br, size_t a, size_t b, const double *cp, unsigned deg,
                    const double uv0[2], const double uv1[2])
{
    double l[3 * (SK_PATCH_MAX_DEGREE + 1)], r[3 * (SK_PATCH_MAX_DEGREE + 1)];
    sk__bezier_halve(cp, deg, l, r);
    size_t m = pool_add(&br->mids, r);
    if (m == SIZE_MAX)
        return false;
    size_t ei = SIZE_MAX;
    if (br->escap)
        for (size_t j = edge_hash(a, b, m) & (br->escap - 1); br->eslot[j];
             j = (j + 1) & (br->escap - 1))
            if (edge_match(&br->edges[br->eslot[j] - 1], a, b, m)) {
                ei = br->eslot[j] - 1;
                break;
            }
    if (ei == SIZE_MAX) {
        if (br->ne == br->ecap) {
            size_t cap = br->ecap ? 2 * br->ecap : 256;
            bedge *e = sk__realloc_array(br->edges, cap * sizeof *e, 1);
            if (!e)
                return false;
            br->edges = e;
            br->ecap = cap;
        }
        if (2 * (br->ne + 1) > br->escap) {
            size_t scap = br->escap ? 2 * br->escap : 1024;
            size_t *slot = sk__calloc_array(scap, sizeof *slot);
            if (!slot)
                return false;
            for (size_t k = 0; k < br->ne; ++k) {
                const bedge *e = &br->edges[k];
                size_t j = edge_hash(e->v0, e->v1, e->mid) & (scap - 1);
                while (slot[j])
                    j = (j + 1) & (scap - 1);
                slot[j] = k + 1;
            }
            sk__free(br->eslot);
            br->eslot = slot;
            br->escap = scap;
        }
        ei = br->ne++;
        bedge *e = &br->edges[ei];
        e->v0 = a;
        e->v1 = b;
        e->mid = m;
        e->deg = deg;
        e->uses = 0;
        memcpy(e->cp, cp, 3 * (deg + 1) * sizeof(double));
        size_t j = edge_hash(a, b, m) & (br->escap - 1);
        while (br->eslot[j])
            j = (j + 1) & (br->escap - 1);
        br->eslot[j] = ei + 1;
    }
    br->edges[ei].uses++;
    if (br->nu == br->ucap) {
        size_t cap = br->ucap ? 2 * br->ucap : 1024;
        use *u = sk__realloc_array(br->uses, cap * sizeof *u, 1);
        if (!u)
            return false;
        br->uses = u;
        br->ucap = cap;
    }
    use *u = &br->uses[br->nu++];
    u->edge = ei;
    u->same = br->edges[ei].v0 == a;
    memcpy(u->uv0, uv0, sizeof u->uv0);
    memcpy(u->uv1, uv1, sizeof u->uv1);
    return true;
}

static void brep_free(brep *br)
{
    pool_free(&br->verts);
    pool_free(&br->mids);
    sk__free(br->edges);
    sk__free(br->eslot);
    sk__free(br->uses);
    sk__free(br->face_first);
}

/* Builds vertices, edges and loops of the tensor patches t[0..nt); stops with *collapsed set at
 * a side collapsed to a point (a singular corner has no B-rep edge here). */
static sk_status build_brep(brep *br, const sk_patch_set *t, double size, bool *collapsed,
                            sk_error *err)
{
    static const double corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    size_t nt = t->count;
    double cell = IGES_CELL_REL * size, tol = IGES_WELD_REL * size;
    br->verts.cell = br->mids.cell = cell;
    br->verts.tol = br->mids.tol = tol;
    sk_status st = SK_OK;
    size_t *cv = sk__malloc_array(4 * (nt ? nt : 1), sizeof *cv);
    br->face_first = sk__malloc_array(nt + 1, sizeof *br->face_first);
    if (!cv || !br->face_first)
        goto nomem;
    for (size_t i = 0; i < nt; ++i)
        for (unsigned k = 0; k < 4; ++k) {
            double q[3];
            sk_patch_edge_point(t, i, k, 0.0, q);
            if ((cv[4 * i + k] = pool_add(&br->verts, q)) == SIZE_MAX)
                goto nomem;
        }
    for (size_t i = 0; i < nt; ++i) {
        br->face_first[i] = br->nu;
        for (unsigned k = 0; k < 4; ++k) {
            double cp[3 * (SK_PATCH_MAX_DEGREE + 1)], l[3 * (SK_PATCH_MAX_DEGREE + 1)],
                r[3 * (SK_PATCH_MAX_DEGREE + 1)];
            unsigned deg = sk_patch_edge_curve(t, i, k, cp);
            size_t a = cv[4 * i + k], b = cv[4 * i + (k + 1) % 4];
            const double *uv0 = corner_uv[k], *uv1 = corner_uv[(k + 1) % 4];
            sk__bezier_halve(cp, deg, l, r);
            size_t vm = pool_find(&br->verts, r);
            if (a == b && vm == a)
                continue; /* a side collapsed to a point (a triangle's s = 0): no edge, the
                             importer adds the degenerated edge */
            if (a == b) { /* a closed side: no B-rep edge here; the caller writes free surfaces */
                *collapsed = true;
                goto done;
            }
            if (vm != SIZE_MAX && vm != a && vm != b) { /* another face's corner: split here */
                double uvm[2] = {0.5 * (uv0[0] + uv1[0]), 0.5 * (uv0[1] + uv1[1])};
                if (!add_use(br, a, vm, l, deg, uv0, uvm) || !add_use(br, vm, b, r, deg, uvm, uv1))
                    goto nomem;
            } else if (!add_use(br, a, b, cp, deg, uv0, uv1)) {
                goto nomem;
            }
        }
    }
    br->face_first[nt] = br->nu;
    goto done;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
done:
    sk__free(cv);
    return st;
}

/* Writes the B-rep entities; *closed tells whether the shell is closed (and a solid written),
 * *edges and *vertices the sizes of the edge and vertex lists. Writes nothing and sets *collapsed
 * when a patch has a side collapsed to a point. */
static sk_status write_brep(sections *s, const sk_patch_set *t, double size, bool pcurves,
                            sk__export_progress *prog, bool *closed, size_t *edges, size_t *vertices, bool *collapsed,
                            sk_error *err)
{
    brep br = {0};
    size_t nt = t->count;
    sk_status st = build_brep(&br, t, size, collapsed, err);
    if (st || *collapsed)
        goto done;
    *closed = br.ne > 0;
    *edges = br.ne;
    *vertices = br.verts.n;
    for (size_t e = 0; e < br.ne; ++e)
        if (br.edges[e].uses != 2)
            *closed = false;
    /* entity numbering (0-based; DE = 2k + 1), in writing order */
    size_t base = *closed ? 1 : 0; /* the solid is entity 0 */
    size_t k_shell = base, k_vlist = base + 1, k_elist = base + 2, k_curve0 = base + 3;
    size_t k_face0 = k_curve0 + br.ne;
    /* face i: surface, pcurves (if any), loop, face at
     * k_face0 + 3 i + face_first[i] + {0, 1.., n+1, n+2} (without pcurves: k_face0 + 3 i + {0, 1, 2}) */
    size_t npc = pcurves ? 1 : 0; /* pcurves per loop piece */
#define K_FACE(i) (k_face0 + 3 * (i) + npc * br.face_first[i])

    if (*closed) {
        sk__iges_packer pp = entity_begin(s, 186);
        sk__iges_pack_size(&pp, de_of(k_shell));
        sk__iges_pack_int(&pp, 1); /* shell orientation agrees with its faces */
        sk__iges_pack_int(&pp, 0); /* no void shells */
        entity_end(s, &pp, 186, 0, ST_INDEPENDENT);
    }
    {
        sk__iges_packer pp = entity_begin(s, 514);
        sk__iges_pack_size(&pp, nt);
        for (size_t i = 0; i < nt; ++i) {
            size_t n = br.face_first[i + 1] - br.face_first[i];
            sk__iges_pack_size(&pp, de_of(K_FACE(i) + npc * n + 2));
            sk__iges_pack_int(&pp, 1); /* face normal is the surface normal */
        }
        entity_end(s, &pp, 514, *closed ? 1 : 2, *closed ? ST_DEPENDENT : ST_INDEPENDENT);
    }
    {
        sk__iges_packer pp = entity_begin(s, 502);
        sk__iges_pack_size(&pp, br.verts.n);
        for (size_t v = 0; v < 3 * br.verts.n; ++v)
            sk__iges_pack_real(&pp, br.verts.xyz[v]);
        entity_end(s, &pp, 502, 1, ST_DEPENDENT);
    }
    {
        sk__iges_packer pp = entity_begin(s, 504);
        sk__iges_pack_size(&pp, br.ne);
        for (size_t e = 0; e < br.ne; ++e) {
            sk__iges_pack_size(&pp, de_of(k_curve0 + e));
            sk__iges_pack_size(&pp, de_of(k_vlist));
            sk__iges_pack_size(&pp, br.edges[e].v0 + 1);
            sk__iges_pack_size(&pp, de_of(k_vlist));
            sk__iges_pack_size(&pp, br.edges[e].v1 + 1);
        }
        entity_end(s, &pp, 504, 1, ST_DEPENDENT);
    }
    for (size_t e = 0; e < br.ne; ++e) { /* 126: one Bezier span, polynomial, not planar */
        const bedge *ed = &br.edges[e];
        sk__iges_packer pp = entity_begin(s, 126);
        sk__iges_pack_int(&pp, (long)ed->deg);
        sk__iges_pack_int(&pp, (long)ed->deg);
        sk__iges_pack_int(&pp, 0); /* PROP1: not planar */
        sk__iges_pack_int(&pp, 0); /* PROP2: open */
        sk__iges_pack_int(&pp, 1); /* PROP3: polynomial */
        sk__iges_pack_int(&pp, 0); /* PROP4: not periodic */
        for (unsigned k = 0; k < 2 * (ed->deg + 1); ++k)
            sk__iges_pack_real(&pp, k <= ed->deg ? 0.0 : 1.0);
        for (unsigned k = 0; k <= ed->deg; ++k)
            sk__iges_pack_real(&pp, 1.0);
        for (unsigned k = 0; k < 3 * (ed->deg + 1); ++k)
            sk__iges_pack_real(&pp, ed->cp[k]);
        sk__iges_pack_real(&pp, 0.0);
        sk__iges_pack_real(&pp, 1.0);
        entity_end(s, &pp, 126, 0, ST_DEPENDENT);
    }
    for (size_t i = 0; i < nt; ++i) {
        size_t f0 = br.face_first[i], n = br.face_first[i + 1] - f0, k0 = K_FACE(i);
        if (sk__export_tick(prog, i)) {
            st = sk__fail(err, SK_ERR_CANCELLED, "cancelled");
            goto done;
        }
        if (s->d_seq + 1 != de_of(k0)) { /* programmer error in the numbering above */
            st = sk__fail(err, SK_ERR_NUMERIC, "IGES: directory numbering mismatch");
            goto done;
        }
        write_surface(s, t, i, ST_DEPENDENT);
        for (size_t j = 0; j < n && pcurves; ++j) { /* pcurve along the edge's own direction */
            const use *u = &br.uses[f0 + j];
            const double *a = u->same ? u->uv0 : u->uv1, *b = u->same ? u->uv1 : u->uv0;
            sk__iges_packer pp = entity_begin(s, 110);
            sk__iges_pack_real(&pp, a[0]);
            sk__iges_pack_real(&pp, a[1]);
            sk__iges_pack_real(&pp, 0.0);
            sk__iges_pack_real(&pp, b[0]);
            sk__iges_pack_real(&pp, b[1]);
            sk__iges_pack_real(&pp, 0.0);
            entity_end(s, &pp, 110, 0, ST_PARAMETRIC);
        }
        {
            sk__iges_packer pp = entity_begin(s, 508);
            sk__iges_pack_size(&pp, n);
            for (size_t j = 0; j < n; ++j) {
                const use *u = &br.uses[f0 + j];
                sk__iges_pack_int(&pp, 0); /* TYPE: edge */
                sk__iges_pack_size(&pp, de_of(k_elist));
                sk__iges_pack_size(&pp, u->edge + 1);
                /* OF: loop direction agrees with the curve */
                sk__iges_pack_int(&pp, u->same ? 1 : 0);
                sk__iges_pack_int(&pp, (long)npc);       /* K: parameter-space curves */
                if (pcurves) {
                    sk__iges_pack_int(&pp, 0); /* ISOP */
                    sk__iges_pack_size(&pp, de_of(k0 + 1 + j));
                }
            }
            entity_end(s, &pp, 508, 1, ST_DEPENDENT);
        }
        {
            sk__iges_packer pp = entity_begin(s, 510);
            sk__iges_pack_size(&pp, de_of(k0));
            sk__iges_pack_int(&pp, 1); /* one loop */
            sk__iges_pack_int(&pp, 1); /* it is the outer loop */
            sk__iges_pack_size(&pp, de_of(k0 + 1 + npc * n));
            entity_end(s, &pp, 510, 1, ST_DEPENDENT);
        }
    }
#undef K_FACE
done:
    brep_free(&br);
    return st;
}

/* Free surfaces: the 128 entities and one 402 (form 1) group of them; false when cancelled. */
static bool write_free_surfaces(sections *s, const sk_patch_set *t, sk__export_progress *prog)
{
    size_t nt = t->count;
    for (size_t i = 0; i < nt; ++i) {
        if (sk__export_tick(prog, i))
            return false;
        write_surface(s, t, i, ST_DEPENDENT);
    }
    sk__iges_packer pp = entity_begin(s, 402);
    sk__iges_pack_size(&pp, nt);
    for (size_t i = 0; i < nt; ++i)
        sk__iges_pack_size(&pp, de_of(i));
    entity_end(s, &pp, 402, 1, ST_INDEPENDENT);
    return true;
}

sk_status sk_export_iges(const char *path, const sk_patch_set *patches,
                         const sk_export_opts *opts, sk_export_stats *stats, sk_error *err)
{
    const sk__unit *unit = sk__unit_lookup(opts ? opts->units : NULL);
    if (!unit)
        return sk__fail(err, SK_ERR_ARG, "unknown unit '%s'", opts->units);
    sk_patch_set ts = {0};
    sk_status st = sk_export_tensor_patches(patches, opts, &ts, err);
    if (st) {
        sk_patch_set_free(&ts);
        return st;
    }
    size_t nt = ts.count;
    bool free_layout = opts && (opts->degenerate_triangles || opts->iges_free_surfaces);
    const char *name = opts && opts->name ? opts->name : "surfkit";
    char when[32], stamp[32];
    sk__export_time(opts, when);
    /* IGES dates: 15HYYYYMMDD.HHNNSS */
    snprintf(stamp, sizeof stamp, "%.4s%.2s%.2s.%.2s%.2s%.2s", when, when + 5, when + 8, when + 11,
             when + 14, when + 17);
    double maxc = sk__patches_max_coord(&ts);
    double size = maxc > 0 ? maxc : 1.0;

    sk__out out = {0};
    sections sec = {0};
    size_t s_seq = 0, g_seq = 0;
    bool closed = false;
    size_t nedges = 0, nverts = 0;
    sk__iges_record(&out,
                    free_layout ? "surfkit: VC1 surface (quartic triangular and bicubic Bezier "
                                  "patches) as IGES entity 128"
                                : "surfkit: VC1 surface (quartic triangular and bicubic Bezier "
                                  "patches) as an IGES B-rep",
                    'S', ++s_seq);

    sk__iges_packer g = {.b = &out, .section = 'G', .seq = &g_seq, .width = 72};
    /* minimum resolution: importers take it as their working tolerance (Open CASCADE with
     * read.precision.mode 0), so the usual 1e-7 model units, not a rounding-level value */
    sk__iges_global(&g, name, path, "surfkit 0.1.0", unit, stamp, fmax(1e-7, IGES_WELD_REL * size),
                    maxc);

    bool collapsed = false;
    sk__export_progress prog;
    sk__export_progress_init(&prog, opts, nt);
    /* the regular split faces keep their parameter-space lines; the default one-face-per-triangle
     * layout leaves them out unless asked (Open CASCADE projects the edges, which costs open
     * time, see bench/export.sh) */
    bool pcurves = !sk__export_degenerate(opts) || (opts && opts->iges_pcurves);
    if (!free_layout &&
        (st = write_brep(&sec, &ts, size, pcurves, &prog, &closed, &nedges, &nverts, &collapsed,
                                err)))
        goto done;
    if ((free_layout || collapsed) && !write_free_surfaces(&sec, &ts, &prog)) {
        st = sk__fail(err, SK_ERR_CANCELLED, "cancelled");
        goto done;
    }
    sk__out_bytes(&out, sec.d.buf ? sec.d.buf : "", sec.d.len);
    sk__out_bytes(&out, sec.p.buf ? sec.p.buf : "", sec.p.len);
    char term[256];
    snprintf(term, sizeof term, "S%07zuG%07zuD%07zuP%07zu", s_seq, g_seq, sec.d_seq, sec.p_seq);
    sk__iges_record(&out, term, 'T', 1);
    if (sec.d.failed || sec.p.failed)
        out.failed = SK_ERR_NOMEM;
    if (sk__export_tick(&prog, nt)) {
        st = sk__fail(err, SK_ERR_CANCELLED, "cancelled");
        goto done;
    }
    st = sk__out_write_file(&out, path, err);
    if (st == SK_OK && stats) {
        memset(stats, 0, sizeof *stats);
        stats->faces = nt;
        stats->bytes = out.len;
        stats->edges = nedges;
        stats->vertices = nverts;
        stats->solid = closed;
    }
done:
    sk__out_free(&out);
    sk__out_free(&sec.d);
    sk__out_free(&sec.p);
    sk_patch_set_free(&ts);
    return st;
}
