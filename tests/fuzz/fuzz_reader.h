/* The body of every reader fuzz target: the reader of SK_FUZZ_FORMAT on arbitrary bytes, then the
 * writer of the same format (binary or ascii by the input's parity) on whatever it accepted.
 * A target defines SK_FUZZ_FORMAT and SK_FUZZ_NAME and includes this file. */
#include "surfkit/io.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sk_read_opts ro = {SK_FUZZ_FORMAT};
    sk_soup *s = NULL;
    if (sk_soup_read_memory(data, size, SK_FUZZ_NAME, &ro, &s, NULL) == SK_OK) {
        sk_write_opts wo = {.format = SK_FUZZ_FORMAT, .ascii = (size & 1) != 0};
        void *out = NULL;
        size_t n = 0;
        if (sk_soup_write_memory(s, &wo, &out, &n, NULL) == SK_OK)
            free(out);
        sk_soup_destroy(&s);
    }
    return 0;
}
