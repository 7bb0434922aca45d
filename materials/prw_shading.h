/* prw_shading.h — the shading rules around the BRDF that the rasterizer (GLSL 4.50, shaders/) and the
 * path tracer (C17, engine/reference) share, so a rule cannot drift between them: light falloff, the
 * glTF metallic-roughness texture channels, the tangent-space normal decode and the normal rules.
 * Like prw_brdf.h a scalar header: functions of scalars only; in C they compute in double (the path
 * tracer's precision), in GLSL in float.  Texture FILTERING is not shared: the GPU samples trilinearly
 * with mip maps, the path tracer bilinearly at full resolution (a documented difference).
 *
 * Rules:
 *  - Range window (point and spot lights with range r > 0): E *= clamp(1 - (d^2 / r^2)^2, 0, 1).
 *  - Spot cone: s = clamp((cos - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0, 1); E *= s^2.
 *  - Channels: roughness = factor * texel.g, metallic = factor * texel.b (glTF); base colour and
 *    emission = factor * texel (sRGB decoded before filtering).
 *  - Normal maps: n_tangent = ((t.x * 2 - 1) * scale, (t.y * 2 - 1) * scale, t.z * 2 - 1), normalised
 *    in the (tangent, bitangent = sign * n x tangent, normal) frame.
 *  - A double-sided material seen from its back shades with the flipped normal.
 *  - A shading normal n facing away from the viewer (n.v < 1e-4) is bent back: n += v * (1e-4 - n.v),
 *    then normalised, so the BRDF sees a valid configuration.
 */
#ifndef PRW_SHADING_H
#define PRW_SHADING_H

#ifdef GL_core_profile
#define PRW_SH_FN
#define prw_sh_real float
#define PRW_SH_CLAMP01(x) clamp((x), 0.0, 1.0)
#define PRW_SH_MAX(a, b) max((a), (b))
#else
#include <math.h>
#include <stdbool.h>
#define PRW_SH_FN static inline
#define prw_sh_real double
#define PRW_SH_CLAMP01(x) fmin(fmax((x), 0.0), 1.0)
#define PRW_SH_MAX(a, b) fmax((a), (b))
#endif

/* The smooth range window of a point or spot light at squared distance d2 (range > 0). */
PRW_SH_FN prw_sh_real prw_range_window(prw_sh_real d2, prw_sh_real range)
{
    prw_sh_real q = d2 / (range * range);
    return PRW_SH_CLAMP01(1.0 - q * q);
}

/* The spot cone factor for the cosine between the light's axis and the direction to the point. */
PRW_SH_FN prw_sh_real prw_spot_factor(prw_sh_real cos_axis, prw_sh_real cos_inner, prw_sh_real cos_outer)
{
    prw_sh_real s = PRW_SH_CLAMP01((cos_axis - cos_outer) / PRW_SH_MAX(cos_inner - cos_outer, 1e-4));
    return s * s;
}

PRW_SH_FN prw_sh_real prw_roughness_from(prw_sh_real factor, prw_sh_real texel_g) { return factor * texel_g; }
PRW_SH_FN prw_sh_real prw_metallic_from(prw_sh_real factor, prw_sh_real texel_b) { return factor * texel_b; }

/* One tangent-space normal component from its texel value: x and y with the material's normal scale,
 * z with scale 1. */
PRW_SH_FN prw_sh_real prw_normal_texel(prw_sh_real t, prw_sh_real scale) { return (t * 2.0 - 1.0) * scale; }

/* Whether the shading normal flips: a double-sided material seen from its back face. */
PRW_SH_FN bool prw_normal_flips(bool double_sided, bool front_facing) { return double_sided && !front_facing; }

/* How much of the view direction to add to a shading normal with n.v = n_dot_v (0: none). */
PRW_SH_FN prw_sh_real prw_normal_bend(prw_sh_real n_dot_v) { return n_dot_v < 1e-4 ? 1e-4 - n_dot_v : 0.0; }

#endif
