/* Half-edge collapse V -> W0 (Hormann, Greiner, Campagna, section 3, "Building hierarchy levels",
 * Fig. 3): V = from(h) disappears, W0 = to(h) keeps its position, the one or two triangles at the
 * edge vanish. Legality (all on the current mesh, O(valence) work):
 *  - boundary: a boundary V collapses only along a boundary edge (which also forbids an interior
 *    edge between two boundary vertices); no triangle may lose its last interior edge;
 *  - link condition: the common neighbours of V and W0 are exactly the tips vl, vr of the
 *    triangles at the edge (vl != vr);
 *  - valence: an interior vertex keeps at least min_valence edges, a boundary one at least 2;
 *  - geometry: every other triangle of V's one-ring, with V moved onto W0, keeps a normal within
 *    the threshold angle of its old normal and does not become degenerate (SK_DEGENERATE_REL).
 * With these rules a collapse removes one vertex, three edges and two faces (interior edge) or one
 * vertex, two edges and one face (boundary edge), so V - E + F and the boundary loops stay. */
#include "hierarchy/hierarchy_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>

void sk__collapse_ctx_init(sk__collapse_ctx *ctx, const sk_collapse_opts *opts)
{
    double deg = opts && opts->max_normal_deviation_deg > 0 ? opts->max_normal_deviation_deg : 90.0;
    ctx->stamp = NULL;
    ctx->stamp_value = 0;
    ctx->valence = NULL;
    ctx->cos_max = deg == 90.0 ? 0.0 : (deg >= 180.0 ? -1.0 : cos(deg * M_PI / 180.0));
    ctx->min_valence = opts && opts->min_valence ? opts->min_valence : 3;
}

void sk__collapse_mark_ring(const sk_mesh *m, uint32_t v, sk__collapse_ctx *ctx)
{
    uint32_t s = ++ctx->stamp_value;
    uint32_t h0 = m->v_halfedge[v], h = h0;
    if (h0 == SK_INVALID)
        return;
    do {
        ctx->stamp[m->h_vertex[h]] = s;
        h = sk_cw_out(m, h);
    } while (h != h0);
}

static bool is_neighbour(const sk_mesh *m, uint32_t v, uint32_t w)
{
    uint32_t h0 = m->v_halfedge[v], h = h0;
    do {
        if (m->h_vertex[h] == w)
            return true;
        h = sk_cw_out(m, h);
    } while (h != h0);
    return false;
}

static uint32_t valence_of(const sk_mesh *m, const sk__collapse_ctx *ctx, uint32_t v)
{
    return ctx->valence ? ctx->valence[v] : (uint32_t)sk_mesh_valence(m, v);
}

/* Valence left for w after losing `lost` edges is enough for its kind. */
static bool valence_ok(const sk_mesh *m, const sk__collapse_ctx *ctx, uint32_t w, uint32_t val,
                       uint32_t lost)
{
    uint32_t need = sk_is_boundary_v(m, w) ? 2 : ctx->min_valence;
    return val >= need + lost;
}

bool sk__collapse_ok(const sk_mesh *m, uint32_t h, const sk__collapse_ctx *ctx)
{
    const uint32_t *hv = m->h_vertex, *hn = m->h_next, *hp = m->h_prev, *hf = m->h_face;
    uint32_t o = h ^ 1u, v0 = hv[o], v1 = hv[h];
    if (m->e_deleted[h >> 1])
        return false;
    bool hb = hf[h] == SK_INVALID, ob = hf[o] == SK_INVALID, be = hb || ob;
    bool b0 = sk_is_boundary_v(m, v0), b1 = sk_is_boundary_v(m, v1);
    if (b0 && !be) /* boundary V: only along a boundary edge (and no interior edge between two
                      boundary vertices) */
        return false;
    if (b0 && valence_of(m, ctx, v0) < 3)
        return false; /* a boundary corner with one triangle has no parent triangle (section 3) */
    uint32_t vl = SK_INVALID, vr = SK_INVALID;
    if (!hb) {
        uint32_t a = hn[h], b = hp[h];
        if (hn[a] != b)
            return false; /* not a triangle */
        if (hf[a ^ 1u] == SK_INVALID && hf[b ^ 1u] == SK_INVALID)
            return false; /* the triangle would leave an edge with no face */
        vl = hv[a];
    }
    if (!ob) {
        uint32_t c = hn[o], d = hp[o];
        if (hn[c] != d)
            return false;
        if (hf[c ^ 1u] == SK_INVALID && hf[d ^ 1u] == SK_INVALID)
            return false;
        vr = hv[c];
    }
    if (vl == vr)
        return false;

    /* link condition: common neighbours of v0 and v1 are exactly vl and vr */
    uint32_t expected = (uint32_t)!hb + (uint32_t)!ob, common = 0, val1 = 0;
    uint32_t s = m->v_halfedge[v1], y = s;
    do {
        uint32_t x = hv[y];
        ++val1;
        if (x != v0) {
            bool nb = ctx->stamp ? ctx->stamp[x] == ctx->stamp_value : is_neighbour(m, v0, x);
            if (nb && ++common > expected)
                return false;
        }
        y = hn[y ^ 1u];
    } while (y != s);
    if (common != expected)
        return false;

    /* valences after the collapse */
    uint32_t val0 = valence_of(m, ctx, v0);
    uint32_t merged = val0 + val1 - (be ? 3u : 4u);
    if (merged < ((b0 || b1) ? 2u : ctx->min_valence))
        return false;
    if (vl != SK_INVALID && !valence_ok(m, ctx, vl, valence_of(m, ctx, vl), 1))
        return false;
    if (vr != SK_INVALID && !valence_ok(m, ctx, vr, valence_of(m, ctx, vr), 1))
        return false;

    /* geometry of the triangles that move with V */
    const double *P = m->positions;
    const double *p0 = P + 3 * (size_t)v0, *p1 = P + 3 * (size_t)v1;
    uint32_t fl = hf[h], fr = hf[o];
    s = m->v_halfedge[v0];
    y = s;
    do {
        uint32_t f = hf[y];
        if (f != SK_INVALID && f != fl && f != fr) {
            const double *pa = P + 3 * (size_t)hv[y], *pb = P + 3 * (size_t)hv[hn[y]];
            double ea[3], eb[3], no[3], nn[3], ab[3];
            sk__sub3(ea, pa, p0);
            sk__sub3(eb, pb, p0);
            sk__cross3(no, ea, eb);
            sk__sub3(ea, pa, p1);
            sk__sub3(eb, pb, p1);
            sk__cross3(nn, ea, eb);
            sk__sub3(ab, pb, pa);
            double l2 = sk__dot3(ea, ea), t = sk__dot3(eb, eb), u = sk__dot3(ab, ab);
            l2 = t > l2 ? t : l2;
            l2 = u > l2 ? u : l2;
            double nn2 = sk__dot3(nn, nn);
            /* twice the area <= SK_DEGENERATE_REL * longest edge^2: degenerate */
            if (!(nn2 > SK_DEGENERATE_REL * SK_DEGENERATE_REL * l2 * l2))
                return false;
            double dot = sk__dot3(no, nn);
            if (ctx->cos_max == 0.0) {
                if (!(dot > 0.0))
                    return false;
            } else if (!(dot > ctx->cos_max * sqrt(sk__dot3(no, no) * nn2))) {
                return false;
            }
        }
        y = hn[y ^ 1u];
    } while (y != s);
    return true;
}

void sk__halfedge_take_place(sk_mesh *m, uint32_t x, uint32_t y)
{
    uint32_t n = m->h_next[y], p = m->h_prev[y], f = m->h_face[y];
    m->h_next[x] = n;
    m->h_prev[n] = x;
    m->h_prev[x] = p;
    m->h_next[p] = x;
    m->h_face[x] = f;
    if (f != SK_INVALID)
        m->f_halfedge[f] = x;
}

void sk__collapse(sk_mesh *m, uint32_t h, uint32_t *valence)
{
    uint32_t *hv = m->h_vertex, *hn = m->h_next, *hp = m->h_prev, *hf = m->h_face;
    uint32_t *vh = m->v_halfedge;
    uint32_t o = h ^ 1u, v0 = hv[o], v1 = hv[h];
    uint32_t fl = hf[h], fr = hf[o];
    uint32_t vl = SK_INVALID, vr = SK_INVALID, any1 = SK_INVALID;
    bool be = fl == SK_INVALID || fr == SK_INVALID;
    uint32_t o_next = hn[o];
    uint32_t val0 = valence ? valence[v0] : 0;

    /* every half-edge into V now ends at W0 */
    uint32_t s = vh[v0], y = s;
    do {
        hv[y ^ 1u] = v1;
        y = hn[y ^ 1u];
    } while (y != s);

    if (fl != SK_INVALID) {
        /* triangle (v0, v1, vl): b = vl->v0 (now vl->v1) takes the place of a^1 = vl->v1 */
        uint32_t a = hn[h], b = hp[h], a1 = a ^ 1u;
        vl = hv[a];
        sk__halfedge_take_place(m, b, a1);
        if (vh[vl] == a1)
            vh[vl] = b;
        if (vh[v1] == a)
            vh[v1] = b ^ 1u;
        any1 = b ^ 1u;
        m->f_deleted[fl] = 1;
        m->e_deleted[a >> 1] = 1;
        m->num_deleted_faces++;
        m->num_deleted_edges++;
    } else {
        uint32_t p = hp[h], n = hn[h];
        hn[p] = n;
        hp[n] = p;
    }
    if (fr != SK_INVALID) {
        /* triangle (v1, v0, vr): c = v0->vr (now v1->vr) takes the place of d^1 = v1->vr */
        uint32_t c = hn[o], d = hp[o], d1 = d ^ 1u;
        vr = hv[c];
        sk__halfedge_take_place(m, c, d1);
        if (vh[vr] == d)
            vh[vr] = c ^ 1u;
        if (vh[v1] == d1)
            vh[v1] = c;
        if (any1 == SK_INVALID)
            any1 = c;
        m->f_deleted[fr] = 1;
        m->e_deleted[d >> 1] = 1;
        m->num_deleted_faces++;
        m->num_deleted_edges++;
    } else {
        uint32_t p = hp[o], n = hn[o];
        hn[p] = n;
        hp[n] = p;
    }
    if (fr == SK_INVALID)
        vh[v1] = o_next; /* W0's new boundary half-edge: V's old one (v0->w, now v1->w) */
    else if (vh[v1] == o)
        vh[v1] = any1;

    m->e_deleted[h >> 1] = 1;
    m->num_deleted_edges++;
    m->v_deleted[v0] = 1;
    m->num_deleted_vertices++;
    vh[v0] = SK_INVALID;
    if (valence) {
        valence[v1] = val0 + valence[v1] - (be ? 3u : 4u);
        if (vl != SK_INVALID)
            valence[vl]--;
        if (vr != SK_INVALID)
            valence[vr]--;
        valence[v0] = 0;
    }
}

size_t sk__collapse_ring(const sk_mesh *m, uint32_t h, uint32_t *ring, bool *closed)
{
    size_t k = 0;
    uint32_t y = h;
    *closed = !sk_is_boundary_v(m, m->h_vertex[h ^ 1u]);
    if (m->h_face[h] == SK_INVALID) {
        do { /* clockwise: W0, vr, ..., the other boundary neighbour */
            ring[k++] = m->h_vertex[y];
            y = sk_cw_out(m, y);
        } while (y != h);
    } else {
        do { /* counter-clockwise: W0, vl, ..., vr (or the other boundary neighbour) */
            ring[k++] = m->h_vertex[y];
            y = sk_ccw_out(m, y);
        } while (y != h);
    }
    return k;
}

bool sk_mesh_collapse_ok(const sk_mesh *mesh, uint32_t h, const sk_collapse_opts *opts)
{
    if (!mesh || h >= mesh->num_halfedges || mesh->e_deleted[h >> 1])
        return false;
    sk__collapse_ctx ctx;
    sk__collapse_ctx_init(&ctx, opts);
    return sk__collapse_ok(mesh, h, &ctx);
}

void sk_mesh_collapse(sk_mesh *mesh, uint32_t h)
{
    sk__collapse(mesh, h, NULL);
}
