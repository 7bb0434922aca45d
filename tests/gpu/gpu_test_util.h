/* Helpers shared by the gpu tests. */
#ifndef GPU_TEST_UTIL_H
#define GPU_TEST_UTIL_H

#include <string.h>

#include "prw_gpu.h"
#include "prw_test.h"

/* Validation is forced on, whatever the environment says: the tests are about clean usage. */
static inline bool test_gpu_open(prw_gpu **gpu, prw_error *e)
{
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    return prw_gpu_create(&d, gpu, e);
}

/* Closes the gpu and checks that neither its use nor its destruction (leaks) produced messages. */
#define TEST_GPU_CLOSE(gpu)                                                          \
    do {                                                                             \
        CHECK(prw_gpu_validation_count(gpu) == 0);                                   \
        uint32_t _before = prw_gpu_validation_total();                               \
        prw_gpu_destroy(gpu);                                                        \
        CHECK_MSG(prw_gpu_validation_total() == _before, "messages at destroy: %u",  \
                  prw_gpu_validation_total() - _before);                             \
    } while (0)

#endif
