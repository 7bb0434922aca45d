// Full-image separable local tone mapping (pass_tonemap.c, operator "local"): scratch layers of one
// r32f 2D-array image in set 1: layer 0 = scaled luminance L, 1 = the horizontal pass, 2 + j = blur
// level j (sigma = 0.25 * 1.6^j, radius RAD[j], normalised sampled Gaussian, clamp-to-edge): the
// same discretisation as prw_tm_local_ld and tonemap_local.comp.
layout(set = 1, binding = 0, r32f) uniform image2DArray scratch;

const int SEP_RAD[9] = int[9](1, 2, 2, 4, 5, 8, 13, 21, 33); // prw_tm_local_radius

// Workgroups are 16 x 16 blocks: the block grid (local), or (selective, dispatched indirectly) the
// blocks of list `list` of tonemap_compact.comp.  Returns the pixel of this invocation.
ivec2 sep_pixel(int list)
{
    uint bx = tm_blocks_x();
    uint b = gl_WorkGroupID.y * bx + gl_WorkGroupID.x;
    if (P.mode.x == OP_SELECTIVE)
        b = tl.data[tm_tiles_x() * tm_tiles_y() + bx * tm_blocks_y() * uint(1 + list) + gl_WorkGroupID.x];
    return ivec2(int(b % bx), int(b / bx)) * 16 + ivec2(gl_LocalInvocationID.xy);
}
