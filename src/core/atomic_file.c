/* The one output-file writer of the library and the CLI (DESIGN.md: a failed or interrupted run
 * never leaves a truncated result, and no debris).
 *
 * - A symlink is followed to its final target and the temporary is made beside the target, so the
 *   link stays a link; an existing file keeps its mode (and owner, when allowed); a new file gets
 *   0666 minus the umask, as any tool's output would.
 * - Anything that is not a regular file (a device such as /dev/full or /dev/stdout, a FIFO) is
 *   written directly, never replaced.
 * - Regular files are written to an anonymous O_TMPFILE in the target's directory, which not even
 *   SIGKILL can leave behind, and given a name only when complete (linkat), then renamed over the
 *   target. Without O_TMPFILE (some file systems) the temporary is named at once; named
 *   temporaries are listed where sk_outputs_remove_pending (async-signal-safe) finds them, so the
 *   CLI's signal handler removes them.
 * - A regular file with more than one name (st_nlink > 1) is not replaced: a rename would give
 *   only this name the new content and leave the other names (hard links) with the old one, as
 *   cp, vim (backupcopy=auto) and rsync --inplace avoid doing. The content is still made
 *   complete in a temporary first; only then is it copied into the existing file in place (same
 *   inode, mode, owner and links), after reserving the space (fallocate), so a full disk fails
 *   before the old content is touched. Such a write is not atomic against a crash during the copy:
 *   keeping the links is what the user asked for by making them.
 * - Temporary names carry the process id and a counter: two processes writing the same target
 *   never share one.
 * - Between sk_outputs_begin and sk_outputs_commit, commits only name the finished temporaries;
 *   sk_outputs_commit renames them all at the end, sk_outputs_abort removes them all: a command
 *   either publishes every output or none.
 * - Errors carry errno's reason ("No space left on device"). */
#define _GNU_SOURCE
#include "core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- pending named temporaries (for the signal handler) and the deferred-commit batch ---- */

#define PENDING_MAX 1024
static _Atomic(char *) pending[PENDING_MAX];

static void pending_add(char *name)
{
    for (int i = 0; i < PENDING_MAX; ++i) {
        char *expect = NULL;
        if (atomic_compare_exchange_strong(&pending[i], &expect, name))
            return;
    }
    /* table full: the name is still removed on every ordinary path, only not by a signal */
}

static void pending_remove(const char *name)
{
    for (int i = 0; i < PENDING_MAX; ++i) {
        char *expect = (char *)name;
        if (atomic_compare_exchange_strong(&pending[i], &expect, NULL))
            return;
    }
}

void sk_outputs_remove_pending(void)
{
    for (int i = 0; i < PENDING_MAX; ++i) {
        char *name = atomic_load(&pending[i]);
        if (name)
            unlink(name); /* async-signal-safe */
    }
}

typedef struct batch_item {
    char *tmp_path, *final_path;
    int in_place; /* copy into final_path (hard links) instead of renaming over it */
} batch_item;

static struct {
    int active;
    batch_item *items;
    size_t count, cap;
} batch;

void sk_outputs_begin(void)
{
    batch.active = 1;
}

static void drop_item(batch_item *it)
{
    pending_remove(it->tmp_path);
    sk__free(it->tmp_path);
    sk__free(it->final_path);
}

void sk_outputs_abort(void)
{
    for (size_t i = 0; i < batch.count; ++i) {
        unlink(batch.items[i].tmp_path);
        drop_item(&batch.items[i]);
    }
    sk__free(batch.items);
    batch.items = NULL;
    batch.count = batch.cap = 0;
    batch.active = 0;
}

static int copy_into(const char *src, const char *dst);

/* Publishes a finished named temporary: renamed over the target, or copied into it (hard links,
 * see the top of the file) and removed. Returns 0 or the errno. */
static int publish(const char *tmp_path, const char *final_path, int in_place)
{
    if (!in_place)
        return rename(tmp_path, final_path) != 0 ? errno : 0;
    int e = copy_into(tmp_path, final_path);
    if (!e)
        unlink(tmp_path);
    return e;
}

sk_status sk_outputs_commit(sk_error *err)
{
    sk_status st = SK_OK;
    size_t i = 0;
    for (; i < batch.count; ++i) {
        batch_item *it = &batch.items[i];
        int e = publish(it->tmp_path, it->final_path, it->in_place);
        if (e) {
            st = sk__fail(err, SK_ERR_IO, "%s: %s: %s", it->final_path,
                          it->in_place ? "cannot write into the hard-linked file"
                                       : "cannot rename into place",
                          strerror(e));
            break;
        }
        drop_item(it);
    }
    for (; i < batch.count; ++i) { /* after a failure: the rest are not published */
        unlink(batch.items[i].tmp_path);
        drop_item(&batch.items[i]);
    }
    sk__free(batch.items);
    batch.items = NULL;
    batch.count = batch.cap = 0;
    batch.active = 0;
    if (st == SK_OK)
        sk__ok(err);
    return st;
}

/* ---- one file ---- */

static atomic_uint temp_counter;

/* "<target>.tmp.<pid>.<n>" (malloc'ed) */
static char *temp_name(const char *target)
{
    size_t n = strlen(target) + 64;
    char *t = sk__malloc_array(n, 1);
    if (t)
        snprintf(t, n, "%s.tmp.%ld.%u", target, (long)getpid(), atomic_fetch_add(&temp_counter, 1u));
    return t;
}

/* Follows symlinks to the final target (which need not exist); malloc'ed. */
static char *resolve_target(const char *path)
{
    char *cur = sk__strdup(path);
    for (int hops = 0; cur && hops < 40; ++hops) {
        struct stat ls;
        if (lstat(cur, &ls) != 0 || !S_ISLNK(ls.st_mode))
            return cur;
        char link[PATH_MAX];
        ssize_t k = readlink(cur, link, sizeof link - 1);
        if (k < 0)
            return cur;
        link[k] = '\0';
        char *next;
        const char *slash = strrchr(cur, '/');
        if (link[0] == '/' || !slash) {
            next = sk__strdup(link);
        } else { /* relative to the link's directory */
            size_t dlen = (size_t)(slash - cur) + 1;
            next = sk__malloc_array(dlen + (size_t)k + 1, 1);
            if (next) {
                memcpy(next, cur, dlen);
                memcpy(next + dlen, link, (size_t)k + 1);
            }
        }
        sk__free(cur);
        cur = next;
    }
    return cur;
}

/* Copies the complete file src into the existing regular file dst in place (keeping its inode,
 * mode, owner and other names); returns 0 or the errno. */
static int copy_into(const char *src, const char *dst)
{
    int e = 0;
    int in = open(src, O_RDONLY | O_CLOEXEC);
    int out = in >= 0 ? open(dst, O_WRONLY | O_CLOEXEC) : -1;
    struct stat sb;
    if (in < 0 || out < 0 || fstat(in, &sb) != 0) {
        e = errno;
        goto done;
    }
    /* reserve the space first: on a full disk this fails before a byte of the old content is
     * overwritten (file systems without fallocate just skip the reservation) */
    if (sb.st_size > 0 && fallocate(out, 0, 0, sb.st_size) != 0 && errno != EOPNOTSUPP &&
        errno != ENOSYS) {
        e = errno;
        goto done;
    }
    char buf[1 << 16];
    off_t total = 0;
    for (;;) {
        ssize_t n = read(in, buf, sizeof buf);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            e = errno;
            goto done;
        }
        if (n == 0)
            break;
        for (ssize_t w = 0; w < n;) {
            ssize_t k = write(out, buf + w, (size_t)(n - w));
            if (k < 0 && errno == EINTR)
                continue;
            if (k < 0) {
                e = errno;
                goto done;
            }
            w += k;
        }
        total += n;
    }
    if (ftruncate(out, total) != 0 || (fsync(out) != 0 && errno != EINVAL && errno != EROFS))
        e = errno;
done:
    if (out >= 0 && close(out) != 0 && !e)
        e = errno;
    if (in >= 0)
        close(in);
    return e;
}

static sk_status io_fail(sk_error *err, const char *path, const char *what, int e)
{
    return sk__fail(err, e == ENOMEM ? SK_ERR_NOMEM : SK_ERR_IO, "%s: %s: %s", path, what,
                    e == ENOMEM ? "out of memory" : strerror(e));
}

sk_status sk__atomic_open(sk__atomic_file *af, const char *path, sk_error *err)
{
    memset(af, 0, sizeof *af);
    af->fd = -1;
    if (!path || !*path)
        return sk__fail(err, SK_ERR_ARG, "empty output path");
    sk_status st = SK_OK;
    int fd = -1;
    struct stat sb;
    int exists = stat(path, &sb) == 0; /* follows links, also /proc/self/fd/N to a pipe */
    af->shown_path = sk__strdup(path);
    af->final_path = exists && !S_ISREG(sb.st_mode) ? sk__strdup(path) : resolve_target(path);
    if (!af->shown_path || !af->final_path) {
        st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
        goto fail;
    }
    if (exists && S_ISDIR(sb.st_mode)) {
        st = sk__fail(err, SK_ERR_IO, "%s: is a directory", path);
        goto fail;
    }
    if (exists && !S_ISREG(sb.st_mode)) {
        /* device, FIFO, socket: write to it, never replace it */
        fd = open(af->final_path, O_WRONLY | O_CLOEXEC);
        if (fd < 0) {
            st = io_fail(err, path, "cannot open output", errno);
            goto fail;
        }
        af->direct = 1;
    } else {
        const char *slash = strrchr(af->final_path, '/');
        char *dir = slash ? sk__strndup(af->final_path, (size_t)(slash - af->final_path) + 1)
                          : sk__strdup(".");
        if (!dir) {
            st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
            goto fail;
        }
#ifdef O_TMPFILE
        fd = open(dir, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
#endif
        sk__free(dir);
        if (fd < 0) { /* no O_TMPFILE here: a named temporary, removed by signal handlers */
            af->tmp_path = temp_name(af->final_path);
            if (!af->tmp_path) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                goto fail;
            }
            fd = open(af->tmp_path, O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
            if (fd < 0) {
                st = io_fail(err, path, "cannot create output file", errno);
                sk__free(af->tmp_path);
                af->tmp_path = NULL;
                goto fail;
            }
            pending_add(af->tmp_path);
        }
        af->in_place = exists && sb.st_nlink > 1; /* hard links: see the top of the file */
        if (exists) { /* keep the existing file's mode and, where allowed, its owner */
            (void)fchmod(fd, sb.st_mode & 07777);
            if (fchown(fd, sb.st_uid, sb.st_gid) != 0)
                (void)fchmod(fd, sb.st_mode & 0777);
        }
    }
    af->fd = fd;
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        st = io_fail(err, path, "cannot open output file", errno);
        goto fail;
    }
    /* a large buffer: writers emit many small records */
    setvbuf(af->fp, NULL, _IOFBF, 1 << 20);
    return SK_OK;
fail:
    if (!af->fp && fd >= 0)
        close(fd);
    af->fd = -1;
    sk__atomic_abort(af);
    return st;
}

sk_status sk__atomic_commit(sk__atomic_file *af, sk_error *err)
{
    sk_status st = SK_OK;
    errno = 0;
    int e = ferror(af->fp) ? (errno ? errno : EIO) : 0;
    if (fflush(af->fp) != 0 && !e)
        e = errno;
    if (!e && !af->direct && fsync(af->fd) != 0 && errno != EINVAL && errno != EROFS)
        e = errno;
    if (!af->tmp_path && !af->direct && !e) {
        /* anonymous temporary: give it a name beside the target */
        char proc[64];
        snprintf(proc, sizeof proc, "/proc/self/fd/%d", af->fd);
        for (int tries = 0; tries < 8 && !e; ++tries) {
            af->tmp_path = temp_name(af->final_path);
            if (!af->tmp_path) {
                e = ENOMEM;
                break;
            }
            if (linkat(AT_FDCWD, proc, AT_FDCWD, af->tmp_path, AT_SYMLINK_FOLLOW) == 0) {
                pending_add(af->tmp_path);
                break;
            }
            int le = errno;
            sk__free(af->tmp_path);
            af->tmp_path = NULL;
            if (le != EEXIST)
                e = le;
        }
        if (!e && !af->tmp_path)
            e = EEXIST;
    }
    if (fclose(af->fp) != 0 && !e)
        e = errno;
    af->fp = NULL;
    af->fd = -1;
    if (e) {
        st = e == ENOMEM ? sk__fail(err, SK_ERR_NOMEM, "out of memory")
                         : sk__fail(err, SK_ERR_IO, "%s: write failed: %s", af->shown_path,
                                    strerror(e));
        sk__atomic_abort(af);
        return st;
    }
    if (af->direct) {
        sk__atomic_abort(af);
        sk__ok(err);
        return SK_OK;
    }
    if (batch.active) { /* published by sk_outputs_commit */
        if (batch.count == batch.cap) {
            size_t cap = batch.cap ? 2 * batch.cap : 8;
            batch_item *items = sk__realloc_array(batch.items, cap * sizeof *items, 1);
            if (!items) {
                st = sk__fail(err, SK_ERR_NOMEM, "out of memory");
                sk__atomic_abort(af);
                return st;
            }
            batch.items = items;
            batch.cap = cap;
        }
        batch.items[batch.count++] = (batch_item){af->tmp_path, af->final_path, af->in_place};
        af->tmp_path = af->final_path = NULL;
        sk__atomic_abort(af);
        sk__ok(err);
        return SK_OK;
    }
    int pe = publish(af->tmp_path, af->final_path, af->in_place);
    if (pe) {
        st = io_fail(err, af->shown_path,
                     af->in_place ? "cannot write into the hard-linked file"
                                  : "cannot rename into place",
                     pe);
        sk__atomic_abort(af);
        return st;
    }
    pending_remove(af->tmp_path);
    sk__free(af->tmp_path);
    af->tmp_path = NULL;
    sk__atomic_abort(af);
    sk__ok(err);
    return SK_OK;
}

void sk__atomic_abort(sk__atomic_file *af)
{
    if (af->fp)
        fclose(af->fp);
    else if (af->fd >= 0)
        close(af->fd);
    if (af->tmp_path) {
        unlink(af->tmp_path);
        pending_remove(af->tmp_path);
    }
    sk__free(af->tmp_path);
    sk__free(af->final_path);
    sk__free(af->shown_path);
    memset(af, 0, sizeof *af);
    af->fd = -1;
}

sk_status sk_write_file(const char *path, sk_status (*fn)(FILE *fp, void *user), void *user,
                        sk_error *err)
{
    sk__atomic_file af;
    sk_status st = sk__atomic_open(&af, path, err);
    if (st)
        return st;
    if ((st = fn(af.fp, user)) != SK_OK) {
        sk__atomic_abort(&af);
        return sk__fail(err, st, "%s: %s", path, sk_status_string(st));
    }
    return sk__atomic_commit(&af, err);
}
