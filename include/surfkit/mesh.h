/* surfkit meshes.
 *
 * Two representations:
 *  - sk_soup: indexed faces as read from a file (any polygon sizes, possibly defective). Readers
 *    produce it, writers consume it, sk_soup_validate reports every defect of it.
 *  - sk_mesh: an index-based half-edge mesh in struct-of-arrays form (pmp-library / OpenMesh
 *    design). Half-edges come in pairs, opposite(h) = h ^ 1, so edge e owns half-edges 2e, 2e+1.
 *    Built only from manifold, consistently oriented input; algorithms work on it.
 */
#ifndef SURFKIT_MESH_H
#define SURFKIT_MESH_H

#include "surfkit/core.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Soup: indexed faces
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_soup {
    size_t num_vertices;
    size_t num_faces;
    double *positions;      /* 3 * num_vertices */
    double *normals;        /* 3 * num_vertices, or NULL */
    double *uvs;            /* 2 * num_vertices, or NULL */
    uint32_t *face_offsets; /* num_faces + 1; face f has indices face_indices[offsets[f] .. offsets[f+1]) */
    uint32_t *face_indices; /* face_offsets[num_faces] indices; may be out of range in a bad file */
    /* capacities (managed by the push functions) */
    size_t cap_vertices, cap_faces, cap_indices;
    /* Per-corner (wedge) attributes, as OBJ's vt / vn index spaces or PLY's face texcoord list:
     * a corner c (an index into face_indices) has the uv wedge_uvs[2 corner_uv[c]] (SK_INVALID:
     * none). NULL when the file has none; set with sk_soup_set_corner_uvs / _normals after the
     * faces. The per-vertex uvs / normals above stay as well (the first corner's value). */
    size_t num_wedge_uvs, num_wedge_normals;
    double *wedge_uvs;        /* 2 * num_wedge_uvs */
    double *wedge_normals;    /* 3 * num_wedge_normals */
    uint32_t *corner_uv;      /* face_offsets[num_faces] entries, or NULL */
    uint32_t *corner_normal;  /* face_offsets[num_faces] entries, or NULL */
} sk_soup;

/* Creates an empty soup with reserved room; attribute arrays are allocated when has_normals /
 * has_uvs is set. */
SK_API sk_status sk_soup_create(size_t reserve_vertices, size_t reserve_faces, size_t reserve_indices,
                                bool has_normals, bool has_uvs, sk_soup **out, sk_error *err);
SK_API void sk_soup_destroy(sk_soup **soup);

/* Appends a vertex (normal / uv may be NULL when the soup has none; ignored when it has none). */
SK_API sk_status sk_soup_push_vertex(sk_soup *soup, const double pos[3], const double normal[3],
                                     const double uv[2]);
/* Appends a face with n indices (n may be < 3 in a defective file: it is kept and reported). */
SK_API sk_status sk_soup_push_face(sk_soup *soup, const uint32_t *indices, size_t n);
/* Adds (zeroed) normal / uv arrays if absent. */
SK_API sk_status sk_soup_add_normals(sk_soup *soup);
SK_API sk_status sk_soup_add_uvs(sk_soup *soup);

/* Replaces the per-corner uvs (normals): n values (2 (3) doubles each) and one index per corner
 * of the faces pushed so far (face_offsets[num_faces] entries, each < n or SK_INVALID); copied.
 * values == NULL and corner == NULL removes them. SK_ERR_ARG on an index out of range. */
SK_API sk_status sk_soup_set_corner_uvs(sk_soup *soup, size_t n, const double *values,
                                        const uint32_t *corner);
SK_API sk_status sk_soup_set_corner_normals(sk_soup *soup, size_t n, const double *values,
                                            const uint32_t *corner);

/* What sk_soup_triangulate split. */
typedef struct sk_triangulate_stats {
    size_t quads;     /* faces of 4 vertices */
    size_t polygons;  /* faces of 5 or more */
    size_t triangles; /* triangles they became */
} sk_triangulate_stats;

/* A copy of soup whose polygons are triangles: a quad by its shorter diagonal (0-2 on a tie), a
 * larger polygon by ear clipping in the plane of its Newell normal (the ear with the shortest
 * diagonal first; a polygon that is not simple in that plane is finished as a fan). A diagonal
 * that is already an edge of the soup (opposite corners of a quad joined outside it) is avoided
 * where the polygon allows, since it would make that edge non-manifold. The
 * triangles of a face take its place in the face order and keep its orientation; vertices,
 * per-vertex and per-corner attributes are kept (each corner keeps its uv and normal). Faces of
 * fewer than 4 vertices, and polygons with an index out of range, are copied as they are (for
 * validation to report). stats may be NULL. *out is a new soup (NULL on error). */
SK_API sk_status sk_soup_triangulate(const sk_soup *soup, sk_soup **out,
                                     sk_triangulate_stats *stats, sk_error *err);

static inline size_t sk_soup_face_size(const sk_soup *s, size_t f)
{
    return s->face_offsets[f + 1] - s->face_offsets[f];
}

/* ---------------------------------------------------------------------------------------------
 * Validation: every defect class, counted and with the first few offending elements
 * ------------------------------------------------------------------------------------------- */

#define SK_DEFECT_EXAMPLES 8

typedef struct sk_defect {
    size_t count;
    size_t num_examples;
    /* element ids; for edge defects (a[i], b[i]) is the vertex pair, else only a[i] is used */
    uint32_t a[SK_DEFECT_EXAMPLES];
    uint32_t b[SK_DEFECT_EXAMPLES];
} sk_defect;

typedef struct sk_validation {
    size_t vertices, faces, edges; /* edges: distinct undirected vertex pairs of valid faces */
    size_t triangles, quads, polygons; /* faces by size (polygons: 5 or more) */
    size_t boundary_edges;
    size_t boundary_loops;  /* loops walked along boundary edges */
    size_t components;      /* edge-connected components of faces (unreferenced vertices excluded) */
    long euler_characteristic; /* V - E + F over referenced vertices and valid faces */
    long genus;             /* sum over components of (2 - chi_c - b_c) / 2 (orientable surfaces) */
    bool genus_defined;     /* false when some component has odd 2 - chi - b or is non-manifold */

    sk_defect out_of_range;          /* faces with an index >= vertices (a: face, b: the index) */
    sk_defect small_faces;           /* faces with fewer than 3 indices */
    sk_defect repeated_vertex_faces; /* faces that use a vertex twice */
    sk_defect nonfinite_vertices;    /* NaN or inf coordinates */
    sk_defect unreferenced_vertices;
    sk_defect degenerate_faces;      /* zero area relative to the face's size */
    sk_defect duplicate_faces;       /* same vertex set as an earlier face (a: face, b: earlier) */
    sk_defect non_manifold_edges;    /* more than two faces */
    sk_defect orientation_conflicts; /* two faces use the edge in the same direction */
    sk_defect non_manifold_vertices; /* more than one fan of faces */

    /* Geometry over valid faces */
    double bbox_min[3], bbox_max[3];
    double edge_min, edge_max, edge_mean;
    double min_angle_deg, max_angle_deg;    /* interior angles of valid triangles */
    double angle_deficit_sum;       /* Alboul & Echeverria: sum of angle deficits */
    double gauss_bonnet_error;      /* angle_deficit_sum - 2 pi chi */
    double area;
} sk_validation;

/* Fills rep with the full report; only allocation failure makes it fail. */
SK_API sk_status sk_soup_validate(const sk_soup *soup, sk_validation *rep, sk_error *err);

/* True when the soup can become an sk_mesh (no index, size, repeat, non-manifold or orientation
 * defect, finite coordinates). */
SK_API bool sk_validation_is_manifold(const sk_validation *rep);

/* Relative tolerance for degenerate faces: twice the area <= SK_DEGENERATE_REL * (longest edge)^2,
 * i.e. the smallest angle of the face is below about 1e-12 radians. */
#define SK_DEGENERATE_REL 1e-12

/* ---------------------------------------------------------------------------------------------
 * Half-edge mesh
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_mesh {
    size_t num_vertices;  /* including deleted ones until sk_mesh_compact */
    size_t num_halfedges; /* always even: edge e = half-edges 2e, 2e + 1 */
    size_t num_faces;
    size_t cap_vertices, cap_halfedges, cap_faces;

    /* vertex properties */
    double *positions;  /* 3 per vertex */
    double *normals;    /* 3 per vertex, or NULL */
    double *uvs;        /* 2 per vertex, or NULL */
    uint32_t *v_halfedge; /* one outgoing half-edge; a boundary one for boundary vertices;
                             SK_INVALID for isolated vertices */

    /* half-edge connectivity */
    uint32_t *h_vertex; /* the vertex the half-edge points to */
    uint32_t *h_next;
    uint32_t *h_prev;
    uint32_t *h_face;   /* SK_INVALID for a boundary half-edge */

    /* face connectivity */
    uint32_t *f_halfedge;

    /* per-corner (wedge) uvs, or NULL: the corner at sk_from(h) in face sk_face(h) has the uv
     * wedge_uvs[2 h_wedge_uv[h]] (SK_INVALID for boundary half-edges and corners without one).
     * Built from / written to the soup's corner_uv; copied and compacted with the mesh. */
    size_t num_wedge_uvs;
    double *wedge_uvs;
    uint32_t *h_wedge_uv; /* cap_halfedges entries when present */
    /* per-corner (wedge) normals, the same way (OBJ vn per corner; the soup's corner_normal):
     * the normal at sk_from(h) in face sk_face(h) is wedge_normals[3 h_wedge_normal[h]]. Two
     * faces whose corners at a vertex hold different normals meet at a crease there. */
    size_t num_wedge_normals;
    double *wedge_normals;
    uint32_t *h_wedge_normal; /* cap_halfedges entries when present */

    /* deletion flags (0 alive, 1 deleted); sk_mesh_compact removes deleted elements */
    uint8_t *v_deleted;
    uint8_t *e_deleted; /* per edge (= per half-edge pair) */
    uint8_t *f_deleted;
    size_t num_deleted_vertices, num_deleted_edges, num_deleted_faces;
} sk_mesh;

static inline uint32_t sk_opp(uint32_t h) { return h ^ 1u; }
static inline uint32_t sk_edge(uint32_t h) { return h >> 1; }
static inline uint32_t sk_to(const sk_mesh *m, uint32_t h) { return m->h_vertex[h]; }
static inline uint32_t sk_from(const sk_mesh *m, uint32_t h) { return m->h_vertex[h ^ 1u]; }
static inline uint32_t sk_next(const sk_mesh *m, uint32_t h) { return m->h_next[h]; }
static inline uint32_t sk_prev(const sk_mesh *m, uint32_t h) { return m->h_prev[h]; }
static inline uint32_t sk_face(const sk_mesh *m, uint32_t h) { return m->h_face[h]; }
static inline bool sk_is_boundary_h(const sk_mesh *m, uint32_t h) { return m->h_face[h] == SK_INVALID; }
static inline bool sk_is_boundary_e(const sk_mesh *m, uint32_t e)
{
    return m->h_face[2 * e] == SK_INVALID || m->h_face[2 * e + 1] == SK_INVALID;
}
static inline bool sk_is_boundary_v(const sk_mesh *m, uint32_t v)
{
    uint32_t h = m->v_halfedge[v];
    return h == SK_INVALID || m->h_face[h] == SK_INVALID;
}
static inline size_t sk_num_edges(const sk_mesh *m) { return m->num_halfedges / 2; }

/* One-ring iteration, ordered. Outgoing half-edges of v in turn: start at m->v_halfedge[v] (the
 * boundary one for a boundary vertex) and step with sk_ccw_out; for a boundary vertex the first
 * half-edge has no face on its left, every following one has. Loop until back at the start:
 *
 *     uint32_t h0 = m->v_halfedge[v], h = h0;
 *     if (h0 != SK_INVALID) do { ...; h = sk_cw_out(m, h); } while (h != h0);
 *
 * sk_cw_out turns clockwise (next(opp(h))), sk_ccw_out counter-clockwise (opp(prev(h))), seen
 * from the side the face normals point to. */
static inline uint32_t sk_cw_out(const sk_mesh *m, uint32_t h) { return m->h_next[h ^ 1u]; }
static inline uint32_t sk_ccw_out(const sk_mesh *m, uint32_t h) { return m->h_prev[h] ^ 1u; }

/* Number of edges (= faces, counting the boundary gap as none) around v. */
SK_API size_t sk_mesh_valence(const sk_mesh *m, uint32_t v);
/* Number of vertices of face f. */
SK_API size_t sk_mesh_face_size(const sk_mesh *m, uint32_t f);

/* Builds a half-edge mesh from a soup; fails with SK_ERR_TOPOLOGY naming the first defect (use
 * sk_soup_validate for the full report). Normals and uvs are copied when the soup has them.
 * Unreferenced vertices become isolated vertices (v_halfedge == SK_INVALID). */
SK_API sk_status sk_mesh_from_soup(const sk_soup *soup, sk_mesh **out, sk_error *err);

/* Builds from plain arrays: positions (3 * nv), polygon faces given by offsets/indices. */
SK_API sk_status sk_mesh_from_faces(size_t nv, const double *positions, size_t nf, const uint32_t *offsets,
                                    const uint32_t *indices, sk_mesh **out, sk_error *err);

/* Converts the (compacted or not) mesh to a soup; deleted elements are skipped and indices
 * renumbered. */
SK_API sk_status sk_mesh_to_soup(const sk_mesh *mesh, sk_soup **out, sk_error *err);

SK_API sk_status sk_mesh_copy(const sk_mesh *mesh, sk_mesh **out, sk_error *err);
SK_API void sk_mesh_destroy(sk_mesh **mesh);

/* Optional property arrays (zero-filled when created). */
SK_API sk_status sk_mesh_add_normals(sk_mesh *mesh, sk_error *err);
SK_API sk_status sk_mesh_add_uvs(sk_mesh *mesh, sk_error *err);

/* Sets the per-corner uvs: n wedge values (2 doubles each, copied) and per half-edge indices
 * (num_halfedges entries, copied; SK_INVALID allowed). values == NULL removes them. */
SK_API sk_status sk_mesh_set_wedge_uvs(sk_mesh *mesh, size_t n, const double *values,
                                       const uint32_t *h_wedge, sk_error *err);
/* The same for the per-corner normals (3 doubles each). */
SK_API sk_status sk_mesh_set_wedge_normals(sk_mesh *mesh, size_t n, const double *values,
                                           const uint32_t *h_wedge, sk_error *err);

/* Room for more elements (mutating algorithms call this before adding). */
SK_API sk_status sk_mesh_reserve(sk_mesh *mesh, size_t vertices, size_t halfedges, size_t faces,
                                 sk_error *err);
/* Appends elements; return the new index (SK_INVALID on allocation failure). Connectivity of the
 * new elements is SK_INVALID and must be set by the caller. */
SK_API uint32_t sk_mesh_new_vertex(sk_mesh *mesh, const double pos[3]);
SK_API uint32_t sk_mesh_new_edge(sk_mesh *mesh); /* returns the first half-edge 2e */
SK_API uint32_t sk_mesh_new_face(sk_mesh *mesh);

/* Removes deleted elements and renumbers the rest, keeping relative order. If the map arrays are
 * not NULL they receive old -> new indices (SK_INVALID for removed elements); vmap has
 * num_vertices entries, fmap num_faces entries (sizes before compaction). */
SK_API sk_status sk_mesh_compact(sk_mesh *mesh, uint32_t *vmap, uint32_t *fmap, sk_error *err);

/* Checks every connectivity invariant (next/prev inverse, faces closed, opposite pairs, vertex
 * half-edge is boundary when possible, no two fans); returns SK_ERR_TOPOLOGY with the first
 * violation. Used by tests and after mutating algorithms. */
SK_API sk_status sk_mesh_check(const sk_mesh *mesh, sk_error *err);

/* ---------------------------------------------------------------------------------------------
 * Topology and geometry queries
 * ------------------------------------------------------------------------------------------- */

typedef struct sk_loops {
    size_t count;
    uint32_t *offsets;   /* count + 1 */
    uint32_t *halfedges; /* boundary half-edges of each loop, in order (loop i: offsets[i]..) */
    double *lengths;     /* count: length of each loop */
} sk_loops;

/* All boundary loops, each as an ordered cycle of boundary half-edges (vertex sk_from(h) in turn). */
SK_API sk_status sk_mesh_boundary_loops(const sk_mesh *mesh, sk_loops *loops, sk_error *err);
SK_API void sk_loops_free(sk_loops *loops);

typedef struct sk_topology {
    size_t vertices, edges, faces, boundary_loops, components;
    long euler_characteristic;
    long genus; /* summed over components */
} sk_topology;

/* Counts over alive, non-isolated elements. face_component (may be NULL; num_faces entries)
 * receives the component id of each face. */
SK_API sk_status sk_mesh_topology(const sk_mesh *mesh, sk_topology *top, uint32_t *face_component,
                                  sk_error *err);

/* Face normal (Newell's method for polygons), unit length; returns twice the area for triangles
 * (the length of the unnormalised Newell vector, area * 2 in general). */
SK_API double sk_mesh_face_normal(const sk_mesh *mesh, uint32_t f, double n[3]);
/* Area of face f. */
SK_API double sk_mesh_face_area(const sk_mesh *mesh, uint32_t f);
SK_API double sk_mesh_edge_length(const sk_mesh *mesh, uint32_t e);
SK_API void sk_mesh_bbox(const sk_mesh *mesh, double min[3], double max[3]);
/* Length of the bounding-box diagonal: the model size tolerances are relative to. */
SK_API double sk_mesh_diagonal(const sk_mesh *mesh);

/* Coordinate range the parametrizations and smooth surfaces work in (products of four
 * coordinates must stay finite and above the subnormals): every coordinate at most
 * SK_COORD_MAX in magnitude and a bounding-box diagonal of at least SK_COORD_MIN_SIZE. */
#define SK_COORD_MAX 1e50
#define SK_COORD_MIN_SIZE 1e-50
/* SK_ERR_TOPOLOGY (bad input) naming the range when the alive vertices leave it. */
SK_API sk_status sk_mesh_check_scale(const sk_mesh *mesh, sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
