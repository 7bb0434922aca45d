/* fuzz_exr — libFuzzer target for the EXR reader: the input is an in-memory EXR file
 * (prw_exr_read_memory: the OpenEXR C API reads it through our read/size callbacks). */
#include <stddef.h>
#include <stdint.h>

#include "prw_image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* both option paths; a small pixel limit keeps single inputs from asking for gigabytes */
    prw_exr_read_opts opts = {.reject_nonfinite = size > 0 && (data[size - 1] & 1), .max_pixels = 1 << 20};
    prw_image img;
    prw_error e;
    if (prw_exr_read_memory(data, size, "fuzz.exr", &opts, &img, &e)) {
        volatile float sink = 0;
        for (size_t i = 0; i < (size_t)img.width * (size_t)img.height * 4; i += 97) sink += img.rgba[i];
        (void)sink;
        prw_image_free(&img);
    } else if (img.rgba || !e.msg[0]) {
        __builtin_trap(); /* a failure must leave no image and say why */
    }
    return 0;
}
