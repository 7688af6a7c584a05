/* placeholder until the reader is written */
#include "io/io_internal.h"

sk_status sk__read_stl(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err)
{
    (void)data;
    (void)size;
    *out = NULL;
    return sk__fail(err, SK_ERR_PARSE, "%s:1: this format is not supported yet", name);
}
void sk__write_stl(sk__out *o, const sk_soup *s, bool ascii)
{
    (void)s; (void)ascii;
    o->failed = SK_ERR_IO;
}
bool sk__stl_is_binary_size(const void *data, size_t size)
{
    (void)data; (void)size;
    return false;
}
