/* surfkit: command-line entry point; dispatches to one file per subcommand. */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <signal.h>
#include <string.h>

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"info", cmd_info, "topology, defects, geometry and Gauss-Bonnet report of a mesh"},
    {"convert", cmd_convert, "convert between OFF, OBJ, PLY and STL"},
    {"subdivide", cmd_subdivide, "Loop or midpoint subdivision"},
    {"smooth", cmd_smooth, "VC1 smooth surface with continuity report; tessellation, IGES, STEP, OBJ free-form"},
    {"param", cmd_param, "parametrization of a disk: hierarchical MIPS, Tutte, Floater, mean value, harmonic, LSCM"},
    {"fit", cmd_fit, "one B-spline surface fitted to a disk within a tolerance; STEP, IGES"},
    {"deviation", cmd_deviation, "two-sided distance between a surface and a mesh, with a colour map"},
    {"view", cmd_view, "interactive HTML viewer: mesh, uv checkerboard, smooth surface with zebra stripes"},
    {"simplify", cmd_simplify, "progressive-mesh hierarchy by random independent half-edge collapses"},
};

static void usage(FILE *fp)
{
    fprintf(fp, "usage: surfkit SUBCOMMAND [options] INPUT [-o OUTPUT]\n\nsubcommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        fprintf(fp, "  %-12s %s\n", commands[i].name, commands[i].summary);
    fprintf(fp, "\n'surfkit SUBCOMMAND --help' describes each one. Exit codes: 0 ok, 1 bad input,\n"
                "2 usage, 3 internal failure (out of memory), 4 the result fails its own quality\n"
                "report (smooth).\n");
}

/* INT/TERM/HUP during a write: remove the named temporaries, then die of the signal as usual */
static void on_signal(int sig)
{
    sk_outputs_remove_pending();
    signal(sig, SIG_DFL);
    raise(sig);
}

/* A command's outputs are published together when it ends: all of them, or none when it fails
 * (exit 4 publishes what the command chose to write: smooth's report). */
static int run(const command *c, int argc, char **argv)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; ++i)
        sigaction(sigs[i], &sa, NULL);
    cli_fault_alloc_install();
    sk_outputs_begin();
    int rc = c->run(argc, argv);
    if (rc == EXIT_OK || rc == EXIT_QUALITY) {
        sk_error err = {0};
        sk_status st = sk_outputs_commit(&err);
        if (st)
            rc = cli_fail(st, &err);
    } else {
        sk_outputs_abort();
    }
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return EXIT_OK;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("surfkit %s\n", sk_version());
        return EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (!strcmp(argv[1], commands[i].name))
            return run(&commands[i], argc - 1, argv + 1);
    cli_error("unknown subcommand '%s' (see 'surfkit --help')", argv[1]);
    return EXIT_USAGE;
}
