// gltf_draco.h — KHR_draco_mesh_compression for the glTF adapter (C++, internal to engine/scene).
//
// Part of the glTF adapter: only gltf_adapter.cpp calls it, and its exceptions (std::bad_alloc)
// stop at prw_scene_import_gltf's extern "C" boundary like the adapter's own.
//  - draco_peek reads the counts a Draco stream claims from its header (no decoding, no allocation)
//    so the caller can refuse absurd streams before libdraco allocates for them;
//  - draco_decode decodes a triangle mesh with libdraco (Debian libdraco-dev) and hands out its
//    faces and attributes (dequantised, normalised integers mapped to [0, 1] / [-1, 1]) per point.
#ifndef PRW_GLTF_DRACO_H
#define PRW_GLTF_DRACO_H

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace prw_gltf {

struct DracoHeader {
    int version_major = 0, version_minor = 0;
    int method = 0;          // 0 sequential, 1 edgebreaker
    uint32_t faces = 0;      // as the connectivity header states
    uint64_t max_points = 0; // upper bound of the decoded point count (sequential: exact)
};

// Reads the header and connectivity counts of a Draco mesh stream.  Returns "" or why the stream
// is not a Draco triangle mesh this decoder accepts.
std::string draco_peek(const uint8_t *data, size_t size, DracoHeader *out);

class DracoMesh {
  public:
    virtual ~DracoMesh() = default;
    virtual uint32_t points() const = 0;
    virtual const std::vector<uint32_t> &indices() const = 0; // 3 per face, < points()
    // The attribute with this unique id as `ncomp` floats per point; "" or why not.
    virtual std::string attribute(uint32_t unique_id, int ncomp, std::vector<float> *out) const = 0;
};

// Decodes; nullptr with *why set when libdraco refuses the stream.
std::unique_ptr<DracoMesh> draco_decode(const uint8_t *data, size_t size, std::string *why);

} // namespace prw_gltf

#endif
