/* libFuzzer target: the scene manifest parser on arbitrary bytes (one fresh scene per input).
 * Beyond "no crash / no leak / no UB" it checks the error contract: a failure leaves exactly the
 * scene it found (here: empty) and a one-line message starting with the file name; a success leaves
 * a consistent scene (indices in range, parents before children). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void die(const char *what, const char *msg)
{
    fprintf(stderr, "fuzz_manifest: contract violated: %s: %s\n", what, msg);
    abort();
}

static void check_scene(const prw_scene *s)
{
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const prw_mesh *m = &s->meshes[i];
        if (m->material < 0 || (uint32_t)m->material >= s->material_count) die("mesh material", m->name);
        for (uint32_t k = 0; k < m->index_count; k++)
            if (m->indices[k] >= m->vertex_count) die("mesh index", m->name);
    }
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *n = &s->nodes[i];
        if (n->parent >= (int)i || n->parent < -1) die("node parent order", n->name);
        if (n->mesh_group >= (int)s->group_count) die("node mesh group", n->name);
        if (n->camera >= (int)s->camera_count) die("node camera", n->name);
        if (n->light >= (int)s->light_count) die("node light", n->name);
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const prw_light *l = &s->lights[i];
        double y = 0.2126 * l->color[0] + 0.7152 * l->color[1] + 0.0722 * l->color[2];
        if (!(y > 0.999 && y < 1.001)) die("light colour luminance", l->name);
        if (!(l->intensity >= 0) || l->node < 0 || (uint32_t)l->node >= s->node_count) die("light", l->name);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *path = "fuzz/manifest.json";
    prw_scene *s = prw_scene_create();
    prw_error e;
    e.msg[0] = '\0';
    static int verbose = -1;
    if (verbose < 0) verbose = getenv("PRW_FUZZ_VERBOSE") != NULL;
    bool ok = prw_scene_parse_manifest(s, (const char *)data, size, path, &e);
    if (verbose) printf("%s\n", ok ? "accepted" : e.msg);
    if (ok) {
        check_scene(s);
    } else {
        if (strncmp(e.msg, path, strlen(path)) != 0) die("message does not start with the file", e.msg);
        if (strchr(e.msg, '\n')) die("message is not one line", e.msg);
        if (s->mesh_count || s->node_count || s->material_count || s->light_count || s->camera_count ||
            s->texture_count || s->group_count)
            die("failed load left content behind", e.msg);
    }
    prw_scene_destroy(s);
    return 0;
}
