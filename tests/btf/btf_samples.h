/* btf_samples — small Bonn-format BTFs built in memory for the tests and the fuzz corpus: every
 * format and header variant, values drawn so that they are exact at the file's scalar size.
 * btf_sample_tensor: the closed-form tensor the "tensor" samples encode (each format its own way). */
#ifndef PRW_TEST_BTF_SAMPLES_H
#define PRW_TEST_BTF_SAMPLES_H

#include "prw_btf_ubo.h"

typedef enum btf_sample_kind {
    BTF_SAMPLE_DFMF_R_V4,   /* DFMF with rotations, meta version 4 (XML, channel names), mixed scalar sizes */
    BTF_SAMPLE_DFMF_V1,     /* DFMF without rotations, meta version 1, floats */
    BTF_SAMPLE_FMF_EXT,     /* FMF "E" header version 2: dynamic-range flag and a height map; doubles */
    BTF_SAMPLE_FMF_PLAIN,   /* FMF without the extra header or rotations, halves */
    BTF_SAMPLE_BDI_SPARSE,  /* BDI, some texels left out, an uneven last chunk */
    BTF_SAMPLE_KIND_COUNT
} btf_sample_kind;

/* A random sample of that kind (views x lights x width x height as given, 3 channels). */
void btf_sample(btf_sample_kind kind, uint32_t views, uint32_t lights, uint32_t w, uint32_t h, uint64_t seed,
                prw_btf_ubo *out);

/* The tensor of the encodings below, exact in half precision: channel c, view v, light l, texel (x, y). */
double btf_sample_tensor(uint32_t c, uint32_t v, uint32_t l, uint32_t x, uint32_t y);
/* The same tensor as DFMF (two components per channel), FMF (two components) and BDI (every texel). */
void btf_sample_tensor_file(prw_btf_ubo_format format, uint32_t views, uint32_t lights, uint32_t w, uint32_t h,
                            prw_btf_ubo *out);

#endif
