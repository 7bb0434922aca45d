/* pass_tonemap — display-aware tone mapping on the GPU (issue 6), two passes:
 *   "tm_stats" (once for all views: tile partials per view -> one reduction: log-average and largest
 *              luminance, and zeroed classification counters); needed when the operator uses frame
 *              statistics (reinhard, adaptive) or pixels are classified (absolute, overlay, report);
 *   "tonemap"  (per view: operator -> gamut mapping -> inverse display model; writes the signal V as
 *              RGBA32F before quantisation and as RGBA8 for PNGs and presenting).
 * The C reference is tonemap_ops.c; shaders/tonemap_{stats,reduce,apply}.comp mirror it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_shaders.h"
#include "render_internal.h"

#define TILE 16
#define SIG_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT

typedef struct tm_pc {
    uint32_t width, height, base, total;
} tm_pc;

/* std140 mirror of shaders/tonemap_apply.comp's prw_tm_params */
typedef struct tm_ubo {
    int32_t mode[4];
    float range[4], disp[4], enc[4], op1[4], op2[4];
    float m[3][4];
} tm_ubo;

/* std430 header of the stats buffer; partial slots (vec4) follow */
typedef struct tm_stats_hdr {
    float final_stats[4];
    uint32_t counts[4];
} tm_stats_hdr;

typedef struct prw_tm_gpu prw_tm_gpu;
struct prw_tm_gpu {
    prw_display display;
    prw_tonemap_settings settings;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline stats_pipe, reduce_pipe, apply_pipe;
    prw_buffer params; /* UPLOAD uniform */
    prw_buffer stats;  /* READBACK storage: header + partials */
    uint32_t tiles_per_view;
    prw_gpu_image signal[PRW_MAX_VIEWS];
    VkDescriptorSet sets[PRW_MAX_VIEWS];
    bool counted; /* the last frame classified pixels */
};

static bool op_needs_stats(prw_tm_op op) { return op == PRW_TM_REINHARD || op == PRW_TM_ADAPTIVE; }
static bool tm_counts(const prw_tonemap_settings *s)
{
    return s->report || s->overlay || s->op == PRW_TM_ABSOLUTE;
}

static uint32_t tiles_for(uint32_t w, uint32_t h) { return ((w + TILE - 1) / TILE) * ((h + TILE - 1) / TILE); }

static void fill_ubo(const prw_tm_params *p, bool count, tm_ubo *u)
{
    memset(u, 0, sizeof *u);
    u->mode[0] = (int32_t)p->op;
    u->mode[1] = (int32_t)p->eotf;
    u->mode[2] = p->overlay ? 1 : 0;
    u->mode[3] = count ? 1 : 0;
    float range[4] = {(float)p->exposure, (float)p->lmin, (float)p->lmax, (float)p->dl};
    float disp[4] = {(float)p->black, (float)p->peak, (float)p->refl, (float)p->gamma};
    float enc[4] = {(float)p->enc_scale, (float)p->bt_a, (float)p->bt_b, (float)p->white_cd};
    float op1[4] = {(float)p->gain, (float)p->key, (float)p->white, (float)p->knee};
    float op2[4] = {(float)p->toe_p, (float)PRW_TM_SHOULDER_LAMBDA, 0, 0};
    memcpy(u->range, range, sizeof range);
    memcpy(u->disp, disp, sizeof disp);
    memcpy(u->enc, enc, sizeof enc);
    memcpy(u->op1, op1, sizeof op1);
    memcpy(u->op2, op2, sizeof op2);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) u->m[r][c] = (float)p->m[3 * r + c];
}

static void write_set(prw_renderer *r, VkDescriptorSet set, VkImageView src, VkImageView ldr, VkImageView sig)
{
    prw_tm_gpu *tm = r->tm;
    prw_desc_write_image(r->gpu, set, 0, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, src,
                         prw_gpu_sampler(r->gpu, PRW_SAMPLER_NEAREST_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(r->gpu, set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, ldr, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    prw_desc_write_image(r->gpu, set, 2, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, sig, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    prw_desc_write_buffer(r->gpu, set, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tm->stats, 0, 0);
    prw_desc_write_buffer(r->gpu, set, 4, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &tm->params, 0, sizeof(tm_ubo));
}

bool prw_tm_gpu_create(prw_renderer *r, prw_error *e)
{
    prw_tm_gpu *tm = prw_calloc(1, sizeof *tm);
    r->tm = tm;
    prw_display_builtin("srgb", &tm->display);
    tm->settings.op = PRW_TM_EXPOSURE;
    VkDescriptorSetLayoutBinding b[5] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {4, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    if (!prw_desc_layout_create(r->gpu, b, 5, &tm->set_layout, e) ||
        !prw_pipeline_layout_create(r->gpu, &tm->set_layout, 1, sizeof(tm_pc), &tm->layout, e) ||
        !prw_pipeline_compute(r->gpu, prw_shader_tonemap_stats_comp(), tm->layout, &tm->stats_pipe, e) ||
        !prw_pipeline_compute(r->gpu, prw_shader_tonemap_reduce_comp(), tm->layout, &tm->reduce_pipe, e) ||
        !prw_pipeline_compute(r->gpu, prw_shader_tonemap_apply_comp(), tm->layout, &tm->apply_pipe, e))
        return false;
    tm->tiles_per_view = tiles_for(r->desc.width, r->desc.height);
    VkDeviceSize stats_size = sizeof(tm_stats_hdr) + (VkDeviceSize)tm->tiles_per_view * r->desc.max_views * 16;
    if (!prw_buffer_create(r->gpu, sizeof(tm_ubo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD, &tm->params,
                           e) ||
        !prw_buffer_create(r->gpu, stats_size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, PRW_MEM_READBACK, &tm->stats, e))
        return false;
    memset(tm->stats.mapped, 0, (size_t)stats_size);
    for (uint32_t v = 0; v < r->desc.max_views; v++) {
        prw_image_desc d = {.width = r->desc.width, .height = r->desc.height, .format = SIG_FORMAT,
                            .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
        if (!prw_image_create(r->gpu, &d, &tm->signal[v], e) ||
            !prw_desc_alloc(r->gpu, r->pool, tm->set_layout, &tm->sets[v], e))
            return false;
        write_set(r, tm->sets[v], r->views[v].hdr.view, r->views[v].ldr.view, tm->signal[v].view);
    }
    return true;
}

void prw_tm_gpu_destroy(prw_renderer *r)
{
    prw_tm_gpu *tm = r->tm;
    if (!tm) return;
    VkDevice dev = prw_gpu_device(r->gpu);
    for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++) prw_image_destroy(r->gpu, &tm->signal[v]);
    prw_buffer_destroy(r->gpu, &tm->params);
    prw_buffer_destroy(r->gpu, &tm->stats);
    VkPipeline pipes[3] = {tm->stats_pipe, tm->reduce_pipe, tm->apply_pipe};
    for (int i = 0; i < 3; i++)
        if (pipes[i]) vkDestroyPipeline(dev, pipes[i], NULL);
    if (tm->layout) vkDestroyPipelineLayout(dev, tm->layout, NULL);
    if (tm->set_layout) vkDestroyDescriptorSetLayout(dev, tm->set_layout, NULL);
    free(tm);
    r->tm = NULL;
}

static void compute_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkAccessFlags2 src_access,
                            VkPipelineStageFlags2 dst, VkAccessFlags2 dst_access)
{
    VkMemoryBarrier2 mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                           .srcStageMask = src,
                           .srcAccessMask = src_access,
                           .dstStageMask = dst,
                           .dstAccessMask = dst_access};
    VkDependencyInfo di = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1, .pMemoryBarriers = &mb};
    vkCmdPipelineBarrier2(cmd, &di);
}

#define CS VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT
#define RW (VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT)

/* The chain on `count` inputs (all already in SHADER_READ_ONLY_OPTIMAL, outputs in GENERAL). */
static void record_stats(prw_tm_gpu *tm, VkCommandBuffer cmd, const VkDescriptorSet *sets, const uint32_t *w,
                         const uint32_t *h, uint32_t count)
{
    compute_barrier(cmd, CS | VK_PIPELINE_STAGE_2_HOST_BIT, RW | VK_ACCESS_2_HOST_READ_BIT, CS, RW);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->stats_pipe);
    uint32_t base = 0;
    for (uint32_t v = 0; v < count; v++) {
        tm_pc pc = {w[v], h[v], base, 0};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->layout, 0, 1, &sets[v], 0, NULL);
        vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (w[v] + TILE - 1) / TILE, (h[v] + TILE - 1) / TILE, 1);
        base += tiles_for(w[v], h[v]);
    }
    compute_barrier(cmd, CS, RW, CS, RW);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->reduce_pipe);
    tm_pc pc = {0, 0, 0, base};
    vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, 1, 1, 1);
    compute_barrier(cmd, CS, RW, CS, RW);
}

static void record_apply(prw_tm_gpu *tm, VkCommandBuffer cmd, const VkDescriptorSet *sets, const uint32_t *w,
                         const uint32_t *h, uint32_t count)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->apply_pipe);
    for (uint32_t v = 0; v < count; v++) {
        tm_pc pc = {w[v], h[v], 0, 0};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->layout, 0, 1, &sets[v], 0, NULL);
        vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (w[v] + 7) / 8, (h[v] + 7) / 8, 1);
    }
    /* the stats buffer is read by the host after the frame */
    compute_barrier(cmd, CS, RW, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

static void upload_params(prw_renderer *r, double ev100)
{
    prw_tm_gpu *tm = r->tm;
    prw_tm_params p;
    prw_tm_prepare(&tm->settings, &tm->display, prw_exposure_scale(ev100), &p);
    tm_ubo u;
    tm->counted = tm_counts(&tm->settings);
    fill_ubo(&p, tm->counted, &u);
    memcpy(tm->params.mapped, &u, sizeof u);
}

static bool stats_needed(const prw_frame_ctx *ctx)
{
    const prw_tm_gpu *tm = ctx->r->tm;
    return ctx->view_count > 0 && tm && (op_needs_stats(tm->settings.op) || tm_counts(&tm->settings));
}

static bool stats_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    uint32_t w[PRW_MAX_VIEWS], h[PRW_MAX_VIEWS];
    for (uint32_t vi = 0; vi < ctx->view_count; vi++) {
        prw_cmd_transition(cmd, &r->views[vi].hdr, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        w[vi] = ctx->views[vi].width;
        h[vi] = ctx->views[vi].height;
    }
    record_stats(r->tm, cmd, r->tm->sets, w, h, ctx->view_count);
    return true;
}

static bool tonemap_needed(const prw_frame_ctx *ctx) { return ctx->view_count > 0; }

static bool tonemap_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    prw_tm_gpu *tm = r->tm;
    upload_params(r, ctx->views[0].ev100); /* both eyes share one exposure (DESIGN.md §6) */
    if (!stats_needed(ctx)) tm->counted = false;
    if (!tm->counted) { /* keep the UBO consistent with the graph: no counting without the stats pass */
        tm_ubo *u = tm->params.mapped;
        u->mode[3] = 0;
    }
    uint32_t w[PRW_MAX_VIEWS], h[PRW_MAX_VIEWS];
    for (uint32_t vi = 0; vi < ctx->view_count; vi++) {
        prw_view_targets *t = &r->views[vi];
        prw_cmd_transition(cmd, &t->hdr, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        prw_cmd_transition(cmd, &t->ldr, VK_IMAGE_LAYOUT_GENERAL);
        prw_cmd_transition(cmd, &tm->signal[vi], VK_IMAGE_LAYOUT_GENERAL);
        w[vi] = ctx->views[vi].width;
        h[vi] = ctx->views[vi].height;
    }
    record_apply(tm, cmd, tm->sets, w, h, ctx->view_count);
    return true;
}

const prw_pass prw_pass_tm_stats = {
    .name = "tm_stats",
    .reads = PRW_RES_HDR,
    .writes = PRW_RES_TM_STATS,
    .needed = stats_needed,
    .record = stats_record,
};

const prw_pass prw_pass_tonemap = {
    .name = "tonemap",
    .reads = PRW_RES_HDR | PRW_RES_TM_STATS,
    .writes = PRW_RES_LDR,
    .needed = tonemap_needed,
    .record = tonemap_record,
};

/* ---- public entry points (prw_render.h) ---- */

bool prw_renderer_set_tonemap(prw_renderer *r, const prw_display *d, const prw_tonemap_settings *s, prw_error *e)
{
    if (d && !prw_display_validate(d, d->name, e)) return false;
    if (s && (unsigned)s->op >= PRW_TM_OP_COUNT) return prw_fail(e, "render: tone-mapping operator %d unknown", s->op);
    if (d) r->tm->display = *d;
    if (s) r->tm->settings = *s;
    return true;
}

void prw_renderer_get_tonemap(const prw_renderer *r, prw_display *d, prw_tonemap_settings *s)
{
    if (d) *d = r->tm->display;
    if (s) *s = r->tm->settings;
}

bool prw_renderer_read_signal(prw_renderer *r, uint32_t v, prw_image *out, prw_error *e)
{
    if (v >= r->desc.max_views) return prw_fail(e, "render: no view %u", v);
    if (!prw_image_alloc(out, (int)r->desc.width, (int)r->desc.height, e)) return false;
    if (!prw_image_readback(r->gpu, &r->tm->signal[v], out->rgba, e)) {
        prw_image_free(out);
        return false;
    }
    return true;
}

static void read_report(const prw_tm_gpu *tm, prw_tm_stats *st, prw_tm_report *rep)
{
    const tm_stats_hdr *h = tm->stats.mapped;
    if (st) {
        st->log_avg = h->final_stats[0];
        st->max_lum = h->final_stats[1];
        st->count = (uint64_t)h->final_stats[2];
    }
    if (rep) {
        memset(rep, 0, sizeof *rep);
        if (tm->counted) {
            rep->below_black = h->counts[0];
            rep->above_peak = h->counts[1];
            rep->out_of_gamut = h->counts[2];
            rep->pixels = h->counts[3];
        }
    }
}

bool prw_renderer_tonemap_report(prw_renderer *r, prw_tm_stats *stats, prw_tm_report *rep)
{
    read_report(r->tm, stats, rep);
    return r->tm->counted;
}

bool prw_renderer_tonemap_image(prw_renderer *r, const prw_image *hdr, double ev100, prw_image *signal,
                                prw_tm_stats *stats, prw_tm_report *rep, prw_error *e)
{
    prw_tm_gpu *tm = r->tm;
    uint32_t w = (uint32_t)hdr->width, h = (uint32_t)hdr->height;
    if (tiles_for(w, h) > tm->tiles_per_view * r->desc.max_views)
        return prw_fail(e, "tonemap: %ux%u image larger than the renderer's stats buffer allows", w, h);
    prw_gpu_image in = {0}, ldr = {0}, sig = {0};
    prw_image_desc din = {.width = w, .height = h, .format = SIG_FORMAT,
                          .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
    prw_image_desc dldr = {.width = w, .height = h, .format = VK_FORMAT_R8G8B8A8_UNORM,
                           .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    prw_image_desc dsig = {.width = w, .height = h, .format = SIG_FORMAT,
                           .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    VkDescriptorSet set;
    VkCommandBuffer cmd;
    bool ok = prw_image_create(r->gpu, &din, &in, e) && prw_image_create(r->gpu, &dldr, &ldr, e) &&
              prw_image_create(r->gpu, &dsig, &sig, e) &&
              prw_image_upload(r->gpu, &in, 0, hdr->rgba, (size_t)w * h * 16, e) &&
              prw_desc_alloc(r->gpu, r->pool, tm->set_layout, &set, e);
    if (ok) {
        write_set(r, set, in.view, ldr.view, sig.view);
        upload_params(r, ev100);
        ok = prw_cmd_begin(r->gpu, &cmd, e);
    }
    if (ok) {
        prw_cmd_transition(cmd, &in, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        prw_cmd_transition(cmd, &ldr, VK_IMAGE_LAYOUT_GENERAL);
        prw_cmd_transition(cmd, &sig, VK_IMAGE_LAYOUT_GENERAL);
        bool need = op_needs_stats(tm->settings.op) || tm_counts(&tm->settings);
        if (!need) {
            tm->counted = false;
            ((tm_ubo *)tm->params.mapped)->mode[3] = 0;
        }
        if (need) record_stats(tm, cmd, &set, &w, &h, 1);
        record_apply(tm, cmd, &set, &w, &h, 1);
        ok = prw_cmd_submit_wait(r->gpu, cmd, e);
    }
    if (ok) ok = prw_image_alloc(signal, (int)w, (int)h, e) && prw_image_readback(r->gpu, &sig, signal->rgba, e);
    if (ok) read_report(tm, stats, rep);
    prw_image_destroy(r->gpu, &in);
    prw_image_destroy(r->gpu, &ldr);
    prw_image_destroy(r->gpu, &sig);
    return ok;
}
