/* prw_env_file: round trip, the strict reader's refusals, the cache (miss, hit, a damaged entry
 * rebuilt, the key's parameters). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "prw_cache.h"
#include "prw_env_file.h"
#include "prw_test.h"

static float *small_map(uint32_t w, uint32_t h)
{
    float *m = prw_malloc((size_t)w * h * 3 * sizeof(float));
    for (size_t k = 0; k < (size_t)w * h * 3; k++) m[k] = (float)((k * 37 % 101) / 50.0);
    return m;
}

static bool data_equal(const prw_env_data *a, const prw_env_data *b)
{
    if (a->height != b->height || a->levels != b->levels || a->samples != b->samples || a->dfg_size != b->dfg_size ||
        a->scale != b->scale || a->rotation != b->rotation || a->source_hash != b->source_hash)
        return false;
    if (memcmp(a->sh, b->sh, sizeof a->sh) != 0) return false;
    if (memcmp(a->dfg, b->dfg, (size_t)2 * a->dfg_size * a->dfg_size * sizeof(float)) != 0) return false;
    return memcmp(a->maps, b->maps, (size_t)a->levels * a->height * 2 * a->height * 3 * sizeof(float)) == 0;
}

static void test_roundtrip_and_refusals(void)
{
    float *m = small_map(16, 8);
    prw_env_params p = {8, 3, 16, 4};
    prw_env_data d, r;
    prw_error e;
    CHECK_OK(prw_env_data_build(m, 16, 8, 2.0, 0.5, 0x1234, &p, &d, &e), &e);
    uint8_t *buf;
    size_t n;
    CHECK_OK(prw_env_encode(&d, &buf, &n, &e), &e);
    CHECK(n == PRW_ENV_FILE_HEADER_BYTES + 4 * (2 * 16 + 3 * 8 * 16 * 3) + 8);
    CHECK_OK(prw_env_decode(buf, n, "x.env", &r, &e), &e);
    CHECK(data_equal(&d, &r));
    prw_env_data_free(&r);
    /* scale is applied: the SH of the map x 2 */
    float sh[9][3];
    CHECK_OK(prw_env_sh_project(m, 16, 8, sh, &e), &e);
    CHECK_NEAR(d.sh[0][1], 2 * sh[0][1], 1e-5 * fabs(sh[0][1]));

    uint8_t *c = prw_malloc(n);
    /* each damaged copy is refused with a message naming the file */
    struct { size_t at; uint8_t val; const char *what; } cases[] = {
        {0, 'X', "magic"}, {8, 2, "version"}, {12, 0, "height"}, {16, 65, "levels"}, {24, 1, "DFG"},
        {28, 1, "reserved"}, {100, 0x55, "checksum"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        memcpy(c, buf, n);
        c[cases[k].at] = cases[k].val;
        CHECK_MSG(!prw_env_decode(c, n, "x.env", &r, &e), "case %s", cases[k].what);
        CHECK_MSG(strncmp(e.msg, "x.env: ", 7) == 0 && strstr(e.msg, cases[k].what), "%s", e.msg);
    }
    CHECK(!prw_env_decode(buf, n - 1, "x.env", &r, &e));
    CHECK(strstr(e.msg, "need") != NULL);
    CHECK(!prw_env_decode(buf, 10, "x.env", &r, &e));
    /* a NaN with a valid checksum: refused as not finite */
    memcpy(c, buf, n);
    float nan = NAN;
    memcpy(c + n - 12, &nan, 4);
    uint64_t h = prw_hash64(c, n - 8, 0);
    for (int k = 0; k < 8; k++) c[n - 8 + k] = (uint8_t)(h >> (8 * k));
    CHECK(!prw_env_decode(c, n, "x.env", &r, &e));
    CHECK(strstr(e.msg, "not finite") != NULL);
    /* a header claiming 16384 rows x 64 levels: refused from the sizes, nothing allocated */
    memcpy(c, buf, n);
    c[12] = 0, c[13] = 0x40, c[16] = 64;
    CHECK(!prw_env_decode(c, n, "x.env", &r, &e));
    free(c);
    free(buf);
    prw_env_data_free(&d);
    free(m);
}

static void test_cache(void)
{
    const char *dir = prw_test_path("cache");
    setenv("PRW_CACHE_DIR", dir, 1);
    float *m = small_map(16, 8);
    prw_env_params p = {8, 2, 16, 4};
    prw_env_data a, b;
    bool hit = true;
    char warn[2048];
    prw_error e;
    prw_cache_clear("env", &(prw_cache_clear_report){0}, &e);
    CHECK_OK(prw_env_cached(m, 16, 8, 1.0, 0.0, 77, &p, &a, &hit, warn, sizeof warn, &e), &e);
    CHECK(!hit);
    CHECK_MSG(warn[0] == 0, "%s", warn);
    CHECK_OK(prw_env_cached(m, 16, 8, 1.0, 0.0, 77, &p, &b, &hit, warn, sizeof warn, &e), &e);
    CHECK(hit);
    CHECK(data_equal(&a, &b));
    prw_env_data_free(&b);
    /* damage the entry: reported, rebuilt, stored over */
    char key[33], path[4096];
    prw_env_cache_key(77, 1.0, 0.0, &p, key);
    CHECK_OK(prw_cache_path("env", key, "env", false, path, sizeof path, &e), &e);
    char *data;
    size_t n;
    CHECK_OK(prw_read_file(path, &data, &n, &e), &e);
    data[n / 2] ^= 1;
    prw_test_write_file(path, data, n);
    free(data);
    CHECK_OK(prw_env_cached(m, 16, 8, 1.0, 0.0, 77, &p, &b, &hit, warn, sizeof warn, &e), &e);
    CHECK(!hit);
    CHECK_MSG(strstr(warn, "checksum") != NULL, "%s", warn);
    CHECK(data_equal(&a, &b));
    prw_env_data_free(&b);
    CHECK_OK(prw_env_cached(m, 16, 8, 1.0, 0.0, 77, &p, &b, &hit, warn, sizeof warn, &e), &e);
    CHECK(hit);
    prw_env_data_free(&b);
    /* every parameter of the build is in the key */
    char k2[33];
    prw_env_params q = p;
    q.height = 16;
    prw_env_cache_key(77, 1.0, 0.0, &q, k2);
    CHECK(strcmp(key, k2) != 0);
    prw_env_cache_key(78, 1.0, 0.0, &p, k2);
    CHECK(strcmp(key, k2) != 0);
    prw_env_cache_key(77, 1.5, 0.0, &p, k2);
    CHECK(strcmp(key, k2) != 0);
    prw_env_cache_key(77, 1.0, 0.1, &p, k2);
    CHECK(strcmp(key, k2) != 0);
    q = p;
    q.levels = 0; /* the default, 6, differs from 2 */
    prw_env_cache_key(77, 1.0, 0.0, &q, k2);
    CHECK(strcmp(key, k2) != 0);
    prw_env_data_free(&a);
    free(m);
}

static const prw_test_case cases[] = {
    {"roundtrip_and_refusals", test_roundtrip_and_refusals},
    {"cache", test_cache},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0])); }
