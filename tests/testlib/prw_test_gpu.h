/* prw_test_gpu — one gpu per test process, validation layer on, made on first use.
 *
 * Pipelines are shared within a gpu (prw_gpu.h), so a test that creates many renderers on this gpu
 * compiles each distinct pipeline once instead of once per renderer (lavapipe has no working
 * pipeline cache).  Validation messages are counted for the whole process (prw_gpu_validation_total);
 * prw_test_gpu_finish destroys the gpu, so the layer's leak reports at destroy are counted too. */
#ifndef PRW_TEST_GPU_H
#define PRW_TEST_GPU_H

#include "prw_render.h"

/* The process's gpu (created on the first call); NULL with e set when none can be made. */
prw_gpu *prw_test_gpu(prw_error *e);
/* Destroys the gpu (if made) and returns the validation messages of the whole process; prints them as
 * a failure line when there are any.  Call once, after the last use. */
uint32_t prw_test_gpu_finish(void);
/* Renders views[0..n) with one renderer made from desc on the process's gpu (desc's size is the
 * first view's when 0), reading view k's HDR image into hdr[k] and its stats into st[k] (st may be
 * NULL).  Fails when the layer has reported anything so far in the process. */
bool prw_test_render(const prw_scene *s, const prw_render_desc *desc, const prw_view *views, size_t n,
                     prw_image *hdr, prw_frame_stats *st, prw_error *e);

#endif
