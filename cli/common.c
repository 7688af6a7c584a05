/* Shared CLI helpers: errors, progress bar, JSON, the option-table parser, option values. */
#include "cli.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
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
    case SK_WARN_TOLERANCE:
        return EXIT_QUALITY;
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
    char buf[32];
    if (isfinite(v)) {
        sk_format_double(buf, v);
        fputs(buf, j->fp);
    } else
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

void json_kuints(cli_json *j, const char *key, const uint32_t *v, size_t n, size_t width)
{
    json_key(j, key);
    json_arr_open(j);
    for (size_t i = 0; i < n; ++i) {
        if (width > 1)
            json_arr_open(j);
        for (size_t k = 0; k < width; ++k)
            json_uint(j, v[width * i + k]);
        if (width > 1)
            json_arr_close(j);
    }
    json_arr_close(j);
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

/* --- the option-table parser (how to add an option: cli.h, above cli_opt) ------------------- */

size_t cli_edit_distance(const char *a, const char *b)
{
    size_t n = strlen(a), m = strlen(b);
    if (n > 64 || m > 64) /* option names and values are short; long ones are not close */
        return n > m ? n : m;
    size_t d[65][65];
    for (size_t i = 0; i <= n; ++i)
        d[i][0] = i;
    for (size_t j = 0; j <= m; ++j)
        d[0][j] = j;
    for (size_t i = 1; i <= n; ++i) {
        for (size_t j = 1; j <= m; ++j) {
            size_t best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < best)
                best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best)
                best = d[i][j - 1] + 1;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    }
    return d[n][m];
}

/* Whether `typed` is close enough to `cand` to suggest it: a prefix of it, or within about a
 * third of its length in edit distance (dashes not counted). */
static bool close_to(const char *typed, const char *cand, size_t *dist)
{
    while (*typed == '-')
        ++typed;
    while (*cand == '-')
        ++cand;
    size_t n = strlen(cand);
    if (*typed && strlen(typed) < n && !strncmp(typed, cand, strlen(typed))) {
        *dist = n - strlen(typed);
        return true;
    }
    *dist = cli_edit_distance(typed, cand);
    return *dist > 0 && 3 * *dist <= n + 1;
}

/* The choice values "a|b|c" one by one: copies value k into buf; false past the last. */
static bool choice_at(const char *values, size_t k, char *buf, size_t cap)
{
    const char *p = values;
    for (size_t i = 0; i < k; ++i) {
        p = strchr(p, '|');
        if (!p)
            return false;
        ++p;
    }
    size_t len = strcspn(p, "|");
    if (len + 1 > cap)
        len = cap - 1;
    memcpy(buf, p, len);
    buf[len] = '\0';
    return true;
}

/* Stores v into an integer field of `size` bytes; false when it does not fit. */
static bool store_uint(void *dest, size_t size, unsigned long long v)
{
    if (size == 1 && v <= UINT8_MAX) {
        uint8_t x = (uint8_t)v;
        memcpy(dest, &x, 1);
    } else if (size == 2 && v <= UINT16_MAX) {
        uint16_t x = (uint16_t)v;
        memcpy(dest, &x, 2);
    } else if (size == 4 && v <= INT32_MAX) { /* int, unsigned and enums alike */
        uint32_t x = (uint32_t)v;
        memcpy(dest, &x, 4);
    } else if (size == 8 && v <= INT64_MAX) {
        uint64_t x = (uint64_t)v;
        memcpy(dest, &x, 8);
    } else {
        return false;
    }
    return true;
}

/* "takes ..." of an INT or DOUBLE row, from its range. */
static void describe_range(const cli_opt *o, char *buf, size_t cap)
{
    bool integer = o->kind == CLI_INT, open = o->flags & CLI_LO_OPEN;
    if (integer && o->hi == 0)
        snprintf(buf, cap, o->lo >= 1 ? "a positive whole number" : "a whole number");
    else if (integer)
        snprintf(buf, cap, "a whole number from %.17g to %.17g", o->lo, o->hi);
    else if (o->hi == 0 && o->lo == 0)
        snprintf(buf, cap, open ? "a positive number" : "a number >= 0");
    else if (o->hi == 0)
        snprintf(buf, cap, "a number %s %.17g", open ? ">" : ">=", o->lo);
    else
        snprintf(buf, cap, "a number in %c%.17g, %.17g]", open ? '(' : '[', o->lo, o->hi);
}

static int bad_value(const cli_spec *spec, const cli_opt *o, const char *val)
{
    char what[160];
    switch (o->kind) {
    case CLI_INT:
    case CLI_DOUBLE:
        describe_range(o, what, sizeof what);
        break;
    case CLI_VEC3:
        snprintf(what, sizeof what, "three numbers X,Y,Z");
        break;
    case CLI_CHOICE: {
        /* "a, b or c", and the closest value when one is close */
        size_t len = 0, k = 0, best = SIZE_MAX, best_k = 0, dist;
        char v[64], next[64];
        what[0] = '\0';
        for (; choice_at(o->meta, k, v, sizeof v); ++k) {
            bool last = !choice_at(o->meta, k + 1, next, sizeof next);
            len += (size_t)snprintf(what + len, len < sizeof what ? sizeof what - len : 0, "%s%s",
                                    k == 0 ? "" : last ? " or " : ", ", v);
            if (val && close_to(val, v, &dist) && dist < best)
                best = dist, best_k = k;
        }
        if (best != SIZE_MAX && choice_at(o->meta, best_k, v, sizeof v))
            return cli_usage(spec->name, "%s takes %s, not '%s' (did you mean %s?)", o->name, what,
                             val, v);
        if (val && *val)
            return cli_usage(spec->name, "%s takes %s, not '%s'", o->name, what, val);
        return cli_usage(spec->name, "%s takes %s", o->name, what);
    }
    case CLI_FILE:
        return cli_usage(spec->name, "%s needs a file name", o->name);
    default:
        return cli_usage(spec->name, "%s needs a value", o->name);
    }
    if (!val)
        return cli_usage(spec->name, "%s takes %s", o->name, what);
    return cli_usage(spec->name, "%s takes %s, not '%s'", o->name, what, val);
}

/* Parses val into o's destination; EXIT_OK or the usage error. */
static int take_value(const cli_spec *spec, const cli_opt *o, const char *val)
{
    if (!val)
        return bad_value(spec, o, val);
    switch (o->kind) {
    case CLI_INT: {
        unsigned long v;
        if (!cli_parse_uint(val, &v) || (double)v < o->lo || (o->hi != 0 && (double)v > o->hi) ||
            !store_uint(o->dest, o->size, v))
            return bad_value(spec, o, val);
        return EXIT_OK;
    }
    case CLI_DOUBLE: {
        double v;
        bool open = o->flags & CLI_LO_OPEN;
        if (!cli_parse_double(val, &v) || (open ? !(v > o->lo) : !(v >= o->lo)) ||
            (o->hi != 0 && v > o->hi))
            return bad_value(spec, o, val);
        *(double *)o->dest = v;
        return EXIT_OK;
    }
    case CLI_VEC3: {
        double v[3];
        if (!cli_parse_vec3(val, v))
            return bad_value(spec, o, val);
        memcpy(o->dest, v, sizeof v);
        return EXIT_OK;
    }
    case CLI_CHOICE: {
        char v[64];
        for (size_t k = 0; choice_at(o->meta, k, v, sizeof v); ++k)
            if (!strcmp(v, val))
                return store_uint(o->dest, o->size, k) ? EXIT_OK : bad_value(spec, o, val);
        return bad_value(spec, o, val);
    }
    case CLI_FILE:
    case CLI_STRING:
        if (!*val)
            return bad_value(spec, o, val);
        *(const char **)o->dest = val;
        return EXIT_OK;
    case CLI_FLAG:
        break;
    }
    return bad_value(spec, o, val);
}

static int unknown_option(const cli_spec *spec, const char *arg)
{
    char name[64];
    size_t len = strcspn(arg, "=");
    if (len >= sizeof name)
        len = sizeof name - 1;
    memcpy(name, arg, len);
    name[len] = '\0';
    size_t best = SIZE_MAX, dist;
    const char *guess = NULL;
    for (size_t k = 0; k < spec->num_opts; ++k)
        if (close_to(name, spec->opts[k].name, &dist) && dist < best)
            best = dist, guess = spec->opts[k].name;
    if (guess)
        return cli_usage(spec->name, "unknown option '%s' (did you mean %s?)", name, guess);
    return cli_usage(spec->name, "unknown option '%s'", name);
}

int cli_parse(const cli_spec *spec, int argc, char **argv, cli_args *args)
{
    assert(spec->num_opts <= 64 && spec->max_inputs <= 4); /* the room in cli_args */
    memset(args, 0, sizeof *args);
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            cli_help(spec, stdout);
            return CLI_HELP;
        }
        if (a[0] != '-' || !a[1]) {
            if (args->num_inputs >= spec->max_inputs)
                return cli_usage(spec->name, spec->max_inputs == 1 ? "more than one input file"
                                                                   : "too many file names");
            args->inputs[args->num_inputs++] = a;
            continue;
        }
        size_t len = strcspn(a, "=");
        const cli_opt *o = NULL;
        size_t k = 0;
        for (; k < spec->num_opts && !o; ++k)
            if (strlen(spec->opts[k].name) == len && !strncmp(a, spec->opts[k].name, len))
                o = &spec->opts[k];
        if (!o || (o->kind == CLI_FLAG && a[len] == '='))
            return unknown_option(spec, a);
        if (!cli_given(args, o->name))
            args->given[args->num_given++] = o->name;
        if (o->kind == CLI_FLAG) {
            *(bool *)o->dest = true;
            continue;
        }
        const char *val = a[len] == '=' ? a + len + 1 : i + 1 < argc ? argv[++i] : NULL;
        int rc = take_value(spec, o, val);
        if (rc)
            return rc;
    }
    bool missing = args->num_inputs < spec->min_inputs;
    for (size_t k = 0; k < spec->num_opts; ++k)
        missing |= (spec->opts[k].flags & CLI_REQUIRED) && !cli_given(args, spec->opts[k].name);
    return missing ? cli_usage(spec->name, "needs %s", spec->usage) : EXIT_OK;
}

const char *cli_input(const cli_args *args, size_t k)
{
    return k < args->num_inputs ? args->inputs[k] : NULL;
}

bool cli_given(const cli_args *args, const char *name)
{
    for (size_t k = 0; k < args->num_given; ++k)
        if (!strcmp(args->given[k], name))
            return true;
    return false;
}

/* text with '\n' inside, each further line indented by `indent` */
static void print_indented(FILE *fp, const char *text, int indent)
{
    for (const char *p = text; *p;) {
        size_t len = strcspn(p, "\n");
        fprintf(fp, "%.*s\n", (int)len, p);
        p += len;
        if (*p == '\n' && *++p)
            fprintf(fp, "%*s", indent, "");
    }
}

void cli_help(const cli_spec *spec, FILE *fp)
{
    enum { COLUMN = 26 };
    fprintf(fp, "usage: surfkit %s %s [options]\n\n", spec->name, spec->usage);
    fputs(spec->about, fp);
    fputs("\noptions:\n", fp);
    for (size_t k = 0; k < spec->num_opts; ++k) {
        const cli_opt *o = &spec->opts[k];
        int w = fprintf(fp, "  %s%s%s", o->name, o->meta ? " " : "", o->meta ? o->meta : "");
        if (w >= COLUMN - 1) {
            fputc('\n', fp);
            w = 0;
        }
        fprintf(fp, "%*s", COLUMN - w, "");
        print_indented(fp, o->help, COLUMN);
    }
    fprintf(fp, "  %-*s%s\n", COLUMN - 2, "-h, --help", "this text");
    if (spec->more)
        fputs(spec->more, fp);
    fprintf(fp, "\nExamples:\n%s", spec->examples);
}

/* --- triangle input ------------------------------------------------------------------------- */

/* Every face a triangle: the soup is its own triangulation (no copy of a million-face soup). */
static bool only_triangles(const sk_soup *s)
{
    for (size_t f = 0; f < s->num_faces; ++f)
        if (sk_soup_face_size(s, f) != 3)
            return false;
    return true;
}

sk_status cli_read_triangles(const char *path, bool keep_polygons, sk_mesh **out,
                             sk_triangulate_stats *tri, sk_error *err)
{
    memset(tri, 0, sizeof *tri);
    if (keep_polygons)
        return sk_mesh_read(path, NULL, out, err);
    *out = NULL;
    sk_soup *soup = NULL, *tris = NULL;
    sk_status st = sk_soup_read(path, NULL, &soup, err);
    if (st == SK_OK && !only_triangles(soup))
        st = sk_soup_triangulate(soup, &tris, tri, err);
    if (st == SK_OK && (st = sk_mesh_from_soup(tris ? tris : soup, out, err)) != SK_OK) {
        /* name the file, as sk_mesh_read does: "NAME: what is wrong" */
        const char *slash = strrchr(path, '/');
        char msg[sizeof err->message];
        memcpy(msg, err->message, sizeof msg);
        snprintf(err->message, sizeof err->message, "%s: %.200s", slash ? slash + 1 : path, msg);
    }
    sk_soup_destroy(&tris);
    sk_soup_destroy(&soup);
    return st;
}

void cli_name_input(const char *path, sk_status st, sk_error *err)
{
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    if (st >= 0 || st == SK_ERR_NOMEM || strstr(err->message, base))
        return;
    char out[2 * sizeof err->message];
    snprintf(out, sizeof out, "%s: %s", path, err->message);
    memcpy(err->message, out, sizeof err->message - 1);
    err->message[sizeof err->message - 1] = '\0';
}

void json_triangulated(cli_json *j, const sk_triangulate_stats *tri)
{
    json_kuint(j, "triangulated_quads", tri->quads);
    json_kuint(j, "triangulated_polygons", tri->polygons);
}

void cli_print_triangulated(const char *path, const sk_triangulate_stats *tri)
{
    if (!tri->quads && !tri->polygons)
        return;
    printf("%s: triangulated ", path);
    if (tri->quads)
        printf("%zu quad%s", tri->quads, tri->quads == 1 ? "" : "s");
    if (tri->polygons)
        printf("%s%zu polygon%s", tri->quads ? " and " : "", tri->polygons,
               tri->polygons == 1 ? "" : "s");
    printf(" into %zu triangles (--keep-polygons refuses polygons instead)\n", tri->triangles);
}
