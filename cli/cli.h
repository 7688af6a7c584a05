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

/* SURFKIT_FAIL_ALLOC=K makes the library's K-th allocation fail (tests; cli/fault_alloc.c). */
void cli_fault_alloc_install(void);

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
/* "key": the n values of v as an array, or (width > 1) an array of n arrays of width values */
void json_kuints(cli_json *j, const char *key, const uint32_t *v, size_t n, size_t width);

/* Writes a text file through fn into a temporary beside path, renamed into place when complete;
 * on failure prints the error and returns EXIT_BAD_INPUT. */
int cli_write_file(const char *path, void (*fn)(FILE *, const void *), const void *ctx);

/* --- Option tables ------------------------------------------------------------------------
 * Every subcommand declares its options in one table of cli_opt rows and calls cli_parse once;
 * the parser handles "--name value" and "--name=value", -h/--help (generated from the table:
 * usage line, the command's text, one line per option, then "Examples:"), unknown options and
 * bad values as one-line usage errors naming the option ("did you mean --tess?" by edit distance
 * for a misspelt option or choice value), and the positional file names.
 *
 * Adding an option is one row in the command's table, e.g. in cmd_smooth.c:
 *     OPT_DOUBLE("--crease-angle", so.crease_angle_deg, 0, 180, CLI_LO_OPEN, "DEG",
 *                "edges sharper than DEG are creases (default 30)"),
 *     OPT_FLAG("--keep-triangulation", so.keep_triangulation, "do not flip edges"),
 * The destination is the field itself (its size is taken with sizeof): a bool for OPT_FLAG, any
 * integer or enum for OPT_INT and OPT_CHOICE (the index of the value in "a|b|c"), a double for
 * OPT_DOUBLE, a const char * for OPT_STRING and OPT_FILE, a double[3] for OPT_VEC3 ("X,Y,Z").
 * INT and DOUBLE rows give their range: lo..hi, hi = 0 for no upper bound, CLI_LO_OPEN to
 * exclude lo. OPT_OUTPUT is a -o the command needs. After cli_parse, cli_given() says whether
 * an option was on the command line. */
typedef enum { CLI_FLAG, CLI_INT, CLI_DOUBLE, CLI_STRING, CLI_FILE, CLI_CHOICE, CLI_VEC3 } cli_kind;
enum { CLI_LO_OPEN = 1, CLI_REQUIRED = 2 };
typedef struct cli_opt {
    const char *name;  /* "--tess", "-o" */
    cli_kind kind;
    void *dest;
    size_t size;       /* sizeof *dest */
    double lo, hi;     /* INT, DOUBLE: the range (hi 0: none) */
    unsigned flags;    /* CLI_LO_OPEN; CLI_REQUIRED: the command needs it */
    const char *meta;  /* the value in the help ("N", "FILE"); CHOICE: the values "a|b|c" */
    const char *help;  /* may hold '\n' for more lines */
} cli_opt;
#define OPT_FLAG(name, field, help) {name, CLI_FLAG, &(field), sizeof(field), 0, 0, 0, NULL, help}
#define OPT_INT(name, field, lo, hi, meta, help)                                                   \
    {name, CLI_INT, &(field), sizeof(field), lo, hi, 0, meta, help}
#define OPT_DOUBLE(name, field, lo, hi, flags, meta, help)                                         \
    {name, CLI_DOUBLE, &(field), sizeof(field), lo, hi, flags, meta, help}
#define OPT_STRING(name, field, meta, help)                                                        \
    {name, CLI_STRING, &(field), sizeof(field), 0, 0, 0, meta, help}
#define OPT_FILE(name, field, meta, help)                                                          \
    {name, CLI_FILE, &(field), sizeof(field), 0, 0, 0, meta, help}
/* -o OUT when the command cannot run without it */
#define OPT_OUTPUT(field, meta, help)                                                              \
    {"-o", CLI_FILE, &(field), sizeof(field), 0, 0, CLI_REQUIRED, meta, help}
#define OPT_CHOICE(name, field, values, help)                                                      \
    {name, CLI_CHOICE, &(field), sizeof(field), 0, 0, 0, values, help}
#define OPT_VEC3(name, field, help)                                                                \
    {name, CLI_VEC3, &(field), sizeof(field), 0, 0, 0, "X,Y,Z", help}

#define CLI_COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* What a command is: its name, the positional part of the usage line ("IN -o OUT"), its text
 * for --help, its option table, how many positional file names it needs and takes, and 2-4
 * example command lines ("  surfkit ...\n" each) that work from the repository root. Too few
 * file names or a missing OPT_OUTPUT is the usage error "needs <usage>". */
typedef struct cli_spec {
    const char *name;
    const char *usage;
    const char *about;
    const cli_opt *opts;
    size_t num_opts;   /* at most 64 */
    size_t min_inputs, max_inputs; /* at most 4 */
    const char *examples;
    const char *more;  /* optional text printed after the options (may be NULL) */
} cli_spec;

/* The result outlives the table (which is usually a local of a parsing function): it keeps the
 * names of the options given (string literals), not the table. */
typedef struct cli_args {
    const char *inputs[4];
    size_t num_inputs;
    const char *given[64]; /* the names of the options on the command line, each once */
    size_t num_given;
} cli_args;

/* cli_parse's result when --help was printed (the command returns EXIT_OK). */
enum { CLI_HELP = -1 };
/* Parses argv[1..argc-1] into the table's destinations. Returns EXIT_OK, CLI_HELP, or EXIT_USAGE
 * after printing the one-line error. */
int cli_parse(const cli_spec *spec, int argc, char **argv, cli_args *args);
/* The k-th positional file name, NULL when there are fewer. */
const char *cli_input(const cli_args *args, size_t k);
/* Whether option `name` (a name in the table) was given. */
bool cli_given(const cli_args *args, const char *name);
/* Prints the generated --help of spec. */
void cli_help(const cli_spec *spec, FILE *fp);
/* Edit distance (optimal string alignment: insertions, deletions, substitutions, swaps of two
 * neighbours) between a and b. */
size_t cli_edit_distance(const char *a, const char *b);

/* Option values (also used by the table parser). */
bool cli_parse_uint(const char *s, unsigned long *out);
bool cli_parse_double(const char *s, double *out);
/* "X,Y,Z" (e.g. a --view direction); false for anything else (s may be NULL). */
bool cli_parse_vec3(const char *s, double v[3]);

/* Reads a mesh for a command that needs triangles: quads and larger polygons are triangulated
 * (sk_soup_triangulate; what was split in *tri) unless keep_polygons, which reads it as it is
 * (the algorithms then refuse polygons). Errors name the file, as sk_mesh_read's do. */
sk_status cli_read_triangles(const char *path, bool keep_polygons, sk_mesh **out,
                             sk_triangulate_stats *tri, sk_error *err);
/* After a computation on the input `path` failed with st: prefixes err's message with "path: "
 * unless it names the file already (reader errors do) or is "out of memory", so that every
 * error names the file. */
void cli_name_input(const char *path, sk_status st, sk_error *err);
/* The JSON keys of that: "triangulated_quads", "triangulated_polygons" (0 for triangle input). */
void json_triangulated(cli_json *j, const sk_triangulate_stats *tri);
/* "IN: triangulated 6 quads (12 triangles)" on stdout when something was split. */
void cli_print_triangulated(const char *path, const sk_triangulate_stats *tri);

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


#endif
