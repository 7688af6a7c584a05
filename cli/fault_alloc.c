/* Allocation-failure injection for the CLI tests (tests/cli/alloc_fail.sh): with
 * SURFKIT_FAIL_ALLOC=K in the environment, the K-th allocation the library makes through its
 * allocator hook (sk_set_allocator; counting malloc and realloc from 1) fails, once; with
 * SURFKIT_FAIL_ALLOC=count nothing fails and the number of allocations is printed to stderr at
 * exit ("surfkit: allocations N"), which tells a test how many K to try.
 *
 * Why here and this way: the library has no test switch of its own (it reads no environment
 * and stays the same code in every build); the CLI installs an ordinary allocator through the
 * public hook, so what is tested is the real release binary end to end (reader, validation,
 * report, printing, exit code), not a special build. Unset (every normal run), the hook is never
 * installed and the C library's allocator is used directly. Allocations inside LAPACK, CHOLMOD,
 * cairo or the C library are not counted (they do not go through the hook). */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static unsigned long long fail_at, count;

static void *fa_malloc(void *user, size_t size)
{
    (void)user;
    return ++count == fail_at ? NULL : malloc(size);
}

static void *fa_realloc(void *user, void *p, size_t size)
{
    (void)user;
    return ++count == fail_at ? NULL : realloc(p, size);
}

static void fa_free(void *user, void *p)
{
    (void)user;
    free(p);
}

static void print_count(void)
{
    fprintf(stderr, "surfkit: allocations %llu\n", count);
}

void cli_fault_alloc_install(void)
{
    const char *v = getenv("SURFKIT_FAIL_ALLOC");
    if (!v || !*v)
        return;
    if (!strcmp(v, "count")) {
        fail_at = 0;
        atexit(print_count);
    } else {
        char *end;
        fail_at = strtoull(v, &end, 10);
        if (*end || fail_at == 0)
            return; /* not a positive number: ignored, as if unset */
    }
    static const sk_allocator a = {fa_malloc, fa_realloc, fa_free, NULL};
    sk_set_allocator(&a);
}
