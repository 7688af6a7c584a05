/* PLY (Stanford polygon file format): ascii, binary_little_endian, binary_big_endian.
 *
 * Reading: element `vertex` with x y z, optional nx ny nz, optional texture coordinates (u v, s t
 * or texture_u texture_v), any scalar type; element `face` with a list `vertex_indices` (or
 * `vertex_index`) of any integer count and index type. Other properties, list properties and
 * elements are skipped. Element order is free: face indices are checked against the declared
 * vertex count. Trailing bytes after the last element of a binary file are ignored.
 *
 * Per-corner uvs: the face list `texcoord` (MeshLab's convention: u v for every corner, any
 * scalar type) is read into the soup's corner_uv, one wedge per corner; an empty list means none
 * for that face. Blender's PLY importer reads only per-vertex s t / u v: for it write the
 * seam-split mesh (surfkit param --split-seams).
 *
 * Writing: float64 x y z [nx ny nz] [s t] (the texture coordinate names Blender and MeshLab
 * read; they ignore u v); faces as `list uchar int vertex_indices` (uint count when a face has
 * more than 255 vertices, uint indices beyond 2^31 vertices), then with per-corner uvs
 * `list uchar double texcoord` (uint count beyond 127 vertices). */
#include "io/formats.h"
#include "io/lexer.h"

#include <math.h>
#include <stdlib.h>

#define PLY_MAX_ELEMENTS 32
#define PLY_MAX_PROPERTIES 64
#define PLY_NAME 48

typedef enum { T_NONE = 0, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

static const int type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

typedef enum {
    R_NONE = 0, R_X, R_Y, R_Z, R_NX, R_NY, R_NZ, R_U, R_V, R_INDICES, R_TEXCOORD
} ply_role;

typedef struct ply_prop {
    ply_type type;       /* scalar type, or item type of a list */
    ply_type count_type; /* T_NONE for a scalar */
    ply_role role;
    char name[PLY_NAME];
} ply_prop;

typedef enum { E_OTHER, E_VERTEX, E_FACE } ply_kind;

typedef struct ply_elem {
    char name[PLY_NAME];
    uint64_t count;
    ply_kind kind;
    int nprops;
    ply_prop props[PLY_MAX_PROPERTIES];
} ply_elem;

typedef enum { F_ASCII, F_LE, F_BE } ply_format;

typedef struct ply_header {
    ply_format format;
    int nelems;
    ply_elem elems[PLY_MAX_ELEMENTS];
    bool has_normals, has_uvs, has_texcoord;
    uint64_t nv, nf;
} ply_header;

static ply_type parse_type(const char *s, size_t n)
{
    static const struct {
        const char *name;
        ply_type type;
    } names[] = {{"char", T_I8},     {"uchar", T_U8},    {"short", T_I16},   {"ushort", T_U16},
                 {"int", T_I32},     {"uint", T_U32},    {"float", T_F32},   {"double", T_F64},
                 {"int8", T_I8},     {"uint8", T_U8},    {"int16", T_I16},   {"uint16", T_U16},
                 {"int32", T_I32},   {"uint32", T_U32},  {"float32", T_F32}, {"float64", T_F64}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (strlen(names[i].name) == n && memcmp(names[i].name, s, n) == 0)
            return names[i].type;
    return T_NONE;
}

static bool is_int_type(ply_type t) { return t != T_NONE && t != T_F32 && t != T_F64; }

/* Reads the next token of the current header line into buf; false at the end of the line. */
static bool header_token(sk__text *t, char *buf, size_t size, size_t *len)
{
    sk__skip_blank(t);
    if (sk__at_eol(t))
        return false;
    size_t n = sk__token_len(t->p, t->end);
    *len = n;
    size_t c = n < size - 1 ? n : size - 1;
    for (size_t i = 0; i < c; ++i) {
        unsigned char ch = (unsigned char)t->p[i];
        buf[i] = (ch >= 32 && ch < 127) ? (char)ch : '?'; /* printable in messages */
    }
    buf[c] = '\0';
    t->p += n;
    return true;
}

static ply_role vertex_role(const char *n)
{
    static const struct {
        const char *name;
        ply_role role;
    } roles[] = {{"x", R_X},         {"y", R_Y},         {"z", R_Z},         {"nx", R_NX},
                 {"ny", R_NY},       {"nz", R_NZ},       {"u", R_U},         {"v", R_V},
                 {"s", R_U},         {"t", R_V},         {"texture_u", R_U}, {"texture_v", R_V},
                 {"texture_s", R_U}, {"texture_t", R_V}};
    for (size_t i = 0; i < sizeof roles / sizeof roles[0]; ++i)
        if (!strcmp(roles[i].name, n))
            return roles[i].role;
    return R_NONE;
}

static sk_status parse_header(sk__text *t, ply_header *h)
{
    char tok[PLY_NAME], tok2[PLY_NAME];
    size_t len;
    if (!sk__at_keyword(t, "ply"))
        return sk__text_error(t, "not a PLY file: the first line is not 'ply'");
    sk__skip_line(t);
    bool have_format = false;
    for (;;) {
        if (sk__at_eof(t))
            return sk__text_error(t, "the file ends inside the header (no end_header)");
        if (!header_token(t, tok, sizeof tok, &len)) {
            sk__skip_line(t); /* blank line */
            continue;
        }
        if (!strcmp(tok, "comment") || !strcmp(tok, "obj_info")) {
            sk__skip_line(t);
            continue;
        }
        if (!strcmp(tok, "end_header")) {
            /* binary data starts right after this line's end */
            const char *p = t->p;
            while (p < t->end && sk__is_blank(*p))
                ++p;
            if (p < t->end && !sk__is_eol(*p))
                return sk__text_error(t, "unexpected text after end_header");
            t->p = p;
            if (t->p < t->end && *t->p == '\r') {
                ++t->p;
                if (t->p < t->end && *t->p == '\n')
                    ++t->p;
                ++t->line;
            } else if (t->p < t->end) {
                ++t->p;
                ++t->line;
            }
            break;
        }
        if (!strcmp(tok, "format")) {
            if (!header_token(t, tok, sizeof tok, &len))
                return sk__text_error(t, "format line without a format");
            if (!strcmp(tok, "ascii"))
                h->format = F_ASCII;
            else if (!strcmp(tok, "binary_little_endian"))
                h->format = F_LE;
            else if (!strcmp(tok, "binary_big_endian"))
                h->format = F_BE;
            else
                return sk__text_error(t, "unknown PLY format '%s'", tok);
            if (header_token(t, tok, sizeof tok, &len) && strcmp(tok, "1.0") != 0)
                return sk__text_error(t, "unsupported PLY version '%s'", tok);
            have_format = true;
        } else if (!strcmp(tok, "element")) {
            if (h->nelems == PLY_MAX_ELEMENTS)
                return sk__text_error(t, "more than %d elements", PLY_MAX_ELEMENTS);
            ply_elem *e = &h->elems[h->nelems];
            memset(e, 0, sizeof *e);
            if (!header_token(t, e->name, sizeof e->name, &len))
                return sk__text_error(t, "element without a name");
            sk__skip_blank(t);
            const char *p = t->p;
            if (!sk__parse_uint(&p, t->end, &e->count) || !(p >= t->end || sk__is_space(*p)))
                return sk__text_error(t, "element '%s' without a valid count", e->name);
            t->p = p;
            e->kind = !strcmp(e->name, "vertex") ? E_VERTEX
                      : !strcmp(e->name, "face") ? E_FACE : E_OTHER;
            for (int i = 0; i < h->nelems; ++i)
                if (e->kind != E_OTHER && h->elems[i].kind == e->kind)
                    return sk__text_error(t, "a second '%s' element", e->name);
            ++h->nelems;
        } else if (!strcmp(tok, "property")) {
            if (h->nelems == 0)
                return sk__text_error(t, "property before any element");
            ply_elem *e = &h->elems[h->nelems - 1];
            if (e->nprops == PLY_MAX_PROPERTIES)
                return sk__text_error(t, "element '%s' has more than %d properties", e->name,
                                      PLY_MAX_PROPERTIES);
            ply_prop *pr = &e->props[e->nprops];
            memset(pr, 0, sizeof *pr);
            if (!header_token(t, tok, sizeof tok, &len))
                return sk__text_error(t, "property without a type");
            bool list = !strcmp(tok, "list");
            if (list) {
                if (!header_token(t, tok, sizeof tok, &len))
                    return sk__text_error(t, "list property without a count type");
                pr->count_type = parse_type(tok, len);
                if (!is_int_type(pr->count_type))
                    return sk__text_error(t, "list count type '%s' is not an integer type", tok);
                if (!header_token(t, tok, sizeof tok, &len))
                    return sk__text_error(t, "list property without an item type");
            }
            pr->type = parse_type(tok, len);
            if (pr->type == T_NONE)
                return sk__text_error(t, "unknown property type '%s'", tok);
            if (!header_token(t, tok2, sizeof tok2, &len))
                return sk__text_error(t, "property without a name");
            memcpy(pr->name, tok2, sizeof pr->name);
            if (e->kind == E_VERTEX && !list)
                pr->role = vertex_role(pr->name);
            if (e->kind == E_FACE && list &&
                (!strcmp(pr->name, "vertex_indices") || !strcmp(pr->name, "vertex_index"))) {
                for (int i = 0; i < e->nprops; ++i)
                    if (e->props[i].role == R_INDICES)
                        return sk__text_error(t, "face element has two vertex index lists");
                if (!is_int_type(pr->type))
                    return sk__text_error(t, "'%s' has a non-integer type", pr->name);
                pr->role = R_INDICES;
            }
            if (e->kind == E_FACE && list && !strcmp(pr->name, "texcoord"))
                pr->role = R_TEXCOORD; /* MeshLab: u v per corner */
            for (int i = 0; i < e->nprops; ++i)
                if (pr->role != R_NONE && e->props[i].role == pr->role)
                    return sk__text_error(t, "property '%s' repeats an earlier one", pr->name);
            ++e->nprops;
        } else {
            return sk__text_error(t, "unknown header line '%s'", tok);
        }
        sk__skip_blank(t);
        if (!sk__at_eol(t))
            return sk__text_error(t, "unexpected '%s' at the end of the header line",
                                  sk__token_str(t->p, t->end, tok, sizeof tok));
        sk__skip_line(t);
    }
    if (!have_format)
        return sk__text_error(t, "the header has no format line");
    for (int i = 0; i < h->nelems; ++i) {
        ply_elem *e = &h->elems[i];
        int seen[R_TEXCOORD + 1] = {0};
        for (int k = 0; k < e->nprops; ++k)
            seen[e->props[k].role] = 1;
        if (e->kind == E_VERTEX) {
            if (!seen[R_X] || !seen[R_Y] || !seen[R_Z])
                return sk__text_error(t, "the vertex element lacks an x, y or z property");
            h->has_normals = seen[R_NX] && seen[R_NY] && seen[R_NZ];
            h->has_uvs = seen[R_U] && seen[R_V];
            h->nv = e->count;
        } else if (e->kind == E_FACE) {
            if (!seen[R_INDICES])
                return sk__text_error(t, "the face element has no vertex_indices list");
            h->has_texcoord = seen[R_TEXCOORD];
            h->nf = e->count;
        }
    }
    if (h->nv >= UINT32_MAX || h->nf >= UINT32_MAX)
        return sk__text_error(t, "too many elements for 32-bit indices");
    return SK_OK;
}

/* Minimal bytes of one instance of e in the data section. */
static uint64_t min_bytes(const ply_elem *e, ply_format f)
{
    uint64_t n = 0;
    for (int k = 0; k < e->nprops; ++k) {
        const ply_prop *p = &e->props[k];
        if (f == F_ASCII)
            n += 2; /* a digit and a separator (a list needs at least its count) */
        else
            n += (uint64_t)type_size[p->count_type ? p->count_type : p->type];
    }
    return n;
}

/* ---------------------------------------------------------------------------------------------
 * Values
 * ------------------------------------------------------------------------------------------- */

static uint64_t load(const unsigned char *p, int size, bool be)
{
    uint64_t v = 0;
    if (be)
        for (int i = 0; i < size; ++i)
            v = v << 8 | p[i];
    else
        for (int i = size - 1; i >= 0; --i)
            v = v << 8 | p[i];
    return v;
}

static int64_t as_int(uint64_t bits, ply_type t)
{
    switch (t) {
    case T_I8: return (int64_t)(bits & 0xff) - (bits & 0x80 ? 0x100 : 0);
    case T_I16: return (int64_t)(bits & 0xffff) - (bits & 0x8000 ? 0x10000 : 0);
    case T_I32: return (int64_t)(bits & 0xffffffffu) - (bits & 0x80000000u ? 0x100000000 : 0);
    default: return (int64_t)bits;
    }
}

static double as_double(uint64_t bits, ply_type t)
{
    if (t == T_F32) {
        uint32_t b = (uint32_t)bits;
        float f;
        memcpy(&f, &b, sizeof f);
        return (double)f;
    }
    if (t == T_F64) {
        double d;
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    return (double)as_int(bits, t);
}

/* ---------------------------------------------------------------------------------------------
 * Data
 * ------------------------------------------------------------------------------------------- */

typedef struct ply_reader {
    const ply_header *h;
    const unsigned char *base, *p, *end; /* binary */
    sk__text t;                          /* ascii */
    sk_soup *s;
    uint32_t *idx;
    size_t idx_cap;
    double *tc;          /* texcoord values of the current face */
    size_t tc_cap;
    uint64_t ntc;        /* their number */
    double *cuv;         /* 2 per corner read so far (texcoord) */
    uint32_t *ccorner;   /* per corner: its own wedge or SK_INVALID */
    size_t cuv_cap;      /* in corners */
    const char *name;
    sk_error *err;
} ply_reader;

/* Room for n values in one of the reader's lists (a face's indices or texcoords); the room
 * doubles from 16. */
static sk_status grow_list(ply_reader *r, void **list, size_t *cap, uint64_t n, size_t size)
{
    if (n <= *cap)
        return SK_OK;
    size_t c = *cap ? *cap : 16;
    while (c < n)
        c *= 2;
    void *a = sk__realloc_array(*list, c, size);
    if (!a)
        return sk__fail(r->err, SK_ERR_NOMEM, "%s: out of memory", r->name);
    *list = a;
    *cap = c;
    return SK_OK;
}

static sk_status grow_tc(ply_reader *r, uint64_t n)
{
    return grow_list(r, (void **)&r->tc, &r->tc_cap, n, sizeof *r->tc);
}

static sk_status grow_idx(ply_reader *r, uint64_t n)
{
    return grow_list(r, (void **)&r->idx, &r->idx_cap, n, sizeof *r->idx);
}

/* Keeps the texcoord list of a face just pushed: one wedge per corner (2 values each), or none
 * for the face when the list is empty. */
static sk_status store_texcoord(ply_reader *r, uint64_t i, uint64_t n, size_t where)
{
    size_t base = r->s->face_offsets[r->s->num_faces - 1], nc = base + (size_t)n;
    if (r->ntc != 0 && r->ntc != 2 * n) {
        if (r->h->format == F_ASCII)
            return sk__text_error(&r->t, "face %llu has %llu texcoord values for %llu corners",
                                  (unsigned long long)i, (unsigned long long)r->ntc,
                                  (unsigned long long)n);
        return sk__bin_error(r->err, r->name, where, "face %llu has %llu texcoord values for "
                             "%llu corners", (unsigned long long)i, (unsigned long long)r->ntc,
                             (unsigned long long)n);
    }
    for (uint64_t k = 0; k < r->ntc; ++k)
        if (!isfinite(r->tc[k])) {
            if (r->h->format == F_ASCII)
                return sk__text_error(&r->t, "face %llu has a non-finite texcoord",
                                      (unsigned long long)i);
            return sk__bin_error(r->err, r->name, where, "face %llu has a non-finite texcoord",
                                 (unsigned long long)i);
        }
    if (nc > r->cuv_cap) {
        size_t cap = r->cuv_cap ? r->cuv_cap : 1024;
        while (cap < nc)
            cap *= 2;
        double *a = sk__realloc_array(r->cuv, cap, 2 * sizeof(double));
        if (a)
            r->cuv = a;
        uint32_t *b = sk__realloc_array(r->ccorner, cap, sizeof(uint32_t));
        if (b)
            r->ccorner = b;
        if (!a || !b)
            return sk__fail(r->err, SK_ERR_NOMEM, "%s: out of memory", r->name);
        r->cuv_cap = cap;
    }
    for (size_t c = base; c < nc; ++c) {
        r->ccorner[c] = r->ntc ? (uint32_t)c : SK_INVALID;
        r->cuv[2 * c] = r->ntc ? r->tc[2 * (c - base)] : 0;
        r->cuv[2 * c + 1] = r->ntc ? r->tc[2 * (c - base) + 1] : 0;
    }
    return SK_OK;
}

static const char *elem_what(const ply_elem *e)
{
    return e->kind == E_VERTEX ? "vertex" : e->kind == E_FACE ? "face" : e->name;
}

/* Stores a finished element instance into the soup. */
static sk_status finish_instance(ply_reader *r, const ply_elem *e, uint64_t i, const double *val,
                                 uint64_t n, size_t where)
{
    if (e->kind == E_VERTEX) {
        for (int k = 0; k < 8; ++k) {
            if (!isfinite(val[k])) {
                if (r->h->format == F_ASCII)
                    return sk__text_error(&r->t, "vertex %llu has a non-finite value",
                                          (unsigned long long)i);
                return sk__bin_error(r->err, r->name, where, "vertex %llu has a non-finite value",
                                     (unsigned long long)i);
            }
        }
        if (sk_soup_push_vertex(r->s, val, val + 3, val + 6))
            return sk__fail(r->err, SK_ERR_NOMEM, "%s: out of memory", r->name);
    } else if (e->kind == E_FACE) {
        if (n < 3) {
            if (r->h->format == F_ASCII)
                return sk__text_error(&r->t, "face %llu has only %llu vertices",
                                      (unsigned long long)i, (unsigned long long)n);
            return sk__bin_error(r->err, r->name, where, "face %llu has only %llu vertices",
                                 (unsigned long long)i, (unsigned long long)n);
        }
        if (sk_soup_push_face(r->s, r->idx, (size_t)n))
            return sk__fail(r->err, SK_ERR_NOMEM, "%s: out of memory", r->name);
        if (r->h->has_texcoord)
            return store_texcoord(r, i, n, where);
    }
    return SK_OK;
}

static sk_status read_binary(ply_reader *r)
{
    const bool be = r->h->format == F_BE;
    for (int ei = 0; ei < r->h->nelems; ++ei) {
        const ply_elem *e = &r->h->elems[ei];
        if (e->nprops == 0)
            continue;
        for (uint64_t i = 0; i < e->count; ++i) {
            size_t where = (size_t)(r->p - r->base);
            double val[8] = {0};
            uint64_t nidx = 0;
            r->ntc = 0;
            for (int k = 0; k < e->nprops; ++k) {
                const ply_prop *pr = &e->props[k];
                size_t off = (size_t)(r->p - r->base);
                if (!pr->count_type) {
                    int sz = type_size[pr->type];
                    if (r->end - r->p < sz)
                        goto truncated;
                    if (pr->role != R_NONE)
                        val[pr->role - R_X] = as_double(load(r->p, sz, be), pr->type);
                    r->p += sz;
                    continue;
                }
                int csz = type_size[pr->count_type], isz = type_size[pr->type];
                if (r->end - r->p < csz)
                    goto truncated;
                int64_t n = as_int(load(r->p, csz, be), pr->count_type);
                r->p += csz;
                if (n < 0)
                    return sk__bin_error(r->err, r->name, off, "%s %llu: list '%s' has a "
                                         "negative length", elem_what(e), (unsigned long long)i,
                                         pr->name);
                if ((uint64_t)n > (uint64_t)(r->end - r->p) / (uint64_t)isz)
                    goto truncated;
                if (pr->role == R_TEXCOORD) {
                    sk_status ts = grow_tc(r, (uint64_t)n);
                    if (ts)
                        return ts;
                    for (int64_t j = 0; j < n; ++j, r->p += isz)
                        r->tc[j] = as_double(load(r->p, isz, be), pr->type);
                    r->ntc = (uint64_t)n;
                    continue;
                }
                if (pr->role != R_INDICES) {
                    r->p += (size_t)n * (size_t)isz;
                    continue;
                }
                sk_status st = grow_idx(r, (uint64_t)n);
                if (st)
                    return st;
                for (int64_t j = 0; j < n; ++j) {
                    int64_t x = as_int(load(r->p, isz, be), pr->type);
                    if (x < 0 || (uint64_t)x >= r->h->nv)
                        return sk__bin_error(r->err, r->name, (size_t)(r->p - r->base),
                                             "face %llu has index %lld but the file has %llu "
                                             "vertices", (unsigned long long)i, (long long)x,
                                             (unsigned long long)r->h->nv);
                    r->idx[j] = (uint32_t)x;
                    r->p += isz;
                }
                nidx = (uint64_t)n;
            }
            sk_status st = finish_instance(r, e, i, val, nidx, where);
            if (st)
                return st;
            continue;
        truncated:
            return sk__bin_error(r->err, r->name, (size_t)(r->p - r->base),
                                 "the file ends inside %s %llu of %llu", elem_what(e),
                                 (unsigned long long)i, (unsigned long long)e->count);
        }
    }
    return SK_OK;
}

static sk_status ascii_value(ply_reader *r, const ply_elem *e, uint64_t i, double *d)
{
    char tok[48];
    sk__text *t = &r->t;
    sk__skip_space(t);
    if (sk__at_eof(t))
        return sk__text_error(t, "the file ends inside %s %llu of %llu", elem_what(e),
                              (unsigned long long)i, (unsigned long long)e->count);
    const char *p = t->p;
    sk__num res = sk__parse_double(&p, t->end, d);
    if (res == SK__NUM_NONFINITE && e->kind == E_VERTEX)
        return sk__text_error(t, "vertex %llu has a non-finite value '%s'", (unsigned long long)i,
                              sk__token_str(t->p, t->end, tok, sizeof tok));
    if (res == SK__NUM_NONFINITE)
        *d = 0; /* a value of an ignored property */
    if (res == SK__NUM_NONE || !(p >= t->end || sk__is_space(*p)))
        return sk__text_error(t, "%s %llu: '%s' is not a number", elem_what(e),
                              (unsigned long long)i, sk__token_str(t->p, t->end, tok, sizeof tok));
    t->p = p;
    return SK_OK;
}

static sk_status ascii_int(ply_reader *r, const ply_elem *e, uint64_t i, int64_t *v)
{
    char tok[48];
    sk__text *t = &r->t;
    sk__skip_space(t);
    if (sk__at_eof(t))
        return sk__text_error(t, "the file ends inside %s %llu of %llu", elem_what(e),
                              (unsigned long long)i, (unsigned long long)e->count);
    const char *p = t->p;
    if (!sk__parse_int(&p, t->end, v) || !(p >= t->end || sk__is_space(*p)))
        return sk__text_error(t, "%s %llu: '%s' is not an integer", elem_what(e),
                              (unsigned long long)i, sk__token_str(t->p, t->end, tok, sizeof tok));
    t->p = p;
    return SK_OK;
}

static sk_status read_ascii(ply_reader *r)
{
    sk__text *t = &r->t;
    sk_status st;
    for (int ei = 0; ei < r->h->nelems; ++ei) {
        const ply_elem *e = &r->h->elems[ei];
        if (e->nprops == 0)
            continue;
        for (uint64_t i = 0; i < e->count; ++i) {
            double val[8] = {0}, d;
            uint64_t nidx = 0;
            r->ntc = 0;
            for (int k = 0; k < e->nprops; ++k) {
                const ply_prop *pr = &e->props[k];
                if (!pr->count_type) {
                    if ((st = ascii_value(r, e, i, &d)))
                        return st;
                    if (pr->role != R_NONE)
                        val[pr->role - R_X] = d;
                    continue;
                }
                int64_t n;
                if ((st = ascii_int(r, e, i, &n)))
                    return st;
                if (n < 0 || (uint64_t)n > (uint64_t)(t->end - t->p) / 2)
                    return sk__text_error(t, "%s %llu: list '%s' of length %lld does not fit in "
                                          "the rest of the file", elem_what(e),
                                          (unsigned long long)i, pr->name, (long long)n);
                if (pr->role == R_INDICES && (st = grow_idx(r, (uint64_t)n)))
                    return st;
                if (pr->role == R_TEXCOORD) {
                    if ((st = grow_tc(r, (uint64_t)n)))
                        return st;
                    r->ntc = (uint64_t)n;
                }
                for (int64_t j = 0; j < n; ++j) {
                    if (pr->role != R_INDICES) {
                        if ((st = ascii_value(r, e, i, &d)))
                            return st;
                        if (pr->role == R_TEXCOORD)
                            r->tc[j] = d;
                        continue;
                    }
                    int64_t x;
                    if ((st = ascii_int(r, e, i, &x)))
                        return st;
                    if (x < 0 || (uint64_t)x >= r->h->nv)
                        return sk__text_error(t, "face %llu has index %lld but the file has %llu "
                                              "vertices", (unsigned long long)i, (long long)x,
                                              (unsigned long long)r->h->nv);
                    r->idx[j] = (uint32_t)x;
                }
                if (pr->role == R_INDICES)
                    nidx = (uint64_t)n;
            }
            if ((st = finish_instance(r, e, i, val, nidx, 0)))
                return st;
        }
    }
    char tok[48];
    sk__skip_space(t);
    if (!sk__at_eof(t))
        return sk__text_error(t, "unexpected '%s' after the last element (are the counts in the "
                              "header right?)", sk__token_str(t->p, t->end, tok, sizeof tok));
    return SK_OK;
}

sk_status sk__read_ply(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err)
{
    *out = NULL;
    ply_header *h = sk__calloc_array(1, sizeof *h);
    if (!h)
        return sk__fail(err, SK_ERR_NOMEM, "%s: out of memory", name);
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.h = h;
    r.name = name;
    r.err = err;
    sk__text_init(&r.t, data, size, name, err);
    sk_status st = parse_header(&r.t, h);
    if (st)
        goto done;

    /* declared counts against the bytes that follow, before allocating */
    uint64_t left = (uint64_t)(r.t.end - r.t.p) + (h->format == F_ASCII ? 1 : 0);
    for (int i = 0; i < h->nelems; ++i) {
        uint64_t m = min_bytes(&h->elems[i], h->format);
        if (m == 0)
            continue;
        if (h->elems[i].count > left / m) {
            size_t off = (size_t)(r.t.p - (const char *)data);
            if (h->format == F_ASCII)
                st = sk__text_error(&r.t, "the header declares %llu '%s' elements but only %llu "
                                    "bytes follow", (unsigned long long)h->elems[i].count,
                                    h->elems[i].name, (unsigned long long)(left - 1));
            else
                st = sk__bin_error(err, name, off, "the header declares %llu '%s' elements but "
                                   "only %llu bytes follow", (unsigned long long)h->elems[i].count,
                                   h->elems[i].name, (unsigned long long)left);
            goto done;
        }
        left -= h->elems[i].count * m;
    }
    uint64_t ind = 3 * h->nf;
    if (ind > size)
        ind = size;
    st = sk_soup_create((size_t)h->nv, (size_t)h->nf, (size_t)ind, h->has_normals, h->has_uvs,
                        &r.s, err);
    if (st)
        goto done;
    if (h->format == F_ASCII) {
        st = read_ascii(&r);
    } else {
        r.base = (const unsigned char *)data;
        r.p = (const unsigned char *)r.t.p;
        r.end = r.base + size;
        st = read_binary(&r);
    }
    if (!st && h->has_texcoord && r.s->num_faces > 0 &&
        sk_soup_set_corner_uvs(r.s, r.s->face_offsets[r.s->num_faces], r.cuv, r.ccorner))
        st = sk__fail(err, SK_ERR_NOMEM, "%s: out of memory", name);
done:
    sk__free(r.idx);
    sk__free(r.tc);
    sk__free(r.cuv);
    sk__free(r.ccorner);
    sk__free(h);
    if (st) {
        sk_soup_destroy(&r.s);
        return st;
    }
    *out = r.s;
    return SK_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Writer
 * ------------------------------------------------------------------------------------------- */

static void put_f64(sk__out *o, double d, bool ascii, bool first)
{
    if (ascii) {
        if (!first)
            sk__out_char(o, ' ');
        sk__out_double(o, d);
        return;
    }
    uint64_t bits;
    memcpy(&bits, &d, sizeof bits);
    if (sk__out_room(o, 8)) {
        sk__put_le64((unsigned char *)o->buf + o->len, bits);
        o->len += 8;
    }
}

static void put_texcoord(sk__out *o, const sk_soup *s, uint32_t a, uint32_t b, bool ascii,
                         bool wide_count)
{
    bool all = true;
    for (uint32_t k = a; k < b; ++k)
        all = all && s->corner_uv[k] != SK_INVALID;
    uint32_t n = all ? 2 * (b - a) : 0;
    if (ascii) {
        sk__out_char(o, ' ');
        sk__out_uint(o, n);
    } else if (sk__out_room(o, 4)) {
        unsigned char *q = (unsigned char *)o->buf + o->len;
        if (wide_count) {
            sk__put_le32(q, n);
            o->len += 4;
        } else {
            *q = (unsigned char)n;
            o->len += 1;
        }
    }
    if (!all)
        return;
    for (uint32_t k = a; k < b; ++k)
        for (int j = 0; j < 2; ++j)
            put_f64(o, s->wedge_uvs[2 * (size_t)s->corner_uv[k] + (size_t)j], ascii, false);
}

/* What the writer's header announced, shared by the rows. */
typedef struct ply_rows {
    const sk_soup *s;
    const uint32_t *cuv; /* per-corner uvs as the face list `texcoord`, or NULL */
    bool normals, vuv;   /* per-vertex nx ny nz, s t */
    bool wide_count, wide_index;
} ply_rows;

static void put_header(sk__out *o, const ply_rows *r, bool ascii)
{
    sk__out_str(o, "ply\n");
    sk__out_str(o, ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n");
    sk__out_str(o, "comment written by surfkit\nelement vertex ");
    sk__out_uint(o, r->s->num_vertices);
    sk__out_str(o, "\nproperty double x\nproperty double y\nproperty double z\n");
    if (r->normals)
        sk__out_str(o, "property double nx\nproperty double ny\nproperty double nz\n");
    if (r->vuv)
        sk__out_str(o, "property double s\nproperty double t\n");
    sk__out_str(o, "element face ");
    sk__out_uint(o, r->s->num_faces);
    sk__out_str(o, r->wide_count ? "\nproperty list uint " : "\nproperty list uchar ");
    sk__out_str(o, r->wide_index ? "uint vertex_indices\n" : "int vertex_indices\n");
    if (r->cuv)
        sk__out_str(o, r->wide_count ? "property list uint double texcoord\n"
                                     : "property list uchar double texcoord\n");
    sk__out_str(o, "end_header\n");
}

/* One vertex's values (ascii: separated by blanks, without the line end). */
static void put_vertex(sk__out *o, const ply_rows *r, size_t v, bool ascii)
{
    const sk_soup *s = r->s;
    for (int k = 0; k < 3; ++k)
        put_f64(o, s->positions[3 * v + (size_t)k], ascii, k == 0);
    if (r->normals)
        for (int k = 0; k < 3; ++k)
            put_f64(o, s->normals[3 * v + (size_t)k], ascii, false);
    if (r->vuv)
        for (int k = 0; k < 2; ++k)
            put_f64(o, s->uvs[2 * v + (size_t)k], ascii, false);
}

static void ascii_vertex_row(sk__out *o, size_t v, const void *ctx)
{
    put_vertex(o, ctx, v, true);
    sk__out_char(o, '\n');
}

static void ascii_face_row(sk__out *o, size_t f, const void *ctx)
{
    const ply_rows *r = ctx;
    uint32_t a = r->s->face_offsets[f], b = r->s->face_offsets[f + 1];
    sk__out_uint(o, b - a);
    for (uint32_t k = a; k < b; ++k) {
        sk__out_char(o, ' ');
        sk__out_uint(o, r->s->face_indices[k]);
    }
    if (r->cuv)
        put_texcoord(o, r->s, a, b, true, r->wide_count);
    sk__out_char(o, '\n');
}

static void write_binary(sk__out *o, const ply_rows *r)
{
    const sk_soup *s = r->s;
    for (size_t v = 0; v < s->num_vertices && !o->failed; ++v)
        put_vertex(o, r, v, false);
    for (size_t f = 0; f < s->num_faces && !o->failed; ++f) {
        uint32_t a = s->face_offsets[f], b = s->face_offsets[f + 1];
        if (!sk__out_room(o, 4 + 4 * (size_t)(b - a)))
            return;
        unsigned char *q = (unsigned char *)o->buf + o->len;
        if (r->wide_count) {
            sk__put_le32(q, b - a);
            q += 4;
        } else {
            *q++ = (unsigned char)(b - a);
        }
        for (uint32_t k = a; k < b; ++k, q += 4)
            sk__put_le32(q, s->face_indices[k]);
        o->len = (size_t)((char *)q - o->buf);
        if (r->cuv)
            put_texcoord(o, s, a, b, false, r->wide_count);
    }
}

void sk__write_ply(sk__out *o, const sk_soup *s, bool normals, bool uvs, bool ascii)
{
    size_t max_face = 0;
    for (size_t f = 0; f < s->num_faces; ++f)
        if (sk_soup_face_size(s, f) > max_face)
            max_face = sk_soup_face_size(s, f);
    /* per-corner uvs as MeshLab's face list `texcoord` (u v per corner), doubles so that a round
     * trip keeps every bit; a face with a corner lacking one gets an empty list */
    ply_rows r = {.s = s, .cuv = uvs ? s->corner_uv : NULL, .normals = normals,
                  .vuv = uvs && s->uvs, .wide_index = s->num_vertices > INT32_MAX};
    r.wide_count = max_face > (r.cuv ? 127 : 255);
    put_header(o, &r, ascii);
    if (!ascii) {
        write_binary(o, &r);
        return;
    }
    sk__out_rows(o, s->num_vertices, ascii_vertex_row, &r);
    sk__out_rows(o, s->num_faces, ascii_face_row, &r);
}
