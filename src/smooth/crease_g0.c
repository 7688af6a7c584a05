/* The G0 construction at creases (docs/creases.md, "Construction"): crease edges are patch
 * boundaries shared by the two sides with one cubic, every vertex with a crease edge is cut into
 * sectors (the faces between consecutive crease edges) with one normal each, and each sector's
 * systems (8) and (4) are chains like a boundary vertex's (docs/VC1-NOTES.md section 4) whose
 * crease ends are fixed: the tangent point of a crease edge at V lies in both sectors' tangent
 * planes, on the line V + t (n1 x n2).
 *
 * A vertex with a single crease edge (the end of a crease line) is one sector, a chain from that
 * edge round to itself: both ends are the same fixed point in the vertex's one tangent plane, so
 * the surface is tangent-plane continuous at the vertex and the crease closes smoothly there, and
 * the vertex needs no parity (it is boundary-like for the edge deletion, as every crease vertex). */
#include "smooth/vc1_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <string.h>

/* One sector of a vertex: L[first .. first + n - 1] are its edges counter-clockwise (its patches
 * lie between consecutive ones); fix_first / fix_last: that end is a crease edge (else a boundary
 * edge, free). */
typedef struct sector {
    int first, n, fix_first, fix_last;
} sector;

/* The sectors of vertex v of m cut at its crease edges (ce per edge). Returns the number of
 * entries written to L (every crease edge appears in both its sectors), 0 when v has no crease
 * edge, -1 when they exceed SK_VSYS_MAX. */
static int sectors_of(const sk_mesh *m, const uint8_t *ce, uint32_t v, uint32_t *L, sector *S,
                      int *nsec)
{
    uint32_t E[SK_VSYS_MAX];
    int closed, n = sk__vc1_ordered_edges(m, v, E, &closed), cut[SK_VSYS_MAX], k = 0, len = 0;
    *nsec = 0;
    if (n <= 0)
        return -1;
    for (int i = 0; i < n; ++i)
        if (ce[sk_edge(E[i])] && (closed || (i > 0 && i < n - 1)))
            cut[k++] = i;
    if (k == 0)
        return 0;
    if (closed) {
        for (int s = 0; s < k; ++s) {
            int a = cut[s], b = s + 1 < k ? cut[s + 1] : cut[0] + n;
            if (len + b - a + 1 > SK_VSYS_MAX)
                return -1;
            S[*nsec] = (sector){len, b - a + 1, 1, 1};
            for (int i = a; i <= b; ++i)
                L[len++] = E[i % n];
            ++*nsec;
        }
    } else {
        int a = 0;
        for (int s = 0; s <= k; ++s) {
            int b = s < k ? cut[s] : n - 1;
            if (len + b - a + 1 > SK_VSYS_MAX)
                return -1;
            S[*nsec] = (sector){len, b - a + 1, a != 0, s < k};
            for (int i = a; i <= b; ++i)
                L[len++] = E[i];
            ++*nsec;
            a = b;
        }
    }
    return len;
}

size_t sk__crease_flags(const sk_mesh *m, const uint32_t *pairs, size_t npairs, uint8_t *flags)
{
    size_t n = 0;
    memset(flags, 0, sk_num_edges(m));
    for (size_t i = 0; i < npairs; ++i) {
        uint32_t a = pairs[2 * i], b = pairs[2 * i + 1];
        if (a >= m->num_vertices || b >= m->num_vertices)
            continue;
        uint32_t h = sk__find_halfedge(m, a, b);
        if (h == SK_INVALID || sk_is_boundary_e(m, sk_edge(h)) || flags[sk_edge(h)])
            continue;
        flags[sk_edge(h)] = 1;
        ++n;
    }
    return n;
}

static bool has_edge(const sk_mesh *m, uint32_t a, uint32_t b)
{
    return sk__find_halfedge(m, a, b) != SK_INVALID;
}

/* faces around v: its edges, less the boundary gap */
static size_t face_count(const sk_mesh *m, uint32_t v)
{
    return sk_mesh_valence(m, v) - sk_is_boundary_v(m, v);
}

size_t sk__crease_split_sectors(sk_mesh *m, const uint8_t *crease)
{
    size_t flips = 0;
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f] || sk_mesh_face_size(m, f) != 3)
            continue;
        uint32_t h = m->f_halfedge[f];
        for (int i = 0; i < 3; ++i, h = m->h_next[h]) {
            uint32_t v = sk_from(m, h), third = m->h_next[h], o = sk_opp(third);
            if (!crease[sk_edge(h)] || !crease[sk_edge(m->h_prev[h])] || crease[sk_edge(third)] ||
                m->h_face[o] == SK_INVALID)
                continue;
            /* v has exactly these two crease edges */
            uint32_t g0 = m->v_halfedge[v], g = g0, k = 0;
            do {
                k += crease[sk_edge(g)];
                g = sk_cw_out(m, g);
            } while (g != g0);
            uint32_t a = sk_from(m, third), b = sk_to(m, third), w = sk_to(m, m->h_next[o]);
            if (k != 2 || w == v || has_edge(m, v, w) || face_count(m, a) <= 2 ||
                face_count(m, b) <= 2)
                continue;
            if (flips == 0) { /* per-corner values do not survive a flip (not used by VC1) */
                sk_mesh_set_wedge_uvs(m, 0, NULL, NULL, NULL);
                sk_mesh_set_wedge_normals(m, 0, NULL, NULL, NULL);
            }
            sk__flip_edge(m, third);
            ++flips;
            break; /* f is a new face now */
        }
    }
    return flips;
}

/* angle-weighted normal of sector S of v (its corners at v) into out; false if degenerate */
static bool sector_normal(const sk_mesh *m, uint32_t v, const uint32_t *L, const sector *S,
                          double out[3])
{
    const double *V = m->positions + 3 * (size_t)v;
    out[0] = out[1] = out[2] = 0.0;
    for (int j = 0; j + 1 < S->n; ++j) {
        uint32_t h = L[S->first + j];
        double a[3], b[3], c[3];
        sk__sub3(a, m->positions + 3 * (size_t)sk_to(m, h), V);
        sk__sub3(b, m->positions + 3 * (size_t)sk_from(m, m->h_prev[h]), V);
        sk__cross3(c, a, b);
        double len_c = sk__norm3(c);
        if (len_c > 0.0)
            sk__axpy3(out, out, atan2(len_c, sk__dot3(a, b)) / len_c, c);
    }
    return sk__normalize3(out) > 0.0;
}

/* clears the crease edges connected to edge e through their vertices (the whole line: a piece
 * left over would be a crease without its feature); returns how many */
static size_t drop_line(const sk_mesh *m, uint8_t *crease, uint32_t e)
{
    size_t n = 0, cap = 64, top = 0;
    uint32_t stack_local[64], *stack = stack_local;
    crease[e] = 0;
    stack[top++] = e;
    while (top) {
        uint32_t x = stack[--top];
        ++n;
        uint32_t ends[2] = {sk_from(m, 2 * x), sk_to(m, 2 * x)};
        for (int k = 0; k < 2; ++k) {
            uint32_t h0 = m->v_halfedge[ends[k]], h = h0;
            do {
                uint32_t y = sk_edge(h);
                if (crease[y]) {
                    crease[y] = 0;
                    if (top == cap) { /* a long line: grow the stack */
                        uint32_t *big = sk__malloc_array(2 * cap, sizeof *big);
                        if (!big)
                            return n; /* out of memory: the rest stays (still valid input) */
                        memcpy(big, stack, top * sizeof *big);
                        if (stack != stack_local)
                            sk__free(stack);
                        stack = big;
                        cap *= 2;
                    }
                    stack[top++] = y;
                }
                h = sk_cw_out(m, h);
            } while (h != h0);
        }
    }
    if (stack != stack_local)
        sk__free(stack);
    return n;
}

size_t sk__crease_drop_at(const sk_mesh *m, uint8_t *crease, uint32_t v)
{
    size_t n = 0;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    if (v >= m->num_vertices || h0 == SK_INVALID)
        return 0;
    do {
        if (crease[sk_edge(h)])
            n += drop_line(m, crease, sk_edge(h));
        h = sk_cw_out(m, h);
    } while (h != h0);
    return n;
}

/* cosine of the largest angle allowed between a crease edge and its tangent line at a vertex
 * with two crease edges (75 degrees) */
#define SK_CREASE_TANGENT_COS 0.2588

size_t sk__crease_validate(const sk_mesh *m, uint8_t *crease)
{
    size_t dropped = 0;
    bool changed = true;
    while (changed) {
        changed = false;
        for (uint32_t v = 0; v < m->num_vertices; ++v) {
            if (m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
                continue;
            uint32_t L[SK_VSYS_MAX];
            sector S[SK_VSYS_MAX];
            int ns, len = sectors_of(m, crease, v, L, S, &ns);
            if (len <= 0 || ns != 2 || !S[0].fix_first || !S[0].fix_last)
                continue;
            double n1[3], n2[3], t[3], dx[3], dy[3];
            bool ok = sector_normal(m, v, L, &S[0], n1) && sector_normal(m, v, L, &S[1], n2);
            uint32_t hx = L[S[0].first], hy = L[S[0].first + S[0].n - 1];
            const double *V = m->positions + 3 * (size_t)v;
            sk__cross3(t, n1, n2);
            if (ok && sk__normalize3(t) > 1e-12) {
                sk__sub3(dx, m->positions + 3 * (size_t)sk_to(m, hx), V);
                sk__sub3(dy, m->positions + 3 * (size_t)sk_to(m, hy), V);
                double cx = sk__dot3(dx, t) / sk__norm3(dx), cy = sk__dot3(dy, t) / sk__norm3(dy);
                /* the two crease curves leave V in opposite directions along the line, neither
                 * far from its edge */
                ok = cx * cy < 0.0 && fmin(fabs(cx), fabs(cy)) >= SK_CREASE_TANGENT_COS;
            }
            if (ok)
                continue;
            dropped += drop_line(m, crease, sk_edge(hx));
            changed = true;
        }
    }
    return dropped;
}

/* the file's normal of the corner at from(h) in face(h), h an edge of m (found in file by its
 * vertex ids), into out; false when there is none */
static bool file_corner_normal(const sk_mesh *file, const sk_mesh *m, uint32_t h, double out[3])
{
    uint32_t a = sk_from(m, h), b = sk_to(m, h);
    if (!file || !file->h_wedge_normal || a >= file->num_vertices || b >= file->num_vertices)
        return false;
    uint32_t g = sk__find_halfedge(file, a, b);
    if (g == SK_INVALID || file->h_face[g] == SK_INVALID || file->h_wedge_normal[g] == SK_INVALID)
        return false;
    memcpy(out, file->wedge_normals + 3 * (size_t)file->h_wedge_normal[g], 3 * sizeof(double));
    return isfinite(out[0] + out[1] + out[2]) && sk__normalize3(out) > 0.0;
}

/* the corner normals of two corners (half-edges, their corners at from()) differ */
static bool corners_differ(const sk_mesh *m, uint32_t g, uint32_t h)
{
    uint32_t a = m->h_wedge_normal[g], b = m->h_wedge_normal[h];
    if (a == b || a == SK_INVALID || b == SK_INVALID)
        return false;
    double x[3], y[3], c[3];
    memcpy(x, m->wedge_normals + 3 * (size_t)a, sizeof x);
    memcpy(y, m->wedge_normals + 3 * (size_t)b, sizeof y);
    sk__cross3(c, x, y);
    /* more than about 1e-6 radians apart (rounding in the file's digits is not a crease) */
    return sk__norm3(c) > 1e-6 * sk__norm3(x) * sk__norm3(y) || sk__dot3(x, y) < 0.0;
}

size_t sk__corner_normal_creases(const sk_mesh *m, uint8_t *crease)
{
    size_t n = 0;
    for (uint32_t e = 0; e < sk_num_edges(m); ++e) {
        uint32_t h = 2 * e, o = h + 1;
        if (crease[e] || m->e_deleted[e] || m->h_face[h] == SK_INVALID ||
            m->h_face[o] == SK_INVALID)
            continue;
        /* at from(h): face(h)'s corner is h, face(o)'s is next(o); at to(h): next(h) and o */
        if (corners_differ(m, h, m->h_next[o]) || corners_differ(m, m->h_next[h], o)) {
            crease[e] = 1;
            ++n;
        }
    }
    return n;
}

sk_status sk__crease_setup(const sk_mesh *m, const double *normals, const sk_mesh *src,
                           const uint8_t *src_crease, const sk_mesh *file, uint8_t **crease_e,
                           double **cn, sk_error *err)
{
    size_t ne = sk_num_edges(m), nh = m->num_halfedges, nv = m->num_vertices;
    *crease_e = NULL;
    *cn = NULL;
    uint8_t *ce = sk__calloc_array(ne ? ne : 1, 1);
    double *N = sk__malloc_array(nh + 1, 3 * sizeof(double));
    uint8_t *cv = sk__calloc_array(nv ? nv : 1, 1);
    sk_status st = SK_OK;
    if (!ce || !N || !cv) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory setting up the creases");
        goto done;
    }
    size_t found = 0;
    for (uint32_t e = 0; e < sk_num_edges(src); ++e) {
        if (!src_crease[e])
            continue;
        uint32_t a = sk_from(src, 2 * e), b = sk_to(src, 2 * e);
        uint32_t h = a < nv && b < nv ? sk__find_halfedge(m, a, b) : SK_INVALID;
        if (h != SK_INVALID && !sk_is_boundary_e(m, sk_edge(h)) && !ce[sk_edge(h)]) {
            ce[sk_edge(h)] = 1;
            ++found;
        }
    }
    if (found == 0)
        goto done; /* none: no creases */
    for (uint32_t e = 0; e < ne; ++e)
        if (ce[e])
            cv[sk_from(m, 2 * e)] = cv[sk_to(m, 2 * e)] = 1;
    for (size_t h = 0; h < nh; ++h)
        memcpy(N + 3 * h, normals + 3 * (size_t)sk_from(m, (uint32_t)h), 3 * sizeof(double));
    for (uint32_t v = 0; v < nv; ++v) {
        if (!cv[v] || m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
            continue;
        uint32_t L[SK_VSYS_MAX];
        sector S[SK_VSYS_MAX];
        int ns, len = sectors_of(m, ce, v, L, S, &ns);
        if (len < 0) {
            st = sk__fail(err, SK_ERR_TOPOLOGY, "vertex %u has more than %d edges", v,
                          SK_VSYS_MAX);
            goto done;
        }
        if (ns <= 1)
            continue; /* one sector (a crease end): the vertex normal */
        for (int s = 0; s < ns; ++s) {
            double sum[3];
            if (file_corner_normal(file, m, L[S[s].first], sum)) {
                /* the file's normal of the sector */
            } else if (!sector_normal(m, v, L, &S[s], sum)) {
                st = sk__fail(err, SK_ERR_NUMERIC,
                              "vertex %u: a crease sector of degenerate faces has no normal", v);
                goto done;
            }
            for (int j = 0; j + 1 < S[s].n; ++j)
                memcpy(N + 3 * (size_t)L[S[s].first + j], sum, sizeof sum);
        }
    }
    /* a boundary half-edge (no face) takes the normal of the sector on its other side */
    for (size_t h = 0; h < nh; ++h) {
        uint32_t o = sk_opp((uint32_t)h);
        if (m->h_face[h] == SK_INVALID && m->h_face[o] != SK_INVALID &&
            cv[sk_from(m, (uint32_t)h)])
            memcpy(N + 3 * h, N + 3 * (size_t)m->h_next[o], 3 * sizeof(double));
    }
    *crease_e = ce;
    *cn = N;
    ce = NULL;
    N = NULL;
done:
    sk__free(ce);
    sk__free(N);
    sk__free(cv);
    return st;
}

void sk__crease_targets(const sk_mesh *m, const uint8_t *ce, const double *cn, double *target)
{
    for (uint32_t h = 0; h < m->num_halfedges; ++h) {
        if (!ce[sk_edge(h)])
            continue;
        const double *V = m->positions + 3 * (size_t)sk_from(m, h);
        const double *n1 = cn + 3 * (size_t)h, *n2 = cn + 3 * (size_t)m->h_next[sk_opp(h)];
        double d[3], t[3];
        sk__sub3(d, m->positions + 3 * (size_t)sk_to(m, h), V);
        double len = sk__norm3(d);
        sk__cross3(t, n1, n2);
        if (sk__norm3(t) <= 1e-12) {
            /* one normal on both sides (a crease end): the edge projected into its plane */
            sk__axpy3(t, d, -sk__dot3(d, n1), n1);
        }
        if (sk__normalize3(t) == 0.0) {
            /* the edge is normal to the tangent plane: any tangent direction will do */
            double a[3] = {fabs(n1[0]) > 0.6 ? 0.0 : 1.0, fabs(n1[0]) > 0.6 ? 1.0 : 0.0, 0.0};
            sk__cross3(t, a, n1);
            sk__normalize3(t);
        }
        if (sk__dot3(t, d) < 0.0)
            sk__scale3(t, t, -1.0);
        /* the wire frame's length rule (wireframe.c): a third of the chord, lengthened for the
         * angle phi between the tangent line and the chord as a circular arc would be */
        double phi = len > 0.0 ? acos(fmin(1.0, sk__dot3(t, d) / len)) : 0.0;
        if (phi > M_PI / 2)
            phi = M_PI / 2;
        double c = cos(phi / 2);
        sk__axpy3(target + 3 * (size_t)h, V, len / (3.0 * c * c), t);
    }
}

/* The ring L and sectors S of crease vertex v when it has two sectors and the first is fixed at
 * both ends (by crease edges); false for any other vertex. */
static bool two_sectors(const sk__vc1_work *W, uint32_t v, uint32_t *L, sector *S)
{
    const sk_mesh *m = W->m;
    if (!W->crease_v[v] || m->v_deleted[v] || m->v_halfedge[v] == SK_INVALID)
        return false;
    int ns, len = sectors_of(m, W->crease_e, v, L, S, &ns);
    return len > 0 && ns == 2 && S[0].fix_first && S[0].fix_last;
}

/* ratio -nu Delta_d / Delta_u of the interior edge h of a two-face sector */
static double sector_ratio(const sk__vc1_work *W, uint32_t h)
{
    const sk_mesh *m = W->m;
    double du = sk__face_delta(m, m->h_face[h]), dd = sk__face_delta(m, m->h_face[sk_opp(h)]);
    return -W->nu[h] * dd / du;
}

/* A vertex with exactly two crease edges X, Y has two sectors with the same two normals, so
 * both crease tangents lie on one line V + t (n1 x n2): p_Y = -c p_X, c = |p_Y| / |p_X|. A sector
 * with one interior edge (two faces, chain p_X, p_1, p_Y) then meets its one constraint (8),
 * Delta_u p_Y - nu Delta_d p_X = w p_1, only with p_1 on that line (a degenerate corner) unless
 * c = -nu Delta_d / Delta_u (then w = 0 and p_1 is free). So the two tangent lengths are set to
 * that ratio, keeping their product (the other sector has at least two interior edges and
 * takes any ratio, or none). Returns the number of vertices where both sectors have one interior
 * edge with ratios that disagree (their systems cannot be met). */
size_t sk__crease_tangent_ratios(sk__vc1_work *W, double *r, double *target)
{
    const sk_mesh *m = W->m;
    size_t conflicts = 0;
    /* both sectors with two faces: their ratios must be reciprocal. r is free per face (any
     * positive r satisfies (5) around every cyclic vertex), so the first face of the second
     * sector takes the r that makes them so, and the nu of its edges follow */
    for (uint32_t v = 0; v < m->num_vertices; ++v) {
        uint32_t L[SK_VSYS_MAX];
        sector S[SK_VSYS_MAX];
        if (!two_sectors(W, v, L, S) || S[0].n != 3 || S[1].n != 3)
            continue;
        uint32_t ha = L[S[0].first + 1], hb = L[S[1].first + 1], f = m->h_face[hb];
        double k = sector_ratio(W, ha) * sector_ratio(W, hb);
        if (!(k > 0.0) || !isfinite(k))
            continue;
        r[f] /= k;
        uint32_t h0 = m->f_halfedge[f], h = h0;
        do {
            uint32_t g = m->h_face[sk_opp(h)];
            if (g != SK_INVALID && !W->crease_e[sk_edge(h)]) {
                W->nu[h] = sk__nu(r[f], r[g]);
                W->nu[sk_opp(h)] = sk__nu(r[g], r[f]);
            }
            h = m->h_next[h];
        } while (h != h0);
    }
    for (uint32_t v = 0; v < m->num_vertices; ++v) {
        uint32_t L[SK_VSYS_MAX];
        sector S[SK_VSYS_MAX];
        if (!two_sectors(W, v, L, S))
            continue;
        const double *V = m->positions + 3 * (size_t)v;
        double ratio[2];
        int want = 0;
        for (int s = 0; s < 2; ++s) {
            ratio[s] = 0.0;
            if (S[s].n != 3)
                continue;
            ratio[s] = sector_ratio(W, L[S[s].first + 1]); /* |p_last| / |p_first| */
            want |= 1 << s;
        }
        if (!want)
            continue;
        uint32_t hx = L[S[0].first], hy = L[S[0].first + S[0].n - 1]; /* sector 0: X .. Y */
        double c = want & 1 ? ratio[0] : 1.0 / ratio[1];
        if (want == 3 && fabs(ratio[0] * ratio[1] - 1.0) > 1e-9)
            ++conflicts;
        if (!(c > 0.0) || !isfinite(c))
            continue;
        double *tx = target + 3 * (size_t)hx, *ty = target + 3 * (size_t)hy, dx[3], dy[3];
        sk__sub3(dx, tx, V);
        sk__sub3(dy, ty, V);
        double lx = sk__norm3(dx), ly = sk__norm3(dy);
        if (!(lx > 0.0 && ly > 0.0))
            continue;
        double nx = sqrt(lx * ly / c), ny = c * nx;
        sk__axpy3(tx, V, nx / lx, dx);
        sk__axpy3(ty, V, ny / ly, dy);
    }
    return conflicts;
}

static int bad_angles(const sk__vsys *q, double alpha)
{
    double lo, hi;
    sk__vsys_angles(q, &lo, &hi);
    return lo <= alpha * M_PI || hi >= M_PI * (1.0 - alpha);
}

/* blend the free targets of chain q from orig (the fixed ends stay) */
static void blend_free(sk__vsys *q, const double *orig, double alpha, double b, double lb)
{
    int n = q->n_edges;
    sk__vc1_blend_targets(orig, q->pstar, n, 0, alpha, b, lb);
    if (q->fixed_first)
        memcpy(q->pstar, orig, 2 * sizeof(double));
    if (q->fixed_last)
        memcpy(q->pstar + 2 * (n - 1), orig + 2 * (n - 1), 2 * sizeof(double));
}

/* sk__vsys_solve for a sector chain. A sector of two faces between the two crease edges of a
 * vertex with two (fixed ends on one line, their lengths set by sk__crease_tangent_ratios so
 * that Delta_u p_2 - nu Delta_d p_0 = 0) meets its constraint with w = 0 and p_1 free: solved
 * here, since the rounding left in that difference would make the iteration move p_1 onto the
 * line (w p_1 must equal it). */
static int solve_sector(sk__vsys *q)
{
    const double *a = q->pstar, *b = q->pstar + 4;
    if (q->n_edges == 3 && q->fixed_first && q->fixed_last &&
        fabs(a[0] * b[1] - a[1] * b[0]) <= 1e-9 * hypot(a[0], a[1]) * hypot(b[0], b[1]) &&
        a[0] * b[0] + a[1] * b[1] < 0.0) {
        double rx = q->du[1] * b[0] - q->nu[1] * q->dd[1] * a[0];
        double ry = q->du[1] * b[1] - q->nu[1] * q->dd[1] * a[1];
        double scale = (hypot(a[0], a[1]) + hypot(b[0], b[1]) + hypot(q->pstar[2], q->pstar[3])) / 3;
        memcpy(q->p, q->pstar, 6 * sizeof(double));
        q->w[0] = q->w[1] = q->w[2] = 0.0;
        q->residual = scale > 0.0 ? hypot(rx, ry) / scale : 0.0;
        q->iterations = 0;
        q->newton_tries = 0;
        q->used_fallback = 0;
        if (q->residual <= 1e-12)
            return 0;
    }
    return sk__vsys_solve(q);
}

int sk__vc1_solve_crease_vertex(sk__vc1_work *W, uint32_t v, sk__vsys *sys, double blend,
                                double lscale)
{
    const sk_mesh *m = W->m;
    uint32_t L[SK_VSYS_MAX];
    sector S[SK_VSYS_MAX];
    int ns, len = sectors_of(m, W->crease_e, v, L, S, &ns);
    if (len <= 0)
        return 3;
    const double *V = m->positions + 3 * (size_t)v;
    int worst = 0;
    sys->n_edges = len;
    sys->closed = 0;
    sys->fixed_first = sys->fixed_last = 0;
    sys->residual = 0.0;
    sys->iterations = 0;
    sys->newton_tries = 0;
    sys->used_fallback = 0;
    sys->relaxed = blend > 0.0 || lscale != 1.0;
    for (int s = 0; s < ns; ++s) {
        sk__vsys q;
        int n = S[s].n;
        const uint32_t *E = L + S[s].first;
        const double *nrm = W->cn + 3 * (size_t)E[0]; /* face(E[0]) is in the sector */
        double e1[3], e2[3], orig[2 * SK_VSYS_MAX];
        sk__tangent_basis(nrm, e1, e2);
        q.n_edges = n;
        q.closed = 0;
        q.fixed_first = S[s].fix_first;
        q.fixed_last = S[s].fix_last;
        q.relaxed = sys->relaxed;
        for (int k = 0; k < n; ++k) {
            uint32_t h = E[k];
            int fixed = (k == 0 && q.fixed_first) || (k == n - 1 && q.fixed_last);
            double d[3], sc = fixed ? 1.0 : lscale;
            sk__sub3(d, W->target + 3 * (size_t)h, V);
            q.pstar[2 * k] = sc * sk__dot3(d, e1);
            q.pstar[2 * k + 1] = sc * sk__dot3(d, e2);
            if (k > 0 && k < n - 1) {
                q.du[k] = sk__face_delta(m, m->h_face[h]);
                q.dd[k] = sk__face_delta(m, m->h_face[sk_opp(h)]);
                q.nu[k] = W->nu[h];
            } else {
                q.du[k] = q.dd[k] = 1.0;
                q.nu[k] = -1.0;
            }
        }
        memcpy(orig, q.pstar, sizeof(double) * (size_t)(2 * n));
        if (blend > 0.0)
            blend_free(&q, orig, W->alpha, blend, 0.0);
        int ok = solve_sector(&q);
        int bad = ok != 0 || bad_angles(&q, W->alpha);
        /* the relaxation of sk__vc1_solve_vertex, on the free points only */
        for (int t = 1; t <= 8 && bad && n > 2; ++t) {
            double b = t <= 4 ? 0.25 * t : 1.0, lb = t <= 4 ? 0.0 : 0.25 * (t - 4);
            if (b <= blend && lb == 0.0)
                continue;
            blend_free(&q, orig, W->alpha, b, lb);
            ok = solve_sector(&q);
            bad = ok != 0 || bad_angles(&q, W->alpha);
            sys->relaxed = 1;
        }
        for (int k = 0; k < n; ++k) {
            uint32_t h = E[k];
            int fixed = (k == 0 && q.fixed_first) || (k == n - 1 && q.fixed_last);
            double *P = W->P + 3 * (size_t)h;
            if (fixed) {
                /* exactly the shared crease point (both sectors write the same value) */
                memcpy(P, W->target + 3 * (size_t)h, 3 * sizeof(double));
            } else {
                for (int x = 0; x < 3; ++x)
                    P[x] = V[x] + q.p[2 * k] * e1[x] + q.p[2 * k + 1] * e2[x];
            }
            W->w1[h] = k == 0 || k == n - 1 ? NAN : q.w[k];
            /* the caller's view: the sectors one after another */
            int j = S[s].first + k;
            sys->pstar[2 * j] = orig[2 * k];
            sys->pstar[2 * j + 1] = orig[2 * k + 1];
            sys->p[2 * j] = q.p[2 * k];
            sys->p[2 * j + 1] = q.p[2 * k + 1];
            sys->w[j] = W->w1[h];
            sys->du[j] = q.du[k];
            sys->dd[j] = q.dd[k];
            sys->nu[j] = q.nu[k];
        }
        sys->residual = fmax(sys->residual, q.residual);
        sys->iterations += q.iterations;
        sys->newton_tries += q.newton_tries;
        sys->used_fallback |= q.used_fallback;
        int code = ok != 0 ? 2 : bad ? 1 : 0;
        worst = code > worst ? code : worst;
    }
    return worst;
}

void sk__vc1_crease_interior_points(sk__vc1_work *W, uint32_t v)
{
    uint32_t L[SK_VSYS_MAX];
    sector S[SK_VSYS_MAX];
    int ns, len = sectors_of(W->m, W->crease_e, v, L, S, &ns);
    if (len <= 0)
        return;
    for (int s = 0; s < ns; ++s)
        sk__vc1_interior_star(W, v, L + S[s].first, S[s].n, 0);
}
