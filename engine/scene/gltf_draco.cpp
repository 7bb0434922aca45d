// gltf_draco.cpp — Draco mesh decoding for the glTF adapter (see gltf_draco.h).
#include "gltf_draco.h"

#include <draco/compression/decode.h>

#include <cstring>

namespace prw_gltf {

namespace {

// Little reader over the stream, as libdraco's DecoderBuffer reads it (LEB128 varints, LE integers).
struct Reader {
    const uint8_t *p;
    size_t n, at = 0;
    bool u8(uint8_t *v)
    {
        if (at >= n) return false;
        *v = p[at++];
        return true;
    }
    bool u16(uint16_t *v)
    {
        if (n - at < 2) return false;
        *v = (uint16_t)(p[at] | (p[at + 1] << 8));
        at += 2;
        return true;
    }
    bool u32(uint32_t *v)
    {
        if (n - at < 4) return false;
        *v = (uint32_t)p[at] | ((uint32_t)p[at + 1] << 8) | ((uint32_t)p[at + 2] << 16) | ((uint32_t)p[at + 3] << 24);
        at += 4;
        return true;
    }
    bool varint(uint32_t *v)
    {
        uint64_t r = 0;
        for (int i = 0; i < 5; i++) {
            uint8_t b;
            if (!u8(&b)) return false;
            r |= (uint64_t)(b & 0x7f) << (7 * i);
            if (!(b & 0x80)) {
                *v = (uint32_t)r; // libdraco keeps the low 32 bits as well
                return true;
            }
        }
        return false; // more than 5 bytes: libdraco refuses it too
    }
    bool skip(size_t k)
    {
        if (n - at < k) return false;
        at += k;
        return true;
    }
    // a count stored as u32 before bitstream 2.0 (or 2.2 for `v22`) and as a varint after
    bool count(int version, int varint_from, uint32_t *v) { return version < varint_from ? u32(v) : varint(v); }
};

constexpr int version_of(int major, int minor) { return (major << 8) | minor; }

// One metadata tree (bitstream >= 1.3 with the metadata flag), skipped in stream order: a body is
// entries (name, value) then a count of sub-metadata, each a name and a body.  libdraco reads the
// subs depth-first from a stack, but every sub has the same layout, so counting the pending ones is
// enough.  Every item consumes at least two bytes, so the loop ends with the stream.
bool skip_metadata_tree(Reader &r)
{
    uint64_t pending = 0;
    bool root = true;
    while (root || pending) {
        if (!root) {
            pending--;
            uint8_t name_len;
            if (!r.u8(&name_len) || !r.skip(name_len)) return false;
        }
        root = false;
        uint32_t entries, subs;
        if (!r.varint(&entries)) return false;
        for (uint32_t e = 0; e < entries; e++) {
            uint8_t name_len;
            uint32_t size;
            if (!r.u8(&name_len) || !r.skip(name_len) || !r.varint(&size) || size == 0 || !r.skip(size)) return false;
        }
        if (!r.varint(&subs) || subs > r.n - r.at) return false;
        pending += subs;
    }
    return true;
}

bool skip_metadata(Reader &r)
{
    uint32_t num_att;
    if (!r.varint(&num_att)) return false;
    for (uint32_t i = 0; i < num_att; i++) {
        uint32_t id;
        if (!r.varint(&id) || !skip_metadata_tree(r)) return false;
    }
    return skip_metadata_tree(r);
}

} // namespace

std::string draco_peek(const uint8_t *data, size_t size, DracoHeader *out)
{
    Reader r{data, size};
    if (size < 11 || memcmp(data, "DRACO", 5) != 0) return "not a Draco stream (no DRACO magic)";
    r.at = 5;
    uint8_t major, minor, type, method;
    uint16_t flags;
    if (!r.u8(&major) || !r.u8(&minor) || !r.u8(&type) || !r.u8(&method) || !r.u16(&flags))
        return "truncated Draco header";
    out->version_major = major;
    out->version_minor = minor;
    out->method = method;
    int v = version_of(major, minor);
    if (major < 1 || v > version_of(2, 2))
        return "Draco bitstream version " + std::to_string(major) + "." + std::to_string(minor) + " is not supported (1.0 .. 2.2)";
    if (type != 1) return "the Draco stream is a point cloud, not a triangle mesh";
    if (method > 1) return "unknown Draco encoding method " + std::to_string(method);
    if (v >= version_of(1, 3) && (flags & 0x8000) && !skip_metadata(r)) return "truncated Draco metadata";
    uint32_t faces = 0;
    if (method == 0) { // sequential
        uint32_t points;
        if (!r.count(v, version_of(2, 2), &faces) || !r.count(v, version_of(2, 2), &points))
            return "truncated Draco connectivity header";
        out->faces = faces;
        out->max_points = points;
    } else { // edgebreaker
        uint8_t traversal;
        uint32_t new_verts = 0, verts;
        if (!r.u8(&traversal)) return "truncated Draco connectivity header";
        if (v < version_of(2, 2) && !r.count(v, version_of(2, 0), &new_verts)) return "truncated Draco connectivity header";
        if (!r.count(v, version_of(2, 0), &verts) || !r.count(v, version_of(2, 0), &faces))
            return "truncated Draco connectivity header";
        out->faces = faces;
        out->max_points = 3 * (uint64_t)faces; // every point is a corner of some face
    }
    return "";
}

namespace {

class Decoded final : public DracoMesh {
  public:
    std::unique_ptr<draco::Mesh> mesh;
    std::vector<uint32_t> idx;
    uint32_t points() const override { return mesh->num_points(); }
    const std::vector<uint32_t> &indices() const override { return idx; }
    std::string attribute(uint32_t unique_id, int ncomp, std::vector<float> *out) const override
    {
        const draco::PointAttribute *a = mesh->GetAttributeByUniqueId(unique_id);
        if (!a) return "the Draco stream has no attribute with id " + std::to_string(unique_id);
        if (a->num_components() != ncomp)
            return "Draco attribute " + std::to_string(unique_id) + " has " + std::to_string(a->num_components()) +
                   " components, expected " + std::to_string(ncomp);
        uint32_t n = mesh->num_points();
        out->assign((size_t)n * (size_t)ncomp, 0.0f);
        for (uint32_t i = 0; i < n; i++) {
            draco::AttributeValueIndex vi = a->mapped_index(draco::PointIndex(i));
            if (vi.value() >= a->size() ||
                !a->ConvertValue<float>(vi, (int8_t)ncomp, out->data() + (size_t)i * (size_t)ncomp))
                return "Draco attribute " + std::to_string(unique_id) + ": value of point " + std::to_string(i) +
                       " cannot be read";
        }
        return "";
    }
};

} // namespace

std::unique_ptr<DracoMesh> draco_decode(const uint8_t *data, size_t size, std::string *why)
{
    draco::DecoderBuffer buf;
    buf.Init(reinterpret_cast<const char *>(data), size);
    draco::Decoder dec;
    auto res = dec.DecodeMeshFromBuffer(&buf);
    if (!res.ok()) {
        *why = "Draco decoding failed: " + res.status().error_msg_string();
        return nullptr;
    }
    std::unique_ptr<Decoded> d(new Decoded);
    d->mesh = std::move(res).value();
    if (!d->mesh) {
        *why = "Draco decoding failed: no mesh";
        return nullptr;
    }
    uint32_t nf = d->mesh->num_faces(), np = d->mesh->num_points();
    d->idx.resize((size_t)nf * 3);
    for (uint32_t f = 0; f < nf; f++) {
        const draco::Mesh::Face &face = d->mesh->face(draco::FaceIndex(f));
        for (int k = 0; k < 3; k++) {
            uint32_t v = face[(size_t)k].value();
            if (v >= np) {
                *why = "Draco face " + std::to_string(f) + " refers to point " + std::to_string(v) + " of " +
                       std::to_string(np);
                return nullptr;
            }
            d->idx[(size_t)f * 3 + (size_t)k] = v;
        }
    }
    return d;
}

} // namespace prw_gltf
