/* STL (stereolithography), ascii and binary.
 *
 * STL stores every triangle with its own three corners. Reading rebuilds the connectivity by
 * merging corners with exactly equal positions (a hash of the coordinates; -0 equals +0); vertex
 * numbers follow the order of first appearance. Facet normals are ignored. Ascii facets with more
 * than three vertices are read as polygons.
 *
 * A file is binary when its size is 84 + 50 n with n the triangle count at byte 80 (this holds
 * for binary files whose 80-byte header begins with "solid"); otherwise it is ascii when it
 * begins with "solid" and has no NUL byte in its first 512 bytes, else binary (and then it must
 * hold the declared triangles).
 *
 * Writing: polygons are fan-triangulated, facet normals computed from the corners (zero for a
 * degenerate triangle). Binary coordinates are float32 (STL has no other type); ascii ones are
 * written with enough digits to read back the same doubles. */
#include "io/formats.h"
#include "io/lexer.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#define STL_HEADER 80
#define STL_RECORD 50

bool sk__stl_is_binary_size(const void *data, size_t size)
{
    if (size < STL_HEADER + 4)
        return false;
    uint64_t n = sk__get_le32((const unsigned char *)data + STL_HEADER);
    return (uint64_t)size == STL_HEADER + 4 + STL_RECORD * n;
}

/* ---------------------------------------------------------------------------------------------
 * Vertex merging
 * ------------------------------------------------------------------------------------------- */

typedef struct vmap {
    uint32_t *slots; /* vertex index + 1, 0 = empty */
    size_t cap;      /* power of two */
    sk_soup *s;
} vmap;

static uint64_t hash_pos(const double *p)
{
    uint64_t h = 0x9e3779b97f4a7c15u;
    for (int k = 0; k < 3; ++k) {
        uint64_t b;
        memcpy(&b, &p[k], sizeof b);
        h ^= b + 0x9e3779b97f4a7c15u + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdu;
        h ^= h >> 33;
    }
    return h;
}

static bool vmap_init(vmap *m, sk_soup *s, size_t expect)
{
    size_t cap = 64;
    while (cap < 2 * expect)
        cap *= 2;
    m->slots = sk__calloc_array(cap, sizeof *m->slots);
    m->cap = cap;
    m->s = s;
    return m->slots != NULL;
}

static bool vmap_grow(vmap *m)
{
    size_t cap = m->cap * 2;
    uint32_t *slots = sk__calloc_array(cap, sizeof *slots);
    if (!slots)
        return false;
    for (size_t v = 0; v < m->s->num_vertices; ++v) {
        size_t i = (size_t)hash_pos(m->s->positions + 3 * v) & (cap - 1);
        while (slots[i])
            i = (i + 1) & (cap - 1);
        slots[i] = (uint32_t)v + 1;
    }
    sk__free(m->slots);
    m->slots = slots;
    m->cap = cap;
    return true;
}

/* Index of the vertex at position p, adding it if new; SK_INVALID on allocation failure. */
static uint32_t vmap_get(vmap *m, const double *pin)
{
    double p[3] = {pin[0] + 0.0, pin[1] + 0.0, pin[2] + 0.0}; /* -0 becomes +0 */
    size_t i = (size_t)hash_pos(p) & (m->cap - 1);
    while (m->slots[i]) {
        uint32_t v = m->slots[i] - 1;
        const double *q = m->s->positions + 3 * (size_t)v;
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2])
            return v;
        i = (i + 1) & (m->cap - 1);
    }
    if (m->s->num_vertices >= UINT32_MAX - 2 || sk_soup_push_vertex(m->s, p, NULL, NULL))
        return SK_INVALID;
    uint32_t v = (uint32_t)(m->s->num_vertices - 1);
    m->slots[i] = v + 1;
    if (2 * m->s->num_vertices > m->cap && !vmap_grow(m))
        return SK_INVALID;
    return v;
}

/* ---------------------------------------------------------------------------------------------
 * Binary
 * ------------------------------------------------------------------------------------------- */

static double get_f32(const unsigned char *b)
{
    uint32_t u = sk__get_le32(b);
    float f;
    memcpy(&f, &u, sizeof f);
    return (double)f;
}

static sk_status read_binary(const unsigned char *d, size_t size, const char *name, sk_soup **out,
                             sk_error *err)
{
    if (size < STL_HEADER + 4)
        return sk__bin_error(err, name, size, "the file ends inside the 84-byte binary STL "
                             "header");
    uint64_t n = sk__get_le32(d + STL_HEADER);
    if (n > (size - STL_HEADER - 4) / STL_RECORD)
        return sk__bin_error(err, name, STL_HEADER, "the header declares %llu triangles "
                             "(%llu bytes) but the file has %zu bytes", (unsigned long long)n,
                             (unsigned long long)(STL_HEADER + 4 + STL_RECORD * n), size);
    sk_soup *s = NULL;
    vmap m = {0};
    sk_status st = sk_soup_create((size_t)n / 2 + 3, (size_t)n, 3 * (size_t)n, false, false, &s,
                                  err);
    if (st)
        return st;
    if (!vmap_init(&m, s, (size_t)n / 2 + 3))
        goto nomem;
    for (uint64_t t = 0; t < n; ++t) {
        size_t off = STL_HEADER + 4 + (size_t)t * STL_RECORD;
        const unsigned char *r = d + off + 12; /* skip the facet normal */
        uint32_t idx[3];
        for (int c = 0; c < 3; ++c) {
            double p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = get_f32(r + 12 * c + 4 * k);
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                st = sk__bin_error(err, name, off + 12 + 12 * (size_t)c,
                                   "triangle %llu has a non-finite coordinate",
                                   (unsigned long long)t);
                goto fail;
            }
            idx[c] = vmap_get(&m, p);
            if (idx[c] == SK_INVALID)
                goto nomem;
        }
        if (sk_soup_push_face(s, idx, 3))
            goto nomem;
    }
    sk__free(m.slots);
    *out = s;
    return SK_OK;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "%s: out of memory", name);
fail:
    sk__free(m.slots);
    sk_soup_destroy(&s);
    return st;
}

/* ---------------------------------------------------------------------------------------------
 * Ascii
 * ------------------------------------------------------------------------------------------- */

static sk_status expect(sk__text *t, const char *kw, const char *where)
{
    char tok[48];
    sk__skip_space(t);
    if (sk__at_eof(t))
        return sk__text_error(t, "the file ends %s (expected '%s')", where, kw);
    if (!sk__at_keyword(t, kw))
        return sk__text_error(t, "expected '%s' %s, found '%s'", kw, where,
                              sk__token_str(t->p, t->end, tok, sizeof tok));
    t->p += strlen(kw);
    return SK_OK;
}

/* Three numbers; non-finite values are an error only when `strict`. */
static sk_status read_xyz(sk__text *t, double *p, bool strict, size_t facet)
{
    char tok[48];
    for (int k = 0; k < 3; ++k) {
        sk__skip_blank(t);
        const char *q = t->p;
        sk__num r = sk__parse_double(&q, t->end, &p[k]);
        if (r == SK__NUM_NONFINITE && !strict) {
            p[k] = 0;
        } else if (r == SK__NUM_NONFINITE) {
            return sk__text_error(t, "facet %zu has a non-finite coordinate '%s'", facet,
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        } else if (r != SK__NUM_OK || !(q >= t->end || sk__is_space(*q))) {
            return sk__text_error(t, "facet %zu: expected a number, found '%s'", facet,
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        }
        t->p = q;
    }
    return SK_OK;
}

static sk_status read_ascii(const void *data, size_t size, const char *name, sk_soup **out,
                            sk_error *err)
{
    sk__text t;
    sk__text_init(&t, data, size, name, err);
    sk_soup *s = NULL;
    vmap m = {0};
    uint32_t *idx = NULL;
    size_t idx_cap = 0;
    char tok[48];
    /* each facet takes well over 100 bytes; this is only a reservation */
    size_t est = size / 200 + 1;
    sk_status st = sk_soup_create(est, est, 3 * est, false, false, &s, err);
    if (st)
        return st;
    if (!vmap_init(&m, s, est))
        goto nomem;
    st = expect(&t, "solid", "at the start");
    if (st)
        goto fail;
    sk__skip_line(&t); /* the solid's name */
    size_t facet = 0;
    for (;;) {
        sk__skip_space(&t);
        if (sk__at_eof(&t)) {
            st = sk__text_error(&t, "the file ends without 'endsolid'");
            goto fail;
        }
        if (sk__at_keyword(&t, "endsolid")) {
            sk__skip_line(&t);
            sk__skip_space(&t);
            if (sk__at_eof(&t))
                break;
            if ((st = expect(&t, "solid", "after 'endsolid'")))
                goto fail;
            sk__skip_line(&t);
            continue;
        }
        if (!sk__at_keyword(&t, "facet")) {
            st = sk__text_error(&t, "expected 'facet' or 'endsolid', found '%s'",
                                sk__token_str(t.p, t.end, tok, sizeof tok));
            goto fail;
        }
        t.p += 5;
        double p[3];
        if ((st = expect(&t, "normal", "after 'facet'")) || (st = read_xyz(&t, p, false, facet)) ||
            (st = expect(&t, "outer", "before a facet's vertices")) ||
            (st = expect(&t, "loop", "after 'outer'")))
            goto fail;
        size_t k = 0;
        for (;;) {
            sk__skip_space(&t);
            if (!sk__at_keyword(&t, "vertex"))
                break;
            t.p += 6;
            if ((st = read_xyz(&t, p, true, facet)))
                goto fail;
            if (k == idx_cap) {
                size_t cap = idx_cap ? 2 * idx_cap : 8;
                uint32_t *a = sk__realloc_array(idx, cap, sizeof *a);
                if (!a)
                    goto nomem;
                idx = a;
                idx_cap = cap;
            }
            idx[k] = vmap_get(&m, p);
            if (idx[k] == SK_INVALID)
                goto nomem;
            ++k;
        }
        if (k < 3) {
            st = sk__text_error(&t, "facet %zu has only %zu vertices", facet, k);
            goto fail;
        }
        if ((st = expect(&t, "endloop", "after a facet's vertices")) ||
            (st = expect(&t, "endfacet", "after 'endloop'")))
            goto fail;
        if (sk_soup_push_face(s, idx, k))
            goto nomem;
        ++facet;
    }
    sk__free(idx);
    sk__free(m.slots);
    *out = s;
    return SK_OK;
nomem:
    st = sk__fail(err, SK_ERR_NOMEM, "%s: out of memory", name);
fail:
    sk__free(idx);
    sk__free(m.slots);
    sk_soup_destroy(&s);
    return st;
}

sk_status sk__read_stl(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err)
{
    *out = NULL;
    const char *p = data;
    if (sk__stl_is_binary_size(data, size))
        return read_binary(data, size, name, out, err);
    size_t i = 0;
    while (i < size && sk__is_space(p[i]))
        ++i;
    /* "solid" starts ascii files and some binary headers: a NUL byte early on (the triangle
     * count, zero coordinates, attribute bytes) tells a binary file that is not size-consistent */
    size_t scan = size < 512 ? size : 512;
    if (size - i >= 5 && memcmp(p + i, "solid", 5) == 0 && !memchr(p, '\0', scan))
        return read_ascii(data, size, name, out, err);
    if (size == 0)
        return sk__fail(err, SK_ERR_PARSE, "%s:1: empty file", name);
    return read_binary(data, size, name, out, err);
}

/* ---------------------------------------------------------------------------------------------
 * Writer
 * ------------------------------------------------------------------------------------------- */

static void facet_normal(const double *a, const double *b, const double *c, double n[3])
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0 && isfinite(l)) {
        n[0] /= l;
        n[1] /= l;
        n[2] /= l;
    } else {
        n[0] = n[1] = n[2] = 0;
    }
}

static void put_f32(unsigned char *q, double d)
{
    /* out-of-range conversions are undefined behaviour: saturate to +-inf explicitly */
    float f = d > FLT_MAX ? INFINITY : d < -FLT_MAX ? -INFINITY : (float)d;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    sk__put_le32(q, u);
}

static void put_xyz(sk__out *o, const char *kw, const double *x)
{
    sk__out_str(o, kw);
    for (int k = 0; k < 3; ++k) {
        sk__out_char(o, ' ');
        sk__out_double(o, x[k]);
    }
    sk__out_char(o, '\n');
}

/* Calls fn for each facet of face f (a fan from its first corner) with its normal and corners. */
typedef void (*facet_fn)(sk__out *o, const double *n, const double *p0, const double *p1,
                         const double *p2);

static void face_facets(sk__out *o, const sk_soup *s, size_t f, facet_fn fn)
{
    uint32_t a = s->face_offsets[f], b = s->face_offsets[f + 1];
    const double *p0 = s->positions + 3 * (size_t)s->face_indices[a];
    for (uint32_t k = a + 1; k + 1 < b && !o->failed; ++k) {
        const double *p1 = s->positions + 3 * (size_t)s->face_indices[k];
        const double *p2 = s->positions + 3 * (size_t)s->face_indices[k + 1];
        double n[3];
        facet_normal(p0, p1, p2, n);
        fn(o, n, p0, p1, p2);
    }
}

static void ascii_facet(sk__out *o, const double *n, const double *p0, const double *p1,
                        const double *p2)
{
    put_xyz(o, "  facet normal", n);
    sk__out_str(o, "    outer loop\n");
    put_xyz(o, "      vertex", p0);
    put_xyz(o, "      vertex", p1);
    put_xyz(o, "      vertex", p2);
    sk__out_str(o, "    endloop\n  endfacet\n");
}

/* The facets of face f as text (a row of sk__out_rows). */
static void ascii_face_row(sk__out *o, size_t f, const void *ctx)
{
    face_facets(o, ctx, f, ascii_facet);
}

static void binary_facet(sk__out *o, const double *n, const double *p0, const double *p1,
                         const double *p2)
{
    if (!sk__out_room(o, STL_RECORD))
        return;
    unsigned char *q = (unsigned char *)o->buf + o->len;
    const double *v[4] = {n, p0, p1, p2};
    for (int r = 0; r < 4; ++r)
        for (int j = 0; j < 3; ++j)
            put_f32(q + 12 * r + 4 * j, v[r][j]);
    q[48] = q[49] = 0;
    o->len += STL_RECORD;
}

static void write_binary(sk__out *o, const sk_soup *s, uint64_t ntri)
{
    char header[STL_HEADER];
    memset(header, ' ', sizeof header);
    memcpy(header, "binary STL written by surfkit", 29);
    sk__out_bytes(o, header, sizeof header);
    unsigned char c[4];
    sk__put_le32(c, (uint32_t)ntri);
    sk__out_bytes(o, c, 4);
    for (size_t f = 0; f < s->num_faces && !o->failed; ++f)
        face_facets(o, s, f, binary_facet);
}

void sk__write_stl(sk__out *o, const sk_soup *s, bool ascii)
{
    if (!ascii) {
        uint64_t ntri = 0;
        for (size_t f = 0; f < s->num_faces; ++f)
            ntri += sk_soup_face_size(s, f) - 2;
        write_binary(o, s, ntri);
        return;
    }
    sk__out_str(o, "solid surfkit\n");
    sk__out_rows(o, s->num_faces, ascii_face_row, s);
    sk__out_str(o, "endsolid surfkit\n");
}
