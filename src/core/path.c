/* File-name helpers shared by the library and the CLI. */
#include "core/internal.h"

#include <stdbool.h>
#include <string.h>

static char lower(char c) { return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c; }

bool sk_path_has_ext(const char *path, const char *ext)
{
    if (!path || !ext)
        return false;
    size_t n = strlen(path), m = strlen(ext);
    if (n < m)
        return false;
    for (size_t i = 0; i < m; ++i)
        if (lower(path[n - m + i]) != lower(ext[i]))
            return false;
    return true;
}
