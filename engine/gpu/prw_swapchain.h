/* prw_swapchain — presenting to a GLFW window.
 *
 * Promises: a FIFO (vsync) or IMMEDIATE/MAILBOX swapchain on the window's surface, images usable as
 * transfer destinations (the renderer blits its display-encoded image into them), recreated
 * transparently when the window is resized or the swapchain is out of date.  Frames in flight: 2.
 */
#ifndef PRW_SWAPCHAIN_H
#define PRW_SWAPCHAIN_H

#include "prw_gpu.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_swapchain prw_swapchain;

/* window is a GLFWwindow* (kept opaque so this header does not need GLFW). */
bool prw_swapchain_create(prw_gpu *gpu, void *window, bool vsync, prw_swapchain **out, prw_error *e);
void prw_swapchain_destroy(prw_gpu *gpu, prw_swapchain *sc);

/* Waits for the frame slot, acquires an image and begins this frame's command buffer.
 * *target is the swapchain image (layout tracked; transition it yourself to TRANSFER_DST).
 * Returns false with *skip = true (and no error) when the window is minimised. */
bool prw_swapchain_begin_frame(prw_gpu *gpu, prw_swapchain *sc, VkCommandBuffer *cmd, prw_gpu_image **target,
                               bool *skip, prw_error *e);
/* Transitions the target to PRESENT_SRC, ends and submits the command buffer, presents. */
bool prw_swapchain_end_frame(prw_gpu *gpu, prw_swapchain *sc, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
