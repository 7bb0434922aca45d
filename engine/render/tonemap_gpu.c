/* tonemap_gpu — display-aware tone mapping on the GPU (issue 6; tonemap_gpu.h): the state and the
 * recording of the two graph passes (pass_tonemap.c), of tone-mapping sessions and the public
 * tone-mapping calls of prw_render.h.  The passes:
 *   "tm_stats" (once for all views: a partial per invocation (16 pixels of a 64 x 64 region) and view
 *              -> one reduction: log-average and largest luminance, and zeroed classification
 *              counters); runs when the operator keys on frame statistics (reinhard, adaptive, local,
 *              selective).  The other operators, when statistics or counts are wanted (absolute,
 *              overlay, report, adaptation), get them from the apply pass itself: tonemap_fused.comp
 *              tone-maps and sums in one pass over the image, then the same reduction runs.
 *              Selective: the stats pass also classifies
 *              (tonemap_classify.comp: the Sobel of the log luminance it already computes gives each
 *              16 x 16 block's largest gradient), so the classification is not a pass of its own;
 *   "tonemap"  (per view: operator -> gamut mapping -> inverse display model; writes the signal V as
 *              RGBA8 for PNGs and presenting and, when the graph keeps it, as RGBA32F before
 *              quantisation).  Global operators with nothing counted and no statistics computed with
 *              them: a full-screen fragment pass (tonemap_apply.frag; on lavapipe colour attachments
 *              are written by vectorised format code, compute imageStores lane by lane), the images
 *              switched to colour-attachment layout and back inside the pass; with counts or fused
 *              statistics: tonemap_fused.comp; selective's global part: tonemap_apply.comp.
 *            local: instead of tonemap_apply.comp, full-image separable passes (tonemap_sep_lum.comp:
 *            scaled luminance; tonemap_sep_blur.comp: 9 levels x horizontal + vertical into layers of a
 *            scratch r32f array; tonemap_sep_final.comp: scale selection, Ld, encoding), or with
 *            settings.local_tiled tonemap_local.comp on every 16 x 16 block;
 *            selective: tonemap_compact.comp (tile marks from the block gradients; the 16 x 16 blocks
 *            within one tile of a marked tile: flags, lists in raster order, counts) ->
 *            tonemap_apply.comp (global curve on the other blocks) and the separable passes on the
 *            lists, dispatched indirectly (a blur level's horizontal pass runs on the blocks within its
 *            radius above or below a needed block and there only on the rows the vertical pass reads;
 *            the vertical pass and the final step on the needed blocks only).
 * Profiling (prw_tm_session_profile): the dispatches are recorded through tm_dispatch*, which leave out
 * every scope from prof_limit on, so a scope's time is the difference of two runs' wall times.
 * The pipelines are specialised (operator, encoding, overlay, counting, float signal, identity display
 * matrix): on lavapipe every branch of a shader costs whether taken or not.
 * The C reference is tonemap_ops.c; shaders/tonemap_*.comp / .frag mirror it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_shaders.h"
#include "render_internal.h"
#include "tonemap_gpu.h"

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
    float adapt[4];
} tm_ubo;

/* std430 header of the stats buffer; partial slots (vec4) follow */
typedef struct tm_stats_hdr {
    float final_stats[4];
    uint32_t counts[4];
} tm_stats_hdr;

struct prw_tm_gpu {
    prw_gpu *gpu;
    prw_desc_pool *pool;
    uint32_t width, height, max_views;
    prw_display display;
    prw_tonemap_settings settings;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline stats_pipe, reduce_pipe, classify_pipe, compact_pipe, local_pipe;
    /* the apply pass specialised on the UBO's mode (op, eotf, overlay, count), on whether it writes the
     * float signal, and fused with the statistics or not: built on first use */
    VkPipeline apply_spec[PRW_TM_OP_COUNT][PRW_EOTF_PQ + 1][2][2][2][2][2]; /* ..., identity primaries */
    VkPipeline apply_pipe; /* this frame's, one of apply_spec (ensure_apply) */
    bool fused;            /* this frame's apply computes the statistics too (tonemap_fused.comp) */
    bool use_fs;           /* this frame's apply is the fragment pass (tonemap_apply.frag): no counts, no statistics */
    VkPipeline apply_fs[PRW_TM_OP_COUNT][PRW_EOTF_PQ + 1][2][2]; /* operator, encoding, signal, identity */
    prw_gpu_image *ldr[PRW_MAX_VIEWS]; /* graph images (pass_tonemap.c binds them) */
    bool write_signal;     /* the apply writes the float signal */
    uint32_t slot_cap;     /* partial slots of the statistics (the counts' partials follow them) */
    /* without the float signal (write_signal false): the local passes' variants that skip its stores,
     * and a 1 x 1 image bound in its place (made on first use) */
    VkPipeline sep_final_nosig, local_nosig;
    prw_gpu_image dummy_sig;
    /* separable local: set 1 = the scratch image (layers: L, horizontal, 9 levels), made on first use */
    VkDescriptorSetLayout sep_set_layout;
    VkPipelineLayout sep_layout;
    VkPipeline sep_lum_pipe, sep_blur_pipe, sep_final_pipe;
    prw_gpu_image sep_img;
    VkDescriptorSet sep_set;
    uint32_t sep_w, sep_h;
    prw_buffer params; /* UPLOAD uniform */
    prw_buffer stats;  /* READBACK storage: header + partials */
    prw_buffer tiles;  /* READBACK storage + indirect: per view a header + marks, needs, block list */
    VkDeviceSize tile_stride; /* bytes per view in `tiles` */
    VkDeviceSize last_tile_off; /* the region of the last view tone-mapped (report) */
    uint32_t tiles_per_view;
    prw_gpu_image *signal[PRW_MAX_VIEWS]; /* graph images (pass_tonemap.c binds them) */
    VkDescriptorSet sets[PRW_MAX_VIEWS];
    bool counted; /* the last frame classified pixels */
    /* temporal adaptation (render path only): La, whether it has a value, the previous frame's
     * statistics were computed, the frame time for the next step (< 0: measured) and the clock */
    double la;
    bool la_valid, prev_stats;
    double dt_next, last_time;
    /* profiling (prw_tm_session_profile): named scopes; with prof_limit >= 0 the dispatches of scopes
     * from prof_limit on are not recorded (prefix timing: GPU timestamps are not usable on lavapipe,
     * whose compute dispatches run synchronously outside its timestamp queries) */
    int prof_limit, prof_count;
    char prof_names[64][24];
};

/* starts the profiling scope `name` (the dispatches up to the next scope belong to it) */
static void tb(prw_tm_gpu *tm, const char *name)
{
    if (tm->prof_count < 64) snprintf(tm->prof_names[tm->prof_count], sizeof tm->prof_names[0], "%s", name);
    tm->prof_count++;
}
static bool tm_on(const prw_tm_gpu *tm) { return tm->prof_limit < 0 || tm->prof_count <= tm->prof_limit; }
static void tm_dispatch(prw_tm_gpu *tm, VkCommandBuffer cmd, uint32_t x, uint32_t y, uint32_t z)
{
    if (tm_on(tm)) vkCmdDispatch(cmd, x, y, z);
}
static void tm_dispatch_indirect(prw_tm_gpu *tm, VkCommandBuffer cmd, VkBuffer b, VkDeviceSize off)
{
    if (tm_on(tm)) vkCmdDispatchIndirect(cmd, b, off);
}

static bool op_needs_stats(prw_tm_op op)
{
    return op == PRW_TM_REINHARD || op == PRW_TM_ADAPTIVE || op == PRW_TM_LOCAL || op == PRW_TM_SELECTIVE;
}

/* bytes of the selective tile region for a w x h view (tiles of 16 at most as many as blocks) */
static VkDeviceSize tile_bytes(uint32_t w, uint32_t h)
{
    VkDeviceSize nb = (VkDeviceSize)((w + 15) / 16) * ((h + 15) / 16);
    return (20 + 8 * nb) * 4; /* header, marks, needs, 5 lists, block gradients (tonemap_compact.comp) */
}
static bool tm_counts(const prw_tonemap_settings *s)
{
    return s->report || s->overlay || s->op == PRW_TM_ABSOLUTE;
}

static uint32_t tiles_for(uint32_t w, uint32_t h) { return ((w + TILE - 1) / TILE) * ((h + TILE - 1) / TILE); }
/* workgroups of the stats pass: 64 x 64 pixel regions (tonemap_stats.glsl), 256 partial slots each */
static uint32_t stats_groups(uint32_t w, uint32_t h) { return ((w + 63) / 64) * ((h + 63) / 64); }
static uint32_t stats_slots(uint32_t w, uint32_t h) { return stats_groups(w, h) * 256; }

/* Statistics or pixel counts wanted beyond what the operator itself keys on. */
static bool stats_wanted(const prw_tonemap_settings *s)
{
    return tm_counts(s) || (s->adapt && s->op != PRW_TM_ABSOLUTE);
}
/* The statistics are computed by the apply pass itself (tonemap_fused.comp): wanted, and the operator
 * does not need them before it maps a pixel. */
static bool fused_stats(const prw_tonemap_settings *s) { return !op_needs_stats(s->op) && stats_wanted(s); }

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
    float op2[4] = {(float)p->toe_p, (float)PRW_TM_SHOULDER_LAMBDA, (float)p->sel_threshold, (float)p->sel_tile};
    memcpy(u->range, range, sizeof range);
    memcpy(u->disp, disp, sizeof disp);
    memcpy(u->enc, enc, sizeof enc);
    memcpy(u->op1, op1, sizeof op1);
    memcpy(u->op2, op2, sizeof op2);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) u->m[r][c] = (float)p->m[3 * r + c];
    u->adapt[0] = (float)p->adapt_la;
    u->adapt[1] = p->adapt_la > 0 ? 1.0f : 0.0f;
}

static void write_set(prw_tm_gpu *tm, VkDescriptorSet set, VkImageView src, VkImageView ldr, VkImageView sig,
                      VkDeviceSize tile_off, VkDeviceSize tile_range)
{
    prw_desc_write_image(tm->gpu, set, 0, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, src,
                         prw_gpu_sampler(tm->gpu, PRW_SAMPLER_NEAREST_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(tm->gpu, set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, ldr, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    prw_desc_write_image(tm->gpu, set, 2, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, sig, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    prw_desc_write_buffer(tm->gpu, set, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tm->stats, 0, 0);
    prw_desc_write_buffer(tm->gpu, set, 4, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &tm->params, 0, sizeof(tm_ubo));
    prw_desc_write_buffer(tm->gpu, set, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tm->tiles, tile_off, tile_range);
}

bool prw_tm_gpu_create(prw_gpu *gpu, prw_desc_pool *pool, uint32_t width, uint32_t height, uint32_t max_views,
                       prw_tm_op op, prw_tm_gpu **out, prw_error *e)
{
    prw_tm_gpu *tm = prw_calloc(1, sizeof *tm);
    *out = tm;
    tm->gpu = gpu;
    tm->pool = pool;
    tm->width = width;
    tm->height = height;
    tm->max_views = max_views;
    prw_display_builtin("srgb", &tm->display);
    tm->dt_next = -1;
    tm->prof_limit = -1;
    tm->write_signal = true;
    tm->settings.op = (unsigned)op < PRW_TM_OP_COUNT ? op : PRW_TM_EXPOSURE;
    const VkShaderStageFlags cf = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_FRAGMENT_BIT; /* tonemap_apply.frag */
    VkDescriptorSetLayoutBinding b[6] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cf, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cf, NULL},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cf, NULL},
        {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cf, NULL},
        {4, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, cf, NULL},
        {5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cf, NULL},
    };
    if (!prw_desc_layout_create(gpu, b, 6, &tm->set_layout, e) ||
        !prw_pipeline_layout_create(gpu, &tm->set_layout, 1, sizeof(tm_pc), &tm->layout, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_stats_comp(), tm->layout, &tm->stats_pipe, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_reduce_comp(), tm->layout, &tm->reduce_pipe, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_classify_comp(), tm->layout, &tm->classify_pipe, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_compact_comp(), tm->layout, &tm->compact_pipe, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_local_comp(), tm->layout, &tm->local_pipe, e))
        return false;
    VkDescriptorSetLayoutBinding sb = {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    VkDescriptorSetLayout two[2];
    if (!prw_desc_layout_create(gpu, &sb, 1, &tm->sep_set_layout, e)) return false;
    two[0] = tm->set_layout;
    two[1] = tm->sep_set_layout;
    if (!prw_pipeline_layout_create(gpu, two, 2, sizeof(tm_pc), &tm->sep_layout, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_sep_lum_comp(), tm->sep_layout, &tm->sep_lum_pipe, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_sep_blur_comp(), tm->sep_layout, &tm->sep_blur_pipe, e) ||
        !prw_pipeline_compute(gpu, prw_shader_tonemap_sep_final_comp(), tm->sep_layout, &tm->sep_final_pipe, e))
        return false;
    tm->tile_stride = (tile_bytes(width, height) + 255) & ~(VkDeviceSize)255;
    if (!prw_buffer_create(gpu, tm->tile_stride * max_views,
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, PRW_MEM_READBACK,
                           &tm->tiles, e))
        return false;
    memset(tm->tiles.mapped, 0, (size_t)(tm->tile_stride * max_views));
    tm->tiles_per_view = tiles_for(width, height);
    tm->slot_cap = stats_slots(width, height) * max_views;
    VkDeviceSize stats_size = sizeof(tm_stats_hdr) + (VkDeviceSize)tm->slot_cap * 2 * 16;
    if (!prw_buffer_create(gpu, sizeof(tm_ubo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD, &tm->params,
                           e) ||
        !prw_buffer_create(gpu, stats_size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, PRW_MEM_READBACK, &tm->stats, e))
        return false;
    memset(tm->stats.mapped, 0, (size_t)stats_size);
    for (uint32_t v = 0; v < max_views; v++)
        if (!prw_desc_alloc(gpu, pool, tm->set_layout, &tm->sets[v], e)) return false;
    return true;
}

bool prw_tm_gpu_bind_view(prw_tm_gpu *tm, uint32_t v, prw_gpu_image *hdr, prw_gpu_image *ldr, prw_gpu_image *signal,
                          prw_error *e)
{
    tm->signal[v] = signal;
    tm->ldr[v] = ldr;
    if (!signal && !tm->dummy_sig.image) { /* a storage image for the binding the shaders then never write */
        prw_image_desc d = {.width = 1, .height = 1, .format = SIG_FORMAT, .usage = VK_IMAGE_USAGE_STORAGE_BIT};
        VkCommandBuffer cmd;
        if (!prw_image_create(tm->gpu, &d, &tm->dummy_sig, e) || !prw_cmd_begin(tm->gpu, &cmd, e)) return false;
        prw_cmd_transition(cmd, &tm->dummy_sig, VK_IMAGE_LAYOUT_GENERAL);
        if (!prw_cmd_submit_wait(tm->gpu, cmd, e)) return false;
    }
    write_set(tm, tm->sets[v], hdr->view, ldr->view, signal ? signal->view : tm->dummy_sig.view, v * tm->tile_stride,
              tm->tile_stride);
    return true;
}

/* The local passes' pipelines without the signal's stores (spec constant 4 = 0; 0-3 read the UBO). */
static bool ensure_nosig(prw_tm_gpu *tm, prw_error *e)
{
    if (tm->write_signal || (tm->settings.op != PRW_TM_LOCAL && tm->settings.op != PRW_TM_SELECTIVE)) return true;
    uint32_t spec[5] = {UINT32_MAX, UINT32_MAX, UINT32_MAX, UINT32_MAX, 0};
    if (!tm->sep_final_nosig &&
        !prw_pipeline_compute_spec(tm->gpu, prw_shader_tonemap_sep_final_comp(), tm->sep_layout, spec, 5,
                                   &tm->sep_final_nosig, e))
        return false;
    if (!tm->local_nosig &&
        !prw_pipeline_compute_spec(tm->gpu, prw_shader_tonemap_local_comp(), tm->layout, spec, 5, &tm->local_nosig, e))
        return false;
    return true;
}

VkBuffer prw_tm_gpu_stats_buffer(const prw_tm_gpu *tm) { return tm->stats.buffer; }
VkBuffer prw_tm_gpu_tiles_buffer(const prw_tm_gpu *tm) { return tm->tiles.buffer; }

void prw_tm_gpu_destroy(prw_tm_gpu *tm)
{
    if (!tm) return;
    VkDevice dev = prw_gpu_device(tm->gpu);
    prw_buffer_destroy(tm->gpu, &tm->params);
    prw_buffer_destroy(tm->gpu, &tm->stats);
    prw_buffer_destroy(tm->gpu, &tm->tiles);
    prw_image_destroy(tm->gpu, &tm->sep_img);
    prw_image_destroy(tm->gpu, &tm->dummy_sig);
    if (tm->sep_final_nosig) prw_pipeline_release(tm->gpu, tm->sep_final_nosig);
    if (tm->local_nosig) prw_pipeline_release(tm->gpu, tm->local_nosig);
    VkPipeline pipes[8] = {tm->stats_pipe, tm->reduce_pipe,  tm->classify_pipe, tm->compact_pipe,
                           tm->local_pipe, tm->sep_lum_pipe, tm->sep_blur_pipe, tm->sep_final_pipe};
    for (int i = 0; i < 8; i++)
        if (pipes[i]) prw_pipeline_release(tm->gpu, pipes[i]);
    VkPipeline *spec = &tm->apply_spec[0][0][0][0][0][0][0];
    for (size_t i = 0; i < sizeof tm->apply_spec / sizeof *spec; i++)
        if (spec[i]) prw_pipeline_release(tm->gpu, spec[i]);
    VkPipeline *fsp = &tm->apply_fs[0][0][0][0];
    for (size_t i = 0; i < sizeof tm->apply_fs / sizeof *fsp; i++)
        if (fsp[i]) prw_pipeline_release(tm->gpu, fsp[i]);
    if (tm->sep_layout) vkDestroyPipelineLayout(dev, tm->sep_layout, NULL);
    if (tm->sep_set_layout) vkDestroyDescriptorSetLayout(dev, tm->sep_set_layout, NULL);
    if (tm->layout) vkDestroyPipelineLayout(dev, tm->layout, NULL);
    if (tm->set_layout) vkDestroyDescriptorSetLayout(dev, tm->set_layout, NULL);
    free(tm);
}

/* Where the dispatches go: a pass of the graph (barriers counted there) or a session's own buffer. */
typedef struct tm_rec {
    VkCommandBuffer cmd;
    const prw_pass_ctx *c; /* NULL: a session */
} tm_rec;

static void compute_barrier(const tm_rec *t, VkPipelineStageFlags2 src, VkAccessFlags2 src_access,
                            VkPipelineStageFlags2 dst, VkAccessFlags2 dst_access)
{
    if (t->c) {
        prw_pass_memory_barrier(t->c, src, src_access, dst, dst_access);
        return;
    }
    VkCommandBuffer cmd = t->cmd;
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

/* The chain on `count` inputs (all already in SHADER_READ_ONLY_OPTIMAL, outputs in GENERAL).  In a
 * graph pass the graph orders the stats buffer against earlier and later passes; a session orders it
 * itself. */
static void record_stats(prw_tm_gpu *tm, const tm_rec *t, const VkDescriptorSet *sets, const uint32_t *w,
                         const uint32_t *h, uint32_t count)
{
    VkCommandBuffer cmd = t->cmd;
    if (!t->c) compute_barrier(t, CS | VK_PIPELINE_STAGE_2_HOST_BIT, RW | VK_ACCESS_2_HOST_READ_BIT, CS, RW);
    bool sel = tm->settings.op == PRW_TM_SELECTIVE; /* fused with the classification */
    tb(tm, sel ? "stats+classify" : "stats");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, sel ? tm->classify_pipe : tm->stats_pipe);
    uint32_t base = 0;
    for (uint32_t v = 0; v < count; v++) {
        tm_pc pc = {w[v], h[v], base, 0};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->layout, 0, 1, &sets[v], 0, NULL);
        vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        tm_dispatch(tm, cmd, (w[v] + 63) / 64, (h[v] + 63) / 64, 1);
        base += stats_slots(w[v], h[v]);
    }
    compute_barrier(t, CS, RW, CS, RW);
    tb(tm, "reduce");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->reduce_pipe);
    tm_pc pc = {0, 0, 0, base};
    vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    tm_dispatch(tm, cmd, 1, 1, 1);
    if (!t->c) compute_barrier(t, CS, RW, CS, RW);
}

/* The scratch image of the separable local operator, at least w x h (recreated larger when needed). */
static bool ensure_sep(prw_tm_gpu *tm, uint32_t w, uint32_t h, prw_error *e)
{
    bool sep = (tm->settings.op == PRW_TM_LOCAL && !tm->settings.local_tiled) || tm->settings.op == PRW_TM_SELECTIVE;
    if (!sep) return true;
    if (tm->sep_img.image && tm->sep_w >= w && tm->sep_h >= h) return true;
    prw_image_destroy(tm->gpu, &tm->sep_img);
    tm->sep_w = PRW_MAX(w, tm->sep_w);
    tm->sep_h = PRW_MAX(h, tm->sep_h);
    prw_image_desc d = {.width = tm->sep_w, .height = tm->sep_h, .layers = 11, .format = VK_FORMAT_R32_SFLOAT,
                        .usage = VK_IMAGE_USAGE_STORAGE_BIT, .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    if (!prw_image_create(tm->gpu, &d, &tm->sep_img, e)) return false;
    if (!tm->sep_set && !prw_desc_alloc(tm->gpu, tm->pool, tm->sep_set_layout, &tm->sep_set, e)) return false;
    prw_desc_write_image(tm->gpu, tm->sep_set, 0, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, tm->sep_img.view, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    return true;
}

/* Selective: dispatches list k of the view's tile region (indirect); local: the block grid. */
static void sep_dispatch(prw_tm_gpu *tm, VkCommandBuffer cmd, VkDeviceSize tile_off, uint32_t gx, uint32_t gy, int list)
{
    if (tm->settings.op == PRW_TM_SELECTIVE) tm_dispatch_indirect(tm, cmd, tm->tiles.buffer, tile_off + 12 * (VkDeviceSize)list);
    else tm_dispatch(tm, cmd, gx, gy, 1);
}

static int sep_rows(uint32_t lev) /* list of a level's horizontal pass: ceil(radius / 16) */
{
    return (prw_tm_local_radius((int)lev) + 15) / 16;
}

static void record_local_sep(prw_tm_gpu *tm, const tm_rec *t, VkDescriptorSet set, uint32_t w, uint32_t h,
                             VkDeviceSize tile_off)
{
    VkCommandBuffer cmd = t->cmd;
    VkDescriptorSet sets[2] = {set, tm->sep_set};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->sep_layout, 0, 2, sets, 0, NULL);
    if (tm->sep_img.layout != VK_IMAGE_LAYOUT_GENERAL) {
        if (t->c) prw_pass_transition(t->c, &tm->sep_img, VK_IMAGE_LAYOUT_GENERAL);
        else prw_cmd_transition(cmd, &tm->sep_img, VK_IMAGE_LAYOUT_GENERAL);
    }
    compute_barrier(t, CS, RW, CS, RW); /* an earlier view's use of the scratch image */
    uint32_t gx = (w + 15) / 16, gy = (h + 15) / 16;
    tm_pc pc = {w, h, 0, 0};
    tb(tm, "sep_lum");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->sep_lum_pipe);
    vkCmdPushConstants(cmd, tm->sep_layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    sep_dispatch(tm, cmd, tile_off, gx, gy, 4);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->sep_blur_pipe);
    for (uint32_t lev = 0; lev <= PRW_TM_LOCAL_SCALES; lev++)
        for (uint32_t dir = 0; dir < 2; dir++) {
            compute_barrier(t, CS, RW, CS, RW);
            char nm[24];
            snprintf(nm, sizeof nm, "blur%u%c", lev, dir ? 'v' : 'h');
            tb(tm, nm);
            tm_pc bp = {w, h, lev, dir};
            vkCmdPushConstants(cmd, tm->sep_layout, VK_SHADER_STAGE_ALL, 0, sizeof bp, &bp);
            sep_dispatch(tm, cmd, tile_off, gx, gy, dir ? 0 : sep_rows(lev));
        }
    compute_barrier(t, CS, RW, CS, RW);
    tb(tm, "sep_final");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->write_signal ? tm->sep_final_pipe : tm->sep_final_nosig);
    vkCmdPushConstants(cmd, tm->sep_layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    sep_dispatch(tm, cmd, tile_off, gx, gy, 0);
    compute_barrier(t, CS, RW, CS, RW);
}

/* The apply pipeline for the mode the UBO now holds (tonemap_common.glsl's specialisation constants). */
static bool ensure_apply(prw_tm_gpu *tm, prw_error *e)
{
    const tm_ubo *u = tm->params.mapped;
    uint32_t op = (uint32_t)u->mode[0], eotf = (uint32_t)u->mode[1], ov = u->mode[2] != 0, cnt = u->mode[3] != 0;
    if (op >= PRW_TM_OP_COUNT || eotf > PRW_EOTF_PQ)
        return prw_fail(e, "render: tone map: operator %u / encoding %u unknown", op, eotf);
    uint32_t sig = tm->write_signal, fu = tm->fused;
    uint32_t id = 1; /* the UBO's display matrix is exactly the identity (Rec.709 displays) */
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) id &= u->m[r][c] == (r == c ? 1.0f : 0.0f);
    /* nothing counted and no statistics with it: the fragment pass (colour attachments) */
    tm->use_fs = !fu && !cnt && !ov && (op == PRW_TM_EXPOSURE || op == PRW_TM_REINHARD || op == PRW_TM_NEUTRAL ||
                                        op == PRW_TM_ADAPTIVE);
    if (tm->use_fs) {
        VkPipeline *f = &tm->apply_fs[op][eotf][sig][id];
        prw_graphics_desc d = {.vs = prw_shader_tonemap_fs_vert(),
                               .fs = sig ? prw_shader_tonemap_apply_sig_frag() : prw_shader_tonemap_apply_frag(),
                               .fs_spec = {op, eotf, 0, 0, sig, id},
                               .fs_spec_count = 6,
                               .layout = tm->layout,
                               .color_formats = {VK_FORMAT_R8G8B8A8_UNORM, SIG_FORMAT},
                               .color_count = sig ? 2 : 1};
        if (!*f && !prw_pipeline_graphics(tm->gpu, &d, f, e)) return prw_fail_wrap(e, "render: tone map");
        tm->apply_pipe = *f;
        return true;
    }
    VkPipeline *p = &tm->apply_spec[op][eotf][ov][cnt][sig][fu][id];
    uint32_t spec[6] = {op, eotf, ov, cnt, sig, id};
    if (!*p && !prw_pipeline_compute_spec(tm->gpu, fu ? prw_shader_tonemap_fused_comp() : prw_shader_tonemap_apply_comp(),
                                          tm->layout, spec, 6, p, e))
        return prw_fail_wrap(e, "render: tone map");
    tm->apply_pipe = *p;
    return true;
}

static void tm_transition(const tm_rec *t, prw_gpu_image *img, VkImageLayout layout)
{
    if (t->c) prw_pass_transition(t->c, img, layout);
    else prw_cmd_transition(t->cmd, img, layout);
}

/* The fragment-shader apply of one view into ldr (and sig when not NULL), which are in GENERAL before
 * and after (the pass declares them as storage images). */
static void record_apply_fs(prw_tm_gpu *tm, const tm_rec *t, VkDescriptorSet set, uint32_t w, uint32_t h,
                            prw_gpu_image *ldr, prw_gpu_image *sig)
{
    VkCommandBuffer cmd = t->cmd;
    prw_gpu_image *img[2] = {ldr, sig};
    uint32_t n = sig ? 2 : 1;
    for (uint32_t i = 0; i < n; i++) tm_transition(t, img[i], VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    /* the statistics (reinhard, adaptive) were written by a compute pass */
    compute_barrier(t, CS, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    VkRenderingAttachmentInfo at[2];
    for (uint32_t i = 0; i < n; i++)
        at[i] = (VkRenderingAttachmentInfo){.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
                                            .imageView = img[i]->view,
                                            .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                            .loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                                            .storeOp = VK_ATTACHMENT_STORE_OP_STORE};
    VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                          .renderArea = {{0, 0}, {w, h}},
                          .layerCount = 1,
                          .colorAttachmentCount = n,
                          .pColorAttachments = at};
    if (t->c) prw_pass_begin_rendering(t->c, &ri);
    else vkCmdBeginRendering(cmd, &ri);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, tm->apply_pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, tm->layout, 0, 1, &set, 0, NULL);
    tm_pc pc = {w, h, 0, 0};
    vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    prw_cmd_viewport(cmd, w, h);
    if (tm_on(tm)) vkCmdDraw(cmd, 3, 1, 0, 0);
    if (t->c) prw_pass_end_rendering(t->c);
    else vkCmdEndRendering(cmd);
    for (uint32_t i = 0; i < n; i++) tm_transition(t, img[i], VK_IMAGE_LAYOUT_GENERAL);
}

static void record_apply(prw_tm_gpu *tm, const tm_rec *t, const VkDescriptorSet *sets, const uint32_t *w,
                         const uint32_t *h, const VkDeviceSize *tile_off, prw_gpu_image *const *ldr,
                         prw_gpu_image *const *sig, uint32_t count)
{
    VkCommandBuffer cmd = t->cmd;
    prw_tm_op op = tm->settings.op;
    uint32_t base = 0; /* fused: the view's first partial slot */
    if (tm->fused && !t->c) compute_barrier(t, CS | VK_PIPELINE_STAGE_2_HOST_BIT, RW | VK_ACCESS_2_HOST_READ_BIT, CS, RW);
    for (uint32_t v = 0; v < count; v++) {
        if (tm->use_fs) {
            tb(tm, "apply_fs");
            record_apply_fs(tm, t, sets[v], w[v], h[v], ldr[v], tm->write_signal ? sig[v] : NULL);
            continue;
        }
        tm_pc pc = {w[v], h[v], base, tm->slot_cap};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->layout, 0, 1, &sets[v], 0, NULL);
        vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        if (op == PRW_TM_LOCAL && !tm->settings.local_tiled) {
            record_local_sep(tm, t, sets[v], w[v], h[v], tile_off[v]);
            continue;
        }
        if (op == PRW_TM_LOCAL) {
            tb(tm, "local_tiled");
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->write_signal ? tm->local_pipe : tm->local_nosig);
            tm_dispatch(tm, cmd, (w[v] + 15) / 16, (h[v] + 15) / 16, 1);
            compute_barrier(t, CS, RW, CS, RW);
            continue;
        }
        if (op == PRW_TM_SELECTIVE) { /* the stats pass left each block's largest gradient */
            tb(tm, "compact");
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->compact_pipe);
            tm_dispatch(tm, cmd, 1, 1, 1);
            compute_barrier(t, CS, RW, CS | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                            RW | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
        }
        if (tm->fused) { /* 64 x 64 regions, statistics and counts into partial slots */
            tb(tm, "stats+apply");
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->apply_pipe);
            tm_dispatch(tm, cmd, (w[v] + 63) / 64, (h[v] + 63) / 64, 1);
            base += stats_slots(w[v], h[v]);
            continue;
        }
        tb(tm, "apply");
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->apply_pipe);
        tm_dispatch(tm, cmd, (w[v] + 15) / 16, (h[v] + 15) / 16, 1);
        compute_barrier(t, CS, RW, CS, RW);
        if (op == PRW_TM_SELECTIVE) record_local_sep(tm, t, sets[v], w[v], h[v], tile_off[v]); /* pixels disjoint from apply's */
    }
    if (tm->fused) { /* the frame's statistics and counts from every view's partials */
        compute_barrier(t, CS, RW, CS, RW);
        tb(tm, "reduce");
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tm->reduce_pipe);
        tm_pc pc = {tm->counted ? 1u : 0u, 0, tm->slot_cap, base};
        vkCmdPushConstants(cmd, tm->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        tm_dispatch(tm, cmd, 1, 1, 1);
        compute_barrier(t, CS, RW, CS, RW);
    }
    if (count) tm->last_tile_off = tile_off[count - 1];
    /* the stats and tile buffers are read by the host after the frame (in a graph: its export barrier) */
    if (!t->c) compute_barrier(t, CS, RW, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

/* Render path, before recording a frame: steps La towards the previous frame's log-average. */
static void adapt_frame(prw_tm_gpu *tm)
{
    const prw_tonemap_settings *s = &tm->settings;
    double now = prw_now();
    double dt = tm->dt_next >= 0 ? tm->dt_next : (tm->last_time > 0 ? now - tm->last_time : 0.0);
    tm->last_time = now;
    tm->dt_next = -1;
    if (!s->adapt || s->op == PRW_TM_ABSOLUTE) {
        tm->la_valid = false;
        return;
    }
    if (!tm->prev_stats) return; /* nothing measured yet: this frame keys on its own statistics */
    double target = ((const tm_stats_hdr *)tm->stats.mapped)->final_stats[0];
    if (!(target > 0) || !isfinite(target)) return;
    if (!tm->la_valid) {
        tm->la = target;
        tm->la_valid = true;
    }
    tm->la = prw_tm_adapt_step(tm->la, target, dt, s->tau_bright > 0 ? s->tau_bright : PRW_TM_TAU_BRIGHT,
                               s->tau_dark > 0 ? s->tau_dark : PRW_TM_TAU_DARK);
}

static void upload_params(prw_tm_gpu *tm, double ev100, bool adapted)
{
    prw_tm_params p;
    prw_tm_prepare(&tm->settings, &tm->display, prw_exposure_scale(ev100), &p);
    if (adapted && tm->la_valid) prw_tm_set_adaptation(&p, tm->la);
    tm_ubo u;
    tm->counted = tm_counts(&tm->settings);
    fill_ubo(&p, tm->counted, &u);
    memcpy(tm->params.mapped, &u, sizeof u);
}

bool prw_tm_gpu_adaptation(const prw_tm_gpu *tm, double *la)
{
    *la = tm->la_valid ? tm->la : 0.0;
    return tm->la_valid;
}

bool prw_tm_gpu_stats_needed(const prw_tm_gpu *tm) { return op_needs_stats(tm->settings.op); }

void prw_tm_gpu_record_stats(prw_tm_gpu *tm, const prw_pass_ctx *c)
{
    uint32_t w[PRW_MAX_VIEWS], h[PRW_MAX_VIEWS];
    for (uint32_t vi = 0; vi < c->frame->view_count; vi++) {
        w[vi] = c->frame->views[vi].width;
        h[vi] = c->frame->views[vi].height;
    }
    tm->prof_count = 0; /* profiling is for sessions; keep the counter bounded */
    tm_rec t = {c->cmd, c};
    record_stats(tm, &t, tm->sets, w, h, c->frame->view_count);
}

bool prw_tm_gpu_record_apply(prw_tm_gpu *tm, const prw_pass_ctx *c, bool stats_ran, prw_error *e)
{
    if (!ensure_sep(tm, tm->width, tm->height, e)) return false;
    adapt_frame(tm);
    upload_params(tm, c->frame->views[0].ev100, true); /* both eyes share one exposure and La (DESIGN.md §6) */
    tm->fused = fused_stats(&tm->settings);
    tm->write_signal = tm->signal[0] != NULL; /* the graph keeps it for every view or for none */
    tm->prev_stats = stats_ran || tm->fused;
    if (!stats_ran && !tm->fused) tm->counted = false;
    if (!tm->counted) { /* keep the UBO consistent with the graph: no counting without the stats pass */
        tm_ubo *u = tm->params.mapped;
        u->mode[3] = 0;
    }
    if (!ensure_apply(tm, e) || !ensure_nosig(tm, e)) return false;
    uint32_t w[PRW_MAX_VIEWS], h[PRW_MAX_VIEWS];
    VkDeviceSize off[PRW_MAX_VIEWS];
    for (uint32_t vi = 0; vi < c->frame->view_count; vi++) {
        off[vi] = vi * tm->tile_stride;
        w[vi] = c->frame->views[vi].width;
        h[vi] = c->frame->views[vi].height;
    }
    tm->prof_count = 0;
    tm_rec t = {c->cmd, c};
    record_apply(tm, &t, tm->sets, w, h, off, tm->ldr, tm->signal, c->frame->view_count);
    return true;
}

/* ---- public entry points (prw_render.h) ---- */

bool prw_renderer_set_tonemap(prw_renderer *r, const prw_display *d, const prw_tonemap_settings *s, prw_error *e)
{
    if (d && !prw_display_validate(d, d->name, e)) return false;
    if (s && (unsigned)s->op >= PRW_TM_OP_COUNT) return prw_fail(e, "render: tone-mapping operator %d unknown", s->op);
    if (s && (s->sel_tile % 16 != 0 || s->sel_tile > 256))
        return prw_fail(e, "render: selective tile size %u is not 0 or a multiple of 16 up to 256", s->sel_tile);
    if (s && !(s->sel_threshold >= 0 && s->tau_bright >= 0 && s->tau_dark >= 0 && isfinite(s->sel_threshold) &&
               isfinite(s->tau_bright) && isfinite(s->tau_dark)))
        return prw_fail(e, "render: selective threshold and adaptation time constants must be finite and >= 0");
    if (d) r->tm->display = *d;
    if (s) {
        const prw_tonemap_settings *o = &r->tm->settings;
        if (s->op != o->op || s->adapt != o->adapt || s->tau_bright != o->tau_bright || s->tau_dark != o->tau_dark)
            r->tm->la_valid = r->tm->prev_stats = false; /* a new adaptation state */
        r->tm->settings = *s;
    }
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
    if (!r->tm->signal[v] || !prw_image_readback(r->gpu, r->tm->signal[v], out->rgba, e)) {
        if (!r->tm->signal[v])
            prw_fail(e, "render: view %u has no display signal (renderer created without display_signal)", v);
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
        if (tm->settings.op == PRW_TM_SELECTIVE) {
            const uint32_t *t = (const uint32_t *)((const char *)tm->tiles.mapped + tm->last_tile_off);
            rep->tiles_marked = t[15];
            rep->tiles = t[16];
            rep->blocks_local = t[17];
            rep->blocks = t[18];
        }
    }
}

void prw_renderer_tonemap_advance(prw_renderer *r, double dt) { r->tm->dt_next = dt >= 0 && isfinite(dt) ? dt : -1; }

bool prw_renderer_tonemap_adaptation(const prw_renderer *r, double *la)
{
    if (la) *la = r->tm->la_valid ? r->tm->la : 0.0;
    return r->tm->la_valid;
}

bool prw_renderer_tonemap_report(prw_renderer *r, prw_tm_stats *stats, prw_tm_report *rep)
{
    read_report(r->tm, stats, rep);
    return r->tm->counted;
}

struct prw_tm_session {
    prw_renderer *r;
    uint32_t w, h;
    prw_gpu_image in, ldr, sig;
    prw_gpu_image copy; /* prw_tm_session_time_copy's destination (made on first use) */
    prw_desc_pool *pool; /* the session's own: its set goes with it (the renderer's pool only grows) */
    VkDescriptorSet set;
    /* the yardsticks (prw_tm_session_time_floor), made on first use */
    VkDescriptorSetLayout floor_set_layout;
    VkPipelineLayout floor_layout;
    VkDescriptorSet floor_set;
    prw_buffer floor_buf; /* one uint per pixel */
    VkPipeline floor_pipe[PRW_TM_FLOOR_COUNT];
};

static const char *const floor_names[PRW_TM_FLOOR_COUNT] = {
    "cs dispatch only", "cs read only", "cs -> rgba8 image", "cs -> rgba32f image", "cs -> rgba8 buffer",
    "cs read + stats reduction", "cs stats, no barrier", "cs read + log", "fs -> rgba8 attachment", "fs -> rgba8 + rgba32f attachments"};

const char *prw_tm_floor_name(prw_tm_floor k) { return (unsigned)k < PRW_TM_FLOOR_COUNT ? floor_names[k] : "?"; }

static void floor_destroy(prw_tm_session *s)
{
    VkDevice dev = prw_gpu_device(s->r->gpu);
    for (int i = 0; i < PRW_TM_FLOOR_COUNT; i++)
        if (s->floor_pipe[i]) prw_pipeline_release(s->r->gpu, s->floor_pipe[i]);
    if (s->floor_layout) vkDestroyPipelineLayout(dev, s->floor_layout, NULL);
    if (s->floor_set_layout) vkDestroyDescriptorSetLayout(dev, s->floor_set_layout, NULL);
    prw_buffer_destroy(s->r->gpu, &s->floor_buf);
}

static bool floor_ensure(prw_tm_session *s, prw_tm_floor k, prw_error *e)
{
    prw_gpu *gpu = s->r->gpu;
    if (!s->floor_layout) {
        VkShaderStageFlags st = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
        VkDescriptorSetLayoutBinding b[4] = {
            {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, st, NULL},
            {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, st, NULL},
            {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, st, NULL},
            {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, st, NULL},
        };
        if (!prw_desc_layout_create(gpu, b, 4, &s->floor_set_layout, e) ||
            !prw_pipeline_layout_create(gpu, &s->floor_set_layout, 1, sizeof(tm_pc), &s->floor_layout, e) ||
            !prw_buffer_create(gpu, (VkDeviceSize)s->w * s->h * 4 + 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               PRW_MEM_GPU, &s->floor_buf, e) ||
            !prw_desc_alloc(gpu, s->pool, s->floor_set_layout, &s->floor_set, e))
            return false;
        prw_desc_write_image(gpu, s->floor_set, 0, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, s->in.view,
                             prw_gpu_sampler(gpu, PRW_SAMPLER_NEAREST_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        prw_desc_write_image(gpu, s->floor_set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, s->ldr.view, VK_NULL_HANDLE,
                             VK_IMAGE_LAYOUT_GENERAL);
        prw_desc_write_image(gpu, s->floor_set, 2, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, s->sig.view, VK_NULL_HANDLE,
                             VK_IMAGE_LAYOUT_GENERAL);
        prw_desc_write_buffer(gpu, s->floor_set, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &s->floor_buf, 0, 0);
    }
    if (s->floor_pipe[k]) return true;
    if (k < PRW_TM_FLOOR_FS_RGBA8) {
        uint32_t mode = (uint32_t)k;
        return prw_pipeline_compute_spec(gpu, prw_shader_tonemap_floor_comp(), s->floor_layout, &mode, 1,
                                         &s->floor_pipe[k], e);
    }
    bool two = k == PRW_TM_FLOOR_FS_BOTH;
    prw_graphics_desc d = {.vs = prw_shader_tonemap_fs_vert(),
                           .fs = two ? prw_shader_tonemap_floor2_frag() : prw_shader_tonemap_floor_frag(),
                           .layout = s->floor_layout,
                           .color_formats = {VK_FORMAT_R8G8B8A8_UNORM, SIG_FORMAT},
                           .color_count = two ? 2 : 1};
    return prw_pipeline_graphics(gpu, &d, &s->floor_pipe[k], e);
}

bool prw_tm_session_time_floor(prw_tm_session *s, prw_tm_floor k, double *ms, prw_error *e)
{
    if ((unsigned)k >= PRW_TM_FLOOR_COUNT) return prw_fail(e, "tonemap: yardstick %d unknown", (int)k);
    prw_gpu *gpu = s->r->gpu;
    VkCommandBuffer cmd;
    if (!floor_ensure(s, k, e) || !prw_cmd_begin(gpu, &cmd, e)) return false;
    prw_cmd_transition(cmd, &s->in, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    tm_pc pc = {s->w, s->h, 0, 0};
    if (k < PRW_TM_FLOOR_FS_RGBA8) {
        prw_cmd_transition(cmd, &s->ldr, VK_IMAGE_LAYOUT_GENERAL);
        prw_cmd_transition(cmd, &s->sig, VK_IMAGE_LAYOUT_GENERAL);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s->floor_pipe[k]);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s->floor_layout, 0, 1, &s->floor_set, 0, NULL);
        vkCmdPushConstants(cmd, s->floor_layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (s->w + 15) / 16, (s->h + 15) / 16, 1);
    } else {
        prw_cmd_transition(cmd, &s->ldr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        prw_cmd_transition(cmd, &s->sig, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        VkRenderingAttachmentInfo at[2];
        prw_gpu_image *img[2] = {&s->ldr, &s->sig};
        for (int i = 0; i < 2; i++)
            at[i] = (VkRenderingAttachmentInfo){.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
                                                .imageView = img[i]->view,
                                                .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                                .loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                                                .storeOp = VK_ATTACHMENT_STORE_OP_STORE};
        VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                              .renderArea = {{0, 0}, {s->w, s->h}},
                              .layerCount = 1,
                              .colorAttachmentCount = k == PRW_TM_FLOOR_FS_BOTH ? 2 : 1,
                              .pColorAttachments = at};
        vkCmdBeginRendering(cmd, &ri);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s->floor_pipe[k]);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s->floor_layout, 0, 1, &s->floor_set, 0, NULL);
        prw_cmd_viewport(cmd, s->w, s->h);
        vkCmdDraw(cmd, 3, 1, 0, 0);
        vkCmdEndRendering(cmd);
    }
    double t0 = prw_now();
    if (!prw_cmd_submit_wait(gpu, cmd, e)) return false;
    *ms = 1e3 * (prw_now() - t0);
    return true;
}


void prw_tm_session_destroy(prw_tm_session *s)
{
    if (!s) return;
    floor_destroy(s);
    prw_image_destroy(s->r->gpu, &s->in);
    prw_image_destroy(s->r->gpu, &s->copy);
    prw_image_destroy(s->r->gpu, &s->ldr);
    prw_image_destroy(s->r->gpu, &s->sig);
    if (s->pool) prw_desc_pool_destroy(s->r->gpu, s->pool);
    free(s);
}

/* IEEE binary16 bits of x, rounded to nearest even; beyond the largest half: the largest half (finite,
 * as the renderer's half radiance targets clip), NaN: 0. */
static uint16_t half_bits(float x)
{
    if (!(x == x)) return 0;
    uint32_t u;
    memcpy(&u, &x, 4);
    uint16_t sign = (uint16_t)((u >> 16) & 0x8000u);
    float a = fabsf(x);
    if (a >= 65504.0f) return (uint16_t)(sign | 0x7bffu);
    if (a < 6.103515625e-05f) { /* subnormal: a / 2^-24 rounded to nearest even (default rounding) */
        return (uint16_t)(sign | (uint16_t)lrintf(a * 16777216.0f));
    }
    uint32_t m = u & 0x7fffffffu;
    uint32_t h = ((m >> 13) - ((127u - 15u) << 10)); /* exponent rebias, mantissa truncated */
    uint32_t rest = m & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) h++;
    return (uint16_t)(sign | h);
}

static bool session_create(prw_renderer *r, const prw_image *hdr, bool half, prw_tm_session **out, prw_error *e)
{
    prw_tm_gpu *tm = r->tm;
    uint32_t w = (uint32_t)hdr->width, h = (uint32_t)hdr->height;
    *out = NULL;
    if (tiles_for(w, h) > tm->tiles_per_view * r->desc.max_views || stats_slots(w, h) > tm->slot_cap ||
        tile_bytes(w, h) > tm->tile_stride * r->desc.max_views)
        return prw_fail(e, "tonemap: %ux%u image larger than the renderer's stats buffer allows", w, h);
    prw_tm_session *s = prw_calloc(1, sizeof *s);
    s->r = r;
    s->w = w;
    s->h = h;
    prw_image_desc din = {.width = w, .height = h, .format = half ? VK_FORMAT_R16G16B16A16_SFLOAT : SIG_FORMAT,
                          .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                   VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    uint16_t *h16 = NULL;
    if (half) {
        h16 = prw_malloc((size_t)w * h * 4 * sizeof *h16);
        for (size_t i = 0; i < (size_t)w * h * 4; i++) h16[i] = half_bits(hdr->rgba[i]);
    }
    prw_image_desc dldr = {.width = w, .height = h, .format = VK_FORMAT_R8G8B8A8_UNORM,
                           .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    prw_image_desc dsig = {.width = w, .height = h, .format = SIG_FORMAT,
                           .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    bool ok = prw_image_create(r->gpu, &din, &s->in, e) && prw_image_create(r->gpu, &dldr, &s->ldr, e) &&
              prw_image_create(r->gpu, &dsig, &s->sig, e) &&
              prw_image_upload(r->gpu, &s->in, 0, half ? (const void *)h16 : (const void *)hdr->rgba,
                               (size_t)w * h * (half ? 8 : 16), e) &&
              prw_desc_pool_create(r->gpu, &s->pool, e) && prw_desc_alloc(r->gpu, s->pool, tm->set_layout, &s->set, e);
    free(h16);
    if (!ok) {
        prw_tm_session_destroy(s);
        return false;
    }
    write_set(tm, s->set, s->in.view, s->ldr.view, s->sig.view, 0, tm->tile_stride * r->desc.max_views);
    *out = s;
    return true;
}

bool prw_tm_session_create(prw_renderer *r, const prw_image *hdr, prw_tm_session **out, prw_error *e)
{
    return session_create(r, hdr, false, out, e);
}

bool prw_tm_session_create_half(prw_renderer *r, const prw_image *hdr, prw_tm_session **out, prw_error *e)
{
    return session_create(r, hdr, true, out, e);
}

bool prw_tm_session_time_copy(prw_tm_session *s, double *ms, prw_error *e)
{
    prw_gpu *gpu = s->r->gpu;
    if (!s->copy.image) {
        prw_image_desc d = {.width = s->w, .height = s->h, .format = s->in.format,
                            .usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
        if (!prw_image_create(gpu, &d, &s->copy, e)) return false;
    }
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(gpu, &cmd, e)) return false;
    prw_cmd_transition(cmd, &s->in, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    prw_cmd_transition(cmd, &s->copy, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkImageCopy region = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .extent = {s->w, s->h, 1},
    };
    vkCmdCopyImage(cmd, s->in.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, s->copy.image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    double t0 = prw_now();
    if (!prw_cmd_submit_wait(gpu, cmd, e)) return false;
    *ms = 1e3 * (prw_now() - t0);
    return true;
}

bool prw_tm_session_run(prw_tm_session *s, double ev100, double *ms, prw_image *signal, prw_tm_stats *stats,
                        prw_tm_report *rep, prw_error *e)
{
    prw_renderer *r = s->r;
    prw_tm_gpu *tm = r->tm;
    VkCommandBuffer cmd;
    if (!ensure_sep(tm, s->w, s->h, e)) return false;
    upload_params(tm, ev100, false);
    tm->prev_stats = false; /* the stats buffer now holds this image's, not the last frame's */
    bool need = op_needs_stats(tm->settings.op) || tm_counts(&tm->settings);
    tm->fused = !op_needs_stats(tm->settings.op) && tm_counts(&tm->settings);
    tm->write_signal = signal != NULL; /* the session's RGBA8 image alone otherwise, as in a frame */
    if (!need) {
        tm->counted = false;
        ((tm_ubo *)tm->params.mapped)->mode[3] = 0;
    }
    if (!ensure_apply(tm, e) || !ensure_nosig(tm, e) || !prw_cmd_begin(r->gpu, &cmd, e)) return false;
    tm->prof_count = 0;
    prw_cmd_transition(cmd, &s->in, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_cmd_transition(cmd, &s->ldr, VK_IMAGE_LAYOUT_GENERAL);
    prw_cmd_transition(cmd, &s->sig, VK_IMAGE_LAYOUT_GENERAL);
    VkDeviceSize off = 0;
    tm_rec t = {cmd, NULL};
    if (need && !tm->fused) record_stats(tm, &t, &s->set, &s->w, &s->h, 1);
    prw_gpu_image *ldr = &s->ldr, *sig = &s->sig;
    record_apply(tm, &t, &s->set, &s->w, &s->h, &off, &ldr, &sig, 1);
    double t0 = prw_now();
    if (!prw_cmd_submit_wait(r->gpu, cmd, e)) return false;
    if (ms) *ms = 1e3 * (prw_now() - t0);
    if (signal && !(prw_image_alloc(signal, (int)s->w, (int)s->h, e) &&
                    prw_image_readback(r->gpu, &s->sig, signal->rgba, e)))
        return false;
    read_report(tm, stats, rep);
    return true;
}

bool prw_renderer_tonemap_image(prw_renderer *r, const prw_image *hdr, double ev100, prw_image *signal,
                                prw_tm_stats *stats, prw_tm_report *rep, prw_error *e)
{
    prw_tm_session *s;
    if (!prw_tm_session_create(r, hdr, &s, e)) return false;
    bool ok = prw_tm_session_run(s, ev100, NULL, signal, stats, rep, e);
    prw_tm_session_destroy(s);
    return ok;
}

bool prw_tm_session_profile(prw_tm_session *s, double ev100, int reps, prw_tm_profile *out, prw_error *e)
{
    prw_tm_gpu *tm = s->r->tm;
    memset(out, 0, sizeof *out);
    bool ok = prw_tm_session_run(s, ev100, NULL, NULL, NULL, NULL, e);
    int n = PRW_MIN(tm->prof_count, 64);
    double prev = 0;
    for (int k = 0; ok && k <= n; k++) {
        double best = 1e30, ms;
        tm->prof_limit = k < n ? k : -1; /* scopes 0..k-1 recorded */
        for (int i = 0; ok && i < PRW_MAX(reps, 1); i++)
            if ((ok = prw_tm_session_run(s, ev100, &ms, NULL, NULL, NULL, e))) best = PRW_MIN(best, ms);
        if (k > 0) {
            snprintf(out->names[k - 1], sizeof out->names[0], "%s", tm->prof_names[k - 1]);
            out->ms[k - 1] = best - prev;
        } else out->base_ms = best;
        prev = best;
    }
    tm->prof_limit = -1;
    out->count = ok ? n : 0;
    return ok;
}
