/* prw_scene — the scene graph: meshes, materials, textures, nodes, cameras, lights.
 *
 * Promises:
 *  - The scene owns everything it holds (create/destroy); add_* functions copy their inputs and
 *    return the new element's index.
 *  - Transforms are double precision: node TRS -> local matrix T*R*S (glTF order) -> world matrix.
 *    prw_scene_update() recomputes world matrices and world bounds (AABB of the transformed mesh
 *    AABBs, including descendants).  Call it after editing nodes.
 *  - Units (DESIGN.md §5): metres; colours linear Rec.709; light `intensity` is cd (point, spot),
 *    lux at normal incidence (directional) or cd/m^2 (rect, one-sided); a light's `color` is a
 *    chromaticity normalised by prw_scene to luminance Y = 1, so `intensity` alone carries the
 *    photometric amount.  Material emission is in cd/m^2.  Base-colour and emissive textures are
 *    sRGB-encoded 8-bit and are decoded before filtering (the GPU samples them as *_SRGB).
 *  - Lights and cameras sit on nodes and look down their node's local -Z (glTF); a rect light
 *    spans local x in [-w/2, w/2] and y in [-h/2, h/2] and emits towards local -Z.
 */
#ifndef PRW_SCENE_H
#define PRW_SCENE_H

#include "prw_core.h"
#include "prw_math.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_NAME_MAX 64 /* add_* copy names truncated to 63 bytes, control characters -> '?' */

typedef struct prw_mesh {
    char name[PRW_NAME_MAX];
    uint32_t vertex_count, index_count;
    float *positions; /* 3 per vertex, object space */
    float *normals;   /* 3 per vertex, unit */
    float *uvs;       /* 2 per vertex (zeros when the source has none) */
    float *tangents;  /* 4 per vertex: xyz unit, w = bitangent sign (+-1) */
    float *uvs1;      /* 2 per vertex, the second uv set (glTF TEXCOORD_1); NULL when the source has none */
    uint32_t *indices;/* triangle list, counter-clockwise front faces */
    int material;     /* index into materials */
    prw_dvec3 bounds_min, bounds_max; /* object space */
} prw_mesh;

/* A glTF mesh: several primitives drawn together by a node. */
typedef struct prw_mesh_group {
    char name[PRW_NAME_MAX];
    uint32_t first, count; /* range in meshes[] */
} prw_mesh_group;

typedef struct prw_texture {
    char name[PRW_NAME_MAX];
    int width, height;
    uint8_t *rgba8; /* width*height*4, row 0 at the top */
    bool srgb;      /* base colour and emissive: true */
} prw_texture;

/* How a material's alpha (base_color[3] x the base-colour texture's alpha) is used (glTF alphaMode). */
typedef enum prw_alpha_mode {
    PRW_ALPHA_OPAQUE = 0, /* alpha is ignored */
    PRW_ALPHA_MASK,       /* alpha < alpha_cutoff: no surface there; otherwise opaque */
    PRW_ALPHA_BLEND,      /* alpha is the coverage, blended over what lies behind */
} prw_alpha_mode;

/* A material's texture slots, for the per-slot data below (uv set and transform). */
typedef enum prw_tex_slot {
    PRW_TEX_BASE_COLOR = 0,
    PRW_TEX_METAL_ROUGH,
    PRW_TEX_NORMAL,
    PRW_TEX_EMISSIVE,
    PRW_TEX_CLEARCOAT,           /* R channel */
    PRW_TEX_CLEARCOAT_ROUGHNESS, /* G channel */
    PRW_TEX_CLEARCOAT_NORMAL,
    PRW_TEX_SLOT_COUNT
} prw_tex_slot;

/* Which uv set a texture slot reads and how it transforms it (KHR_texture_transform):
 *   uv' = offset + R(rotation) (scale . uv),  R(r) = [cos r  sin r; -sin r  cos r]
 * i.e. u' = offset[0] + cos r * scale[0] * u + sin r * scale[1] * v,
 *      v' = offset[1] - sin r * scale[0] * u + cos r * scale[1] * v
 * (u right, v down the image: a positive rotation turns the uvs counter-clockwise as drawn in uv
 * space, as the extension's example and its implementations do; the GLSL listing in the extension
 * has the opposite sign).  Identity: offset 0, rotation 0, scale 1 (prw_material_default). */
typedef struct prw_tex_transform {
    float offset[2];
    float rotation; /* radians */
    float scale[2];
    int tex_coord;  /* uv set: 0 = prw_mesh.uvs, 1 = prw_mesh.uvs1 (textureInfo.texCoord, or the extension's) */
} prw_tex_transform;

/* uv' of the formula above (in and out may alias). */
void prw_tex_transform_apply(const prw_tex_transform *t, const float uv[2], float out[2]);
/* True when t leaves every uv unchanged (it may still name uv set 1). */
bool prw_tex_transform_is_identity(const prw_tex_transform *t);

/* How a material is evaluated: each kind has its model in materials/ (C and one GLSL include, shared by
 * the rasterizer and the path tracer). */
typedef enum prw_material_kind {
    PRW_MATERIAL_GLTF_MR = 0, /* glTF metallic-roughness (materials/prw_brdf.h, shaders/material_gltf.glsl) */
    PRW_MATERIAL_BTF,         /* a measured BTF (materials/btf: a PRWBTFC1 file, prw_btf_eval.h); the path tracer
                                 and the base pass (shaders/base_btf.frag) evaluate it */
    PRW_MATERIAL_KIND_COUNT
} prw_material_kind;

typedef struct prw_material {
    char name[PRW_NAME_MAX];
    prw_material_kind kind; /* 0: glTF metallic-roughness, the fields below */
    float base_color[4];    /* linear */
    int base_color_tex;     /* -1: none */
    float metallic, roughness; /* roughness is perceptual (alpha = roughness^2) */
    float specular;         /* dielectric F0 scale (KHR_materials_specular specularFactor): F0 = 0.04 * specular;
                               0 makes a non-metal purely Lambertian (closed-form tests) */
    int metal_rough_tex;    /* glTF: G = roughness, B = metallic; -1: none */
    int normal_tex;         /* -1: none */
    float normal_scale;
    float emission[3];      /* cd/m^2, linear RGB */
    int emissive_tex;       /* -1: none (multiplies emission) */
    bool double_sided;
    /* Stored for the renderers, not drawn yet (the fields above are all they read today): */
    prw_alpha_mode alpha_mode; /* OPAQUE */
    float alpha_cutoff;        /* MASK threshold, 0.5 */
    prw_tex_transform tex_xf[PRW_TEX_SLOT_COUNT]; /* per slot: uv set 0, identity */
    /* KHR_materials_clearcoat: a clear dielectric coat (IOR 1.5, F0 0.04, GGX) over the base layer,
     * weighted by clearcoat x clearcoat_tex.R; its own roughness (perceptual, x roughness_tex.G) and
     * normal map.  clearcoat 0 (default) = no coat. */
    float clearcoat;
    int clearcoat_tex;           /* -1: none; linear */
    float clearcoat_roughness;   /* 0 */
    int clearcoat_roughness_tex; /* -1: none; linear */
    int clearcoat_normal_tex;    /* -1: none; linear */
    float clearcoat_normal_scale;/* 1 */
    /* PRW_MATERIAL_BTF: the file (resolved path; the scene holds the path and a hash of its bytes,
     * renderers read it) and the size of one BTF texel on the surface.  The BTF tiles the surface in the
     * uv set 0 parametrisation at that size: texel (x, y) = (u |dP/du|, v |dP/dv|) / btf_texel_m with
     * dP/du, dP/dv the triangle's metres per uv unit (world space); its frame: x along dP/du, y along
     * dP/dv (rows), z the shading normal.  The fields above other than emission, double_sided and the
     * alpha mode are not used by the BTF kind. */
    char btf_file[1024];
    uint64_t btf_hash;    /* FNV-1a (prw_hash64) of the file's bytes at load */
    double btf_texel_m;   /* metres per texel, > 0 */
    bool btf_scale_rule;  /* the path tracer too switches to the file's fitted average BRDF where a texel is
                             smaller than the pixel footprint (camera-ray hits; the rasterizer's scale rule);
                             false: it evaluates the BTF everywhere (its pixel samples average the texels) */
} prw_material;

/* Checks that `path` is a readable compressed BTF (PRWBTFC1: header, sizes, direction set) and hashes
 * its bytes; errors are "<path>: <problem>". */
bool prw_scene_btf_check(const char *path, uint64_t *hash, prw_error *e);

typedef struct prw_node {
    char name[PRW_NAME_MAX];
    int parent;           /* -1: root */
    prw_dvec3 translation;
    prw_dquat rotation;
    prw_dvec3 scale;
    int mesh_group;       /* -1: none */
    int camera;           /* -1: none */
    int light;            /* -1: none */
    /* computed by prw_scene_update */
    prw_dmat4 world;
    bool has_bounds;
    prw_dvec3 world_min, world_max; /* this node's meshes and all descendants */
} prw_node;

typedef struct prw_camera {
    char name[PRW_NAME_MAX];
    int node;
    double yfov;    /* radians, vertical */
    double znear;   /* metres */
    double aspect;  /* 0: from the image */
    double ev100;   /* exposure value at ISO 100 */
} prw_camera;

typedef enum prw_light_type {
    PRW_LIGHT_POINT = 0,
    PRW_LIGHT_SPOT,
    PRW_LIGHT_DIRECTIONAL,
    PRW_LIGHT_RECT,
} prw_light_type;

typedef struct prw_light {
    char name[PRW_NAME_MAX];
    prw_light_type type;
    int node;
    float color[3];      /* chromaticity, normalised to Y = 1 on add */
    double intensity;    /* cd | lux | cd/m^2, see header comment */
    double range;        /* 0: infinite */
    double inner_cone, outer_cone; /* spot half-angles, radians */
    double width, height;          /* rect, metres */
    bool cast_shadows;
} prw_light;

/* Light from infinitely far away (manifest "environment"), in cd/m^2.  Either an equirectangular
 * EXR (linear Rec.709; pixel value x scale = radiance in cd/m^2) or, when file is "", a constant
 * radiance from every direction.  Mapping of a world direction d (unit): the map direction is
 * d' = R_y(-rotation) d (R_y: right-handed rotation about +Y, so a positive rotation turns the map's
 * -Z towards world -X); u = 0.5 + atan2(d'.x, -d'.z) / (2 pi) (image centre column = -Z, u grows
 * towards +X), v = acos(d'.y) / pi (row 0 = zenith +Y); pixel coordinates (u W, v H).  The scene
 * only holds the path (resolved against the manifest) and a hash of the file's bytes; renderers read
 * the pixels (prw_exr_read). */
typedef struct prw_environment {
    bool present;       /* false: black */
    char file[1024];    /* resolved path, "" = uniform */
    uint64_t file_hash; /* FNV-1a of the file's bytes at load */
    double scale;       /* cd/m^2 per unit of the file's values */
    double rotation;    /* radians about +Y */
    float uniform[3];   /* cd/m^2 (linear RGB) when file is "" */
} prw_environment;

/* A trimmed-NURBS model drawn with per-frame seam-graph LOD (issue 7; drawn by engine/render's
 * prw_lod_render.h, loaded by engine/scene/prw_lod_node.h).  Plain data: the entry says where the
 * model comes from; the baker (engine/bake/prw_bake_scene.h) attaches the loaded model and its
 * hierarchy to the scene (prw_scene_nurbs_attach, prw_lod_node.h), which the renderer and the
 * reference then use. */
typedef struct prw_scene_nurbs {
    char name[PRW_NAME_MAX];
    char file[1024];       /* resolved .igs/.iges/.json path; "" for a procedural model */
    char procedural[32];   /* "car_shell" | "box" | "plate" when file is "" */
    int node;              /* the model's metres are in this node's space */
    int material;          /* index into materials */
    int grid[2];           /* instances: grid[0] x grid[1] copies (>= 1 each) */
    double spacing[2];     /* copy (i, j) = the node's placement moved by (i * spacing[0], 0, j * spacing[1])
                              in world space (a grid on the floor, whatever the node's rotation) */
    double chord_rel;      /* sewing chordal tolerance / model diagonal (0: 2e-4) */
    double finest_rel;     /* > 0: the finest level is refined to finest_rel x diagonal (prw_lod_options),
                              sewing at half of it; 0: the finest level targets the sewing chord */
    double tol_px;         /* LOD screen-space tolerance in pixels (0: 0.5) */
    bool single_sided;     /* closed, outward-oriented: back-face culling of patches and triangles */
    prw_dvec3 model_min, model_max; /* model-space bounds of the trimmed faces, set by the loader */
} prw_scene_nurbs;

/* Import warnings: data for the caller (the app prints them; loaders never print).  Each is one line
 * "<file>: <what>" and has a kind so a caller can act on it. */
typedef enum prw_warning_kind {
    PRW_WARN_EXTENSION = 1, /* a glTF extension in extensionsUsed that prw does not implement (ignored) */
    PRW_WARN_SKIPPED,       /* content that is not drawn: line/point primitives, primitives without triangles */
    PRW_WARN_NO_LIGHT,      /* after the load nothing emits light: no light, emissive material or environment */
    PRW_WARN_NO_CAMERA,     /* after the load there is no camera (prw_scene_add_framing_camera makes one) */
    PRW_WARN_OTHER,
} prw_warning_kind;

typedef struct prw_scene_warning {
    prw_warning_kind kind;
    char msg[PRW_ERROR_MAX];
} prw_scene_warning;

typedef struct prw_scene {
    prw_mesh *meshes;
    uint32_t mesh_count;
    prw_mesh_group *groups;
    uint32_t group_count;
    prw_material *materials;
    uint32_t material_count;
    prw_texture *textures;
    uint32_t texture_count;
    prw_node *nodes;
    uint32_t node_count;
    prw_camera *cameras;
    uint32_t camera_count;
    prw_light *lights;
    uint32_t light_count;
    bool has_bounds;
    prw_dvec3 bounds_min, bounds_max; /* world */
    char source[256]; /* manifest or model file path, or "demo" (set by the loaders when empty) */
    prw_environment environment; /* zeroed: none */
    prw_scene_nurbs *nurbs; /* NURBS models with LOD (issue 7) */
    uint32_t nurbs_count;
    /* per NURBS entry, what the baker attached (prw_lod_node.h: prw_scene_nurbs_attach / _baked);
       owned by the scene */
    struct prw_scene_nurbs_baked *nurbs_baked;
    prw_scene_warning *warnings; /* what the loaders noticed but did not refuse, in order */
    uint32_t warning_count;
} prw_scene;

prw_scene *prw_scene_create(void);
void prw_scene_destroy(prw_scene *s);

/* Copies the arrays of m (positions, indices required; normals, uvs, tangents optional: normals are
 * computed area-weighted when absent, tangents by prw_mesh_generate_tangents when absent). Computes
 * bounds.  Returns the index, or -1 with e set on invalid input (index out of range, NaN/Inf, index
 * count not a multiple of 3, m->material not an existing material index: add materials first).
 * Given normals/tangents are renormalised; zero-length normals are replaced by computed ones. */
int prw_scene_add_mesh(prw_scene *s, const prw_mesh *m, prw_error *e);
int prw_scene_add_group(prw_scene *s, const char *name, uint32_t first, uint32_t count);
int prw_scene_add_material(prw_scene *s, const prw_material *m);
int prw_scene_add_texture(prw_scene *s, const prw_texture *t); /* copies pixels; -1 if empty */
int prw_scene_add_node(prw_scene *s, const prw_node *n);       /* parent must already exist, else -1 */
int prw_scene_add_camera(prw_scene *s, const prw_camera *c);
/* Normalises l->color to Y = 1; a black (or negative / non-finite) colour becomes white. */
int prw_scene_add_light(prw_scene *s, const prw_light *l);
/* Copies n (node and material must exist, grid >= 1; -1 otherwise); its instances' world bounds
 * count in the scene bounds.  The new entry has nothing attached (not baked). */
int prw_scene_add_nurbs(prw_scene *s, const prw_scene_nurbs *n);

/* Defaults: identity TRS, no parent/mesh/camera/light; material: white, roughness 1, no textures. */
prw_node prw_node_default(void);
prw_material prw_material_default(void);

/* Convenience: a node at `position` whose -Z axis looks at `target` (up hint `up`). */
prw_node prw_node_look_at(const char *name, prw_dvec3 position, prw_dvec3 target, prw_dvec3 up);

void prw_scene_update(prw_scene *s);

/* Appends a warning (printf format, made one line, truncated to PRW_ERROR_MAX - 1 bytes); returns its
 * index.  Failed loads remove the warnings they added. */
int prw_scene_add_warning(prw_scene *s, prw_warning_kind kind, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Index of the first warning of that kind, -1 when there is none. */
int prw_scene_find_warning(const prw_scene *s, prw_warning_kind kind);

/* A camera placement that frames the scene's world bounds, for scenes without a camera.  The view
 * looks at the centre c of the bounds' bounding sphere (radius r = half the diagonal, at least
 * 1 micrometre, so a part in micrometre units still fills the view)
 * from the front-right, above: position = c + d (sin 30deg cos 25deg, sin 25deg, cos 30deg cos 25deg)
 * (glTF: +Y up, +Z front), up = +Y, yfov = 50 deg.  d = r / sin(min(yfov, xfov) / 2) with
 * tan(xfov / 2) = aspect tan(yfov / 2), so the whole sphere — hence every point of the bounds — is
 * inside the view frustum and touches its tighter pair of planes; znear = (d - r) / 2, in front of
 * everything.  aspect = width / height; <= 0 or not finite means 1 (then any image at least as wide
 * as it is tall shows everything).  Call after prw_scene_update.  Returns false (out untouched)
 * when the scene has no bounds. */
typedef struct prw_framing {
    prw_dvec3 position, target, up;
    double yfov;   /* radians, vertical */
    double znear;  /* metres */
    double radius; /* of the framed sphere, metres */
} prw_framing;
bool prw_scene_frame_camera(const prw_scene *s, double aspect, prw_framing *out);
/* Adds a node looking along prw_scene_frame_camera's framing and a camera on it (yfov, znear; aspect
 * 0 = from the image, ev100 0) named `name` (NULL: "framing"); returns the camera index, or -1 when
 * the scene has no bounds.  Runs prw_scene_update. */
int prw_scene_add_framing_camera(prw_scene *s, double aspect, const char *name);

/* The light the scene's emissive surfaces send out, for deciding whether a scene is lit (the
 * rasterizer lights from emissive meshes as area lights: prw_emissive.h).  mesh_flux_lm: luminous flux of the drawn
 * meshes with an emissive material, sum of pi x luminance x world area (x 2 when double-sided), the
 * luminance being emission's Rec.709 Y times the emissive texture's mean (sRGB decoded); mesh_count:
 * how many such drawn meshes; nurbs_count: NURBS entries with an emissive material (their area is
 * known only after the bake, so no flux).  Call after prw_scene_update. */
typedef struct prw_emitters {
    double mesh_flux_lm;
    uint32_t mesh_count, nurbs_count;
} prw_emitters;
prw_emitters prw_scene_emitters(const prw_scene *s);

/* Opens a model file as (part of) a scene: .gltf / .glb through prw_scene_import_gltf, .igs / .iges as
 * one trimmed-NURBS entry (its own node, a light grey double-sided material; the hierarchy is baked
 * later, engine/bake).  Warnings as the loaders add them ("no light", "no camera").  Errors name the
 * file; a failed open leaves the scene as it was. */
bool prw_scene_open_model(prw_scene *s, const char *path, prw_error *e);
/* Whether prw_scene_open_model takes this path (by its extension, case-insensitive). */
bool prw_scene_is_model_file(const char *path);

/* Finds a camera by name (NULL or "" -> first camera); -1 when absent. */
int prw_scene_find_camera(const prw_scene *s, const char *name);

/* Per-vertex tangents from uvs (accumulated per triangle, Gram-Schmidt against the normal; a
 * consistent fallback frame where uvs are degenerate). Allocates m->tangents if NULL.
 * Convention (glTF): tangent.xyz points along +u; bitangent = cross(normal, tangent.xyz) * w points
 * along DECREASING v (uv (0,0) is the image's top-left, so that is "up" = +Y of a glTF normal map);
 * an unmirrored mapping has w = +1.  Degenerate uvs: a deterministic unit vector orthogonal to the
 * normal, w = +1. */
void prw_mesh_generate_tangents(prw_mesh *m);

/* Content hash of everything that affects an image (geometry, materials, lights, cameras). */
uint64_t prw_scene_hash(const prw_scene *s);

/* ---- builder helpers (each adds mesh + group + node and returns the node index, or -1 with e set).
 * Meshes are built around the node's origin (the node carries the double-precision position), with
 * per-face normals, uvs 0..1 per face and generated tangents. `material` must be an existing index. */

/* Axis-aligned box [min, max]: 24 vertices, 12 triangles, counter-clockwise front faces seen from
 * outside (normals outward), or seen from inside with normals inward when `inward` (rooms). */
int prw_scene_add_box(prw_scene *s, const char *name, prw_dvec3 min, prw_dvec3 max, int material,
                      bool inward, prw_error *e);
/* Rectangle centre +- half_u +- half_v (half_u, half_v: half-axis vectors, need not be orthogonal
 * but must not be parallel); front face and normal = normalize(cross(half_u, half_v)); uv (0,0) at
 * centre - half_u + half_v, u along half_u, v along -half_v (glTF: v down the image). */
int prw_scene_add_quad(prw_scene *s, const char *name, prw_dvec3 centre, prw_dvec3 half_u,
                       prw_dvec3 half_v, int material, prw_error *e);
/* UV sphere: `slices` around +Y (>= 3), `stacks` from pole to pole (>= 2); smooth normals. */
int prw_scene_add_sphere(prw_scene *s, const char *name, prw_dvec3 centre, double r, int slices,
                         int stacks, int material, prw_error *e);

/* Splits an affine matrix into T, R (unit quaternion) and S, assuming no shear (a negative
 * determinant goes into scale.x).  Returns false when the matrix is not affine, has shear beyond
 * 1e-4 (cosine between axes) or is not finite; zero-length axes are completed to a rotation. */
bool prw_decompose_trs(prw_dmat4 m, prw_dvec3 *t, prw_dquat *r, prw_dvec3 *scale);
/* Unit quaternion from an orthonormal rotation (columns = images of the x, y, z axes). */
prw_dquat prw_quat_from_axes(prw_dvec3 x, prw_dvec3 y, prw_dvec3 z);

/* ---- loaders ----
 * All-or-nothing: on failure everything the call added is removed again (the scene is as before)
 * and e holds one line "<file>:<place>: <reason>".  On success prw_scene_update() has been run. */
/* Scene manifest (JSON): see engine/scene/manifest.md. Relative paths resolve against the manifest. */
bool prw_scene_load_manifest(prw_scene *s, const char *path, prw_error *e);
/* Manifest text already in memory (path is used for messages and relative paths). */
bool prw_scene_parse_manifest(prw_scene *s, const char *text, size_t size, const char *path, prw_error *e);
/* glTF 2.0 (.gltf or .glb) under node `parent` (-1: root); meshes (triangles, strips, fans; Draco),
 * hierarchy, metallic-roughness materials, textures, cameras, KHR_lights_punctual.  Refuses glTF 1.0
 * and files that require an extension prw does not implement.  Adds warnings (prw_scene.warnings)
 * for ignored extensions and skipped line/point primitives and, when the scene has no light or no
 * camera after the import, PRW_WARN_NO_LIGHT / PRW_WARN_NO_CAMERA.  Conventions (matrix decomposition,
 * emission units, what is ignored): manifest.md, section "glTF import".  The manifest loader also
 * ends with the no-light / no-camera check (for the whole manifest, not per glTF entry). */
bool prw_scene_import_gltf(prw_scene *s, const char *path, int parent, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
