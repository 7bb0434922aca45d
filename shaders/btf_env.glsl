// btf_env.glsl — the BTF kind's environment term (issue 17): the environment light reaching the surface
// directly and leaving it towards the eye after one scattering (the reference's environment-direct
// paths), through the BTF as the path tracer interpolates it (prw_btf_interp.h): with w_k(l) the
// interpolation weight of measured light direction k,
//   L = int BTF(v, l) L_env(l) dl = sum_k f(v, l_k) int w_k(l) L_env(l) dl ~ sum_k f(v, l_k) A_k P(r_k, c_k),
// f at the fragment's 3 view directions and 4 texels (btf_setup's), A_k = int w_k dl, c_k the weight's
// centroid and r_k the prefilter roughness of its width (the material's environment table,
// engine/render/prw_btf_gpu.h), P the prefiltered environment levels (gi_env.glsl).  What is left is the
// prefilter's kernel standing in for w_k's shape.  Times vis, the light maps' environment visibility
// (prw_env_visibility: the unoccluded fraction of the environment's irradiance; 1 without light maps),
// one factor for the whole sum (the BTF reflects mostly diffusely; the open cone that gi_env.glsl uses
// for the specular lobe is not used here).  Mirror images draw it only in the light-map variants, as
// gi_env.glsl.  PRW_SC_ENV = 0 or the term off: nothing (the specialisation removes the code).
// Needs gi_env.glsl, btf_eval.glsl and btf_lights.glsl first.
#ifndef PRW_BTF_ENV_GLSL
#define PRW_BTF_ENV_GLSL

vec3 prw_btf_env_light(btf_px X, btf_frame F, uint m, float vis)
{
    if (prw_env_on == 0 || (prw_terms & PRW_TERM_ENVIRONMENT) == 0) return vec3(0.0);
#ifndef PRW_GI
    if (g.params.z > 0.5) return vec3(0.0);
#endif
    uint tab = PRW_BTF_BLOB(m + 19u);
    vec3 s = vec3(0.0);
    for (uint k = 0u; k < X.H.lights; k++) {
        uint o = tab + 5u * k;
        vec3 c = vec3(uintBitsToFloat(PRW_BTF_BLOB(o)), uintBitsToFloat(PRW_BTF_BLOB(o + 1u)),
                      uintBitsToFloat(PRW_BTF_BLOB(o + 2u)));
        float A = uintBitsToFloat(PRW_BTF_BLOB(o + 3u)), r = uintBitsToFloat(PRW_BTF_BLOB(o + 4u));
        vec3 f = vec3(0.0);
        for (uint a = 0u; a < 3u; a++) {
            if (!(X.vw[a] > 0.0)) continue;
            for (uint j = 0u; j < 2u; j++)
                for (uint i = 0u; i < 2u; i++) {
                    float wt = X.vw[a] * X.wx[i] * X.wy[j];
                    if (wt > 0.0) f += wt * btf_rgb(X, 2u * j + i, X.vi[a], k);
                }
        }
        // codec ringing below 0: no light (as the direct light and the path tracer)
        s += max(f, vec3(0.0)) * (A * prw_env_prefiltered(F.t * c.x + F.b * c.y + F.n * c.z, r));
    }
    return s * vis;
}

#endif
