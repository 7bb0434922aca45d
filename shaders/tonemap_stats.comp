#version 450
// Tone-mapping statistics, stage 1 (pass_tonemap.c "tm_stats"): per 16x16 tile of one view, the sum of
// ln(delta + Y) (Reinhard et al. 2002, eq. 1, delta guards against log 0), the largest Y and the pixel
// count, written to one partial slot.  Input is sanitised like tonemap_ops.c: NaN and negative -> 0,
// values above 1e12 cd/m^2 (and +Inf) -> 1e12.
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 3, std430) buffer prw_tm_stats_buf {
    vec4 final_stats; // log-average, max, count, sum
    uvec4 counts;     // below black, above peak, out of gamut, pixels
    vec4 partial[];
} st;
layout(push_constant) uniform prw_tm_pc {
    uint width, height, base, total;
} pc;

const float LOG_DELTA = 1e-6;
shared float s_sum[256];
shared float s_max[256];
shared float s_n[256];

float san(float x) { return (isnan(x) || !(x > 0.0)) ? 0.0 : min(x, 1e12); }

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    uint t = gl_LocalInvocationIndex;
    float s = 0.0, m = 0.0, n = 0.0;
    if (p.x < pc.width && p.y < pc.height) {
        vec3 c = texelFetch(src, ivec2(p), 0).rgb;
        float y = 0.2126 * san(c.r) + 0.7152 * san(c.g) + 0.0722 * san(c.b);
        s = log(LOG_DELTA + y);
        m = y;
        n = 1.0;
    }
    s_sum[t] = s;
    s_max[t] = m;
    s_n[t] = n;
    barrier();
    for (uint k = 128u; k > 0u; k >>= 1) {
        if (t < k) {
            s_sum[t] += s_sum[t + k];
            s_max[t] = max(s_max[t], s_max[t + k]);
            s_n[t] += s_n[t + k];
        }
        barrier();
    }
    if (t == 0u)
        st.partial[pc.base + gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] =
            vec4(s_sum[0], s_max[0], s_n[0], 0.0);
}
