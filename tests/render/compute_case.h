/* compute_case — the harness of the GPU-equals-CPU tests (test_brdf_gpu, test_ltc_gpu, test_btf_gpu): one
 * compute dispatch over storage buffers (bindings 0 .. n-1, uploaded from host data; the ones with a
 * readback pointer are copied back after the dispatch) and optionally one RGBA32F 2-D array texture
 * (binding n, linear filtering, clamp to edge), push constants visible to every stage, on a device with the
 * validation layer on. */
#ifndef PRW_TEST_COMPUTE_CASE_H
#define PRW_TEST_COMPUTE_CASE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "prw_core.h"
#include "prw_gpu.h"

typedef struct compute_buffer {
    const void *data; /* size bytes uploaded (NULL: zeros) */
    size_t size;      /* > 0 */
    void *readback;   /* non-NULL: size bytes copied back after the dispatch */
} compute_buffer;

typedef struct compute_texture {
    const float *texels; /* width * height * 4 floats per layer, layer after layer */
    uint32_t width, height, layers;
} compute_texture;

bool compute_case_run(prw_spirv shader, const compute_buffer *bufs, int nbufs, const compute_texture *tex,
                      const void *push, uint32_t push_size, uint32_t groups_x, prw_error *e);

#endif
