/* prw_env_file — build, encode, strict decode and the cache of the environment light (see the header). */
#include "prw_env_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_cache.h"

static const char env_magic[8] = {'P', 'R', 'W', 'E', 'N', 'V', '1', 0};

static void env_params_resolve(const prw_env_params *p, prw_env_params *r)
{
    *r = *p;
    if (!r->levels) r->levels = PRW_ENV_DEFAULT_LEVELS;
    if (!r->samples) r->samples = PRW_ENV_DEFAULT_SAMPLES;
    if (!r->dfg_size) r->dfg_size = PRW_ENV_DEFAULT_DFG;
}

/* Floats of the maps, or UINT64_MAX when the sizes are out of range. */
static uint64_t env_map_floats(uint32_t height, uint32_t levels)
{
    if (height < 1 || height > 16384 || levels < 1 || levels > 64) return UINT64_MAX;
    return (uint64_t)levels * height * 2 * height * 3;
}

void prw_env_data_free(prw_env_data *d)
{
    if (!d) return;
    free(d->dfg);
    free(d->maps);
    memset(d, 0, sizeof *d);
}

bool prw_env_data_build(const float *rgb, uint32_t w, uint32_t h, double scale, double rotation, uint64_t source_hash,
                        const prw_env_params *p, prw_env_data *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    prw_env_params r;
    env_params_resolve(p, &r);
    if (!isfinite(scale) || scale < 0 || !isfinite(rotation))
        return prw_fail(e, "environment: scale %g / rotation %g must be finite, scale >= 0", scale, rotation);
    if (r.dfg_size < 2 || r.dfg_size > 256) return prw_fail(e, "environment: DFG table size %u out of 2..256", r.dfg_size);
    uint64_t nf = env_map_floats(r.height, r.levels);
    if (nf == UINT64_MAX)
        return prw_fail(e, "environment: map height %u (1..16384) or levels %u (1..64) out of range", r.height,
                        r.levels);
    if (!prw_mem_check(prw_mul_sat(nf, sizeof(float)), "environment", "prefiltered maps", e)) return false;
    float sh[PRW_ENV_SH_COUNT][3];
    if (!prw_env_sh_project(rgb, w, h, sh, e)) return false;
    out->maps = prw_malloc((size_t)nf * sizeof(float));
    if (!prw_env_prefilter(rgb, w, h, r.height, r.levels, r.samples, out->maps, e)) {
        prw_env_data_free(out);
        return false;
    }
    for (uint64_t k = 0; k < nf; k++) out->maps[k] = (float)(out->maps[k] * scale);
    for (int i = 0; i < PRW_ENV_SH_COUNT; i++)
        for (int c = 0; c < 3; c++) out->sh[i][c] = (float)(sh[i][c] * scale);
    uint32_t N = r.dfg_size;
    out->dfg = prw_malloc((size_t)2 * N * N * sizeof(float));
    for (uint32_t i = 0; i < N; i++)
        for (uint32_t j = 0; j < N; j++) {
            double A, B;
            prw_env_dfg((i + 0.5) / N, (double)j / (N - 1), &A, &B);
            out->dfg[2 * ((size_t)i * N + j)] = (float)A;
            out->dfg[2 * ((size_t)i * N + j) + 1] = (float)B;
        }
    out->height = r.height;
    out->levels = r.levels;
    out->samples = r.samples;
    out->dfg_size = N;
    out->scale = scale;
    out->rotation = rotation;
    out->source_hash = source_hash;
    return true;
}

static void put32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; k++) p[k] = (uint8_t)(v >> (8 * k));
}
static void put64(uint8_t *p, uint64_t v)
{
    for (int k = 0; k < 8; k++) p[k] = (uint8_t)(v >> (8 * k));
}
static uint32_t get32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int k = 0; k < 4; k++) v |= (uint32_t)p[k] << (8 * k);
    return v;
}
static uint64_t get64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int k = 0; k < 8; k++) v |= (uint64_t)p[k] << (8 * k);
    return v;
}
static void putf(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put32(p, u);
}
static float getf(const uint8_t *p)
{
    uint32_t u = get32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}
static void putd(uint8_t *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put64(p, u);
}
static double getd(const uint8_t *p)
{
    uint64_t u = get64(p);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

/* Total file bytes for the sizes, or UINT64_MAX out of range. */
static uint64_t env_file_bytes(uint32_t height, uint32_t levels, uint32_t dfg_size)
{
    uint64_t nf = env_map_floats(height, levels);
    if (nf == UINT64_MAX || dfg_size < 2 || dfg_size > 256) return UINT64_MAX;
    return PRW_ENV_FILE_HEADER_BYTES + 4 * ((uint64_t)2 * dfg_size * dfg_size + nf) + 8;
}

bool prw_env_encode(const prw_env_data *d, uint8_t **buf, size_t *n, prw_error *e)
{
    uint64_t total = env_file_bytes(d->height, d->levels, d->dfg_size);
    if (total == UINT64_MAX) return prw_fail(e, "environment: cannot encode: sizes out of range");
    if (!prw_mem_check(total, "environment", "file", e)) return false;
    uint8_t *b = prw_malloc((size_t)total);
    memcpy(b, env_magic, 8);
    put32(b + 8, PRW_ENV_FILE_VERSION);
    put32(b + 12, d->height);
    put32(b + 16, d->levels);
    put32(b + 20, d->samples);
    put32(b + 24, d->dfg_size);
    put32(b + 28, 0);
    putd(b + 32, d->scale);
    putd(b + 40, d->rotation);
    put64(b + 48, d->source_hash);
    uint8_t *p = b + 56;
    for (int i = 0; i < PRW_ENV_SH_COUNT; i++)
        for (int c = 0; c < 3; c++, p += 4) putf(p, d->sh[i][c]);
    for (size_t k = 0; k < (size_t)2 * d->dfg_size * d->dfg_size; k++, p += 4) putf(p, d->dfg[k]);
    uint64_t nf = env_map_floats(d->height, d->levels);
    for (uint64_t k = 0; k < nf; k++, p += 4) putf(p, d->maps[k]);
    put64(p, prw_hash64(b, (size_t)(p - b), 0));
    *buf = b;
    *n = (size_t)total;
    return true;
}

bool prw_env_decode(const uint8_t *buf, size_t n, const char *name, prw_env_data *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (n < PRW_ENV_FILE_HEADER_BYTES + 8) return prw_fail(e, "%s: %zu bytes, shorter than the header", name, n);
    if (memcmp(buf, env_magic, 8) != 0) return prw_fail(e, "%s: not a prw environment file (magic)", name);
    uint32_t ver = get32(buf + 8);
    if (ver != PRW_ENV_FILE_VERSION)
        return prw_fail(e, "%s: version %u, this reader reads %u", name, ver, PRW_ENV_FILE_VERSION);
    uint32_t H = get32(buf + 12), K = get32(buf + 16), S = get32(buf + 20), N = get32(buf + 24);
    if (H < 1 || H > 16384) return prw_fail(e, "%s: height %u out of 1..16384", name, H);
    if (K < 1 || K > 64) return prw_fail(e, "%s: levels %u out of 1..64", name, K);
    if (S < 1 || S > (1u << 20)) return prw_fail(e, "%s: samples %u out of 1..1048576", name, S);
    if (N < 2 || N > 256) return prw_fail(e, "%s: DFG table size %u out of 2..256", name, N);
    if (get32(buf + 28) != 0) return prw_fail(e, "%s: reserved field is not 0", name);
    uint64_t total = env_file_bytes(H, K, N);
    if (total != n)
        return prw_fail(e, "%s: %zu bytes, the header's sizes (height %u, levels %u, DFG %u) need %llu", name, n, H, K,
                        N, (unsigned long long)total);
    if (get64(buf + n - 8) != prw_hash64(buf, n - 8, 0)) return prw_fail(e, "%s: checksum mismatch", name);
    double scale = getd(buf + 32), rot = getd(buf + 40);
    if (!isfinite(scale) || scale < 0 || !isfinite(rot)) return prw_fail(e, "%s: scale or rotation not valid", name);
    uint64_t nf = env_map_floats(H, K);
    if (!prw_mem_check(prw_mul_sat(nf + 2ull * N * N, sizeof(float)), name, "environment maps", e)) return false;
    const uint8_t *p = buf + 56;
    for (int i = 0; i < PRW_ENV_SH_COUNT; i++)
        for (int c = 0; c < 3; c++, p += 4) {
            out->sh[i][c] = getf(p);
            if (!isfinite(out->sh[i][c])) return prw_fail(e, "%s: SH coefficient %d/%d not finite", name, i, c);
        }
    out->dfg = prw_malloc((size_t)2 * N * N * sizeof(float));
    out->maps = prw_malloc((size_t)nf * sizeof(float));
    for (size_t k = 0; k < (size_t)2 * N * N; k++, p += 4) {
        out->dfg[k] = getf(p);
        if (!isfinite(out->dfg[k]) || out->dfg[k] < 0 || out->dfg[k] > 1.5f) {
            prw_env_data_free(out);
            return prw_fail(e, "%s: DFG entry %zu not in [0, 1.5]", name, k);
        }
    }
    for (uint64_t k = 0; k < nf; k++, p += 4) {
        out->maps[k] = getf(p);
        if (!isfinite(out->maps[k])) {
            prw_env_data_free(out);
            return prw_fail(e, "%s: map value %llu not finite", name, (unsigned long long)k);
        }
    }
    out->height = H;
    out->levels = K;
    out->samples = S;
    out->dfg_size = N;
    out->scale = scale;
    out->rotation = rot;
    out->source_hash = get64(buf + 48);
    return true;
}

void prw_env_cache_key(uint64_t source_hash, double scale, double rotation, const prw_env_params *p, char key[33])
{
    prw_env_params r;
    env_params_resolve(p, &r);
    prw_cache_key k;
    prw_cache_key_begin(&k, "prw-env-key");
    prw_cache_key_add_str(&k, PRW_ENV_ALGO_VERSION);
    prw_cache_key_add_u64(&k, PRW_ENV_FILE_VERSION);
    prw_cache_key_add_u64(&k, source_hash);
    prw_cache_key_add_f64(&k, scale);
    prw_cache_key_add_f64(&k, rotation);
    prw_cache_key_add_u64(&k, r.height);
    prw_cache_key_add_u64(&k, r.levels);
    prw_cache_key_add_u64(&k, r.samples);
    prw_cache_key_add_u64(&k, r.dfg_size);
    prw_cache_key_finish(&k, NULL, 0, key);
}

bool prw_env_cached(const float *rgb, uint32_t w, uint32_t h, double scale, double rotation, uint64_t source_hash,
                    const prw_env_params *p, prw_env_data *out, bool *from_cache, char *warning, size_t warning_cap,
                    prw_error *e)
{
    char key[33], path[4096];
    prw_error ce = {{0}};
    *from_cache = false;
    if (warning && warning_cap) warning[0] = 0;
    prw_env_cache_key(source_hash, scale, rotation, p, key);
    prw_env_params r;
    env_params_resolve(p, &r);
    uint64_t expect = env_file_bytes(r.height, r.levels, r.dfg_size);
    if (expect != UINT64_MAX && prw_cache_path("env", key, "env", false, path, sizeof path, &ce)) {
        FILE *f = fopen(path, "rb");
        if (f) {
            fclose(f);
            char *data = NULL;
            size_t n = 0;
            if (prw_read_file_bounded(path, expect, 1, "environment cache entry", &data, &n, &ce) &&
                prw_env_decode((const uint8_t *)data, n, path, out, &ce)) {
                free(data);
                *from_cache = true;
                return true;
            }
            free(data);
            if (warning) snprintf(warning, warning_cap, "environment cache entry not read, rebuilt: %s", ce.msg);
        }
    }
    if (!prw_env_data_build(rgb, w, h, scale, rotation, source_hash, p, out, e)) return false;
    uint8_t *buf = NULL;
    size_t n = 0;
    if (!prw_env_encode(out, &buf, &n, &ce) || !prw_cache_store("env", key, "env", buf, n, NULL, 0, &ce)) {
        if (warning && !warning[0]) snprintf(warning, warning_cap, "environment cache not written: %s", ce.msg);
    }
    free(buf);
    return true;
}
