/* Internal pieces of the VC1 construction shared by the files of src/smooth. */
#ifndef SK_SMOOTH_INTERNAL_H
#define SK_SMOOTH_INTERNAL_H

#include "surfkit/smooth.h"
#include "bezier/bezier_internal.h"

/* Degree-elevation factor Delta of eq. (1): 3/4 for a (quartic) triangle, 1 for a bicubic quad. */
static inline double sk__delta(size_t face_size) { return face_size == 3 ? 0.75 : 1.0; }

/* Wire frame targets (paper section 4), one per half-edge h of the triangle/quad mesh: the cubic
 * control point next to from(h) on edge h, written to target[3 h]. Fails naming the edge when its
 * normals make a cubic impossible. */
sk_status sk__wireframe_targets(const sk_mesh *m, const double *normals, double *target,
                                sk_error *err);

/* The same with per-half-edge normals cn (cn[h]: the normal at from(h) on face(h)'s side; NULL =
 * normals per vertex), edges with skip[e] set left to the caller (NULL = none). */
sk_status sk__wireframe_targets_cn(const sk_mesh *m, const double *normals, const double *cn,
                                   const uint8_t *skip, double *target, sk_error *err);

/* Creases (crease_g0.c, docs/creases.md). sk__crease_flags: flags[e] = 1 (sk_num_edges(m)
 * entries, written in full) for the interior edges of m joining one of the npairs vertex pairs;
 * returns their number. sk__crease_setup: the crease flags of m (the edges of src flagged in
 * src_crease, by their vertex ids) and the per-half-edge normals
 * (the sector normal at from(h) on face(h)'s side: the angle-weighted normal of the sector's
 * corners where a vertex has two or more sectors, or the file's per-corner normal of the
 * sector's first edge in file (the input mesh, may be NULL), else normals[from(h)]); both NULL
 * when none is an edge of m. sk__crease_targets: the wire frame target of every crease half-edge, on the
 * line V + t (n1 x n2) shared by both sides. */
size_t sk__crease_flags(const sk_mesh *m, const uint32_t *pairs, size_t npairs, uint8_t *flags);
sk_status sk__crease_setup(const sk_mesh *m, const double *normals, const sk_mesh *src,
                           const uint8_t *src_crease, const sk_mesh *file, uint8_t **crease_e,
                           double **cn, sk_error *err);
/* sk_mesh_crease_edges, and hinges[e] = 1 (NULL: not wanted; ne entries, written in full) for
 * the crease edges that are fold hinges (crease.c step 4b: the sharpest edge of a face whose
 * edges were all sharp, its faces more than 90 degrees apart). */
sk_status sk__crease_edges_hinges(const sk_mesh *mesh, const sk_crease_opts *opts, uint8_t *crease,
                                  uint8_t *hinges, size_t *count, sk_error *err);
/* Sets crease[e] for the interior edges of m whose per-corner normals (m->h_wedge_normal, the
 * file's) differ across the edge at one of its ends; returns how many it set that were not set. */
size_t sk__corner_normal_creases(const sk_mesh *m, uint8_t *crease);
/* Drops (clears) the crease edges at vertices with two of them that the construction cannot
 * follow: both crease curves share one tangent line there, so the two edges must leave the
 * vertex on opposite sides of it and within 75 degrees of it (a crease that turns back, or a
 * loop of three creases round one face, is not a feature line). Returns the edges dropped. */
size_t sk__crease_validate(const sk_mesh *m, uint8_t *crease);
/* Clears the crease lines (connected crease edges) through vertex v; returns the edges. */
size_t sk__crease_drop_at(const sk_mesh *m, uint8_t *crease, uint32_t v);
void sk__crease_targets(const sk_mesh *m, const uint8_t *ce, const double *cn, double *target);

/* Edge deletion (sk_edge_deletion) that keeps the edges with crease[e] set (NULL = none): their
 * vertices are boundary-like (no parity, paths end there), so crease edges are never deleted. */
sk_status sk__edge_deletion_creases(const sk_mesh *m, const uint8_t *crease, sk_mesh **out,
                                    uint32_t **deleted, sk_edge_deletion_stats *stats,
                                    sk_error *err);

/* sk__edge_deletion_creases warm-started from hint (nhint vertex pairs of m, e.g. the edges an
 * earlier deletion over a mesh that agrees with m away from a few vertex splits deleted): the
 * hinted edges that may be deleted are kept where they leave no triangle with two deleted edges,
 * and only the vertices whose parity they leave wrong are paired (so the result changes only
 * near where m differs; it is an edge deletion, not the near-minimal one of m alone). avoid (per
 * edge of m, may be NULL): edges the paths do not delete (as those making a quad corner too
 * wide; an even vertex with all its edges avoided still keeps one). */
sk_status sk__edge_deletion_hinted(const sk_mesh *m, const uint8_t *crease, const uint32_t *hint,
                                   size_t nhint, const uint8_t *avoid, sk_mesh **out,
                                   uint32_t **deleted, sk_edge_deletion_stats *stats,
                                   sk_error *err);
/* sk_edge_deletion that also returns the vertex of every cycle exchange applied, in order
 * (*trace, *ntrace; free() it); try_all: the exchanges' ordered pass tries every even vertex
 * instead of only those its parallel pre-pass (or an exchange nearby) selects. For the tests:
 * both must apply the same exchanges in the same order. */
sk_status sk__edge_deletion_traced(const sk_mesh *m, bool try_all, uint32_t **trace,
                                   size_t *ntrace, sk_mesh **out, sk_edge_deletion_stats *stats,
                                   sk_error *err);
/* sk_smooth_build with the edge deletion warm-started from hint (sk__edge_deletion_hinted; NULL:
 * sk_smooth_build), nhint pairs of the mesh's vertex ids */
sk_status sk__smooth_build_hinted(const sk_mesh *mesh, const sk_smooth_opts *opts,
                                  const uint32_t *hint, size_t nhint, sk_smooth **out,
                                  sk_error *err);

/* The normal at corner i of patch p: its sector's (s->corner_normals) or the vertex normal. */
/* The half-edge from a to b in m, or SK_INVALID. */
static inline uint32_t sk__find_halfedge(const sk_mesh *m, uint32_t a, uint32_t b)
{
    uint32_t h0 = m->v_halfedge[a], h = h0;
    if (h0 == SK_INVALID)
        return SK_INVALID;
    do {
        if (sk_to(m, h) == b)
            return h;
        h = sk_cw_out(m, h);
    } while (h != h0);
    return SK_INVALID;
}

static inline const double *sk__corner_normal(const sk_smooth *s, size_t p, unsigned i)
{
    const sk_patch *pa = &s->surface.patches[p];
    if (!s->corner_normals)
        return s->normals + 3 * (size_t)pa->corner_ids[i];
    uint32_t h = s->config->f_halfedge[p];
    while (i--)
        h = s->config->h_next[h];
    return s->corner_normals + 3 * (size_t)h;
}

/* r_m of eq. (7) for every face: Delta/3 (triangles) or 1/4 (quads) times the sum over the corners
 * of the area of (corner, its two targets). */
void sk__patch_ratios(const sk_mesh *m, const double *target, double *r);

/* nu of the edge between the patch containing P_{m+1} (up) and the one containing P_{m-1} (down):
 * nu = -r_up / r_down, the orientation that agrees with eq. (3) (see docs/VC1-NOTES.md 1). */
double sk__nu(double r_up, double r_down);

/* One vertex system (8) in the tangent plane, in 2D coordinates relative to V.
 * n_edges edge directions in counter-clockwise order; closed = interior vertex (cyclic), else a
 * chain whose first and last edges are boundary edges and whose constraints are the interior edges
 * 1 .. n_edges - 2. For constraint m (edge m): du[m] = Delta of the patch after edge m (containing
 * p_{m+1}), dd[m] = Delta of the patch before it, nu[m]. */
#define SK_VSYS_MAX 64

/* Loops of the smooth build over fewer vertices, faces or patches than this run on one thread:
 * below it the team's waiting workers spin for longer than the loop saves (cow, 5.8k triangles:
 * the deletion 2 -> 15 CPU ms with 2 threads, the repair with its re-routed rounds 88 -> 165;
 * the wall seconds gained were under 3 ms per loop). The results are the same either way. */
#define SK_SMOOTH_TEAM_MIN 10000
typedef struct sk__vsys {
    int n_edges;
    int closed;
    double pstar[2 * SK_VSYS_MAX];
    double du[SK_VSYS_MAX], dd[SK_VSYS_MAX], nu[SK_VSYS_MAX];
    /* results */
    double p[2 * SK_VSYS_MAX];
    double w[SK_VSYS_MAX];  /* w_1^m of each constraint (0 for boundary edges) */
    double residual;        /* max |c| relative to the scale of the targets */
    int iterations;
    int newton_tries;       /* Newton steps tried (taken or undone) */
    int used_fallback;
    int relaxed;            /* set by the caller when the targets were relaxed */
    /* chains only: the first / last point is fixed at its target (a crease edge, whose tangent
     * point both sides share: docs/creases.md); 0 = free (a boundary edge). Set by the caller. */
    int fixed_first, fixed_last;
} sk__vsys;

/* Solves min sum |P_m - P*_m|^2 subject to (8) by Gauss-Newton / SQP on (P, w). Returns 0 when the
 * constraints hold to rounding (residual <= 1e-12), else -1 (the best iterate is left in p, w).
 * Newton steps are tried after GN_FIRST Gauss-Newton steps, until NEWTON_REJECTS (40) in a row
 * were undone (vertex_system.c). */
int sk__vsys_solve(sk__vsys *s);

/* sk__vsys_solve of count systems, ret[i] its return value for sys[i]: the same results to the
 * bit, the closed systems of 3, 5 and 7 edges solved SK_VSYS_LANES at a time in lockstep (their
 * steps are chains of dependent divisions; interleaved they overlap). */
#define SK_VSYS_LANES 4
void sk__vsys_solve_lanes(sk__vsys *const *sys, int count, int *ret);

/* A memo of solves (vertex_system.c): the solver is deterministic, so inputs equal to the bit
 * (n_edges, closed, fixed_first, fixed_last, pstar, du, dd, nu) give the same p, w, residual,
 * iterations, used_fallback and return value; a repeated solve is copied from the memo. The
 * regularity repair keeps one (its variants of one vertex step through the same relaxed targets
 * inside sk__vc1_solve_vertex). Not thread-safe: one memo per thread. */
typedef struct sk__vsys_memo sk__vsys_memo;
sk__vsys_memo *sk__vsys_memo_create(void); /* NULL when out of memory (then solve without) */
void sk__vsys_memo_destroy(sk__vsys_memo *memo);
/* sk__vsys_solve through memo (NULL: plain sk__vsys_solve) */
int sk__vsys_solve_memo(sk__vsys *s, sk__vsys_memo *memo);

/* Smallest and largest counter-clockwise angle (radians) between consecutive edges of a patch
 * corner around the vertex (n_edges pairs if closed, n_edges - 1 else). */
void sk__vsys_angles(const sk__vsys *s, double *min_angle, double *max_angle);

/* The regularity test of the continuity report: true when patch p has a vanishing normal
 * (|du x dv| <= 1e-10 |du| |dv| at the centre) or a normal turned away from the sum of its corner
 * normals, found on a grid of 9 x 9 parameters (triangles: the 45 with u + v <= 1) unless the
 * control net certifies it regular everywhere (sk__patch_certify, src/bezier). cone_regular (may be NULL):
 * the Ginkel-Peters-Umlauf cone test. */
bool sk__patch_singular(const sk_smooth *s, size_t p, bool *cone_regular);
/* The same test with the sample tried first: *first on entry (0 .. 80; beyond the grid: none),
 * on a singular answer the sample that failed (the repair keeps one per patch). */
bool sk__patch_singular_from(const sk_smooth *s, size_t p, bool *cone_regular, uint8_t *first);

/* The patches whose control-point box overlaps the box of a patch sharing no corner with it
 * (box_candidates.c): cand[p] = 1 for those (np bytes), the only ones that can cross another. */
sk_status sk__patch_box_candidates(const sk_patch_set *set, uint8_t *cand, sk_error *err);
/* The pairs themselves (box_candidates.c): *pairs (sk__malloc_array, free with sk__free) gets the
 * *npairs keys (a << 32) | b, a < b, sorted, of the patch pairs sharing no corner whose boxes
 * (padded by 1e-9 of the largest coordinate) overlap. *pairs is NULL where the grid cannot give
 * them (a crowded cell, too many big boxes, a non-finite or all-point set): the caller then
 * falls back to sk__patch_box_candidates. */
sk_status sk__patch_box_pairs(const sk_patch_set *set, uint64_t **pairs, size_t *npairs,
                              sk_error *err);

/* Parity split (parity_split.c): every closed component of m with an odd number of vertices gets
 * its longest edge split at the midpoint of its wire frame curve (normals there: the mean of the
 * end normals made orthogonal to the curve). *out is the new mesh with its normals in
 * *out_normals, or NULL when no component needs a split; *splits counts them. */
sk_status sk__split_odd_components(const sk_mesh *m, const double *normals, sk_mesh **out,
                                   double **out_normals, size_t *splits, sk_error *err);

/* The triangulation pass before the edge deletion (edge_flips.c): flips edges of the triangle
 * mesh m in place (same vertices; normals per vertex) to remove slivers and near-folds, bounded
 * by a dihedral-angle limit so the shape is kept; *flipped counts the flips. Drops per-corner uvs.
 * The _keep variant never flips the edges with keep[e] set (crease edges; NULL = none). */
sk_status sk__improve_triangulation(sk_mesh *m, const double *normals, size_t *flipped,
                                    sk_error *err);
/* One refinement of base (refine_base.c): the edges e with split[e] get their midpoint as a new
 * vertex (numbered from base's vertex count on, in edge order; *out_split of them), with the
 * normalised sum of the edge's unit facet normals as normal; each triangle becomes 4, 3 or 2 (the
 * quad left by two split edges cut along its shorter diagonal). *out_normals: the old normals,
 * then the new ones; *out_creases: the crease pairs that are edges of base, split ones as their
 * two halves (*out_ncreases pairs). */
/* split[e] (sk_num_edges(base) flags) for the uniform refinement of the base: every edge but the
 * near-folds, whose facet normals are more than fold_deg apart, except that a closed component
 * whose count of split edges would be odd gets its flattest near-fold split too (*count: the
 * edges split). */
#define SK_REFINE_FOLD_DEG 120.0
sk_status sk__refine_base_flags(const sk_mesh *base, double fold_deg, uint8_t *split,
                                size_t *count, sk_error *err);
sk_status sk__refine_base_split(const sk_mesh *base, const double *normals, const uint8_t *split,
                                const uint32_t *creases, size_t ncreases, sk_mesh **out,
                                double **out_normals, uint32_t **out_creases, size_t *out_ncreases,
                                size_t *out_split, sk_error *err);
sk_status sk__improve_triangulation_keep(sk_mesh *m, const double *normals, const uint8_t *keep,
                                         size_t *flipped, sk_error *err);

/* The parity pass after sk__improve_triangulation_keep (edge_flips.c, opts.parity_flips): flips
 * that make even interior vertices odd (four or three of the four vertices of the flip), where
 * the new edge is no crease, no new face agrees worse with its corner normals than the better
 * old one and the smallest angle keeps 0.8 of what it was; crease and boundary vertices
 * and the keep edges are left alone. The edge deletion then needs fewer deletions. *flipped
 * counts the flips. */
sk_status sk__parity_flips(sk_mesh *m, const double *normals, const uint8_t *keep,
                           size_t *flipped, sk_error *err);

/* Estimated normals at folded stars (fold_normals.c): where a face around v is more than 90
 * degrees off normals[v], the normal becomes the direction with the largest smallest cosine to
 * the faces around v when that sees every face within see_deg degrees (SK_FOLD_SEE_DEG, or
 * SK_FOLD_HINGE_SEE_DEG at the ends of fold hinges) and gains; vertices with skip[v] set (skip
 * may be NULL) are left alone; returns how many vertices changed. */
#define SK_FOLD_SEE_DEG 84.0
#define SK_FOLD_HINGE_SEE_DEG 85.0
size_t sk__fold_normals(const sk_mesh *m, double *normals, const uint8_t *skip, double see_deg);

/* Flips the interior edge of half-edge h of a triangle mesh (edge_flips.c): the two triangles
 * abc, bad become cdb... the edge joins the two opposite vertices instead, its id kept. */
void sk__flip_edge(sk_mesh *m, uint32_t h);
/* sk__flip_edge where the flip is valid: an interior edge, not flagged in keep (may be NULL),
 * whose new edge is not an edge yet and whose new triangles are not degenerate, each end keeping
 * three faces; returns whether it flipped. */
bool sk__flip_edge_if_valid(sk_mesh *m, uint32_t h, const uint8_t *keep);

/* The quality test of a flip chosen for the edge deletion (edge_flips.c): the parity pass's
 * bounds without its parity condition (no sliver, no crease, no worse normal agreement, valence at
 * most 12, no vertex with noparity set). */
bool sk__deletion_flip_ok(const sk_mesh *m, const double *N, const uint8_t *noparity, uint32_t h);
/* The vertices the parity and deletion flips leave alone (noparity[v] = 1, one per vertex of m):
 * deleted, isolated and boundary vertices, crease vertices (keep: crease flags per edge, may be
 * NULL) and their neighbours; crease_v (one per vertex) is scratch. */
void sk__flip_noparity(const sk_mesh *m, const uint8_t *keep, uint8_t *noparity,
                       uint8_t *crease_v);
/* Flips chosen for the edge deletion (deletion_flips.c): deleted (ndel vertex pairs of m) is an
 * edge deletion of m with even even vertices and keep the crease flags (NULL = none). Flips, in
 * edge order, where the flip keeps the quality (sk__deletion_flip_ok): the kept edges whose quad
 * has two opposite sides deleted, when that lowers deleted / bound, and the kept edges with one
 * side of their quad deleted whose flip does not lower the even count (one per quad). *flips
 * (*flipped half-edges, to be freed) lists them in order: sk__flip_edge on each in reverse order
 * restores m. hint (may be NULL): when there are flips, *hint (*nhint vertex pairs, to be freed)
 * is deleted without the edges the flips un-deleted (the gains' two sides, the moves' quad
 * sides), a warm start for sk__edge_deletion_hinted on the flipped m. */
sk_status sk__deletion_flips(sk_mesh *m, const double *normals, const uint8_t *keep,
                             const uint32_t *deleted, size_t ndel, size_t even, uint32_t **flips,
                             size_t *flipped, uint32_t **hint, size_t *nhint, sk_error *err);

/* A vertex with exactly two crease edges has both crease tangents on one line, so a sector of
 * one face between them would be a patch with a 180-degree corner: the edge opposite the vertex
 * in such a triangle is flipped (crease_g0.c). Returns the number of flips; drops per-corner
 * uvs when it flips. */
size_t sk__crease_split_sectors(sk_mesh *m, const uint8_t *crease);

/* PN triangles on the triangle mesh s->config with normals s->normals (fills s->surface). */
sk_status sk__pn_build(sk_smooth *s, sk_error *err);

/* Shape measures (shape.c): a context holding the deleted edges (to know the diagonal each quad
 * replaces) and the grid size; sk__patch_shape gives patch p's overshoot and fairness
 * (sk_patch_shape in smooth.h). */
typedef struct sk__shape_ctx {
    const sk_smooth *s;
    uint64_t *keys; /* sorted deleted edges, (min id << 32) | max id */
    size_t nkeys;
    unsigned n;     /* grid steps per patch side */
    double *tab;    /* the screen's Bernstein table of the triangle grid (shape.c), or NULL */
    unsigned tab_ns; /* its samples, (n + 1) (n + 2) / 2 */
} sk__shape_ctx;
sk_status sk__shape_ctx_init(sk__shape_ctx *c, const sk_smooth *s, unsigned samples,
                             sk_error *err);
void sk__shape_ctx_free(sk__shape_ctx *c);
void sk__patch_shape(const sk__shape_ctx *c, size_t p, double *overshoot, double *fairness_deg);

#endif
