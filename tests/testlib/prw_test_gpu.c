/* prw_test_gpu.c — see prw_test_gpu.h. */
#include <stdio.h>

#include "prw_test_gpu.h"

static prw_gpu *g_gpu;

prw_gpu *prw_test_gpu(prw_error *e)
{
    if (g_gpu) return g_gpu;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &g_gpu, e)) g_gpu = NULL;
    return g_gpu;
}

uint32_t prw_test_gpu_finish(void)
{
    if (g_gpu) {
        uint32_t pipes = 0;
        uint64_t hits = 0;
        prw_pipeline_memo_stats(g_gpu, &pipes, &hits);
        printf("gpu: %u pipelines compiled, %llu requests shared\n", pipes, (unsigned long long)hits);
        prw_gpu_destroy(g_gpu);
        g_gpu = NULL;
    }
    uint32_t msgs = prw_gpu_validation_total();
    if (msgs) printf("FAIL %u validation messages in this process\n", msgs);
    return msgs;
}

bool prw_test_render(const prw_scene *s, const prw_render_desc *desc, const prw_view *views, size_t n,
                     prw_image *hdr, prw_frame_stats *st, prw_error *e)
{
    prw_render_desc d = *desc;
    if (!d.width) d.width = views[0].width, d.height = views[0].height;
    prw_gpu *gpu = prw_test_gpu(e);
    prw_renderer *r = NULL;
    bool ok = gpu && prw_renderer_create(gpu, s, &d, &r, e);
    for (size_t k = 0; ok && k < n; k++)
        ok = prw_renderer_render(r, &views[k], 1, st ? &st[k] : NULL, e) && prw_renderer_read_hdr(r, 0, &hdr[k], e);
    prw_renderer_destroy(r);
    uint32_t msgs = prw_gpu_validation_total(); /* the process's so far; leak reports come at the end */
    if (ok && msgs) ok = prw_fail(e, "%u validation messages", msgs);
    return ok;
}
