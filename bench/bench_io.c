/* bench_io: times one read or one write of a mesh file and prints one table row:
 *   bench_io read FILE            -> format, MB, seconds, MB/s, peak RSS
 *   bench_io write IN OUT [ascii] -> reads IN untimed, times writing OUT
 * bench/io.sh runs it once per format and operation (separate processes, so the peak memory is
 * that of one operation). */
#include "surfkit/surfkit.h"

#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

static double file_mb(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (double)st.st_size / 1e6 : 0.0;
}

static double peak_mb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0;
}

int main(int argc, char **argv)
{
    if (argc < 3 || (strcmp(argv[1], "read") && strcmp(argv[1], "write")) ||
        (!strcmp(argv[1], "write") && argc < 4)) {
        fprintf(stderr, "usage: bench_io read FILE | bench_io write IN OUT [ascii]\n");
        return 2;
    }
    sk_error err;
    sk_soup *soup = NULL;
    bool reading = !strcmp(argv[1], "read");
    double t0 = sk_seconds();
    if (sk_soup_read(argv[2], NULL, &soup, &err) != SK_OK) {
        fprintf(stderr, "bench_io: %s\n", err.message);
        return 1;
    }
    double t = sk_seconds() - t0;
    const char *path = argv[2];
    sk_write_opts wo = {0};
    if (!reading) {
        wo.ascii = argc > 4 && !strcmp(argv[4], "ascii");
        t0 = sk_seconds();
        if (sk_soup_write(argv[3], soup, &wo, &err) != SK_OK) {
            fprintf(stderr, "bench_io: %s\n", err.message);
            return 1;
        }
        t = sk_seconds() - t0;
        path = argv[3];
    }
    double mb = file_mb(path);
    const char *fmt = sk_format_name(sk_format_from_path(path));
    printf("| %-5s | %-6s | %-6s | %9zu | %7.1f | %7.3f | %7.1f | %8.0f |\n", argv[1], fmt,
           (!reading && wo.ascii) || (reading && strstr(path, "ascii")) ? "ascii" : "", soup->num_faces,
           mb, t, mb / t, peak_mb());
    sk_soup_destroy(&soup);
    return 0;
}
