/* test_gpu_swapchain — presenting to a GLFW window (run under xvfb-run; skipped without DISPLAY). */
#include <stdio.h>
#include <stdlib.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "gpu_test_util.h"
#include "prw_swapchain.h"

/* Clears the target to a colour and presents; returns the target's width (0 on skip/failure). */
static uint32_t one_frame(prw_gpu *gpu, prw_swapchain *sc, float shade)
{
    prw_error e;
    VkCommandBuffer cmd;
    prw_gpu_image *target;
    bool skip;
    if (!prw_swapchain_begin_frame(gpu, sc, &cmd, &target, &skip, &e)) {
        CHECK_MSG(skip, "begin_frame: %s", e.msg);
        return 0;
    }
    prw_cmd_transition(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkClearColorValue c = {.float32 = {shade, 0.5f, 1.0f - shade, 1.0f}};
    VkImageSubresourceRange r = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, target->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &c, 1, &r);
    uint32_t w = target->width;
    if (!prw_swapchain_end_frame(gpu, sc, &e)) {
        CHECK_MSG(false, "end_frame: %s", e.msg);
        return 0;
    }
    return w;
}

static void test_swapchain(void)
{
    if (!getenv("DISPLAY") || !*getenv("DISPLAY")) {
        printf("  skipped: no display\n");
        return;
    }
    CHECK(glfwInit());
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow *win = glfwCreateWindow(64, 48, "prw test", NULL, NULL);
    CHECK(win != NULL);
    if (!win) return;
    prw_error e;
    prw_gpu *gpu = NULL;
    prw_gpu_desc d = {.device_index = -1, .validation = true, .present = true};
    prw_swapchain *sc = NULL;
    bool ok = prw_gpu_create(&d, &gpu, &e);
    CHECK_MSG(ok, "%s", e.msg);
    if (ok) {
        ok = prw_swapchain_create(gpu, win, true, &sc, &e);
        CHECK_MSG(ok, "%s", e.msg);
    }
    if (ok) {
        for (int i = 0; i < 6; i++) {
            glfwPollEvents();
            CHECK(one_frame(gpu, sc, (float)i / 6.0f) == 64);
        }
        /* Resize: the swapchain follows within a few frames. */
        glfwSetWindowSize(win, 100, 80);
        uint32_t w = 0;
        for (int i = 0; i < 50 && w != 100; i++) {
            glfwPollEvents();
            w = one_frame(gpu, sc, 0.5f);
        }
        CHECK_MSG(w == 100, "swapchain width %u after resize to 100", w);
        for (int i = 0; i < 4; i++) CHECK(one_frame(gpu, sc, 0.25f) == 100);
        prw_swapchain_destroy(gpu, sc);
    }
    if (gpu) TEST_GPU_CLOSE(gpu);
    glfwDestroyWindow(win);
    glfwTerminate();
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"swapchain", test_swapchain},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
