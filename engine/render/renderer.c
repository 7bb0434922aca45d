/* renderer — a scene on the GPU drawn by the pass graph (prw_render.h): owns the scene's GPU copy,
 * the drawables, the pipelines, the per-view globals, the tone-mapping service and the graph; per
 * frame it updates the drawables for the view set, fills the views' globals and executes the graph. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_render.h"
#include "render_internal.h"
#include "view_globals.h"

static bool validate_desc(prw_render_desc *d, prw_error *e)
{
    static const prw_quality zero;
    if (memcmp(&d->quality, &zero, sizeof zero) == 0) d->quality = prw_quality_default();
    if (!d->max_views) d->max_views = 1;
    const prw_quality *q = &d->quality;
    if (!prw_quality_validate(q, e)) return prw_fail_wrap(e, "render");
    if (d->width == 0 || d->height == 0 || d->width > 16384 || d->height > 16384)
        return prw_fail(e, "render: image size %ux%u out of range (1..16384)", d->width, d->height);
    if (d->max_views > PRW_MAX_VIEWS)
        return prw_fail(e, "render: %u views requested, at most %d", d->max_views, PRW_MAX_VIEWS);
    if (d->width * q->supersample > 16384 || d->height * q->supersample > 16384)
        return prw_fail(e, "render: supersampling %ux%u of %ux%u out of range (<= 16384 pixels a side)",
                        q->supersample, q->supersample, d->width, d->height);
    if (d->compose && (d->compose->eye_w != d->width || d->compose->eye_h != d->height || d->compose->out_w < 2 ||
                       d->compose->out_w % 2 || d->compose->out_h < 1 || d->compose->out_w > 16384 ||
                       d->compose->out_h > 16384))
        return prw_fail(e, "render: composition of %ux%u eyes into a %ux%u panel: the eyes must be the views' size "
                           "(%ux%u) and the panel width even, at most 16384",
                        d->compose->eye_w, d->compose->eye_h, d->compose->out_w, d->compose->out_h, d->width, d->height);
#ifndef PRW_HAVE_GLARE
    if (d->glare) return prw_fail(e, "render: temporal glare: this build has no kissfft (install libkissfft-dev)");
#endif
    if (!d->terms) d->terms = PRW_TERM_ALL;
    if (d->terms & ~(uint32_t)PRW_TERM_ALL) return prw_fail(e, "render: terms %#x: unknown bits", d->terms);
    if (d->views_backend == PRW_VIEWS_MULTIVIEW && d->max_views > 2)
        return prw_fail(e, "render: views backend multiview supports 2 views (max_views %u)", d->max_views);
    if (d->views_backend == PRW_VIEWS_MULTIVIEW && d->max_views == 2 && q->supersample > 1)
        return prw_fail(e, "render: views backend multiview does not support supersampling");
    return true;
}

/* Everything that depends on the scene: its GPU copy, shadow plan, drawables, graph. */
static void destroy_scene_parts(prw_renderer *r)
{
    prw_graph_destroy(r->graph);
    r->graph = NULL;
    prw_drawables_destroy(&r->drawables, &r->env);
    prw_scene_gpu_destroy(r->gpu, r->sg);
    r->sg = NULL;
    r->env.sg = NULL;
    prw_emissive_lights_free(&r->emissive);
}

static bool create_scene_parts(prw_renderer *r, prw_error *e)
{
    /* emissive meshes light like rect lights in the slots the scene's lights leave (prw_emissive.h) */
    uint32_t free_slots = r->scene->light_count < PRW_MAX_LIGHTS ? PRW_MAX_LIGHTS - r->scene->light_count : 0;
    uint32_t budget = r->desc.quality.emissive_lights < free_slots ? r->desc.quality.emissive_lights : free_slots;
    prw_emissive_lights_build(r->scene, budget, &r->emissive);
    prw_shadow_plan_make_with(r->scene, &r->emissive, &r->plan);
    if (!prw_scene_gpu_create(r->gpu, r->scene, r->pipes->material_layout, r->pool, &r->sg, e)) return false;
    /* only the probed materials' pipelines carry the probe term (gi_probe.glsl, PRW_GPU_MAT_PROBE) */
    for (uint32_t i = 0; r->probes && r->probes->active && i < r->probes->count; i++)
        r->sg->slot_flags[prw_scene_gpu_slot(r->scene, r->desc.probes->probe[i].material)] |=
            (uint32_t)PRW_GPU_MAT_PROBE << PRW_SG_LACKS_SHIFT;
    r->env.sg = r->sg;
    if (!prw_drawables_create(&r->drawables, prw_drawables_default, &r->env, e)) return false;
    const prw_pass *const *table = r->desc.debug && r->desc.debug->passes ? r->desc.debug->passes : prw_passes_default;
    const char *const *exports = r->desc.debug ? r->desc.debug->exports : NULL;
    if (!prw_graph_create(&r->env, table, exports, &r->graph, e)) return false;
    /* the shadow atlas is set 0, bindings 1 (compare sampler) and 2 (gathers) of every view's globals */
    prw_gpu_image *shadow = prw_graph_image(r->graph, "shadow_map", 0);
    if (!shadow) return prw_fail(e, "render: the pass table has no pass creating 'shadow_map'");
    for (uint32_t v = 0; v < r->desc.max_views; v++) {
        prw_desc_write_image(r->gpu, r->globals_set[v], 1, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow->view,
                             prw_gpu_sampler(r->gpu, PRW_SAMPLER_SHADOW), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        prw_desc_write_image(r->gpu, r->globals_set[v], 2, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow->view,
                             prw_gpu_sampler(r->gpu, PRW_SAMPLER_SHADOW_DEPTH), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    return true;
}

bool prw_renderer_create(prw_gpu *gpu, const prw_scene *scene, const prw_render_desc *desc, prw_renderer **out,
                         prw_error *e)
{
    *out = NULL;
    prw_renderer *r = prw_calloc(1, sizeof *r);
    r->gpu = gpu;
    r->scene = scene;
    r->desc = *desc;
    if (desc->debug) {
        r->debug = *desc->debug;
        r->desc.debug = &r->debug;
    }
    if (desc->compose) {
        r->compose = *desc->compose;
        r->desc.compose = &r->compose;
    }
    if (desc->glare) {
        r->glare = *desc->glare;
        r->desc.glare = &r->glare;
    }
    bool ok = validate_desc(&r->desc, e);
    if (!r->desc.quality.gi_lookups) /* the knob's B frame: no baked or environment light at all */
        r->desc.lightmaps = NULL, r->desc.environment = NULL, r->desc.probes = NULL;
    VkSampleCountFlagBits samples = r->desc.quality.msaa == 4 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;
    r->env = (prw_render_env){.gpu = gpu, .scene = scene, .desc = &r->desc, .samples = samples,
                              .shadows = &r->plan, .drawables = &r->drawables};
    ok = ok && prw_desc_pool_create(gpu, &r->pool, e);
    r->env.pool = r->pool;
    ok = ok && prw_pipes_create(&r->env, &r->pipes, e);
    r->env.pipes = r->pipes;
    if (ok && !prw_lightmap_gpu_create(gpu, scene, r->desc.lightmaps, &r->lm, e))
        ok = prw_fail_wrap(e, "render");
    r->env.lm = r->lm;
    if (ok) r->pipes->lightmap_atlas = r->lm->atlas.view; /* globals binding 4 */
    if (ok && !prw_env_gpu_create(gpu, r->desc.environment, &r->envlight, e)) ok = prw_fail_wrap(e, "render");
    if (ok) r->pipes->envlight = r->envlight; /* globals bindings 5-7 */
    if (ok && !prw_probe_gpu_create(gpu, scene, r->desc.probes, r->desc.quality.probe_count, &r->probes, e))
        ok = prw_fail_wrap(e, "render");
    if (ok) r->pipes->probes = r->probes; /* globals bindings 8-10 */
    ok = ok && prw_tm_gpu_create(gpu, r->pool, r->desc.width, r->desc.height, r->desc.max_views,
                                 (prw_tm_op)r->desc.quality.tonemap,
                                 &r->tm, e);
    r->env.tm = r->tm;
    for (uint32_t v = 0; ok && v < r->desc.max_views; v++) {
        ok = prw_buffer_create(gpu, sizeof(prw_gpu_globals), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD,
                               &r->globals[v], e) &&
             prw_desc_alloc(gpu, r->pool, r->pipes->globals_layout, &r->globals_set[v], e);
        if (ok) {
            prw_desc_write_buffer(gpu, r->globals_set[v], 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &r->globals[v], 0,
                                  sizeof(prw_gpu_globals));
            prw_pipes_write_globals(r->pipes, r->globals_set[v]);
        }
    }
    ok = ok && create_scene_parts(r, e);
    if (ok && r->desc.timestamps) ok = prw_timer_create(gpu, 64, &r->timer, e);
    if (!ok) {
        prw_renderer_destroy(r);
        return false;
    }
    *out = r;
    return true;
}

void prw_renderer_destroy(prw_renderer *r)
{
    if (!r) return;
    prw_error ignored;
    prw_gpu_wait_idle(r->gpu, &ignored);
    destroy_scene_parts(r);
    prw_tm_gpu_destroy(r->tm);
    for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++) prw_buffer_destroy(r->gpu, &r->globals[v]);
    prw_lightmap_gpu_destroy(r->gpu, r->lm);
    prw_env_gpu_destroy(r->gpu, r->envlight);
    prw_probe_gpu_destroy(r->gpu, r->probes);
    prw_pipes_destroy(r->pipes);
    if (r->pool) prw_desc_pool_destroy(r->gpu, r->pool);
    if (r->timer) prw_timer_destroy(r->gpu, r->timer);
    free(r);
}

const prw_emissive_lights *prw_renderer_emissive(const prw_renderer *r) { return &r->emissive; }

bool prw_renderer_sync_scene(prw_renderer *r, prw_error *e)
{
    if (!prw_gpu_wait_idle(r->gpu, e)) return false;
    destroy_scene_parts(r);
    return create_scene_parts(r, e) || prw_fail_wrap(e, "render: scene sync");
}

/* The frame's mode (which passes render which views) and each view's draw view and globals. */
static void prepare_frame(prw_renderer *r, const prw_view *views, uint32_t count, prw_frame *f)
{
    memset(f, 0, sizeof *f);
    f->views = views;
    f->view_count = count;
    f->mode = PRW_FRAME_LOOP;
    if (count == 2 && r->desc.views_backend == PRW_VIEWS_MULTIVIEW) f->mode = PRW_FRAME_MULTIVIEW;
    /* cut-out and blended surfaces are not reprojected (their pre-pass would need the alpha test): both
     * eyes shaded (pass_reproject.c says so in the frame's pass list) */
    else if (count == 2 && r->desc.quality.stereo_reuse == PRW_STEREO_REUSE_REPROJECT && !r->sg->alpha_meshes)
        f->mode = PRW_FRAME_REPROJECT;
    for (uint32_t v = 0; v < count; v++) {
        /* camera-relative rendering: each view relative to its own eye, so every eye of a view set is
         * bit-identical to a mono render from it; multiview draws all views with the first eye's origin */
        prw_dvec3 o = f->mode == PRW_FRAME_MULTIVIEW ? views[0].eye : views[v].eye;
        prw_gpu_globals g;
        prw_view_globals_fill(r->scene, &r->plan, r->desc.quality.shadow_size, &views[v], o, &g);
        memcpy(r->globals[v].mapped, &g, sizeof g);
        f->draw[v] = (prw_draw_view){.origin = o, .eye = views[v].eye, .globals = r->globals_set[v]};
    }
}

typedef struct split_ctx {
    prw_renderer *r;
} split_ctx;

/* --pass-times: a compute pass gets a command buffer of its own, timed by the host clock around its
 * submit (lavapipe's timestamps do not time compute dispatches). */
static bool split(void *user, VkCommandBuffer *cmd, double *ms, prw_error *e)
{
    split_ctx *s = user;
    double t0 = prw_now();
    if (!prw_cmd_submit_wait(s->r->gpu, *cmd, e)) {
        *cmd = VK_NULL_HANDLE;
        return false;
    }
    *ms = 1e3 * (prw_now() - t0);
    return prw_cmd_begin(s->r->gpu, cmd, e);
}

static bool record(prw_renderer *r, prw_graph_exec *x, const prw_view *views, uint32_t count, prw_error *e)
{
    if (count == 0 || count > r->desc.max_views)
        return prw_fail(e, "render: %u views, renderer made for 1..%u", count, r->desc.max_views);
    for (uint32_t i = 0; i < count; i++)
        if (views[i].width != r->desc.width || views[i].height != r->desc.height)
            return prw_fail(e, "render: view %u is %ux%u, targets are %ux%u", i, views[i].width, views[i].height,
                            r->desc.width, r->desc.height);
    if (!prw_drawables_update(&r->drawables, &r->env, views, count, e)) return false;
    prw_frame f;
    prepare_frame(r, views, count, &f);
    if (r->timer) prw_timer_reset(x->cmd, r->timer);
    x->timer = r->timer;
    if (!prw_graph_execute(r->graph, &f, x, &r->last, e)) return false;
    r->last.glare_pupil_mm = f.glare_pupil_mm;
    r->last.glare_psf_radius = f.glare_psf_radius;
    return true;
}

bool prw_renderer_record(prw_renderer *r, VkCommandBuffer cmd, const prw_view *views, uint32_t count,
                         prw_error *e)
{
    prw_graph_exec x = {.cmd = cmd};
    return record(r, &x, views, count, e);
}

bool prw_renderer_render(prw_renderer *r, const prw_view *views, uint32_t count, prw_frame_stats *stats,
                         prw_error *e)
{
    double t0 = prw_now();
    split_ctx sc = {r};
    prw_graph_exec x = {.split = split, .user = &sc, .time_compute = r->timer != NULL};
    if (!prw_cmd_begin(r->gpu, &x.cmd, e)) return false;
    if (!record(r, &x, views, count, e)) {
        prw_error ignored;
        if (x.cmd) prw_cmd_submit_wait(r->gpu, x.cmd, &ignored);
        return false;
    }
    if (!prw_cmd_submit_wait(r->gpu, x.cmd, e)) return false;
    r->last.cpu_ms = 1e3 * (prw_now() - t0);
    if (r->timer) {
        uint32_t n;
        const char *const *names;
        const double *ms;
        if (!prw_timer_read(r->gpu, r->timer, &n, &names, &ms, e)) return false;
        for (uint32_t i = 0; i < r->last.pass_count; i++)
            if (r->last.passes[i].timer_scope < n) r->last.passes[i].gpu_ms = ms[r->last.passes[i].timer_scope];
    }
    if (stats) *stats = r->last;
    return true;
}

void prw_renderer_last_passes(const prw_renderer *r, prw_frame_stats *stats) { *stats = r->last; }

struct prw_lod_scene *prw_renderer_lod(prw_renderer *r) { return prw_drawables_state(&r->drawables, "nurbs"); }

struct prw_graph *prw_renderer_graph(prw_renderer *r) { return r->graph; }

static bool read_view_image(prw_renderer *r, const char *name, uint32_t v, prw_gpu_image **img, prw_error *e)
{
    if (v >= r->desc.max_views) return prw_fail(e, "render: no view %u", v);
    *img = prw_graph_image(r->graph, name, v);
    if (!*img) return prw_fail(e, "render: the graph has no image '%s'", name);
    return true;
}

bool prw_renderer_read_hdr(prw_renderer *r, uint32_t v, prw_image *out, prw_error *e)
{
    prw_gpu_image *img;
    if (!read_view_image(r, "hdr", v, &img, e)) return false;
    if (!prw_image_alloc(out, (int)r->desc.width, (int)r->desc.height, e)) return false;
    if (!prw_image_readback(r->gpu, img, out->rgba, e)) {
        prw_image_free(out);
        return false;
    }
    return true;
}

bool prw_renderer_read_ldr(prw_renderer *r, uint32_t v, uint8_t *rgba, prw_error *e)
{
    prw_gpu_image *img;
    if (!read_view_image(r, "ldr", v, &img, e)) return false;
    size_t n = (size_t)r->desc.width * r->desc.height * 4;
    float *tmp = prw_malloc(n * sizeof(float));
    bool ok = prw_image_readback(r->gpu, img, tmp, e);
    if (ok)
        for (size_t i = 0; i < n; i++) {
            float x = tmp[i] * 255.0f + 0.5f;
            rgba[i] = (uint8_t)(x < 0 ? 0 : x > 255 ? 255 : x);
        }
    free(tmp);
    return ok;
}

bool prw_renderer_read_image(prw_renderer *r, const char *name, uint32_t v, void **out, uint32_t *w, uint32_t *h,
                             prw_error *e)
{
    prw_gpu_image *img;
    *out = NULL;
    if (!read_view_image(r, name, v, &img, e)) return false;
    bool r32 = img->format == VK_FORMAT_D32_SFLOAT || img->format == VK_FORMAT_R32_UINT ||
               img->format == VK_FORMAT_R32_SFLOAT;
    size_t n = (size_t)img->width * img->height * (r32 ? 1 : 4);
    void *buf = prw_malloc(n * 4);
    bool ok = r32 ? prw_image_readback_r32(r->gpu, img, buf, e) : prw_image_readback(r->gpu, img, buf, e);
    if (!ok) {
        free(buf);
        return prw_fail_wrap(e, "render: image '%s' of view %u", name, v);
    }
    *out = buf;
    *w = img->width;
    *h = img->height;
    return true;
}

prw_gpu_image *prw_renderer_ldr_image(prw_renderer *r, uint32_t v)
{
    return v < r->desc.max_views ? prw_graph_image(r->graph, "ldr", v) : NULL;
}

void prw_renderer_describe(const prw_renderer *r, char *buf, size_t cap) { prw_graph_describe(r->graph, buf, cap); }

bool prw_renderer_set_extra_work(prw_renderer *r, double fraction, prw_error *e)
{
    if (!(r->desc.quality.extra_gpu_work > 0))
        return prw_fail(e, "renderer: extra GPU work can only be changed on a renderer created with it");
    if (!(fraction > 0) || !(fraction <= 16))
        return prw_fail(e, "renderer: extra GPU work %g is not in (0, 16]", fraction);
    r->desc.quality.extra_gpu_work = fraction;
    return true;
}

bool prw_frame_stats_base_floor(const prw_frame_stats *st, double *base_ms, double *floor_ms)
{
    double base = 0, floor = -1;
    for (uint32_t i = 0; i < st->pass_count; i++) {
        const prw_pass_stat *p = &st->passes[i];
        if (p->skipped || p->gpu_ms < 0) continue;
        if (p->flags & PRW_PASS_RADIANCE) base += p->gpu_ms;
        if (strcmp(p->name, "floor") == 0) floor = p->gpu_ms;
    }
    if (!(floor >= 0)) return false;
    *base_ms = base;
    *floor_ms = floor;
    return true;
}
