/* pass_tonemap — display-aware tone mapping as two graph passes (the work is in tonemap_gpu.c):
 *   "tm_stats" (once for all views: log-average and largest luminance, classification counters and,
 *              for the selective operator, block gradients; only for operators that key on them: the
 *              others get statistics and counts, when wanted, from "tonemap" itself, tonemap_gpu.c);
 *   "tonemap"  (every view: operator -> gamut mapping -> inverse display model into "ldr" (RGBA8,
 *              exported) and the display signal "signal" (RGBA32F), an optional image: it exists and is
 *              written only when exported (prw_render_desc.display_signal) or read by a pass).
 * Both read "hdr", or "hdr_glare" when the glare stage runs (pass_glare.c).
 * The statistics and tile buffers belong to the tone-mapping service; both passes import them, so the
 * graph orders them between the passes and for the host's report. */
#include "pipes.h"
#include "prw_pass.h"
#include "tonemap_gpu.h"

/* The radiance the tone mapping reads: the glare stage's copy when there is one (pass_glare.c). */
static const char *input_name(const prw_render_env *env) { return env->desc->glare ? "hdr_glare" : "hdr"; }

static void import_buffers(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    prw_setup_import_buffer(s, "tm_stats", prw_tm_gpu_stats_buffer(env->tm));
    prw_setup_import_buffer(s, "tm_tiles", prw_tm_gpu_tiles_buffer(env->tm));
}

static void stats_setup(prw_setup *s)
{
    import_buffers(s);
    prw_setup_use(s, input_name(prw_setup_env(s)), PRW_USE_SAMPLED);
    prw_setup_use(s, "tm_stats", PRW_USE_STORAGE_WRITE);
    prw_setup_use(s, "tm_tiles", PRW_USE_STORAGE_WRITE);
}

static bool stats_needed(const prw_pass_ctx *c, const char **why)
{
    if (!c->frame->view_count) return (*why = "no views"), false;
    if (!prw_tm_gpu_stats_needed(c->env->tm))
        return (*why = "the operator keys on no frame statistics (counts and statistics, if wanted, come from the apply)"), false;
    return true;
}

static bool stats_record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    prw_tm_gpu_record_stats(c->env->tm, c);
    return true;
}

const prw_pass prw_pass_tm_stats = {
    .name = "tm_stats",
    .scope = PRW_SCOPE_FRAME,
    .queue = PRW_QUEUE_COMPUTE,
    .setup = stats_setup,
    .needed = stats_needed,
    .record = stats_record,
};

static void tonemap_setup(prw_setup *s)
{
    import_buffers(s);
    /* written as storage images, or as colour attachments by the fragment-shader apply (tonemap_gpu.c) */
    prw_image_decl ldr = {.format = VK_FORMAT_R8G8B8A8_UNORM, .size = PRW_SIZE_VIEW,
                          .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    prw_image_decl sig = {.format = VK_FORMAT_R32G32B32A32_SFLOAT, .size = PRW_SIZE_VIEW,
                          .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    prw_setup_image(s, "ldr", &ldr);
    prw_setup_image(s, "signal", &sig);
    prw_setup_optional(s, "signal");
    prw_setup_export(s, "ldr");
    if (prw_setup_env(s)->desc->display_signal) prw_setup_export(s, "signal");
    prw_setup_export(s, "tm_stats");
    prw_setup_export(s, "tm_tiles");
    prw_setup_use(s, input_name(prw_setup_env(s)), PRW_USE_SAMPLED);
    prw_setup_use(s, "ldr", PRW_USE_STORAGE_WRITE);
    prw_setup_use(s, "signal", PRW_USE_STORAGE_WRITE);
    prw_setup_use(s, "tm_stats", PRW_USE_STORAGE_WRITE);
    prw_setup_use(s, "tm_tiles", PRW_USE_STORAGE_WRITE);
}

static bool tonemap_create(const prw_pass_init *in, void **state, prw_error *e)
{
    *state = NULL;
    for (uint32_t v = 0; v < in->env->desc->max_views; v++)
        if (!prw_tm_gpu_bind_view(in->env->tm, v, prw_graph_image(in->graph, input_name(in->env), v),
                                  prw_graph_image(in->graph, "ldr", v), prw_graph_image(in->graph, "signal", v), e))
            return false;
    return true;
}

static bool tonemap_needed(const prw_pass_ctx *c, const char **why)
{
    if (!c->frame->view_count) return (*why = "no views"), false;
    return true;
}

static bool tonemap_record(prw_pass_ctx *c, prw_error *e)
{
    return prw_tm_gpu_record_apply(c->env->tm, c, prw_graph_written(c->graph, "tm_stats"), e);
}

const prw_pass prw_pass_tonemap = {
    .name = "tonemap",
    .scope = PRW_SCOPE_FRAME,
    .queue = PRW_QUEUE_COMPUTE,
    .setup = tonemap_setup,
    .create = tonemap_create,
    .needed = tonemap_needed,
    .record = tonemap_record,
};
