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
 *    then normalised, so the BRDF sees a valid configuration.  The same for the clear coat's normal.
 *  - Texture slots (prw_scene.h prw_tex_slot) read uv set 0 or 1; a slot reading set 1 on a mesh
 *    without TEXCOORD_1 reads set 0.  KHR_texture_transform then maps the pair (prw_uv_xf_u / _v):
 *      u' = o_u + c s_u u + s s_v v,  v' = o_v - s s_u u + c s_v v,  c = cos(rotation), s = sin(rotation)
 *    (the convention written in prw_scene.h at prw_tex_transform).
 *  - A normal map read through a transform: its x axis is the surface direction of increasing u', its
 *    y axis that of decreasing v' (as for an untransformed map), expressed in the (tangent, bitangent)
 *    frame of the mesh (which belongs to uv set 0): x-axis = normalize(c / s_u, -s / s_v),
 *    y-axis = normalize(s / s_u, c / s_v) (prw_normal_xf_t / _b; exact when the mesh's own uv mapping
 *    is conformal; identity without a transform).  A map on uv set 1 uses the same frame.
 *  - Alpha = base_color.a x texel.a; MASK keeps a fragment where alpha >= cutoff (glTF); BLEND uses
 *    alpha as coverage.
 *  - Clear coat: weight = factor x texel.r (clearcoatTexture), roughness = factor x texel.g
 *    (clearcoatRoughnessTexture), its normal map decoded like the base's with clearcoatNormalTexture's
 *    scale; without one, the coat's normal is the interpolated (flipped) surface normal, not the
 *    base's normal-mapped one.
 */
#ifndef PRW_SHADING_H
#define PRW_SHADING_H

#ifdef GL_core_profile
#define PRW_SH_FN
#define prw_sh_real float
#define PRW_SH_CLAMP01(x) clamp((x), 0.0, 1.0)
#define PRW_SH_MAX(a, b) max((a), (b))
#define PRW_SH_MIN(a, b) min((a), (b))
#define PRW_SH_SQRT(x) sqrt(x)
#else
#include <math.h>
#include <stdbool.h>
#define PRW_SH_FN static inline
#define prw_sh_real double
#define PRW_SH_CLAMP01(x) fmin(fmax((x), 0.0), 1.0)
#define PRW_SH_MAX(a, b) fmax((a), (b))
#define PRW_SH_MIN(a, b) fmin((a), (b))
#define PRW_SH_SQRT(x) sqrt(x)
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

/* KHR_texture_transform of (u, v) (see the rules above); c, s: cosine and sine of the rotation. */
PRW_SH_FN prw_sh_real prw_uv_xf_u(prw_sh_real u, prw_sh_real v, prw_sh_real o_u, prw_sh_real c, prw_sh_real s,
                                  prw_sh_real s_u, prw_sh_real s_v)
{
    return o_u + c * s_u * u + s * s_v * v;
}
PRW_SH_FN prw_sh_real prw_uv_xf_v(prw_sh_real u, prw_sh_real v, prw_sh_real o_v, prw_sh_real c, prw_sh_real s,
                                  prw_sh_real s_u, prw_sh_real s_v)
{
    return o_v - s * s_u * u + c * s_v * v;
}

/* A scale component as a divisor: sign kept, magnitude at least 1e-6 (a zero scale maps every uv to
 * one texel; its frame is then that of the limit). */
PRW_SH_FN prw_sh_real prw_xf_div(prw_sh_real scale) { return scale < 0.0 ? PRW_SH_MIN(scale, -1e-6) : PRW_SH_MAX(scale, 1e-6); }

/* The tangent (t) and bitangent (b) components of the decoded normal-map xy (x, y) of a slot read
 * through a transform (c, s, s_u, s_v); z is unchanged.  Without a transform: (x, y). */
PRW_SH_FN prw_sh_real prw_normal_xf_t(prw_sh_real x, prw_sh_real y, prw_sh_real c, prw_sh_real s, prw_sh_real s_u,
                                      prw_sh_real s_v)
{
    prw_sh_real iu = 1.0 / prw_xf_div(s_u), iv = 1.0 / prw_xf_div(s_v);
    prw_sh_real lx = PRW_SH_SQRT(c * c * iu * iu + s * s * iv * iv), ly = PRW_SH_SQRT(s * s * iu * iu + c * c * iv * iv);
    return x * (c * iu) / lx + y * (s * iu) / ly;
}
PRW_SH_FN prw_sh_real prw_normal_xf_b(prw_sh_real x, prw_sh_real y, prw_sh_real c, prw_sh_real s, prw_sh_real s_u,
                                      prw_sh_real s_v)
{
    prw_sh_real iu = 1.0 / prw_xf_div(s_u), iv = 1.0 / prw_xf_div(s_v);
    prw_sh_real lx = PRW_SH_SQRT(c * c * iu * iu + s * s * iv * iv), ly = PRW_SH_SQRT(s * s * iu * iu + c * c * iv * iv);
    return x * (-s * iv) / lx + y * (c * iv) / ly;
}

PRW_SH_FN prw_sh_real prw_alpha_from(prw_sh_real factor, prw_sh_real texel_a) { return factor * texel_a; }
/* MASK: whether the surface is there (glTF: alpha >= alphaCutoff is opaque, below is nothing). */
PRW_SH_FN bool prw_alpha_mask_keeps(prw_sh_real alpha, prw_sh_real cutoff) { return alpha >= cutoff; }
PRW_SH_FN prw_sh_real prw_clearcoat_from(prw_sh_real factor, prw_sh_real texel_r) { return factor * texel_r; }
PRW_SH_FN prw_sh_real prw_clearcoat_roughness_from(prw_sh_real factor, prw_sh_real texel_g) { return factor * texel_g; }

#endif
