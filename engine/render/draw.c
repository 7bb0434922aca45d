/* draw — the draw context and the drawable list (prw_draw.h). */
#include <string.h>

#include "pipes.h"
#include "prw_constants.h"
#include "prw_pass.h"
#include "scene_gpu.h"

typedef struct draw_pc {
    prw_mat4 model;
    float normal_m[12];
} draw_pc;
_Static_assert(sizeof(draw_pc) == PRW_DRAW_PUSH_BYTES, "draw push constants");

bool prw_draw_mirrors(prw_dmat4 world)
{
    const double *m = world.m;
    double det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
                 m[8] * (m[1] * m[6] - m[5] * m[2]);
    return det < 0;
}

void prw_draw_push_model(prw_dmat4 world, prw_dvec3 origin, float out[28])
{
    draw_pc pc;
    prw_dmat4 rel = world;
    rel.m[12] -= origin.x;
    rel.m[13] -= origin.y;
    rel.m[14] -= origin.z;
    pc.model = prw_m4_from_d(rel);
    prw_dmat4 inv;
    if (!prw_dm4_inverse(world, &inv)) inv = prw_dm4_identity();
    /* normal matrix = inverse-transpose: column c of it is row c of the inverse */
    for (int c = 0; c < 3; c++) {
        pc.normal_m[c * 4 + 0] = (float)inv.m[0 * 4 + c];
        pc.normal_m[c * 4 + 1] = (float)inv.m[1 * 4 + c];
        pc.normal_m[c * 4 + 2] = (float)inv.m[2 * 4 + c];
        pc.normal_m[c * 4 + 3] = 0.0f;
    }
    pc.normal_m[3] = prw_draw_mirrors(world) ? -1.0f : 1.0f; /* mirrored nodes flip the bitangent */
    memcpy(out, &pc, sizeof pc);
}

uint32_t prw_draw_features(const prw_draw_ctx *c, uint32_t slot, bool uv1)
{
    uint32_t f = c->sg->slot_flags[slot], out = 0;
    if (c->kind == PRW_DRAW_SHADOW) out = f & (PRW_SG_MASK | PRW_SG_BLEND) ? PRW_PIPE_MASK : 0;
    else if (f & PRW_SG_EXT)
        out = PRW_PIPE_EXT | (f & PRW_SG_COAT ? PRW_PIPE_COAT : 0) | (c->kind == PRW_DRAW_BLEND ? PRW_PIPE_BLEND : 0) |
              (f & PRW_SG_MASK ? PRW_PIPE_MASK : 0);
    if (out && !uv1) out |= PRW_PIPE_NO_UV1;
    if (c->kind != PRW_DRAW_SHADOW)
        out |= ((f >> PRW_SG_LACKS_SHIFT) & PRW_GPU_MAT_MASK) << PRW_PIPE_LACKS_SHIFT;
    return out;
}

bool prw_draw_bind(prw_draw_ctx *c, uint32_t material_kind, bool two_sided, bool node_mirrored)
{
    return prw_draw_bind_features(c, material_kind, 0, two_sided, node_mirrored);
}

bool prw_draw_bind_features(prw_draw_ctx *c, uint32_t material_kind, uint32_t features, bool two_sided,
                            bool node_mirrored)
{
    if (c->failed) return false;
    prw_pipe_key k = {
        .recipe = c->recipe,
        .material_kind = material_kind,
        .two_sided = two_sided,
        .mirrored = node_mirrored != c->view->mirrored,
        .clip = c->view->clip,
        .view_mask = c->view_mask,
        .variant = c->variant,
        .features = features,
    };
    VkPipeline p;
    if (!prw_pipes_get(c->pipes, &k, &p, &c->err)) {
        c->failed = true;
        return false;
    }
    if (p != c->bound) {
        vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p);
        if (c->kind != PRW_DRAW_SHADOW)
            vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 0, 1, &c->view->globals, 0,
                                    NULL);
        else if (c->depth_bias) /* dynamic in the shadow recipe */
            vkCmdSetDepthBias(c->cmd, c->bias_constant, 0.0f, c->bias_slope);
        c->bound = p;
    }
    return true;
}
