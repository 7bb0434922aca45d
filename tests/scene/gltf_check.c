/* gltf_check FILE — imports one .gltf/.glb with prw_scene_import_gltf and prints one summary line:
 *   ok: meshes M, triangles T, materials X, textures Y, warnings W
 * followed by one "  warning: ..." line per import warning, or
 *   refused: <the loader's message>
 * Exit status 0 when the file loads, 1 when it is refused, 2 on a usage error.  Used by
 * scripts/corpus_gltf.sh; not a test by itself.  Built with -DPRW_GLTF_CHECK_NO_WARNINGS it also
 * compiles against loaders that predate import warnings (for comparisons with older commits). */
#include <stdio.h>
#include <string.h>

#include "prw_scene.h"

int main(int argc, char **argv)
{
    if (argc != 2 || strcmp(argv[1], "--help") == 0) {
        fprintf(stderr, "usage: gltf_check FILE.gltf|FILE.glb\n");
        return 2;
    }
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    if (!prw_scene_import_gltf(s, argv[1], -1, &e)) {
        printf("refused: %s\n", e.msg);
        prw_scene_destroy(s);
        return 1;
    }
    unsigned long long tris = 0;
    for (uint32_t i = 0; i < s->mesh_count; i++) tris += s->meshes[i].index_count / 3;
    unsigned warnings = 0;
#ifndef PRW_GLTF_CHECK_NO_WARNINGS
    warnings = s->warning_count;
#endif
    printf("ok: meshes %u, triangles %llu, materials %u, textures %u, warnings %u\n", s->mesh_count, tris,
           s->material_count, s->texture_count, warnings);
#ifndef PRW_GLTF_CHECK_NO_WARNINGS
    for (uint32_t i = 0; i < s->warning_count; i++) printf("  warning: %s\n", s->warnings[i].msg);
#endif
    prw_scene_destroy(s);
    return 0;
}
