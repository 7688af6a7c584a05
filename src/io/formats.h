/* Entry points of the four mesh formats, for the dispatcher io.c (not installed). */
#ifndef SK_IO_FORMATS_H
#define SK_IO_FORMATS_H

#include "surfkit/io.h"
#include "core/internal.h"

#include <stdbool.h>
#include <stddef.h>

sk_status sk__read_off(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err);
sk_status sk__read_obj(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err);
sk_status sk__read_ply(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err);
sk_status sk__read_stl(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err);

/* Writers append to o; the caller checks o->failed. normals / uvs say what to write. */
void sk__write_off(sk__out *o, const sk_soup *s, bool normals, bool uvs);
void sk__write_obj(sk__out *o, const sk_soup *s, bool normals, bool uvs);
void sk__write_ply(sk__out *o, const sk_soup *s, bool normals, bool uvs, bool ascii);
void sk__write_stl(sk__out *o, const sk_soup *s, bool ascii);

/* True when size matches a binary STL's triangle count (84 + 50 n bytes). */
bool sk__stl_is_binary_size(const void *data, size_t size);

#endif
