/* The tolerance route's internals (tolerance.c, the driver; tolerance_cut.c, cuts of the
 * progressive mesh in the input's numbering; tolerance_check.c, the surface of a cut and its
 * distances to the input both ways). */
#ifndef SK_FIT_TOLERANCE_INTERNAL_H
#define SK_FIT_TOLERANCE_INTERNAL_H

#include "surfkit/tolerance.h"
#include "surfkit/analysis.h"
#include "hierarchy/hierarchy_internal.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct tol_ctx {
    const sk_mesh *fine;
    size_t nv, nf;
    const uint32_t *tri;       /* 3 per fine face (compact triangle mesh) */
    double *normals;           /* fine normals, 3 per vertex */
    sk_hierarchy *hier;
    size_t levels;
    uint32_t *birth;           /* level at which each fine vertex appears (0 = coarsest) */
    sk_vertex_split *rec;      /* per fine vertex born above 0: its split, ids in fine numbering */
    uint32_t *order;           /* fine vertices born above 0, in application order */
    size_t num_order;
    uint32_t *coarse_fine;     /* coarsest vertex -> fine vertex */
    uint32_t *comp;            /* fine vertex -> component */
    uint8_t *comp_closed;      /* per component */
    size_t num_comps;
    uint32_t *ring_off, *ring; /* fine one-rings (neighbours) */
    uint32_t *f2m;             /* scratch: fine -> mixed vertex */
    size_t *comp_count;        /* scratch per component */
    sk_bvh *mesh_bvh;
    double tol;
    int n;                     /* face samples per edge */
    double bary[64 * 64][2];
    unsigned tess;
    sk_smooth_opts so;
    bool incremental;          /* the refinement rounds' checks reuse the last round's */
    sk_status last_fail;       /* the last VC1 failure and its message */
    char last_msg[SK_ERROR_MESSAGE_SIZE];
} tol_ctx;

/* The last surface a refinement round checked (tolerance_reuse.c), for the next round's
 * incremental check: its patches (corners as input vertices, SK_INVALID when not all are) and,
 * per patch, its groups of surface samples' distances */
typedef struct tol_prev {
    bool valid;
    size_t count, cap, cap_points, cap_s;
    uint32_t *kind;     /* kind | degree << 8 | degree_v << 16 */
    uint32_t *corners;  /* 4 per patch */
    size_t *first;      /* control points in points */
    double *points;
    size_t *goff;       /* count + 1: the patch's groups in sd, sf */
    double *sd;
    uint32_t *sf;
    uint32_t *head;     /* per input vertex: the first patch whose smallest corner it is */
    uint32_t *next;
} tol_prev;

/* per-sample distances of one check, kept between checks */
typedef struct check_buf {
    double *fd;     /* per fine face: largest distance of its samples to the surface */
    double *vd;     /* per fine vertex (dead ones): distance to the surface */
    uint32_t *fh;   /* per fine face: the surface triangle its last sample's walk found in this
                       check (SK_INVALID: not walked), the first guess for its vertices' walks */
    double *sd;     /* per surface sample group: largest distance to the mesh */
    uint32_t *sf;   /* ... and the fine face nearest to the worst of them */
    size_t cap_s;
    /* the refinement's incremental checks: per fine face sample and per fine vertex, the patch
     * of the surface triangle found within T (SK_INVALID: beyond T, or not recorded) */
    uint32_t *fw, *vw;
    tol_prev prev;
    size_t reused_patches, checked_patches; /* of the last check (incremental) */
    size_t unmoved_patches, far_patches;    /* ... of the reused: bit-identical, moved >= T / 10 */
} check_buf;

/* The refinement's warm start of the edge deletion: the last round's deleted edges as pairs
 * of fine vertices (sk__edge_deletion_hinted) */
typedef struct tol_hint {
    uint32_t *pairs;
    size_t n, cap;
} tol_hint;

/* one surface of a cut and its figures */
typedef struct cut_result {
    sk_smooth *s;
    size_t singular;   /* singular patches (sk_smooth_patch_shapes) */
    uint32_t *m2f;     /* mixed -> fine, for the config's vertices */
    double max;
    size_t patches;
    bool met;
} cut_result;

/* tolerance_cut.c */
sk_status sk__tol_index_hierarchy(tol_ctx *c, sk_error *err);
sk_status sk__tol_index_mesh(tol_ctx *c, sk_error *err);
size_t sk__tol_want_step(const tol_ctx *c, uint8_t *alive, uint32_t v, uint32_t *stack,
                         uint32_t *stamp, uint32_t stamp_value);
size_t sk__tol_fix_parity(const tol_ctx *c, uint8_t *alive);
sk_status sk__tol_build_cut(tol_ctx *c, uint8_t *alive, sk_mesh **out, uint32_t *m2f,
                            sk_error *err);
void sk__tol_level_cut(const tol_ctx *c, size_t j, uint8_t *alive);
void sk__tol_ctx_free(tol_ctx *c);

/* tolerance_reuse.c */
void sk__tol_prev_free(tol_prev *pv);
/* keep[p] := the last round's patch over the same corners as the new patch p, of the same kind
 * and degrees (else SK_INVALID), prev2new the inverse, moved[q] (for those q) the largest
 * distance between their control points (a bound on how far any point of the patch moved);
 * *kept: how many */
void sk__tol_match(const sk_smooth *s, const uint32_t *m2f, const tol_prev *pv, uint32_t *keep,
                   uint32_t *prev2new, double *moved, size_t *kept);
/* pv := the patches of s (its sd, sf, goff are the caller's) */
sk_status sk__tol_remember(const sk_smooth *s, const uint32_t *m2f, size_t nv, tol_prev *pv,
                           sk_error *err);

/* tolerance_check.c */
void sk__tol_check_buf_free(check_buf *b);
void sk__tol_cut_result_free(cut_result *r);
void sk__tol_record_try(sk_tolerance_stats *stats, size_t level, bool refined, sk_status status,
                        size_t vertices, const cut_result *r);
/* The search's check (stops at the first sample of the mesh side beyond T) of the cut alive's
 * own triangles, the piecewise linear surface through its vertices: the level estimate */
sk_status sk__tol_check_linear(tol_ctx *c, uint8_t *alive, check_buf *b, double *max_out,
                               sk_error *err);
/* hint (NULL: none; the refinement rounds): the edge deletion starts from it, and it gets the
 * new surface's deleted edges */
sk_status sk__tol_build_surface(tol_ctx *c, uint8_t *alive, check_buf *b, uint8_t *bad,
                                tol_hint *hint, cut_result *r, sk_status *vc1_status,
                                size_t *vertices, sk_tolerance_stats *stats, sk_error *err);

#endif
