/* Crease regions: the first charts of a CAD-like mesh follow its sharp edges. Faces are joined
 * across every interior edge whose dihedral angle (between the two face normals) is below the
 * crease angle; a region holding less than SK__CREASE_MIN_AREA of its component's area (the
 * scattered sharp edges of a scan: single spikes, a coarse ear) joins, round by round, the
 * neighbour it shares the longest sharp boundary with, so that organic meshes keep one region per
 * component. */
#include "atlas/atlas_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rounds of merging small regions into neighbours at most (each round merges every small region
 * at once; chains of small regions need one round per link). */
#define MERGE_ROUNDS 16

typedef struct link {
    uint32_t small, other;
    double length;
} link;

static int cmp_link(const void *x, const void *y)
{
    const link *a = x, *b = y;
    if (a->small != b->small)
        return a->small < b->small ? -1 : 1;
    return (a->other > b->other) - (a->other < b->other);
}

static uint32_t root(uint32_t *par, uint32_t f)
{
    uint32_t r = f;
    while (par[r] != r)
        r = par[r];
    while (par[f] != r) {
        uint32_t n = par[f];
        par[f] = r;
        f = n;
    }
    return r;
}

/* joins the sets of a and b; area[] is kept at the roots */
static void join(uint32_t *par, double *area, uint32_t a, uint32_t b)
{
    a = root(par, a);
    b = root(par, b);
    if (a == b)
        return;
    if (b < a) { /* the smaller face index stays the root: the result does not depend on order */
        uint32_t t = a;
        a = b;
        b = t;
    }
    par[b] = a;
    area[a] += area[b];
}

static bool is_sharp(const sk_mesh *m, uint32_t e, double cos_max, uint32_t *f0, uint32_t *f1)
{
    *f0 = m->h_face[2 * (size_t)e];
    *f1 = m->h_face[2 * (size_t)e + 1];
    if (*f0 == SK_INVALID || *f1 == SK_INVALID)
        return false;
    double n0[3], n1[3];
    sk_mesh_face_normal(m, *f0, n0);
    sk_mesh_face_normal(m, *f1, n1);
    return sk__dot3(n0, n1) < cos_max;
}

/* One round: every small region joins the neighbour with the longest shared sharp boundary.
 * Returns the number of small regions that found one (0: done). */
static size_t merge_round(const sk_mesh *m, double cos_max, double min_frac, const uint32_t *comp,
                          const double *carea, uint32_t *par, double *area, link *links)
{
    size_t nl = 0;
    for (size_t e = 0; e < sk_num_edges(m); ++e) {
        uint32_t f0, f1;
        if (!is_sharp(m, (uint32_t)e, cos_max, &f0, &f1))
            continue;
        uint32_t a = root(par, f0), b = root(par, f1);
        if (a == b)
            continue;
        double len = sk_mesh_edge_length(m, (uint32_t)e), lim = min_frac * carea[comp[f0]];
        if (area[a] < lim)
            links[nl++] = (link){a, b, len};
        if (area[b] < lim)
            links[nl++] = (link){b, a, len};
    }
    if (nl == 0)
        return 0;
    qsort(links, nl, sizeof *links, cmp_link);
    /* per small region: the neighbour with the largest summed length (the first on ties) */
    size_t best_n = 0;
    for (size_t i = 0; i < nl;) {
        uint32_t s = links[i].small, best = SK_INVALID;
        double best_len = -1;
        while (i < nl && links[i].small == s) {
            uint32_t o = links[i].other;
            double len = 0;
            for (; i < nl && links[i].small == s && links[i].other == o; ++i)
                len += links[i].length;
            if (len > best_len) {
                best_len = len;
                best = o;
            }
        }
        links[best_n++] = (link){s, best, best_len};
    }
    for (size_t i = 0; i < best_n; ++i)
        join(par, area, links[i].small, links[i].other);
    return best_n;
}

sk_status sk__crease_regions(const sk_mesh *m, double angle_deg, double min_frac,
                             const uint32_t *comp, size_t ncomp, uint32_t *region,
                             size_t *nregions, sk_error *err)
{
    size_t nf = m->num_faces, ne = sk_num_edges(m);
    sk_status st = SK_OK;
    double cos_max = cos(angle_deg * (M_PI / 180.0));
    uint32_t *par = sk__malloc_array(nf, sizeof(uint32_t));
    double *area = sk__malloc_array(nf, sizeof(double));
    double *carea = sk__calloc_array(ncomp ? ncomp : 1, sizeof(double));
    size_t nsharp = 0;
    for (size_t e = 0; e < ne; ++e) {
        uint32_t f0, f1;
        nsharp += is_sharp(m, (uint32_t)e, cos_max, &f0, &f1);
    }
    link *links = sk__malloc_array(2 * nsharp + 1, sizeof(link));
    if (!par || !area || !carea || !links) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto done;
    }
    for (size_t f = 0; f < nf; ++f) {
        par[f] = (uint32_t)f;
        area[f] = sk_mesh_face_area(m, (uint32_t)f);
        carea[comp[f]] += area[f];
    }
    for (size_t e = 0; e < ne; ++e) {
        uint32_t f0, f1;
        if (!is_sharp(m, (uint32_t)e, cos_max, &f0, &f1) && f0 != SK_INVALID && f1 != SK_INVALID)
            join(par, area, f0, f1);
    }
    for (int round = 0; round < MERGE_ROUNDS && nsharp > 0; ++round)
        if (merge_round(m, cos_max, min_frac, comp, carea, par, area, links) == 0)
            break;
    /* ids in the order of each region's first face (the component order when no crease cuts) */
    size_t n = 0;
    for (size_t f = 0; f < nf; ++f)
        region[f] = SK_INVALID;
    for (size_t f = 0; f < nf; ++f) {
        uint32_t r = root(par, (uint32_t)f);
        if (region[r] == SK_INVALID)
            region[r] = (uint32_t)n++;
        region[f] = region[r];
    }
    *nregions = n;
done:
    sk__free(par);
    sk__free(area);
    sk__free(carea);
    sk__free(links);
    return st;
}
