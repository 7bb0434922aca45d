/* test_env — a stand-in for the environment pass: per view, a constant environment radiance added into
 * the view's radiance where the base pass drew nothing (its depth is still the clear value). */
#include <stdlib.h>

#include "tp_util.h"

typedef struct env_state {
    tp_fullscreen f;
    prw_gpu_image sky;
} env_state;

static void setup(prw_setup *s)
{
    prw_setup_use(s, "depth", PRW_USE_SAMPLED);
    prw_setup_use(s, "hdr", PRW_USE_COLOR_ADD);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    env_state *s = prw_calloc(1, sizeof *s);
    *state = s;
    bool ms = in->env->samples != VK_SAMPLE_COUNT_1_BIT;
    if (!tp_fullscreen_create(in->env, ms, &s->f, e) || !tp_texture(in->env, 1, 1, 3.0f, &s->sky, e)) return false;
    for (uint32_t v = 0; v < in->env->desc->max_views; v++)
        tp_fullscreen_bind(in->env, &s->f, v, &s->sky, prw_graph_image(in->graph, "depth", v), &s->sky);
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    env_state *s = state;
    if (!s) return;
    tp_fullscreen_destroy(in->env, &s->f);
    prw_image_destroy(in->env->gpu, &s->sky);
    free(s);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    env_state *s = c->state;
    tp_log_record("test_env", c->view);
    tp_fullscreen_add(c, &s->f, prw_pass_image(c, "hdr"), 1, 1.0f);
    return true;
}

const prw_pass test_pass_env = {
    .name = "test_env",
    .scope = PRW_SCOPE_VIEW,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .record = record,
};
