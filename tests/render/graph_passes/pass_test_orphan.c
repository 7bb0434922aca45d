/* test_orphan — a pass whose output nobody reads: the graph must cull it every frame (it records
 * nothing: no barrier, begin or draw).  Its record would log itself and clear its image. */
#include "tp_util.h"

static void setup(prw_setup *s)
{
    prw_image_decl d = {.format = VK_FORMAT_R16G16B16A16_SFLOAT, .size = PRW_SIZE_FIXED, .width = 16, .height = 16,
                        .shared = true};
    prw_setup_image(s, "orphan_out", &d);
    prw_setup_use(s, "orphan_out", PRW_USE_COLOR);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    (void)e;
    tp_log_record("test_orphan", c->view);
    prw_gpu_image *img = prw_pass_image(c, "orphan_out");
    VkRenderingAttachmentInfo ca = {.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
                                    .imageView = img->view,
                                    .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                    .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
                                    .storeOp = VK_ATTACHMENT_STORE_OP_STORE};
    VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO, .renderArea = {{0, 0}, {16, 16}},
                          .layerCount = 1, .colorAttachmentCount = 1, .pColorAttachments = &ca};
    prw_pass_begin_rendering(c, &ri);
    prw_pass_end_rendering(c);
    return true;
}

const prw_pass test_pass_orphan = {
    .name = "test_orphan",
    .scope = PRW_SCOPE_FRAME,
    .setup = setup,
    .record = record,
};
