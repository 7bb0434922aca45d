/* The entry point of the fuzz targets of files sealed by a trailing checksum (the light-map and probe
 * cache files: the last 8 bytes are prw_hash64 of the rest): each input is tried as given and again
 * with its checksum made right, so the mutations reach the reader behind the check. */
#ifndef PRW_FUZZ_SEALED_H
#define PRW_FUZZ_SEALED_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "prw_core.h"

static inline int prw_fuzz_sealed(const uint8_t *data, size_t size, void (*one)(const uint8_t *, size_t))
{
    if (size > 1 << 22) return 0;
    one(data, size);
    if (size >= 16) {
        uint8_t *c = malloc(size);
        memcpy(c, data, size);
        uint64_t sum = prw_hash64(c, size - 8, 0);
        for (int i = 0; i < 8; i++) c[size - 8 + i] = (uint8_t)(sum >> (8 * i));
        one(c, size);
        free(c);
    }
    return 0;
}
#endif
