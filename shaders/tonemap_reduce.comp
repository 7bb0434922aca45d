#version 450
// Tone-mapping statistics, stage 2: one workgroup reduces the pc.total partial slots of every view
// (one state for all eyes) to the frame's log-average luminance, largest luminance and pixel count.
// pc.width == 0: zeroes the classification counters the apply pass adds to (it runs after this);
// pc.width == 1: the counters are the sums of the partial counts at pc.base + i (tonemap_fused.comp,
// which ran before this).
layout(local_size_x = 256) in;
layout(set = 0, binding = 3, std430) buffer prw_tm_stats_buf {
    vec4 final_stats;
    uvec4 counts;
    vec4 partial[];
} st;
layout(push_constant) uniform prw_tm_pc {
    uint width, height, base, total;
} pc;

const float LOG_DELTA = 1e-6;
shared float s_sum[256];
shared float s_max[256];
shared float s_n[256];
shared uvec4 s_cnt[256];

void main()
{
    uint t = gl_LocalInvocationIndex;
    float s = 0.0, m = 0.0, n = 0.0;
    uvec4 c = uvec4(0u);
    for (uint i = t; i < pc.total; i += 256u) {
        vec4 q = st.partial[i];
        s += q.x;
        m = max(m, q.y);
        n += q.z;
        if (pc.width == 1u) c += uvec4(st.partial[pc.base + i]);
    }
    s_sum[t] = s;
    s_max[t] = m;
    s_n[t] = n;
    s_cnt[t] = c;
    barrier();
    for (uint k = 128u; k > 0u; k >>= 1) {
        if (t < k) {
            s_sum[t] += s_sum[t + k];
            s_max[t] = max(s_max[t], s_max[t + k]);
            s_n[t] += s_n[t + k];
            s_cnt[t] += s_cnt[t + k];
        }
        barrier();
    }
    if (t == 0u) {
        float cnt = s_n[0];
        st.final_stats = vec4(cnt > 0.0 ? exp(s_sum[0] / cnt) : LOG_DELTA, s_max[0], cnt, s_sum[0]);
        st.counts = s_cnt[0];
    }
}
