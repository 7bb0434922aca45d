/* libFuzzer target: glTF import (.gltf / .glb bytes written to a scratch file, since the API takes a
 * path).  Checks the same contract as fuzz_manifest: no crash, a failed import leaves the scene as
 * it was and reports one line starting with the path; a successful one leaves valid indices. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "prw_scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void die(const char *what, const char *msg)
{
    fprintf(stderr, "fuzz_gltf: contract violated: %s: %s\n", what, msg);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[128];
    if (!path[0]) snprintf(path, sizeof path, "fuzz-gltf-%ld.bin", (long)getpid());
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fwrite(data, 1, size, f);
    fclose(f);
    prw_scene *s = prw_scene_create();
    prw_node root = prw_node_default();
    prw_scene_add_node(s, &root);
    prw_error e;
    e.msg[0] = '\0';
    bool ok = prw_scene_import_gltf(s, path, 0, &e);
    if (getenv("PRW_FUZZ_VERBOSE")) printf("%s\n", ok ? "accepted" : e.msg);
    if (ok) {
        for (uint32_t i = 0; i < s->mesh_count; i++) {
            const prw_mesh *m = &s->meshes[i];
            if (m->material < 0 || (uint32_t)m->material >= s->material_count) die("mesh material", m->name);
            for (uint32_t k = 0; k < m->index_count; k++)
                if (m->indices[k] >= m->vertex_count) die("mesh index", m->name);
        }
        for (uint32_t i = 1; i < s->node_count; i++)
            if (s->nodes[i].parent < 0 || s->nodes[i].parent >= (int)i) die("node parent order", s->nodes[i].name);
        for (uint32_t i = 0; i < s->material_count; i++) {
            const prw_material *m = &s->materials[i];
            int t[7] = {m->base_color_tex, m->metal_rough_tex,         m->normal_tex,          m->emissive_tex,
                        m->clearcoat_tex,  m->clearcoat_roughness_tex, m->clearcoat_normal_tex};
            for (int k = 0; k < 7; k++)
                if (t[k] < -1 || t[k] >= (int)s->texture_count) die("material texture", m->name);
            for (int k = 0; k < PRW_TEX_SLOT_COUNT; k++)
                if (m->tex_xf[k].tex_coord < 0 || m->tex_xf[k].tex_coord > 1) die("texture uv set", m->name);
        }
        for (uint32_t i = 0; i < s->warning_count; i++)
            if (strncmp(s->warnings[i].msg, path, strlen(path)) != 0 || strchr(s->warnings[i].msg, '\n'))
                die("warning is not one line starting with the path", s->warnings[i].msg);
    } else {
        if (strncmp(e.msg, path, strlen(path)) != 0) die("message does not start with the path", e.msg);
        if (strchr(e.msg, '\n')) die("message is not one line", e.msg);
        if (s->node_count != 1 || s->mesh_count || s->material_count || s->texture_count || s->light_count ||
            s->camera_count || s->group_count || s->warning_count)
            die("failed import left content behind", e.msg);
    }
    prw_scene_destroy(s);
    remove(path);
    return 0;
}
