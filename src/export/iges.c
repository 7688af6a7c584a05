/* IGES 5.3 writer: one rational B-spline surface entity (type 128, form 0, polynomial flag set)
 * per tensor Bezier patch; fixed 80-column records in the Start, Global, Directory Entry,
 * Parameter Data and Terminate sections. */
#include "export/export_internal.h"

#include <stdlib.h>
#include <string.h>

/* Appends one 80-column record: 72 (or 64 + pointer) columns of text, the section letter and the
 * sequence number. */
static void record(sk__buf *b, const char *text, char section, size_t seq)
{
    sk__buf_printf(b, "%-72.72s%c%7zu\n", text, section, seq);
}

/* Packs free-format tokens into records of `width` columns; each token ends with its delimiter.
 * For the P section, each record carries the DE pointer in columns 66-72. Returns records used. */
typedef struct packer {
    sk__buf *b;
    char section;
    size_t *seq;
    size_t width;
    size_t de; /* P section: directory entry pointer */
    char line[81];
    size_t len, count;
} packer;

static void pack_flush(packer *p)
{
    if (!p->len)
        return;
    p->line[p->len] = '\0';
    if (p->section == 'P') {
        char text[256];
        snprintf(text, sizeof text, "%-64.64s %7zu", p->line, p->de);
        record(p->b, text, 'P', ++*p->seq);
    } else {
        record(p->b, p->line, p->section, ++*p->seq);
    }
    p->len = 0;
    p->count++;
}

static void pack(packer *p, const char *token, char delim)
{
    size_t n = strlen(token);
    if (p->len + n + 1 > p->width)
        pack_flush(p);
    if (n + 1 > p->width) { /* cannot happen for our tokens (numbers, short strings) */
        n = p->width - 1;
    }
    memcpy(p->line + p->len, token, n);
    p->len += n;
    p->line[p->len++] = delim;
}

static void pack_real(packer *p, double x, char delim)
{
    char buf[32];
    pack(p, sk__fmt_real(buf, x), delim);
}

static void pack_int(packer *p, long x, char delim)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%ld", x);
    pack(p, buf, delim);
}

static void pack_string(packer *p, const char *s, char delim)
{
    char buf[96];
    snprintf(buf, sizeof buf, "%zuH%.60s", strlen(s) > 60 ? (size_t)60 : strlen(s), s);
    pack(p, buf, delim);
}

sk_status sk_export_iges(const char *path, const sk_patch_set *patches,
                         const sk_export_opts *opts, sk_export_stats *stats, sk_error *err)
{
    const sk__unit *unit = sk__unit_lookup(opts ? opts->units : NULL);
    if (!unit)
        return sk__fail(err, SK_ERR_ARG, "unknown unit '%s'", opts->units);
    sk_patch_set ts = {0};
    sk_status st = sk_export_tensor_patches(patches, opts, &ts, err);
    if (st) {
        sk_patch_set_free(&ts);
        return st;
    }
    size_t nt = ts.count;
    const char *name = opts && opts->name ? opts->name : "surfkit";
    char when[32], stamp[32];
    sk__export_time(opts, when);
    /* IGES dates: 15HYYYYMMDD.HHNNSS */
    snprintf(stamp, sizeof stamp, "%.4s%.2s%.2s.%.2s%.2s%.2s", when, when + 5, when + 8, when + 11,
             when + 14, when + 17);
    double maxc = sk__patches_max_coord(&ts);

    sk__buf out = {0}, dsec = {0}, psec = {0};
    size_t s_seq = 0, g_seq = 0, d_seq = 0, p_seq = 0;
    record(&out, "surfkit: VC1 surface (quartic triangular and bicubic Bezier patches) as IGES "
                 "entity 128", 'S', ++s_seq);

    packer g = {.b = &out, .section = 'G', .seq = &g_seq, .width = 72};
    char file_name[128];
    snprintf(file_name, sizeof file_name, "%s", sk__basename(path));
    pack(&g, "1H,", ',');
    pack(&g, "1H;", ',');
    pack_string(&g, name, ',');
    pack_string(&g, file_name, ',');
    pack_string(&g, "surfkit", ',');
    pack_string(&g, "surfkit 0.1.0", ',');
    pack_int(&g, 32, ',');
    pack_int(&g, 38, ',');
    pack_int(&g, 6, ',');
    pack_int(&g, 308, ',');
    pack_int(&g, 15, ',');
    pack_string(&g, name, ',');
    pack_real(&g, 1.0, ',');
    pack_int(&g, unit->iges_flag, ',');
    pack_string(&g, unit->iges_name, ',');
    pack_int(&g, 1, ',');
    pack_real(&g, 1.0, ',');
    pack_string(&g, stamp, ',');
    pack_real(&g, 1e-9 * (maxc > 0 ? maxc : 1.0), ',');
    pack_real(&g, maxc, ',');
    pack_string(&g, "surfkit", ',');
    pack_string(&g, "surfkit", ',');
    pack_int(&g, 11, ','); /* version 5.3 */
    pack_int(&g, 0, ',');
    pack_string(&g, stamp, ';');
    pack_flush(&g);

    for (size_t i = 0; i < nt; ++i) {
        const sk_patch *p = &ts.patches[i];
        const double *cp = sk_patch_cp(&ts, i);
        unsigned du = p->degree, dv = p->degree_v;
        size_t de = 2 * i + 1, first = p_seq + 1;
        packer pp = {.b = &psec, .section = 'P', .seq = &p_seq, .width = 64, .de = de};
        pack_int(&pp, 128, ',');
        pack_int(&pp, (long)du, ',');   /* K1: upper index of the u sum */
        pack_int(&pp, (long)dv, ',');   /* K2 */
        pack_int(&pp, (long)du, ',');   /* M1: degree */
        pack_int(&pp, (long)dv, ',');   /* M2 */
        pack_int(&pp, 0, ',');          /* PROP1: not closed in u */
        pack_int(&pp, 0, ',');          /* PROP2: not closed in v */
        pack_int(&pp, 1, ',');          /* PROP3: polynomial */
        pack_int(&pp, 0, ',');          /* PROP4: not periodic in u */
        pack_int(&pp, 0, ',');          /* PROP5: not periodic in v */
        for (unsigned k = 0; k < 2 * (du + 1); ++k)
            pack_real(&pp, k <= du ? 0.0 : 1.0, ',');
        for (unsigned k = 0; k < 2 * (dv + 1); ++k)
            pack_real(&pp, k <= dv ? 0.0 : 1.0, ',');
        for (unsigned k = 0; k < (du + 1) * (dv + 1); ++k)
            pack_real(&pp, 1.0, ',');
        for (unsigned j = 0; j <= dv; ++j) /* first index (u) varies fastest */
            for (unsigned a = 0; a <= du; ++a)
                for (int x = 0; x < 3; ++x)
                    pack_real(&pp, cp[3 * sk_tensor_index(du, a, j) + (unsigned)x], ',');
        pack_real(&pp, 0.0, ',');
        pack_real(&pp, 1.0, ',');
        pack_real(&pp, 0.0, ',');
        pack_real(&pp, 1.0, ';');
        pack_flush(&pp);
        size_t lines = p_seq - first + 1;
        char l1[256], l2[256];
        snprintf(l1, sizeof l1, "%8d%8zu%8d%8d%8d%8d%8d%8d%8s", 128, first, 0, 1, 0, 0, 0, 0,
                 "00000000");
        snprintf(l2, sizeof l2, "%8d%8d%8d%8zu%8d%8s%8s%8s%8zu", 128, 0, 0, lines, 0, "", "",
                 "BEZIER", i + 1);
        record(&dsec, l1, 'D', ++d_seq);
        record(&dsec, l2, 'D', ++d_seq);
    }
    sk__buf_put(&out, dsec.s ? dsec.s : "", dsec.n);
    sk__buf_put(&out, psec.s ? psec.s : "", psec.n);
    char term[256];
    snprintf(term, sizeof term, "S%07zuG%07zuD%07zuP%07zu", s_seq, g_seq, d_seq, p_seq);
    record(&out, term, 'T', 1);
    if (dsec.failed || psec.failed)
        out.failed = true;
    st = sk__buf_write_file(&out, path, err);
    if (st == SK_OK && stats) {
        memset(stats, 0, sizeof *stats);
        stats->faces = nt;
        stats->bytes = out.n;
    }
    sk__buf_free(&out);
    sk__buf_free(&dsec);
    sk__buf_free(&psec);
    sk_patch_set_free(&ts);
    return st;
}
