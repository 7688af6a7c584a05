/* The patch set: headers over one pooled array of control points. */
#include "bezier/bezier_internal.h"
#include "core/internal.h"

#include <stdlib.h>
#include <string.h>

/* Grows *p (elements of size `size`, capacity *cap) to hold at least `need`. */
static bool grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return true;
    size_t c = *cap ? *cap : 16;
    while (c < need)
        c = c > SIZE_MAX / 2 ? need : 2 * c;
    if (c > SIZE_MAX / size)
        return false;
    void *q = sk__realloc_array(*p, c * size, 1);
    if (!q)
        return false;
    *p = q;
    *cap = c;
    return true;
}

sk_status sk_patch_set_reserve(sk_patch_set *set, size_t patches, size_t points, sk_error *err)
{
    if (!set)
        return sk__fail(err, SK_ERR_ARG, "sk_patch_set_reserve: NULL set");
    if (patches > SIZE_MAX - set->count || points > SIZE_MAX - set->num_points)
        return sk__fail(err, SK_ERR_NOMEM, "patch set too large");
    void *pp = set->patches, *pt = set->points;
    bool ok = grow(&pp, &set->patch_capacity, set->count + patches, sizeof(sk_patch));
    set->patches = pp;
    ok = ok && grow(&pt, &set->point_capacity, set->num_points + points, 3 * sizeof(double));
    set->points = pt;
    if (!ok)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory growing a patch set");
    return SK_OK;
}

sk_status sk_patch_set_add(sk_patch_set *set, sk_patch_kind kind, unsigned degree,
                           unsigned degree_v, const double *cp, const uint32_t *corner_ids,
                           size_t *index, sk_error *err)
{
    if (!set || (kind != SK_PATCH_TRIANGLE && kind != SK_PATCH_TENSOR) ||
        degree > SK_PATCH_MAX_DEGREE || (kind == SK_PATCH_TENSOR && degree_v > SK_PATCH_MAX_DEGREE))
        return sk__fail(err, SK_ERR_ARG, "sk_patch_set_add: bad patch (kind %d, degree %u x %u)",
                        (int)kind, degree, degree_v);
    if (kind == SK_PATCH_TRIANGLE)
        degree_v = 0;
    unsigned np = sk_bezier_num_points(kind, degree, degree_v);
    double local[3 * SK__PATCH_MAX_POINTS];
    uint32_t ids[4];
    unsigned nc = kind == SK_PATCH_TRIANGLE ? 3 : 4;
    /* cp and corner_ids may point into the set, whose arrays the reserve may move */
    if (cp)
        memcpy(local, cp, 3 * np * sizeof(double));
    for (unsigned c = 0; c < 4; ++c)
        ids[c] = corner_ids && c < nc ? corner_ids[c] : SK_INVALID;
    sk_status st = sk_patch_set_reserve(set, 1, np, err);
    if (st)
        return st;
    sk_patch *p = &set->patches[set->count];
    memset(p, 0, sizeof *p);
    p->kind = (uint8_t)kind;
    p->degree = (uint8_t)degree;
    p->degree_v = (uint8_t)degree_v;
    p->tag = SK_INVALID;
    p->first = set->num_points;
    memcpy(p->corner_ids, ids, sizeof ids);
    double *dst = set->points + 3 * p->first;
    if (cp)
        memcpy(dst, local, 3 * np * sizeof(double));
    else
        memset(dst, 0, 3 * np * sizeof(double));
    set->num_points += np;
    if (index)
        *index = set->count;
    set->count++;
    return SK_OK;
}

sk_status sk__patch_set_add_tagged(sk_patch_set *set, sk_patch_kind kind, unsigned degree,
                                   unsigned degree_v, const double *cp, const uint32_t *corner_ids,
                                   uint32_t tag, sk_error *err)
{
    size_t k;
    sk_status st = sk_patch_set_add(set, kind, degree, degree_v, cp, corner_ids, &k, err);
    if (st == SK_OK)
        set->patches[k].tag = tag;
    return st;
}

sk_status sk__patch_set_extend_unset(sk_patch_set *set, size_t patches, size_t points,
                                     sk_error *err)
{
    sk_status st = sk_patch_set_reserve(set, patches, points, err);
    if (st)
        return st;
    set->count += patches;
    set->num_points += points;
    return SK_OK;
}

void sk_patch_set_clear(sk_patch_set *set)
{
    if (set)
        set->count = set->num_points = 0;
}

void sk_patch_set_free(sk_patch_set *set)
{
    if (!set)
        return;
    sk__free(set->patches);
    sk__free(set->points);
    memset(set, 0, sizeof *set);
}
