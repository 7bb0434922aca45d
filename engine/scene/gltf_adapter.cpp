// gltf_adapter.cpp — glTF 2.0 (.gltf / .glb) import through tinygltf (Debian's libtinygltf).
//
// The only C++ file of prw_scene.  prw_scene_import_gltf is extern "C"; every exception stops at
// that boundary and becomes a one-line prw_error.  Import is all-or-nothing (rolled back on error).
//
// Conventions (see manifest.md, "glTF import"):
//  - nodes: TRS as given; a `matrix` is decomposed into T, R, S assuming no shear (shear -> error);
//  - each primitive -> one prw_mesh, each glTF mesh -> one prw_mesh_group; TRIANGLES mode only;
//  - every accessor is bounds-checked against its bufferView, every bufferView against its buffer;
//  - emission [cd/m^2] = emissiveFactor x KHR_materials_emissive_strength (glTF value 1 = 1 cd/m^2);
//  - KHR_lights_punctual: point/spot intensity in cd, directional in lux (as the extension states);
//  - textures become RGBA8; baseColor and emissive are sRGB, the others linear; an image used both
//    ways is stored twice.  Samplers (wrap/filter) and texCoord sets other than 0 are ignored;
//  - orthographic cameras, skins, morph targets and animations are ignored.
#include "scene_internal.h"

#include <tiny_gltf.h>

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

struct ImportError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
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
std::string one_line(const std::string &s, size_t max = 200)
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

const size_t kMaxElements = size_t(1) << 28; // per accessor, far above any sane asset

struct Importer {
    prw_scene *s;
    std::string file; // for messages
    const tinygltf::Model &m;

    std::map<std::pair<int, bool>, int> textures; // (image, srgb) -> scene texture
    std::vector<int> materials;                   // glTF material -> scene material
    int default_material = -1;
    std::vector<int> groups; // glTF mesh -> scene group

    Importer(prw_scene *scene, const std::string &path, const tinygltf::Model &model)
        : s(scene), file(path), m(model)
    {
    }

    [[noreturn]] void fail(const std::string &msg) const { throw ImportError(file + ": " + msg); }

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
            pm.base_color_tex = texture(pbr.baseColorTexture.index, true, what + " baseColorTexture");
            pm.metal_rough_tex = texture(pbr.metallicRoughnessTexture.index, false, what + " metallicRoughnessTexture");
            pm.normal_tex = texture(g.normalTexture.index, false, what + " normalTexture");
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
            pm.emissive_tex = texture(g.emissiveTexture.index, true, what + " emissiveTexture");
            // KHR_materials_specular: specularFactor scales the dielectric F0 (the colour term is not supported)
            auto spx = g.extensions.find("KHR_materials_specular");
            if (spx != g.extensions.end() && spx->second.IsObject() && spx->second.Has("specularFactor")) {
                const tinygltf::Value &v = spx->second.Get("specularFactor");
                if (!v.IsNumber() || !(v.GetNumberAsDouble() >= 0.0 && v.GetNumberAsDouble() <= 1.0))
                    fail(what + ": KHR_materials_specular.specularFactor must be a number in [0, 1]");
                pm.specular = (float)v.GetNumberAsDouble();
            }
            pm.double_sided = g.doubleSided;
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
    void import_meshes()
    {
        for (size_t mi = 0; mi < m.meshes.size(); mi++) {
            const tinygltf::Mesh &gm = m.meshes[mi];
            std::string nm = one_line(gm.name.empty() ? format("mesh%zu", mi) : gm.name, PRW_NAME_MAX - 1);
            uint32_t first = s->mesh_count;
            for (size_t pi = 0; pi < gm.primitives.size(); pi++) {
                const tinygltf::Primitive &p = gm.primitives[pi];
                std::string where = format("mesh '%s' primitive %zu", nm.c_str(), pi);
                if (p.mode != -1 && p.mode != TINYGLTF_MODE_TRIANGLES)
                    fail(where + format(": mode %d is not supported (only TRIANGLES = 4)", p.mode));
                auto attr = [&](const char *key) {
                    auto it = p.attributes.find(key);
                    return it == p.attributes.end() ? -2 : it->second;
                };
                int ipos = attr("POSITION"), inrm = attr("NORMAL"), iuv = attr("TEXCOORD_0"), itan = attr("TANGENT");
                if (ipos == -2) fail(where + ": no POSITION attribute");
                std::string mwhat = format("mesh '%s'", nm.c_str());
                View vp = view(ipos, mwhat + " POSITION", 3);
                size_t n = vp.count;
                std::vector<float> pos = read_floats(vp), nrm, uv, tan;
                auto other = [&](int idx, const char *sem, int ncomp, std::vector<float> &out) {
                    if (idx == -2) return;
                    View v = view(idx, mwhat + " " + sem, ncomp);
                    if (v.count != n)
                        fail(format("accessor %d (%s %s): count %zu differs from POSITION count %zu", idx, mwhat.c_str(),
                                    sem, v.count, n));
                    out = read_floats(v);
                };
                other(inrm, "NORMAL", 3, nrm);
                other(iuv, "TEXCOORD_0", 2, uv);
                other(itan, "TANGENT", 4, tan);
                std::vector<uint32_t> idx;
                if (p.indices != -1) {
                    View vi = view(p.indices, mwhat + " indices", 1);
                    if (vi.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                        vi.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                        vi.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                        fail(format("accessor %d (%s indices): componentType %d is not an unsigned integer type",
                                    p.indices, mwhat.c_str(), vi.comp_type));
                    idx.resize(vi.count, 0);
                    if (vi.base)
                        for (size_t i = 0; i < vi.count; i++)
                            idx[i] = (uint32_t)component(vi.base + i * vi.stride, vi.comp_type, false);
                } else {
                    idx.resize(n);
                    for (size_t i = 0; i < n; i++) idx[i] = (uint32_t)i;
                }
                prw_mesh pm;
                memset(&pm, 0, sizeof pm);
                prw_copy_name(pm.name, nm.c_str());
                pm.vertex_count = (uint32_t)n;
                pm.index_count = (uint32_t)idx.size();
                pm.positions = pos.data();
                pm.normals = nrm.empty() ? nullptr : nrm.data();
                pm.uvs = uv.empty() ? nullptr : uv.data();
                pm.tangents = tan.empty() ? nullptr : tan.data();
                pm.indices = idx.data();
                pm.material = material(p.material, where);
                prw_error e;
                if (prw_scene_add_mesh(s, &pm, &e) < 0) { // e: "mesh '<name>': <reason>"
                    const char *reason = strstr(e.msg, "': ");
                    fail(where + ": " + (reason ? reason + 3 : e.msg));
                }
            }
            int g = prw_scene_add_group(s, nm.c_str(), first, s->mesh_count - first);
            if (g < 0) fail(format("mesh '%s': cannot add group", nm.c_str()));
            groups.push_back(g);
        }
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

bool is_glb(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    char magic[4] = {0, 0, 0, 0};
    size_t n = fread(magic, 1, 4, f);
    fclose(f);
    return n == 4 && memcmp(magic, "glTF", 4) == 0;
}

bool import(prw_scene *s, const char *path, int parent, prw_error *e)
{
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open: %s", path, strerror(errno));
    fclose(f);
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot open: not a regular file", path);
    if (parent < -1 || (parent >= 0 && (uint32_t)parent >= s->node_count))
        return prw_fail(e, "%s: parent node %d does not exist", path, parent);

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    bool ok = is_glb(path) ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                           : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) return prw_fail(e, "%s: %s", path, one_line(err.empty() ? "cannot parse glTF" : err, 600).c_str());

    Importer im(s, path, model);
    im.import_materials();
    im.import_meshes();
    im.import_nodes(parent);
    return true;
}

} // namespace

extern "C" bool prw_scene_import_gltf(prw_scene *s, const char *path, int parent, prw_error *e)
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
