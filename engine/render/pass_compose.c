/* pass_compose — the HMD panel (or the side-by-side stereo image) of a two-view frame, as a graph stage
 * (DESIGN.md §6): the composer (compose.c, shaders/hmd_compose.comp: barrel pre-distortion and
 * per-channel chromatic pre-correction, or plain side by side) applied to both eyes' linear HDR images
 * ("panel_hdr") and to their display signals ("panel_signal"), both RGBA32F at the panel size and
 * exported for readback.  In the graph only when the renderer is made with compose parameters. */
#include <stdlib.h>

#include "prw_compose.h"
#include "prw_pass.h"

typedef struct compose_state {
    prw_composer *c;
    VkDescriptorSet hdr_set, signal_set;
} compose_state;

static void setup(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    if (!env->desc->compose) return prw_setup_skip(s, "no composition asked for (stereo / HMD stills)");
    if (env->desc->max_views < 2) return prw_setup_skip(s, "a renderer for one view");
    prw_image_decl d = {.format = VK_FORMAT_R32G32B32A32_SFLOAT, .size = PRW_SIZE_FIXED,
                        .width = env->desc->compose->out_w, .height = env->desc->compose->out_h, .shared = true};
    prw_setup_image(s, "panel_hdr", &d);
    prw_setup_image(s, "panel_signal", &d);
    prw_setup_export(s, "panel_hdr");
    prw_setup_export(s, "panel_signal");
    prw_setup_use_view(s, "hdr", 0, PRW_USE_SAMPLED);
    prw_setup_use_view(s, "hdr", 1, PRW_USE_SAMPLED);
    prw_setup_use_view(s, "signal", 0, PRW_USE_SAMPLED);
    prw_setup_use_view(s, "signal", 1, PRW_USE_SAMPLED);
    prw_setup_use(s, "panel_hdr", PRW_USE_STORAGE_WRITE);
    prw_setup_use(s, "panel_signal", PRW_USE_STORAGE_WRITE);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    compose_state *s = prw_calloc(1, sizeof *s);
    *state = s;
    prw_graph *g = in->graph;
    return prw_composer_create(in->env->gpu, &s->c, e) &&
           prw_composer_view_set(s->c, prw_graph_image(g, "hdr", 0), prw_graph_image(g, "hdr", 1),
                                 prw_graph_image(g, "panel_hdr", 0), &s->hdr_set, e) &&
           prw_composer_view_set(s->c, prw_graph_image(g, "signal", 0), prw_graph_image(g, "signal", 1),
                                 prw_graph_image(g, "panel_signal", 0), &s->signal_set, e);
}

static void destroy(const prw_pass_init *in, void *state)
{
    (void)in;
    compose_state *s = state;
    if (!s) return;
    prw_composer_destroy(s->c);
    free(s);
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (c->frame->view_count != 2) return (*why = "not a two-view frame"), false;
    return true;
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    compose_state *s = c->state;
    prw_composer_record(s->c, c->cmd, s->hdr_set, c->env->desc->compose);
    prw_composer_record(s->c, c->cmd, s->signal_set, c->env->desc->compose);
    return true;
}

const prw_pass prw_pass_compose = {
    .name = "compose",
    .scope = PRW_SCOPE_FRAME,
    .queue = PRW_QUEUE_COMPUTE,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .needed = needed,
    .record = record,
};
