/* tp_util — what the graph test's passes share (tests/render/test_graph.c): an additive full-screen
 * draw of three sampled inputs (shaders/tp_add.frag), a small texture, and the log every test pass
 * writes when it records (pass name and view), so the test can check order, scope and culling. */
#ifndef TP_UTIL_H
#define TP_UTIL_H

#include "prw_pass.h"

typedef struct tp_fullscreen {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipe;
    VkDescriptorSet sets[PRW_MAX_VIEWS];
} tp_fullscreen;

/* ms_input1: input 1 is a multisampled image (a depth buffer at the renderer's MSAA). */
bool tp_fullscreen_create(const prw_render_env *env, bool ms_input1, tp_fullscreen *f, prw_error *e);
void tp_fullscreen_destroy(const prw_render_env *env, tp_fullscreen *f);
void tp_fullscreen_bind(const prw_render_env *env, tp_fullscreen *f, uint32_t view, const prw_gpu_image *in0,
                        const prw_gpu_image *in1, const prw_gpu_image *in2);
/* target += weight * f(inputs of `view`) with blending ONE + ONE (a render-pass begin of its own). */
void tp_fullscreen_add(const prw_pass_ctx *c, tp_fullscreen *f, prw_gpu_image *target, int mode, float weight);
/* A w x h RGBA16F sampled texture filled with `value` (uploaded). */
bool tp_texture(const prw_render_env *env, uint32_t w, uint32_t h, float value, prw_gpu_image *out, prw_error *e);
/* The scene's mirror: the first node named "mirror*" with a mesh; plane n.x = d in world space. */
bool tp_scene_mirror(const prw_scene *s, prw_dvec3 *n, double *d);

#define TP_LOG_MAX 256
typedef struct tp_log_entry {
    const char *pass;
    uint32_t view;
} tp_log_entry;
extern tp_log_entry tp_log[TP_LOG_MAX];
extern uint32_t tp_log_count;
extern uint64_t tp_mirror_triangles; /* drawn by the mirror pass */
void tp_log_record(const char *pass, uint32_t view);

#endif
