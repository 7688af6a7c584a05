/* Shared CLI helpers: errors, progress bar, JSON, option values. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

void cli_error(const char *fmt, ...)
{
    va_list ap;
    fputs("surfkit: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

int cli_fail(sk_status st, const sk_error *err)
{
    cli_error("%s", err && err->message[0] ? err->message : sk_status_string(st));
    return cli_exit_code(st);
}

int cli_exit_code(sk_status st)
{
    switch (st) {
    case SK_OK:
    case SK_WARN_FLIPS:
        return EXIT_OK;
    case SK_ERR_IO:
    case SK_ERR_PARSE:
    case SK_ERR_TOPOLOGY:
        return EXIT_BAD_INPUT;
    case SK_ERR_ARG:
        return EXIT_USAGE;
    case SK_ERR_NUMERIC:
    case SK_ERR_NOMEM:
    case SK_ERR_CANCELLED:
        return EXIT_INTERNAL;
    }
    return EXIT_INTERNAL;
}

int cli_usage(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "surfkit %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, " (see 'surfkit %s --help')\n", cmd);
    return EXIT_USAGE;
}

void cli_progress_init(cli_progress *p, const char *label, bool quiet)
{
    p->enabled = !quiet && isatty(STDERR_FILENO);
    p->label = label;
    p->last = -1;
}

int cli_progress_cb(void *user, double fraction)
{
    cli_progress *p = user;
    if (!p || !p->enabled)
        return 0;
    int pct = (int)(fraction * 100.0 + 0.5);
    if (pct == p->last)
        return 0;
    p->last = pct;
    int bar = pct * 30 / 100;
    fprintf(stderr, "\r%-12s [%.*s%*s] %3d%%", p->label, bar, "##############################",
            30 - bar, "", pct);
    fflush(stderr);
    return 0;
}

void cli_progress_done(cli_progress *p)
{
    if (p->enabled && p->last >= 0)
        fprintf(stderr, "\r%*s\r", 60, "");
}

/* --- JSON ---------------------------------------------------------------------------------- */

static void json_raw_str(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
        if (*p == '"' || *p == '\\')
            fprintf(fp, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(fp, "\\u%04x", *p);
        else
            fputc(*p, fp);
    }
    fputc('"', fp);
}

static void json_sep(cli_json *j)
{
    if (j->depth > 0 && j->need_comma[j->depth])
        fputs(",", j->fp);
    if (j->depth > 0)
        j->need_comma[j->depth] = true;
}

void json_begin(cli_json *j, FILE *fp)
{
    j->fp = fp;
    j->depth = 0;
    j->after_key = false;
    memset(j->need_comma, 0, sizeof j->need_comma);
}

void json_end(cli_json *j)
{
    fputc('\n', j->fp);
}

void json_key(cli_json *j, const char *key)
{
    json_sep(j);
    fprintf(j->fp, "\n%*s", 2 * j->depth, "");
    json_raw_str(j->fp, key);
    fputs(": ", j->fp);
    j->after_key = true;
}

static void value_prefix(cli_json *j)
{
    if (j->after_key) {
        j->after_key = false;
        return;
    }
    json_sep(j);
}

static void open_(cli_json *j, char c)
{
    value_prefix(j);
    fputc(c, j->fp);
    if (j->depth < 31)
        j->need_comma[++j->depth] = false;
}

static void close_(cli_json *j, char c)
{
    if (j->depth > 0)
        j->depth--;
    fputc(c, j->fp);
}

void json_obj_open(cli_json *j) { open_(j, '{'); }
void json_obj_close(cli_json *j)
{
    fprintf(j->fp, "\n%*s", 2 * (j->depth - 1 > 0 ? j->depth - 1 : 0), "");
    close_(j, '}');
}
void json_arr_open(cli_json *j) { open_(j, '['); }
void json_arr_close(cli_json *j) { close_(j, ']'); }

void json_uint(cli_json *j, unsigned long long v)
{
    value_prefix(j);
    fprintf(j->fp, "%llu", v);
}

void json_int(cli_json *j, long long v)
{
    value_prefix(j);
    fprintf(j->fp, "%lld", v);
}

void json_num(cli_json *j, double v)
{
    value_prefix(j);
    if (isfinite(v))
        fprintf(j->fp, "%.17g", v);
    else
        fputs("null", j->fp);
}

void json_bool(cli_json *j, bool v)
{
    value_prefix(j);
    fputs(v ? "true" : "false", j->fp);
}

void json_str(cli_json *j, const char *s)
{
    value_prefix(j);
    json_raw_str(j->fp, s);
}

void json_kuint(cli_json *j, const char *key, unsigned long long v) { json_key(j, key); json_uint(j, v); }
void json_kint(cli_json *j, const char *key, long long v) { json_key(j, key); json_int(j, v); }
void json_knum(cli_json *j, const char *key, double v) { json_key(j, key); json_num(j, v); }
void json_kbool(cli_json *j, const char *key, bool v) { json_key(j, key); json_bool(j, v); }
void json_kstr(cli_json *j, const char *key, const char *s)
{
    json_key(j, key);
    json_str(j, s);
}

typedef struct write_ctx {
    void (*fn)(FILE *, const void *);
    const void *ctx;
} write_ctx;

static sk_status write_through(FILE *fp, void *user)
{
    const write_ctx *w = user;
    w->fn(fp, w->ctx);
    return SK_OK; /* a write error shows in ferror(fp), which the writer checks */
}

int cli_write_file(const char *path, void (*fn)(FILE *, const void *), const void *ctx)
{
    write_ctx w = {fn, ctx};
    sk_error err = {0};
    sk_status st = sk_write_file(path, write_through, &w, &err);
    return st ? cli_fail(st, &err) : EXIT_OK;
}

int cli_take_path(int argc, char **argv, int *i, const char *cmd, const cli_path_opt *opts,
                  size_t n)
{
    for (size_t k = 0; k < n; ++k) {
        const char *val;
        if (!cli_opt_value(argc, argv, i, opts[k].name, &val))
            continue;
        if (!val || !*val) {
            cli_usage(cmd, "%s needs a file name", opts[k].name);
            return -1;
        }
        *opts[k].value = val;
        return 1;
    }
    return 0;
}

/* --- options --------------------------------------------------------------------------------- */

bool cli_opt_value(int argc, char **argv, int *i, const char *name, const char **out)
{
    const char *a = argv[*i];
    size_t n = strlen(name);
    if (strncmp(a, name, n) != 0)
        return false;
    if (a[n] == '=') {
        *out = a + n + 1;
        return true;
    }
    if (a[n] != '\0')
        return false;
    if (*i + 1 >= argc) {
        *out = NULL;
        return true;
    }
    *out = argv[++*i];
    return true;
}

bool cli_parse_uint(const char *s, unsigned long *out)
{
    if (!s || !*s || *s == '-')
        return false;
    char *end;
    errno = 0;
    unsigned long v = strtoul(s, &end, 10);
    if (errno || *end)
        return false;
    *out = v;
    return true;
}

bool cli_parse_double(const char *s, double *out)
{
    if (!s || !*s)
        return false;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || *end || !isfinite(v))
        return false;
    *out = v;
    return true;
}

bool cli_parse_vec3(const char *s, double v[3])
{
    if (!s)
        return false;
    char *end;
    for (int k = 0; k < 3; ++k) {
        v[k] = strtod(s, &end);
        if (end == s)
            return false;
        s = end;
        if (k < 2) {
            if (*s != ',')
                return false;
            ++s;
        }
    }
    return *s == '\0';
}
