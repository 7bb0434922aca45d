#define _POSIX_C_SOURCE 200809L
#include "prw_core.h"

#include <errno.h>
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
