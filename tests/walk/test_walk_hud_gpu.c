/* The HUD overlay on the GPU (app/walk_hud.c), without a window: the panel is blitted onto an
 * offscreen image standing in for the swapchain image, after a transfer write (the write-after-write
 * barrier path) and onto an image in another layout (the transition path), clipped to a small
 * target.  The read-back must equal the CPU composition inside the panel and the untouched fill
 * outside it; validation (forced on) must stay silent. */
#include <stdlib.h>
#include <string.h>

#include "prw_test.h"
#include "walk_hud.h"

static bool open_gpu(prw_gpu **gpu, prw_error *e)
{
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    return prw_gpu_create(&d, gpu, e);
}

static const char *const lines[] = {"frame 12.3 ms  render 9.9 ms", "GPU ms: shadow 1.00 base 2.00", "gpqy |~"};

/* Fills target with grey (upload), optionally clears to `clear` with a transfer write, blits the HUD,
 * reads back and compares with the CPU panel.  Returns the number of mismatching pixels. */
static int run_case(prw_gpu *gpu, walk_hud *hud, uint32_t w, uint32_t h, bool clear_first, prw_error *e)
{
    prw_image_desc d = {.width = w, .height = h, .format = VK_FORMAT_R8G8B8A8_UNORM,
                        .usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
    prw_gpu_image target;
    if (!prw_image_create(gpu, &d, &target, e)) return -1;
    uint8_t *fill = malloc((size_t)w * h * 4);
    memset(fill, 90, (size_t)w * h * 4);
    int bad = -1;
    float *back = malloc((size_t)w * h * 4 * sizeof(float));
    VkCommandBuffer cmd;
    if (!prw_image_upload(gpu, &target, 0, fill, (size_t)w * h * 4, e)) goto out;
    if (!prw_cmd_begin(gpu, &cmd, e)) goto out;
    if (clear_first) {
        prw_cmd_transition(cmd, &target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkClearColorValue cc = {.float32 = {90 / 255.0f, 90 / 255.0f, 90 / 255.0f, 90 / 255.0f}};
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, target.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &cc, 1, &range);
    }
    walk_hud_record(cmd, hud, &target);
    if (!prw_cmd_submit_wait(gpu, cmd, e)) goto out;
    if (!prw_image_readback(gpu, &target, back, e)) goto out;
    /* expected: the CPU panel over the fill */
    int hw = 30 * WALK_CELL_W + 2 * WALK_HUD_PAD, hh = 3 * WALK_CELL_H + 2 * WALK_HUD_PAD;
    uint8_t *want = malloc((size_t)hw * hh * 4);
    int uw, uh;
    walk_hud_compose(want, hw, hh, 1, lines, 3, &uw, &uh);
    bad = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (int c = 0; c < 4; c++) {
                int got = (int)(back[4 * ((size_t)y * w + x) + c] * 255.0f + 0.5f);
                int exp = ((int)x < uw && (int)y < uh) ? want[4 * ((size_t)y * hw + x) + c] : 90;
                if (got != exp) bad++;
            }
    free(want);
out:
    free(back);
    free(fill);
    prw_image_destroy(gpu, &target);
    return bad;
}

static void test_overlay(void)
{
    prw_gpu *gpu;
    prw_error e;
    CHECK_OK(open_gpu(&gpu, &e), &e);
    walk_hud *hud;
    CHECK_OK(walk_hud_create(gpu, 30, 3, 1, &hud, &e), &e);
    CHECK_OK(walk_hud_upload(gpu, hud, lines, 3, &e), &e);
    int bad = run_case(gpu, hud, 256, 64, true, &e); /* after a transfer write: the barrier path */
    CHECK_MSG(bad == 0, "%d channel values differ (%s)", bad, bad < 0 ? e.msg : "");
    bad = run_case(gpu, hud, 256, 64, false, &e); /* target in another layout: the transition path */
    CHECK_MSG(bad == 0, "%d channel values differ (%s)", bad, bad < 0 ? e.msg : "");
    bad = run_case(gpu, hud, 40, 12, true, &e); /* smaller than the panel: clipped */
    CHECK_MSG(bad == 0, "%d channel values differ (%s)", bad, bad < 0 ? e.msg : "");
    /* re-upload (the image is in TRANSFER_SRC after the blits) */
    CHECK_OK(walk_hud_upload(gpu, hud, lines, 2, &e), &e);
    walk_hud_destroy(gpu, hud);
    CHECK(prw_gpu_validation_count(gpu) == 0);
    uint32_t before = prw_gpu_validation_total();
    prw_gpu_destroy(gpu);
    CHECK(prw_gpu_validation_total() == before);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"overlay", test_overlay}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
