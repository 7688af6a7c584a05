/* The one output buffer of the library (mesh writers, CAD exporters): a growing memory buffer,
 * flushed to a FILE when one is attached (numbers through the formatter of fmt.c). */
#include "core/internal.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* sk__out_rows: fewer rows than this are formatted on the caller's thread alone (a thread costs
 * tens of microseconds, a row about a hundred nanoseconds); more go in rounds of SK__ROWS_ROUND
 * rows, whose second half a second thread formats, so that the private buffer stays small (a
 * few MB) and warm in the cache whatever the number of rows. */
#define SK__ROWS_MIN ((size_t)1 << 15)
#define SK__ROWS_ROUND ((size_t)1 << 16)

void sk__out_flush(sk__out *o)
{
    if (!o->fp || o->failed || o->len == 0)
        return;
    errno = 0;
    if (fwrite(o->buf, 1, o->len, o->fp) != o->len) {
        o->failed = SK_ERR_IO;
        o->io_errno = errno ? errno : EIO; /* kept: later calls change errno */
    }
    o->len = 0;
}

bool sk__out_room(sk__out *o, size_t n)
{
    if (o->failed)
        return false;
    if (o->cap - o->len >= n)
        return true;
    if (o->fp && o->len > 0) {
        sk__out_flush(o);
        if (o->failed)
            return false;
        if (o->cap >= n)
            return true;
    }
    size_t cap = o->cap ? o->cap : 4096;
    while (cap - o->len < n) {
        if (cap > SIZE_MAX / 2) {
            o->failed = SK_ERR_NOMEM;
            return false;
        }
        cap *= 2;
    }
    char *b = sk__realloc_array(o->buf, cap, 1);
    if (!b) {
        o->failed = SK_ERR_NOMEM;
        return false;
    }
    o->buf = b;
    o->cap = cap;
    return true;
}

void sk__out_bytes(sk__out *o, const void *data, size_t n)
{
    if (n && sk__out_room(o, n)) {
        memcpy(o->buf + o->len, data, n);
        o->len += n;
    }
}

void sk__out_str(sk__out *o, const char *s) { sk__out_bytes(o, s, strlen(s)); }

void sk__out_char(sk__out *o, char c)
{
    if (sk__out_room(o, 1))
        o->buf[o->len++] = c;
}

void sk__out_double(sk__out *o, double v)
{
    if (!sk__out_room(o, 32))
        return;
    char *b = o->buf + o->len;
    int n = 0;
    if (v == 0.0) {
        /* keeps the sign of -0 */
        n = signbit(v) ? 2 : 1;
        memcpy(b, "-0", 2);
        if (n == 1)
            b[0] = '0';
    } else if (fabs(v) < 1e15 && v == (double)(int64_t)v) { /* range first: the cast */
        int64_t i = (int64_t)v;
        uint64_t u = i < 0 ? (uint64_t)-i : (uint64_t)i;
        char t[24];
        int k = 0;
        do {
            t[k++] = (char)('0' + u % 10);
            u /= 10;
        } while (u);
        if (i < 0)
            b[n++] = '-';
        while (k > 0)
            b[n++] = t[--k];
    } else {
        char t[32]; /* formatted locally: gcc -O3 -fsanitize warns about b otherwise */
        n = sk__fmt_shortest(t, v);
        if (n > 0 && n < 32)
            memcpy(b, t, (size_t)n);
        else
            n = 0;
    }
    if (n > 0)
        o->len += (size_t)n;
}

void sk__out_uint(sk__out *o, uint64_t v)
{
    char tmp[24];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    if (!sk__out_room(o, (size_t)n))
        return;
    for (int i = n - 1; i >= 0; --i)
        o->buf[o->len++] = tmp[i];
}

void sk__out_printf(sk__out *o, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0) {
        if (!o->failed)
            o->failed = SK_ERR_IO;
        return;
    }
    if ((size_t)n < sizeof tmp) {
        sk__out_bytes(o, tmp, (size_t)n);
        return;
    }
    if (!sk__out_room(o, (size_t)n + 1))
        return;
    va_start(ap, fmt);
    vsnprintf(o->buf + o->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    o->len += (size_t)n;
}

typedef struct rows_job {
    sk__out out; /* memory only, reused round after round */
    size_t from, to;
    sk__row_fn row;
    const void *ctx;
} rows_job;

static void rows_serial(sk__out *o, size_t from, size_t to, sk__row_fn row, const void *ctx)
{
    for (size_t i = from; i < to && !o->failed; ++i)
        row(o, i, ctx);
}

static void *rows_thread(void *arg)
{
    rows_job *j = arg;
    rows_serial(&j->out, j->from, j->to, j->row, j->ctx);
    return NULL;
}

/* Rows [from, to): the second half on a second thread into j->out, appended after the first;
 * false when no thread could be started (nothing written then). */
static bool rows_round(sk__out *o, rows_job *j, size_t from, size_t to)
{
    pthread_t t;
    j->out.len = 0;
    j->from = from + (to - from) / 2;
    j->to = to;
    if (pthread_create(&t, NULL, rows_thread, j) != 0)
        return false;
    rows_serial(o, from, j->from, j->row, j->ctx);
    pthread_join(t, NULL);
    if (j->out.failed && !o->failed)
        o->failed = j->out.failed; /* memory only: SK_ERR_NOMEM */
    sk__out_bytes(o, j->out.buf, j->out.len);
    return true;
}

void sk__out_rows(sk__out *o, size_t n, sk__row_fn row, const void *ctx)
{
    size_t i = 0;
    if (n >= SK__ROWS_MIN) {
        rows_job j = {.row = row, .ctx = ctx};
        for (; i < n && !o->failed; i += SK__ROWS_ROUND) {
            size_t end = n - i > SK__ROWS_ROUND ? i + SK__ROWS_ROUND : n;
            if (!rows_round(o, &j, i, end))
                break; /* no second thread: the rest on this one */
        }
        sk__out_free(&j.out);
    }
    rows_serial(o, i, n, row, ctx);
}

void sk__out_free(sk__out *o)
{
    sk__free(o->buf);
    o->buf = NULL;
    o->len = o->cap = 0;
}

sk_status sk__out_write_file(const sk__out *o, const char *path, sk_error *err)
{
    if (o->failed == SK_ERR_NOMEM)
        return sk__fail(err, SK_ERR_NOMEM, "out of memory");
    if (o->failed)
        return sk__fail(err, o->failed, "%s: cannot format the output", path);
    sk__atomic_file af;
    sk_status st = sk__atomic_open(&af, path, err);
    if (st)
        return st;
    if (o->len && fwrite(o->buf, 1, o->len, af.fp) != o->len) {
        int e = errno;
        sk__atomic_abort(&af);
        return sk__fail(err, SK_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return sk__atomic_commit(&af, err);
}
