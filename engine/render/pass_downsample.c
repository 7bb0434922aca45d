/* pass_downsample — N x N supersampling for stills: box-filters each view's internal HDR image
 * ("hdr_ss", N*W x N*H) into its W x H "hdr".  Needed only when supersampling is on. */
#include <stdlib.h>

#include "pipes.h"
#include "prw_pass.h"

typedef struct downsample_pc {
    uint32_t factor, width, height;
} downsample_pc;

typedef struct ds_state {
    VkDescriptorSet sets[PRW_MAX_VIEWS];
} ds_state;

static void setup(prw_setup *s)
{
    if (prw_setup_env(s)->desc->quality.supersample <= 1) return; /* in the graph, never needed (listed as skipped) */
    prw_setup_use(s, "hdr_ss", PRW_USE_STORAGE_READ);
    prw_setup_use(s, "hdr", PRW_USE_STORAGE_WRITE);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    ds_state *s = prw_calloc(1, sizeof *s);
    *state = s;
    if (env->desc->quality.supersample <= 1) return true;
    for (uint32_t v = 0; v < env->desc->max_views; v++) {
        if (!prw_desc_alloc(env->gpu, env->pool, env->pipes->storage2_layout, &s->sets[v], e)) return false;
        prw_desc_write_image(env->gpu, s->sets[v], 0, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             prw_graph_image(in->graph, "hdr_ss", v)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        prw_desc_write_image(env->gpu, s->sets[v], 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             prw_graph_image(in->graph, "hdr", v)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    }
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    (void)in;
    free(state); /* the sets live in the renderer's pool */
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (c->env->desc->quality.supersample <= 1) return (*why = "no supersampling"), false;
    return true;
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    const prw_render_env *env = c->env;
    ds_state *s = c->state;
    vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, env->pipes->downsample);
    downsample_pc pc = {env->desc->quality.supersample, env->desc->width, env->desc->height};
    vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, env->pipes->storage2_pl, 0, 1, &s->sets[c->view], 0,
                            NULL);
    vkCmdPushConstants(c->cmd, env->pipes->storage2_pl, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    vkCmdDispatch(c->cmd, (pc.width + 7) / 8, (pc.height + 7) / 8, 1);
    return true;
}

const prw_pass prw_pass_downsample = {
    .name = "downsample",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_VIEW,
    .queue = PRW_QUEUE_COMPUTE,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .needed = needed,
    .record = record,
};
