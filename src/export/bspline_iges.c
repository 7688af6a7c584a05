/* IGES 5.3 of one B-spline surface (bspline_export.h): a single independent entity 128
 * (rational B-spline surface, polynomial: PROP3 = 1, all weights 1) in fixed 80-column records
 * of the Start, Global, Directory Entry, Parameter Data and Terminate sections. */
#include "surfkit/bspline_export.h"
#include "export/export_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One 80-column record: 72 columns of text, the section letter, the sequence number. */
static void record(sk__out *b, const char *text, char section, size_t seq)
{
    sk__out_printf(b, "%-72.72s%c%7zu\n", text, section, seq);
}

/* Free-format tokens packed into records of `width` columns, separated by ',' and ended by ';'.
 * In the P section every record carries the DE pointer in columns 66-72. */
typedef struct packer {
    sk__out *b;
    char section;
    size_t seq, width, de;
    char line[81];
    size_t len;
    char token[64];
    bool pending;
} packer;

static void flush_line(packer *p)
{
    if (!p->len)
        return;
    p->line[p->len] = '\0';
    char text[96];
    if (p->section == 'P')
        snprintf(text, sizeof text, "%-64.64s %7zu", p->line, p->de);
    else
        snprintf(text, sizeof text, "%s", p->line);
    record(p->b, text, p->section, ++p->seq);
    p->len = 0;
}

static void emit(packer *p, char delim)
{
    size_t n = strlen(p->token);
    if (p->len + n + 1 > p->width)
        flush_line(p);
    memcpy(p->line + p->len, p->token, n);
    p->len += n;
    p->line[p->len++] = delim;
    p->pending = false;
}

static void token(packer *p, const char *t)
{
    if (p->pending)
        emit(p, ',');
    snprintf(p->token, sizeof p->token, "%s", t);
    p->pending = true;
}

static void finish(packer *p)
{
    if (p->pending)
        emit(p, ';');
    flush_line(p);
}

static void real(packer *p, double x)
{
    char buf[32];
    token(p, sk__fmt_real(buf, x));
}

static void integer(packer *p, long x)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%ld", x);
    token(p, buf);
}

static void string(packer *p, const char *s)
{
    char buf[64];
    size_t n = strlen(s) > 40 ? 40 : strlen(s);
    snprintf(buf, sizeof buf, "%zuH%.*s", n, (int)n, s);
    token(p, buf);
}

sk_status sk_export_bspline_iges(const char *path, const sk_bspline_surface *s,
                                 const sk_export_opts *opts, sk_export_stats *stats, sk_error *err)
{
    if (!path || !s)
        return sk__fail(err, SK_ERR_ARG, "sk_export_bspline_iges: NULL argument");
    double maxc = 0;
    for (size_t i = 0; i < 3 * s->nu * s->nv; ++i) {
        if (!isfinite(s->points[i]))
            return sk__fail(err, SK_ERR_ARG, "the B-spline surface has a coordinate that is not "
                            "finite");
        maxc = fmax(maxc, fabs(s->points[i]));
    }
    if (s->nu <= (size_t)s->degree_u || s->nv <= (size_t)s->degree_v)
        return sk__fail(err, SK_ERR_ARG, "the B-spline surface is malformed (grid %zu x %zu, "
                        "degrees %d x %d)", s->nu, s->nv, s->degree_u, s->degree_v);
    const sk__unit *unit = sk__unit_lookup(opts ? opts->units : NULL);
    if (!unit)
        return sk__fail(err, SK_ERR_ARG, "unknown unit '%s'", opts->units);
    const char *name = opts && opts->name ? opts->name : "surfkit";
    char when[32], stamp[32], file_name[48], version[48];
    sk__export_time(opts, when);
    snprintf(stamp, sizeof stamp, "%.4s%.2s%.2s.%.2s%.2s%.2s", when, when + 5, when + 8, when + 11,
             when + 14, when + 17); /* IGES dates: YYYYMMDD.HHNNSS */
    snprintf(file_name, sizeof file_name, "%s", sk__basename(path));
    snprintf(version, sizeof version, "surfkit %s", sk_version());

    sk__out o = {0}, d = {0}, pd = {0};
    record(&o, "surfkit: B-spline fit of a disk as IGES entity 128", 'S', 1);
    packer g = {.b = &o, .section = 'G', .width = 72};
    token(&g, "1H,");
    token(&g, "1H;");
    string(&g, name);
    string(&g, file_name);
    string(&g, "surfkit");
    string(&g, version);
    integer(&g, 32);
    integer(&g, 38);
    integer(&g, 6);
    integer(&g, 308);
    integer(&g, 15);
    string(&g, name);
    real(&g, 1.0);
    integer(&g, unit->iges_flag);
    string(&g, unit->iges_name);
    integer(&g, 1);
    real(&g, 1.0);
    string(&g, stamp);
    real(&g, fmax(1e-7, 1e-9 * maxc)); /* minimum resolution, as the patch writer's */
    real(&g, maxc);
    string(&g, "surfkit");
    string(&g, "surfkit");
    integer(&g, 11); /* version 5.3 */
    integer(&g, 0);
    string(&g, stamp);
    finish(&g);

    /* entity 128, DE pointer 1 */
    packer p = {.b = &pd, .section = 'P', .width = 64, .de = 1};
    integer(&p, 128);
    integer(&p, (long)s->nu - 1); /* K1: upper index of the u sum */
    integer(&p, (long)s->nv - 1); /* K2 */
    integer(&p, s->degree_u);     /* M1 */
    integer(&p, s->degree_v);     /* M2 */
    integer(&p, 0);               /* PROP1: not closed in u */
    integer(&p, 0);               /* PROP2: not closed in v */
    integer(&p, 1);               /* PROP3: polynomial */
    integer(&p, 0);               /* PROP4: not periodic in u */
    integer(&p, 0);               /* PROP5: not periodic in v */
    for (size_t k = 0; k < s->nu + (size_t)s->degree_u + 1; ++k)
        real(&p, s->knots_u[k]);
    for (size_t k = 0; k < s->nv + (size_t)s->degree_v + 1; ++k)
        real(&p, s->knots_v[k]);
    for (size_t k = 0; k < s->nu * s->nv; ++k)
        real(&p, 1.0);
    for (size_t k = 0; k < 3 * s->nu * s->nv; ++k) /* point (i, j) at i + nu j: u fastest */
        real(&p, s->points[k]);
    real(&p, 0.0);
    real(&p, 1.0);
    real(&p, 0.0);
    real(&p, 1.0);
    finish(&p);
    char l1[96], l2[96];
    snprintf(l1, sizeof l1, "%8d%8d%8d%8d%8d%8d%8d%8d%8s", 128, 1, 0, 0, 0, 0, 0, 0, "00000000");
    snprintf(l2, sizeof l2, "%8d%8d%8d%8zu%8d%8s%8s%8s%8d", 128, 0, 0, p.seq, 0, "", "", "", 0);
    record(&d, l1, 'D', 1);
    record(&d, l2, 'D', 2);

    sk__out_bytes(&o, d.buf ? d.buf : "", d.len);
    sk__out_bytes(&o, pd.buf ? pd.buf : "", pd.len);
    char term[64];
    snprintf(term, sizeof term, "S%07dG%07zuD%07dP%07zu", 1, g.seq, 2, p.seq);
    record(&o, term, 'T', 1);
    if (d.failed || pd.failed)
        o.failed = SK_ERR_NOMEM;
    sk_status st = sk__out_write_file(&o, path, err);
    if (!st && stats) {
        memset(stats, 0, sizeof *stats);
        stats->faces = 1;
        stats->bytes = o.len;
    }
    sk__out_free(&o);
    sk__out_free(&d);
    sk__out_free(&pd);
    return st;
}
