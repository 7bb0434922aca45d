/* test_baked — a stand-in for the baked indirect-diffuse lookup: per view, a light-map texture of its
 * own (made at create: "baked" once) looked up for the surfaces of the G-buffer and added into the view's
 * radiance. */
#include <stdlib.h>

#include "tp_util.h"

typedef struct baked_state {
    tp_fullscreen f;
    prw_gpu_image lightmap;
} baked_state;

static void setup(prw_setup *s)
{
    prw_setup_use(s, "gbuf_normal", PRW_USE_SAMPLED);
    prw_setup_use(s, "hdr", PRW_USE_COLOR_ADD);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    baked_state *b = prw_calloc(1, sizeof *b);
    *state = b;
    if (!tp_fullscreen_create(in->env, false, &b->f, e) || !tp_texture(in->env, 4, 4, 0.02f, &b->lightmap, e))
        return false;
    for (uint32_t v = 0; v < in->env->desc->max_views; v++)
        tp_fullscreen_bind(in->env, &b->f, v, &b->lightmap, prw_graph_image(in->graph, "gbuf_normal", v), &b->lightmap);
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    baked_state *b = state;
    if (!b) return;
    tp_fullscreen_destroy(in->env, &b->f);
    prw_image_destroy(in->env->gpu, &b->lightmap);
    free(b);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    baked_state *b = c->state;
    tp_log_record("test_baked", c->view);
    tp_fullscreen_add(c, &b->f, prw_pass_image(c, "hdr"), 0, 1.0f);
    return true;
}

const prw_pass test_pass_baked = {
    .name = "test_baked",
    .scope = PRW_SCOPE_VIEW,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .record = record,
};
