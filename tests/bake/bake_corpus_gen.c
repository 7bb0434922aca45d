/* Writes the seed corpus of fuzz_lod (not a test): bake_corpus_gen <dir>
 *   two_patch_l3.lod  the two-patch model, few sewing points, 3 levels (~5 KB)
 *   one_patch_l1.lod  its flat patch alone, 1 level
 *   no_patches.lod    an empty hierarchy (0 nodes, segments, patches) */
#include <stdio.h>
#include <string.h>

#include "bake_models.h"
#include "prw_bake.h"
#include "prw_nurbs_json.h"

static int write(const char *dir, const char *name, const char *json, int levels)
{
    prw_nurbs_model m;
    prw_error e;
    prw_baked_lod *b;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (!prw_nurbs_json_parse(json, strlen(json), "corpus.json", &m, &e)) goto fail;
    if (m.count > 1 && levels == 1) prw_nurbs_model_pop(&m);
    prw_bake_options o;
    memset(&o, 0, sizeof o);
    o.seam.max_edge = 0.5;
    o.seam.chord = 0.02;
    o.lod.levels = levels;
    o.lod.max_cells = 2;
    bool ok = prw_baked_lod_build(&m, &o, &b, NULL, NULL, &e);
    prw_nurbs_model_free(&m);
    if (!ok) goto fail;
    ok = prw_lod_file_write(path, b, &e);
    prw_lod_file_destroy(b);
    if (!ok) goto fail;
    printf("wrote %s\n", path);
    return 0;
fail:
    fprintf(stderr, "bake_corpus_gen: %s: %s\n", name, e.msg);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: bake_corpus_gen DIR\n");
        return 2;
    }
    int bad = write(argv[1], "two_patch_l3.lod", BAKE_TWO_PATCH_JSON, 3);
    bad += write(argv[1], "one_patch_l1.lod", BAKE_TWO_PATCH_JSON, 1);
    prw_baked_lod empty;
    memset(&empty, 0, sizeof empty);
    empty.lod.g = &empty.graph;
    empty.lod.levels = 1;
    char path[4096];
    prw_error e;
    snprintf(path, sizeof path, "%s/no_patches.lod", argv[1]);
    if (!prw_lod_file_write(path, &empty, &e)) {
        fprintf(stderr, "bake_corpus_gen: %s\n", e.msg);
        bad++;
    } else printf("wrote %s\n", path);
    return bad ? 1 : 0;
}
