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
