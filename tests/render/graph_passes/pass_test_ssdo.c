/* test_ssdo — a stand-in for screen-space directional occlusion: per view, reads the base pass's depth
 * and G-buffer normals (so the base pass writes them) and the once-per-frame ISM atlas, and adds a small
 * term into the view's radiance. */
#include <stdlib.h>

#include "tp_util.h"

typedef struct ssdo_state {
    tp_fullscreen f;
} ssdo_state;

static void setup(prw_setup *s)
{
    prw_setup_use(s, "depth", PRW_USE_SAMPLED);
    prw_setup_use(s, "gbuf_normal", PRW_USE_SAMPLED);
    prw_setup_use(s, "ism_atlas", PRW_USE_SAMPLED);
    prw_setup_use(s, "hdr", PRW_USE_COLOR_ADD);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    ssdo_state *s = prw_calloc(1, sizeof *s);
    *state = s;
    bool ms = in->env->samples != VK_SAMPLE_COUNT_1_BIT;
    if (!tp_fullscreen_create(in->env, ms, &s->f, e)) return false;
    for (uint32_t v = 0; v < in->env->desc->max_views; v++)
        tp_fullscreen_bind(in->env, &s->f, v, prw_graph_image(in->graph, "gbuf_normal", v),
                           prw_graph_image(in->graph, "depth", v), prw_graph_image(in->graph, "ism_atlas", 0));
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    ssdo_state *s = state;
    if (!s) return;
    tp_fullscreen_destroy(in->env, &s->f);
    free(s);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    ssdo_state *s = c->state;
    tp_log_record("test_ssdo", c->view);
    tp_fullscreen_add(c, &s->f, prw_pass_image(c, "hdr"), 2, 0.01f);
    return true;
}

const prw_pass test_pass_ssdo = {
    .name = "test_ssdo",
    .scope = PRW_SCOPE_VIEW,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .record = record,
};
