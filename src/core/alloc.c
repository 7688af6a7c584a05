/* Overflow-checked array allocation. */
#include "core/internal.h"

#include <stdint.h>
#include <stdlib.h>

void *sk__malloc_array(size_t n, size_t size)
{
    if (size != 0 && n > SIZE_MAX / size)
        return NULL;
    return malloc(n != 0 && size != 0 ? n * size : 1);
}

void *sk__calloc_array(size_t n, size_t size)
{
    if (size != 0 && n > SIZE_MAX / size)
        return NULL;
    return calloc(n ? n : 1, size ? size : 1);
}

void *sk__realloc_array(void *p, size_t n, size_t size)
{
    if (size != 0 && n > SIZE_MAX / size)
        return NULL;
    return realloc(p, n != 0 && size != 0 ? n * size : 1);
}
