/* Tessellation of a patch network into a triangle soup with the exact patch normals. Each patch
 * gets its own grid of vertices (positions along shared edges agree to rounding: both patches use
 * the same cubic boundary curve), so the soup is not welded along patch boundaries. */
#include "smooth/smooth_internal.h"
#include "core/internal.h"

sk_status sk_smooth_tessellate(const sk_smooth *s, unsigned n, sk_soup **out, sk_error *err)
{
    if (!s || !out || n == 0 || n > 1024)
        return sk__fail(err, SK_ERR_ARG, "sk_smooth_tessellate: bad arguments (n = %u)", n);
    size_t nv = 0, nf = 0;
    for (size_t p = 0; p < s->num_patches; ++p) {
        if (s->patches[p].kind == SK_SMOOTH_QUAD) {
            nv += (size_t)(n + 1) * (n + 1);
            nf += 2 * (size_t)n * n;
        } else {
            nv += (size_t)(n + 1) * (n + 2) / 2;
            nf += (size_t)n * n;
        }
    }
    if (nv > UINT32_MAX - 1)
        return sk__fail(err, SK_ERR_ARG, "tessellation too large (%zu vertices)", nv);
    sk_soup *soup = NULL;
    sk_status st = sk_soup_create(nv, nf, 3 * nf, true, false, &soup, err);
    if (st != SK_OK)
        return st;
    uint32_t base = 0;
    for (size_t p = 0; p < s->num_patches && st == SK_OK; ++p) {
        const sk_smooth_patch *pa = s->patches + p;
        if (pa->kind == SK_SMOOTH_QUAD) {
            for (unsigned j = 0; j <= n; ++j)
                for (unsigned i = 0; i <= n; ++i) {
                    double x[3], nn[3];
                    sk_smooth_eval(s, p, (double)i / n, (double)j / n, x, NULL, NULL, nn);
                    if ((st = sk_soup_push_vertex(soup, x, nn, NULL)) != SK_OK)
                        goto done;
                }
            for (unsigned j = 0; j < n; ++j)
                for (unsigned i = 0; i < n; ++i) {
                    uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
                    uint32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
                    if ((st = sk_soup_push_face(soup, t1, 3)) != SK_OK ||
                        (st = sk_soup_push_face(soup, t2, 3)) != SK_OK)
                        goto done;
                }
            base += (n + 1) * (n + 1);
        } else {
            /* rows by v (k), inside a row by u (j): index of (j, k) as sk__tri_index(n, j, k) */
            for (unsigned k = 0; k <= n; ++k)
                for (unsigned j = 0; j <= n - k; ++j) {
                    double x[3], nn[3];
                    sk_smooth_eval(s, p, (double)j / n, (double)k / n, x, NULL, NULL, nn);
                    if ((st = sk_soup_push_vertex(soup, x, nn, NULL)) != SK_OK)
                        goto done;
                }
            for (unsigned k = 0; k < n; ++k)
                for (unsigned j = 0; j < n - k; ++j) {
                    uint32_t a = base + (uint32_t)sk__tri_index((int)n, (int)j, (int)k);
                    uint32_t b = base + (uint32_t)sk__tri_index((int)n, (int)j + 1, (int)k);
                    uint32_t c = base + (uint32_t)sk__tri_index((int)n, (int)j, (int)k + 1);
                    uint32_t t1[3] = {a, b, c};
                    if ((st = sk_soup_push_face(soup, t1, 3)) != SK_OK)
                        goto done;
                    if (j + 1 < n - k) {
                        uint32_t d = base + (uint32_t)sk__tri_index((int)n, (int)j + 1, (int)k + 1);
                        uint32_t t2[3] = {b, d, c};
                        if ((st = sk_soup_push_face(soup, t2, 3)) != SK_OK)
                            goto done;
                    }
                }
            base += (n + 1) * (n + 2) / 2;
        }
    }
done:
    if (st != SK_OK) {
        sk_soup_destroy(&soup);
        return sk__fail(err, st, "out of memory tessellating");
    }
    *out = soup;
    sk__ok(err);
    return SK_OK;
}
