/* Fair free points of the VC1 construction: the tangent control points chosen by minimal bending
 * energy of the patches (Miao et al., "Bezier Surfaces of Minimal Internal Energy", Mathematics of
 * Surfaces XI) subject to the VC1 equations, instead of by least squares to the wire frame
 * targets alone.
 *
 * Once the weights w_1 and the ratios nu of the vertex systems (8) are set, (8) is linear and
 * homogeneous in the tangent vectors p_m = P_m - V of a vertex (scalar coefficients, both tangent
 * coordinates obey the same recurrence), so every solution stays a solution under a linear map
 * p_m -> (I + D) p_m of the tangent plane (D a 2x2 matrix: four free parameters per vertex). The
 * interior points of system (4) are affine in the P (of the vertex and of its neighbours), and so
 * are the patches: the whole network is an affine function of the D of all vertices, and
 *
 *     E(D) = sum over patches of E_bend(patch) + FAIR_TARGET_WEIGHT * sum |P_m - P*_m|^2
 *
 * (E_bend = integral of |b_ss|^2 + 2 |b_st|^2 + |b_tt|^2 over the parameter domain, Miao et al.
 * section 2; P* the wire frame targets in the tangent plane) is a convex quadratic in them. It is
 * lowered by block Gauss-Seidel sweeps, one vertex (four unknowns) at a time: the patches around
 * the vertex and its neighbours are the ones it moves, their control points are affine in D and
 * the 4 x 4 normal equations give the best D with the neighbours fixed. The sweeps are local:
 * they start at the corners of the patches that are singular or whose control net strays far from
 * their face (and their neighbours), stay within one ring around those, and visit again only the
 * vertices that moved (or whose neighbours moved) noticeably in the sweep before; elsewhere the
 * least-squares fit stands. (Sweeping every vertex changed the singular counts and the overshoot
 * on the shared meshes by nothing measurable and cost 5 to 10 times more.) A step that would
 * break the angle bounds alpha < angle / pi < 1 - alpha between consecutive tangents (the linear
 * map keeps the winding only while det(I + D) > 0) is halved until it keeps them, else skipped.
 * The VC1 property holds exactly at the end: the final maps are written into the tangents and
 * system (4) is solved again around the vertices that moved.
 *
 * The sweeps run on a quadratic model: D of every vertex is taken against its tangents as solved
 * (p0), so the control nets are exactly affine in all the D together. When a vertex is first
 * visited, its Jacobian (how each local control point moves per unit of its four parameters) is
 * found once by moving its tangents and solving system (4) again at it and its neighbours (two
 * directions along e_0 of its tangent basis; the two along e_1 are e_1 times the same scalars:
 * (4) and the assembly have scalar coefficients), and only the rows that move are kept, as two
 * scalars each; its 4 x 4 block of the Hessian (two copies of one 2 x 2 per face) follows. The
 * control nets the unknowns move are kept as they stand (one copy per patch, updated by the rows
 * after each step), so a block step is the gradient from those nets and a 4 x 4 solve: no system
 * (4), no patch assembly. The step bound and the halving are those of a step against the
 * tangents as they stand (D' = d (I + X)^-1), so the steps are those of re-solving and
 * re-assembling at every step (11,888 on the cow, outputs equal to rounding) at about half the
 * cost. The model's energy equals the patches' (stats fair_energy_after; test_fair_model_energy).
 * (Measured on the cow: sweeping the whole region until every step is below 1e-12 took 19 times
 * the steps; bounding the steps against p0 instead changed the steps and raised max_overshoot
 * from 0.28 to 0.34, with the same singular count.)
 *
 * The fit to the scan (sk_smooth_opts.fit_weight, fit_data.c) adds W * sum_i |S(u_i) - p_i|^2
 * over points p_i with fixed patch parameters u_i: S(u_i) = sum_c B_c(u_i) b_c is affine in the
 * D too, so the term is another quadratic (data_hessian: constant, as the u_i are fixed;
 * data_gradient: from the nets as they stand), and the sweeps then start from every vertex.
 *
 * The energy matrices are built from Bernstein integrals by Gauss quadrature (exact: the
 * integrands are polynomials of degree 4 on the triangle, 2 x 6 on the square), not from the
 * printed formulas (which divide by zero at n = 4, see the papers' errata). For the triangle the
 * parametric energy depends on which barycentric coordinate is eliminated; the mean over the
 * three choices is used, so that no corner is preferred. */
#include "smooth/vc1_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

/* weight of the distance to the wire frame targets against the bending energy (both are squared
 * lengths of control points; measured on the shared meshes, see bench/smooth.sh) */
#define FAIR_TARGET_WEIGHT 1.0
/* the largest |D| (Frobenius) of one step: the sweeps converge anyway; large single steps only
 * risk the angle bounds */
#define FAIR_MAX_STEP 0.5
/* a vertex whose step |D| exceeded this is visited again in the next sweep, with its neighbours */
#define FAIR_ACTIVE_STEP 1e-2
/* steps |D| at or below this are not taken */
#define FAIR_MIN_STEP 1e-9
/* var_of: a vertex that is no unknown (its star does not fit) */
#define FAIR_NO_VAR (SK_INVALID - 1)
/* patches whose control net leaves their face's plane by more than this (relative to the
 * longest side) seed the sweeps, with the singular ones */
#define FAIR_SEED_OVERSHOOT 0.3
/* the sweeps stay within this many rings around the seeds */
#define FAIR_REGION_RINGS 1
#define FAIR_LOCAL_FACES 1024
#define FAIR_LOCAL_VERTS (SK_VSYS_MAX + 1)

/* 5-point Gauss-Legendre on [0, 1] */
static const double gl_x[5] = {0.04691007703066800, 0.23076534494715845, 0.5, 0.76923465505284155,
                               0.95308992296933200};
static const double gl_w[5] = {0.11846344252809454, 0.23931433524968324, 0.28444444444444444,
                               0.23931433524968324, 0.11846344252809454};

static double falling(int a, int d)
{
    double r = 1.0;
    for (int i = 0; i < d; ++i)
        r *= a - i;
    return r;
}

static double ipow(double x, int e) { return e < 0 ? 0.0 : e == 0 ? 1.0 : x * ipow(x, e - 1); }

/* d^(a+b+c) / du^a dv^b dw^c of u^i v^j w^k at (u, v, w), the variables independent */
static double mono_d(const int e[3], const int d[3], const double x[3])
{
    double r = 1.0;
    for (int q = 0; q < 3; ++q) {
        if (d[q] > e[q])
            return 0.0;
        r *= falling(e[q], d[q]) * ipow(x[q], e[q] - d[q]);
    }
    return r;
}

/* second derivatives (ss, st, tt) of the monomial with barycentric `el` eliminated and the other
 * two (in cyclic order) as the coordinates s, t: D_s = d_s - d_el, D_t = d_t - d_el */
static void tri_second(const int e[3], int el, const double x[3], double out[3])
{
    int s = (el + 1) % 3, t = (el + 2) % 3;
    /* D_a D_b = d_ab - d_a,el - d_b,el + d_el,el */
    int pairs[3][2] = {{s, s}, {s, t}, {t, t}};
    for (int q = 0; q < 3; ++q) {
        int a = pairs[q][0], b = pairs[q][1];
        int terms[4][2] = {{a, b}, {a, el}, {b, el}, {el, el}};
        double sgn[4] = {1, -1, -1, 1}, v = 0.0;
        for (int k = 0; k < 4; ++k) {
            int d[3] = {0, 0, 0};
            d[terms[k][0]]++;
            d[terms[k][1]]++;
            v += sgn[k] * mono_d(e, d, x);
        }
        out[q] = v;
    }
}

void sk__fair_energy_matrices(double qt[15 * 15], double qq[16 * 16])
{
    /* quartic triangle: b_{ijk} at sk_tri_index(4, j, k), barycentrics (u, v, w) */
    memset(qt, 0, 15 * 15 * sizeof(double));
    int ex[15][3];
    double coef[15];
    for (int k = 0; k <= 4; ++k)
        for (int j = 0; j + k <= 4; ++j) {
            unsigned id = sk_tri_index(4, (unsigned)j, (unsigned)k);
            ex[id][0] = 4 - j - k, ex[id][1] = j, ex[id][2] = k;
            coef[id] = 24.0 / (falling(4 - j - k, 4 - j - k) * falling(j, j) * falling(k, k));
        }
    for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b) {
            /* Duffy map of the square onto the triangle s >= 0, t >= 0, s + t <= 1 */
            double s = gl_x[a], t = gl_x[b] * (1.0 - gl_x[a]), wq = gl_w[a] * gl_w[b] * (1.0 - s);
            for (int el = 0; el < 3; ++el) {
                double x[3];
                x[el] = 1.0 - s - t, x[(el + 1) % 3] = s, x[(el + 2) % 3] = t;
                double d2[15][3];
                for (int i = 0; i < 15; ++i) {
                    tri_second(ex[i], el, x, d2[i]);
                    for (int q = 0; q < 3; ++q)
                        d2[i][q] *= coef[i];
                }
                for (int i = 0; i < 15; ++i)
                    for (int j = 0; j < 15; ++j)
                        qt[15 * i + j] += wq / 3.0 *
                                          (d2[i][0] * d2[j][0] + 2.0 * d2[i][1] * d2[j][1] +
                                           d2[i][2] * d2[j][2]);
            }
        }
    /* bicubic: b_{ij} at sk_tensor_index(3, i, j) */
    memset(qq, 0, 16 * 16 * sizeof(double));
    for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b) {
            double s = gl_x[a], t = gl_x[b], wq = gl_w[a] * gl_w[b];
            double B[2][4][3]; /* B[dir][i][derivative order] of the cubic Bernstein basis */
            for (int dir = 0; dir < 2; ++dir) {
                double x = dir ? t : s, y = 1.0 - x;
                double c[4] = {1, 3, 3, 1};
                for (int i = 0; i < 4; ++i) {
                    int e[3] = {i, 3 - i, 0};
                    double xx[3] = {x, y, 0.0};
                    for (int d = 0; d <= 2; ++d) {
                        /* d/dx of x^i (1-x)^(3-i): sum over splitting d between the factors */
                        double v = 0.0;
                        for (int p = 0; p <= d; ++p) {
                            int dd[3] = {p, d - p, 0};
                            double bin = d == 2 && p == 1 ? 2.0 : 1.0;
                            v += bin * ((d - p) & 1 ? -1.0 : 1.0) * mono_d(e, dd, xx);
                        }
                        B[dir][i][d] = c[i] * v;
                    }
                }
            }
            double d2[16][3];
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) {
                    unsigned id = sk_tensor_index(3, (unsigned)i, (unsigned)j);
                    d2[id][0] = B[0][i][2] * B[1][j][0];
                    d2[id][1] = B[0][i][1] * B[1][j][1];
                    d2[id][2] = B[0][i][0] * B[1][j][2];
                }
            for (int i = 0; i < 16; ++i)
                for (int j = 0; j < 16; ++j)
                    qq[16 * i + j] += wq * (d2[i][0] * d2[j][0] + 2.0 * d2[i][1] * d2[j][1] +
                                            d2[i][2] * d2[j][2]);
        }
}

double sk__fair_patch_energy(const double *qt, const double *qq, int corners, const double *b)
{
    int n = corners == 3 ? 15 : 16;
    const double *Q = corners == 3 ? qt : qq;
    double e = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            e += Q[n * i + j] * sk__dot3(b + 3 * i, b + 3 * j);
    return e;
}

typedef struct fair_scratch {
    uint32_t verts[FAIR_LOCAL_VERTS];
    size_t nverts;
    uint32_t faces[FAIR_LOCAL_FACES];
    int corners[FAIR_LOCAL_FACES];
    size_t nfaces;
    size_t nfaces_v; /* faces[0 .. nfaces_v) are the faces around v (gathered first) */
    double base[FAIR_LOCAL_FACES * 48];
    double dir[4][FAIR_LOCAL_FACES * 48];
    double savedC[FAIR_LOCAL_VERTS][3 * SK_VSYS_MAX];
    uint8_t *mark; /* per face of the mesh, zero between calls */
} fair_scratch;

/* v, its neighbours and the faces around them; false when they do not fit */
static bool gather_marked(const sk_mesh *m, uint32_t v, fair_scratch *S);
static bool gather(const sk_mesh *m, uint32_t v, fair_scratch *S)
{
    bool ok = gather_marked(m, v, S);
    for (size_t i = 0; i < S->nfaces; ++i)
        S->mark[S->faces[i]] = 0;
    return ok;
}

static bool gather_marked(const sk_mesh *m, uint32_t v, fair_scratch *S)
{
    S->nverts = 0;
    S->nfaces = 0;
    S->verts[S->nverts++] = v;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        if (S->nverts == FAIR_LOCAL_VERTS)
            return false;
        S->verts[S->nverts++] = sk_to(m, h);
        h = sk_cw_out(m, h);
    } while (h != h0);
    for (size_t i = 0; i < S->nverts; ++i) {
        if (i == 1)
            S->nfaces_v = S->nfaces;
        uint32_t g0 = m->v_halfedge[S->verts[i]], g = g0;
        int deg = 0;
        do {
            uint32_t f = m->h_face[g];
            if (++deg > SK_VSYS_MAX)
                return false;
            if (f != SK_INVALID && !S->mark[f]) {
                if (S->nfaces == FAIR_LOCAL_FACES)
                    return false;
                S->mark[f] = 1;
                S->corners[S->nfaces] = (int)sk_mesh_face_size(m, f);
                S->faces[S->nfaces++] = f;
            }
            g = sk_cw_out(m, g);
        } while (g != g0);
    }
    if (S->nverts == 1)
        S->nfaces_v = S->nfaces;
    return true;
}

/* saves (dir < 0) or restores the interior points of the local vertices */
static void save_restore_C(sk__vc1_work *W, fair_scratch *S, bool restore)
{
    for (size_t i = 0; i < S->nverts; ++i) {
        uint32_t E[SK_VSYS_MAX];
        int closed, n = sk__vc1_ordered_edges(W->m, S->verts[i], E, &closed);
        for (int k = 0; k < n; ++k) {
            double *C = W->C + 3 * (size_t)E[k];
            if (restore)
                memcpy(C, S->savedC[i] + 3 * k, 3 * sizeof(double));
            else
                memcpy(S->savedC[i] + 3 * k, C, 3 * sizeof(double));
        }
    }
}

/* Position in face f's control net of the interior point W->C[h] of its k-th half-edge h (the
 * layout of sk__vc1_assemble_patch). */
static unsigned interior_slot(int corners, int k)
{
    static const unsigned inner[4][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
    if (corners == 3)
        return k == 0 ? sk_tri_index(4, 1, 1) : k == 1 ? sk_tri_index(4, 2, 1) : sk_tri_index(4, 1, 2);
    return sk_tensor_index(3, inner[k][0], inner[k][1]);
}

/* the interior slots of a control net with `corners` corners, as bits */
static unsigned interior_mask(int corners)
{
    unsigned mask = 0;
    for (int k = 0; k < corners; ++k)
        mask |= 1u << interior_slot(corners, k);
    return mask;
}

/* out = the local patches after a change of v's tangents, minus S->base: system (4) again at v
 * and its neighbours; the faces around v assembled again, the others differ from base only in
 * their interior points (their sides do not touch v: exactly zero there, left unwritten). */
static void local_difference(sk__vc1_work *W, const fair_scratch *S, double *out)
{
    const sk_mesh *m = W->m;
    for (size_t i = 0; i < S->nverts; ++i)
        sk__vc1_interior_points(W, S->verts[i]);
    for (size_t i = 0; i < S->nfaces; ++i) {
        double *o = out + 48 * i;
        const double *b = S->base + 48 * i;
        if (i < S->nfaces_v) {
            sk__vc1_assemble_patch(W, S->faces[i], o);
            for (int x = 0; x < 48; ++x)
                o[x] -= b[x];
            continue;
        }
        uint32_t h = m->f_halfedge[S->faces[i]];
        for (int k = 0; k < S->corners[i]; ++k, h = m->h_next[h]) {
            unsigned slot = interior_slot(S->corners[i], k);
            for (int x = 0; x < 3; ++x)
                o[3 * slot + x] = W->C[3 * (size_t)h + x] - b[3 * slot + x];
        }
    }
}

/* 4 x 4 symmetric positive definite solve by Cholesky; false when not positive definite */
static bool solve4(double A[4][4], double b[4], double x[4])
{
    double L[4][4] = {{0}};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j <= i; ++j) {
            double s = A[i][j];
            for (int k = 0; k < j; ++k)
                s -= L[i][k] * L[j][k];
            if (i == j) {
                if (!(s > 1e-14 * (fabs(A[0][0]) + fabs(A[3][3]))))
                    return false;
                L[i][i] = sqrt(s);
            } else {
                L[i][j] = s / L[j][j];
            }
        }
    double y[4];
    for (int i = 0; i < 4; ++i) {
        double s = b[i];
        for (int k = 0; k < i; ++k)
            s -= L[i][k] * y[k];
        y[i] = s / L[i][i];
    }
    for (int i = 3; i >= 0; --i) {
        double s = y[i];
        for (int k = i + 1; k < 4; ++k)
            s -= L[k][i] * x[k];
        x[i] = s / L[i][i];
    }
    return true;
}

/* consecutive tangents (2D, counter-clockwise) keep alpha < angle / pi < 1 - alpha */
static bool angles_ok(const double *q, int n, int closed, double alpha)
{
    int pairs = closed ? n : n - 1;
    for (int k = 0; k < pairs; ++k) {
        const double *a = q + 2 * k, *b = q + 2 * ((k + 1) % n);
        double ang = atan2(sk__cross2(a, b), sk__dot2(a, b));
        if (!(ang > alpha * M_PI && ang < M_PI * (1.0 - alpha)))
            return false;
    }
    return true;
}

/* One row of an unknown's Jacobian: control point `row` of the net in slot `slot` moves by
 * e_ra r[cb] per unit of the vertex's map parameter a = (ra, cb) (e: its tangent basis). */
typedef struct fair_row {
    uint32_t slot, row;
    double r[2];
} fair_row;

/* One unknown vertex v: its rows, the 4 x 4 Hessian of its block (bending and targets), the
 * target term's own Hessian and gradient at x = 0, the offset of its tangents (as solved, 2 per
 * edge) in the model's pool, and its map D = [x0 x1; x2 x3] (p -> (I + D) p). */
typedef struct fair_var {
    uint32_t v;
    int n, closed;
    size_t first, nrows, p0;
    double e[2][3], H[4][4], Ht[4][4], tg[4], x[4];
} fair_var;

/* A control net that some unknown moves: its face and its current points */
typedef struct fair_slot {
    uint32_t face;
    int corners;
    double net[48];
} fair_slot;

/* The quadratic model of the energy in the maps of all unknowns: every control net the unknowns
 * move is affine in their D (exactly: system (4) is linear in the tangents), so it is kept as
 * its current value in its slot (updated by the rows after each step); a block step is a
 * 4 x 4 solve with the gradient from those nets, no system (4) and no patch assembly. */
typedef struct fair_model {
    fair_var *vars;
    size_t nvars, capvars;
    fair_row *rows;
    size_t nrows, caprows;
    double *p;
    size_t np, capp;
    uint32_t *slot_of; /* per face of the mesh: its slot, SK_INVALID while no unknown moves it */
    fair_slot *slots;
    size_t nslots, capslots;
    uint32_t *var_of; /* per vertex: its unknown, FAIR_NO_VAR for none, SK_INVALID not yet */
    double energy_before;
    const sk__fit_data *fit; /* the data term (NULL: none) */
} fair_model;

/* p (*cap elements of size sz) grown to hold at least need; NULL when out of memory (p is then
 * kept as it was) */
static void *reserve(void *p, size_t *cap, size_t need, size_t sz)
{
    if (need <= *cap)
        return p;
    size_t c = *cap ? *cap : 64;
    while (c < need)
        c *= 2;
    void *q = sk__realloc_array(p, c, sz);
    if (q)
        *cap = c;
    return q;
}

/* The tangents p (2 per edge, in the basis e of v's tangent plane) of v's edges E as they stand
 * in W->P, and what of them lies off the plane (rounding; kept as it is). */
static void vertex_tangents(const sk__vc1_work *W, uint32_t v, const uint32_t *E, int n,
                            double e[2][3], double *p, double *off)
{
    const double *V = W->m->positions + 3 * (size_t)v;
    sk__tangent_basis(W->normals + 3 * (size_t)v, e[0], e[1]);
    for (int k = 0; k < n; ++k) {
        double d[3];
        sk__sub3(d, W->P + 3 * (size_t)E[k], V);
        p[2 * k] = sk__dot3(d, e[0]);
        p[2 * k + 1] = sk__dot3(d, e[1]);
        for (int x = 0; x < 3; ++x)
            off[3 * k + x] = d[x] - p[2 * k] * e[0][x] - p[2 * k + 1] * e[1][x];
    }
}

/* direction a = (ra, cb) of a vertex's map: delta p = e_ra (p . e_cb) */
static const int fair_dirs[4][2] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};

/* The differences of the local patches at v (the vertex's tangents as solved) in the directions
 * along e_0 (a = (0, 0), (0, 1)) into S->dir[0, 1] (systems (4) and the assembly act on each
 * coordinate alike, with scalar coefficients, so the points move along e_0 by some r and, in the
 * directions along e_1, by the same r along e_1), and the patches as they stand into S->base (from s->surface: W is the state it
 * was assembled from until the sweeps end); W is left exactly as it was. */
static void local_jacobian(const sk_smooth *s, sk__vc1_work *W, const uint32_t *E, int n,
                           double e[2][3], const double *p, fair_scratch *S)
{
    double P0[3 * SK_VSYS_MAX];
    for (int k = 0; k < n; ++k)
        memcpy(P0 + 3 * k, W->P + 3 * (size_t)E[k], 3 * sizeof(double));
    save_restore_C(W, S, false);
    for (size_t i = 0; i < S->nfaces; ++i)
        memcpy(S->base + 48 * i, sk_patch_cp(&s->surface, S->faces[i]),
               3 * sizeof(double) * sk_patch_num_points(&s->surface.patches[S->faces[i]]));
    for (int d = 0; d < 2; ++d) { /* the directions along e_0: fair_dirs[0, 1] */
        for (int k = 0; k < n; ++k) {
            double *P = W->P + 3 * (size_t)E[k], c = p[2 * k + fair_dirs[d][1]];
            for (int x = 0; x < 3; ++x)
                P[x] += c * e[fair_dirs[d][0]][x];
        }
        local_difference(W, S, S->dir[d]);
        for (int k = 0; k < n; ++k) /* restored exactly */
            memcpy(W->P + 3 * (size_t)E[k], P0 + 3 * k, 3 * sizeof(double));
    }
    save_restore_C(W, S, true);
}

/* The slot of face i of S (a new one holds its net as it stands, S->base); SK_INVALID when out
 * of memory. */
static uint32_t face_slot(fair_model *M, const fair_scratch *S, size_t i, const double *qt,
                          const double *qq)
{
    uint32_t f = S->faces[i];
    if (M->slot_of[f] != SK_INVALID)
        return M->slot_of[f];
    fair_slot *grown = reserve(M->slots, &M->capslots, M->nslots + 1, sizeof(fair_slot));
    if (!grown)
        return SK_INVALID;
    M->slots = grown;
    uint32_t sl = (uint32_t)M->nslots++;
    M->slots[sl].face = f;
    M->slots[sl].corners = S->corners[i];
    memcpy(M->slots[sl].net, S->base + 48 * i, 48 * sizeof(double));
    M->energy_before += sk__fair_patch_energy(qt, qq, S->corners[i], S->base + 48 * i);
    M->slot_of[f] = sl;
    return sl;
}

/* The rows of face i (its control points that some direction moves: exact zeros elsewhere) and
 * their part of the bending Hessian H (lower triangle; a = (ra, cb) at 2 ra + cb: the blocks of
 * ra = 0 and 1 are the same 2 x 2 K, the others zero); false when out of memory. */
static bool face_rows(fair_model *M, const fair_scratch *S, size_t i, const double e0[3],
                      const double *qt, const double *qq, double H[4][4])
{
    int nc = S->corners[i] == 3 ? 15 : 16, idx[16], ni = 0;
    const double *Q = nc == 15 ? qt : qq;
    unsigned cand = i < S->nfaces_v ? 0xffffu : interior_mask(S->corners[i]);
    double r[16][2];
    for (int c = 0; c < nc; ++c) {
        if (!(cand >> c & 1u))
            continue; /* exactly zero in every direction (local_difference) */
        for (int d = 0; d < 2; ++d)
            r[ni][d] = sk__dot3(S->dir[d] + 48 * i + 3 * c, e0);
        if (r[ni][0] != 0.0 || r[ni][1] != 0.0)
            idx[ni++] = c;
    }
    if (!ni)
        return true;
    uint32_t sl = face_slot(M, S, i, qt, qq);
    fair_row *grown = sl == SK_INVALID ? NULL
                      : reserve(M->rows, &M->caprows, M->nrows + (size_t)ni, sizeof(fair_row));
    if (!grown)
        return false;
    M->rows = grown;
    double K[2][2] = {{0, 0}, {0, 0}};
    for (int ri = 0; ri < ni; ++ri) {
        fair_row *row = &M->rows[M->nrows + (size_t)ri];
        row->slot = sl;
        row->row = (uint32_t)idx[ri];
        row->r[0] = r[ri][0], row->r[1] = r[ri][1];
        const double *Qr = Q + nc * idx[ri];
        double q[2] = {0, 0};
        for (int ci = 0; ci < ni; ++ci) {
            q[0] += Qr[idx[ci]] * r[ci][0];
            q[1] += Qr[idx[ci]] * r[ci][1];
        }
        K[0][0] += r[ri][0] * q[0];
        K[1][0] += r[ri][1] * q[0];
        K[1][1] += r[ri][1] * q[1];
    }
    for (int ra = 0; ra < 2; ++ra) {
        H[2 * ra][2 * ra] += K[0][0];
        H[2 * ra + 1][2 * ra] += K[1][0];
        H[2 * ra + 1][2 * ra + 1] += K[1][1];
    }
    M->nrows += (size_t)ni;
    return true;
}

/* The model's arrays sized once for the region (nregion vertices, edges edges around them):
 * the unknowns and their tangents exactly, the rows and the patches as measured (about 55 rows
 * and 2.4 patches per unknown on the cow; they grow when needed); false when out of memory. */
static bool model_reserve(fair_model *M, size_t nregion, size_t edges)
{
    fair_var *vars = reserve(M->vars, &M->capvars, nregion + 1, sizeof(fair_var));
    if (vars)
        M->vars = vars;
    double *p = vars ? reserve(M->p, &M->capp, 2 * edges + 1, sizeof(double)) : NULL;
    if (p)
        M->p = p;
    fair_row *rows = p ? reserve(M->rows, &M->caprows, 64 * nregion + 1, sizeof(fair_row)) : NULL;
    if (rows)
        M->rows = rows;
    fair_slot *slots =
        rows ? reserve(M->slots, &M->capslots, 3 * nregion + 1, sizeof(fair_slot)) : NULL;
    if (slots)
        M->slots = slots;
    return slots != NULL;
}

/* The data term's part of an unknown's Hessian (lower triangle, as face_rows) from its rows in
 * face f: at a point with basis B the surface moves by s_cb = sum_rows B_row r[cb] along e_ra per
 * unit of a = (ra, cb); the foot points are fixed, so this is constant. */
static void data_hessian(const fair_model *M, uint32_t f, int corners, const fair_row *rows,
                         size_t nrows, double H[4][4])
{
    const sk__fit_data *fit = M->fit;
    double K[2][2] = {{0, 0}, {0, 0}}, B[16];
    for (size_t j = fit->first[f]; j < fit->first[f + 1]; ++j) {
        sk__fit_basis(corners, fit->uv[2 * j], fit->uv[2 * j + 1], B);
        double sc[2] = {0, 0};
        for (size_t ri = 0; ri < nrows; ++ri) {
            sc[0] += B[rows[ri].row] * rows[ri].r[0];
            sc[1] += B[rows[ri].row] * rows[ri].r[1];
        }
        K[0][0] += sc[0] * sc[0];
        K[1][0] += sc[1] * sc[0];
        K[1][1] += sc[1] * sc[1];
    }
    for (int ra = 0; ra < 2; ++ra) {
        H[2 * ra][2 * ra] += fit->weight * K[0][0];
        H[2 * ra + 1][2 * ra] += fit->weight * K[1][0];
        H[2 * ra + 1][2 * ra + 1] += fit->weight * K[1][1];
    }
}

/* The data term's part of an unknown's gradient G (half of it, as the bending part) from the
 * nets as they stand: for each face its rows move, sum over its points of
 * W s_cb (S(u_i) - p_i) . e_ra. */
static void data_gradient(const fair_model *M, const fair_var *var, double G[4])
{
    const sk__fit_data *fit = M->fit;
    double B[16];
    for (size_t i = var->first; i < var->first + var->nrows;) {
        size_t end = i;
        uint32_t sl = M->rows[i].slot;
        while (end < var->first + var->nrows && M->rows[end].slot == sl)
            ++end;
        const fair_slot *slot = &M->slots[sl];
        int nc = slot->corners == 3 ? 15 : 16;
        for (size_t j = fit->first[slot->face]; j < fit->first[slot->face + 1]; ++j) {
            sk__fit_basis(slot->corners, fit->uv[2 * j], fit->uv[2 * j + 1], B);
            double res[3];
            for (int x = 0; x < 3; ++x)
                res[x] = -fit->p[3 * j + x];
            for (int c = 0; c < nc; ++c)
                sk__axpy3(res, res, B[c], slot->net + 3 * c);
            double sc[2] = {0, 0};
            for (size_t r = i; r < end; ++r) {
                sc[0] += B[M->rows[r].row] * M->rows[r].r[0];
                sc[1] += B[M->rows[r].row] * M->rows[r].r[1];
            }
            double g[2] = {sk__dot3(res, var->e[0]), sk__dot3(res, var->e[1])};
            for (int a = 0; a < 4; ++a)
                G[a] += fit->weight * sc[a & 1] * g[a >> 1];
        }
        i = end;
    }
}

/* Adds v as an unknown of the model (when its star fits); false when out of memory. */
static bool model_add(fair_model *M, const sk_smooth *s, sk__vc1_work *W, const double *qt,
                      const double *qq, uint32_t v, fair_scratch *S)
{
    uint32_t E[SK_VSYS_MAX];
    int closed, n = sk__vc1_ordered_edges(W->m, v, E, &closed);
    if (n < 2 || !gather(W->m, v, S))
        return true;
    double e[2][3], p[2 * SK_VSYS_MAX], off[3 * SK_VSYS_MAX];
    vertex_tangents(W, v, E, n, e, p, off);
    local_jacobian(s, W, E, n, e, p, S);
    fair_var *vars = reserve(M->vars, &M->capvars, M->nvars + 1, sizeof(fair_var));
    if (vars)
        M->vars = vars;
    double *pool = vars ? reserve(M->p, &M->capp, M->np + 2 * (size_t)n, sizeof(double)) : NULL;
    if (!pool)
        return false;
    M->p = pool;
    fair_var *var = &M->vars[M->nvars];
    memset(var, 0, sizeof *var);
    var->v = v, var->n = n, var->closed = closed, var->first = M->nrows, var->p0 = M->np;
    memcpy(M->p + M->np, p, 2 * (size_t)n * sizeof(double));
    M->np += 2 * (size_t)n;
    memcpy(var->e, e, sizeof var->e);
    for (size_t i = 0; i < S->nfaces; ++i) {
        size_t r0 = M->nrows;
        if (!face_rows(M, S, i, e[0], qt, qq, var->H))
            return false;
        if (M->fit && M->nrows > r0)
            data_hessian(M, S->faces[i], S->corners[i], M->rows + r0, M->nrows - r0, var->H);
    }
    var->nrows = M->nrows - var->first;
    const double *V = W->m->positions + 3 * (size_t)v;
    for (int k = 0; k < n; ++k) {
        double dp[4][2], d[3], t[2];
        sk__sub3(d, W->target + 3 * (size_t)E[k], V);
        t[0] = sk__dot3(d, e[0]);
        t[1] = sk__dot3(d, e[1]);
        for (int a = 0; a < 4; ++a) {
            dp[a][0] = dp[a][1] = 0.0;
            dp[a][fair_dirs[a][0]] = p[2 * k + fair_dirs[a][1]];
        }
        double r[2] = {p[2 * k] - t[0], p[2 * k + 1] - t[1]};
        for (int a = 0; a < 4; ++a) {
            var->tg[a] += FAIR_TARGET_WEIGHT * sk__dot2(dp[a], r);
            for (int b = 0; b <= a; ++b)
                var->Ht[a][b] += FAIR_TARGET_WEIGHT * sk__dot2(dp[a], dp[b]);
        }
    }
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b <= a; ++b) {
            var->H[a][b] += var->Ht[a][b];
            var->H[b][a] = var->H[a][b];
            var->Ht[b][a] = var->Ht[a][b];
        }
    M->var_of[v] = (uint32_t)M->nvars++;
    return true;
}

/* q = (I + D(x)) p for n tangents */
static void map_tangents(const double x[4], const double *p, int n, double *q)
{
    for (int k = 0; k < n; ++k) {
        q[2 * k] = (1.0 + x[0]) * p[2 * k] + x[1] * p[2 * k + 1];
        q[2 * k + 1] = x[2] * p[2 * k] + (1.0 + x[3]) * p[2 * k + 1];
    }
}

/* |d (I + X)^-1| (Frobenius) for the maps X = [x0 x1; x2 x3] and d alike; infinite when I + X
 * is singular */
static double relative_size(const double x[4], const double d[4])
{
    double det = (1.0 + x[0]) * (1.0 + x[3]) - x[1] * x[2];
    if (!(det != 0.0))
        return INFINITY;
    double inv[4] = {(1.0 + x[3]) / det, -x[1] / det, -x[2] / det, (1.0 + x[0]) / det};
    double r[4] = {d[0] * inv[0] + d[1] * inv[2], d[0] * inv[1] + d[1] * inv[3],
                   d[2] * inv[0] + d[3] * inv[2], d[2] * inv[1] + d[3] * inv[3]};
    return sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
}

/* One block step of unknown k: the best map with the others fixed (a 4 x 4 solve), bounded to
 * FAIR_MAX_STEP and halved until the tangents keep the angle bounds (else no step); the nets it
 * moves are updated. Returns the length of the step taken (0 when none). */
static double model_step(fair_model *M, size_t k, const double *qt, const double *qq,
                         double alpha)
{
    fair_var *var = &M->vars[k];
    double G[4], H[4][4], d[4];
    for (int a = 0; a < 4; ++a) {
        G[a] = var->tg[a];
        for (int b = 0; b < 4; ++b)
            G[a] += var->Ht[a][b] * var->x[b];
    }
    for (size_t i = var->first; i < var->first + var->nrows; ++i) {
        const fair_row *r = &M->rows[i];
        int nc = M->slots[r->slot].corners == 3 ? 15 : 16;
        const double *Qr = (nc == 15 ? qt : qq) + nc * (int)r->row;
        const double *b = M->slots[r->slot].net;
        double qb[3] = {0, 0, 0};
        for (int c = 0; c < nc; ++c)
            sk__axpy3(qb, qb, Qr[c], b + 3 * c);
        double g[2] = {sk__dot3(qb, var->e[0]), sk__dot3(qb, var->e[1])};
        for (int a = 0; a < 4; ++a)
            G[a] += r->r[a & 1] * g[a >> 1];
    }
    if (M->fit)
        data_gradient(M, var, G);
    for (int a = 0; a < 4; ++a) {
        G[a] = -G[a];
        memcpy(H[a], var->H[a], sizeof H[a]);
    }
    if (!solve4(H, G, d))
        return 0.0;
    /* the step as a map of the tangents as they stand: (I + D') (I + X) = I + X + d, so
     * D' = d (I + X)^-1; its size bounds the step and says whether the vertex moved */
    double len = relative_size(var->x, d);
    if (!(len > FAIR_MIN_STEP))
        return 0.0;
    if (len > FAIR_MAX_STEP) {
        for (int a = 0; a < 4; ++a)
            d[a] *= FAIR_MAX_STEP / len;
        len = FAIR_MAX_STEP;
    }
    double q[2 * SK_VSYS_MAX], xn[4];
    for (int tries = 0; tries < 4; ++tries, len *= 0.5) {
        for (int a = 0; a < 4; ++a)
            xn[a] = var->x[a] + d[a];
        map_tangents(xn, M->p + var->p0, var->n, q);
        if (angles_ok(q, var->n, var->closed, alpha)) {
            memcpy(var->x, xn, sizeof xn);
            for (size_t i = var->first; i < var->first + var->nrows; ++i) {
                const fair_row *r = &M->rows[i];
                double *b = M->slots[r->slot].net + 3 * r->row;
                sk__axpy3(b, b, r->r[0] * d[0] + r->r[1] * d[1], var->e[0]);
                sk__axpy3(b, b, r->r[0] * d[2] + r->r[1] * d[3], var->e[1]);
            }
            return len;
        }
        for (int a = 0; a < 4; ++a)
            d[a] *= 0.5;
    }
    return 0.0;
}

/* Largest distance of a control point of patch p from the plane of its corners (Newell normal),
 * relative to its longest side: a cheap bound-like proxy of the overshoot. */
static double net_overshoot(const sk_smooth *s, size_t p)
{
    const sk_patch *pa = &s->surface.patches[p];
    unsigned nc = sk_patch_num_corners(pa), np = sk_patch_num_points(pa);
    const double *X[4];
    double n[3] = {0, 0, 0}, c[3] = {0, 0, 0}, longest = 0.0;
    for (unsigned i = 0; i < nc; ++i)
        X[i] = s->config->positions + 3 * (size_t)pa->corner_ids[i];
    for (unsigned i = 0; i < nc; ++i) {
        const double *a = X[i], *b = X[(i + 1) % nc];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
        sk__axpy3(c, c, 1.0 / nc, a);
        longest = fmax(longest, sk__dist3(a, b));
    }
    if (sk__normalize3(n) == 0.0 || !(longest > 0.0))
        return 0.0;
    const double *cp = sk_patch_cp(&s->surface, p);
    double worst = 0.0;
    for (unsigned i = 0; i < np; ++i) {
        double d[3];
        sk__sub3(d, cp + 3 * i, c);
        worst = fmax(worst, fabs(sk__dot3(d, n)));
    }
    return worst / longest;
}

/* sk__fair_patch_energy over the upper triangle of Q (half the products; the same to rounding) */
static double net_energy(const double *qt, const double *qq, int corners, const double *b)
{
    int n = corners == 3 ? 15 : 16;
    const double *Q = corners == 3 ? qt : qq;
    double e = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = 0.5 * Q[n * i + i] * sk__dot3(b + 3 * i, b + 3 * i);
        for (int j = i + 1; j < n; ++j)
            r += Q[n * i + j] * sk__dot3(b + 3 * i, b + 3 * j);
        e += 2.0 * r;
    }
    return e;
}

/* The vertices to start from: the corners of the patches (assembled in s->surface) that are
 * singular or whose control net strays from their face by more than FAIR_SEED_OVERSHOOT of the
 * longest side, and the neighbours of those corners; pe gets the bending energy of every patch. */
static size_t seed_vertices(const sk_smooth *s, const uint8_t *status, const uint8_t *limit,
                            uint8_t *active, uint8_t *bad, uint8_t *sing, const double *qt,
                            const double *qq, double *pe)
{
    const sk_mesh *m = s->config;
    long np = (long)s->surface.count;
#ifdef SK_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 256) if (np >= SK_SMOOTH_TEAM_MIN)
#endif
    for (long p = 0; p < np; ++p) {
        const sk_patch *pa = &s->surface.patches[p];
        bool in = !limit;
        for (unsigned i = 0; !in && i < sk_patch_num_corners(pa); ++i)
            in = limit[pa->corner_ids[i]];
        sing[p] = in && sk__patch_singular(s, (size_t)p, NULL);
        bad[p] = in && (sing[p] || net_overshoot(s, (size_t)p) > FAIR_SEED_OVERSHOOT);
        pe[p] = net_energy(qt, qq, (int)sk_patch_num_corners(pa),
                           sk_patch_cp(&s->surface, (size_t)p));
    }
    memset(active, 0, m->num_vertices);
    for (long p = 0; p < np; ++p) {
        if (!bad[p])
            continue;
        const sk_patch *pa = &s->surface.patches[p];
        for (unsigned i = 0; i < sk_patch_num_corners(pa); ++i) {
            uint32_t v = pa->corner_ids[i], h0 = m->v_halfedge[v], h = h0;
            active[v] = 1;
            do {
                active[sk_to(m, h)] = 1;
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
    }
    size_t n = 0;
    for (uint32_t v = 0; v < m->num_vertices; ++v) {
        active[v] = active[v] && !m->v_deleted[v] && m->v_halfedge[v] != SK_INVALID &&
                    status[v] < 2;
        n += active[v];
    }
    return n;
}

/* r gets the vertices within `rings` rings of those set in r (tmp: scratch of the same size) */
static void grow(const sk_mesh *m, uint8_t *r, uint8_t *tmp, int rings)
{
    size_t nv = m->num_vertices;
    for (int ring = 0; ring < rings; ++ring) {
        memcpy(tmp, r, nv);
        for (uint32_t v = 0; v < nv; ++v)
            if (tmp[v]) {
                uint32_t h0 = m->v_halfedge[v], h = h0;
                do {
                    r[sk_to(m, h)] = 1;
                    h = sk_cw_out(m, h);
                } while (h != h0);
            }
    }
}

/* The final maps written into W->P (the tangents of each moved unknown), system (4) solved again
 * at the moved vertices and their neighbours (mark: per vertex, zero before and after), and sing
 * of the patches around those set unknown (the patches to assemble again). */
static void model_write(const fair_model *M, sk__vc1_work *W, uint8_t *mark, uint8_t *sing)
{
    const sk_mesh *m = W->m;
    for (size_t k = 0; k < M->nvars; ++k) {
        const fair_var *var = &M->vars[k];
        if (var->x[0] == 0.0 && var->x[1] == 0.0 && var->x[2] == 0.0 && var->x[3] == 0.0)
            continue;
        uint32_t E[SK_VSYS_MAX], v = var->v;
        int closed, n = sk__vc1_ordered_edges(m, v, E, &closed);
        double e[2][3], p[2 * SK_VSYS_MAX], off[3 * SK_VSYS_MAX], q[2 * SK_VSYS_MAX];
        vertex_tangents(W, v, E, n, e, p, off);
        map_tangents(var->x, p, n, q);
        const double *V = m->positions + 3 * (size_t)v;
        for (int j = 0; j < n; ++j) {
            double *P = W->P + 3 * (size_t)E[j];
            for (int c = 0; c < 3; ++c)
                P[c] = V[c] + q[2 * j] * e[0][c] + q[2 * j + 1] * e[1][c] + off[3 * j + c];
        }
        mark[v] = 1;
        uint32_t h0 = m->v_halfedge[v], h = h0;
        do {
            mark[sk_to(m, h)] = 1;
            h = sk_cw_out(m, h);
        } while (h != h0);
    }
    for (uint32_t v = 0; v < m->num_vertices; ++v)
        if (mark[v]) {
            sk__vc1_interior_points(W, v);
            mark[v] = 0;
            uint32_t h0 = m->v_halfedge[v], h = h0;
            do { /* the patches whose points it may have moved */
                if (m->h_face[h] != SK_INVALID)
                    sing[m->h_face[h]] = SK_SING_UNKNOWN;
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
}

/* Block Gauss-Seidel sweeps in vertex order: the first over the active vertices, each later one
 * over the vertices that stepped by more than FAIR_ACTIVE_STEP in the sweep before and their
 * neighbours, within the region; a vertex becomes an unknown of the model when first visited.
 * Returns the steps taken, SIZE_MAX when out of memory. */
static size_t model_sweeps(fair_model *M, const sk_smooth *s, sk__vc1_work *W,
                           const double *qt, const double *qq, int sweeps, uint8_t *active,
                           uint8_t *next, const uint8_t *region, fair_scratch *S)
{
    const sk_mesh *m = W->m;
    size_t nv = m->num_vertices, count = 0;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        memset(next, 0, nv);
        for (uint32_t v = 0; v < nv; ++v) {
            if (!active[v])
                continue;
            if (M->var_of[v] == SK_INVALID) {
                M->var_of[v] = FAIR_NO_VAR;
                if (!model_add(M, s, W, qt, qq, v, S))
                    return SIZE_MAX;
            }
            if (M->var_of[v] == FAIR_NO_VAR)
                continue;
            double step = model_step(M, M->var_of[v], qt, qq, W->alpha);
            count += step > 0.0;
            next[v] = step > FAIR_ACTIVE_STEP;
        }
        grow(m, next, active, 1);
        for (uint32_t v = 0; v < nv; ++v)
            active[v] = next[v] && region[v];
    }
    return count;
}

static void model_free(fair_model *M)
{
    sk__free(M->vars);
    sk__free(M->rows);
    sk__free(M->p);
    sk__free(M->slot_of);
    sk__free(M->slots);
    sk__free(M->var_of);
}

sk_status sk__vc1_fair_points(const sk_smooth *s, sk__vc1_work *W, const uint8_t *status,
                              int sweeps, const sk__fit_data *fit, uint8_t *sing, uint8_t *before,
                              size_t *moved, double energy[2], sk_error *err)
{
    const sk_mesh *m = W->m;
    size_t nv = m->num_vertices, nf = m->num_faces;
    sk_status st = SK_OK;
    fair_model M = {.fit = fit};
    fair_scratch *S = sk__calloc_array(1, sizeof *S);
    double *qt = sk__malloc_array(15 * 15 + 16 * 16, sizeof(double));
    /* active, next, region (per vertex), bad (per patch) */
    uint8_t *active = sk__malloc_array(3 * nv + s->surface.count + 1, 1);
    uint8_t *next = active + nv, *region = next + nv, *bad = region + nv;
    M.slot_of = sk__malloc_array(nf + 1, sizeof(uint32_t));
    M.var_of = sk__malloc_array(nv + 1, sizeof(uint32_t));
    double *pe = sk__malloc_array(s->surface.count + 1, sizeof(double));
    if (S)
        S->mark = sk__calloc_array(nf + 1, 1);
    if (!S || !qt || !active || !S->mark || !M.slot_of || !M.var_of || !pe)
        goto nomem;
    double *qq = qt + 15 * 15;
    sk__fair_energy_matrices(qt, qq);
    seed_vertices(s, status, W->limit, active, bad, sing, qt, qq, pe);
    if (fit) /* the fit to the scan: every vertex */
        memset(active, 1, nv);
    memcpy(region, active, nv);
    grow(m, region, next, FAIR_REGION_RINGS);
    memset(M.slot_of, 0xff, (nf + 1) * sizeof(uint32_t));
    memset(M.var_of, 0xff, (nv + 1) * sizeof(uint32_t));
    for (uint32_t v = 0; v < nv; ++v)
        region[v] = region[v] && (!W->limit || W->limit[v]) && !m->v_deleted[v] &&
                    m->v_halfedge[v] != SK_INVALID &&
                    status[v] < 2 && !(W->crease_v && W->crease_v[v]);
    /* (a crease vertex has one tangent plane per sector and fixed crease tangents: one linear
     * map of all its tangents would break both, so it keeps its least-squares points) */
    size_t nregion = 0, edges = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        active[v] = active[v] && region[v]; /* the first sweep too */
        nregion += region[v];
        edges += region[v] ? sk_mesh_valence(m, v) : 0;
    }
    if (!model_reserve(&M, nregion, edges))
        goto nomem;
    size_t count = model_sweeps(&M, s, W, qt, qq, sweeps, active, next, region, S);
    if (count == SIZE_MAX)
        goto nomem;
    memset(next, 0, nv);
    if (before)
        memcpy(before, sing, s->surface.count);
    model_write(&M, W, next, sing);
    if (moved)
        *moved = count;
    if (energy) { /* pe: the patches before the sweeps, in order (deterministic) */
        double total = 0.0, after = 0.0;
        for (size_t p = 0; p < s->surface.count; ++p)
            total += pe[p];
        for (size_t sl = 0; sl < M.nslots; ++sl)
            after += sk__fair_patch_energy(qt, qq, M.slots[sl].corners, M.slots[sl].net);
        energy[0] = total;
        energy[1] = total - M.energy_before + after;
    }
    goto done;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "out of memory choosing the fair free points");
done:
    model_free(&M);
    if (S)
        sk__free(S->mark);
    sk__free(S);
    sk__free(qt);
    sk__free(active);
    sk__free(pe);
    return st;
}
