/* test_glossy — a stand-in for the glossy convolution: per view, the mirror image (test_mirror's
 * "mirror_hdr") weighted and added into the view's radiance ("hdr", additive).  Not in the graph without
 * a mirror. */
#include <stdlib.h>

#include "tp_util.h"

typedef struct glossy_state {
    tp_fullscreen f;
    prw_gpu_image dummy;
} glossy_state;

static void setup(prw_setup *s)
{
    prw_dvec3 n;
    double d;
    if (!tp_scene_mirror(prw_setup_env(s)->scene, &n, &d)) return prw_setup_skip(s, "no mirror in the scene");
    prw_setup_use(s, "mirror_hdr", PRW_USE_SAMPLED);
    prw_setup_use(s, "hdr", PRW_USE_COLOR_ADD);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    glossy_state *g = prw_calloc(1, sizeof *g);
    *state = g;
    if (!tp_fullscreen_create(in->env, false, &g->f, e) || !tp_texture(in->env, 1, 1, 0, &g->dummy, e)) return false;
    for (uint32_t v = 0; v < in->env->desc->max_views; v++)
        tp_fullscreen_bind(in->env, &g->f, v, prw_graph_image(in->graph, "mirror_hdr", v), &g->dummy, &g->dummy);
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    glossy_state *g = state;
    if (!g) return;
    tp_fullscreen_destroy(in->env, &g->f);
    prw_image_destroy(in->env->gpu, &g->dummy);
    free(g);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    glossy_state *g = c->state;
    tp_log_record("test_glossy", c->view);
    tp_fullscreen_add(c, &g->f, prw_pass_image(c, "hdr"), 0, 0.05f);
    return true;
}

const prw_pass test_pass_glossy = {
    .name = "test_glossy",
    .scope = PRW_SCOPE_VIEW,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .record = record,
};
