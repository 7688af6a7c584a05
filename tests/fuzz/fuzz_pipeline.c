/* libFuzzer target: read (any format, sniffed from the content) -> validate -> build -> check.
 * The reader targets stop after reading; this one also drives the validator and the half-edge
 * builder over whatever a reader accepts, and holds them to their contract: the builder succeeds
 * exactly when the validator calls the soup manifold, and a built mesh passes sk_mesh_check.
 * (Issue 17: a target written this way found the walk_boundary uninitialised read.) */
#include "surfkit/io.h"
#include "surfkit/mesh.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sk_read_opts ro = {SK_FORMAT_AUTO};
    sk_soup *s = NULL;
    if (sk_soup_read_memory(data, size, "fuzz.mesh", &ro, &s, NULL) != SK_OK)
        return 0;
    sk_validation r;
    if (sk_soup_validate(s, &r, NULL) != SK_OK)
        abort(); /* only allocation failure may make validation fail */
    sk_mesh *m = NULL;
    sk_status st = sk_mesh_from_soup(s, &m, NULL);
    if ((st == SK_OK) != sk_validation_is_manifold(&r))
        abort(); /* validator and builder disagree */
    if (st == SK_OK) {
        if (sk_mesh_check(m, NULL) != SK_OK)
            abort();
        sk_mesh_destroy(&m);
    }
    sk_soup_destroy(&s);
    return 0;
}
