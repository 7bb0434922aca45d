#define _POSIX_C_SOURCE 200809L
#include "prw_core.h"

#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

bool prw_fail(prw_error *e, const char *fmt, ...)
{
    if (e) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(e->msg, sizeof e->msg, fmt, ap);
        va_end(ap);
    }
    return false;
}

bool prw_fail_wrap(prw_error *e, const char *fmt, ...)
{
    if (!e) return false;
    char prefix[PRW_ERROR_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    char old[PRW_ERROR_MAX];
    memcpy(old, e->msg, sizeof old);
    snprintf(e->msg, sizeof e->msg, "%.*s: %.*s", 400, prefix, 600, old);
    return false;
}

static prw_log_level g_level = PRW_LOG_INFO;

void prw_log_set_level(prw_log_level level) { g_level = level; }
prw_log_level prw_log_get_level(void) { return g_level; }

bool prw_log_parse_level(const char *s, prw_log_level *out)
{
    static const char *names[] = {"error", "warn", "info", "debug"};
    for (int i = 0; i < 4; i++) {
        if (strcmp(s, names[i]) == 0) {
            *out = (prw_log_level)i;
            return true;
        }
    }
    return false;
}

void prw_log(prw_log_level level, const char *fmt, ...)
{
    if (level > g_level) return;
    static const char *tags[] = {"error", "warning", "info", "debug"};
    fprintf(stderr, "prw: %s: ", tags[level]);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

static int g_threads = 0;

void prw_threads_set(int n)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (cores < 1) cores = 1;
    g_threads = n > 0 ? n : (int)cores;
    char buf[32];
    /* lavapipe: LP_NUM_THREADS is the number of rasterizer threads besides the caller. */
    snprintf(buf, sizeof buf, "%d", g_threads);
    setenv("LP_NUM_THREADS", buf, 1);
    setenv("OMP_NUM_THREADS", buf, 1);
}

int prw_threads_get(void)
{
    if (g_threads <= 0) prw_threads_set(0);
    return g_threads;
}

static void oom(size_t n)
{
    fprintf(stderr, "prw: error: out of host memory allocating %zu bytes\n", n);
    abort();
}

void *prw_malloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) oom(n);
    return p;
}

void *prw_calloc(size_t count, size_t size)
{
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p) oom(count * size);
    return p;
}

void *prw_realloc(void *p, size_t n)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) oom(n);
    return q;
}

char *prw_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = prw_malloc(n);
    memcpy(d, s, n);
    return d;
}

bool prw_read_file(const char *path, char **data, size_t *size, prw_error *e)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *buf = prw_malloc(cap + 1);
    for (;;) {
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap) {
            if (ferror(f)) {
                int err = errno;
                fclose(f);
                free(buf);
                return prw_fail(e, "%s: read error: %s", path, strerror(err));
            }
            break;
        }
        cap *= 2;
        buf = prw_realloc(buf, cap + 1);
    }
    fclose(f);
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return true;
}

bool prw_read_file_bounded(const char *path, uint64_t max_bytes, uint64_t expansion, const char *what, char **data,
                           size_t *size, prw_error *e)
{
    *data = NULL;
    *size = 0;
    if (expansion < 1) expansion = 1;
    uint64_t cap = prw_mem_budget() / expansion;
    if (max_bytes && max_bytes < cap) cap = max_bytes;
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0) {
        int err = errno;
        fclose(f);
        return prw_fail(e, "%s: cannot stat: %s", path, strerror(err));
    }
    if (S_ISDIR(st.st_mode)) {
        fclose(f);
        return prw_fail(e, "%s: cannot open: is a directory", path);
    }
    /* regular files are judged by their size; pipes and the like by what they deliver */
    uint64_t known = S_ISREG(st.st_mode) ? (uint64_t)st.st_size : 0;
    bool too_big = known > cap;
    size_t n = 0, alloc = (size_t)PRW_MIN(known ? known + 1 : (uint64_t)1 << 16, cap + 1);
    char *buf = too_big ? NULL : prw_malloc(alloc + 1);
    while (!too_big) {
        if (n == alloc) {
            if (alloc > cap) { /* more than the limit arrived */
                too_big = true;
                break;
            }
            alloc = (size_t)PRW_MIN((uint64_t)alloc * 2, cap + 1);
            buf = prw_realloc(buf, alloc + 1);
        }
        size_t got = fread(buf + n, 1, alloc - n, f);
        n += got;
        if (got == 0) {
            if (ferror(f)) {
                int err = errno;
                fclose(f);
                free(buf);
                return prw_fail(e, "%s: read error: %s", path, strerror(err));
            }
            break;
        }
    }
    if (n > cap) too_big = true;
    fclose(f);
    if (too_big) {
        free(buf);
        char have[32];
        if (max_bytes && cap == max_bytes) {
            if (known) return prw_fail(e, "%s: file of %llu bytes exceeds the limit of %llu bytes for %s", path,
                                       (unsigned long long)known, (unsigned long long)max_bytes, what);
            return prw_fail(e, "%s: more than the limit of %llu bytes for %s", path, (unsigned long long)max_bytes, what);
        }
        prw_mem_format(prw_mem_budget(), have, sizeof have);
        return prw_fail(e, "%s: %s of %llu bytes needs up to %llu times its size in memory, more than the memory budget "
                           "of %s (%s)",
                        path, what, (unsigned long long)(known ? known : n), (unsigned long long)expansion, have,
                        strcmp(prw_mem_budget_source(), "--max-memory") == 0 ? "set by --max-memory"
                                                                               : "available memory; see --max-memory");
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return true;
}

/* dir part of path ("." when there is none) */
static void dir_of(const char *path, char *dir, size_t cap)
{
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, cap, ".");
    else if (slash == path) snprintf(dir, cap, "/");
    else snprintf(dir, cap, "%.*s", (int)(slash - path), path);
}

/* Creates and removes probe (O_EXCL: never touches an existing file). */
static bool probe_create(const char *probe, int *err)
{
    int fd = open(probe, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        *err = errno;
        return false;
    }
    close(fd);
    unlink(probe);
    return true;
}

/* dir does not exist: the nearest existing ancestor must be a directory that takes new entries
 * (the command creates the missing levels). */
static bool ancestor_ok(const char *who, const char *dir, prw_error *e)
{
    char up[4096];
    struct stat st;
    snprintf(up, sizeof up, "%s", dir);
    for (;;) {
        char *slash = strrchr(up, '/');
        if (!slash) snprintf(up, sizeof up, ".");
        else if (slash == up) up[1] = '\0';
        else *slash = '\0';
        if (stat(up, &st) == 0) break;
        if ((errno != ENOENT && errno != ENOTDIR) || strcmp(up, ".") == 0 || strcmp(up, "/") == 0)
            return prw_fail(e, "%s: cannot write: directory %s: %s", who, up, strerror(errno));
    }
    if (!S_ISDIR(st.st_mode)) return prw_fail(e, "%s: cannot write: %s is not a directory", who, up);
    if (access(up, W_OK | X_OK) != 0)
        return prw_fail(e, "%s: cannot write: cannot create directories in %s: %s", who, up, strerror(errno));
    return true;
}

bool prw_check_writable(const char *path, bool create_parents, prw_error *e)
{
    if (!path || !path[0]) return prw_fail(e, "(empty path): cannot write: no file name");
    size_t len = strlen(path);
    if (path[len - 1] == '/') return prw_fail(e, "%s: cannot write: names a directory, not a file", path);
    struct stat st;
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) return prw_fail(e, "%s: cannot write: is a directory", path);
        if (!S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot write: not a regular file", path);
    }
    char dir[4096];
    if (len + 32 >= sizeof dir) return prw_fail(e, "%s: cannot write: path too long", path);
    dir_of(path, dir, sizeof dir);
    if (stat(dir, &st) != 0) {
        if (errno == ENOTDIR) return ancestor_ok(path, dir, e); /* names the file in the way */
        if (errno != ENOENT || !create_parents)
            return prw_fail(e, "%s: cannot write: directory %s: %s", path, dir, strerror(errno));
        return ancestor_ok(path, dir, e);
    }
    if (!S_ISDIR(st.st_mode)) return prw_fail(e, "%s: cannot write: %s is not a directory", path, dir);
    char probe[4200];
    snprintf(probe, sizeof probe, "%s.tmp-%ld", path, (long)getpid());
    int err = 0;
    if (!probe_create(probe, &err) && err != EEXIST)
        return prw_fail(e, "%s: cannot write: %s", path, strerror(err));
    return true;
}

bool prw_check_writable_dir(const char *dir, bool create, prw_error *e)
{
    if (!dir || !dir[0]) return prw_fail(e, "(empty path): cannot write: no directory name");
    if (strlen(dir) + 32 >= 4096) return prw_fail(e, "%s: cannot write: path too long", dir);
    struct stat st;
    if (stat(dir, &st) != 0) {
        if (errno == ENOTDIR) return ancestor_ok(dir, dir, e); /* names the file in the way */
        if (errno != ENOENT || !create) return prw_fail(e, "%s: cannot write: %s", dir, strerror(errno));
        return ancestor_ok(dir, dir, e);
    }
    if (!S_ISDIR(st.st_mode)) return prw_fail(e, "%s: cannot write: not a directory", dir);
    char probe[4200];
    snprintf(probe, sizeof probe, "%s/.prw-probe-%ld", dir, (long)getpid());
    int err = 0;
    if (!probe_create(probe, &err) && err != EEXIST) return prw_fail(e, "%s: cannot write: %s", dir, strerror(err));
    return true;
}

bool prw_write_file_atomic(const char *path, const void *data, size_t size, prw_error *e)
{
    size_t len = strlen(path) + 32;
    char *tmp = prw_malloc(len);
    snprintf(tmp, len, "%s.tmp-%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        bool r = prw_fail(e, "%s: cannot create: %s", path, strerror(errno));
        free(tmp);
        return r;
    }
    bool ok = fwrite(data, 1, size, f) == size;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0) {
        int err = errno;
        remove(tmp);
        free(tmp);
        return prw_fail(e, "%s: write failed: %s", path, strerror(err));
    }
    free(tmp);
    return true;
}

double prw_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

uint64_t prw_hash64(const void *data, size_t n, uint64_t seed)
{
    const unsigned char *p = data;
    uint64_t h = 1469598103934665603ull ^ seed;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

bool prw_mkdirs(const char *dir, prw_error *e)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf) return prw_fail(e, "%s: path too long", dir);
    for (char *p = buf + 1;; p++) {
        if (*p == '/' || *p == '\0') {
            char saved = *p;
            *p = '\0';
            if (mkdir(buf, 0755) != 0 && errno != EEXIST) return prw_fail(e, "%s: cannot create: %s", buf, strerror(errno));
            *p = saved;
            if (!saved) break;
        }
    }
    return true;
}
