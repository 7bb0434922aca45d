/* Test helper (C API over libdraco's encoder): encodes a triangle mesh as a Draco stream. */
#ifndef TEST_DRACO_ENCODE_H
#define TEST_DRACO_ENCODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct test_draco_input {
    const float *positions; /* 3 per vertex */
    const float *normals;   /* 3 per vertex or NULL */
    const float *uvs;       /* 2 per vertex or NULL */
    uint32_t vertex_count;
    const uint32_t *indices;
    uint32_t index_count;
    int position_bits; /* quantisation of positions */
    bool edgebreaker;  /* else sequential */
} test_draco_input;

typedef struct test_draco_output {
    uint8_t *data; /* malloc'ed; free() it */
    size_t size;
    uint32_t uid_position, uid_normal, uid_uv; /* attribute ids for the glTF extension */
} test_draco_output;

bool test_draco_encode(const test_draco_input *in, test_draco_output *out);

#ifdef __cplusplus
}
#endif
#endif
