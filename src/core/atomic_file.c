/* Output files are written to a temporary in the target directory and renamed into place when
 * complete, so an interrupted or failed run never leaves a truncated result (DESIGN.md). */
#define _POSIX_C_SOURCE 200809L
#include "core/internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

sk_status sk__atomic_open(sk__atomic_file *af, const char *path, sk_error *err)
{
    af->fp = NULL;
    af->final_path = NULL;
    af->tmp_path = NULL;
    if (!path || !*path)
        return sk__fail(err, SK_ERR_ARG, "empty output path");
    size_t n = strlen(path);
    af->final_path = malloc(n + 1);
    af->tmp_path = malloc(n + 16);
    if (!af->final_path || !af->tmp_path) {
        sk__atomic_abort(af);
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    }
    memcpy(af->final_path, path, n + 1);
    snprintf(af->tmp_path, n + 16, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(af->tmp_path);
    if (fd < 0) {
        int e = errno;
        free(af->tmp_path);
        af->tmp_path = NULL;
        sk__atomic_abort(af);
        return sk__fail(err, SK_ERR_IO, "%s: cannot create output file: %s", path, strerror(e));
    }
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        int e = errno;
        close(fd);
        sk__atomic_abort(af);
        return sk__fail(err, SK_ERR_IO, "%s: cannot open output file: %s", path, strerror(e));
    }
    /* a large buffer: writers emit many small records */
    setvbuf(af->fp, NULL, _IOFBF, 1 << 20);
    return SK_OK;
}

sk_status sk__atomic_commit(sk__atomic_file *af, sk_error *err)
{
    int bad = ferror(af->fp);
    int e = errno;
    if (fclose(af->fp) != 0) {
        bad = 1;
        e = errno;
    }
    af->fp = NULL;
    if (bad) {
        sk_status st = sk__fail(err, SK_ERR_IO, "%s: write failed: %s", af->final_path, strerror(e));
        sk__atomic_abort(af);
        return st;
    }
    if (rename(af->tmp_path, af->final_path) != 0) {
        e = errno;
        sk_status st = sk__fail(err, SK_ERR_IO, "%s: cannot rename into place: %s", af->final_path,
                                strerror(e));
        sk__atomic_abort(af);
        return st;
    }
    free(af->tmp_path);
    free(af->final_path);
    af->tmp_path = NULL;
    af->final_path = NULL;
    return SK_OK;
}

void sk__atomic_abort(sk__atomic_file *af)
{
    if (af->fp)
        fclose(af->fp);
    if (af->tmp_path)
        remove(af->tmp_path);
    free(af->tmp_path);
    free(af->final_path);
    af->fp = NULL;
    af->tmp_path = NULL;
    af->final_path = NULL;
}
