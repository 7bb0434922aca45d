/* btf_ubo_internal.h — what the Bonn-format reader and writer share (internal to materials/btf). */
#ifndef PRW_BTF_UBO_INTERNAL_H
#define PRW_BTF_UBO_INTERNAL_H

#include "prw_btf_ubo.h"

static inline uint32_t prw_btf_le32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

#endif
