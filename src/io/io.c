/* Mesh file I/O: format detection, dispatch to the format readers and writers, file wrappers. */
#define _POSIX_C_SOURCE 200809L
#include "io/formats.h"
#include "io/lexer.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

sk_format sk_format_from_path(const char *path)
{
    if (!path || strlen(sk__basename(path)) < 4)
        return SK_FORMAT_UNKNOWN;
    if (sk_path_has_ext(path, ".off"))
        return SK_FORMAT_OFF;
    if (sk_path_has_ext(path, ".obj"))
        return SK_FORMAT_OBJ;
    if (sk_path_has_ext(path, ".ply"))
        return SK_FORMAT_PLY;
    if (sk_path_has_ext(path, ".stl"))
        return SK_FORMAT_STL;
    return SK_FORMAT_UNKNOWN;
}

const char *sk_format_name(sk_format format)
{
    switch (format) {
    case SK_FORMAT_AUTO: return "auto";
    case SK_FORMAT_OFF: return "OFF";
    case SK_FORMAT_OBJ: return "OBJ";
    case SK_FORMAT_PLY: return "PLY";
    case SK_FORMAT_STL: return "STL";
    case SK_FORMAT_UNKNOWN: return "unknown";
    }
    return "unknown";
}

/* Does the text at p (length n) contain word at the start of a line (after blanks)? Looks only
 * at the first `limit` bytes. */
static bool has_line_starting(const char *p, size_t n, const char *word, size_t limit)
{
    size_t wl = strlen(word);
    if (n > limit)
        n = limit;
    size_t i = 0;
    while (i < n) {
        while (i < n && sk__is_blank(p[i]))
            ++i;
        if (n - i >= wl && memcmp(p + i, word, wl) == 0)
            return true;
        while (i < n && !sk__is_eol(p[i]))
            ++i;
        while (i < n && sk__is_eol(p[i]))
            ++i;
    }
    return false;
}

/* Guesses the format from the content: PLY magic, an OFF keyword, ascii STL ("solid" and a
 * "facet"), binary STL (size 84 + 50 n), OBJ statements. */
static sk_format sniff(const char *p, size_t n)
{
    if (n >= 3 && memcmp(p, "ply", 3) == 0 && (n == 3 || sk__is_eol(p[3])))
        return SK_FORMAT_PLY;
    size_t i = 0;
    while (i < n && (sk__is_space(p[i]) || p[i] == '#')) {
        if (p[i] == '#')
            while (i < n && !sk__is_eol(p[i]))
                ++i;
        else
            ++i;
    }
    size_t tl = sk__token_len(p + i, p + n);
    if (tl >= 3 && tl <= 8 && memcmp(p + i + tl - 3, "OFF", 3) == 0)
        return SK_FORMAT_OFF;
    if (n - i >= 5 && memcmp(p + i, "solid", 5) == 0 && has_line_starting(p, n, "facet", 4096))
        return SK_FORMAT_STL;
    if (sk__stl_is_binary_size(p, n))
        return SK_FORMAT_STL;
    if (has_line_starting(p, n, "v ", 65536) || has_line_starting(p, n, "f ", 65536) ||
        has_line_starting(p, n, "v\t", 65536))
        return SK_FORMAT_OBJ;
    return SK_FORMAT_UNKNOWN;
}

sk_status sk_soup_read_memory(const void *data, size_t size, const char *name,
                              const sk_read_opts *opts, sk_soup **out, sk_error *err)
{
    if (!out)
        return sk__fail(err, SK_ERR_ARG, "no output soup");
    *out = NULL;
    if (!name)
        name = "<memory>";
    if (!data && size)
        return sk__fail(err, SK_ERR_ARG, "%s: no data", name);
    if (!data)
        data = "";
    sk__ok(err);
    size_t lead = 0;
    while (lead < size && sk__is_space(((const char *)data)[lead]))
        ++lead;
    if (lead == size)
        return sk__fail(err, SK_ERR_PARSE, "%s:1: empty file", name);
    sk_format fmt = opts ? opts->format : SK_FORMAT_AUTO;
    if (fmt == SK_FORMAT_AUTO)
        fmt = sk_format_from_path(name);
    if (fmt == SK_FORMAT_AUTO || fmt == SK_FORMAT_UNKNOWN) {
        fmt = sniff(data, size);
    }
    switch (fmt) {
    case SK_FORMAT_OFF: return sk__read_off(data, size, name, out, err);
    case SK_FORMAT_OBJ: return sk__read_obj(data, size, name, out, err);
    case SK_FORMAT_PLY: return sk__read_ply(data, size, name, out, err);
    case SK_FORMAT_STL: return sk__read_stl(data, size, name, out, err);
    case SK_FORMAT_AUTO:
    case SK_FORMAT_UNKNOWN: break;
    }
    return sk__fail(err, SK_ERR_PARSE,
                    "%s:1: cannot tell the file format (not OFF, OBJ, PLY or STL)", name);
}

/* Reads a whole file into a malloc'ed buffer. */
static sk_status read_file(const char *path, char **data, size_t *size, sk_error *err)
{
    *data = NULL;
    *size = 0;
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever; regular
     * files ignore the flag */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return sk__fail(err, SK_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(fd);
        return sk__fail(err, SK_ERR_IO, "%s: not a regular file (a pipe, device or directory)", path);
    }
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        int e = errno;
        close(fd);
        return sk__fail(err, e == ENOMEM ? SK_ERR_NOMEM : SK_ERR_IO, "%s: cannot open: %s", path,
                        strerror(e));
    }
    size_t cap = sb.st_size > 0 ? (size_t)sb.st_size : 0;
    char *buf = sk__malloc_array(cap + 1, 1);
    if (!buf) {
        fclose(f);
        return sk__fail(err, SK_ERR_NOMEM, "%s: out of memory reading %zu bytes", path, cap);
    }
    size_t n = fread(buf, 1, cap, f);
    if (n != cap || ferror(f)) {
        int e = errno;
        sk__free(buf);
        fclose(f);
        return sk__fail(err, SK_ERR_IO, "%s: read failed: %s", path, strerror(e));
    }
    fclose(f);
    *data = buf;
    *size = n;
    return SK_OK;
}

sk_status sk_soup_read(const char *path, const sk_read_opts *opts, sk_soup **out, sk_error *err)
{
    if (!out)
        return sk__fail(err, SK_ERR_ARG, "no output soup");
    *out = NULL;
    if (!path || !*path)
        return sk__fail(err, SK_ERR_ARG, "empty input path");
    char *data;
    size_t size;
    sk_status st = read_file(path, &data, &size, err);
    if (st)
        return st;
    sk_read_opts o = opts ? *opts : (sk_read_opts){0};
    if (o.format == SK_FORMAT_AUTO)
        o.format = sk_format_from_path(path);
    if (o.format == SK_FORMAT_UNKNOWN)
        o.format = SK_FORMAT_AUTO;
    st = sk_soup_read_memory(data, size, sk__basename(path), &o, out, err);
    sk__free(data);
    return st;
}

static sk_status write_sink(sk__out *o, const sk_soup *soup, const sk_write_opts *opts,
                            sk_format fmt, sk_error *err)
{
    sk_status st = sk__check_soup_for_write(soup, err);
    if (st)
        return st;
    bool normals = soup->normals && !opts->no_normals;
    bool uvs = soup->uvs && !opts->no_uvs;
    /* OBJ and PLY also carry per-corner values (the writers look at soup->corner_*) */
    bool any_normals = (soup->normals || soup->corner_normal) && !opts->no_normals;
    bool any_uvs = (soup->uvs || soup->corner_uv) && !opts->no_uvs;
    switch (fmt) {
    case SK_FORMAT_OFF: sk__write_off(o, soup, normals, uvs); break;
    case SK_FORMAT_OBJ: sk__write_obj(o, soup, any_normals, any_uvs); break;
    case SK_FORMAT_PLY: sk__write_ply(o, soup, normals, any_uvs, opts->ascii); break;
    case SK_FORMAT_STL: sk__write_stl(o, soup, opts->ascii); break;
    case SK_FORMAT_AUTO:
    case SK_FORMAT_UNKNOWN:
        return sk__fail(err, SK_ERR_ARG, "no output format given");
    }
    sk__out_flush(o);
    if (o->failed == SK_ERR_NOMEM)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory writing the %s file",
                        sk_format_name(fmt));
    if (o->failed)
        return sk__fail(err, SK_ERR_IO, "write failed: %s", strerror(o->io_errno ? o->io_errno : EIO));
    return SK_OK;
}

sk_status sk_soup_write_memory(const sk_soup *soup, const sk_write_opts *opts, void **data,
                               size_t *size, sk_error *err)
{
    if (!data || !size || !soup)
        return sk__fail(err, SK_ERR_ARG, "no soup or no output buffer");
    *data = NULL;
    *size = 0;
    sk_write_opts o = opts ? *opts : (sk_write_opts){0};
    sk__out out = {0};
    sk_status st = write_sink(&out, soup, &o, o.format, err);
    if (st) {
        sk__free(out.buf);
        return st;
    }
    if (!out.buf)
        out.buf = sk__malloc_array(1, 1);
    if (!out.buf)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    *data = out.buf;
    *size = out.len;
    sk__ok(err);
    return SK_OK;
}

sk_status sk_soup_write(const char *path, const sk_soup *soup, const sk_write_opts *opts,
                        sk_error *err)
{
    if (!soup)
        return sk__fail(err, SK_ERR_ARG, "no soup");
    if (!path || !*path)
        return sk__fail(err, SK_ERR_ARG, "empty output path");
    sk_write_opts o = opts ? *opts : (sk_write_opts){0};
    if (o.format == SK_FORMAT_AUTO)
        o.format = sk_format_from_path(path);
    if (o.format == SK_FORMAT_AUTO || o.format == SK_FORMAT_UNKNOWN)
        return sk__fail(err, SK_ERR_ARG,
                        "%s: cannot tell the output format (use .off, .obj, .ply or .stl)", path);
    /* refuse a bad soup before creating any file */
    sk_status st = sk__check_soup_for_write(soup, err);
    if (st)
        return st;
    sk__atomic_file af;
    st = sk__atomic_open(&af, path, err);
    if (st)
        return st;
    sk__out out = {0};
    out.fp = af.fp;
    st = write_sink(&out, soup, &o, o.format, err);
    sk__free(out.buf);
    if (st) {
        sk__atomic_abort(&af);
        if (err && st == SK_ERR_IO) { /* name the file, keep the reason */
            char why[sizeof err->message];
            memcpy(why, err->message, sizeof why);
            sk__fail(err, st, "%s: %s", path, why);
        }
        return st;
    }
    st = sk__atomic_commit(&af, err);
    if (!st)
        sk__ok(err);
    return st;
}
