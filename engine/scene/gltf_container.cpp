// gltf_container.cpp — see gltf_container.h.
#include "scene_internal.h"
#include "gltf_container.h"

#include <cJSON.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace prw_gltf {

std::string format(const char *fmt, ...)
{
    char buf[PRW_ERROR_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    return buf;
}

// One printable line from untrusted text (names, tinygltf messages), at most `max` bytes.
std::string one_line(const std::string &s, size_t max)
{
    std::string r;
    for (size_t i = 0; i < s.size() && r.size() < max; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '\n') {
            if (i + 1 < s.size()) r += "; ";
        } else if (c >= 0x20 && c != 0x7f) {
            r += (char)c;
        } else {
            r += '?';
        }
    }
    return r;
}
uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

// 0: not a GLB; else the GLB container version (bytes 4..7).
uint32_t glb_version(const std::string &d)
{
    if (d.size() < 4 || memcmp(d.data(), "glTF", 4) != 0) return 0;
    if (d.size() < 8) return 0xffffffffu;
    return le32((const unsigned char *)d.data() + 4);
}

// The GLB container's chunk layout, checked before tinygltf reads it: tinygltf 2.7 lets a BIN chunk
// end up to 8 bytes past the container (it forgets the chunk header; found by fuzz_gltf).  "" or why not.
std::string glb_layout(const std::string &d)
{
    const unsigned char *p = (const unsigned char *)d.data();
    if (d.size() < 20) return format("GLB: %zu bytes is shorter than the 20-byte header", d.size());
    uint64_t length = le32(p + 8), jlen = le32(p + 12);
    if (length > d.size()) return format("GLB: header length %llu exceeds the file's %zu bytes", (unsigned long long)length, d.size());
    if (le32(p + 16) != 0x4E4F534Au) return "GLB: the first chunk is not JSON";
    if (20 + jlen > length) return format("GLB: JSON chunk of %llu bytes exceeds the container", (unsigned long long)jlen);
    uint64_t at = 20 + jlen;
    if (at == length) return "";
    if (at + 8 > length) return "GLB: truncated chunk header after the JSON chunk";
    uint64_t blen = le32(p + at);
    if (at + 8 + blen > length)
        return format("GLB: chunk of %llu bytes at offset %llu exceeds the container (%llu bytes)", (unsigned long long)blen,
                      (unsigned long long)at, (unsigned long long)length);
    return "";
}

// tinygltf 2.7 decodes an image stored in a bufferView without checking that the view lies inside its
// buffer (stb_image then reads past it; found by fuzz_gltf).  Checked here on the JSON before
// parsing: buffer data is exactly byteLength long once tinygltf has loaded it.  "" or why not.
std::string image_views(const char *json, size_t size)
{
    if (!memmem(json, size, "\"images\"", 8)) return "";
    cJSON *root = cJSON_ParseWithLength(json, size);
    if (!root) return ""; // tinygltf reports the syntax error
    std::string why;
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images");
    const cJSON *views = cJSON_GetObjectItemCaseSensitive(root, "bufferViews");
    const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(root, "buffers");
    int n = cJSON_IsArray(images) ? cJSON_GetArraySize(images) : 0;
    for (int i = 0; i < n && why.empty(); i++) {
        const cJSON *bvj = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(images, i), "bufferView");
        if (!bvj) continue;
        auto num = [](const cJSON *o, const char *key, double dflt) {
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
            return !v ? dflt : cJSON_IsNumber(v) ? v->valuedouble : -1.0;
        };
        double b = cJSON_IsNumber(bvj) ? bvj->valuedouble : -1;
        const cJSON *bv = b >= 0 && cJSON_IsArray(views) && b < cJSON_GetArraySize(views) ? cJSON_GetArrayItem(views, (int)b) : nullptr;
        double buf = bv ? num(bv, "buffer", -1) : -1;
        const cJSON *bo = buf >= 0 && cJSON_IsArray(buffers) && buf < cJSON_GetArraySize(buffers)
                              ? cJSON_GetArrayItem(buffers, (int)buf) : nullptr;
        double off = bv ? num(bv, "byteOffset", 0) : -1, len = bv ? num(bv, "byteLength", -1) : -1;
        double blen = bo ? num(bo, "byteLength", -1) : -1;
        if (!bo || off < 0 || len < 0 || blen < 0)
            why = format("image %d: bufferView %g is missing or malformed", i, b);
        else if (off + len > blen)
            why = format("image %d: bufferView %g (bytes %.0f..%.0f) exceeds buffer %g length %.0f", i, b, off, off + len,
                         buf, blen);
    }
    cJSON_Delete(root);
    return why;
}

// A texture reference (textureInfo) of material mi: `key` inside `parent`.  "" or the refusal.
static std::string texture_info(const cJSON *parent, const char *key, int mi, const char *path,
                                std::vector<std::string> *warn)
{
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(parent, key);
    if (!t) return "";
    if (!cJSON_IsObject(t)) return format("material %d: %s%s is not an object", mi, path, key);
    const cJSON *index = cJSON_GetObjectItemCaseSensitive(t, "index");
    if (!index) {
        warn->push_back(format("material %d: %s%s has no index; ignored", mi, path, key));
    } else if (!cJSON_IsNumber(index) || !(index->valuedouble >= 0 && index->valuedouble <= 2147483647.0) ||
               index->valuedouble != floor(index->valuedouble)) {
        char *text = cJSON_PrintUnformatted(index);
        std::string v = one_line(text ? text : "?", 40);
        free(text);
        return format("material %d: %s%s.index %s is not a texture index (an integer >= 0)", mi, path, key, v.c_str());
    }
    for (const char *num : {"scale", "strength"}) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(t, num);
        if (v && !cJSON_IsNumber(v)) warn->push_back(format("material %d: %s%s.%s is not a number; 1 used", mi, path, key, num));
    }
    const cJSON *ext = cJSON_GetObjectItemCaseSensitive(t, "extensions");
    const cJSON *xf = cJSON_IsObject(ext) ? cJSON_GetObjectItemCaseSensitive(ext, "KHR_texture_transform") : nullptr;
    if (xf && !cJSON_IsObject(xf))
        warn->push_back(format("material %d: %s%s: KHR_texture_transform is not an object; ignored", mi, path, key));
    return "";
}

std::string wrong_types(const char *json, size_t size, std::vector<std::string> *warn)
{
    cJSON *root = cJSON_ParseWithLength(json, size);
    if (!root) return ""; // tinygltf reports the syntax error
    std::string why;
    const cJSON *meshes = cJSON_GetObjectItemCaseSensitive(root, "meshes");
    int n = cJSON_IsArray(meshes) ? cJSON_GetArraySize(meshes) : 0;
    for (int i = 0; i < n && why.empty(); i++) {
        const cJSON *prims = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(meshes, i), "primitives");
        if (!cJSON_IsArray(prims)) why = format("mesh %d: primitives is %s", i, prims ? "not an array" : "missing");
    }
    const cJSON *mats = cJSON_GetObjectItemCaseSensitive(root, "materials");
    n = cJSON_IsArray(mats) ? cJSON_GetArraySize(mats) : 0;
    for (int i = 0; i < n && why.empty(); i++) {
        const cJSON *mat = cJSON_GetArrayItem(mats, i);
        if (!cJSON_IsObject(mat)) {
            why = format("material %d is not an object", i);
            break;
        }
        const cJSON *pbr = cJSON_GetObjectItemCaseSensitive(mat, "pbrMetallicRoughness");
        if (pbr && !cJSON_IsObject(pbr)) {
            why = format("material %d: pbrMetallicRoughness is not an object", i);
            break;
        }
        for (const char *k : {"baseColorTexture", "metallicRoughnessTexture"})
            if (why.empty() && pbr) why = texture_info(pbr, k, i, "pbrMetallicRoughness.", warn);
        for (const char *k : {"normalTexture", "occlusionTexture", "emissiveTexture"})
            if (why.empty()) why = texture_info(mat, k, i, "", warn);
    }
    cJSON_Delete(root);
    return why;
}

// tinygltf 2.7 (Debian's, built without its own Draco support) refuses a primitive whose indices
// accessor has no bufferView — which is how KHR_draco_mesh_compression declares Draco indices.  So
// before parsing, each Draco primitive's "indices" moves into its extension object as
// "prw_indices" (read_draco takes it from there).  Returns false when nothing had to change.
bool draco_rewrite_json(const char *text, size_t size, std::string *out)
{
    cJSON *root = cJSON_ParseWithLength(text, size);
    if (!root) return false;
    bool changed = false;
    const cJSON *meshes = cJSON_GetObjectItemCaseSensitive(root, "meshes");
    if (!cJSON_IsArray(meshes)) meshes = nullptr;
    const cJSON *mesh;
    cJSON_ArrayForEach(mesh, meshes)
    {
        const cJSON *prims = cJSON_GetObjectItemCaseSensitive(mesh, "primitives");
        if (!cJSON_IsArray(prims)) prims = nullptr;
        cJSON *prim;
        cJSON_ArrayForEach(prim, prims)
        {
            cJSON *ext = cJSON_GetObjectItemCaseSensitive(prim, "extensions");
            cJSON *dx = cJSON_IsObject(ext) ? cJSON_GetObjectItemCaseSensitive(ext, "KHR_draco_mesh_compression") : nullptr;
            if (!cJSON_IsObject(dx) || !cJSON_GetObjectItemCaseSensitive(prim, "indices")) continue;
            cJSON_DeleteItemFromObjectCaseSensitive(dx, "prw_indices");
            cJSON_AddItemToObject(dx, "prw_indices", cJSON_DetachItemFromObjectCaseSensitive(prim, "indices"));
            changed = true;
        }
    }
    if (changed) {
        char *t = cJSON_PrintUnformatted(root);
        if (t) *out = t;
        else changed = false;
        cJSON_free(t);
    }
    cJSON_Delete(root);
    return changed;
}

// The same for a GLB container: a new container with the rewritten JSON chunk and the other chunks
// as they were.  False when the container is not well-formed (tinygltf then says why) or unchanged.
bool draco_rewrite_glb(const std::string &d, std::string *out)
{
    const unsigned char *p = (const unsigned char *)d.data();
    if (d.size() < 20) return false;
    uint32_t jlen = le32(p + 12);
    if (le32(p + 16) != 0x4E4F534Au || jlen > d.size() - 20) return false;
    std::string json;
    if (!draco_rewrite_json(d.data() + 20, jlen, &json)) return false;
    while (json.size() % 4) json += ' ';
    size_t rest = 20 + (size_t)jlen;
    size_t total = 20 + json.size() + (d.size() - rest);
    if (total > 0xffffffffu) return false;
    out->clear();
    out->reserve(total);
    unsigned char h[20];
    memcpy(h, p, 8);
    uint32_t w[3] = {(uint32_t)total, (uint32_t)json.size(), 0x4E4F534Au};
    for (int i = 0; i < 3; i++)
        for (int b = 0; b < 4; b++) h[8 + 4 * i + b] = (unsigned char)(w[i] >> (8 * b));
    out->append((const char *)h, 20);
    out->append(json);
    out->append(d, rest, std::string::npos);
    return true;
}

// After tinygltf refused a .gltf: is it a glTF 1.0 file (asset.version 1.x, or dictionaries where
// 2.0 has arrays)?  Then that is the message a user needs, not tinygltf's.
std::string diagnose_v1(const char *path)
{
    char *text = nullptr;
    size_t size = 0;
    prw_error e;
    if (!prw_read_file(path, &text, &size, &e)) return "";
    cJSON *root = cJSON_ParseWithLength(text, size);
    free(text);
    if (!root) return "";
    std::string r;
    const cJSON *asset = cJSON_GetObjectItemCaseSensitive(root, "asset");
    const cJSON *ver = cJSON_IsObject(asset) ? cJSON_GetObjectItemCaseSensitive(asset, "version") : nullptr;
    if (cJSON_IsString(ver) && ver->valuestring[0] == '1')
        r = "glTF 1.0 (asset.version \"" + one_line(ver->valuestring, 20) + "\") is not supported; convert to 2.0";
    else if (cJSON_IsNumber(ver) && ver->valuedouble >= 1 && ver->valuedouble < 2)
        r = format("glTF 1.0 (asset.version %g) is not supported; convert to 2.0", ver->valuedouble);
    else if (cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, "meshes")) ||
             cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, "accessors")))
        r = "glTF 1.0 (objects keyed by id instead of arrays) is not supported; convert to 2.0";
    cJSON_Delete(root);
    return r;
}
} // namespace prw_gltf
