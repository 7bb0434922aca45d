/* gltf_writer.h — a small glTF 2.0 writer for the rendering tests: meshes (positions, normals, one or
 * two uv sets, 32-bit indices) with one node each, the materials' JSON as given, PNG images as
 * textures, one perspective camera and at most one KHR_lights_punctual light.  Files go into the
 * test's scratch directory (prw_test_path); failures abort the test (prw_test_write_file). */
#ifndef PRW_TEST_GLTF_WRITER_H
#define PRW_TEST_GLTF_WRITER_H

#include <stdbool.h>
#include <stdint.h>

typedef struct gmesh {
    float *pos, *nrm, *uv, *uv1; /* uv1 may be NULL */
    uint32_t nv, ni;
    uint32_t *idx;
    int material;
    double at[3]; /* its node's translation */
} gmesh;

typedef struct gfile {
    gmesh mesh[6];
    int mesh_count;
    const char *materials;  /* the JSON array's members */
    const char *images[4];  /* texture i = image i */
    int image_count;
    const char *ext_used;   /* extensionsUsed members, e.g. "\"KHR_texture_transform\"" (may be NULL) */
    double eye[3], target[3], yfov;
    int light;              /* 1 directional, 2 point, 0 none */
    double light_at[3], light_to[3], intensity; /* lux or cd */
} gfile;

void gltfw_mesh_free(gmesh *m);
/* a quad with centre c and half axes hu, hv (normal hu x hv), uv over [0, 1]^2 */
gmesh gltfw_quad(const double c[3], const double hu[3], const double hv[3], int material);
/* a uv sphere of radius r */
gmesh gltfw_sphere(const double c[3], double r, int slices, int stacks, int material);
/* Writes <name>.gltf and <name>.bin (camera aspect ratio `aspect`); returns the .gltf path. */
const char *gltfw_write(const char *name, const gfile *f, double aspect);
/* Writes an RGBA8 PNG <name>; false (message on stderr) when it cannot. */
bool gltfw_png(const char *name, int w, int h, const uint8_t *rgba);

#endif
