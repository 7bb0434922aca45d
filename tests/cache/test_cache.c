/* core/prw_cache.h — the content-addressed cache store.
 *  - key_formula: a key is the documented composition of two FNV-1a hashes, recomputed here from the
 *    FNV-1a definition (prime 1099511628211; the loop checked against the published vector for "a"
 *    with the published offset basis, then run with prw_hash64's basis, see prw_core.h); every header
 *    or input byte changes it; no input = header alone;
 *  - names_and_paths: kinds / keys / extensions outside their alphabets are refused (no "../");
 *    <cache>/<kind>/<key>.<ext> with $PRW_CACHE_DIR before $XDG_CACHE_HOME/prw before
 *    $HOME/.cache/prw, and a message when none is set;
 *  - store: creates the kind's directory, writes the bytes, leaves no temporary file, replaces an
 *    entry; an invalid name writes nothing;
 *  - clear: removes exactly the entry files (and leftovers of interrupted writes) of one kind or of
 *    every kind — never a decoy (other names, upper case, directories, a symbolic link or its
 *    target, a directory that is not a kind); reports files and bytes; an unknown kind fails and
 *    names the kinds present; a missing cache is not an error. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "prw_cache.h"
#include "prw_test.h"

/* FNV-1a 64 from its definition, with a given offset basis. */
static uint64_t fnv1a_basis(const void *d, size_t n, uint64_t basis)
{
    const unsigned char *p = d;
    uint64_t h = basis;
    for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

/* prw_hash64: basis 1469598103934665603 (prw_core.h) XOR the seed. */
static uint64_t fnv1a(const void *d, size_t n, uint64_t seed) { return fnv1a_basis(d, n, 1469598103934665603ull ^ seed); }

static void test_key_formula(void)
{
    CHECK(fnv1a_basis("a", 1, 14695981039346656037ull) == 0xaf63dc4c8601ec8cull); /* the published vector */
    prw_cache_key k;
    prw_cache_key_begin(&k, "tag-1");
    prw_cache_key_add_u64(&k, 0x0102030405060708ull);
    prw_cache_key_add_f64(&k, 1.5);
    prw_cache_key_add_str(&k, "s");
    /* the same header written by hand: "tag-1\0", u64 LE, the bits of 1.5 LE, "s\0" */
    unsigned char hdr[6 + 8 + 8 + 2] = {'t', 'a', 'g', '-', '1', 0, 8, 7, 6, 5, 4, 3, 2, 1, 0, 0, 0, 0, 0, 0, 0xf8, 0x3f,
                                        's', 0};
    CHECK(k.n == sizeof hdr && memcmp(k.header, hdr, sizeof hdr) == 0);
    char key[PRW_CACHE_KEY_LEN + 1], want[PRW_CACHE_KEY_LEN + 1];
    prw_cache_key_finish(&k, "input", 5, key);
    uint64_t a = fnv1a("input", 5, fnv1a(hdr, sizeof hdr, 0)), b = fnv1a("input", 5, fnv1a(hdr, sizeof hdr, 0x9e3779b97f4a7c15ull));
    snprintf(want, sizeof want, "%016llx%016llx", (unsigned long long)a, (unsigned long long)b);
    CHECK_MSG(strcmp(key, want) == 0, "%s vs %s", key, want);
    CHECK(strlen(key) == PRW_CACHE_KEY_LEN && prw_cache_key_valid(key));
    prw_cache_key_finish(&k, NULL, 0, key);
    snprintf(want, sizeof want, "%016llx%016llx", (unsigned long long)fnv1a(hdr, sizeof hdr, 0),
             (unsigned long long)fnv1a(hdr, sizeof hdr, 0x9e3779b97f4a7c15ull));
    CHECK(strcmp(key, want) == 0);
    /* every byte matters */
    char k0[33], k1[33];
    prw_cache_key_finish(&k, "input", 5, k0);
    prw_cache_key_finish(&k, "inpuT", 5, k1);
    CHECK(strcmp(k0, k1) != 0);
    for (size_t i = 0; i < k.n; i++) {
        prw_cache_key c = k;
        c.header[i] ^= 1;
        prw_cache_key_finish(&c, "input", 5, k1);
        CHECK(strcmp(k0, k1) != 0);
    }
}

static void test_names_and_paths(void)
{
    CHECK(prw_cache_kind_valid("lod") && prw_cache_kind_valid("light_maps-2") && !prw_cache_kind_valid("") &&
          !prw_cache_kind_valid("..") && !prw_cache_kind_valid("a/b") && !prw_cache_kind_valid("Lod") &&
          !prw_cache_kind_valid("abcdefghijabcdefghijabcdefghijabc"));
    CHECK(prw_cache_key_valid("0123abcdef") && !prw_cache_key_valid("0123ABCDEF") && !prw_cache_key_valid("xyz") &&
          !prw_cache_key_valid(""));
    char p[4096];
    prw_error e;
    setenv("PRW_CACHE_DIR", "/c/prw", 1);
    setenv("XDG_CACHE_HOME", "/x", 1);
    setenv("HOME", "/h", 1);
    CHECK_OK(prw_cache_path("lod", "00ff", "lod", false, p, sizeof p, &e), &e);
    CHECK(strcmp(p, "/c/prw/lod/00ff.lod") == 0);
    unsetenv("PRW_CACHE_DIR");
    CHECK_OK(prw_cache_path("refs", "0a", "exr", false, p, sizeof p, &e), &e);
    CHECK(strcmp(p, "/x/prw/refs/0a.exr") == 0);
    unsetenv("XDG_CACHE_HOME");
    CHECK_OK(prw_cache_path("views", "0b", "json", false, p, sizeof p, &e), &e);
    CHECK(strcmp(p, "/h/.cache/prw/views/0b.json") == 0);
    unsetenv("HOME");
    CHECK(!prw_cache_path("lod", "0b", "lod", false, p, sizeof p, &e) && strstr(e.msg, "PRW_CACHE_DIR"));
    setenv("PRW_CACHE_DIR", "/c", 1);
    CHECK(!prw_cache_path("../etc", "0b", "lod", false, p, sizeof p, &e) && strstr(e.msg, "'../etc' is not a cache kind"));
    CHECK(!prw_cache_path("lod", "0b/..", "lod", false, p, sizeof p, &e) && strstr(e.msg, "is not a key"));
    CHECK(!prw_cache_path("lod", "0b", "l/d", false, p, sizeof p, &e) && strstr(e.msg, "extension"));
    char small[12];
    CHECK(!prw_cache_path("lod", "0b", "lod", false, small, sizeof small, &e) && strstr(e.msg, "too long"));
}

static bool exists(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0;
}

static void put(const char *dir, const char *name, size_t n)
{
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    char *d = calloc(n + 1, 1);
    prw_test_write_file(p, d, n);
    free(d);
}

static void test_store(void)
{
    char root[1024], p[4096], dir[1100];
    snprintf(root, sizeof root, "%s", prw_test_path("store-cache"));
    setenv("PRW_CACHE_DIR", root, 1);
    prw_error e;
    CHECK_OK(prw_cache_store("lod", "abc123", "lod", "hello", 5, p, sizeof p, &e), &e);
    char want[2048];
    snprintf(want, sizeof want, "%s/lod/abc123.lod", root);
    CHECK(strcmp(p, want) == 0);
    char *d;
    size_t n;
    CHECK_OK(prw_read_file(p, &d, &n, &e), &e);
    CHECK(n == 5 && memcmp(d, "hello", 5) == 0);
    free(d);
    CHECK_OK(prw_cache_store("lod", "abc123", "lod", "bye", 3, NULL, 0, &e), &e); /* replaces */
    CHECK_OK(prw_read_file(p, &d, &n, &e), &e);
    CHECK(n == 3 && memcmp(d, "bye", 3) == 0);
    free(d);
    snprintf(dir, sizeof dir, "%s/lod", root);
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp-%ld", p, (long)getpid());
    CHECK(!exists(tmp));
    CHECK(!prw_cache_store("Bad", "abc123", "lod", "x", 1, NULL, 0, &e) && strstr(e.msg, "'Bad'"));
    snprintf(tmp, sizeof tmp, "%s/Bad", root);
    CHECK(!exists(tmp));
}

static void test_clear(void)
{
    char root[1024], a[1100], b[1100], up[1100], outside[1100], link[1200], sub[1200];
    snprintf(root, sizeof root, "%s", prw_test_path("clear-cache"));
    snprintf(a, sizeof a, "%s/a", root);
    snprintf(b, sizeof b, "%s/b", root);
    snprintf(up, sizeof up, "%s/UPPER", root);
    prw_error e;
    setenv("PRW_CACHE_DIR", root, 1);
    prw_cache_clear_report r;
    CHECK_OK(prw_cache_clear(NULL, &r, &e), &e); /* no cache yet */
    CHECK(r.files == 0 && r.kinds == 0);
    CHECK(prw_mkdirs(a, &e) && prw_mkdirs(b, &e) && prw_mkdirs(up, &e));
    /* entries: removed */
    put(a, "abcd.lod", 10);
    put(a, "0123.exr", 20);
    put(a, "abcd.lod.tmp-123", 30);
    put(a, "abcd.lod.77.tmp", 40);
    put(b, "ff.json", 7);
    /* decoys: kept */
    const char *decoys[] = {"readme.txt", "ABCD.lod", "abcd.LOD", "abcd", "abcd.lod.tmp-", "abcd.lod.tmp-12x", "xyz.lod",
                            "abcd.lod.tmp", ".abcd.lod"};
    for (size_t i = 0; i < PRW_ARRAY_LEN(decoys); i++) put(a, decoys[i], 3);
    snprintf(sub, sizeof sub, "%s/beef.lod", a);
    CHECK(prw_mkdirs(sub, &e));
    snprintf(outside, sizeof outside, "%s", prw_test_path("outside.lod"));
    prw_test_write_file(outside, "keep", 4);
    snprintf(link, sizeof link, "%s/cafe.lod", a);
    CHECK(symlink("../../outside.lod", link) == 0);
    put(up, "abcd.lod", 5); /* not a kind directory: never visited */

    CHECK(!prw_cache_clear("nope", &r, &e) && strstr(e.msg, "no cache kind 'nope'") && strstr(e.msg, "a") &&
          strstr(e.msg, "b"));
    CHECK(!prw_cache_clear("../clear-cache/a", &r, &e) && strstr(e.msg, "is not a cache kind"));
    CHECK_OK(prw_cache_clear("a", &r, &e), &e);
    CHECK_MSG(r.files == 4 && r.bytes == 100 && r.kinds == 1, "files %llu bytes %llu kinds %u",
              (unsigned long long)r.files, (unsigned long long)r.bytes, r.kinds);
    char p[1300];
    const char *gone[] = {"abcd.lod", "0123.exr", "abcd.lod.tmp-123", "abcd.lod.77.tmp"};
    for (size_t i = 0; i < PRW_ARRAY_LEN(gone); i++) {
        snprintf(p, sizeof p, "%s/%s", a, gone[i]);
        CHECK_MSG(!exists(p), "%s", p);
    }
    for (size_t i = 0; i < PRW_ARRAY_LEN(decoys); i++) {
        snprintf(p, sizeof p, "%s/%s", a, decoys[i]);
        CHECK_MSG(exists(p), "%s", p);
    }
    CHECK(exists(sub) && exists(link) && exists(outside));
    snprintf(p, sizeof p, "%s/ff.json", b);
    CHECK(exists(p)); /* another kind: untouched */
    CHECK_OK(prw_cache_clear(NULL, &r, &e), &e);
    CHECK(r.files == 1 && r.bytes == 7 && r.kinds == 2);
    CHECK(!exists(p));
    snprintf(p, sizeof p, "%s/abcd.lod", up);
    CHECK(exists(p) && exists(outside) && exists(link));
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"key_formula", test_key_formula},
        {"names_and_paths", test_names_and_paths},
        {"store", test_store},
        {"clear", test_clear},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
