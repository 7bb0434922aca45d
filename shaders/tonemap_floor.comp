#version 450
// Yardsticks of the tone-mapping stage (prw tmbench --vs-copy, tonemap_gpu.c prw_tm_session_time_floor):
// the least a compute pass over the image costs on this device.  FLOOR_MODE (specialisation constant):
//   0 the dispatch alone (16 x 16 workgroups over the image, nothing read or written);
//   1 read only (texelFetch of every pixel, nothing written unless a value is below -1e30);
//   2 texelFetch -> imageStore of one RGBA8 image;  3 the same into the RGBA32F image;
//   4 texelFetch -> packUnorm4x8 into a storage buffer (one uint per pixel, row-major);
//   5 read + the statistics' per-workgroup reduction (sum of ln(delta + Y), largest Y, count) in
//     subgroup operations, one partial per workgroup.
#extension GL_KHR_shader_subgroup_arithmetic : require
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D ldr;
layout(set = 0, binding = 2, rgba32f) uniform writeonly image2D sig;
layout(set = 0, binding = 3, std430) buffer prw_tm_floor_buf {
    uint px[];
} ob;
layout(push_constant) uniform prw_tm_pc {
    uint width, height, base, total;
} pc;
layout(constant_id = 0) const int FLOOR_MODE = 0;

shared vec4 s_part[64]; // one per subgroup (256 invocations, subgroups of at least 4)

void main()
{
    if (FLOOR_MODE == 0) return;
    uvec2 p = gl_GlobalInvocationID.xy;
    bool inside = p.x < pc.width && p.y < pc.height;
    if (FLOOR_MODE >= 5) {
        float y = 0.0, l = 0.0, n = 0.0;
        if (inside) {
            vec3 c = texelFetch(src, ivec2(p), 0).rgb;
            y = dot(c, vec3(0.2126, 0.7152, 0.0722));
            l = log(1e-6 + y);
            n = 1.0;
        }
        vec3 r = vec3(subgroupAdd(l), subgroupMax(y), subgroupAdd(n));
        if (FLOOR_MODE == 6) { // no barrier: one partial per subgroup into the buffer
            uint g = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_NumSubgroups + gl_SubgroupID;
            if (subgroupElect() && 4u * g + 2u < pc.width * pc.height) {
                ob.px[4u * g] = floatBitsToUint(r.x);
                ob.px[4u * g + 1u] = floatBitsToUint(r.y);
                ob.px[4u * g + 2u] = floatBitsToUint(r.z);
            }
            return;
        }
        if (FLOOR_MODE == 7) { // log only, no reduction
            if (l < -1e30) ob.px[0] = 1u;
            return;
        }
        if (subgroupElect()) s_part[gl_SubgroupID] = vec4(r, 0.0);
        barrier();
        if (gl_LocalInvocationIndex == 0u) {
            vec4 a = vec4(0.0);
            for (uint i = 0u; i < gl_NumSubgroups; i++) a = vec4(a.x + s_part[i].x, max(a.y, s_part[i].y), a.z + s_part[i].z, 0.0);
            uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
            ob.px[4u * g] = floatBitsToUint(a.x);
            ob.px[4u * g + 1u] = floatBitsToUint(a.y);
            ob.px[4u * g + 2u] = floatBitsToUint(a.z);
        }
        return;
    }
    if (!inside) return;
    vec4 c = texelFetch(src, ivec2(p), 0);
    if (FLOOR_MODE == 1) {
        if (c.r < -1e30) ob.px[0] = 1u;
    } else if (FLOOR_MODE == 2) {
        imageStore(ldr, ivec2(p), clamp(c, 0.0, 1.0));
    } else if (FLOOR_MODE == 3) {
        imageStore(sig, ivec2(p), c);
    } else {
        ob.px[p.y * pc.width + p.x] = packUnorm4x8(clamp(c, 0.0, 1.0));
    }
}
