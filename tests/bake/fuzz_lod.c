/* Fuzz target for the .lod reader (engine/scene/prw_lod_file.h): the input is parsed in memory; a failure must
 * leave one message "fuzz.lod: <reason>"; a success must give a hierarchy that selection and
 * extraction walk at every level (selection also with the file's culling data; ASan / UBSan catch
 * stray reads) with finite output positions, and proxy levels whose every index is in range.
 * Each input is tried twice: as given, and with its header's payload size and checksum rewritten
 * to match (so mutations reach the structural checks instead of stopping at the checksum).
 * Violations abort.  The seed corpus (corpus/) is written by bake_corpus_gen. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_file.h"
#include "prw_lod_select.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void one(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 22) return 0;
    one(data, size);
    if (size >= PRW_LOD_HEADER_SIZE) {
        uint8_t *c = malloc(size);
        memcpy(c, data, size);
        uint64_t payload = size - PRW_LOD_HEADER_SIZE, sum = prw_hash64(c + PRW_LOD_HEADER_SIZE, payload, 0);
        for (int i = 0; i < 8; i++) {
            c[16 + i] = (uint8_t)(payload >> (8 * i));
            c[24 + i] = (uint8_t)(sum >> (8 * i));
        }
        one(c, size);
        free(c);
    }
    return 0;
}

static void one(const uint8_t *data, size_t size)
{
    prw_baked_lod *b;
    prw_error e = {{0}};
    if (!prw_lod_file_parse(data, size, "fuzz.lod", &b, &e)) {
        if (strncmp(e.msg, "fuzz.lod: ", 10) != 0 || !e.msg[10] || strchr(e.msg, '\n')) abort();
        return;
    }
    const prw_lod_model *lm = &b->lod;
    if (lm->g != &b->graph) abort();
    int *lv = malloc(sizeof(int) * (size_t)lm->npatches + 1), *sl = malloc(sizeof(int) * (size_t)b->graph.nsegs + 1);
    prw_lod_view v = {.eye = {{1, 2, 3}, {1.1, 2, 3}}, .neyes = 2, .pixel_angle = 1e-3, .tri_budget = 100};
    prw_lod_select_report rep;
    prw_lod_select(lm, &v, lv, &rep);
    /* again with the file's culling data, every patch single-sided so the cones are used */
    for (int p = 0; p < b->cull.npatches; p++) b->cull.single_sided[p] = 1;
    v.cull = &b->cull;
    prw_lod_select(lm, &v, lv, &rep);
    prw_lod_mesh m;
    memset(&m, 0, sizeof m);
    for (int k = 0; k < lm->levels; k++) {
        for (int p = 0; p < lm->npatches; p++) lv[p] = k;
        prw_lod_segment_levels(lm, lv, sl);
        prw_lod_mesh_reset(&m);
        for (int p = 0; p < lm->npatches; p++) prw_lod_emit(lm, p, k, sl, &m);
        for (size_t i = 0; i < 3 * m.nverts; i++)
            if (!isfinite(m.pos[i])) abort();
        for (size_t i = 0; i < 3 * m.ntris; i++)
            if (m.tris[i] >= m.nverts) abort();
    }
    prw_lod_mesh_free(&m);
    /* the proxy levels (format version 3): every index in range, every coordinate finite, the
     * triangle counts strictly decreasing */
    for (int l = 0; b->have_proxy && l < b->proxy.nlevels; l++) {
        const prw_lod_proxy_level *pl = &b->proxy.levels[l];
        if (l > 0 && pl->ntris >= b->proxy.levels[l - 1].ntris) abort();
        for (int t = 0; t < pl->ntris; t++) {
            if (pl->tri_patch[t] < 0 || pl->tri_patch[t] >= lm->npatches) abort();
            for (int c = 0; c < 3; c++) {
                uint32_t v = pl->tris[3 * t + c];
                if (v >= (uint32_t)pl->nverts || !isfinite(pl->pos[3 * v] + pl->pos[3 * v + 1] + pl->pos[3 * v + 2]))
                    abort();
                if (pl->corner_patch[3 * t + c] < 0 || pl->corner_patch[3 * t + c] >= lm->npatches) abort();
                if (!isfinite(pl->corner_uv[6 * t + 2 * c] + pl->corner_uv[6 * t + 2 * c + 1])) abort();
            }
        }
    }
    free(lv);
    free(sl);
    prw_lod_file_destroy(b);
}
