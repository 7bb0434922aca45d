/* prw_brdf.h — THE material model, one source for the rasterizer (GLSL 4.50) and the CPU side
 * (C17: path tracer, tests).  Keep it a scalar header: functions of cosines and scalars only, one
 * colour channel at a time, no vector types, no samplers.  A test (tests/render/test_brdf_gpu.c)
 * evaluates it on the GPU and on the CPU for 10^4 random configurations.
 *
 * Model (glTF metallic-roughness):
 *   alpha = roughness^2 (clamped to PRW_MIN_ALPHA so the GGX lobe stays finite)
 *   f0    = mix(0.04 * specular, base, metallic)   (specular: KHR_materials_specular factor, default 1)
 *   f     = (1 - metallic) * base / pi                      (Lambert)
 *         + D_GGX(n.h) * V_SmithGGXCorrelated(n.v, n.l) * F_Schlick(f0, v.h)
 * Units: f is in 1/sr; outgoing luminance L_o = f * E_perp * cos(theta_l) for a light giving
 * illuminance E_perp (lux) at normal incidence.
 * Not yet here (issue 3): multiple-scattering energy compensation and the reciprocal diffuse
 * weighting by (1 - E_spec); until then dielectrics can reflect up to ~4 % more than they receive.
 */
#ifndef PRW_BRDF_H
#define PRW_BRDF_H

#ifdef GL_core_profile
#define PRW_FN
#define PRW_B_SQRT(x) sqrt(x)
#define PRW_B_MAX(a, b) max((a), (b))
#define PRW_B_MIN(a, b) min((a), (b))
#define PRW_B_POW5(x) ((x) * (x) * (x) * (x) * (x))
#define PRW_B_CONST const
#else
#include <math.h>
#define PRW_FN static inline
#define PRW_B_SQRT(x) sqrtf(x)
#define PRW_B_MAX(a, b) fmaxf((a), (b))
#define PRW_B_MIN(a, b) fminf((a), (b))
#define PRW_B_POW5(x) ((x) * (x) * (x) * (x) * (x))
#define PRW_B_CONST static const
#endif

PRW_B_CONST float PRW_BRDF_PI = 3.14159265358979323846;
PRW_B_CONST float PRW_MIN_ALPHA = 0.002;
PRW_B_CONST float PRW_DIELECTRIC_F0 = 0.04;

PRW_FN float prw_clamp01(float x) { return PRW_B_MIN(PRW_B_MAX(x, 0.0), 1.0); }

PRW_FN float prw_alpha_from_roughness(float roughness)
{
    float r = prw_clamp01(roughness);
    return PRW_B_MAX(r * r, PRW_MIN_ALPHA);
}

/* GGX / Trowbridge-Reitz normal distribution, normalised so that int D(h) (n.h) dh = 1. */
PRW_FN float prw_D_ggx(float NoH, float alpha)
{
    float a2 = alpha * alpha;
    float d = NoH * NoH * (a2 - 1.0) + 1.0;
    return a2 / (PRW_BRDF_PI * d * d);
}

/* Height-correlated Smith visibility V = G2 / (4 n.l n.v). */
PRW_FN float prw_V_smith_ggx(float NoV, float NoL, float alpha)
{
    float a2 = alpha * alpha;
    float gv = NoL * PRW_B_SQRT(NoV * NoV * (1.0 - a2) + a2);
    float gl = NoV * PRW_B_SQRT(NoL * NoL * (1.0 - a2) + a2);
    return 0.5 / PRW_B_MAX(gv + gl, 1e-12);
}

PRW_FN float prw_F_schlick(float f0, float VoH)
{
    float m = prw_clamp01(1.0 - VoH);
    return f0 + (1.0 - f0) * PRW_B_POW5(m);
}

PRW_FN float prw_lambert(float rho) { return rho / PRW_BRDF_PI; }

/* Full BRDF for one channel.  Cosines are clamped; returns 0 below either horizon. */
PRW_FN float prw_f0(float base, float metallic, float specular)
{
    float d = PRW_DIELECTRIC_F0 * prw_clamp01(specular);
    return d + (base - d) * prw_clamp01(metallic);
}

PRW_FN float prw_brdf_channel(float NoV, float NoL, float NoH, float VoH, float base, float metallic,
                              float roughness, float specular)
{
    if (NoL <= 0.0 || NoV <= 0.0) return 0.0;
    float alpha = prw_alpha_from_roughness(roughness);
    float m = prw_clamp01(metallic);
    float f0 = prw_f0(base, m, specular);
    float spec = prw_D_ggx(prw_clamp01(NoH), alpha) * prw_V_smith_ggx(NoV, NoL, alpha) * prw_F_schlick(f0, prw_clamp01(VoH));
    return (1.0 - m) * prw_lambert(base) + spec;
}

#endif
