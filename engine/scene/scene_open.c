/* scene_open — a model file opened as a scene (prw_scene.h prw_scene_open_model): glTF 2.0 (.gltf, .glb)
 * through the glTF importer, IGES (.igs, .iges) as one trimmed-NURBS entry with a neutral material. */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "prw_lod_node.h"
#include "scene_internal.h"

static bool ends_with(const char *s, const char *ext)
{
    size_t n = strlen(s), k = strlen(ext);
    return n > k && strcasecmp(s + n - k, ext) == 0;
}

bool prw_scene_is_model_file(const char *path)
{
    return path && (ends_with(path, ".gltf") || ends_with(path, ".glb") || ends_with(path, ".igs") ||
                    ends_with(path, ".iges"));
}

static void set_source(prw_scene *s, const char *path)
{
    if (!s->source[0]) snprintf(s->source, sizeof s->source, "%s", path);
}

bool prw_scene_open_model(prw_scene *s, const char *path, prw_error *e)
{
    if (ends_with(path, ".gltf") || ends_with(path, ".glb")) {
        if (!prw_scene_import_gltf(s, path, -1, e)) return false;
        set_source(s, path);
        return true;
    }
    if (!ends_with(path, ".igs") && !ends_with(path, ".iges"))
        return prw_fail(e, "%s: not a model file prw opens directly (.gltf, .glb, .igs, .iges; scenes: .json)", path);
    prw_scene_mark mark = prw_scene_mark_get(s);
    prw_scene_nurbs nb;
    memset(&nb, 0, sizeof nb);
    nb.material = -1;
    nb.grid[0] = nb.grid[1] = 1;
    if (strlen(path) >= sizeof nb.file) return prw_fail(e, "%s: path longer than %zu bytes", path, sizeof nb.file - 1);
    snprintf(nb.file, sizeof nb.file, "%s", path);
    const char *base = strrchr(path, '/');
    prw_copy_name(nb.name, base ? base + 1 : path);
    /* CAD solids come with either orientation: a light grey seen from both sides */
    prw_material m = prw_material_default();
    snprintf(m.name, sizeof m.name, "iges-grey");
    m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.6f;
    m.roughness = 0.5f;
    m.double_sided = true;
    nb.material = prw_scene_add_material(s, &m);
    prw_nurbs_model model;
    if (nb.material < 0 || !prw_scene_nurbs_load(&nb, &model, e)) {
        prw_scene_rollback(s, mark);
        return nb.material < 0 ? prw_fail(e, "%s: cannot add its material", path) : false;
    }
    prw_nurbs_model_trimmed_bounds(&model, &nb.model_min, &nb.model_max);
    prw_nurbs_model_free(&model);
    prw_node n = prw_node_default();
    prw_copy_name(n.name, nb.name);
    nb.node = prw_scene_add_node(s, &n);
    if (nb.node < 0 || prw_scene_add_nurbs(s, &nb) < 0) {
        prw_scene_rollback(s, mark);
        return prw_fail(e, "%s: cannot add the model", path);
    }
    prw_scene_note_missing(s, path);
    set_source(s, path);
    return true;
}
