/* The atlas's packing, with trial cuts when there are few charts: with 2..8 charts the chart cut
 * decides the utilization (a chart with a deep notch or a bend leaves a void its bounding box
 * cannot share), so each chart's layout is cut, in its own plane, by straight lines (6
 * directions, at the 1/8 .. 7/8 quantiles of its triangles along each) into two edge-connected
 * disks; the cuts that save the most smallest-box area, within a seam budget, are packed, and the
 * best kept when the packing's scale grows enough. A cut beyond the budget (up to SPLIT_SEAM_MAX)
 * is kept only when it pays: SPLIT_PAY utilization or more per unit of seam_length_rel added. Each piece keeps its triangles' layout up to a uniform
 * scale that gives it its own 3D area (as every chart has before packing), so MIPS does not
 * change; a cut whose piece is above the atlas's bounds (sigma1/sigma2 or area-log deviation,
 * measured on the piece as on a chart) is not tried. Only the seams grow by the cut. Up to
 * SPLIT_ROUNDS cuts, one packing each. */
#include "atlas/atlas_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* atlases of 2..SPLIT_MAX_CHARTS charts (a disk input stays one chart) and at most
 * SPLIT_MAX_FACES triangles are tried */
#define SPLIT_MAX_CHARTS 8
#define SPLIT_MAX_FACES 20000
#define SPLIT_DIRS 6
#define SPLIT_CUTS 8 /* cut at the k / SPLIT_CUTS quantiles, 0 < k < SPLIT_CUTS */
/* the cuts add at most this fraction of the atlas's seam length (3D) */
#define SPLIT_SEAM 0.10
/* ... or up to this fraction when each cut beyond the budget raises the utilization (the scale
 * squared times the 3D area) by at least SPLIT_PAY per unit of seam length / sqrt(3D area) it
 * adds. The pack cuts within the budget on the shared meshes pay 0.16 (blobby), 0.21 (holes),
 * 0.39 (icosahedron), 0.69 (eight), 0.82 (sphere); beyond it, at up to 30% of the seams, the best
 * cuts pay 0.35 (mask_cone: one cut of 0.20 x sqrt(area) over its budget of 0.14, utilization
 * 0.656 -> 0.739; xatlas 0.662 at seams 2.50 against 1.58), 0.18 (icosahedron's second: 0.612 ->
 * 0.663 at seams 4.76 -> 5.10, above xatlas's 4.76), 0.07 (blobby's second), 0.065 (holes'
 * second), 0.14 (mech-holes-shark): 0.3 takes mask_cone's alone (bench/atlas.sh, issue 11). */
#define SPLIT_SEAM_MAX 0.30
#define SPLIT_PAY 0.3
/* a cut is kept when the utilization (the scale squared) grows by this factor */
#define SPLIT_GAIN 1.01
#define SPLIT_ROUNDS 2
/* the cuts saving the most box area, per round, packed on a coarse grid (COARSE_RES texels, the
 * gutter scaled) to pick one; the layout kept is packed at full resolution once more and kept
 * when it beats the uncut one there too */
#define SPLIT_TRIES 3
#define COARSE_RES 256.0

/* One atlas layout: charts, their uv points (chart c owns [off[c], off[c+1])), the corners. */
typedef struct layout {
    size_t nc, n;
    uint32_t *off, *chart, *corner_uv, *face_chart;
    double *uv;     /* at scale 1, as laid out */
    double *packed; /* the packing of uv */
    double scale;
} layout;

static void layout_free(layout *l)
{
    sk__free(l->off);
    sk__free(l->chart);
    sk__free(l->corner_uv);
    sk__free(l->face_chart);
    sk__free(l->uv);
    sk__free(l->packed);
    memset(l, 0, sizeof *l);
}

/* The charts' outline edges (uv index pairs: edges on the boundary or on a seam), then the
 * packing of l->uv into l->packed. */
static sk_status pack_layout(const sk_mesh *m, layout *l, double res, double pad, sk_error *err)
{
    const uint32_t *cu = l->corner_uv;
    size_t ne = 0;
    uint32_t *edges = sk__malloc_array(2 * m->num_halfedges + 2, sizeof(uint32_t));
    if (!l->packed)
        l->packed = sk__malloc_array(2 * (l->n ? l->n : 1), sizeof(double));
    if (!edges || !l->packed) {
        sk__free(edges);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    for (size_t h = 0; h < m->num_halfedges; ++h) {
        if (m->h_face[h] == SK_INVALID)
            continue;
        if (m->h_face[h ^ 1u] == SK_INVALID || sk__uv_seam(m, cu, (uint32_t)h)) {
            edges[2 * ne] = cu[h];
            edges[2 * ne++ + 1] = cu[m->h_next[h]];
        }
    }
    if (l->packed != l->uv)
        memcpy(l->packed, l->uv, 2 * l->n * sizeof(double));
    sk_status st = sk__pack_charts(l->nc, l->off, l->chart, l->packed, ne, edges, res, pad,
                                   &l->scale, err);
    sk__free(edges);
    return st;
}

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* l's layout with the faces' charts fc (nc of them): one uv point per (chart, uv point of src)
 * its corners use, in that order (the charts src keeps whole keep their points in order). */
static sk_status relabel(const sk_mesh *m, const layout *src, const uint32_t *fc, size_t nc,
                         layout *l, sk_error *err)
{
    size_t nh = m->num_halfedges, nk = 0;
    memset(l, 0, sizeof *l);
    uint64_t *key = sk__malloc_array(nh ? nh : 1, sizeof(uint64_t));
    l->corner_uv = sk__malloc_array(nh ? nh : 1, sizeof(uint32_t));
    l->face_chart = sk__malloc_array(m->num_faces ? m->num_faces : 1, sizeof(uint32_t));
    l->off = sk__calloc_array(nc + 1, sizeof(uint32_t));
    if (!key || !l->corner_uv || !l->face_chart || !l->off)
        goto nomem;
    memcpy(l->face_chart, fc, m->num_faces * sizeof(uint32_t));
    for (size_t h = 0; h < nh; ++h)
        if (m->h_face[h] != SK_INVALID)
            key[nk++] = (uint64_t)fc[m->h_face[h]] << 32 | src->corner_uv[h];
    qsort(key, nk, sizeof *key, cmp_u64);
    size_t n = 0;
    for (size_t i = 0; i < nk; ++i)
        if (n == 0 || key[i] != key[n - 1])
            key[n++] = key[i];
    l->nc = nc;
    l->n = n;
    l->chart = sk__malloc_array(n ? n : 1, sizeof(uint32_t));
    l->uv = sk__malloc_array(2 * (n ? n : 1), sizeof(double));
    if (!l->chart || !l->uv)
        goto nomem;
    for (size_t i = 0; i < n; ++i) {
        uint32_t c = (uint32_t)(key[i] >> 32), u = (uint32_t)key[i];
        l->chart[i] = c;
        l->off[c + 1]++;
        memcpy(l->uv + 2 * i, src->uv + 2 * (size_t)u, 2 * sizeof(double));
    }
    for (size_t c = 0; c < nc; ++c)
        l->off[c + 1] += l->off[c];
    for (size_t h = 0; h < nh; ++h) {
        l->corner_uv[h] = SK_INVALID;
        if (m->h_face[h] == SK_INVALID)
            continue;
        uint64_t k = (uint64_t)fc[m->h_face[h]] << 32 | src->corner_uv[h];
        const uint64_t *at = bsearch(&k, key, n, sizeof *key, cmp_u64);
        l->corner_uv[h] = (uint32_t)(at - key);
    }
    sk__free(key);
    return SK_OK;
nomem:
    sk__free(key);
    layout_free(l);
    return sk__fail(err, SK_ERR_NOMEM, "out of memory");
}

/* Scratch of the cut search. */
typedef struct cutter {
    const sk_mesh *m;
    const layout *l;
    uint32_t *faces, *start; /* faces grouped by chart: [start[c], start[c+1]) */
    double *key;             /* 2 per face of a chart: projection, face */
    uint8_t *side;           /* per face: 0 or 1 in the cut tried, 2 outside the chart */
    uint32_t *queue;         /* per face */
    uint32_t *ustamp;        /* per uv point: the last piece that counted it */
    uint32_t stamp;
    double *pts, *hull;      /* 6 per face of a chart (and 6 more) */
    double *box;             /* per chart: its smallest box's area */
    double *a3, *cr, *ls;    /* per face: 3D area, sigma1/sigma2, log(uv area / 3D area) */
    double max_conf, max_stretch; /* the pieces' bounds (<= 0: none) */
    double seam;             /* the seam length (3D) the cuts may add in all within the budget */
    double seam_max;         /* ... and beyond it, when they pay SPLIT_PAY */
    /* the best cut so far */
    size_t ncut;             /* the best cuts so far (most box area saved first) */
    double gain[SPLIT_TRIES], added[SPLIT_TRIES]; /* box area saved, seam length added */
    uint32_t chart[SPLIT_TRIES];
    uint8_t *cut_side;       /* SPLIT_TRIES x faces: per face of the chart, in faces[] order */
} cutter;

static void uv_centroid(const layout *l, const sk_mesh *m, uint32_t f, double *c)
{
    uint32_t h = m->f_halfedge[f];
    c[0] = c[1] = 0;
    for (int k = 0; k < 3; ++k, h = m->h_next[h]) {
        c[0] += l->uv[2 * (size_t)l->corner_uv[h]] / 3;
        c[1] += l->uv[2 * (size_t)l->corner_uv[h] + 1] / 3;
    }
}

/* The neighbour of face f across h inside piece s of its chart (not across a seam), or
 * SK_INVALID. */
static uint32_t piece_neighbour(const cutter *k, uint32_t h, uint8_t s)
{
    const sk_mesh *m = k->m;
    uint32_t g = m->h_face[h ^ 1u];
    if (g == SK_INVALID || k->side[g] != s || sk__uv_seam(m, k->l->corner_uv, h))
        return SK_INVALID;
    return g;
}

/* Piece s (the faces of side s) of the chart: edge-connected with Euler characteristic 1 (a
 * disk: the layout is planar)? *box receives its smallest box's area. */
static bool piece_ok(cutter *k, const uint32_t *faces, size_t nf, uint8_t s, double *box)
{
    const sk_mesh *m = k->m;
    size_t first = nf, nfaces = 0;
    for (size_t i = 0; i < nf && first == nf; ++i)
        if (k->side[faces[i]] == s)
            first = i;
    if (first == nf)
        return false;
    for (size_t i = 0; i < nf; ++i)
        nfaces += k->side[faces[i]] == s;
    /* breadth-first over the piece; side s + 4 marks the faces seen */
    size_t head = 0, tail = 0, np = 0;
    long long v = 0, e2 = 0;
    k->stamp++;
    k->queue[tail++] = faces[first];
    k->side[faces[first]] = (uint8_t)(s + 4);
    while (head < tail) {
        uint32_t f = k->queue[head++], h = m->f_halfedge[f];
        for (int j = 0; j < 3; ++j, h = m->h_next[h]) {
            uint32_t u = k->l->corner_uv[h];
            memcpy(k->pts + 2 * np++, k->l->uv + 2 * (size_t)u, 2 * sizeof(double));
            if (k->ustamp[u] != k->stamp) {
                k->ustamp[u] = k->stamp;
                v++;
            }
            uint32_t g = m->h_face[h ^ 1u];
            bool inside = g != SK_INVALID && (k->side[g] == s || k->side[g] == s + 4) &&
                          !sk__uv_seam(m, k->l->corner_uv, h);
            e2 += inside ? 1 : 2; /* an inner edge is seen from both sides */
            if (inside && k->side[g] == s) {
                k->side[g] = (uint8_t)(s + 4);
                k->queue[tail++] = g;
            }
        }
    }
    for (size_t i = 0; i < tail; ++i)
        k->side[k->queue[i]] = s;
    if (tail != nfaces || 2 * v - e2 + 2 * (long long)nfaces != 2)
        return false;
    *box = sk__min_box_area(k->pts, np, k->hull);
    return true;
}

/* Piece s of the chart (faces[0..nf)) within the atlas's bounds, measured as the atlas measures
 * a chart (chart_param.c): 3D-area weighted mean sigma1/sigma2 (pieces of 2 faces or more) and
 * 3D-area weighted |log area scale - the piece's mean| (pieces of 8 faces or more)? */
static bool piece_within(const cutter *k, const uint32_t *faces, size_t nf, uint8_t s)
{
    double a = 0, conf = 0, mean = 0, dev = 0;
    size_t n = 0;
    for (size_t i = 0; i < nf; ++i) {
        uint32_t f = faces[i];
        if (k->side[f] != s)
            continue;
        n++;
        a += k->a3[f];
        conf += k->a3[f] * k->cr[f];
        mean += k->a3[f] * k->ls[f];
    }
    if (n >= 2 && k->max_conf > 0 && conf / a > k->max_conf)
        return false;
    if (n < 8 || k->max_stretch <= 0)
        return true;
    mean /= a;
    for (size_t i = 0; i < nf; ++i)
        if (k->side[faces[i]] == s)
            dev += k->a3[faces[i]] * fabs(k->ls[faces[i]] - mean);
    return dev / a <= log(k->max_stretch);
}

static int cmp_key(const void *x, const void *y)
{
    const double *a = x, *b = y;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* Keeps the cut in k->side of chart c (faces[0..nf)) among the best when it saves gain. */
static void keep_cut(cutter *k, uint32_t c, const uint32_t *faces, size_t nf, double gain,
                     double added)
{
    size_t at = k->ncut < SPLIT_TRIES ? k->ncut++ : SPLIT_TRIES - 1;
    size_t stride = k->m->num_faces;
    for (; at > 0 && k->gain[at - 1] < gain; --at) {
        k->gain[at] = k->gain[at - 1];
        k->added[at] = k->added[at - 1];
        k->chart[at] = k->chart[at - 1];
        memcpy(k->cut_side + at * stride, k->cut_side + (at - 1) * stride, stride);
    }
    k->gain[at] = gain;
    k->added[at] = added;
    k->chart[at] = c;
    for (size_t i = 0; i < nf; ++i)
        k->cut_side[at * stride + i] = k->side[faces[i]];
}

/* The cuts of chart c: the ones saving the most box area within SPLIT_SEAM_MAX are kept. */
static void cut_chart(cutter *k, uint32_t c)
{
    const sk_mesh *m = k->m;
    const uint32_t *faces = k->faces + k->start[c];
    size_t nf = k->start[c + 1] - k->start[c];
    if (nf < 2)
        return;
    for (int d = 0; d < SPLIT_DIRS; ++d) {
        double a = d * M_PI / SPLIT_DIRS, dir[2] = {cos(a), sin(a)};
        for (size_t i = 0; i < nf; ++i) {
            double q[2];
            uv_centroid(k->l, m, faces[i], q);
            k->key[2 * i] = q[0] * dir[0] + q[1] * dir[1];
            k->key[2 * i + 1] = (double)faces[i];
        }
        qsort(k->key, nf, 2 * sizeof(double), cmp_key);
        for (int q = 1; q < SPLIT_CUTS; ++q) {
            size_t cut = nf * (size_t)q / SPLIT_CUTS;
            if (cut == 0 || cut == nf)
                continue;
            for (size_t i = 0; i < nf; ++i)
                k->side[(uint32_t)k->key[2 * i + 1]] = i < cut;
            double added = 0, b0, b1;
            for (size_t i = 0; i < nf; ++i) {
                uint32_t f = faces[i], h = m->f_halfedge[f];
                for (int j = 0; j < 3; ++j, h = m->h_next[h])
                    if (k->side[f] == 1 && piece_neighbour(k, h, 0) != SK_INVALID)
                        added += sk_mesh_edge_length(m, h >> 1);
            }
            double floor = k->ncut < SPLIT_TRIES ? 0 : k->gain[SPLIT_TRIES - 1];
            if (added > k->seam_max || !piece_ok(k, faces, nf, 0, &b0) ||
                !piece_ok(k, faces, nf, 1, &b1) || !(k->box[c] - b0 - b1 > floor) ||
                !piece_within(k, faces, nf, 0) || !piece_within(k, faces, nf, 1))
                continue;
            keep_cut(k, c, faces, nf, k->box[c] - b0 - b1, added);
        }
        for (size_t i = 0; i < nf; ++i)
            k->side[faces[i]] = 2;
    }
}

/* The best cuts of the charts of l (k->ncut of them: 0 when none saves box area within the
 * budget). */
static void find_cut(cutter *k)
{
    const sk_mesh *m = k->m;
    const layout *l = k->l;
    memset(k->start, 0, (l->nc + 1) * sizeof(uint32_t));
    for (size_t f = 0; f < m->num_faces; ++f)
        k->start[l->face_chart[f] + 1]++;
    for (size_t c = 0; c < l->nc; ++c)
        k->start[c + 1] += k->start[c];
    for (size_t f = 0; f < m->num_faces; ++f) {
        k->side[f] = 2;
        k->queue[f] = k->start[l->face_chart[f]]++; /* the slot of f */
    }
    for (size_t f = 0; f < m->num_faces; ++f)
        k->faces[k->queue[f]] = (uint32_t)f;
    for (size_t c = l->nc; c > 0; --c)
        k->start[c] = k->start[c - 1];
    k->start[0] = 0;
    for (size_t c = 0; c < l->nc; ++c) {
        size_t np = 0;
        for (uint32_t u = l->off[c]; u < l->off[c + 1]; ++u, ++np)
            memcpy(k->pts + 2 * np, l->uv + 2 * (size_t)u, 2 * sizeof(double));
        k->box[c] = sk__min_box_area(k->pts, np, k->hull);
    }
    k->ncut = 0;
    for (uint32_t c = 0; c < l->nc; ++c)
        cut_chart(k, c);
}

static void cutter_free(cutter *k)
{
    sk__free(k->faces);
    sk__free(k->start);
    sk__free(k->key);
    sk__free(k->side);
    sk__free(k->queue);
    sk__free(k->ustamp);
    sk__free(k->pts);
    sk__free(k->hull);
    sk__free(k->box);
    sk__free(k->a3);
    sk__free(k->cr);
    sk__free(k->ls);
    sk__free(k->cut_side);
}

static sk_status cutter_init(cutter *k, const sk_mesh *m, size_t n_uv, sk_error *err)
{
    size_t nf = m->num_faces ? m->num_faces : 1, nc = SPLIT_MAX_CHARTS + SPLIT_ROUNDS + 1;
    memset(k, 0, sizeof *k);
    k->m = m;
    k->faces = sk__malloc_array(nf, sizeof(uint32_t));
    k->start = sk__malloc_array(nc + 1, sizeof(uint32_t));
    k->key = sk__malloc_array(2 * nf, sizeof(double));
    k->side = sk__malloc_array(nf, 1);
    k->queue = sk__malloc_array(nf, sizeof(uint32_t));
    /* relabelled layouts have at most 3 points per face */
    k->ustamp = sk__calloc_array(3 * nf + n_uv, sizeof(uint32_t));
    k->pts = sk__malloc_array(6 * nf + 6 + 2 * n_uv, sizeof(double));
    k->hull = sk__malloc_array(12 * nf + 12 + 4 * n_uv, sizeof(double));
    k->box = sk__malloc_array(nc, sizeof(double));
    k->cut_side = sk__malloc_array(SPLIT_TRIES * nf, 1);
    k->a3 = sk__malloc_array(nf, sizeof(double));
    k->cr = sk__malloc_array(nf, sizeof(double));
    k->ls = sk__malloc_array(nf, sizeof(double));
    if (!k->faces || !k->start || !k->key || !k->side || !k->queue || !k->ustamp || !k->pts ||
        !k->hull || !k->box || !k->cut_side || !k->a3 || !k->cr || !k->ls) {
        cutter_free(k);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    return SK_OK;
}

/* The faces' 3D area, sigma1/sigma2 and log area scale in layout l. A piece's layout is its
 * parent's up to a uniform scale, so the ratio stays and the log scale moves by a constant over
 * the piece: measured once on the uncut layout, they measure every piece. */
static void measure_faces(cutter *k, const layout *l)
{
    const sk_mesh *m = k->m;
    for (size_t f = 0; f < m->num_faces; ++f) {
        uint32_t h = m->f_halfedge[f], v[3];
        const double *q[3];
        for (int j = 0; j < 3; ++j, h = m->h_next[h]) {
            v[j] = sk_from(m, h);
            q[j] = l->uv + 2 * (size_t)l->corner_uv[h];
        }
        double auv, mips;
        sk__tri_distortion(m->positions + 3 * (size_t)v[0], m->positions + 3 * (size_t)v[1],
                           m->positions + 3 * (size_t)v[2], q[0], q[1], q[2], &k->a3[f], &auv,
                           &mips, &k->cr[f]);
        k->ls[f] = log(fabs(auv) / k->a3[f]);
    }
}

/* Chart c of l scaled (uniformly) so that its uv area equals its 3D area. */
static void fit_area(const cutter *k, layout *l, uint32_t c)
{
    const sk_mesh *m = k->m;
    double a3 = 0, auv = 0;
    for (size_t f = 0; f < m->num_faces; ++f) {
        if (l->face_chart[f] != c)
            continue;
        uint32_t h = m->f_halfedge[f];
        const double *q[3];
        for (int j = 0; j < 3; ++j, h = m->h_next[h])
            q[j] = l->uv + 2 * (size_t)l->corner_uv[h];
        double d1[2] = {q[1][0] - q[0][0], q[1][1] - q[0][1]};
        double d2[2] = {q[2][0] - q[0][0], q[2][1] - q[0][1]};
        a3 += k->a3[f];
        auv += 0.5 * fabs(sk__cross2(d1, d2));
    }
    double s = auv > 0 ? sqrt(a3 / auv) : 1.0;
    for (size_t i = 2 * (size_t)l->off[c]; i < 2 * (size_t)l->off[c + 1]; ++i)
        l->uv[i] *= s;
}

/* The layout of cur with cut i of k: side 1 becomes a new chart, each piece scaled to its 3D
 * area; packed on the coarse grid. */
static sk_status cut_layout(const sk_mesh *m, const cutter *k, size_t i, const layout *cur,
                            uint32_t *fc, double res, double pad, layout *t, sk_error *err)
{
    memcpy(fc, cur->face_chart, m->num_faces * sizeof(uint32_t));
    const uint32_t *faces = k->faces + k->start[k->chart[i]];
    size_t nf = k->start[k->chart[i] + 1] - k->start[k->chart[i]];
    for (size_t j = 0; j < nf; ++j)
        if (k->cut_side[i * m->num_faces + j])
            fc[faces[j]] = (uint32_t)cur->nc;
    sk_status st = relabel(m, cur, fc, cur->nc + 1, t, err);
    if (st)
        return st;
    fit_area(k, t, k->chart[i]);
    fit_area(k, t, (uint32_t)cur->nc);
    return pack_layout(m, t, res, pad, err);
}

/* Cuts (see the top of the file) from cur, packed at full resolution: cur becomes the layout
 * kept, packed. */
static sk_status try_cuts(const sk_mesh *m, layout *cur, const double bound[2], double res,
                          double pad, size_t *cuts, sk_error *err)
{
    cutter k;
    layout t = {0}, best = {0}, orig = *cur;
    double cres = res > 2 * COARSE_RES ? COARSE_RES : res, cpad = pad * cres / res;
    uint32_t *fc = sk__malloc_array(m->num_faces ? m->num_faces : 1, sizeof(uint32_t));
    sk_status st = fc ? cutter_init(&k, m, cur->n, err)
                      : sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (st) {
        sk__free(fc);
        return st;
    }
    k.max_conf = bound[0];
    k.max_stretch = bound[1];
    measure_faces(&k, cur);
    double seams = sk__uv_seam_length(m, cur->corner_uv, NULL), area = 0, added = 0;
    bool over = false; /* a cut beyond the budget taken */
    k.seam = SPLIT_SEAM * seams; /* the budget */
    k.seam_max = SPLIT_SEAM_MAX * seams;
    for (size_t f = 0; f < m->num_faces; ++f)
        area += k.a3[f];
    /* cur: the layout cut so far, packed coarsely (orig keeps the full packing of the uncut) */
    memset(cur, 0, sizeof *cur);
    if ((st = relabel(m, &orig, orig.face_chart, orig.nc, cur, err)) ||
        (st = pack_layout(m, cur, cres, cpad, err)))
        goto done;
    for (int round = 0; round < SPLIT_ROUNDS && !st; ++round) {
        k.l = cur;
        find_cut(&k);
        size_t won = SPLIT_TRIES;
        for (size_t i = 0; i < k.ncut && !st; ++i) {
            if ((st = cut_layout(m, &k, i, cur, fc, cres, cpad, &t, err)))
                break;
            /* beyond the budget: only a cut that pays */
            bool pays = k.added[i] <= k.seam ||
                        area * (t.scale * t.scale - cur->scale * cur->scale) >=
                            SPLIT_PAY * k.added[i] / sqrt(area);
            if (pays && t.scale > (best.off ? best.scale : 0)) {
                layout_free(&best);
                best = t;
                won = i;
            } else {
                layout_free(&t);
            }
            memset(&t, 0, sizeof t);
        }
        if (st || won == SPLIT_TRIES ||
            !(best.scale * best.scale >= SPLIT_GAIN * cur->scale * cur->scale))
            break;
        over = over || k.added[won] > k.seam;
        k.seam -= k.added[won];
        k.seam_max -= k.added[won];
        added += k.added[won];
        layout_free(cur);
        *cur = best;
        memset(&best, 0, sizeof best);
        ++*cuts;
    }
    if (!st && *cuts > 0 && !(st = pack_layout(m, cur, res, pad, err)) &&
        (cur->scale * cur->scale < SPLIT_GAIN * orig.scale * orig.scale ||
         (over && area * (cur->scale * cur->scale - orig.scale * orig.scale) <
                      SPLIT_PAY * added / sqrt(area))))
        *cuts = 0; /* at full resolution the cuts did not pay */
done:
    if (st || *cuts == 0) {
        layout_free(cur);
        *cur = orig;
    } else {
        layout_free(&orig);
    }
    layout_free(&t);
    layout_free(&best);
    cutter_free(&k);
    sk__free(fc);
    return st;
}

sk_status sk__pack_atlas(const sk_mesh *m, sk__atlas_layout *a, bool may_cut, double res,
                         double pad, double *scale, size_t *cuts, sk_error *err)
{
    layout cur = {a->nc, a->n, a->off, a->chart, a->corner_uv, a->face_chart, a->uv, NULL, 0};
    size_t nf = m->num_faces, nh = m->num_halfedges;
    *cuts = 0;
    bool cut = may_cut && a->nc >= 2 && a->nc <= SPLIT_MAX_CHARTS && nf <= SPLIT_MAX_FACES;
    if (!cut) { /* in place */
        cur.packed = a->uv;
        sk_status st = pack_layout(m, &cur, res, pad, err);
        *scale = cur.scale;
        return st;
    }
    /* a copy to cut: the caller's arrays are replaced by the layout kept */
    layout given = cur;
    sk_status st = relabel(m, &given, a->face_chart, a->nc, &cur, err);
    if (!st)
        st = pack_layout(m, &cur, res, pad, err);
    if (!st)
        st = try_cuts(m, &cur, (const double[2]){a->max_conf, a->max_stretch}, res, pad, cuts,
                      err);
    if (st) {
        layout_free(&cur);
        return st;
    }
    memcpy(a->corner_uv, cur.corner_uv, nh * sizeof(uint32_t));
    memcpy(a->face_chart, cur.face_chart, nf * sizeof(uint32_t));
    sk__free(a->off);
    sk__free(a->chart);
    sk__free(a->uv);
    a->nc = cur.nc;
    a->n = cur.n;
    a->off = cur.off;
    a->chart = cur.chart;
    a->uv = cur.packed;
    *scale = cur.scale;
    sk__free(cur.uv);
    sk__free(cur.corner_uv);
    sk__free(cur.face_chart);
    return SK_OK;
}
