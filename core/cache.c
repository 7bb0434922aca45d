/* cache.c — the content-addressed cache store (prw_cache.h). */
#define _POSIX_C_SOURCE 200809L
#include "prw_cache.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- keys ---- */

void prw_cache_key_begin(prw_cache_key *k, const char *tag)
{
    k->n = 0;
    prw_cache_key_add_str(k, tag);
}

void prw_cache_key_add(prw_cache_key *k, const void *data, size_t n)
{
    if (n > sizeof k->header - k->n) {
        /* headers are a few fixed fields written by our own code: overflowing one is a bug */
        fprintf(stderr, "prw: internal error: cache key header over %d bytes\n", PRW_CACHE_KEY_HEADER_MAX);
        abort();
    }
    if (n) memcpy(k->header + k->n, data, n);
    k->n += n;
}

void prw_cache_key_add_u64(prw_cache_key *k, uint64_t v)
{
    uint8_t t[8];
    for (int i = 0; i < 8; i++) t[i] = (uint8_t)(v >> (8 * i));
    prw_cache_key_add(k, t, 8);
}

void prw_cache_key_add_f64(prw_cache_key *k, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    prw_cache_key_add_u64(k, u);
}

void prw_cache_key_add_str(prw_cache_key *k, const char *s) { prw_cache_key_add(k, s, strlen(s) + 1); }

void prw_cache_key_finish(const prw_cache_key *k, const void *input, size_t n, char key[PRW_CACHE_KEY_LEN + 1])
{
    uint64_t a = prw_hash64(k->header, k->n, 0), b = prw_hash64(k->header, k->n, 0x9e3779b97f4a7c15ull);
    if (input) {
        a = prw_hash64(input, n, a);
        b = prw_hash64(input, n, b);
    }
    snprintf(key, PRW_CACHE_KEY_LEN + 1, "%016llx%016llx", (unsigned long long)a, (unsigned long long)b);
}

/* ---- names and paths ---- */

static bool name_ok(const char *s, size_t max, const char *extra, bool hex_only)
{
    size_t n = strlen(s);
    if (n == 0 || n > max) return false;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        bool ok = (c >= '0' && c <= '9') || (c >= 'a' && c <= (hex_only ? 'f' : 'z')) || (extra && c && strchr(extra, c));
        if (!ok) return false;
    }
    return true;
}

bool prw_cache_kind_valid(const char *kind) { return kind && name_ok(kind, 32, "_-", false); }
bool prw_cache_key_valid(const char *key) { return key && name_ok(key, 64, NULL, true); }
static bool ext_valid(const char *ext) { return ext && name_ok(ext, 16, NULL, false); }

bool prw_cache_root(char *buf, size_t cap, prw_error *e)
{
    const char *d = getenv("PRW_CACHE_DIR"), *x = getenv("XDG_CACHE_HOME"), *h = getenv("HOME");
    int n;
    if (d && d[0]) n = snprintf(buf, cap, "%s", d);
    else if (x && x[0]) n = snprintf(buf, cap, "%s/prw", x);
    else if (h && h[0]) n = snprintf(buf, cap, "%s/.cache/prw", h);
    else return prw_fail(e, "cache: no PRW_CACHE_DIR, XDG_CACHE_HOME or HOME");
    if (n < 0 || (size_t)n >= cap) return prw_fail(e, "cache: directory path too long");
    return true;
}

bool prw_cache_dir(const char *sub, const char *who, bool create, char *buf, size_t cap, prw_error *e)
{
    char root[4096];
    if (!prw_cache_root(root, sizeof root, e)) return prw_fail(e, "%s: no PRW_CACHE_DIR, XDG_CACHE_HOME or HOME", who);
    int n = snprintf(buf, cap, "%s/%s", root, sub);
    if (n < 0 || (size_t)n >= cap) return prw_fail(e, "%s: directory path too long", who);
    return !create || prw_mkdirs(buf, e);
}

bool prw_cache_path(const char *kind, const char *key, const char *ext, bool create_dir, char *buf, size_t cap,
                    prw_error *e)
{
    if (!prw_cache_kind_valid(kind)) return prw_fail(e, "cache: '%.64s' is not a cache kind ([a-z0-9_-], 1-32)", kind ? kind : "");
    if (!prw_cache_key_valid(key)) return prw_fail(e, "cache: '%.80s' is not a key (lowercase hex, 1-64)", key ? key : "");
    if (!ext_valid(ext)) return prw_fail(e, "cache: '%.32s' is not an entry extension ([a-z0-9], 1-16)", ext ? ext : "");
    char dir[4096];
    char who[64];
    snprintf(who, sizeof who, "%s cache", kind);
    if (!prw_cache_dir(kind, who, create_dir, dir, sizeof dir, e)) return false;
    int n = snprintf(buf, cap, "%s/%s.%s", dir, key, ext);
    if (n < 0 || (size_t)n >= cap) return prw_fail(e, "%s: entry path too long", who);
    return true;
}

bool prw_cache_store(const char *kind, const char *key, const char *ext, const void *data, size_t n, char *path,
                     size_t path_cap, prw_error *e)
{
    char p[4200];
    if (!prw_cache_path(kind, key, ext, true, p, sizeof p, e)) return false;
    if (path && path_cap) snprintf(path, path_cap, "%s", p);
    return prw_write_file_atomic(p, data, n, e);
}

/* ---- clearing ---- */

/* <key>.<ext>, <key>.<ext>.tmp-<digits> (prw_write_file_atomic) or <key>.<ext>.<digits>.tmp. */
static bool is_entry_name(const char *name)
{
    char buf[256];
    if (snprintf(buf, sizeof buf, "%s", name) >= (int)sizeof buf) return false;
    char *dot = strchr(buf, '.');
    if (!dot) return false;
    *dot = '\0';
    if (!prw_cache_key_valid(buf)) return false;
    char *ext = dot + 1, *rest = strchr(ext, '.');
    if (rest) *rest++ = '\0';
    if (!ext_valid(ext)) return false;
    if (!rest) return true;
    const char *digits = NULL;
    size_t len = strlen(rest);
    if (strncmp(rest, "tmp-", 4) == 0) digits = rest + 4, len -= 4;
    else if (len > 4 && strcmp(rest + len - 4, ".tmp") == 0) digits = rest, len -= 4;
    if (!digits || len == 0) return false;
    for (size_t i = 0; i < len; i++)
        if (digits[i] < '0' || digits[i] > '9') return false;
    return true;
}

static bool clear_dir(const char *dir, prw_cache_clear_report *r, prw_error *e)
{
    DIR *d = opendir(dir);
    if (!d) return prw_fail(e, "%s: cannot open: %s", dir, strerror(errno));
    bool ok = true;
    struct dirent *de;
    while ((de = readdir(d))) {
        if (!is_entry_name(de->d_name)) continue;
        char path[4400];
        if (snprintf(path, sizeof path, "%s/%s", dir, de->d_name) >= (int)sizeof path) continue;
        struct stat st;
        if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode)) continue;
        if (unlink(path) != 0) {
            if (errno == ENOENT) continue; /* another process removed or renamed it meanwhile */
            if (ok) ok = prw_fail(e, "%s: cannot remove: %s", path, strerror(errno));
            continue;
        }
        r->files++;
        r->bytes += (uint64_t)st.st_size;
    }
    closedir(d);
    r->kinds++;
    return ok;
}

/* The kinds present under root, ", "-separated, for messages. */
static void list_kinds(const char *root, char *buf, size_t cap)
{
    buf[0] = '\0';
    DIR *d = opendir(root);
    if (!d) return;
    struct dirent *de;
    size_t n = 0;
    while ((de = readdir(d))) {
        char path[4400];
        struct stat st;
        if (!prw_cache_kind_valid(de->d_name)) continue;
        if (snprintf(path, sizeof path, "%s/%s", root, de->d_name) >= (int)sizeof path) continue;
        if (lstat(path, &st) != 0 || !S_ISDIR(st.st_mode)) continue;
        int w = snprintf(buf + n, cap - n, "%s%s", n ? ", " : "", de->d_name);
        if (w < 0 || (size_t)w >= cap - n) break;
        n += (size_t)w;
    }
    closedir(d);
}

bool prw_cache_clear(const char *kind, prw_cache_clear_report *r, prw_error *e)
{
    memset(r, 0, sizeof *r);
    if (!prw_cache_root(r->root, sizeof r->root, e)) return false;
    struct stat st;
    if (kind) {
        if (!prw_cache_kind_valid(kind)) return prw_fail(e, "cache: '%.64s' is not a cache kind ([a-z0-9_-], 1-32)", kind);
        char dir[4200];
        snprintf(dir, sizeof dir, "%s/%s", r->root, kind);
        if (lstat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
            char kinds[512];
            list_kinds(r->root, kinds, sizeof kinds);
            return prw_fail(e, "%s: no cache kind '%s' (present: %s)", r->root, kind, kinds[0] ? kinds : "none");
        }
        return clear_dir(dir, r, e);
    }
    if (lstat(r->root, &st) != 0) {
        if (errno == ENOENT) return true; /* nothing cached yet */
        return prw_fail(e, "%s: %s", r->root, strerror(errno));
    }
    DIR *d = opendir(r->root);
    if (!d) return prw_fail(e, "%s: cannot open: %s", r->root, strerror(errno));
    bool ok = true;
    struct dirent *de;
    while ((de = readdir(d))) {
        if (!prw_cache_kind_valid(de->d_name)) continue;
        char dir[4400];
        if (snprintf(dir, sizeof dir, "%s/%s", r->root, de->d_name) >= (int)sizeof dir) continue;
        if (lstat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) continue;
        prw_error de_err;
        if (!clear_dir(dir, r, &de_err) && ok) ok = prw_fail(e, "%s", de_err.msg);
    }
    closedir(d);
    return ok;
}
