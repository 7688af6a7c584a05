/* Re-routed edge deletion at the patches still singular after the regularity repair of the VC1
 * construction.
 *
 * The repair (regularity_repair.c) varies the vertex systems on a fixed configuration; where
 * patches stay singular, the configuration itself is the trouble: which edges the deletion took
 * and, at slivers, the triangulation. Both came out of order-dependent choices (the flips' work
 * stack, the deletion's matching and searches), so a renumbered input can leave singular patches
 * where the input order left none (the cow: 0 to 10). Here the build is done again with the
 * deletion changed only near those patches (reroute_hint) and the slivers among them flipped
 * (flip_slivers), kept when it leaves fewer singular patches.
 *
 * The deletion and the targets are done again in full; the rest reuses the build the round starts
 * from (sk__vc1_reuse_plan and the sk__vc1_reuse_* steps below, which vc1.c calls): a vertex whose
 * star, targets, nu and creases are the same and that lies more than SK_REUSE_RINGS rings from a
 * change and from a corner of a singular patch keeps its tangents and weights as they stand (after
 * that build's fair points and repair: a solution of (8) for the same star, targets and nu is one
 * still), its interior points and patches are copied, and the fair points and the repair work only
 * near the changes. So the far vertices are not faired and repaired again, and the surface is not
 * byte for byte the one of a whole build (cow: the same singular counts and rounds over 9 orders,
 * max overshoot and mean fairness within 1%; docs/edge-deletion.md). */
#include "smooth/vc1_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <string.h>

/* A build's results in s (the configuration and what sits on it), moved out and back. */
typedef struct built {
    sk_mesh *config;
    sk_patch_set surface;
    uint32_t *deleted, *problems;
    uint8_t *crease_edge;
    double *corner_normals;
    size_t num_deleted, num_problems;
    sk_smooth_stats stats;
} built;

static void move_build_out(sk_smooth *s, built *b, const sk_smooth_stats *fresh)
{
    *b = (built){s->config, s->surface, s->deleted, s->problems, s->crease_edge,
                 s->corner_normals, s->num_deleted, s->num_problems, s->stats};
    s->config = NULL;
    s->surface = (sk_patch_set){0};
    s->deleted = s->problems = NULL;
    s->crease_edge = NULL;
    s->corner_normals = NULL;
    s->num_deleted = s->num_problems = 0;
    s->stats = *fresh;
}

static void move_build_in(sk_smooth *s, built *b)
{
    sk__vc1_forget_build(s, &b->stats);
    s->config = b->config;
    s->surface = b->surface;
    s->deleted = b->deleted;
    s->problems = b->problems;
    s->crease_edge = b->crease_edge;
    s->corner_normals = b->corner_normals;
    s->num_deleted = b->num_deleted;
    s->num_problems = b->num_problems;
}

/* marks the vertices one ring around the marked ones (in mark) too; scratch: nv bytes */
static void grow_ring(const sk_mesh *m, uint8_t *mark, uint8_t *scratch)
{
    size_t nv = m->num_vertices;
    memcpy(scratch, mark, nv);
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t h0 = m->v_halfedge[v], h = h0;
        if (!scratch[v] || h0 == SK_INVALID)
            continue;
        do {
            mark[sk_to(m, h)] = 1;
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
}

/* the side of triangle c (from c[j] to c[j + 1]) that is the (rank + 1)-th longest */
static int side_by_length(const sk_mesh *m, const uint32_t c[3], int rank)
{
    double len[3];
    for (int j = 0; j < 3; ++j)
        len[j] = sk__dist3(m->positions + 3 * (size_t)c[j],
                           m->positions + 3 * (size_t)c[(j + 1) % 3]);
    int order[3] = {0, 1, 2};
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (len[order[j]] > len[order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    return order[rank];
}

/* Re-routed deletion of round r around the patches still singular (singular, per patch of s),
 * as a hint and avoided edges for sk__edge_deletion_hinted: first one side of each singular
 * triangle, to be deleted (the triangle joins a quad: its longest side in rounds 0, 3, ..., the
 * second longest in rounds 1, 4, ..., the shortest in 2, 5, ...), then the deleted edges of s
 * that are more than r rings away from every corner of a singular patch (kept as they are); the
 * sides and diagonals of a singular quad are avoided (it falls apart into triangles). So only the
 * deletion within r rings of those patches changes, more of it in each round. r counts the rounds
 * since the last kept one (see sk__vc1_reroute_singular). */
static sk_status reroute_hint(const sk_smooth *s, const sk_mesh *base, const uint32_t *singular,
                              int round, uint32_t **hint, size_t *nhint, uint8_t **avoid,
                              sk_error *err)
{
    size_t nv = base->num_vertices, ns = s->stats.singular_after_repair, n = 0;
    uint8_t *near = sk__calloc_array(2 * nv + 1, 1);
    *avoid = sk__calloc_array(sk_num_edges(base) + 1, 1);
    *hint = sk__malloc_array(2 * (s->num_deleted + ns) + 1, sizeof **hint);
    if (!near || !*avoid || !*hint) {
        sk__free(near);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory re-routing the edge deletion");
    }
    for (size_t i = 0; i < ns; ++i) {
        const sk_patch *p = &s->surface.patches[singular[i]];
        const uint32_t *c = p->corner_ids;
        unsigned k = sk_patch_num_corners(p);
        if (k == 3) {
            int j = side_by_length(base, c, round % 3);
            (*hint)[2 * n] = c[j];
            (*hint)[2 * n++ + 1] = c[(j + 1) % 3];
        }
        for (unsigned a = 0; a < k; ++a) {
            near[c[a]] = 1;
            for (unsigned b = a + 1; b < k && k == 4; ++b) {
                uint32_t h = sk__find_halfedge(base, c[a], c[b]);
                if (h != SK_INVALID)
                    (*avoid)[sk_edge(h)] = 1;
            }
        }
    }
    for (int r = 0; r < round; ++r)
        grow_ring(base, near, near + nv);
    for (size_t i = 0; i < s->num_deleted; ++i) {
        uint32_t a = s->deleted[2 * i], b = s->deleted[2 * i + 1];
        if (!near[a] && !near[b]) {
            (*hint)[2 * n] = a;
            (*hint)[2 * n++ + 1] = b;
        }
    }
    *nhint = n;
    sk__free(near);
    return SK_OK;
}

/* v's star in m is the one in o (prev->config), half-edge by half-edge from the same first one,
 * with the same faces (same_face), targets, nu and creases */
static bool same_star(const sk__vc1_work *W, const sk__vc1_state *prev, const uint32_t *hmap,
                      const uint32_t *same_face, uint32_t v)
{
    const sk_mesh *m = W->m, *o = prev->config;
    uint32_t h0 = m->v_halfedge[v], h = h0, g0 = o->v_halfedge[v], g = g0;
    if (h0 == SK_INVALID || g0 == SK_INVALID || hmap[h0] != g0)
        return false;
    do {
        uint32_t f = m->h_face[h], e = sk_edge(h);
        if (hmap[h] != g || (f == SK_INVALID) != (o->h_face[g] == SK_INVALID) ||
            (f != SK_INVALID && same_face[f] != o->h_face[g]) ||
            memcmp(W->target + 3 * (size_t)h, prev->target + 3 * (size_t)g, 3 * sizeof(double)) ||
            memcmp(W->nu + h, prev->nu + g, sizeof(double)) ||
            (W->crease_e ? W->crease_e[e] : 0) !=
                (prev->crease_edge ? prev->crease_edge[sk_edge(g)] : 0) ||
            (W->cn && prev->corner_normals &&
             memcmp(W->cn + 3 * (size_t)h, prev->corner_normals + 3 * (size_t)g,
                    3 * sizeof(double))) ||
            (!W->cn) != (!prev->corner_normals))
            return false;
        h = sk_cw_out(m, h);
        g = sk_cw_out(o, g);
    } while (h != h0 && g != g0);
    return h == h0 && g == g0;
}

size_t sk__vc1_reuse_plan(const sk__vc1_work *W, const sk__vc1_state *prev, sk__vc1_reuse *R)
{
    const sk_mesh *m = W->m, *o = prev->config;
    uint32_t *hmap = R->hmap, *same_face = R->same_face;
    uint8_t *near = R->near, *near2 = R->near2;
    size_t nh = m->num_halfedges, nf = m->num_faces, nv = m->num_vertices, n = 0;
    long nhl = (long)nh, nfl = (long)nf, nvl = (long)nv;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nhl > 100000)
#endif
    for (long h = 0; h < nhl; ++h) {
        uint32_t a = sk_from(m, (uint32_t)h), b = sk_to(m, (uint32_t)h);
        hmap[h] = a < o->num_vertices && b < o->num_vertices ? sk__find_halfedge(o, a, b)
                                                             : SK_INVALID;
    }
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nfl > 100000)
#endif
    for (long f = 0; f < nfl; ++f) { /* the same corners from the same start */
        uint32_t h0 = m->f_halfedge[f], h = h0, g0 = hmap[h0], g = g0;
        uint32_t of = g0 != SK_INVALID ? o->h_face[g0] : SK_INVALID;
        bool same = of != SK_INVALID && o->f_halfedge[of] == g0;
        if (same) {
            do {
                h = m->h_next[h];
                g = o->h_next[g];
            } while (h != h0 && g != g0 && hmap[h] == g);
            same = h == h0 && g == g0;
        }
        same_face[f] = same ? of : SK_INVALID;
    }
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(static) if (nvl > 100000)
#endif
    for (long v = 0; v < nvl; ++v)
        near[v] = !m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID &&
                  (v >= (long)o->num_vertices || !same_star(W, prev, hmap, same_face, (uint32_t)v));
    for (size_t i = 0; i < prev->num_corners; ++i)
        if (prev->corners[i] < nv)
            near[prev->corners[i]] = 1;
    for (int r = 0; r < SK_REUSE_RINGS; ++r)
        grow_ring(m, near, near2);
    memcpy(near2, near, nv);
    uint8_t *tmp = sk__malloc_array(nv + 1, 1);
    if (tmp) {
        grow_ring(m, near2, tmp);
        sk__free(tmp);
    } else { /* no scratch: every vertex around a near one, one by one */
        for (uint32_t v = 0; v < nv; ++v) {
            uint32_t h0 = m->v_halfedge[v], h = h0;
            if (near2[v] || h0 == SK_INVALID)
                continue;
            do {
                near2[v] = near2[v] || near[sk_to(m, h)];
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
    }
    for (size_t v = 0; v < nv; ++v)
        n += near[v];
    return n;
}

void sk__vc1_reuse_free(sk__vc1_reuse *R)
{
    sk__free(R->hmap);
    sk__free(R->same_face);
    sk__free(R->near);
    sk__free(R->near2);
    *R = (sk__vc1_reuse){0};
}

bool sk__vc1_reuse_alloc(sk__vc1_reuse *R, const sk_mesh *m)
{
    R->hmap = sk__malloc_array(m->num_halfedges + 1, sizeof(uint32_t));
    R->same_face = sk__malloc_array(m->num_faces + 1, sizeof(uint32_t));
    R->near = sk__malloc_array(m->num_vertices + 1, 1);
    R->near2 = sk__malloc_array(m->num_vertices + 1, 1);
    if (R->hmap && R->same_face && R->near && R->near2)
        return true;
    sk__vc1_reuse_free(R);
    return false;
}

/* the solutions of (8) (tangents, weights, codes, figures) of the vertices outside R->near, as
 * they stand in prev (after its fair points and repair: a solution of (8) stays one, the star,
 * targets and nu being the same) */
void sk__vc1_reuse_solutions(sk__vc1_work *W, const sk__vc1_state *prev, const sk__vc1_reuse *R,
                             uint8_t *status, sk__vsys_fig *fig)
{
    const sk_mesh *m = W->m;
    for (uint32_t h = 0; h < m->num_halfedges; ++h) {
        uint32_t v = sk_from(m, h), g = R->hmap[h];
        if (R->near[v] || g == SK_INVALID)
            continue;
        memcpy(W->P + 3 * (size_t)h, prev->P + 3 * (size_t)g, 3 * sizeof(double));
        W->w1[h] = prev->w1[g];
    }
    for (uint32_t v = 0; v < m->num_vertices; ++v)
        if (!R->near[v] && v < prev->config->num_vertices) {
            status[v] = prev->status[v];
            fig[v] = prev->fig[v];
        }
}

/* system (4) at the vertices of R->near2 (a tangent moved at them or a neighbour); elsewhere the
 * interior points of prev */
void sk__vc1_reuse_interior_points(sk__vc1_work *W, const sk__vc1_state *prev,
                                   const sk__vc1_reuse *R)
{
    const sk_mesh *m = W->m;
    for (uint32_t h = 0; h < m->num_halfedges; ++h) {
        uint32_t g = R->hmap[h];
        if (!R->near2[sk_from(m, h)] && g != SK_INVALID)
            memcpy(W->C + 3 * (size_t)h, prev->C + 3 * (size_t)g, 3 * sizeof(double));
    }
    for (uint32_t v = 0; v < m->num_vertices; ++v)
        if (R->near2[v] && !m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID)
            sk__vc1_interior_points(W, v);
}

/* face f has a corner in mark */
static bool face_touches(const sk_mesh *m, uint32_t f, const uint8_t *mark)
{
    uint32_t h0 = m->f_halfedge[f], h = h0;
    do {
        if (mark[sk_from(m, h)])
            return true;
        h = m->h_next[h];
    } while (h != h0);
    return false;
}

/* the patches with a corner in R->near2 (or no face of prev's) assembled, the others copied */
void sk__vc1_reuse_patches(sk_smooth *s, const sk__vc1_work *W, const sk__vc1_state *prev,
                           const sk__vc1_reuse *R)
{
    const sk_mesh *m = W->m;
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        uint32_t g = R->same_face[f];
        double *cp = sk_patch_cp(&s->surface, f);
        if (g == SK_INVALID || face_touches(m, f, R->near2))
            sk__vc1_assemble_patch(W, f, cp);
        else
            memcpy(cp, prev->points + 3 * prev->patches[g].first,
                   3 * sk_patch_num_points(&s->surface.patches[f]) * sizeof(double));
    }
}

/* The regularity flags for the repair: the patches assembled again (a corner in R->near2) and
 * not tested by the fair points (fair: those with a corner in R->near) to be tested, the others
 * regular (as in the build before: its singular patches are near) */
void sk__vc1_reuse_untested(const sk__vc1_work *W, const sk__vc1_reuse *R, bool fair,
                             uint8_t *sing)
{
    const sk_mesh *m = W->m;
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        if (fair && face_touches(m, f, R->near))
            continue;
        sing[f] = face_touches(m, f, R->near2) || R->same_face[f] == SK_INVALID
                      ? SK_SING_UNKNOWN
                      : 0;
    }
}

static void free_built(built *b)
{
    sk_smooth t = {0}; /* the one place that frees a build: sk__vc1_forget_build */
    move_build_in(&t, b);
    sk__vc1_forget_build(&t, &t.stats);
}

/* the largest corner angle of triangle c (radians) and the side opposite it (c[j] to c[j + 1]) */
static double largest_angle(const sk_mesh *m, const uint32_t c[3], int *side)
{
    double best = -1.0;
    for (int k = 0; k < 3; ++k) {
        const double *x = m->positions + 3 * (size_t)c[k];
        double u[3], v[3], w[3];
        sk__sub3(u, m->positions + 3 * (size_t)c[(k + 1) % 3], x);
        sk__sub3(v, m->positions + 3 * (size_t)c[(k + 2) % 3], x);
        sk__cross3(w, u, v);
        double a = atan2(sk__norm3(w), sk__dot3(u, v));
        if (a > best) {
            best = a;
            *side = (k + 1) % 3;
        }
    }
    return best;
}

/* The singular triangles with a corner above SK_REROUTE_SLIVER_DEG get their longest edge
 * flipped in c->flippable (where valid: sk__flip_edge_if_valid); the flipped half-edges go to
 * flipped (one per singular patch at most), their number to *nflipped. */
#define SK_REROUTE_SLIVER_DEG 150.0

static void flip_slivers(const sk_smooth *s, const sk__build_ctx *c, const uint32_t *singular,
                         const uint8_t *keep, uint32_t *flipped, size_t *nflipped)
{
    *nflipped = 0;
    for (size_t i = 0; c->flippable && i < s->stats.singular_after_repair; ++i) {
        const sk_patch *p = &s->surface.patches[singular[i]];
        int j = 0;
        if (sk_patch_num_corners(p) != 3 ||
            largest_angle(c->base, p->corner_ids, &j) < SK_REROUTE_SLIVER_DEG * M_PI / 180.0)
            continue;
        uint32_t h = sk__find_halfedge(c->base, p->corner_ids[j], p->corner_ids[(j + 1) % 3]);
        if (h != SK_INVALID && sk__flip_edge_if_valid(c->flippable, h, keep))
            flipped[(*nflipped)++] = h;
    }
}

/* Round round of the re-routed deletion: the slivers flipped (flip_slivers; not when !flips),
 * the build again with reroute_hint, kept when it leaves fewer patches singular and no more
 * problem vertices (*kept); else the build before it and the flipped edges are put back
 * (*kept_flips counts the kept, *tried the flips made). */
static sk_status reroute_round(sk_smooth *s, const sk__build_ctx *c, const sk_smooth_stats *fresh,
                               uint32_t **singular, sk__vc1_state **state, int round, bool flips,
                               size_t *kept_flips, size_t *tried, bool *kept, sk_error *err)
{
    sk__vc1_state *next = NULL;
    uint32_t *hint = NULL, *again = NULL;
    uint8_t *avoid = NULL;
    size_t nhint = 0, nflip = 0, before = s->stats.singular_after_repair;
    size_t ne = sk_num_edges(c->base);
    /* the round's own crease flags: a crease line it drops stays if the round is not kept */
    uint8_t *keep = c->keep ? sk__malloc_array(ne + 1, 1) : NULL;
    uint32_t *flipped = sk__malloc_array(before + 1, sizeof *flipped);
    if ((c->keep && !keep) || !flipped) {
        sk__free(keep);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory re-routing the edge deletion");
    }
    if (c->keep)
        memcpy(keep, c->keep, ne);
    if (flips)
        flip_slivers(s, c, *singular, keep, flipped, &nflip);
    *tried = nflip;
    sk_status st = reroute_hint(s, c->base, *singular, round, &hint, &nhint, &avoid, err);
    if (st == SK_OK) {
        built prev;
        double t0[2] = {sk_seconds(), sk_cpu_seconds()};
        move_build_out(s, &prev, fresh);
        st = sk__vc1_build_reusing(s, c, keep, hint, nhint, avoid, *state, &next, &again, t0,
                                   err);
        bool gain = st == SK_OK && s->stats.singular_after_repair < before &&
                    s->num_problems <= prev.num_problems;
        if (st == SK_ERR_NUMERIC)
            st = SK_OK; /* a vertex system of the re-routed build failed: the one before stands */
        *kept = gain;
        if (gain) {
            sk__vc1_state_free(state); /* it points into prev */
            *state = next;
            next = NULL;
            free_built(&prev);
            sk__free(*singular);
            *singular = again;
            *kept_flips += nflip;
            if (c->keep)
                memcpy(c->keep, keep, ne);
            nflip = 0;
        } else {
            sk__vc1_state_free(&next); /* before its build goes */
            move_build_in(s, &prev);
            sk__free(again);
        }
    }
    while (nflip > 0) /* not kept: flipping again restores the edges */
        sk__flip_edge(c->flippable, flipped[--nflip]);
    sk__free(hint);
    sk__free(avoid);
    sk__free(keep);
    sk__free(flipped);
    return st;
}

/* Rounds of the re-routed deletion (reroute_round; at most opts->reroute_rounds, default
 * SK_REROUTE_ROUNDS) while patches stay singular after the regularity repair, whose variants of
 * the vertex systems cannot change the configuration. Each round is a deletion and the build again
 * near its changes (see the top of this file); their time is counted as the repair's. Measured on
 * the cow in 8 random orders (singular patches in all): 34 without rounds; with the singular
 * triangles' sides avoided instead of hinted, 16; as here without the sliver flips, 6 with 4
 * rounds and 4 with 6; with them, 3 (bench/smooth_orders.sh has the table over 9 orders and 8
 * meshes).
 *
 * The rings (and the side of a singular triangle) start again after a kept round: a kept round
 * can move the singular patches away from the first ones. On test_reroute_orders' cow order 1
 * (with the breadth-first Initialise of edge_deletion.c), round 2 left one singular triangle in
 * place of five; counting on, rounds 3 to 5 freed 3 to 5 rings around it, which took in the first
 * five's region, whose deletion came back as it was and the five with it (1 left after 6 rounds).
 * Starting again, 1 ring around the new triangle cleared it (0 after 5 rounds). */
#define SK_REROUTE_ROUNDS 6
/* over a refined base (refine_base.c): the cow refined twice kept 1 singular patch after 6
 * rounds, none after 9 (rounds stop when none is left) */
#define SK_REROUTE_ROUNDS_REFINED 12

sk_status sk__vc1_reroute_singular(sk_smooth *s, const sk__build_ctx *c,
                                   const sk_smooth_stats *fresh, uint32_t **singular,
                                   sk__vc1_state **state, sk_error *err)
{
    double wall = sk_seconds(), cpu = sk_cpu_seconds();
    double repair_wall = s->stats.seconds_repair, repair_cpu = s->stats.cpu_repair;
    sk_status st = SK_OK;
    size_t rounds = 0, flips = 0;
    int most = c->opts->reroute_rounds          ? c->opts->reroute_rounds
               : c->opts->base_refinements ? SK_REROUTE_ROUNDS_REFINED
                                           : SK_REROUTE_ROUNDS;
    int since = 0;
    for (; st == SK_OK && *singular && (int)rounds < most; ++rounds) {
        bool kept = false;
        size_t tried = 0;
        st = reroute_round(s, c, fresh, singular, state, since, true, &flips, &tried, &kept, err);
        /* over a refined base (refine_base.c) the slivers lie beside the near-folds left whole,
         * and flipping them can undo the round's gain (pig refined twice: 13 singular patches
         * -> 460 to 525 in every round with flips): such a round is tried again without them */
        if (st == SK_OK && !kept && tried && c->opts->base_refinements)
            st = reroute_round(s, c, fresh, singular, state, since, false, &flips, &tried, &kept,
                               err);
        since = kept ? 0 : since + 1;
    }
    s->stats.rerouted_rounds = rounds;
    s->stats.flipped_edges += flips; /* the kept build's stats start from fresh */
    s->stats.seconds_repair = repair_wall + (sk_seconds() - wall);
    s->stats.cpu_repair = repair_cpu + (sk_cpu_seconds() - cpu);
    return st;
}
