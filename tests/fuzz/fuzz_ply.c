/* libFuzzer target: the PLY reader on arbitrary bytes, then the PLY writer on what it accepted. */
#include "surfkit/io.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sk_read_opts ro = {SK_FORMAT_PLY};
    sk_soup *s = NULL;
    if (sk_soup_read_memory(data, size, "fuzz.ply", &ro, &s, NULL) == SK_OK) {
        sk_write_opts wo = {.format = SK_FORMAT_PLY, .ascii = (size & 1) != 0};
        void *out = NULL;
        size_t n = 0;
        if (sk_soup_write_memory(s, &wo, &out, &n, NULL) == SK_OK)
            free(out);
        sk_soup_destroy(&s);
    }
    return 0;
}
