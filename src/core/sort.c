/* LSD radix sort of (64-bit key, 32-bit value) pairs: the edge tables of million-triangle meshes
 * are sorted with it. Passes whose byte is constant across all keys are skipped. */
#include "core/internal.h"

#include <stdlib.h>
#include <string.h>

sk_status sk__sort_u64_u32(uint64_t *keys, uint32_t *vals, size_t n)
{
    if (n < 2)
        return SK_OK;
    uint64_t *k2 = sk__malloc_array(n, sizeof *k2);
    uint32_t *v2 = sk__malloc_array(n, sizeof *v2);
    if (!k2 || !v2) {
        sk__free(k2);
        sk__free(v2);
        return SK_ERR_NOMEM;
    }
    uint64_t *ka = keys, *kb = k2;
    uint32_t *va = vals, *vb = v2;
    for (int shift = 0; shift < 64; shift += 8) {
        size_t count[256] = {0};
        for (size_t i = 0; i < n; ++i)
            count[(ka[i] >> shift) & 0xff]++;
        if (count[(ka[0] >> shift) & 0xff] == n)
            continue; /* all keys share this byte */
        size_t sum = 0;
        for (int b = 0; b < 256; ++b) {
            size_t c = count[b];
            count[b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; ++i) {
            size_t d = count[(ka[i] >> shift) & 0xff]++;
            kb[d] = ka[i];
            vb[d] = va[i];
        }
        uint64_t *tk = ka;
        ka = kb;
        kb = tk;
        uint32_t *tv = va;
        va = vb;
        vb = tv;
    }
    if (ka != keys) {
        memcpy(keys, ka, n * sizeof *keys);
        memcpy(vals, va, n * sizeof *vals);
    }
    sk__free(k2);
    sk__free(v2);
    return SK_OK;
}
