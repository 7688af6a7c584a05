/* The one allocator of the library: every allocation and free in src/ goes through these
 * wrappers, so an application (or the allocation-failure test) can install its own with
 * sk_set_allocator. Overflow-checked array sizes. */
#define _POSIX_C_SOURCE 200809L
#include "core/internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Process-wide, not thread-local: OpenMP workers allocate and the main thread frees what they
 * made, so every thread must see the same allocator. */
static sk_allocator current;

void sk_set_allocator(const sk_allocator *alloc)
{
    if (alloc && alloc->malloc && alloc->realloc && alloc->free)
        current = *alloc;
    else
        memset(&current, 0, sizeof current);
}

static void *raw_malloc(size_t bytes)
{
    return current.malloc ? current.malloc(current.user, bytes) : malloc(bytes);
}

void *sk__malloc_array(size_t n, size_t size)
{
    if (size != 0 && n > SIZE_MAX / size)
        return NULL;
    return raw_malloc(n != 0 && size != 0 ? n * size : 1);
}

void *sk__calloc_array(size_t n, size_t size)
{
    if (size != 0 && n > SIZE_MAX / size)
        return NULL;
    if (!current.malloc)
        return calloc(n ? n : 1, size ? size : 1);
    size_t bytes = n != 0 && size != 0 ? n * size : 1;
    void *p = raw_malloc(bytes);
    if (p)
        memset(p, 0, bytes);
    return p;
}

void *sk__realloc_array(void *p, size_t n, size_t size)
{
    if (size != 0 && n > SIZE_MAX / size)
        return NULL;
    size_t bytes = n != 0 && size != 0 ? n * size : 1;
    return current.realloc ? current.realloc(current.user, p, bytes) : realloc(p, bytes);
}

void sk__free(void *p)
{
    if (!p)
        return;
    if (current.free)
        current.free(current.user, p);
    else
        free(p);
}

char *sk__strndup(const char *s, size_t n)
{
    size_t len = strnlen(s, n);
    char *d = raw_malloc(len + 1);
    if (d) {
        memcpy(d, s, len);
        d[len] = '\0';
    }
    return d;
}

char *sk__strdup(const char *s)
{
    return sk__strndup(s, SIZE_MAX);
}
