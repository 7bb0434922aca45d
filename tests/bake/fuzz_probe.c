/* Fuzz target for the reflection-probe reader (engine/bake/prw_probe.h, probe_bake.c): the input is
 * parsed in memory; a failure must leave one message "fuzz.probe: <reason>" and no bake; a success must
 * give a header within the documented ranges, finite float-representable probe data, a non-negative
 * material, finite non-negative levels, and re-encode to the same bytes.  Each input is tried twice: as
 * given, and with its trailing checksum rewritten to match (so mutations reach the structural checks).
 * Violations abort.  The seed corpus (corpus_probe/) is written by probe_corpus_gen. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_sealed.h"
#include "prw_probe.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void one(const uint8_t *data, size_t size)
{
    prw_probe_bake *b = NULL;
    prw_error e = {{0}};
    char key[33];
    if (!prw_probe_decode(data, size, "fuzz.probe", &b, key, &e)) {
        if (strncmp(e.msg, "fuzz.probe: ", 12) != 0 || !e.msg[12] || strchr(e.msg, '\n') || b) abort();
        return;
    }
    if (b->count > PRW_PROBE_MAX || b->size < 8 || b->size > 512 || b->levels < 1 || b->levels > 64) abort();
    for (uint32_t i = 0; i < b->count; i++) {
        const prw_probe_info *p = &b->probes[i];
        if (p->material < 0 || !(p->tnear >= 0)) abort();
        for (int c = 0; c < 3; c++)
            if (!(fabs(p->centre[c]) <= 1e30) || !(fabs(p->box_min[c]) <= 1e30) || !(fabs(p->box_max[c]) <= 1e30))
                abort();
    }
    size_t nv = (size_t)b->count * b->levels * b->level_height * 2 * b->level_height * 3;
    for (size_t i = 0; i < nv; i++)
        if (!isfinite(b->levels_rgb[i]) || b->levels_rgb[i] < 0) abort();
    uint8_t *re = NULL;
    size_t n = 0;
    if (!prw_probe_encode(b, key, &re, &n, &e) || n != size || memcmp(re, data, size) != 0) abort();
    free(re);
    prw_probe_bake_destroy(b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return prw_fuzz_sealed(data, size, one); }
