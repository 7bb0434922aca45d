/* prw_env_file — the environment light as the renderer reads it: the SH irradiance, the prefiltered
 * specular levels and the split-sum albedo table in one versioned file, stored in the content-
 * addressed cache (core/prw_cache.h, kind "env", extension "env").
 *
 * Layout (version 1, little-endian, no padding):
 *   0   char[8]  "PRWENV1\0"
 *   8   u32      version (1)
 *   12  u32      height H of every level (width 2H), 1..16384
 *   16  u32      levels K, 1..64 (level k: roughness k / (K - 1); K = 1: roughness 0)
 *   20  u32      samples per texel of the prefilter, 1..2^20 (informative)
 *   24  u32      DFG table size N, 2..256
 *   28  u32      reserved, 0
 *   32  f64      scale (applied: every value below is in cd/m^2, resp. lux for the SH irradiance)
 *   40  f64      rotation (radians about +Y; NOT applied: the maps are in map space)
 *   48  u64      FNV-1a hash of the source file's bytes
 *   56  f32[27]  SH radiance coefficients sh[i][c] (prw_env.h's basis order), i-major
 *   164 f32[2N^2] DFG table: entry (i, j) = A, B at mu = (i + 0.5) / N, roughness j / (N - 1), i-major
 *   ... f32[K H 2H 3] prefiltered levels, level-major, rows top down (prw_env_prefilter)
 *   end u64      FNV-1a (prw_hash64, seed 0) of every byte before it
 * The reader checks the magic, version, every size against its range and the file's length, and the
 * total against the memory budget before allocating, then the checksum, then that every float is
 * finite; any failure is one line "<name>: <what>".
 *
 * What the renderer computes from it (the split sum with our model, prw_brdf.h), for a surface point
 * with unit normal n, unit view vector v (towards the eye), mu = max(n.v, 1e-4), R = 2 (n.v) n - v,
 * base colour b, metallic m, roughness r, specular s; every direction first taken to map space,
 * d' = R_y(-rotation) d (prw_environment's convention):
 *   E_irr(n)  = sum_i A_l sh[i] Y_i(n')            (prw_env_sh_irradiance; A_l = pi, 2pi/3, pi/4)
 *   P(r, R)   = the levels interpolated linearly in roughness at r (k = r (K - 1)), each read at R'
 *   dielectric: E_ds(mu) = s Ed(mu, r) + F_ms(s F_avg_d, Ec_avg(r)) Ec(mu, r)   (prw_brdf.h's fits)
 *   metal:      E_m(mu)  = F0 A(mu, r) + B(mu, r) + F_ms((20 F0 + 1) / 21, Ec_avg(r)) Ec(mu, r), F0 = b
 *   L_o = (1 - m) [ b (1 - E_ds(mu)) E_irr(n) / pi + E_ds(mu) P(r, R) ] + m E_m(mu) P(r, R)
 * (per colour channel; times the per-texel visibility when that is baked).  The approximations are the
 * split sum's (the lobe's shape at n = v = R, the incident weight (1 - E_ds(mu_i)) / (1 - E_ds_avg) of
 * the diffuse lobe replaced by its mean 1) and SH9's truncation: the check is the path tracer's
 * `--filter environment-direct` (engine/reference/prw_reference.h).
 */
#ifndef PRW_ENV_FILE_H
#define PRW_ENV_FILE_H

#include "prw_core.h"
#include "prw_env.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_ENV_FILE_VERSION 1u
#define PRW_ENV_FILE_HEADER_BYTES 164u
/* The algorithm version: part of the cache key, changed whenever what a key's entry holds changes. */
#define PRW_ENV_ALGO_VERSION "env-2026-12-06a"
#define PRW_ENV_DEFAULT_LEVELS 6u
#define PRW_ENV_DEFAULT_SAMPLES 256u
#define PRW_ENV_DEFAULT_DFG 32u

typedef struct prw_env_data {
    uint32_t height, levels, samples, dfg_size;
    double scale, rotation;
    uint64_t source_hash;
    float sh[PRW_ENV_SH_COUNT][3];
    float *dfg;  /* 2 N^2 */
    float *maps; /* K H 2H 3 */
} prw_env_data;

typedef struct prw_env_params {
    uint32_t height;   /* the quality knob envmap_size (engine/render/prw_quality.h) */
    uint32_t levels;   /* 0: PRW_ENV_DEFAULT_LEVELS */
    uint32_t samples;  /* 0: PRW_ENV_DEFAULT_SAMPLES */
    uint32_t dfg_size; /* 0: PRW_ENV_DEFAULT_DFG */
} prw_env_params;

/* Builds everything from the decoded source (w x h RGB floats, the file's values): the maps and SH
 * of value x scale.  Fails as prw_env_prefilter / prw_env_sh_project, on a non-finite or negative
 * scale, or when the result does not fit the memory budget. */
bool prw_env_data_build(const float *rgb, uint32_t w, uint32_t h, double scale, double rotation, uint64_t source_hash,
                        const prw_env_params *p, prw_env_data *out, prw_error *e);
void prw_env_data_free(prw_env_data *d);

/* The file bytes (caller frees *buf). */
bool prw_env_encode(const prw_env_data *d, uint8_t **buf, size_t *n, prw_error *e);
/* Strict reader (see the top); name prefixes the errors.  On failure out holds nothing. */
bool prw_env_decode(const uint8_t *buf, size_t n, const char *name, prw_env_data *out, prw_error *e);

/* The cache key (32 hex digits) of a build: tag "prw-env-key", PRW_ENV_ALGO_VERSION, file format
 * version, source hash, scale, rotation, and the resolved params. */
void prw_env_cache_key(uint64_t source_hash, double scale, double rotation, const prw_env_params *p,
                       char key[33]);

/* Looks the build up in the cache (kind "env"); on a miss, or an entry that does not read back
 * (reported in *warning, rebuilt and stored over), builds and stores it.  A cache that cannot be
 * written is a warning too.  *from_cache tells whether the entry was read.  warning may be NULL. */
bool prw_env_cached(const float *rgb, uint32_t w, uint32_t h, double scale, double rotation, uint64_t source_hash,
                    const prw_env_params *p, prw_env_data *out, bool *from_cache, char *warning, size_t warning_cap,
                    prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
