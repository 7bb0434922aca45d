// gltf_container.h — the glTF adapter's checks and rewrites of the raw file, before tinygltf parses
// it (C++, internal to engine/scene; only gltf_adapter.cpp calls it).
//  - glb_version / glb_layout: the GLB container's version and chunk layout ("" when well-formed);
//  - image_views: every image stored in a bufferView lies inside its buffer ("" or why not);
//  - draco_rewrite_json / _glb: KHR_draco_mesh_compression primitives' "indices" moved into the
//    extension as "prw_indices" (false when nothing had to change or the container is malformed);
//  - diagnose_v1: after tinygltf refused a .gltf, the message for a glTF 1.0 file ("" if it is not);
//  - wrong_types: values of the wrong JSON type that tinygltf 2.7 drops without a word: "" or the
//    refusal (a mesh's primitives not an array, a material's pbrMetallicRoughness or texture
//    reference not an object, a texture index not an integer >= 0), else warnings added to *warn
//    (a texture reference without an index, a normal scale / occlusion strength not a number, a
//    KHR_texture_transform not an object: what tinygltf leaves out is named);
//  - format / one_line: message text (printf into a string; one printable line from untrusted text).
// Nothing here throws except std::bad_alloc, which stops at the adapter's extern "C" boundary.
#ifndef PRW_GLTF_CONTAINER_H
#define PRW_GLTF_CONTAINER_H

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace prw_gltf {

std::string format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
std::string one_line(const std::string &s, size_t max = 200);

uint32_t le32(const unsigned char *p);
uint32_t glb_version(const std::string &d); // 0: not a GLB; 0xffffffff: truncated
std::string glb_layout(const std::string &d);
std::string image_views(const char *json, size_t size);
bool draco_rewrite_json(const char *text, size_t size, std::string *out);
bool draco_rewrite_glb(const std::string &d, std::string *out);
std::string diagnose_v1(const char *path);
std::string wrong_types(const char *json, size_t size, std::vector<std::string> *warn);

} // namespace prw_gltf

#endif
