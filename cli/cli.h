/* Shared pieces of the surfkit command-line tool: exit codes, one-line errors, progress bar,
 * a small JSON emitter, option parsing helpers. The CLI parses arguments and prints; all geometry
 * is in the library. */
#ifndef SK_CLI_H
#define SK_CLI_H

#include "surfkit/surfkit.h"

#include <stdbool.h>
#include <stdio.h>

/* EXIT_QUALITY: the result fails its own quality report (smooth) */
enum { EXIT_OK = 0, EXIT_BAD_INPUT = 1, EXIT_USAGE = 2, EXIT_INTERNAL = 3, EXIT_QUALITY = 4 };

/* "surfkit: message" on stderr, one line. */
void cli_error(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;
/* Prints err's message and returns the exit code for the status. */
int cli_fail(sk_status st, const sk_error *err);
/* The exit code for a status. */
int cli_exit_code(sk_status st);
/* Usage error: prints "surfkit CMD: message" and a hint, returns EXIT_USAGE. */
int cli_usage(const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Progress bar on stderr, drawn only when stderr is a terminal and not quiet. */
typedef struct cli_progress {
    bool enabled;
    const char *label;
    int last;
} cli_progress;
void cli_progress_init(cli_progress *p, const char *label, bool quiet);
int cli_progress_cb(void *user, double fraction);
void cli_progress_done(cli_progress *p);

/* Minimal JSON writer. */
typedef struct cli_json {
    FILE *fp;
    int depth;
    bool need_comma[32];
    bool after_key;
} cli_json;
void json_begin(cli_json *j, FILE *fp);
void json_end(cli_json *j);
void json_key(cli_json *j, const char *key); /* inside an object: "key": */
void json_obj_open(cli_json *j);
void json_obj_close(cli_json *j);
void json_arr_open(cli_json *j);
void json_arr_close(cli_json *j);
void json_uint(cli_json *j, unsigned long long v);
void json_int(cli_json *j, long long v);
void json_num(cli_json *j, double v); /* non-finite numbers become null */
void json_bool(cli_json *j, bool v);
void json_str(cli_json *j, const char *s);
/* key + value shorthands */
void json_kuint(cli_json *j, const char *key, unsigned long long v);
void json_kint(cli_json *j, const char *key, long long v);
void json_knum(cli_json *j, const char *key, double v);
void json_kbool(cli_json *j, const char *key, bool v);
void json_kstr(cli_json *j, const char *key, const char *s);

/* Writes a text file through fn into a temporary beside path, renamed into place when complete;
 * on failure prints the error and returns EXIT_BAD_INPUT. */
int cli_write_file(const char *path, void (*fn)(FILE *, const void *), const void *ctx);

/* Option parsing: returns true and sets *out when argv[*i] is `name` followed by a value, or
 * `name=value`; advances *i. */
bool cli_opt_value(int argc, char **argv, int *i, const char *name, const char **out);
/* Options that take a file name: when argv[*i] is one of them, stores its value and returns 1;
 * a missing value prints the usage error and returns -1; any other argument returns 0. */
typedef struct cli_path_opt {
    const char *name;
    const char **value;
} cli_path_opt;
int cli_take_path(int argc, char **argv, int *i, const char *cmd, const cli_path_opt *opts,
                  size_t n);
bool cli_parse_uint(const char *s, unsigned long *out);
bool cli_parse_double(const char *s, double *out);
/* "X,Y,Z" (e.g. a --view direction); false for anything else (s may be NULL). */
bool cli_parse_vec3(const char *s, double v[3]);

/* Subcommands */
int cmd_info(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_subdivide(int argc, char **argv);
int cmd_smooth(int argc, char **argv);
int cmd_param(int argc, char **argv);
int cmd_simplify(int argc, char **argv);
int cmd_deviation(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_view(int argc, char **argv);

/* surfkit param with an atlas (cli/cmd_param_atlas.c): takes the run (*handled = true) when the
 * input is not one disk or an atlas option is given; else leaves it to cmd_param. */
int cmd_param_atlas(int argc, char **argv, bool *handled);
extern const char cli_param_atlas_help[];

#endif
