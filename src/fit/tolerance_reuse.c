/* The refinement's memory of the last checked surface (tolerance_internal.h): its patches with
 * their corners as input vertices, so that the next round's check can pair each new patch with
 * the last round's over the same corners (same kind and degrees) and bound how far it moved: the
 * largest displacement of a control point, which bounds that of every point of the patch (the
 * difference of two Bezier patches is the Bezier patch of the differences, a convex combination
 * of them). A patch is looked up under its smallest corner (a list per input vertex). */
#include "fit/tolerance_internal.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

void sk__tol_prev_free(tol_prev *pv)
{
    sk__free(pv->kind);
    sk__free(pv->corners);
    sk__free(pv->first);
    sk__free(pv->points);
    sk__free(pv->goff);
    sk__free(pv->sd);
    sk__free(pv->sf);
    sk__free(pv->head);
    sk__free(pv->next);
    memset(pv, 0, sizeof *pv);
}

/* The corners of patch p as input vertices, or false when one is not (a vertex of an edge the
 * VC1 build split: such a patch is never matched). */
static bool fine_corners(const sk_smooth *s, const uint32_t *m2f, size_t p, uint32_t fc[4])
{
    const sk_patch *pa = &s->surface.patches[p];
    size_t built = s->config->num_vertices - s->stats.split_edges;
    unsigned nc = sk_patch_num_corners(pa);
    fc[3] = SK_INVALID;
    for (unsigned q = 0; q < nc; ++q) {
        if (pa->corner_ids[q] >= built)
            return false;
        fc[q] = m2f[pa->corner_ids[q]];
    }
    return true;
}

static uint32_t min_corner(const uint32_t fc[4])
{
    uint32_t m = fc[0];
    for (int q = 1; q < 4; ++q)
        if (fc[q] < m)
            m = fc[q];
    return m;
}

static uint32_t patch_kind(const sk_patch *pa)
{
    return (uint32_t)pa->kind | (uint32_t)pa->degree << 8 | (uint32_t)pa->degree_v << 16;
}

/* the largest distance between corresponding control points */
static double displacement(const double *a, const double *b, size_t n)
{
    double mx = 0;
    for (size_t k = 0; k < n; ++k) {
        double dx = a[3 * k] - b[3 * k], dy = a[3 * k + 1] - b[3 * k + 1],
               dz = a[3 * k + 2] - b[3 * k + 2];
        mx = fmax(mx, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return mx;
}

void sk__tol_match(const sk_smooth *s, const uint32_t *m2f, const tol_prev *pv, uint32_t *keep,
                   uint32_t *prev2new, double *moved, size_t *kept)
{
    const sk_patch_set *set = &s->surface;
    *kept = 0;
    for (size_t q = 0; q < pv->count; ++q)
        prev2new[q] = SK_INVALID;
    for (size_t p = 0; p < set->count; ++p) {
        keep[p] = SK_INVALID;
        uint32_t fc[4];
        if (!pv->valid || !fine_corners(s, m2f, p, fc))
            continue;
        const sk_patch *pa = &set->patches[p];
        size_t np = sk_patch_num_points(pa);
        for (uint32_t q = pv->head[min_corner(fc)]; q != SK_INVALID; q = pv->next[q]) {
            if (pv->kind[q] != patch_kind(pa) || memcmp(pv->corners + 4 * (size_t)q, fc, sizeof fc) ||
                prev2new[q] != SK_INVALID)
                continue;
            moved[q] = displacement(pv->points + 3 * pv->first[q], sk_patch_cp(set, p), np);
            keep[p] = q;
            prev2new[q] = (uint32_t)p;
            ++*kept;
            break;
        }
    }
}

sk_status sk__tol_remember(const sk_smooth *s, const uint32_t *m2f, size_t nv, tol_prev *pv,
                           sk_error *err)
{
    const sk_patch_set *set = &s->surface;
    size_t n = set->count;
    if (pv->head)
        for (size_t q = 0; q < pv->count; ++q) /* clear the old lists */
            if (pv->corners[4 * q] != SK_INVALID)
                pv->head[min_corner(pv->corners + 4 * q)] = SK_INVALID;
    pv->valid = false;
    if (n > pv->cap) {
        sk__free(pv->kind);
        sk__free(pv->corners);
        sk__free(pv->first);
        sk__free(pv->next);
        pv->kind = sk__malloc_array(n, sizeof *pv->kind);
        pv->corners = sk__malloc_array(4 * n, sizeof *pv->corners);
        pv->first = sk__malloc_array(n, sizeof *pv->first);
        pv->next = sk__malloc_array(n, sizeof *pv->next);
        pv->cap = n;
    }
    if (set->num_points > pv->cap_points) {
        sk__free(pv->points);
        pv->points = sk__malloc_array(3 * set->num_points, sizeof *pv->points);
        pv->cap_points = set->num_points;
    }
    if (!pv->head && (pv->head = sk__malloc_array(nv ? nv : 1, sizeof *pv->head)))
        for (size_t v = 0; v < nv; ++v)
            pv->head[v] = SK_INVALID;
    if (!pv->kind || !pv->corners || !pv->first || !pv->next || !pv->points || !pv->head) {
        sk__tol_prev_free(pv);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    pv->count = n;
    memcpy(pv->points, set->points, 3 * set->num_points * sizeof *pv->points);
    for (size_t p = 0; p < n; ++p) {
        uint32_t *fc = pv->corners + 4 * p;
        pv->kind[p] = patch_kind(&set->patches[p]);
        pv->first[p] = set->patches[p].first;
        pv->next[p] = SK_INVALID;
        if (!fine_corners(s, m2f, p, fc)) {
            fc[0] = fc[1] = fc[2] = fc[3] = SK_INVALID;
            continue;
        }
        uint32_t v = min_corner(fc);
        pv->next[p] = pv->head[v];
        pv->head[v] = (uint32_t)p;
    }
    pv->valid = true;
    return SK_OK;
}
