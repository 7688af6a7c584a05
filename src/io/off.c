/* OFF (Geomview Object File Format), ascii: [ST][C][N]OFF headers, polygon faces.
 *
 * Accepted: '#' comments anywhere, the header keyword and the counts on one line or on separate
 * lines, a missing header keyword (counts first), an edge count that is ignored or absent, face
 * colours after the indices (ignored), vertex colours (ignored) when the header has C, per-vertex
 * normals (N) and texture coordinates (ST, the last two values of a vertex line). One vertex and
 * one face per line. Anything after the last declared face other than comments is an error: it
 * means the counts in the header are wrong. */
#include "io/formats.h"
#include "io/lexer.h"

#include <stdlib.h>

/* Minimal bytes of one vertex line ("0 0 0\n") and of one face line ("0\n", which is an error
 * but must be reported as such, not as a wrong count). */
#define OFF_MIN_VERTEX_BYTES 6
#define OFF_MIN_FACE_BYTES 2
/* Values kept of one vertex line: x y z nx ny nz and a few more */
#define OFF_MAX_KEPT 8

static void skip_space_comments(sk__text *t)
{
    for (;;) {
        sk__skip_space(t);
        if (t->p < t->end && *t->p == '#')
            sk__skip_line(t);
        else
            break;
    }
}

/* A value ends at a space, a line end, a comment or the end of the input. */
static bool ends_value(const char *p, const char *end)
{
    return p >= end || sk__is_space(*p) || *p == '#';
}

static bool at_line_end(const sk__text *t)
{
    return sk__at_eol(t) || *t->p == '#';
}

typedef struct off_header {
    bool st, colour, normals;
} off_header;

static sk_status parse_header(sk__text *t, off_header *h)
{
    memset(h, 0, sizeof *h);
    skip_space_comments(t);
    if (sk__at_eof(t))
        return sk__text_error(t, "empty file: expected an OFF header");
    char tok[48];
    size_t n = sk__token_len(t->p, t->end);
    if (sk__is_digit(*t->p) && !(n >= 3 && memcmp(t->p + n - 3, "OFF", 3) == 0))
        return SK_OK; /* no keyword: the counts come first */
    const char *s = t->p, *e = t->p + n;
    if (e - s >= 2 && s[0] == 'S' && s[1] == 'T') {
        h->st = true;
        s += 2;
    }
    if (s < e && *s == 'C') {
        h->colour = true;
        ++s;
    }
    if (s < e && *s == 'N') {
        h->normals = true;
        ++s;
    }
    if (s < e && (*s == '4' || *s == 'n'))
        return sk__text_error(t, "'%s': only 3-dimensional OFF files are supported",
                              sk__token_str(t->p, t->end, tok, sizeof tok));
    if (e - s != 3 || memcmp(s, "OFF", 3) != 0)
        return sk__text_error(t, "expected an OFF header keyword (OFF, COFF, NOFF, STOFF...), "
                                 "found '%s'", sk__token_str(t->p, t->end, tok, sizeof tok));
    t->p = e;
    sk__skip_blank(t);
    if (sk__at_keyword(t, "BINARY"))
        return sk__text_error(t, "binary OFF files are not supported");
    return SK_OK;
}

/* Reads the counts line: vertices faces [edges]. */
static sk_status parse_counts(sk__text *t, uint64_t *nv, uint64_t *nf, size_t *line)
{
    char tok[48];
    skip_space_comments(t);
    *line = t->line;
    if (sk__at_eof(t))
        return sk__text_error(t, "the file ends before the vertex and face counts");
    uint64_t c[3];
    int k = 0;
    while (k < 3 && !at_line_end(t)) {
        const char *p = t->p;
        if (!sk__parse_uint(&p, t->end, &c[k]) || !ends_value(p, t->end))
            return sk__text_error(t, "expected the vertex, face and edge counts, found '%s'",
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        t->p = p;
        ++k;
        sk__skip_blank(t);
    }
    if (k < 2)
        return sk__text_error(t, "expected the vertex, face and edge counts on one line");
    if (!at_line_end(t))
        return sk__text_error(t, "unexpected '%s' after the counts",
                              sk__token_str(t->p, t->end, tok, sizeof tok));
    sk__skip_line(t);
    *nv = c[0];
    *nf = c[1];
    return SK_OK;
}

/* The declared counts against the bytes that follow, before anything is allocated. */
static sk_status check_counts(sk__text *t, uint64_t nv, uint64_t nf, size_t counts_line)
{
    uint64_t left = (uint64_t)(t->end - t->p);
    if (nv > left || nf > left ||
        nv * OFF_MIN_VERTEX_BYTES + nf * OFF_MIN_FACE_BYTES > left + 1) {
        t->line = counts_line;
        return sk__text_error(t, "the header declares %llu vertices and %llu faces but only "
                                 "%llu bytes follow", (unsigned long long)nv,
                              (unsigned long long)nf, (unsigned long long)left);
    }
    if (nv >= UINT32_MAX || nf >= UINT32_MAX) {
        t->line = counts_line;
        return sk__text_error(t, "too many elements for 32-bit indices");
    }
    return SK_OK;
}

/* Vertex line v of nv: x y z [nx ny nz] [colour...] [s t], into s. */
static sk_status read_vertex(sk__text *t, sk_soup *s, const off_header *h, size_t v, uint64_t nv,
                             const char *name, sk_error *err)
{
    char tok[48];
    const int want = 3 + (h->normals ? 3 : 0) + (h->st ? 2 : 0);
    skip_space_comments(t);
    if (sk__at_eof(t))
        return sk__text_error(t, "the file ends after %zu of %llu vertices", v,
                              (unsigned long long)nv);
    double val[OFF_MAX_KEPT], last[2] = {0, 0};
    int count = 0;
    while (!at_line_end(t)) {
        double d = 0;
        const char *p = t->p;
        sk__num r = sk__parse_double(&p, t->end, &d);
        if (r == SK__NUM_NONFINITE)
            return sk__text_error(t, "vertex %zu has a non-finite value '%s'", v,
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        if (r != SK__NUM_OK || !ends_value(p, t->end))
            return sk__text_error(t, "vertex %zu: '%s' is not a number", v,
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        t->p = p;
        if (count < OFF_MAX_KEPT)
            val[count] = d;
        last[0] = last[1];
        last[1] = d;
        ++count;
        sk__skip_blank(t);
    }
    if (count < want || (count > want && !h->colour))
        return sk__text_error(t, "vertex %zu has %d values but the header asks for %d%s", v,
                              count, want,
                              count > want ? " (is the vertex count in the header right?)" : "");
    sk__skip_line(t);
    sk_status st = sk_soup_push_vertex(s, val, h->normals ? val + 3 : NULL, h->st ? last : NULL);
    return st ? sk__fail(err, st, "%s: out of memory", name) : SK_OK;
}

/* Face line f: n i1 .. in [colour...], into s; *idx (capacity *cap) is the reused index buffer. */
static sk_status read_face(sk__text *t, sk_soup *s, size_t f, uint64_t nf, uint64_t nv,
                           uint32_t **idx, size_t *cap, const char *name, sk_error *err)
{
    char tok[48];
    skip_space_comments(t);
    if (sk__at_eof(t))
        return sk__text_error(t, "the file ends after %zu of %llu faces", f,
                              (unsigned long long)nf);
    uint64_t n;
    const char *p = t->p;
    if (!sk__parse_uint(&p, t->end, &n) || !ends_value(p, t->end))
        return sk__text_error(t, "face %zu: expected the number of its vertices, found '%s'%s",
                              f, sk__token_str(t->p, t->end, tok, sizeof tok),
                              f == 0 ? " (is the vertex count in the header right?)" : "");
    t->p = p;
    if (n < 3)
        return sk__text_error(t, "face %zu has only %llu vertices%s", f, (unsigned long long)n,
                              f == 0 ? " (is the vertex count in the header right?)" : "");
    if (n > (uint64_t)(t->end - t->p) / 2)
        return sk__text_error(t, "face %zu declares %llu vertices, more than the file holds", f,
                              (unsigned long long)n);
    if (n > *cap) {
        size_t c = *cap ? *cap : 16;
        while (c < n)
            c *= 2;
        uint32_t *ni = sk__realloc_array(*idx, c, sizeof *ni);
        if (!ni)
            return sk__fail(err, SK_ERR_NOMEM, "%s: out of memory", name);
        *idx = ni;
        *cap = c;
    }
    for (uint64_t k = 0; k < n; ++k) {
        sk__skip_blank(t);
        if (at_line_end(t))
            return sk__text_error(t, "face %zu declares %llu vertices but lists %llu", f,
                                  (unsigned long long)n, (unsigned long long)k);
        uint64_t i;
        p = t->p;
        if (*p == '-')
            return sk__text_error(t, "face %zu has a negative index '%s'", f,
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        if (!sk__parse_uint(&p, t->end, &i) || !ends_value(p, t->end))
            return sk__text_error(t, "face %zu: '%s' is not a vertex index", f,
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        if (i >= nv)
            return sk__text_error(t, "face %zu has index %llu but the file has %llu vertices",
                                  f, (unsigned long long)i, (unsigned long long)nv);
        t->p = p;
        (*idx)[k] = (uint32_t)i;
    }
    sk__skip_line(t); /* face colour values, if any, are ignored */
    sk_status st = sk_soup_push_face(s, *idx, (size_t)n);
    return st ? sk__fail(err, st, "%s: out of memory", name) : SK_OK;
}

sk_status sk__read_off(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err)
{
    *out = NULL;
    sk__text t;
    sk__text_init(&t, data, size, name, err);
    sk_soup *s = NULL;
    uint32_t *idx = NULL;
    size_t idx_cap = 0;
    char tok[48];
    off_header h;
    uint64_t nv = 0, nf = 0;
    size_t counts_line = 1;
    sk_status st = parse_header(&t, &h);
    if (!st)
        st = parse_counts(&t, &nv, &nf, &counts_line);
    if (!st)
        st = check_counts(&t, nv, nf, counts_line);
    if (!st)
        st = sk_soup_create((size_t)nv, (size_t)nf, (size_t)nf * 3, h.normals, h.st, &s, err);
    if (st)
        return st;
    for (size_t v = 0; v < nv && !st; ++v)
        st = read_vertex(&t, s, &h, v, nv, name, err);
    for (size_t f = 0; f < nf && !st; ++f)
        st = read_face(&t, s, f, nf, nv, &idx, &idx_cap, name, err);
    if (!st) {
        skip_space_comments(&t);
        if (!sk__at_eof(&t))
            st = sk__text_error(&t, "unexpected '%s' after the last of %llu faces (are the counts "
                                    "in the header right?)",
                                sk__token_str(t.p, t.end, tok, sizeof tok), (unsigned long long)nf);
    }
    sk__free(idx);
    if (st) {
        sk_soup_destroy(&s);
        return st;
    }
    *out = s;
    return SK_OK;
}

/* A vertex line: x y z [nx ny nz] [s t]. */
typedef struct vertex_rows {
    const sk_soup *s;
    bool normals, uvs;
} vertex_rows;

static void put_values(sk__out *o, const double *x, int n)
{
    for (int k = 0; k < n; ++k) {
        sk__out_char(o, ' ');
        sk__out_double(o, x[k]);
    }
}

static void vertex_row(sk__out *o, size_t v, const void *ctx)
{
    const vertex_rows *r = ctx;
    sk__out_double(o, r->s->positions[3 * v]);
    put_values(o, r->s->positions + 3 * v + 1, 2);
    if (r->normals)
        put_values(o, r->s->normals + 3 * v, 3);
    if (r->uvs)
        put_values(o, r->s->uvs + 2 * v, 2);
    sk__out_char(o, '\n');
}

/* A face line: n i0 i1 ... (0-based). */
static void face_row(sk__out *o, size_t f, const void *ctx)
{
    const sk_soup *s = ctx;
    uint32_t a = s->face_offsets[f], b = s->face_offsets[f + 1];
    sk__out_uint(o, b - a);
    for (uint32_t k = a; k < b; ++k) {
        sk__out_char(o, ' ');
        sk__out_uint(o, s->face_indices[k]);
    }
    sk__out_char(o, '\n');
}

void sk__write_off(sk__out *o, const sk_soup *s, bool normals, bool uvs)
{
    sk__out_str(o, uvs ? "ST" : "");
    sk__out_str(o, normals ? "NOFF\n" : "OFF\n");
    sk__out_uint(o, s->num_vertices);
    sk__out_char(o, ' ');
    sk__out_uint(o, s->num_faces);
    sk__out_str(o, " 0\n");
    vertex_rows vr = {s, normals, uvs};
    sk__out_rows(o, s->num_vertices, vertex_row, &vr);
    sk__out_rows(o, s->num_faces, face_row, s);
}
