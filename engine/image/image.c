/* image.c — prw_image allocation with size checks. */
#include "prw_image.h"

#include <stdio.h>
#include <stdlib.h>

bool prw_image_size_ok(int64_t width, int64_t height, const char *who, prw_error *e)
{
    if (width <= 0 || height <= 0)
        return prw_fail(e, "%s: image size: invalid size %lldx%lld (both dimensions must be > 0)", who,
                        (long long)width, (long long)height);
    if (width > PRW_IMAGE_MAX_PIXELS || height > PRW_IMAGE_MAX_PIXELS ||
        width * height > PRW_IMAGE_MAX_PIXELS)
        return prw_fail(e, "%s: image size: %lldx%lld exceeds the limit of %lld pixels", who,
                        (long long)width, (long long)height, (long long)PRW_IMAGE_MAX_PIXELS);
    return true;
}

bool prw_image_alloc(prw_image *img, int width, int height, prw_error *e)
{
    img->width = img->height = 0;
    img->rgba = NULL;
    if (!prw_image_size_ok(width, height, "prw_image", e)) return false;
    char what[64];
    snprintf(what, sizeof what, "a %dx%d RGBA float image", width, height);
    if (!prw_mem_check((uint64_t)width * (uint64_t)height * 16, "prw_image", what, e)) return false;
    img->rgba = prw_calloc((size_t)width * (size_t)height * 4, sizeof(float));
    img->width = width;
    img->height = height;
    return true;
}

void prw_image_free(prw_image *img)
{
    if (!img) return;
    free(img->rgba);
    img->rgba = NULL;
    img->width = img->height = 0;
}
