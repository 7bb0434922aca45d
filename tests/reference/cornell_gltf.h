/* cornell_gltf — the classic Cornell box (Cornell University Program of Computer Graphics' measured
 * geometry, in metres) as a glTF 2.0 file with its .bin beside it: Lambert walls and blocks
 * (metallic 0, roughness 1, KHR_materials_specular specularFactor 0: no dielectric specular layer),
 * the ceiling light as an emissive quad (KHR_materials_emissive_strength; glTF value 1 = 1 cd/m^2 in
 * prw) emitting downwards only, flush with the ceiling (which has a hole for it), the classic
 * camera (35 mm lens on 25 mm film: 39.3 degrees).  Walls and blocks are double-sided, so no
 * renderer's culling rule matters.  The scene of the path tracer's efficiency figures (README
 * "Reference efficiency"); Blender imports the same file. */
#ifndef CORNELL_GLTF_H
#define CORNELL_GLTF_H
#include <stdbool.h>
#include <stddef.h>

/* Writes path (must end in .gltf) and the .bin beside it; emission: the light's cd/m^2 at its
 * white point (1000 is the default of the tool).  On failure a message in err. */
bool cornell_write_gltf(const char *path, double emission, char *err, size_t cap);
/* Triangles of the model (the light included). */
#define CORNELL_TRIANGLES 38
#endif
