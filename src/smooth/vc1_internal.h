/* Internal pieces of the VC1 construction (Cottin & van Damme, section 4) shared by its files:
 * vertex_targets.c (the vertex systems (8) set up from the wire frame targets, with target
 * blending), patch_assembly.c (system (4) and the patches), regularity_repair.c, reroute.c (the
 * re-routed deletion at patches still singular), vc1.c (driver). */
#ifndef SK_VC1_INTERNAL_H
#define SK_VC1_INTERNAL_H

#include "smooth/smooth_internal.h"

/* Per-half-edge and per-face state of one construction. */
typedef struct sk__vc1_work {
    const sk_mesh *m;
    const double *normals;
    const double *target; /* per half-edge */
    const double *r;      /* per face */
    double *P;            /* per half-edge: the cubic control point next to from(h) */
    double *w1;           /* per half-edge: w_1 of (8) at from(h), NaN on boundary edges */
    double *nu;           /* per half-edge: nu at from(h) (upper patch = face(h)) */
    double *C;            /* per half-edge: interior control point of face(h) at from(h) */
    double alpha;
    /* creases (docs/creases.md; all NULL without creases): per edge of m a crease flag, per
     * vertex its number of crease edges (capped at 255), per half-edge h the normal at from(h)
     * of the sector holding face(h) */
    const uint8_t *crease_e;
    const uint8_t *crease_v;
    const double *cn;
    sk__vsys_memo *memo; /* the solves of sk__vc1_solve_vertex go through it (NULL: none) */
    /* a re-routed round that reuses the build before it (sk__vc1_reuse_plan): per vertex 1 where
     * it works (NULL: everywhere); the fair points seed only at patches with a corner there and
     * sweep only there, the other patches are regular (they were, in the build before) */
    const uint8_t *limit;
} sk__vc1_work;

/* Delta of eq. (1) for face f. */
static inline double sk__face_delta(const sk_mesh *m, uint32_t f)
{
    /* sk__delta(sk_mesh_face_size(m, f)) without walking the face: a triangle closes after three
     * half-edges (the faces here have 3 or 4 sides) */
    uint32_t h = m->f_halfedge[f];
    return sk__delta(m->h_next[m->h_next[m->h_next[h]]] == h ? 3 : 4);
}

/* Outgoing half-edges of v counter-clockwise into E; for a boundary vertex the first and the last
 * are the boundary edges and the patches lie between consecutive ones. Returns the count (0 if
 * more than SK_VSYS_MAX). */
int sk__vc1_ordered_edges(const sk_mesh *m, uint32_t v, uint32_t *E, int *closed);

/* Solves vertex v's system (8) and writes W->P, W->w1 of its edges; returns 0 ok, 1 angle
 * violation, 2 not converged, 3 too many edges. blend > 0 starts from targets blended by that
 * much towards an even spread and lscale scales their lengths (the regularity repair's
 * variations); 0 and 1 give the plain construction. Where the angle bounds fail, the targets are
 * relaxed further (blend up to 1). */
int sk__vc1_solve_vertex(sk__vc1_work *W, uint32_t v, sk__vsys *sys, double blend, double lscale);

/* sk__vc1_solve_vertex(W, v[i], &sys[i], 0, 1) for count <= SK_VC1_VERTEX_CHUNK vertices into
 * code[i]: the same results, the systems solved in lanes (sk__vsys_solve_lanes) unless W->memo */
#define SK_VC1_VERTEX_CHUNK 16
void sk__vc1_solve_vertices(sk__vc1_work *W, const uint32_t *v, int count, sk__vsys *sys,
                            int *code);

/* blend_targets of vertex_targets.c (the relaxation of the targets towards an even spread). */
void sk__vc1_blend_targets(const double *orig, double *out, int n, int closed, double alpha,
                           double b, double lb);

/* A vertex with crease edges (crease.c): its star is cut at them into sectors, each solved as a
 * chain with the crease tangent points as fixed ends; same codes and arguments as
 * sk__vc1_solve_vertex (sys receives the sectors one after another, residual the worst). */
int sk__vc1_solve_crease_vertex(sk__vc1_work *W, uint32_t v, sk__vsys *sys, double blend,
                                double lscale);

/* System (4) of the ordered star E (n edges, closed = cycle) of v, and the same per sector of
 * a vertex with crease edges (crease.c). */
void sk__vc1_interior_star(sk__vc1_work *W, uint32_t v, const uint32_t *E, int n, int closed);
void sk__vc1_crease_interior_points(sk__vc1_work *W, uint32_t v);

/* The tangent lengths of the crease edges at vertices with two of them, set so that a sector
 * of two faces can meet its constraint (8) (crease.c); returns the vertices where both sectors
 * need it with different ratios. */
size_t sk__crease_tangent_ratios(sk__vc1_work *W, double *r, double *target);

/* Bounds the ratios nu between neighbouring patches: r (per face, r_m of eq. 7, all positive) is
 * lowered where needed so that r_f / r_g <= max_ratio for neighbouring faces (see
 * vertex_targets.c). */
#define SK_RATIO_SWEEPS 16
void sk__bound_ratios(const sk_mesh *m, double *r, double max_ratio);

/* System (4) around v: the interior control points W->C of the patches at v. */
void sk__vc1_interior_points(sk__vc1_work *W, uint32_t v);

/* The patch header of face f (kind, degree, corner ids = the face's vertices, tag f). */
void sk__vc1_patch_header(const sk_mesh *m, uint32_t f, sk_patch *pa);

/* Control points of face f's patch (quartic triangle or bicubic quad) into b. */
void sk__vc1_assemble_patch(const sk__vc1_work *W, uint32_t f, double *b);

/* The regularity repair: re-solves the vertex systems at the corners of singular patches with
 * varied targets and keeps a variant that leaves fewer singular patches; updates status (the
 * codes of sk__vc1_solve_vertex) and s->stats. known (may be NULL): the regularity test of each
 * patch as it stands (0 or 1), SK_SING_UNKNOWN where it has to be done. singular (may be NULL):
 * a new array of the patches still singular (s->stats.singular_after_repair; NULL when none). */
#define SK_SING_UNKNOWN 2
sk_status sk__vc1_repair_regularity(sk_smooth *s, sk__vc1_work *W, uint8_t *status,
                                    const uint8_t *known, uint32_t **singular, sk_error *err);

/* Fair free points (fair_points.c): up to `sweeps` block Gauss-Seidel sweeps, starting from the
 * vertices around the patches of s->surface (assembled from W) that are singular or stray far
 * from their faces, over the vertices with status < 2; they move each vertex's tangents W->P by the linear map of its tangent plane
 * minimising the bending energy of the patches it moves plus the distance to the targets; keeps
 * (8) and the angle bounds and leaves W->C consistent (system (4)). *moved counts the steps.
 * sing (one per patch) gets the regularity test of every patch before the sweeps, and
 * SK_SING_UNKNOWN for the patches the sweeps may have moved (to be assembled again; for
 * sk__vc1_repair_regularity). energy (may be NULL): the bending energy of all patches before
 * (summed from s->surface) and after (the change from the quadratic model the sweeps run on). */
/* The data term of the fit to the scan (fit_data.c): weight W of W * sum_i |S(u_i) - p_i|^2,
 * and the points p_i with their foot-point parameters u_i, grouped by patch (face of the
 * config): points first[f] .. first[f + 1] - 1 lie on patch f. */
typedef struct sk__fit_data {
    double weight;
    size_t *first; /* per patch + 1 */
    double *uv;    /* 2 per point: the patch parameters of its foot point */
    double *p;     /* 3 per point */
    size_t count;
} sk__fit_data;
/* The points of `fine` (every vertex and 4 points inside every triangle) and their foot points on
 * the patches of s->surface (as assembled). */
sk_status sk__vc1_fit_data(const sk_smooth *s, const sk_mesh *fine, double weight,
                           sk__fit_data *out, sk_error *err);
void sk__fit_data_free(sk__fit_data *d);
/* The Bernstein basis of a quartic triangle (corners 3: 15 values in sk_tri_index order, with
 * (a, b) the parameters of sk_patch_eval) or a bicubic (16, sk_tensor_index) at (a, b). */
void sk__fit_basis(int corners, double a, double b, double B[16]);
/* fit (may be NULL): the data term added to the energy (the fit to the scan); the sweeps then
 * start from every vertex (not only around the patches that are singular or stray). before (may
 * be NULL): the regularity test of every patch before the sweeps (sing before SK_SING_UNKNOWN is
 * set). */
sk_status sk__vc1_fair_points(const sk_smooth *s, sk__vc1_work *W, const uint8_t *status,
                              int sweeps, const sk__fit_data *fit, uint8_t *sing, uint8_t *before,
                              size_t *moved, double energy[2], sk_error *err);

/* The bending-energy matrices of Miao et al. (integral of |b_ss|^2 + 2 |b_st|^2 + |b_tt|^2 over
 * the parameter domain) of the quartic triangle (15 x 15, in sk_tri_index order, the mean over
 * the three choices of the eliminated barycentric) and the bicubic (16 x 16, sk_tensor_index), and
 * the energy of one control net with them (corners 3 or 4). */
void sk__fair_energy_matrices(double qt[15 * 15], double qq[16 * 16]);
double sk__fair_patch_energy(const double *qt, const double *qq, int corners, const double *b);

/* The build of a VC1 surface over a triangulation (vc1.c), and what the re-routed rounds of
 * reroute.c need to run it again. */
/* The flips chosen for the edge deletion (vc1.c, deletion_flips): how many are kept, the base as
 * it was before the first (a copy, made when they are first tried; NULL before), and whether a
 * build with them was dropped (then no more are tried) */
typedef struct sk__deletion_flip_log {
    size_t n;
    sk_mesh *saved;
    bool off;
} sk__deletion_flip_log;

typedef struct sk__build_ctx {
    const sk_mesh *mesh;  /* the input */
    const sk_mesh *base;  /* the triangulation the edge deletion runs on */
    sk_mesh *flippable;   /* base when its edges may be flipped (not with keep_triangulation) */
    uint8_t *keep;        /* crease flags per edge of base (NULL: no creases) */
    sk__deletion_flip_log *deletion_flips; /* flips for the deletion are tried (NULL: none) */
    bool file_normals;
    double alpha, max_nu;
    const sk_smooth_opts *opts;
} sk__build_ctx;

/* A vertex's figures of its least-squares solve of (8) (vc1.c: the solver stats are summed from
 * them, so that a re-routed round can reuse them where it reuses the solve). */
typedef struct sk__vsys_fig {
    double dev, residual; /* target deviation summed over its edges, the solver's residual */
    uint32_t dev_n, iterations;
    uint8_t relaxed, fallback;
} sk__vsys_fig;

/* A finished build's work state, kept while re-routed rounds may start from it (vc1.c): its
 * configuration and crease data (owned by the build: the state must not outlive it), per
 * half-edge of config the targets, nu, tangents P, weights w1 and interior points C as they stand
 * after the fair points and the repair, per vertex its status and solver figures, the corners of
 * the patches still singular, and the build's stats. */
typedef struct sk__vc1_state {
    const sk_mesh *config;
    const uint8_t *crease_edge;
    const double *corner_normals;
    const sk_patch *patches; /* its surface's patches and points */
    const double *points;
    double *target, *nu, *P, *w1, *C;
    uint8_t *status;
    sk__vsys_fig *fig;
    uint32_t *corners;
    size_t num_corners;
    sk_smooth_stats stats;
} sk__vc1_state;

void sk__vc1_state_free(sk__vc1_state **state);

/* The reuse of a re-routed round (reroute.c) on the new configuration W->m (targets and nu set)
 * from the build prev: hmap per half-edge of W->m the one of prev->config with the same ends
 * (SK_INVALID: none); near per vertex 1 where the round solves (8) again: the vertices whose star,
 * targets, nu or creases differ from prev's, and prev's corners of singular patches, grown by
 * SK_REUSE_RINGS rings; near2 near and one ring more (their interior points are solved again);
 * same_face per face of W->m: its patch is prev's face's (same corners from the same start). */
typedef struct sk__vc1_reuse {
    uint32_t *hmap, *same_face;
    uint8_t *near, *near2;
} sk__vc1_reuse;
#define SK_REUSE_RINGS 2
/* R's arrays for the configuration m; false (nothing held) when out of memory */
bool sk__vc1_reuse_alloc(sk__vc1_reuse *R, const sk_mesh *m);
void sk__vc1_reuse_free(sk__vc1_reuse *R);
/* R filled (sk__vc1_reuse_alloc'd for W->m); returns the count of near vertices. */
size_t sk__vc1_reuse_plan(const sk__vc1_work *W, const sk__vc1_state *prev, sk__vc1_reuse *R);
/* The steps of the build (vc1.c) on a plan: the solutions of (8) outside near taken from prev;
 * the interior points solved at near2, taken elsewhere; the patches with a corner in near2 (or
 * no face of prev's) assembled, the others copied; the regularity flags for the repair (unknown
 * for the patches assembled again and not tested by the fair points). */
void sk__vc1_reuse_solutions(sk__vc1_work *W, const sk__vc1_state *prev, const sk__vc1_reuse *R,
                             uint8_t *status, sk__vsys_fig *fig);
void sk__vc1_reuse_interior_points(sk__vc1_work *W, const sk__vc1_state *prev,
                                   const sk__vc1_reuse *R);
void sk__vc1_reuse_patches(sk_smooth *s, const sk__vc1_work *W, const sk__vc1_state *prev,
                           const sk__vc1_reuse *R);
void sk__vc1_reuse_untested(const sk__vc1_work *W, const sk__vc1_reuse *R, bool fair,
                            uint8_t *sing);

/* Edge deletion (sk__edge_deletion_hinted with hint and avoid) and the VC1 construction over
 * c->base, with the creases keep (may be NULL); crease lines whose sectors cannot be built are
 * dropped from keep and the round is done again (at most SK_CREASE_ROUNDS times). singular: the
 * patches still singular after the regularity repair (see sk__vc1_repair_regularity). */
sk_status sk__vc1_build_creases(sk_smooth *s, const sk__build_ctx *c, uint8_t *keep,
                                const uint32_t *hint, size_t nhint, const uint8_t *avoid,
                                uint32_t **singular, double t0[2], sk_error *err);
/* The same, starting from the build prev (NULL: from nothing) where the configuration did not
 * change (sk__vc1_reuse_plan), and leaving its own work state in *state when patches stay
 * singular (state NULL: not wanted; *state NULL: none kept). */
sk_status sk__vc1_build_reusing(sk_smooth *s, const sk__build_ctx *c, uint8_t *keep,
                                const uint32_t *hint, size_t nhint, const uint8_t *avoid,
                                const sk__vc1_state *prev, sk__vc1_state **state,
                                uint32_t **singular, double t0[2], sk_error *err);
/* Back to the state before a build: no configuration, surface or creases; stats = *saved. */
void sk__vc1_forget_build(sk_smooth *s, const sk_smooth_stats *saved);
/* Rounds of re-routed deletions (reroute.c) while patches stay singular after the build in s
 * (*singular: their ids, replaced by those of the build kept); fresh: the stats before the
 * build. */
sk_status sk__vc1_reroute_singular(sk_smooth *s, const sk__build_ctx *c,
                                   const sk_smooth_stats *fresh, uint32_t **singular,
                                   sk__vc1_state **state, sk_error *err);

#endif
