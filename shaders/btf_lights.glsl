// btf_lights.glsl — direct light of every light of the per-view globals on a BTF surface (btf_eval.glsl),
// in cd/m^2.  The BTF stores f cos theta_l (radiance per lux of normal illuminance), so
//  - point / spot / directional: btf(v, l) x the light's normal illuminance (punctual_incidence:
//    intensity / d^2 with the range window and the spot cone), exactly the path tracer's direct term;
//  - rect area lights: btf(v, l_f) / cos theta_f x the exact irradiance (quad_irradiance, Lambert's
//    polygon formula clipped to the hemisphere), l_f the vector form factor's direction: exact for a
//    Lambertian BTF, one BTF evaluation per light;
// shadowed as the other kinds (shadows.glsl; rect lights from their one shadow map).  One loop over the
// lights (no written-out slots: a BTF evaluation is far costlier than the branches, and copies of it
// would slow the pipeline's JIT).  Needs common.glsl, shadows.glsl, lights.glsl and btf_eval.glsl first.
#ifndef PRW_BTF_LIGHTS_GLSL
#define PRW_BTF_LIGHTS_GLSL

// The BTF frame at a point: x, y (tangents), z the shading normal; xy the texel coordinates.
struct btf_frame {
    vec3 t, b, n;
    vec2 xy;
};

vec3 btf_to_local(btf_frame F, vec3 d) { return vec3(dot(d, F.t), dot(d, F.b), dot(d, F.n)); }

vec3 btf_light_one(btf_px X, btf_frame F, prw_gpu_light L, int type, bool shadowed, bool may_be_cube, vec3 p,
                   float shadow_offset)
{
    vec3 l;
    float E;
    if (type == PRW_GPU_LIGHT_RECT) {
        vec3 c = L.pos_type.xyz;
        if (dot(p - c, L.dir_range.xyz) <= 0.0) return vec3(0.0); // one-sided emitter
        vec3 q0, q1, q2, q3;
        rect_corners(L, q0, q1, q2, q3);
        E = quad_irradiance(p, F.n, q0, q1, q2, q3, l);
        float c_f = dot(F.n, l);
        if (E <= 0.0 || c_f <= 1e-4) return vec3(0.0);
        E /= c_f; // btf carries the cosine at l
    } else {
        punctual_incidence(L, type, p, l, E);
        if (dot(F.n, l) <= 0.0 || E <= 0.0) return vec3(0.0);
    }
    vec3 f = max(btf_eval_light(X, btf_to_local(F, l)), vec3(0.0)); // codec ringing below 0: no light
    return f * L.radiance.rgb * E * (shadowed ? shadow_factor(L, p, F.n, shadow_offset, may_be_cube) : 1.0);
}

// X: btf_setup at the fragment (the view's directions and the texels: once for every light)
void prw_btf_direct_light_px(inout vec3 radiance, btf_px X, btf_frame F, vec3 p, float shadow_offset)
{
    if (prw_lights_sorted) {
        for (int i = 0; i < PRW_N_LIGHTS; i++)
            radiance += btf_light_one(X, F, g.lights[i], PRW_SLOT_RECT(i) ? PRW_GPU_LIGHT_RECT : int(g.lights[i].pos_type.w),
                                      PRW_SLOT_SHADOWED(i), PRW_SLOT_CUBE(i), p, shadow_offset);
        return;
    }
    int count = int(g.params.x);
    for (int i = 0; i < count; i++) {
        prw_gpu_light L = g.lights[i];
        radiance += btf_light_one(X, F, L, int(L.pos_type.w), L.cone_shadow.z >= 0.0, true, p, shadow_offset);
    }
}

void prw_btf_direct_light(inout vec3 radiance, uint m, btf_frame F, vec3 p, vec3 v, float shadow_offset)
{
    prw_btf_direct_light_px(radiance, btf_setup(m, F.xy, btf_to_local(F, v)), F, p, shadow_offset);
}

#endif
