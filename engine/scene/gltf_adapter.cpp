// gltf_adapter.cpp — glTF 2.0 (.gltf / .glb) import through tinygltf (Debian's libtinygltf).
//
// The glTF import of prw_scene (C++, with gltf_container.cpp: the raw file's checks and rewrites,
// and gltf_draco.cpp).  prw_scene_import_gltf is extern "C"; every exception stops at
// that boundary and becomes a one-line prw_error.  Import is all-or-nothing (rolled back on error).
//
// Conventions (see manifest.md, "glTF import"):
//  - glTF 2.x only (1.0 refused by name); a file that requires an extension not in kImplemented is
//    refused naming it; other unknown extensions in extensionsUsed get one warning each;
//  - nodes: TRS as given; a `matrix` is decomposed into T, R, S assuming no shear (shear -> error);
//  - each primitive -> one prw_mesh, each glTF mesh -> one prw_mesh_group; TRIANGLES, strips and
//    fans (converted to lists with glTF's winding); lines and points are skipped with one warning,
//    or refused when the file has no triangles at all; KHR_draco_mesh_compression via gltf_draco;
//  - every accessor is bounds-checked against its bufferView, every bufferView against its buffer;
//    Draco streams are checked against what their header claims before libdraco allocates;
//  - warnings go into the scene (prw_scene_add_warning), never to a stream;
//  - emission [cd/m^2] = emissiveFactor x KHR_materials_emissive_strength (glTF value 1 = 1 cd/m^2);
//  - KHR_lights_punctual: point/spot intensity in cd, directional in lux (as the extension states);
//  - textures become RGBA8; baseColor and emissive are sRGB, the others linear; an image used both
//    ways is stored twice.  Samplers (wrap/filter) are ignored; uv sets 0 and 1 are imported;
//  - stored for the renderers: alphaMode/alphaCutoff, KHR_texture_transform per texture slot,
//    KHR_materials_clearcoat; malformed data of these extensions is ignored with a warning;
//  - orthographic cameras, skins, morph targets and animations are ignored.
#include "scene_internal.h"
#include "gltf_container.h"
#include "gltf_draco.h"

#include <cJSON.h>
#include <stb/stb_image.h>
#include <tiny_gltf.h>

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using prw_gltf::diagnose_v1;
using prw_gltf::draco_rewrite_glb;
using prw_gltf::draco_rewrite_json;
using prw_gltf::format;
using prw_gltf::glb_layout;
using prw_gltf::glb_version;
using prw_gltf::image_views;
using prw_gltf::le32;
using prw_gltf::one_line;

struct ImportError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

const size_t kMaxElements = size_t(1) << 28; // per accessor, far above any sane asset
// An accessor without a bufferView is all zeros and claims no bytes: its count is capped instead.
const size_t kMaxZeroElements = size_t(1) << 20;
// A Draco stream may claim at most this many faces or points per compressed byte (real streams
// hold a few; the cap keeps a tiny stream from making libdraco allocate gigabytes).
const uint64_t kDracoPerByte = 1024;
const uint32_t kMaxWarnings = 32; // per import; then one "N more" line
const uint64_t kMaxPixels = uint64_t(1) << 27; // per image (16384 x 8192); RGBA8 512 MiB

// Extensions whose data the importer reads (KHR_materials_specular: specularFactor only;
// KHR_mesh_quantization: the accessor reader takes every integer component type).
const char *const kImplemented[] = {
    "KHR_lights_punctual",        "KHR_materials_emissive_strength", "KHR_materials_specular",
    "KHR_texture_transform",      "KHR_materials_clearcoat",         "KHR_draco_mesh_compression",
    "KHR_mesh_quantization",
};

// tinygltf's image decoder, after a size check from the image header: stb_image would otherwise
// allocate whatever width x height a few header bytes claim.
bool guarded_image_loader(tinygltf::Image *image, const int index, std::string *err, std::string *warn, int req_w,
                          int req_h, const unsigned char *bytes, int size, void *)
{
    int w = 0, h = 0, c = 0;
    if (size > 0 && stbi_info_from_memory(bytes, size, &w, &h, &c) &&
        (w > 65536 || h > 65536 || (uint64_t)w * (uint64_t)h > kMaxPixels)) {
        if (err)
            *err += format("image %d: %d x %d pixels is too large (at most %llu pixels)\n", index, w, h,
                           (unsigned long long)kMaxPixels);
        return false;
    }
    return tinygltf::LoadImageData(image, index, err, warn, req_w, req_h, bytes, size, nullptr);
}

bool implemented(const std::string &ext)
{
    for (const char *k : kImplemented)
        if (ext == k) return true;
    return false;
}

const char *mode_name(int mode)
{
    switch (mode) {
    case TINYGLTF_MODE_POINTS: return "POINTS";
    case TINYGLTF_MODE_LINE: return "LINES";
    case TINYGLTF_MODE_LINE_LOOP: return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP: return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLES: return "TRIANGLES";
    case TINYGLTF_MODE_TRIANGLE_STRIP: return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN: return "TRIANGLE_FAN";
    }
    return nullptr;
}

// Malformed data of an optional extension: the importer ignores that extension with a warning.
struct Malformed : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Importer {
    prw_scene *s;
    std::string file; // for messages
    const tinygltf::Model &m;

    std::map<std::pair<int, bool>, int> textures; // (image, srgb) -> scene texture
    std::vector<int> materials;                   // glTF material -> scene material
    int default_material = -1;
    std::vector<int> groups; // glTF mesh -> scene group
    uint32_t warnings = 0, warnings_dropped = 0;
    uint64_t triangles = 0;
    struct Skip {
        bool lines_or_points; // else: a strip/fan/list that yields no triangle
        std::string mode;     // "LINES"
        std::string place;    // "mesh 'x', primitive 2"
    };
    std::vector<Skip> skipped;

    Importer(prw_scene *scene, const std::string &path, const tinygltf::Model &model)
        : s(scene), file(path), m(model)
    {
    }

    [[noreturn]] void fail(const std::string &msg) const { throw ImportError(file + ": " + msg); }

    void warn(prw_warning_kind kind, const std::string &msg)
    {
        if (warnings >= kMaxWarnings) {
            warnings_dropped++;
            return;
        }
        warnings++;
        prw_scene_add_warning(s, kind, "%s: %s", file.c_str(), msg.c_str());
    }

    void finish_warnings()
    {
        if (warnings_dropped)
            prw_scene_add_warning(s, PRW_WARN_OTHER, "%s: %u more warnings", file.c_str(), warnings_dropped);
    }

    // ---- version and extensions ----
    void check_asset()
    {
        const std::string &v = m.asset.version;
        if (v.empty()) {
            warn(PRW_WARN_OTHER, "asset.version is missing; read as glTF 2.0");
        } else if (v[0] == '1' && (v.size() == 1 || v[1] == '.')) {
            fail("glTF 1.0 (asset.version \"" + one_line(v, 20) + "\") is not supported; convert to 2.0");
        } else if (!(v[0] == '2' && (v.size() == 1 || v[1] == '.'))) {
            fail("glTF version \"" + one_line(v, 20) + "\" (asset.version) is not supported; prw reads 2.x");
        }
        const std::string &mv = m.asset.minVersion;
        if (!mv.empty() && !(mv == "2.0" || mv == "2"))
            fail("asset.minVersion \"" + one_line(mv, 20) + "\" is newer than the glTF 2.0 this reader implements");
    }

    void check_extensions()
    {
        std::string missing;
        std::set<std::string> seen;
        for (const std::string &x : m.extensionsRequired)
            if (!implemented(x) && seen.insert(x).second) missing += (missing.empty() ? "" : ", ") + one_line(x, 80);
        if (!missing.empty())
            fail(format("the file requires %s %s, which prw does not implement (supported: ",
                        seen.size() > 1 ? "extensions" : "extension", missing.c_str()) +
                 supported_list() + ")");
        for (const std::string &x : m.extensionsUsed)
            if (!implemented(x) && seen.insert(x).second)
                warn(PRW_WARN_EXTENSION, "extension " + one_line(x, 80) + " is not supported; its data is ignored");
    }

    static std::string supported_list()
    {
        std::string r;
        for (const char *k : kImplemented) r += (r.empty() ? "" : ", ") + std::string(k);
        return r;
    }

    // What the importer does not draw at all: said once each.
    void note_ignored()
    {
        if (!m.animations.empty()) warn(PRW_WARN_SKIPPED, format("%zu animations are ignored", m.animations.size()));
        if (!m.skins.empty()) warn(PRW_WARN_SKIPPED, format("%zu skins are ignored (meshes drawn in bind pose)", m.skins.size()));
        size_t morph = 0, ortho = 0;
        for (const tinygltf::Mesh &gm : m.meshes)
            for (const tinygltf::Primitive &p : gm.primitives) morph += p.targets.empty() ? 0 : 1;
        for (const tinygltf::Camera &c : m.cameras) ortho += c.type == "orthographic" ? 1 : 0;
        if (morph) warn(PRW_WARN_SKIPPED, format("morph targets of %zu primitives are ignored (base shape drawn)", morph));
        if (ortho) warn(PRW_WARN_SKIPPED, format("%zu orthographic cameras are ignored", ortho));
    }

    // ---- accessors ----
    struct View {
        const unsigned char *base = nullptr; // nullptr: all zeros (accessor without bufferView)
        size_t stride = 0, count = 0;
        int comp_type = 0, ncomp = 0, comp_size = 0;
        bool normalized = false;
    };

    View view(int index, const std::string &what, int want_ncomp) const
    {
        if (index < 0 || (size_t)index >= m.accessors.size())
            fail(format("%s: accessor %d does not exist (%zu accessors)", what.c_str(), index, m.accessors.size()));
        const tinygltf::Accessor &a = m.accessors[(size_t)index];
        std::string label = format("accessor %d (%s)", index, what.c_str());
        if (a.sparse.isSparse) fail(label + ": sparse accessors are not supported");
        View v;
        v.comp_type = a.componentType;
        v.comp_size = tinygltf::GetComponentSizeInBytes((uint32_t)a.componentType);
        v.ncomp = tinygltf::GetNumComponentsInType((uint32_t)a.type);
        v.normalized = a.normalized;
        v.count = a.count;
        if (v.comp_size <= 0 || v.ncomp <= 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE)
            fail(label + format(": invalid componentType %d / type %d", a.componentType, a.type));
        if (v.ncomp != want_ncomp) fail(label + format(": has %d components, expected %d", v.ncomp, want_ncomp));
        if (a.count == 0) fail(label + ": count is 0");
        if (a.count > kMaxElements) fail(label + format(": count %zu is too large", a.count));
        size_t elem = (size_t)v.comp_size * (size_t)v.ncomp;
        if (a.bufferView < 0) { // glTF: zeros
            if (a.count > kMaxZeroElements)
                fail(label + format(": has no bufferView (all zeros) and count %zu; more than %zu such elements are refused",
                                    a.count, kMaxZeroElements));
            v.stride = elem;
            return v;
        }
        if ((size_t)a.bufferView >= m.bufferViews.size())
            fail(label + format(": bufferView %d does not exist (%zu bufferViews)", a.bufferView, m.bufferViews.size()));
        const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
        if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
            fail(format("bufferView %d: buffer %d does not exist (%zu buffers)", a.bufferView, bv.buffer, m.buffers.size()));
        const tinygltf::Buffer &buf = m.buffers[(size_t)bv.buffer];
        if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
            fail(format("bufferView %d: byte range %zu..%zu exceeds buffer %d length %zu", a.bufferView, bv.byteOffset,
                        bv.byteOffset + bv.byteLength, bv.buffer, buf.data.size()));
        v.stride = bv.byteStride ? bv.byteStride : elem;
        if (v.stride < elem)
            fail(label + format(": bufferView %d byteStride %zu is smaller than the element size %zu", a.bufferView,
                                bv.byteStride, elem));
        // last byte read: byteOffset + stride * (count - 1) + elem  (count <= 2^28, stride < 2^32: no overflow)
        if (v.stride > 0xffffffffu) fail(label + ": byteStride is too large");
        size_t end = a.byteOffset + v.stride * (a.count - 1) + elem;
        if (a.byteOffset > bv.byteLength || end > bv.byteLength || end < a.byteOffset)
            fail(label + format(": byte range %zu..%zu exceeds bufferView %d length %zu", a.byteOffset, end,
                                a.bufferView, bv.byteLength));
        v.base = buf.data.data() + bv.byteOffset + a.byteOffset;
        return v;
    }

    static double component(const unsigned char *p, int type, bool normalized)
    {
        switch (type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float f;
            memcpy(&f, p, 4);
            return f;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            double x = (signed char)p[0];
            return normalized ? std::fmax(x / 127.0, -1.0) : x;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t u;
            memcpy(&u, p, 2);
            return normalized ? u / 65535.0 : u;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t x;
            memcpy(&x, p, 2);
            return normalized ? std::fmax(x / 32767.0, -1.0) : x;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t u;
            memcpy(&u, p, 4);
            return u;
        }
        case TINYGLTF_COMPONENT_TYPE_INT: {
            int32_t x;
            memcpy(&x, p, 4);
            return x;
        }
        }
        return 0;
    }

    std::vector<float> read_floats(const View &v) const
    {
        std::vector<float> out(v.count * (size_t)v.ncomp, 0.0f);
        if (!v.base) return out;
        for (size_t i = 0; i < v.count; i++)
            for (int c = 0; c < v.ncomp; c++)
                out[i * (size_t)v.ncomp + (size_t)c] =
                    (float)component(v.base + i * v.stride + (size_t)c * (size_t)v.comp_size, v.comp_type, v.normalized);
        return out;
    }

    // ---- textures ----
    int texture(int index, bool srgb, const std::string &what)
    {
        if (index < 0) return -1;
        if ((size_t)index >= m.textures.size())
            fail(format("%s: texture %d does not exist (%zu textures)", what.c_str(), index, m.textures.size()));
        int src = m.textures[(size_t)index].source;
        if (src < 0 || (size_t)src >= m.images.size())
            fail(format("texture %d: image %d does not exist (%zu images)", index, src, m.images.size()));
        auto key = std::make_pair(src, srgb);
        auto it = textures.find(key);
        if (it != textures.end()) return it->second;

        const tinygltf::Image &img = m.images[(size_t)src];
        std::string label = format("image %d ('%s')", src, one_line(img.name.empty() ? img.uri : img.name, 60).c_str());
        int comp = img.component, bytes = img.bits == 16 ? 2 : 1;
        if (img.width <= 0 || img.height <= 0 || img.width > 65536 || img.height > 65536 || comp < 1 || comp > 4 ||
            (img.bits != 8 && img.bits != 16))
            fail(label + format(": not decoded or unsupported (%dx%d, %d channels, %d bits)", img.width, img.height,
                                comp, img.bits));
        size_t npix = (size_t)img.width * (size_t)img.height;
        if (img.image.size() != npix * (size_t)comp * (size_t)bytes)
            fail(label + format(": pixel data has %zu bytes, expected %zu", img.image.size(), npix * comp * bytes));
        std::vector<uint8_t> rgba(npix * 4);
        const unsigned char *p = img.image.data();
        for (size_t i = 0; i < npix; i++) {
            unsigned ch[4];
            for (int c = 0; c < comp; c++) {
                const unsigned char *q = p + (i * (size_t)comp + (size_t)c) * (size_t)bytes;
                if (bytes == 2) {
                    uint16_t u;
                    memcpy(&u, q, 2);
                    ch[c] = (u * 255u + 32767u) / 65535u;
                } else {
                    ch[c] = q[0];
                }
            }
            uint8_t *o = &rgba[i * 4];
            switch (comp) { // grey, grey+alpha, rgb, rgba
            case 1: o[0] = o[1] = o[2] = (uint8_t)ch[0], o[3] = 255; break;
            case 2: o[0] = o[1] = o[2] = (uint8_t)ch[0], o[3] = (uint8_t)ch[1]; break;
            case 3: o[0] = (uint8_t)ch[0], o[1] = (uint8_t)ch[1], o[2] = (uint8_t)ch[2], o[3] = 255; break;
            default: o[0] = (uint8_t)ch[0], o[1] = (uint8_t)ch[1], o[2] = (uint8_t)ch[2], o[3] = (uint8_t)ch[3];
            }
        }
        prw_texture t;
        memset(&t, 0, sizeof t);
        std::string name = img.name.empty() ? img.uri.substr(0, 200) : img.name;
        if (name.empty() || name.compare(0, 5, "data:") == 0) name = format("image%d", src);
        prw_copy_name(t.name, one_line(name, PRW_NAME_MAX - 1).c_str());
        t.width = img.width;
        t.height = img.height;
        t.rgba8 = rgba.data();
        t.srgb = srgb;
        int ti = prw_scene_add_texture(s, &t);
        if (ti < 0) fail(label + ": cannot add texture");
        textures[key] = ti;
        return ti;
    }

    // ---- materials ----
    static bool finite_all(const std::vector<double> &v)
    {
        for (double x : v)
            if (!std::isfinite(x)) return false;
        return true;
    }

    // ---- texture slots: uv set and KHR_texture_transform ----
    int uv_set(double tc, const std::string &what)
    {
        if (tc == 0 || tc == 1) return (int)tc;
        warn(PRW_WARN_OTHER, what + format(": texCoord %g is not imported (uv sets 0 and 1 are); set 0 is used", tc));
        return 0;
    }

    static float finite_number(const tinygltf::Value &v, const char *key)
    {
        if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()) || std::fabs(v.GetNumberAsDouble()) > 1e9)
            throw Malformed(std::string(key) + " must be a finite number");
        return (float)v.GetNumberAsDouble();
    }

    // Fills t from a KHR_texture_transform object (xf may be null: nothing to do).  Malformed: a warning,
    // t unchanged.
    void tex_transform(const tinygltf::Value *xf, const std::string &what, prw_tex_transform *t)
    {
        if (!xf) return;
        prw_tex_transform r = *t;
        try {
            const tinygltf::Value &v = *xf;
            if (!v.IsObject()) throw Malformed("is not an object");
            for (const char *key : {"offset", "scale"}) {
                if (!v.Has(key)) continue;
                const tinygltf::Value &a = v.Get(key);
                if (!a.IsArray() || a.ArrayLen() != 2) throw Malformed(std::string(key) + " must be 2 numbers");
                float *out = key[0] == 'o' ? r.offset : r.scale;
                for (int k = 0; k < 2; k++) out[k] = finite_number(a.Get(k), key);
            }
            if (v.Has("rotation")) r.rotation = finite_number(v.Get("rotation"), "rotation");
            if (v.Has("texCoord")) {
                const tinygltf::Value &tc = v.Get("texCoord");
                if (!tc.IsNumber() || tc.GetNumberAsDouble() < 0 || tc.GetNumberAsDouble() != std::floor(tc.GetNumberAsDouble()))
                    throw Malformed("texCoord must be an integer >= 0");
                r.tex_coord = uv_set(tc.GetNumberAsDouble(), what);
            }
        } catch (const Malformed &x) {
            warn(PRW_WARN_OTHER, what + ": KHR_texture_transform ignored: " + x.what());
            return;
        }
        *t = r;
    }

    static const tinygltf::Value *xf_of(const tinygltf::ExtensionMap &ext)
    {
        auto it = ext.find("KHR_texture_transform");
        return it == ext.end() ? nullptr : &it->second;
    }

    // A texture slot: the texture (index -1: none), its uv set and transform.
    int slot(int index, double tex_coord, const tinygltf::Value *xf, bool srgb, const std::string &what,
             prw_material *pm, prw_tex_slot sl)
    {
        int t = texture(index, srgb, what);
        if (t < 0) return -1;
        pm->tex_xf[sl].tex_coord = uv_set(tex_coord, what);
        tex_transform(xf, what, &pm->tex_xf[sl]);
        return t;
    }

    // KHR_materials_clearcoat.  Malformed values or texture references: a warning, no coat.
    void clearcoat(const tinygltf::Material &g, const std::string &what, prw_material *pm)
    {
        auto it = g.extensions.find("KHR_materials_clearcoat");
        if (it == g.extensions.end()) return;
        const tinygltf::Value &v = it->second;
        struct Tex {
            int index = -1;
            double tex_coord = 0, scale = 1;
            const tinygltf::Value *xf = nullptr;
        } tex[3];
        const char *tex_keys[3] = {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"};
        float factor = 0, rough = 0;
        try {
            if (!v.IsObject()) throw Malformed("is not an object");
            auto unit = [&](const char *key, float *out) {
                if (!v.Has(key)) return;
                float x = finite_number(v.Get(key), key);
                if (!(x >= 0 && x <= 1)) throw Malformed(std::string(key) + " must be in [0, 1]");
                *out = x;
            };
            unit("clearcoatFactor", &factor);
            unit("clearcoatRoughnessFactor", &rough);
            for (int k = 0; k < 3; k++) {
                if (!v.Has(tex_keys[k])) continue;
                const tinygltf::Value &t = v.Get(tex_keys[k]);
                std::string key = tex_keys[k];
                if (!t.IsObject() || !t.Has("index") || !t.Get("index").IsNumber())
                    throw Malformed(key + " must be an object with an index");
                double i = t.Get("index").GetNumberAsDouble();
                if (!(i >= 0 && i < (double)m.textures.size()) || i != std::floor(i))
                    throw Malformed(key + format(": texture %g does not exist (%zu textures)", i, m.textures.size()));
                tex[k].index = (int)i;
                if (t.Has("texCoord")) {
                    double tc = t.Get("texCoord").IsNumber() ? t.Get("texCoord").GetNumberAsDouble() : -1;
                    if (!(tc >= 0) || tc != std::floor(tc)) throw Malformed(key + ": texCoord must be an integer >= 0");
                    tex[k].tex_coord = tc;
                }
                if (k == 2 && t.Has("scale")) tex[k].scale = finite_number(t.Get("scale"), "clearcoatNormalTexture.scale");
                if (t.Has("extensions") && t.Get("extensions").IsObject() && t.Get("extensions").Has("KHR_texture_transform"))
                    tex[k].xf = &t.Get("extensions").Get("KHR_texture_transform");
            }
        } catch (const Malformed &x) {
            warn(PRW_WARN_OTHER, what + ": KHR_materials_clearcoat ignored: " + x.what());
            return;
        }
        pm->clearcoat = factor;
        pm->clearcoat_roughness = rough;
        pm->clearcoat_normal_scale = (float)tex[2].scale;
        std::string w = what + " KHR_materials_clearcoat.";
        pm->clearcoat_tex = slot(tex[0].index, tex[0].tex_coord, tex[0].xf, false, w + tex_keys[0], pm, PRW_TEX_CLEARCOAT);
        pm->clearcoat_roughness_tex =
            slot(tex[1].index, tex[1].tex_coord, tex[1].xf, false, w + tex_keys[1], pm, PRW_TEX_CLEARCOAT_ROUGHNESS);
        pm->clearcoat_normal_tex =
            slot(tex[2].index, tex[2].tex_coord, tex[2].xf, false, w + tex_keys[2], pm, PRW_TEX_CLEARCOAT_NORMAL);
    }

    // extras.prw_btf = {"file": "<PRWBTFC1 file, relative to the glTF file>", "texel_m": metres per texel}:
    // the BTF material kind (engine/scene/manifest.md).  Malformed: an error (the material would look wrong).
    void btf(const tinygltf::Material &g, const std::string &what, prw_material *pm)
    {
        if (!g.extras.IsObject() || !g.extras.Has("prw_btf")) return;
        const tinygltf::Value &b = g.extras.Get("prw_btf");
        std::string w = what + ": extras.prw_btf";
        if (!b.IsObject()) fail(w + ": must be an object {\"file\": ..., \"texel_m\": ...}");
        for (const std::string &k : b.Keys())
            if (k != "file" && k != "texel_m" && k != "scale_rule") fail(w + ": unknown key '" + one_line(k, 40) + "'");
        if (b.Has("scale_rule") && !b.Get("scale_rule").IsBool()) fail(w + ".scale_rule: must be true or false");
        if (!b.Has("file") || !b.Get("file").IsString() || b.Get("file").Get<std::string>().empty())
            fail(w + ".file: must be a non-empty string");
        if (!b.Has("texel_m") || !b.Get("texel_m").IsNumber()) fail(w + ".texel_m: must be a number (metres per texel)");
        double t = b.Get("texel_m").GetNumberAsDouble();
        if (!(std::isfinite(t) && t > 0 && t <= 1)) fail(w + ".texel_m: must be a finite number > 0 and <= 1");
        std::string f = b.Get("file").Get<std::string>();
        size_t slash = file.find_last_of('/');
        std::string path = f[0] == '/' || slash == std::string::npos ? f : file.substr(0, slash + 1) + f;
        if (path.size() >= sizeof pm->btf_file) fail(w + ".file: path too long");
        prw_error fe;
        if (!prw_scene_btf_check(path.c_str(), &pm->btf_hash, &fe)) fail(w + ".file: " + fe.msg);
        std::snprintf(pm->btf_file, sizeof pm->btf_file, "%s", path.c_str());
        pm->kind = PRW_MATERIAL_BTF;
        pm->btf_texel_m = t;
        pm->btf_scale_rule = b.Has("scale_rule") && b.Get("scale_rule").Get<bool>();
    }

    void import_materials()
    {
        for (size_t i = 0; i < m.materials.size(); i++) {
            const tinygltf::Material &g = m.materials[i];
            std::string nm = one_line(g.name.empty() ? format("material%zu", i) : g.name, PRW_NAME_MAX - 1);
            std::string what = format("material %zu ('%s')", i, nm.c_str());
            const tinygltf::PbrMetallicRoughness &pbr = g.pbrMetallicRoughness;
            prw_material pm = prw_material_default();
            prw_copy_name(pm.name, nm.c_str());
            if (pbr.baseColorFactor.size() != 4 || !finite_all(pbr.baseColorFactor))
                fail(what + ": baseColorFactor must be 4 finite numbers");
            for (int c = 0; c < 4; c++) pm.base_color[c] = (float)std::fmin(std::fmax(pbr.baseColorFactor[(size_t)c], 0.0), 1.0);
            if (!std::isfinite(pbr.metallicFactor) || !std::isfinite(pbr.roughnessFactor) ||
                !std::isfinite(g.normalTexture.scale))
                fail(what + ": metallicFactor, roughnessFactor and normalTexture.scale must be finite");
            pm.metallic = (float)std::fmin(std::fmax(pbr.metallicFactor, 0.0), 1.0);
            pm.roughness = (float)std::fmin(std::fmax(pbr.roughnessFactor, 0.0), 1.0);
            pm.base_color_tex = slot(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                     xf_of(pbr.baseColorTexture.extensions), true, what + " baseColorTexture", &pm,
                                     PRW_TEX_BASE_COLOR);
            pm.metal_rough_tex = slot(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                                      xf_of(pbr.metallicRoughnessTexture.extensions), false,
                                      what + " metallicRoughnessTexture", &pm, PRW_TEX_METAL_ROUGH);
            pm.normal_tex = slot(g.normalTexture.index, g.normalTexture.texCoord, xf_of(g.normalTexture.extensions), false,
                                 what + " normalTexture", &pm, PRW_TEX_NORMAL);
            pm.normal_scale = (float)g.normalTexture.scale;
            // emission: glTF emissive value 1 == 1 cd/m^2, times KHR_materials_emissive_strength
            double strength = 1.0;
            auto ext = g.extensions.find("KHR_materials_emissive_strength");
            if (ext != g.extensions.end() && ext->second.IsObject() && ext->second.Has("emissiveStrength")) {
                const tinygltf::Value &v = ext->second.Get("emissiveStrength");
                if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()) || v.GetNumberAsDouble() < 0)
                    fail(what + ": KHR_materials_emissive_strength.emissiveStrength must be a finite number >= 0");
                strength = v.GetNumberAsDouble();
            }
            std::vector<double> ef = g.emissiveFactor.empty() ? std::vector<double>{0, 0, 0} : g.emissiveFactor;
            if (ef.size() != 3 || !finite_all(ef)) fail(what + ": emissiveFactor must be 3 finite numbers");
            for (int c = 0; c < 3; c++) {
                double e = std::fmax(ef[(size_t)c], 0.0) * strength;
                if (!std::isfinite(e) || e > 1e12) fail(what + ": emission is out of range");
                pm.emission[c] = (float)e;
            }
            pm.emissive_tex = slot(g.emissiveTexture.index, g.emissiveTexture.texCoord, xf_of(g.emissiveTexture.extensions),
                                   true, what + " emissiveTexture", &pm, PRW_TEX_EMISSIVE);
            // KHR_materials_specular: specularFactor scales the dielectric F0 (the colour term is not supported)
            auto spx = g.extensions.find("KHR_materials_specular");
            if (spx != g.extensions.end() && spx->second.IsObject() && spx->second.Has("specularFactor")) {
                const tinygltf::Value &v = spx->second.Get("specularFactor");
                if (!v.IsNumber() || !(v.GetNumberAsDouble() >= 0.0 && v.GetNumberAsDouble() <= 1.0))
                    fail(what + ": KHR_materials_specular.specularFactor must be a number in [0, 1]");
                pm.specular = (float)v.GetNumberAsDouble();
            }
            pm.double_sided = g.doubleSided;
            if (g.alphaMode.empty() || g.alphaMode == "OPAQUE") pm.alpha_mode = PRW_ALPHA_OPAQUE;
            else if (g.alphaMode == "MASK") pm.alpha_mode = PRW_ALPHA_MASK;
            else if (g.alphaMode == "BLEND") pm.alpha_mode = PRW_ALPHA_BLEND;
            else fail(what + ": alphaMode '" + one_line(g.alphaMode, 40) + "' is not OPAQUE, MASK or BLEND");
            if (!std::isfinite(g.alphaCutoff) || g.alphaCutoff < 0 || g.alphaCutoff > 1e9)
                fail(what + ": alphaCutoff must be a finite number >= 0");
            pm.alpha_cutoff = (float)g.alphaCutoff;
            clearcoat(g, what, &pm);
            btf(g, what, &pm);
            materials.push_back(prw_scene_add_material(s, &pm));
        }
    }

    int material(int index, const std::string &what)
    {
        if (index < 0) {
            if (default_material < 0) {
                prw_material d = prw_material_default();
                default_material = prw_scene_add_material(s, &d);
            }
            return default_material;
        }
        if ((size_t)index >= materials.size())
            fail(format("%s: material %d does not exist (%zu materials)", what.c_str(), index, materials.size()));
        return materials[(size_t)index];
    }

    // ---- meshes ----
    struct Prim {
        size_t n = 0; // vertices
        std::vector<float> pos, nrm, uv, uv1, tan;
        std::vector<uint32_t> idx; // as the primitive's mode orders them
    };

    static int attr(const tinygltf::Primitive &p, const char *key)
    {
        auto it = p.attributes.find(key);
        return it == p.attributes.end() ? -2 : it->second;
    }

    // Vertex attributes of the semantics prw uses, except those `draco` provides (names in `skip`).
    void read_attributes(const tinygltf::Primitive &p, const std::string &mwhat, const std::set<std::string> &skip,
                         Prim *out)
    {
        struct {
            const char *sem;
            int ncomp;
            std::vector<float> *dst;
        } sems[] = {{"NORMAL", 3, &out->nrm}, {"TEXCOORD_0", 2, &out->uv}, {"TEXCOORD_1", 2, &out->uv1},
                    {"TANGENT", 4, &out->tan}};
        if (!skip.count("POSITION")) {
            int ipos = attr(p, "POSITION");
            View vp = view(ipos, mwhat + " POSITION", 3);
            if (out->n && vp.count != out->n)
                fail(format("accessor %d (%s POSITION): count %zu differs from the Draco stream's %zu points", ipos,
                            mwhat.c_str(), vp.count, out->n));
            out->n = vp.count;
            out->pos = read_floats(vp);
        }
        for (auto &x : sems) {
            int idx = attr(p, x.sem);
            if (idx == -2 || skip.count(x.sem)) continue;
            View v = view(idx, mwhat + " " + x.sem, x.ncomp);
            if (v.count != out->n)
                fail(format("accessor %d (%s %s): count %zu differs from POSITION count %zu", idx, mwhat.c_str(), x.sem,
                            v.count, out->n));
            *x.dst = read_floats(v);
        }
    }

    void read_indices(const tinygltf::Primitive &p, const std::string &mwhat, Prim *out)
    {
        if (p.indices == -1) {
            out->idx.resize(out->n);
            for (size_t i = 0; i < out->n; i++) out->idx[i] = (uint32_t)i;
            return;
        }
        View vi = view(p.indices, mwhat + " indices", 1);
        if (vi.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && vi.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            vi.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(format("accessor %d (%s indices): componentType %d is not an unsigned integer type", p.indices,
                        mwhat.c_str(), vi.comp_type));
        out->idx.resize(vi.count, 0);
        if (vi.base)
            for (size_t i = 0; i < vi.count; i++)
                out->idx[i] = (uint32_t)component(vi.base + i * vi.stride, vi.comp_type, false);
    }

    // KHR_draco_mesh_compression: the attributes it names and the faces come from the Draco stream,
    // the others from their accessors.  Counts are checked against the stream's size before decoding.
    void read_draco(const tinygltf::Primitive &p, const tinygltf::Value &ext, const std::string &where,
                    const std::string &mwhat, Prim *out)
    {
        std::string dw = where + ": KHR_draco_mesh_compression";
        if (p.mode != -1 && p.mode != TINYGLTF_MODE_TRIANGLES)
            fail(dw + format(" with primitive mode %s is not supported (Draco streams hold triangle lists)",
                             mode_name(p.mode) ? mode_name(p.mode) : "?"));
        if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Get("bufferView").IsNumber() || !ext.Has("attributes") ||
            !ext.Get("attributes").IsObject())
            fail(dw + ": needs a bufferView index and an attributes object");
        double bvd = ext.Get("bufferView").GetNumberAsDouble();
        if (!(bvd >= 0 && bvd < (double)m.bufferViews.size()) || bvd != std::floor(bvd))
            fail(dw + format(": bufferView %g does not exist (%zu bufferViews)", bvd, m.bufferViews.size()));
        int bvi = (int)bvd;
        const tinygltf::BufferView &bv = m.bufferViews[(size_t)bvi];
        if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
            fail(format("bufferView %d: buffer %d does not exist (%zu buffers)", bvi, bv.buffer, m.buffers.size()));
        const tinygltf::Buffer &buf = m.buffers[(size_t)bv.buffer];
        if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
            fail(format("bufferView %d: byte range %zu..%zu exceeds buffer %d length %zu", bvi, bv.byteOffset,
                        bv.byteOffset + bv.byteLength, bv.buffer, buf.data.size()));
        const uint8_t *data = buf.data.data() + bv.byteOffset;
        size_t len = bv.byteLength;

        prw_gltf::DracoHeader h;
        std::string why = prw_gltf::draco_peek(data, len, &h);
        if (!why.empty()) fail(dw + format(" (bufferView %d): ", bvi) + why);
        uint64_t cap = std::min<uint64_t>(kMaxElements, kDracoPerByte * (uint64_t)len + 1024);
        if (h.faces > cap || h.max_points > 3 * cap)
            fail(dw + format(" (bufferView %d): the stream claims %u faces in %zu bytes (more than %llu are refused)", bvi,
                             h.faces, len, (unsigned long long)cap));
        int ind = p.indices; // moved into the extension before parsing (draco_rewrite_json)
        if (ext.Has("prw_indices")) {
            const tinygltf::Value &iv = ext.Get("prw_indices");
            double d = iv.IsNumber() ? iv.GetNumberAsDouble() : -2;
            ind = d >= 0 && d < (double)m.accessors.size() && d == std::floor(d) ? (int)d : -2;
            if (ind == -2) fail(format("%s indices: accessor %g does not exist (%zu accessors)", mwhat.c_str(), d, m.accessors.size()));
        }
        if (ind != -1) {
            if (ind < 0 || (size_t)ind >= m.accessors.size())
                fail(format("%s indices: accessor %d does not exist (%zu accessors)", mwhat.c_str(), ind, m.accessors.size()));
            size_t ic = m.accessors[(size_t)ind].count;
            if (ic != 3 * (size_t)h.faces)
                fail(format("accessor %d (%s indices): count %zu differs from the Draco stream's %u faces x 3", ind,
                            mwhat.c_str(), ic, h.faces));
        }
        std::unique_ptr<prw_gltf::DracoMesh> dm = prw_gltf::draco_decode(data, len, &why);
        if (!dm) fail(dw + format(" (bufferView %d): ", bvi) + why);
        out->n = dm->points();
        if (out->n == 0 || dm->indices().empty()) fail(dw + format(" (bufferView %d): the stream holds no triangle", bvi));

        const tinygltf::Value &atts = ext.Get("attributes");
        std::set<std::string> from_draco;
        struct {
            const char *sem;
            int ncomp;
            std::vector<float> *dst;
        } sems[] = {{"POSITION", 3, &out->pos}, {"NORMAL", 3, &out->nrm}, {"TEXCOORD_0", 2, &out->uv},
                    {"TEXCOORD_1", 2, &out->uv1}, {"TANGENT", 4, &out->tan}};
        for (auto &x : sems) {
            if (!atts.Has(x.sem)) continue;
            int ai = attr(p, x.sem);
            if (ai == -2) continue; // compressed but not used by the primitive
            const tinygltf::Value &u = atts.Get(x.sem);
            if (!u.IsNumber() || u.GetNumberAsDouble() < 0 || u.GetNumberAsDouble() > 4294967295.0 ||
                u.GetNumberAsDouble() != std::floor(u.GetNumberAsDouble()))
                fail(dw + ": attributes." + x.sem + " must be an attribute id (integer >= 0)");
            if (ai < 0 || (size_t)ai >= m.accessors.size())
                fail(format("%s %s: accessor %d does not exist (%zu accessors)", mwhat.c_str(), x.sem, ai, m.accessors.size()));
            const tinygltf::Accessor &a = m.accessors[(size_t)ai];
            if (tinygltf::GetNumComponentsInType((uint32_t)a.type) != x.ncomp)
                fail(format("accessor %d (%s %s): has %d components, expected %d", ai, mwhat.c_str(), x.sem,
                            tinygltf::GetNumComponentsInType((uint32_t)a.type), x.ncomp));
            if (a.count != out->n)
                fail(format("accessor %d (%s %s): count %zu differs from the Draco stream's %zu points", ai, mwhat.c_str(),
                            x.sem, a.count, out->n));
            why = dm->attribute((uint32_t)u.GetNumberAsDouble(), x.ncomp, x.dst);
            if (!why.empty()) fail(dw + ": " + x.sem + ": " + why);
            from_draco.insert(x.sem);
        }
        if (!from_draco.count("POSITION") && attr(p, "POSITION") == -2) fail(where + ": no POSITION attribute");
        read_attributes(p, mwhat, from_draco, out);
        out->idx = dm->indices();
    }

    // Triangle list from a primitive's index sequence r (TRIANGLES: r itself).  Strips and fans follow
    // glTF 2.0 section 3.7.2.1 (front faces counter-clockwise like TRIANGLES):
    //   strip triangle i = (r[i], r[i + 1 + i % 2], r[i + 2 - i % 2]),  fan triangle i = (r[i + 1], r[i + 2], r[0]).
    // Triangles with a repeated index (strip restarts, stitching) are dropped.
    std::vector<uint32_t> to_list(int mode, std::vector<uint32_t> r, size_t n, const std::string &where) const
    {
        if (mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) return r;
        for (size_t i = 0; i < r.size(); i++)
            if (r[i] >= n)
                fail(where + format(": index %u at position %zu is out of range (vertex count %zu)", r[i], i, n));
        std::vector<uint32_t> t;
        if (r.size() < 3) return t;
        t.reserve(3 * (r.size() - 2));
        for (size_t i = 0; i + 2 < r.size(); i++) {
            uint32_t a, b, c;
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                a = r[i];
                b = r[i + 1 + i % 2];
                c = r[i + 2 - i % 2];
            } else {
                a = r[i + 1];
                b = r[i + 2];
                c = r[0];
            }
            if (a == b || b == c || a == c) continue;
            t.push_back(a);
            t.push_back(b);
            t.push_back(c);
        }
        return t;
    }

    void import_meshes()
    {
        for (size_t mi = 0; mi < m.meshes.size(); mi++) {
            const tinygltf::Mesh &gm = m.meshes[mi];
            std::string nm = one_line(gm.name.empty() ? format("mesh%zu", mi) : gm.name, PRW_NAME_MAX - 1);
            uint32_t first = s->mesh_count;
            for (size_t pi = 0; pi < gm.primitives.size(); pi++) {
                const tinygltf::Primitive &p = gm.primitives[pi];
                std::string where = format("mesh '%s' primitive %zu", nm.c_str(), pi);
                int mode = p.mode == -1 ? TINYGLTF_MODE_TRIANGLES : p.mode;
                const char *mname = mode_name(mode);
                if (!mname) fail(where + format(": mode %d is not a glTF primitive mode (0..6)", p.mode));
                if (mode < TINYGLTF_MODE_TRIANGLES) { // points and lines: not drawn
                    skipped.push_back({true, mname, format("mesh '%s', primitive %zu", nm.c_str(), pi)});
                    continue;
                }
                std::string mwhat = format("mesh '%s'", nm.c_str());
                Prim pr;
                auto dx = p.extensions.find("KHR_draco_mesh_compression");
                if (dx != p.extensions.end()) {
                    read_draco(p, dx->second, where, mwhat, &pr);
                } else {
                    if (attr(p, "POSITION") == -2) fail(where + ": no POSITION attribute");
                    read_attributes(p, mwhat, {}, &pr);
                    read_indices(p, mwhat, &pr);
                    pr.idx = to_list(mode, std::move(pr.idx), pr.n, where);
                }
                if (pr.idx.empty()) {
                    skipped.push_back({false, mname, format("mesh '%s', primitive %zu", nm.c_str(), pi)});
                    continue;
                }
                if (pr.idx.size() > 0xffffffffu) fail(where + ": too many indices");
                prw_mesh pm;
                memset(&pm, 0, sizeof pm);
                prw_copy_name(pm.name, nm.c_str());
                pm.vertex_count = (uint32_t)pr.n;
                pm.index_count = (uint32_t)pr.idx.size();
                pm.positions = pr.pos.data();
                pm.normals = pr.nrm.empty() ? nullptr : pr.nrm.data();
                pm.uvs = pr.uv.empty() ? nullptr : pr.uv.data();
                pm.uvs1 = pr.uv1.empty() ? nullptr : pr.uv1.data();
                pm.tangents = pr.tan.empty() ? nullptr : pr.tan.data();
                pm.indices = pr.idx.data();
                pm.material = material(p.material, where);
                prw_error e;
                if (prw_scene_add_mesh(s, &pm, &e) < 0) { // e: "mesh '<name>': <reason>"
                    const char *reason = strstr(e.msg, "': ");
                    fail(where + ": " + (reason ? reason + 3 : e.msg));
                }
                triangles += pr.idx.size() / 3;
            }
            int g = prw_scene_add_group(s, nm.c_str(), first, s->mesh_count - first);
            if (g < 0) fail(format("mesh '%s': cannot add group", nm.c_str()));
            groups.push_back(g);
        }
        if (skipped.empty()) return;
        std::string list;
        for (size_t i = 0; i < skipped.size() && i < 4; i++)
            list += (i ? ", " : "") + skipped[i].mode + (skipped[i].lines_or_points ? "" : " without a triangle") + " (" +
                    skipped[i].place + ")";
        if (skipped.size() > 4) list += format(" and %zu more", skipped.size() - 4);
        if (triangles == 0) {
            std::string more = skipped.size() > 1 ? format(" (and %zu more primitives without triangles)", skipped.size() - 1)
                                                  : std::string();
            const Skip &k = skipped[0];
            fail((k.lines_or_points ? "primitive mode " + k.mode + " is not supported (" + k.place + ")"
                                    : k.mode + " primitive without a triangle (" + k.place + ")") +
                 more + "; the file has no triangles to draw");
        }
        warn(PRW_WARN_SKIPPED, format("%zu primitives without triangles are not drawn: ", skipped.size()) + list);
    }

    // ---- nodes, cameras, lights ----
    void local_trs(const tinygltf::Node &n, const std::string &what, prw_node *out) const
    {
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16 || !finite_all(n.matrix)) fail(what + ": matrix must be 16 finite numbers");
            prw_dmat4 mm;
            for (int i = 0; i < 16; i++) mm.m[i] = n.matrix[(size_t)i]; // both column-major
            if (!prw_decompose_trs(mm, &out->translation, &out->rotation, &out->scale))
                fail(what + ": matrix is not an affine transform without shear (not supported)");
            return;
        }
        if (!(n.translation.empty() || n.translation.size() == 3) || !finite_all(n.translation))
            fail(what + ": translation must be 3 finite numbers");
        if (!(n.rotation.empty() || n.rotation.size() == 4) || !finite_all(n.rotation))
            fail(what + ": rotation must be 4 finite numbers");
        if (!(n.scale.empty() || n.scale.size() == 3) || !finite_all(n.scale))
            fail(what + ": scale must be 3 finite numbers");
        if (!n.translation.empty()) out->translation = prw_v3(n.translation[0], n.translation[1], n.translation[2]);
        if (!n.scale.empty()) out->scale = prw_v3(n.scale[0], n.scale[1], n.scale[2]);
        if (!n.rotation.empty()) {
            const std::vector<double> &q = n.rotation;
            double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
            if (!(l > 1e-9) || !std::isfinite(l)) fail(what + ": rotation quaternion is zero");
            out->rotation = prw_dquat{q[0] / l, q[1] / l, q[2] / l, q[3] / l};
        }
    }

    int light_of(const tinygltf::Node &n, const std::string &what) const
    {
        auto ext = n.extensions.find("KHR_lights_punctual");
        if (ext == n.extensions.end()) return -1;
        const tinygltf::Value &v = ext->second.IsObject() ? ext->second.Get("light") : tinygltf::Value();
        if (!v.IsNumber()) fail(what + ": KHR_lights_punctual.light must be an index");
        double d = v.GetNumberAsDouble();
        if (!(d >= 0 && d < (double)m.lights.size()) || d != std::floor(d))
            fail(what + format(": light %g does not exist (%zu lights)", d, m.lights.size()));
        return (int)d;
    }

    void add_camera(int ci, int node, const std::string &what, const std::string &node_name)
    {
        if (ci < 0 || (size_t)ci >= m.cameras.size())
            fail(what + format(": camera %d does not exist (%zu cameras)", ci, m.cameras.size()));
        const tinygltf::Camera &c = m.cameras[(size_t)ci];
        if (c.type != "perspective") return; // orthographic cameras are ignored (no prw equivalent)
        const tinygltf::PerspectiveCamera &p = c.perspective;
        if (!(p.yfov > 0 && p.yfov < PRW_PI)) fail(format("camera %d: yfov must be in (0, pi)", ci));
        if (!(p.znear > 0) || !std::isfinite(p.znear)) fail(format("camera %d: znear must be > 0", ci));
        if (!(p.aspectRatio >= 0) || !std::isfinite(p.aspectRatio))
            fail(format("camera %d: aspectRatio must be > 0", ci));
        prw_camera pc;
        memset(&pc, 0, sizeof pc);
        prw_copy_name(pc.name, one_line(c.name.empty() ? node_name : c.name, PRW_NAME_MAX - 1).c_str());
        pc.node = node;
        pc.yfov = p.yfov;
        pc.znear = p.znear;
        pc.aspect = p.aspectRatio;
        pc.ev100 = 0.0; // glTF has no exposure; the manifest or the app sets it
        s->nodes[node].camera = prw_scene_add_camera(s, &pc);
    }

    void add_light(int li, int node, const std::string &node_name)
    {
        if (li < 0) return;
        const tinygltf::Light &l = m.lights[(size_t)li];
        std::string what = format("light %d", li);
        prw_light pl;
        memset(&pl, 0, sizeof pl);
        prw_copy_name(pl.name, one_line(l.name.empty() ? node_name : l.name, PRW_NAME_MAX - 1).c_str());
        if (l.type == "point") pl.type = PRW_LIGHT_POINT;
        else if (l.type == "spot") pl.type = PRW_LIGHT_SPOT;
        else if (l.type == "directional") pl.type = PRW_LIGHT_DIRECTIONAL;
        else fail(what + ": unknown type '" + one_line(l.type, 40) + "'");
        std::vector<double> col = l.color.empty() ? std::vector<double>{1, 1, 1} : l.color;
        if (col.size() != 3 || !finite_all(col) || col[0] < 0 || col[1] < 0 || col[2] < 0)
            fail(what + ": color must be 3 finite numbers >= 0");
        if (!std::isfinite(l.intensity) || l.intensity < 0) fail(what + ": intensity must be a finite number >= 0");
        if (!std::isfinite(l.range) || l.range < 0) fail(what + ": range must be a finite number >= 0");
        for (int c = 0; c < 3; c++) pl.color[c] = (float)col[(size_t)c];
        pl.intensity = l.intensity; // cd (point, spot) or lux (directional), as KHR_lights_punctual defines
        pl.range = l.range;
        if (pl.type == PRW_LIGHT_SPOT) {
            double in = l.spot.innerConeAngle, out = l.spot.outerConeAngle;
            if (!(in >= 0 && in <= out && out > 0 && out <= PRW_PI / 2 + 1e-9))
                fail(what + ": spot cone angles need 0 <= innerConeAngle <= outerConeAngle <= pi/2");
            pl.inner_cone = in;
            pl.outer_cone = out;
        }
        pl.cast_shadows = true;
        pl.node = node;
        s->nodes[node].light = prw_scene_add_light(s, &pl);
    }

    void import_nodes(int parent)
    {
        size_t nn = m.nodes.size();
        std::vector<int> parent_of(nn, -1);
        for (size_t i = 0; i < nn; i++)
            for (int c : m.nodes[i].children) {
                if (c < 0 || (size_t)c >= nn) fail(format("node %zu: child %d does not exist (%zu nodes)", i, c, nn));
                if (parent_of[(size_t)c] >= 0 || (size_t)c == i)
                    fail(format("node %d has more than one parent or is its own child", c));
                parent_of[(size_t)c] = (int)i;
            }
        std::vector<int> roots;
        int sc = m.defaultScene >= 0 ? m.defaultScene : (m.scenes.empty() ? -1 : 0);
        if (sc >= 0) {
            if ((size_t)sc >= m.scenes.size()) fail(format("scene %d does not exist", sc));
            roots = m.scenes[(size_t)sc].nodes;
        } else {
            for (size_t i = 0; i < nn; i++)
                if (parent_of[i] < 0) roots.push_back((int)i);
        }
        std::vector<char> visited(nn, 0);
        std::vector<std::pair<int, int>> stack; // (glTF node, scene parent); pre-order: parents first
        for (size_t r = roots.size(); r-- > 0;) stack.push_back({roots[r], parent});
        while (!stack.empty()) {
            auto [gi, sp] = stack.back();
            stack.pop_back();
            if (gi < 0 || (size_t)gi >= nn) fail(format("scene %d: node %d does not exist (%zu nodes)", sc, gi, nn));
            if (visited[(size_t)gi]) fail(format("node %d is reached twice (the hierarchy must be a tree)", gi));
            visited[(size_t)gi] = 1;
            const tinygltf::Node &g = m.nodes[(size_t)gi];
            std::string nm = one_line(g.name.empty() ? format("node%d", gi) : g.name, PRW_NAME_MAX - 1);
            std::string what = format("node %d ('%s')", gi, nm.c_str());
            prw_node n = prw_node_default();
            prw_copy_name(n.name, nm.c_str());
            n.parent = sp;
            local_trs(g, what, &n);
            if (g.mesh != -1) {
                if (g.mesh < 0 || (size_t)g.mesh >= groups.size())
                    fail(what + format(": mesh %d does not exist (%zu meshes)", g.mesh, groups.size()));
                n.mesh_group = groups[(size_t)g.mesh];
            }
            int li = light_of(g, what);
            int ni = prw_scene_add_node(s, &n);
            if (ni < 0) fail(what + ": cannot add node");
            if (g.camera != -1) add_camera(g.camera, ni, what, nm);
            add_light(li, ni, nm);
            for (size_t c = g.children.size(); c-- > 0;) stack.push_back({g.children[c], ni});
        }
    }
};

bool import(prw_scene *s, const char *path, int parent, prw_error *e)
{
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open: %s", path, strerror(errno));
    fclose(f);
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot open: not a regular file", path);
    if (parent < -1 || (parent >= 0 && (uint32_t)parent >= s->node_count))
        return prw_fail(e, "%s: parent node %d does not exist", path, parent);

    std::string data;
    {
        char *text = nullptr;
        size_t size = 0;
        if (!prw_read_file(path, &text, &size, e)) return false;
        if (size > 0xffffffffu) {
            free(text);
            return prw_fail(e, "%s: %zu bytes is too large for a glTF file (at most 4 GiB)", path, size);
        }
        data.assign(text, size);
        free(text);
    }
    uint32_t glb = glb_version(data);
    if (glb == 1) return prw_fail(e, "%s: glTF 1.0 binary (GLB version 1) is not supported; convert to 2.0", path);
    if (glb != 0 && glb != 2) return prw_fail(e, "%s: GLB container version %u is not supported (glTF 2.0 is GLB 2)", path, glb);
    if (glb) {
        std::string why = glb_layout(data);
        if (!why.empty()) return prw_fail(e, "%s: %s", path, why.c_str());
    }
    std::vector<std::string> type_warnings;
    {
        size_t jo = glb ? 20 : 0, jn = glb ? le32((const unsigned char *)data.data() + 12) : data.size();
        std::string why = image_views(data.data() + jo, jn);
        if (why.empty()) why = prw_gltf::wrong_types(data.data() + jo, jn, &type_warnings);
        if (!why.empty()) return prw_fail(e, "%s: %s", path, why.c_str());
    }
    if (data.find("KHR_draco_mesh_compression") != std::string::npos) {
        std::string fixed;
        if (glb ? draco_rewrite_glb(data, &fixed) : draco_rewrite_json(data.data(), data.size(), &fixed)) data.swap(fixed);
    }

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(guarded_image_loader, nullptr);
    std::string err, warn;
    std::string p(path), base = p.find_last_of('/') == std::string::npos ? "" : p.substr(0, p.find_last_of('/'));
    bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, (const unsigned char *)data.data(),
                                                (unsigned)data.size(), base)
                  : loader.LoadASCIIFromString(&model, &err, &warn, data.data(), (unsigned)data.size(), base);
    if (!ok) {
        std::string v1 = glb ? "" : diagnose_v1(path);
        if (!v1.empty()) return prw_fail(e, "%s: %s", path, v1.c_str());
        return prw_fail(e, "%s: %s", path, one_line(err.empty() ? "cannot parse glTF" : err, 600).c_str());
    }

    Importer im(s, path, model);
    for (const std::string &w : type_warnings) im.warn(PRW_WARN_OTHER, w);
    im.check_asset();
    im.check_extensions();
    im.import_materials();
    im.import_meshes();
    im.import_nodes(parent);
    im.note_ignored();
    im.finish_warnings();
    return true;
}

} // namespace

extern "C" bool prw_gltf_import(prw_scene *s, const char *path, int parent, prw_error *e)
{
    if (!path) return prw_fail(e, "(null): no glTF path");
    prw_scene_mark mark = prw_scene_mark_get(s);
    bool ok = false;
    try {
        ok = import(s, path, parent, e);
    } catch (const ImportError &x) {
        ok = prw_fail(e, "%s", x.what());
    } catch (const std::bad_alloc &) {
        ok = prw_fail(e, "%s: out of memory while importing", path);
    } catch (const std::exception &x) {
        ok = prw_fail(e, "%s: glTF import failed: %s", path, one_line(x.what()).c_str());
    } catch (...) {
        ok = prw_fail(e, "%s: glTF import failed (unknown exception)", path);
    }
    if (!ok) {
        prw_scene_rollback(s, mark);
        return false;
    }
    prw_scene_update(s);
    return true;
}

extern "C" bool prw_scene_import_gltf(prw_scene *s, const char *path, int parent, prw_error *e)
{
    if (!prw_gltf_import(s, path, parent, e)) return false;
    prw_scene_note_missing(s, path);
    return true;
}
