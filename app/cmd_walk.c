/* prw walk — the interactive window: renders the scene each frame and presents it.
 * Controls: WASD move, Q/E down/up, right mouse drag to look, +/- speed, Esc quits.
 * (The full walkthrough — walk mode, HUD, recording, input scripts — is issue 5.) */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "app.h"
#include "prw_render.h"
#include "prw_swapchain.h"
#include "prw_view.h"

typedef struct walk_cam {
    prw_dvec3 pos;
    double yaw, pitch; /* radians; yaw 0 looks along -Z */
    double speed;      /* m/s */
} walk_cam;

static prw_dvec3 cam_forward(const walk_cam *c)
{
    return prw_v3(-sin(c->yaw) * cos(c->pitch), sin(c->pitch), -cos(c->yaw) * cos(c->pitch));
}

static void walk_usage(void)
{
    printf("usage: prw walk [SCENE] [options]\n"
           "  --size WxH      render size (default 1280x720; the window scales it)\n"
           "  --camera NAME   start camera (default: the first)\n"
           "  --frames N      exit after N frames (0 = run until closed; default 0)\n"
           "  --msaa 1|4      (default 4)\n"
           "  --display PROFILE  display profile: built-in name or .json file (default srgb)\n"
           "  --tonemap OP       exposure, reinhard, neutral, adaptive or absolute (default exposure)\n"
           "  controls: WASD move, Q/E down/up, right mouse drag to look, +/- speed, Esc quits\n");
}

static void blit_to(VkCommandBuffer cmd, prw_gpu_image *src, prw_gpu_image *dst)
{
    prw_cmd_transition(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    prw_cmd_transition(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkImageBlit2 region = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_BLIT_2,
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .srcOffsets = {{0, 0, 0}, {(int32_t)src->width, (int32_t)src->height, 1}},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstOffsets = {{0, 0, 0}, {(int32_t)dst->width, (int32_t)dst->height, 1}},
    };
    VkBlitImageInfo2 info = {
        .sType = VK_STRUCTURE_TYPE_BLIT_IMAGE_INFO_2,
        .srcImage = src->image,
        .srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
        .dstImage = dst->image,
        .dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
        .regionCount = 1,
        .pRegions = &region,
        .filter = VK_FILTER_LINEAR,
    };
    vkCmdBlitImage2(cmd, &info);
}

int prw_cmd_walk(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        walk_usage();
        prw_args_free(&a);
        return 0;
    }
    uint32_t w = 1280, h = 720, msaa = 4;
    long frames = 0, n;
    const char *v, *camera = prw_args_value(&a, "camera", &e, &bad);
    const char *display_name = prw_args_value(&a, "display", &e, &bad);
    const char *tonemap_name = prw_args_value(&a, "tonemap", &e, &bad);
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &w, &h, &e)) bad = true;
    if ((v = prw_args_value(&a, "frames", &e, &bad)) && !prw_parse_int(v, "--frames", 0, 100000000, &frames, &e))
        bad = true;
    if ((v = prw_args_value(&a, "msaa", &e, &bad))) {
        if (!prw_parse_int(v, "--msaa", 1, 4, &n, &e) || (n != 1 && n != 4))
            bad = true, prw_fail(&e, "--msaa '%s': lavapipe offers 1 or 4", v);
        msaa = (uint32_t)n;
    }
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (bad) {
        fprintf(stderr, "prw walk: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    const char *path = a.positional_count ? a.positional[0] : NULL;

    int rc = 1;
    prw_scene *scene = NULL;
    prw_gpu *gpu = NULL;
    prw_renderer *r = NULL;
    prw_swapchain *sc = NULL;
    GLFWwindow *win = NULL;
    bool glfw = false;
    if (!prw_app_load_scene(path, &scene, &e)) goto done;
    int cam = prw_scene_find_camera(scene, camera);
    if (cam < 0) {
        prw_fail(&e, "%s: no camera named '%s'", scene->source, camera ? camera : "(first)");
        goto done;
    }
    if (!glfwInit()) {
        prw_fail(&e, "walk: cannot open a window (no display? GLFW failed to initialise); use 'prw render'");
        goto done;
    }
    glfw = true;
    if (!glfwVulkanSupported()) {
        prw_fail(&e, "walk: GLFW reports no Vulkan loader");
        goto done;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    win = glfwCreateWindow((int)w, (int)h, "prw", NULL, NULL);
    if (!win) {
        prw_fail(&e, "walk: cannot create a %ux%u window", w, h);
        goto done;
    }
    if (!prw_app_create_gpu(true, &gpu, &e)) goto done;
    if (!prw_swapchain_create(gpu, win, true, &sc, &e)) goto done;
    prw_render_desc rd = {.width = w, .height = h, .msaa = msaa};
    if (!prw_renderer_create(gpu, scene, &rd, &r, &e)) goto done;
    {
        prw_display disp;
        prw_tonemap_settings tms = {.op = PRW_TM_EXPOSURE};
        if (!prw_display_resolve(display_name ? display_name : "srgb", &disp, &e) ||
            (tonemap_name && !prw_tm_op_parse(tonemap_name, &tms.op, &e)) ||
            !prw_renderer_set_tonemap(r, &disp, &tms, &e))
            goto done;
    }

    prw_view view;
    if (!prw_view_from_camera(scene, cam, w, h, &view, &e)) goto done;
    walk_cam wc = {.pos = view.eye, .speed = 1.5};
    {
        const double *m = view.view.m; /* row 2 of the view matrix is +Z of the eye: forward is its negation */
        prw_dvec3 f = prw_v3(-m[2], -m[6], -m[10]);
        wc.yaw = atan2(-f.x, -f.z);
        wc.pitch = asin(fmax(-1.0, fmin(1.0, f.y)));
    }
    double ev100 = view.ev100, yfov = scene->cameras[cam].yfov, last = glfwGetTime();
    double mx0 = 0, my0 = 0, t_report = last, frame_ms_sum = 0;
    bool dragging = false;
    long frame = 0, report_frames = 0;
    while (!glfwWindowShouldClose(win) && (frames == 0 || frame < frames)) {
        glfwPollEvents();
        double now = glfwGetTime(), dt = fmin(now - last, 0.1);
        last = now;
        if (glfwGetKey(win, GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
        double mx, my;
        glfwGetCursorPos(win, &mx, &my);
        bool rmb = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        if (rmb && dragging) {
            wc.yaw -= (mx - mx0) * 0.003;
            wc.pitch = fmax(-1.5, fmin(1.5, wc.pitch - (my - my0) * 0.003));
        }
        dragging = rmb;
        mx0 = mx;
        my0 = my;
        if (glfwGetKey(win, GLFW_KEY_EQUAL) == GLFW_PRESS) wc.speed *= 1.0 + dt;
        if (glfwGetKey(win, GLFW_KEY_MINUS) == GLFW_PRESS) wc.speed /= 1.0 + dt;
        prw_dvec3 f = cam_forward(&wc), up = prw_v3(0, 1, 0), right = prw_v3_norm(prw_v3_cross(f, up));
        double step = wc.speed * dt;
        if (glfwGetKey(win, GLFW_KEY_W) == GLFW_PRESS) wc.pos = prw_v3_add(wc.pos, prw_v3_scale(f, step));
        if (glfwGetKey(win, GLFW_KEY_S) == GLFW_PRESS) wc.pos = prw_v3_sub(wc.pos, prw_v3_scale(f, step));
        if (glfwGetKey(win, GLFW_KEY_D) == GLFW_PRESS) wc.pos = prw_v3_add(wc.pos, prw_v3_scale(right, step));
        if (glfwGetKey(win, GLFW_KEY_A) == GLFW_PRESS) wc.pos = prw_v3_sub(wc.pos, prw_v3_scale(right, step));
        if (glfwGetKey(win, GLFW_KEY_E) == GLFW_PRESS) wc.pos = prw_v3_add(wc.pos, prw_v3_scale(up, step));
        if (glfwGetKey(win, GLFW_KEY_Q) == GLFW_PRESS) wc.pos = prw_v3_sub(wc.pos, prw_v3_scale(up, step));
        view = prw_view_look_at(wc.pos, prw_v3_add(wc.pos, f), up, yfov, 0.05, w, h, ev100);

        VkCommandBuffer cmd;
        prw_gpu_image *target;
        bool skip = false;
        double t0 = prw_now();
        if (!prw_swapchain_begin_frame(gpu, sc, &cmd, &target, &skip, &e)) {
            if (skip) continue;
            goto done;
        }
        if (!prw_renderer_record(r, cmd, &view, 1, &e)) goto done;
        blit_to(cmd, prw_renderer_ldr_image(r, 0), target);
        if (!prw_swapchain_end_frame(gpu, sc, &e)) goto done;
        frame_ms_sum += 1e3 * (prw_now() - t0);
        frame++;
        report_frames++;
        if (now - t_report > 1.0) {
            char title[128];
            snprintf(title, sizeof title, "prw - %.1f ms/frame - %.2f m/s", frame_ms_sum / (double)report_frames,
                     wc.speed);
            glfwSetWindowTitle(win, title);
            t_report = now;
            frame_ms_sum = 0;
            report_frames = 0;
        }
    }
    if (!prw_gpu_wait_idle(gpu, &e)) goto done;
    printf("walk: presented %ld frames\n", frame);
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw: error: %s\n", e.msg[0] ? e.msg : "walk failed");
    prw_renderer_destroy(r);
    if (sc) prw_swapchain_destroy(gpu, sc);
    if (gpu) {
        prw_gpu_destroy(gpu);
        if (prw_gpu_validation_total() != 0) {
            fprintf(stderr, "prw: error: %u Vulkan validation messages (see above)\n", prw_gpu_validation_total());
            rc = 1;
        }
    }
    if (win) glfwDestroyWindow(win);
    if (glfw) glfwTerminate();
    prw_scene_destroy(scene);
    prw_args_free(&a);
    return rc;
}
