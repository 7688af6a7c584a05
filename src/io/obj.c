/* Wavefront OBJ, polygonal subset: v, vn, vt, f.
 *
 * Reading: `v x y z` (an optional w or vertex colour after them is ignored), `vn x y z`, `vt u [v
 * [w]]`, `f` with corners v, v/vt, v//vn or v/vt/vn, positive (1-based) or negative (relative)
 * indices, polygons of any size. A face may only refer to elements defined before it. `g o s
 * usemtl mtllib l p` and unknown statements are ignored. A backslash at the end of a line
 * continues the statement on the next line.
 *
 * Attributes: every corner's vt / vn index is kept as given (soup corner_uv / corner_normal over
 * the file's vt / vn lists, SK_INVALID for a corner without), so texture seams and crease normals
 * survive. The per-vertex uvs / normals are filled too, from the first corner in file order that
 * uses the vertex (vertices never given one get zeros). Writing uses the per-corner values when
 * the soup has them (`f v/vt/vn` with their own index spaces), else the per-vertex ones. */
#include "io/formats.h"
#include "io/lexer.h"

#include <stdlib.h>

typedef struct dvec {
    double *a;
    size_t n, cap; /* in doubles */
} dvec;

typedef struct uvec {
    uint32_t *a;
    size_t n, cap;
} uvec;

static bool dvec_push(dvec *v, const double *x, size_t k)
{
    if (v->n + k > v->cap) {
        size_t cap = v->cap ? v->cap * 2 : 1024;
        double *a = sk__realloc_array(v->a, cap, sizeof *a);
        if (!a)
            return false;
        v->a = a;
        v->cap = cap;
    }
    memcpy(v->a + v->n, x, k * sizeof *x);
    v->n += k;
    return true;
}

static bool uvec_reserve(uvec *v, size_t n)
{
    if (n <= v->cap)
        return true;
    size_t cap = v->cap ? v->cap : 1024;
    while (cap < n)
        cap *= 2;
    uint32_t *a = sk__realloc_array(v->a, cap, sizeof *a);
    if (!a)
        return false;
    v->a = a;
    v->cap = cap;
    return true;
}

/* Skips blanks and backslash line continuations. */
static void obj_skip_blank(sk__text *t)
{
    for (;;) {
        sk__skip_blank(t);
        if (t->p + 1 < t->end && t->p[0] == '\\' && sk__is_eol(t->p[1])) {
            ++t->p;
            sk__eat_eol(t);
        } else if (t->p + 1 == t->end && t->p[0] == '\\') {
            ++t->p;
        } else {
            return;
        }
    }
}

/* End of the statement: a line end, a comment or the end of the input. */
static bool obj_at_end(const sk__text *t) { return sk__at_eol(t) || *t->p == '#'; }

static bool ends_value(const char *p, const char *end)
{
    return p >= end || sk__is_space(*p) || *p == '#' ||
           (*p == '\\' && (p + 1 >= end || sk__is_eol(p[1])));
}

/* Skips the rest of the statement including continued lines. */
static void obj_skip_statement(sk__text *t)
{
    for (;;) {
        const char *p = t->p;
        while (p < t->end && !sk__is_eol(*p))
            ++p;
        bool cont = p > t->p && p[-1] == '\\';
        t->p = p;
        sk__eat_eol(t);
        if (!cont || sk__at_eof(t))
            return;
    }
}

/* Parses up to max numbers of a v / vn / vt statement; returns how many (at least min) or -1
 * after reporting the error. Values after max are ignored. */
static int parse_values(sk__text *t, double *out, int min, int max, const char *what, size_t num)
{
    char tok[48];
    int k = 0;
    for (; k < max; ++k) {
        obj_skip_blank(t);
        if (obj_at_end(t))
            break;
        const char *p = t->p;
        sk__num r = sk__parse_double(&p, t->end, &out[k]);
        if (r == SK__NUM_NONFINITE) {
            sk__text_error(t, "%s %zu has a non-finite value '%s'", what, num,
                           sk__token_str(t->p, t->end, tok, sizeof tok));
            return -1;
        }
        if (r != SK__NUM_OK || !ends_value(p, t->end)) {
            sk__text_error(t, "%s %zu: '%s' is not a number", what, num,
                           sk__token_str(t->p, t->end, tok, sizeof tok));
            return -1;
        }
        t->p = p;
    }
    if (k < min) {
        sk__text_error(t, "%s %zu has %d values, expected %d", what, num, k, min);
        return -1;
    }
    obj_skip_statement(t);
    return k;
}

/* Resolves a 1-based or negative OBJ index against count defined elements. */
static bool resolve(int64_t i, size_t count, uint32_t *out)
{
    if (i > 0 && (uint64_t)i <= count) {
        *out = (uint32_t)(i - 1);
        return true;
    }
    if (i < 0 && (uint64_t)(-i) <= count) {
        *out = (uint32_t)((int64_t)count + i);
        return true;
    }
    return false;
}

/* Cheap first pass: counts lines starting with "v " and "f " to reserve the arrays. */
static void estimate(const char *p, const char *end, size_t *nv, size_t *nf)
{
    size_t v = 0, f = 0;
    while (p < end) {
        if (end - p > 1 && sk__is_blank(p[1])) {
            v += p[0] == 'v';
            f += p[0] == 'f';
        }
        const char *q = memchr(p, '\n', (size_t)(end - p));
        if (!q)
            break;
        p = q + 1;
    }
    *nv = v;
    *nf = f;
}

typedef struct obj_state {
    sk_soup *s;
    dvec vn, vt;
    uvec corner_vn, corner_vt; /* per corner, SK_INVALID when absent; empty until first used */
    uvec idx;                  /* scratch: position indices of one face */
    uvec fvt, fvn;             /* scratch: vt / vn indices of one face */
    size_t faces;
} obj_state;

static sk_status parse_face(sk__text *t, obj_state *o)
{
    char tok[48];
    size_t nv = o->s->num_vertices, nvt = o->vt.n / 2, nvn = o->vn.n / 3;
    size_t k = 0;
    bool any_vt = false, any_vn = false;
    for (;;) {
        obj_skip_blank(t);
        if (obj_at_end(t))
            break;
        if (!uvec_reserve(&o->idx, k + 1) || !uvec_reserve(&o->fvt, k + 1) ||
            !uvec_reserve(&o->fvn, k + 1))
            return sk__fail(t->err, SK_ERR_NOMEM, "%s: out of memory", t->name);
        const char *p = t->p;
        int64_t i, j;
        uint32_t vi, ti = SK_INVALID, ni = SK_INVALID;
        if (!sk__parse_int(&p, t->end, &i))
            goto bad;
        if (!resolve(i, nv, &vi))
            return sk__text_error(t, "face %zu has index %lld but %zu vertices are defined before "
                                     "it%s", o->faces, (long long)i, nv,
                                  i == 0 ? " (OBJ indices start at 1)" : "");
        if (p < t->end && *p == '/') {
            ++p;
            if (p < t->end && *p != '/') {
                if (!sk__parse_int(&p, t->end, &j))
                    goto bad;
                if (!resolve(j, nvt, &ti))
                    return sk__text_error(t, "face %zu has texture index %lld but %zu texture "
                                             "coordinates are defined before it", o->faces,
                                          (long long)j, nvt);
                any_vt = true;
            }
            if (p < t->end && *p == '/') {
                ++p;
                if (!sk__parse_int(&p, t->end, &j))
                    goto bad;
                if (!resolve(j, nvn, &ni))
                    return sk__text_error(t, "face %zu has normal index %lld but %zu normals are "
                                             "defined before it", o->faces, (long long)j, nvn);
                any_vn = true;
            }
        }
        if (!ends_value(p, t->end))
            goto bad;
        t->p = p;
        o->idx.a[k] = vi;
        o->fvt.a[k] = ti;
        o->fvn.a[k] = ni;
        ++k;
    }
    if (k < 3)
        return sk__text_error(t, "face %zu has only %zu vertices", o->faces, k);
    size_t base = o->s->face_offsets[o->s->num_faces];
    uvec *cv[2] = {&o->corner_vt, &o->corner_vn};
    uvec *fv[2] = {&o->fvt, &o->fvn};
    bool any[2] = {any_vt, any_vn};
    for (int a = 0; a < 2; ++a) {
        if (!any[a] && cv[a]->a == NULL)
            continue;
        if (!uvec_reserve(cv[a], base + k))
            return sk__fail(t->err, SK_ERR_NOMEM, "%s: out of memory", t->name);
        for (size_t c = cv[a]->n; c < base; ++c)
            cv[a]->a[c] = SK_INVALID; /* corners before the first use */
        memcpy(cv[a]->a + base, fv[a]->a, k * sizeof(uint32_t));
        cv[a]->n = base + k;
    }
    if (sk_soup_push_face(o->s, o->idx.a, k))
        return sk__fail(t->err, SK_ERR_NOMEM, "%s: out of memory", t->name);
    ++o->faces;
    obj_skip_statement(t);
    return SK_OK;
bad:
    return sk__text_error(t, "face %zu: '%s' is not a vertex reference (v, v/vt, v//vn or "
                             "v/vt/vn)", o->faces, sk__token_str(t->p, t->end, tok, sizeof tok));
}

/* Attaches the per-corner attributes to the position vertices: the first corner wins. */
static sk_status attach(obj_state *o, const uvec *corner, const dvec *vals, int dim,
                        double *dst)
{
    uint8_t *done = sk__calloc_array(o->s->num_vertices, 1);
    if (!done)
        return SK_ERR_NOMEM;
    const uint32_t *fi = o->s->face_indices;
    for (size_t c = 0; c < corner->n; ++c) {
        uint32_t a = corner->a[c], v = fi[c];
        if (a == SK_INVALID || done[v])
            continue;
        done[v] = 1;
        memcpy(dst + (size_t)dim * v, vals->a + (size_t)dim * a, (size_t)dim * sizeof(double));
    }
    sk__free(done);
    return SK_OK;
}

/* Corners after the last face that used the attribute get none. */
static bool pad_corners(uvec *c, const sk_soup *s)
{
    size_t nc = s->face_offsets[s->num_faces];
    if (!uvec_reserve(c, nc ? nc : 1))
        return false;
    for (size_t i = c->n; i < nc; ++i)
        c->a[i] = SK_INVALID;
    c->n = nc;
    return true;
}

sk_status sk__read_obj(const void *data, size_t size, const char *name, sk_soup **out,
                       sk_error *err)
{
    *out = NULL;
    sk__text t;
    sk__text_init(&t, data, size, name, err);
    obj_state o;
    memset(&o, 0, sizeof o);
    size_t est_v, est_f;
    estimate(t.p, t.end, &est_v, &est_f);
    sk_status st = sk_soup_create(est_v, est_f, 3 * est_f, false, false, &o.s, err);
    if (st)
        return st;
    double val[4];
    while (!sk__at_eof(&t)) {
        obj_skip_blank(&t);
        if (sk__at_eol(&t)) {
            sk__eat_eol(&t);
            continue;
        }
        const char *kw = t.p;
        size_t kl = 0;
        while (kw + kl < t.end && !sk__is_space(kw[kl]) && kw[kl] != '\\')
            ++kl;
        t.p += kl;
        if (kl == 1 && kw[0] == 'v') {
            if (parse_values(&t, val, 3, 3, "vertex", o.s->num_vertices + 1) < 0)
                goto fail_parse;
            if (o.s->num_vertices >= UINT32_MAX - 2) {
                st = sk__text_error(&t, "too many vertices for 32-bit indices");
                goto done;
            }
            if (sk_soup_push_vertex(o.s, val, NULL, NULL))
                goto fail_mem;
        } else if (kl == 2 && kw[0] == 'v' && kw[1] == 'n') {
            if (parse_values(&t, val, 3, 3, "normal", o.vn.n / 3 + 1) < 0)
                goto fail_parse;
            if (!dvec_push(&o.vn, val, 3))
                goto fail_mem;
        } else if (kl == 2 && kw[0] == 'v' && kw[1] == 't') {
            val[1] = 0;
            if (parse_values(&t, val, 1, 2, "texture coordinate", o.vt.n / 2 + 1) < 0)
                goto fail_parse;
            if (!dvec_push(&o.vt, val, 2))
                goto fail_mem;
        } else if (kl == 1 && kw[0] == 'f') {
            st = parse_face(&t, &o);
            if (st)
                goto done;
        } else {
            /* comments, g o s usemtl mtllib l p and anything unknown */
            obj_skip_statement(&t);
        }
    }
    if (o.s->num_vertices == 0 && o.s->num_faces == 0) {
        st = sk__text_error(&t, "no vertices and no faces: not an OBJ mesh");
        goto done;
    }
    if (o.corner_vt.a) {
        if (sk_soup_add_uvs(o.s) || attach(&o, &o.corner_vt, &o.vt, 2, o.s->uvs) ||
            !pad_corners(&o.corner_vt, o.s) ||
            sk_soup_set_corner_uvs(o.s, o.vt.n / 2, o.vt.a, o.corner_vt.a))
            goto fail_mem;
    }
    if (o.corner_vn.a) {
        if (sk_soup_add_normals(o.s) || attach(&o, &o.corner_vn, &o.vn, 3, o.s->normals) ||
            !pad_corners(&o.corner_vn, o.s) ||
            sk_soup_set_corner_normals(o.s, o.vn.n / 3, o.vn.a, o.corner_vn.a))
            goto fail_mem;
    }
    st = SK_OK;
    goto done;
fail_parse:
    st = SK_ERR_PARSE;
    goto done;
fail_mem:
    st = sk__fail(err, SK_ERR_NOMEM, "%s: out of memory", name);
done:
    sk__free(o.vn.a);
    sk__free(o.vt.a);
    sk__free(o.corner_vn.a);
    sk__free(o.corner_vt.a);
    sk__free(o.idx.a);
    sk__free(o.fvt.a);
    sk__free(o.fvn.a);
    if (st) {
        sk_soup_destroy(&o.s);
        return st;
    }
    *out = o.s;
    return SK_OK;
}

/* One `kw x y [z]` line per row of an array of dim doubles per element. */
typedef struct vec_rows {
    const char *kw;
    const double *x;
    int dim;
} vec_rows;

static void vec_row(sk__out *o, size_t i, const void *ctx)
{
    const vec_rows *r = ctx;
    const double *x = r->x + (size_t)r->dim * i;
    sk__out_str(o, r->kw);
    for (int k = 0; k < r->dim; ++k) {
        sk__out_char(o, ' ');
        sk__out_double(o, x[k]);
    }
    sk__out_char(o, '\n');
}

static void put_vecs(sk__out *o, const char *kw, const double *x, int dim, size_t n)
{
    vec_rows r = {kw, x, dim};
    sk__out_rows(o, n, vec_row, &r);
}

/* Writes the index of corner c's attribute (per corner, else the position's) 1-based. */
static void put_attr(sk__out *o, const uint32_t *corner, size_t c, uint64_t vi)
{
    sk__out_uint(o, corner ? (uint64_t)corner[c] + 1 : vi);
}

static bool face_has(const uint32_t *corner, uint32_t a, uint32_t b)
{
    if (!corner)
        return true;
    for (uint32_t k = a; k < b; ++k)
        if (corner[k] == SK_INVALID)
            return false;
    return true;
}

/* The `f` lines: corner uvs / normals per corner (cuv, cn) or per vertex (NULL). */
typedef struct face_rows {
    const sk_soup *s;
    const uint32_t *cuv, *cn;
    bool normals, uvs;
} face_rows;

static void face_row(sk__out *o, size_t f, const void *ctx)
{
    const face_rows *r = ctx;
    uint32_t a = r->s->face_offsets[f], b = r->s->face_offsets[f + 1];
    /* a face with a corner lacking a per-corner value is written without that attribute */
    bool fu = r->uvs && face_has(r->cuv, a, b), fn = r->normals && face_has(r->cn, a, b);
    sk__out_char(o, 'f');
    for (uint32_t k = a; k < b; ++k) {
        uint64_t i = (uint64_t)r->s->face_indices[k] + 1;
        sk__out_char(o, ' ');
        sk__out_uint(o, i);
        if (fu || fn) {
            sk__out_char(o, '/');
            if (fu)
                put_attr(o, r->cuv, k, i);
            if (fn) {
                sk__out_char(o, '/');
                put_attr(o, r->cn, k, i);
            }
        }
    }
    sk__out_char(o, '\n');
}

void sk__write_obj(sk__out *o, const sk_soup *s, bool normals, bool uvs)
{
    /* per-corner values win over per-vertex ones: vt / vn get their own index spaces */
    face_rows fr = {s, uvs ? s->corner_uv : NULL, normals ? s->corner_normal : NULL, normals,
                    uvs};
    sk__out_str(o, "# written by surfkit\n");
    put_vecs(o, "v", s->positions, 3, s->num_vertices);
    if (fr.cuv)
        put_vecs(o, "vt", s->wedge_uvs, 2, s->num_wedge_uvs);
    else if (uvs)
        put_vecs(o, "vt", s->uvs, 2, s->num_vertices);
    if (fr.cn)
        put_vecs(o, "vn", s->wedge_normals, 3, s->num_wedge_normals);
    else if (normals)
        put_vecs(o, "vn", s->normals, 3, s->num_vertices);
    sk__out_rows(o, s->num_faces, face_row, &fr);
}
