/* prw_env — environment light precomputation (CPU): the spherical-harmonic irradiance and the
 * split-sum prefiltered specular maps of an equirectangular radiance map (issue 16).
 *
 * Promises:
 *  - Directions: the maps here are in MAP space, the convention of prw_environment
 *    (engine/scene/prw_scene.h): for a unit map direction d', u = 0.5 + atan2(d'.x, -d'.z) / (2 pi),
 *    v = acos(d'.y) / pi, row 0 = zenith +Y, pixel (i, j) covers u in [i/W, (i+1)/W), v in [j/H, (j+1)/H).
 *    A world direction d maps to d' = R_y(-rotation) d (the caller rotates; nothing here knows the
 *    scene).  Lookups are nearest-texel, as the path tracer's (engine/reference/ref_scene.c).
 *  - SH: real spherical harmonics of order 2 (l <= 2, 9 coefficients per channel, basis order
 *    Y00, Y1-1 (y), Y10 (z), Y11 (x), Y2-2 (xy), Y2-1 (yz), Y20 (3z^2-1), Y21 (xz), Y22 (x^2-y^2),
 *    x, y, z the map-space components).  The map being constant over a pixel, a coefficient is
 *    the sum of L times the basis integrated over the pixel, by the midpoint rule on 4 x 4 sub-pixels
 *    with their exact solid angles (a constant map: E = pi L to 3e-5 relative at 32 rows).  Irradiance
 *    E(n) = sum A_l L_lm Y_lm(n) with A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4 (Ramamoorthi & Hanrahan
 *    2001); for maps whose l >= 3 content is odd (a constant, a hemisphere step) this is exact, A_l
 *    being 0 for odd l >= 3.
 *  - Prefilter (split sum, Karis 2013): level k of `levels` has roughness r_k = k / (levels - 1)
 *    (levels = 1: r = 0) and alpha = prw_alpha_from_roughness(r_k) (prw_brdf.h, so r = 0 is alpha
 *    0.002); texel centre direction d gets
 *      P_k(d) = sum_s L(l_s) max(d.l_s, 0) / sum_s max(d.l_s, 0),  l_s = 2 (d.h_s) h_s - d,
 *    h_s drawn from D_GGX(alpha) around n = v = d with the Hammersley point set of `samples` points
 *    (fixed, no seed: the result depends on neither the thread count nor the run).  The weights are
 *    normalised per texel, so a constant map stays constant to float rounding, and the kernel depends
 *    on d.l only, so the sphere mean is kept up to the sampling error.
 *  - Directional albedo of our specular lobes for the split sum (prw_env_dfg): the single-scattering
 *    GGX lobe (D V_SmithGGXCorrelated, prw_brdf.h) integrated with Schlick's F split in F0:
 *      int f_ss cos dl = F0 A(mu, r) + B(mu, r),  A = int D V (1 - (1 - v.h)^5) cos,  B = int D V (1 - v.h)^5 cos,
 *    by GGX importance sampling of the half vector with PRW_ENV_DFG_SAMPLES Hammersley points.
 *  - Everything that fails returns false with e set; nothing prints.
 */
#ifndef PRW_ENV_H
#define PRW_ENV_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_ENV_SH_COUNT 9
#define PRW_ENV_DFG_SAMPLES 1024

/* Map direction of the map point (u, v) in [0,1]^2 (the inverse of the mapping above). */
void prw_env_uv_to_dir(double u, double v, double d[3]);
/* (u, v) of a unit map direction. */
void prw_env_dir_to_uv(const double d[3], double *u, double *v);
/* Nearest-texel lookup of an RGB float map (w x h, rows top down) in map direction d. */
void prw_env_lookup(const float *rgb, uint32_t w, uint32_t h, const double d[3], float out[3]);
/* Solid angle of a pixel of row j of an h-row map w pixels wide. */
double prw_env_pixel_solid_angle(uint32_t w, uint32_t h, uint32_t j);

/* The 9 basis functions at a unit direction, in the order above. */
void prw_env_sh_basis(const double d[3], double y[PRW_ENV_SH_COUNT]);
/* sh[i][c] = sum over pixels of L_c Y_i dOmega.  Fails on w < 2, h < 1, w x h x 3 overflowing, a
 * non-finite pixel (its position named). */
bool prw_env_sh_project(const float *rgb, uint32_t w, uint32_t h, float sh[PRW_ENV_SH_COUNT][3], prw_error *e);
/* Irradiance E(n) (same units as L times sr) at the unit normal n (map space). */
void prw_env_sh_irradiance(const float sh[PRW_ENV_SH_COUNT][3], const double n[3], float out[3]);

/* The Hammersley point (i / n, radical inverse of i in base 2). */
void prw_env_hammersley(uint32_t i, uint32_t n, double *x1, double *x2);

/* Prefiltered maps: out has levels x out_h x (2 out_h) x 3 floats (level-major, rows top down),
 * filled from the w x h source as promised above, on prw_threads_get() threads.  Fails on sizes out
 * of range (out_h in [1, 16384], levels in [1, 64], samples in [1, 1 << 20], source as for
 * prw_env_sh_project) or a non-finite pixel. */
bool prw_env_prefilter(const float *rgb, uint32_t w, uint32_t h, uint32_t out_h, uint32_t levels, uint32_t samples,
                       float *out, prw_error *e);
/* Roughness of level k of `levels`. */
double prw_env_level_roughness(uint32_t k, uint32_t levels);

/* A and B of the split sum at mu = n.v in (0, 1] and roughness in [0, 1] (see above). */
void prw_env_dfg(double mu, double roughness, double *A, double *B);

#ifdef __cplusplus
}
#endif
#endif
