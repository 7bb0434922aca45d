/* Fuzz target for the light-map reader (engine/bake/prw_gi.h, gi_file.c): the input is parsed in
 * memory; a failure must leave one message "fuzz.gi: <reason>"; a success must give finite,
 * non-negative light-map values, states 0..2, ATLAS instances naming an existing atlas, and
 * re-encode to the same bytes.  Each input is tried twice: as given, and with its trailing checksum
 * rewritten to match (so mutations reach the structural checks).  Violations abort.  The seed corpus
 * (corpus_gi/) is written by gi_corpus_gen. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_sealed.h"
#include "prw_gi.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void one(const uint8_t *data, size_t size)
{
    prw_gi_bake *b = NULL;
    prw_error e = {{0}};
    char key[33];
    if (!prw_gi_decode(data, size, "fuzz.gi", &b, key, &e)) {
        if (strncmp(e.msg, "fuzz.gi: ", 9) != 0 || !e.msg[9] || strchr(e.msg, '\n') || b) abort();
        return;
    }
    for (uint32_t a = 0; a < b->atlas_count; a++) {
        const prw_gi_atlas *A = &b->atlases[a];
        size_t t = (size_t)A->width * A->height;
        for (size_t i = 0; i < 3 * t; i++)
            if (!isfinite(A->rgb[i]) || A->rgb[i] < 0 || !isfinite(A->var[i]) || A->var[i] < 0) abort();
        for (size_t i = 0; i < t; i++)
            if (A->state[i] > 2) abort();
    }
    for (uint32_t i = 0; i < b->instance_count; i++) {
        const prw_gi_instance *in = &b->inst[i];
        if (in->mode > PRW_GI_VERTEX) abort();
        if (in->mode == PRW_GI_ATLAS && in->atlas >= b->atlas_count) abort();
        for (size_t k = 0; in->mode == PRW_GI_ATLAS && k < 6 * (size_t)in->triangle_count; k++)
            if (!isfinite(in->uv[k])) abort();
    }
    uint8_t *re = NULL;
    size_t n = 0;
    if (!prw_gi_encode(b, key, &re, &n, &e) || n != size || memcmp(re, data, size) != 0) abort();
    free(re);
    prw_gi_bake_destroy(b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return prw_fuzz_sealed(data, size, one); }
