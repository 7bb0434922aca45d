/* test_gpu_render — rendering and images: MSAA triangle with resolve, uploads with mips, layers
 * and cube maps, readback formats, depth images and the shadow sampler. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_test_util.h"
#include "prw_shaders.h"

/* float -> half for test data that is exactly representable (normal numbers and zero). */
static uint16_t to_half(float f)
{
    if (f == 0.0f) return 0;
    int ex;
    float m = frexpf(fabsf(f), &ex); /* f = m * 2^ex, m in [0.5, 1) */
    uint16_t man = (uint16_t)lrintf((m * 2.0f - 1.0f) * 1024.0f);
    uint16_t exp = (uint16_t)(ex - 1 + 15);
    return (uint16_t)((f < 0 ? 0x8000 : 0) | (exp << 10) | man);
}

/* ---- a compute "probe": runs a shader that reads a sampled view into a float buffer ---- */
typedef struct probe {
    VkDescriptorSetLayout dsl;
    VkPipelineLayout pl;
    VkPipeline pipe;
    prw_desc_pool *pool;
    prw_buffer out;
} probe;

static bool probe_create(prw_gpu *gpu, prw_spirv cs, probe *p, prw_error *e)
{
    memset(p, 0, sizeof *p);
    VkDescriptorSetLayoutBinding b[2] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    return prw_desc_layout_create(gpu, b, 2, &p->dsl, e) && prw_pipeline_layout_create(gpu, &p->dsl, 1, 8, &p->pl, e) &&
           prw_pipeline_compute(gpu, cs, p->pl, &p->pipe, e) && prw_desc_pool_create(gpu, &p->pool, e) &&
           prw_buffer_create(gpu, 4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, PRW_MEM_READBACK, &p->out, e);
}

/* Records one dispatch reading `view` (in layout SHADER_READ_ONLY_OPTIMAL) with push {slot, mips}. */
static bool probe_record(prw_gpu *gpu, probe *p, VkCommandBuffer cmd, VkImageView view, VkSampler sampler,
                         uint32_t slot, uint32_t mips, prw_error *e)
{
    VkDescriptorSet set;
    if (!prw_desc_alloc(gpu, p->pool, p->dsl, &set, e)) return false;
    prw_desc_write_image(gpu, set, 0, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, view, sampler,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_buffer(gpu, set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &p->out, 0, 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pl, 0, 1, &set, 0, NULL);
    uint32_t push[2] = {slot, mips};
    vkCmdPushConstants(cmd, p->pl, VK_SHADER_STAGE_ALL, 0, sizeof push, push);
    vkCmdDispatch(cmd, 1, 1, 1);
    return true;
}

static void probe_host_barrier(VkCommandBuffer cmd)
{
    VkMemoryBarrier2 mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                           .srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                           .srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                           .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
                           .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT};
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                            .pMemoryBarriers = &mb};
    vkCmdPipelineBarrier2(cmd, &dep);
}

static void probe_destroy(prw_gpu *gpu, probe *p)
{
    VkDevice dev = prw_gpu_device(gpu);
    prw_buffer_destroy(gpu, &p->out);
    prw_desc_pool_destroy(gpu, p->pool);
    if (p->pipe) prw_pipeline_release(gpu, p->pipe);
    if (p->pl) vkDestroyPipelineLayout(dev, p->pl, NULL);
    if (p->dsl) vkDestroyDescriptorSetLayout(dev, p->dsl, NULL);
}

/* ---- tests ---- */

static void test_msaa_triangle(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    VkDevice dev = prw_gpu_device(gpu);
    const uint32_t W = 16, H = 16;
    const VkFormat fmt = VK_FORMAT_R16G16B16A16_SFLOAT;
    prw_gpu_image msaa, resolved;
    prw_image_desc md = {.width = W, .height = H, .format = fmt, .samples = VK_SAMPLE_COUNT_4_BIT,
                         .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    prw_image_desc rd = {.width = W, .height = H, .format = fmt,
                         .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    CHECK_OK(prw_image_create(gpu, &md, &msaa, &e), &e);
    CHECK_OK(prw_image_create(gpu, &rd, &resolved, &e), &e);
    CHECK(msaa.samples == VK_SAMPLE_COUNT_4_BIT && msaa.aspect == VK_IMAGE_ASPECT_COLOR_BIT);

    VkPipelineLayout pl;
    VkPipeline pipe;
    CHECK_OK(prw_pipeline_layout_create(gpu, NULL, 0, 16, &pl, &e), &e);
    prw_graphics_desc gd = {.vs = prw_shader_tri_vert(), .fs = prw_shader_tri_frag(), .layout = pl,
                            .color_formats = {fmt}, .color_count = 1, .samples = VK_SAMPLE_COUNT_4_BIT};
    CHECK_OK(prw_pipeline_graphics(gpu, &gd, &pipe, &e), &e);

    VkCommandBuffer cmd;
    CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
    prw_cmd_transition(cmd, &msaa, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    prw_cmd_transition(cmd, &resolved, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = msaa.view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT,
        .resolveImageView = resolved.view,
        .resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .clearValue = {.color = {.float32 = {0, 0, 0, 0}}},
    };
    VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                          .renderArea = {{0, 0}, {W, H}},
                          .layerCount = 1,
                          .colorAttachmentCount = 1,
                          .pColorAttachments = &ca};
    vkCmdBeginRendering(cmd, &ri);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
    prw_cmd_viewport(cmd, W, H);
    float color[4] = {1.0f, 0.25f, 0.0f, 1.0f};
    vkCmdPushConstants(cmd, pl, VK_SHADER_STAGE_ALL, 0, sizeof color, color);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
    CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);

    float *px = malloc(sizeof(float) * 4 * W * H);
    CHECK_OK(prw_image_readback(gpu, &resolved, px, &e), &e);
    CHECK(resolved.layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL); /* restored after readback */
    int inside_bad = 0, outside_bad = 0, edge = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float *p = px + 4 * (y * W + x);
            if (x + y < W - 1) {
                inside_bad += fabsf(p[0] - 1) > 1e-3f || fabsf(p[1] - 0.25f) > 1e-3f || fabsf(p[3] - 1) > 1e-3f;
            } else if (x + y > W - 1) {
                outside_bad += fabsf(p[0]) > 1e-3f || fabsf(p[3]) > 1e-3f;
            } else {
                /* The edge passes through the pixel centre: 2 of the 4 standard samples are covered. */
                bool partial = p[0] > 0.2f && p[0] < 0.8f && fabsf(p[1] - p[0] * 0.25f) < 2e-3f &&
                               fabsf(p[3] - p[0]) < 1e-3f;
                edge += partial;
                if (!partial) printf("  edge pixel (%u,%u) = %g %g %g %g\n", x, y, p[0], p[1], p[2], p[3]);
            }
        }
    printf("  edge pixel (8,7) = %.3f %.3f %.3f %.3f\n", px[4 * (7 * W + 8)], px[4 * (7 * W + 8) + 1],
           px[4 * (7 * W + 8) + 2], px[4 * (7 * W + 8) + 3]);
    CHECK_MSG(inside_bad == 0, "%d wrong pixels inside", inside_bad);
    CHECK_MSG(outside_bad == 0, "%d wrong pixels outside", outside_bad);
    CHECK_MSG(edge == (int)W, "%d of %u edge pixels have partial coverage", edge, W);
    if (prw_gpu_properties(gpu)->limits.standardSampleLocations) CHECK_NEAR(px[4 * (7 * W + 8)], 0.5, 1e-3);
    free(px);

    prw_pipeline_release(gpu, pipe);
    vkDestroyPipelineLayout(dev, pl, NULL);
    prw_image_destroy(gpu, &msaa);
    prw_image_destroy(gpu, &resolved);
    TEST_GPU_CLOSE(gpu);
}

/* 8x8 RGBA16F with 4 mips: R = (x + 8y) / 64, G = 1 - R.  Box-filtered mips have known means. */
static void test_image_mips(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    prw_gpu_image img;
    prw_image_desc d = {.width = 8, .height = 8, .mips = 4, .format = VK_FORMAT_R16G16B16A16_SFLOAT,
                        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
    uint16_t pix[8 * 8 * 4];
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++) {
            float r = (float)(x + 8 * y) / 64.0f;
            uint16_t *p = pix + 4 * (y * 8 + x);
            p[0] = to_half(r);
            p[1] = to_half(1.0f - r);
            p[2] = to_half(0.25f);
            p[3] = to_half(1.0f);
        }
    CHECK(!prw_image_upload(gpu, &img, 0, pix, sizeof pix - 8, &e)); /* wrong size is an error */
    CHECK_OK(prw_image_upload(gpu, &img, 0, pix, sizeof pix, &e), &e);
    CHECK(img.layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

    float back[8 * 8 * 4];
    CHECK_OK(prw_image_readback(gpu, &img, back, &e), &e);
    int bad = 0;
    for (int i = 0; i < 64; i++) bad += fabsf(back[4 * i] - (float)i / 64.0f) > 1e-6f || back[4 * i + 2] != 0.25f;
    CHECK_MSG(bad == 0, "%d pixels read back wrong", bad);

    probe p;
    CHECK_OK(probe_create(gpu, prw_shader_sample_comp(), &p, &e), &e);
    VkCommandBuffer cmd;
    CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
    CHECK_OK(probe_record(gpu, &p, cmd, img.view, prw_gpu_sampler(gpu, PRW_SAMPLER_LINEAR_CLAMP), 0, 4, &e), &e);
    probe_host_barrier(cmd);
    CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);
    const float *v = p.out.mapped;
    printf("  mip0 (3,2) %.5f, mip1 (0,0) %.5f, mip2 centre %.5f, mip3 %.5f\n", v[0], v[4], v[8], v[12]);
    CHECK_NEAR(v[0], 19.0 / 64, 1e-4);
    CHECK_NEAR(v[4], 4.5 / 64, 2e-3);
    CHECK_NEAR(v[8], 31.5 / 64, 2e-3);
    CHECK_NEAR(v[12], 31.5 / 64, 2e-3);
    CHECK_NEAR(v[13], 1 - 31.5 / 64, 2e-3);
    CHECK_NEAR(v[14], 0.25, 1e-3);
    probe_destroy(gpu, &p);
    prw_image_destroy(gpu, &img);
    TEST_GPU_CLOSE(gpu);
}

/* A cube map (6 layers) of RGBA8: each face uploaded separately, read through its per-layer view. */
static void test_image_cube_layers(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    prw_gpu_image img;
    prw_image_desc d = {.width = 8, .height = 8, .layers = 6, .cube = true, .format = VK_FORMAT_R8G8B8A8_UNORM,
                        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
    CHECK(img.layer_views != NULL);
    unsigned char pix[8 * 8 * 4];
    for (uint32_t layer = 0; layer < 6; layer++) {
        for (int i = 0; i < 64; i++) {
            pix[4 * i] = (unsigned char)(10 + 40 * layer);
            pix[4 * i + 1] = (unsigned char)i;
            pix[4 * i + 2] = 0;
            pix[4 * i + 3] = 255;
        }
        CHECK_OK(prw_image_upload(gpu, &img, layer, pix, sizeof pix, &e), &e);
    }
    float back[8 * 8 * 4];
    CHECK_OK(prw_image_readback(gpu, &img, back, &e), &e); /* layer 0 */
    CHECK_NEAR(back[0], 10 / 255.0, 1e-6);
    CHECK_NEAR(back[4 * 63 + 1], 63 / 255.0, 1e-6);

    probe p;
    CHECK_OK(probe_create(gpu, prw_shader_sample_comp(), &p, &e), &e);
    VkCommandBuffer cmd;
    CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
    for (uint32_t layer = 0; layer < 6; layer++)
        CHECK_OK(probe_record(gpu, &p, cmd, img.layer_views[layer], prw_gpu_sampler(gpu, PRW_SAMPLER_NEAREST_CLAMP),
                              layer, 1, &e),
                 &e);
    probe_host_barrier(cmd);
    CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);
    const float *v = p.out.mapped;
    for (uint32_t layer = 0; layer < 6; layer++) {
        CHECK_NEAR(v[16 * layer], (10 + 40 * layer) / 255.0, 1e-5);
        CHECK_NEAR(v[16 * layer + 1], (3 + 8 * 2) / 255.0, 1e-5);
    }
    probe_destroy(gpu, &p);
    prw_image_destroy(gpu, &img);

    /* Invalid shapes are errors, not validation messages. */
    prw_image_desc bad = d;
    bad.layers = 5;
    CHECK(!prw_image_create(gpu, &bad, &img, &e));
    bad = d;
    bad.cube = false;
    bad.mips = 9;
    CHECK(!prw_image_create(gpu, &bad, &img, &e));
    TEST_GPU_CLOSE(gpu);
}

static void test_readback_formats(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    prw_gpu_image img;
    float back[4 * 4];

    /* RGBA32F: exact. */
    float f32[16] = {1.5f, -2.0f, 1e-20f, 65504.0f, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    prw_image_desc d = {.width = 2, .height = 2, .format = VK_FORMAT_R32G32B32A32_SFLOAT, .usage = usage};
    CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
    CHECK_OK(prw_image_upload(gpu, &img, 0, f32, sizeof f32, &e), &e);
    CHECK_OK(prw_image_readback(gpu, &img, back, &e), &e);
    CHECK(memcmp(back, f32, sizeof f32) == 0);
    prw_image_destroy(gpu, &img);

    /* RGBA16F: negative, subnormal, infinity, NaN, max. */
    uint16_t h[16] = {0xC000, 0x0001, 0x7C00, 0x7E00, 0x7BFF, 0x3C00, 0x8000, 0x3555};
    d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
    CHECK_OK(prw_image_upload(gpu, &img, 0, h, sizeof h, &e), &e);
    CHECK_OK(prw_image_readback(gpu, &img, back, &e), &e);
    CHECK(back[0] == -2.0f);
    CHECK(back[1] == ldexpf(1.0f, -24));
    CHECK(isinf(back[2]) && back[2] > 0);
    CHECK(isnan(back[3]));
    CHECK(back[4] == 65504.0f);
    CHECK(back[5] == 1.0f);
    CHECK(back[6] == 0.0f && signbit(back[6]));
    CHECK_NEAR(back[7], 1.0 / 3.0, 1e-3);
    prw_image_destroy(gpu, &img);

    /* RGBA8 UNORM and SRGB: stored value / 255, no decoding. */
    unsigned char b8[16] = {0, 1, 128, 255, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120};
    VkFormat f8[2] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_SRGB};
    for (int k = 0; k < 2; k++) {
        d.format = f8[k];
        CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
        CHECK_OK(prw_image_upload(gpu, &img, 0, b8, sizeof b8, &e), &e);
        CHECK_OK(prw_image_readback(gpu, &img, back, &e), &e);
        for (int i = 0; i < 16; i++) CHECK_NEAR(back[i], b8[i] / 255.0, 1e-6);
        prw_image_destroy(gpu, &img);
    }

    /* Unsupported readback format is an error. */
    d.format = VK_FORMAT_R32_SFLOAT;
    d.width = d.height = 1;
    CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
    float one = 1.0f;
    CHECK_OK(prw_image_upload(gpu, &img, 0, &one, 4, &e), &e);
    CHECK(!prw_image_readback(gpu, &img, back, &e));
    prw_image_destroy(gpu, &img);
    TEST_GPU_CLOSE(gpu);
}

/* Clears a depth image to 0.25 with dynamic rendering, then compares through the shadow sampler. */
static void test_depth_shadow(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    const VkFormat formats[2] = {VK_FORMAT_D32_SFLOAT, VK_FORMAT_D32_SFLOAT_S8_UINT};
    for (int k = 0; k < 2; k++) {
        prw_gpu_image img;
        prw_image_desc d = {.width = 4, .height = 4, .format = formats[k],
                            .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT};
        CHECK_OK(prw_image_create(gpu, &d, &img, &e), &e);
        bool stencil = k == 1;
        CHECK(img.aspect == (stencil ? (VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT)
                                     : VK_IMAGE_ASPECT_DEPTH_BIT));
        probe p;
        CHECK_OK(probe_create(gpu, prw_shader_shadow_comp(), &p, &e), &e);
        VkCommandBuffer cmd;
        CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
        VkImageLayout att = stencil ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                                    : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        prw_cmd_transition(cmd, &img, att);
        VkRenderingAttachmentInfo da = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = img.layer_views[0],
            .imageLayout = att,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue = {.depthStencil = {0.25f, 0}},
        };
        VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                              .renderArea = {{0, 0}, {4, 4}},
                              .layerCount = 1,
                              .pDepthAttachment = &da,
                              .pStencilAttachment = stencil ? &da : NULL};
        vkCmdBeginRendering(cmd, &ri);
        vkCmdEndRendering(cmd);
        prw_cmd_transition(cmd, &img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        CHECK_OK(probe_record(gpu, &p, cmd, img.view, prw_gpu_sampler(gpu, PRW_SAMPLER_SHADOW), 0, 1, &e), &e);
        probe_host_barrier(cmd);
        CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);
        const float *v = p.out.mapped;
        printf("  format %d: ref 0.1 -> %g, 0.5 -> %g, outside -> %g, equal -> %g\n", (int)formats[k], v[0], v[1],
               v[2], v[3]);
        CHECK(v[0] == 0.0f); /* 0.1 is farther than the stored 0.25 (reversed Z): shadowed */
        CHECK(v[1] == 1.0f); /* nearer: lit */
        CHECK(v[2] == 1.0f); /* outside the map: border depth 0 = far: lit */
        CHECK(v[3] == 1.0f); /* equal passes GREATER_OR_EQUAL */
        probe_destroy(gpu, &p);
        prw_image_destroy(gpu, &img);
    }
    TEST_GPU_CLOSE(gpu);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"msaa_triangle", test_msaa_triangle},
        {"image_mips", test_image_mips},
        {"image_cube_layers", test_image_cube_layers},
        {"readback_formats", test_readback_formats},
        {"depth_shadow", test_depth_shadow},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
