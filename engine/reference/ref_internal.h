/* Private to engine/reference: the prepared scene (Embree + emitter tables + environment) and the
 * per-sample integrator. */
#ifndef PRW_REF_INTERNAL_H
#define PRW_REF_INTERNAL_H

#include <embree3/rtcore.h>

#include "prw_btf_eval.h"
#include "prw_reference.h"

/* One mesh drawn by one node: world-space, camera-relative float vertices given to Embree. */
typedef struct ref_inst {
    const prw_mesh *mesh;
    const prw_material *mat;
    float *pos;          /* 3 per vertex (+1 float padding for Embree's 16-byte loads) */
    double *tri;         /* 4 per triangle: ref_tri_geometry of it (computed once at build) */
    double nmat[9];      /* normal matrix (inverse transpose of the world 3x3), row-major */
    double lmat[9];      /* world 3x3, row-major (tangents) */
    bool flip;           /* negative determinant: winding (front face) flips */
    double emit_pdf_area;/* > 0: emissive; density per m^2 of the emissive-triangle sampler */
    bool two_sided;      /* NURBS models: shaded on the side the ray arrives from (ref_nurbs.c) */
    int nurbs_entry;     /* index into scene->nurbs, -1 for glTF/builder meshes */
    prw_dmat4 world;     /* NURBS instances: model metres -> world */
    const struct prw_ref_renderer *r; /* for the alpha filter (MASK / BLEND materials) */
    uint32_t geom;       /* Embree geometry id (= index in inst) */
} ref_inst;

/* The intersection context of every ray: Embree hands it to the alpha filter of MASK / BLEND
 * geometry (ref_scene.c).  key: the ray's own random key (BLEND coverage is decided per ray and
 * triangle by a hash of it, so a repeated query of the same ray decides the same way);
 * blend_invisible: G-buffer queries (prw_ref_primary_hit) pass through BLEND surfaces, as the
 * rasterizer's G-buffer does. */
typedef struct ref_ray_ctx {
    struct RTCIntersectContext ctx; /* first member: the filter casts back */
    uint64_t key;
    bool blend_invisible;
} ref_ray_ctx;

/* Alpha (base_color.a x texel.a, prw_shading.h) of instance `in` at barycentrics (b1, b2) of triangle
 * prim; and the surface coverage there: 1 (OPAQUE), 0 or 1 (MASK by the cutoff), alpha clamped to
 * [0, 1] (BLEND). */
double ref_alpha_at(const struct prw_ref_renderer *r, const ref_inst *in, uint32_t prim, double b1, double b2);
double ref_coverage_at(const struct prw_ref_renderer *r, const ref_inst *in, uint32_t prim, double b1, double b2);
/* uv of texture slot `slot` of the instance's material at barycentrics (b1, b2): uv set (set 1 falls
 * back to set 0 without TEXCOORD_1) then KHR_texture_transform (prw_shading.h). */
void ref_slot_uv(const ref_inst *in, int slot, uint32_t prim, double b1, double b2, double out[2]);
/* Bilinear, repeat wrap; sRGB channels (rgb) decoded before filtering.  uv (0,0) = top-left. */
void ref_tex_sample(const struct prw_ref_renderer *r, const prw_texture *t, const double uv[2], double out[4]);
const prw_texture *ref_tex_of(const struct prw_ref_renderer *r, int idx);

typedef struct ref_rect {
    double c[3];          /* centre, camera-relative */
    double ax[3], ay[3];  /* half-axes (unit node x/y columns times w/2, h/2) */
    double dx[3], dy[3];  /* dual vectors: dot(p - c, dx) in [-1, 1] inside */
    double np[3];         /* unit plane normal */
    double emit[3];       /* unit: the side it emits to (node -Z) */
    double area;
    double L[3];          /* cd/m^2 */
} ref_rect;

typedef struct ref_delta {
    prw_light_type type;
    double p[3];     /* camera-relative position (point, spot) */
    double dir[3];   /* unit: spot axis / directional light travel direction (node -Z) */
    double I[3];     /* cd (point, spot) or lux (directional), times colour */
    double range, cos_inner, cos_outer;
} ref_delta;

typedef struct ref_env {
    int kind;             /* 0 none, 1 uniform, 2 map */
    double uniform[3];
    int w, h;
    float *rgb;           /* 3 per pixel, scaled to cd/m^2, negatives and non-finite clamped to 0 */
    double cr, sr;        /* cos, sin of the rotation */
    double *marg;         /* h + 1: CDF over rows */
    double *cond;         /* h * (w + 1): CDF within each row */
    double *pdf_uv;       /* w * h: density over [0,1]^2 */
} ref_env;

struct prw_ref_renderer {
    const prw_scene *scene;
    prw_dvec3 origin;
    int threads;
    RTCDevice dev;
    RTCScene rtc;
    ref_inst *inst;
    uint32_t inst_count;
    /* emissive triangles: CDF over area * luminance */
    uint32_t etri_count;
    uint32_t *etri_inst, *etri_prim;
    double *etri_cdf; /* etri_count + 1 */
    ref_rect *rects;
    uint32_t rect_count;
    ref_delta *deltas;
    uint32_t delta_count;
    ref_env env;
    float srgb_lut[256];
    prw_mesh *nurbs_meshes; /* level-0 tessellation per NURBS entry (ref_nurbs.c) */
    uint32_t nurbs_mesh_count;
    double *nurbs_err;      /* its error bound, model metres */
    /* BTF materials (ref_btf.c): per scene material its loaded BTF (NULL: another kind); each file once */
    const prw_btf_material **btf_of;
    prw_btf_material *btf_owned;
    uint32_t btf_count;
};

/* ref_btf.c: loads the scene's BTF materials (each file once; refused when the file changed since the
 * scene was loaded, by its hash), naming the material and the file. */
bool ref_btf_load(prw_ref_renderer *r, prw_error *e);
void ref_btf_free(prw_ref_renderer *r);
/* The BTF of an instance's material, or NULL. */
const prw_btf_material *ref_btf_of(const prw_ref_renderer *r, const ref_inst *in);

bool ref_add_instance(prw_ref_renderer *r, const prw_node *n, const prw_mesh *m, prw_error *e);
/* ref_nurbs.c */
uint32_t ref_nurbs_instance_count(const prw_scene *s);
bool ref_nurbs_add(prw_ref_renderer *r, prw_error *e);
void ref_nurbs_free(prw_ref_renderer *r);
/* Worst projected tessellation error of the NURBS instances for view v, pixels (0: none). */
double ref_nurbs_px(const prw_ref_renderer *r, const prw_view *v);

/* Per-thread state: the random-number key and counters. */
typedef struct ref_rng {
    uint64_t key;  /* hash of (seed, pixel, sample) */
    uint32_t dim;
} ref_rng;

static inline uint64_t ref_splitmix(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

static inline ref_rng ref_rng_make(uint64_t seed, uint64_t pixel, uint64_t sample)
{
    ref_rng r;
    r.key = ref_splitmix(ref_splitmix(ref_splitmix(seed) ^ pixel) ^ (sample * 0xd1342543de82ef95ull));
    r.dim = 0;
    return r;
}

/* ---- pixel positions: Owen-scrambled Sobol (0,2)-sequence per pixel ----
 * The jitter of sample s inside pixel `pixel` is point s of the first two Sobol dimensions (base-2
 * radical inverse; the Pascal-matrix dimension), Owen-scrambled per pixel and dimension by a
 * nested uniform scramble (reverse bits, hash-based Laine-Karras permutation, reverse back; Burley
 * 2020, "Practical Hash-based Owen Scrambling").  Every prefix of the sample range is stratified, so
 * the pixel-footprint integral (edges, a light's rim) converges faster than with random jitter;
 * samples are not shuffled, so any sample range of a pixel (batches, farm tasks) is the same
 * points.  A pure function of (seed, pixel, sample): bit-exact merging is kept.  The price: the
 * sample variance of a pixel whose value depends on the position in it over-estimates the error of
 * its mean (the variance file is conservative there), unchanged where it does not. */
static inline uint32_t ref_reverse_bits(uint32_t x)
{
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

static inline uint32_t ref_owen_scramble(uint32_t x, uint32_t seed)
{
    x = ref_reverse_bits(x);
    x += seed; /* Laine-Karras style permutation: each bit flipped by a hash of the bits below it */
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return ref_reverse_bits(x);
}

static inline void ref_pixel_jitter(uint64_t seed, uint64_t pixel, uint64_t sample, double *jx, double *jy)
{
    uint64_t k = ref_splitmix(ref_splitmix(ref_splitmix(seed ^ 0x243f6a8885a308d3ull) ^ pixel) ^ (sample >> 32));
    uint32_t i = (uint32_t)sample;
    uint32_t x = ref_reverse_bits(i), y = 0;
    for (uint32_t v = 0x80000000u; i; i >>= 1, v ^= v >> 1)
        if (i & 1) y ^= v;
    *jx = ref_owen_scramble(x, (uint32_t)k) * 0x1.0p-32;
    *jy = ref_owen_scramble(y, (uint32_t)(k >> 32)) * 0x1.0p-32;
}

/* Uniform in [0, 1): a pure function of (key, dimension). */
static inline double ref_rand(ref_rng *r)
{
    uint64_t h = ref_splitmix(r->key ^ ref_splitmix(0x5851f42d4c957f2dull + r->dim++));
    return (double)(h >> 11) * 0x1.0p-53;
}

/* Triangle prim of in: its unit geometric normal (front side; winding flipped for mirrored
 * instances) in out[0..2] and the largest |coordinate| of its vertices in out[3] (ray offsets). */
void ref_tri_geometry(const ref_inst *in, uint32_t prim, double out[4]);

/* One sample's radiance through image point (x, y) (pixels); rays counts traced rays. */
void ref_trace_sample(const prw_ref_renderer *r, const prw_view *v, prw_ref_filter f, double x, double y,
                      ref_rng *rng, double out[3], uint64_t *rays);

/* The camera ray through image point (x, y): origin (camera-relative), unit direction, near distance. */
void ref_camera_ray(const prw_ref_renderer *r, const prw_view *v, double x, double y, double o[3], double d[3],
                    double *tnear);
/* The same path from any ray: origin o (camera-relative), unit direction d, near distance tnear.
 * camera: the first hit passes through back faces of single-sided materials (camera rays);
 * otherwise they are opaque black, as for every bounce ray.  k counts from this ray (its first hit
 * is scattering vertex 1).  back_first (may be NULL): set when the ray's first surface is the back
 * face of a single-sided material (the path ends there).  ref_trace_sample is camera_ray + this. */
void ref_trace_ray(const prw_ref_renderer *r, const double o[3], const double d[3], double tnear, bool camera,
                   prw_ref_filter f, ref_rng *rng, double out[3], uint64_t *rays, bool *back_first);
/* ref_trace_ray with the pixel's angular size `spread` (radians; 0: none) for the BTF scale rule at the
 * first hit (prw_material.btf_scale_rule). */
void ref_trace_ray_px(const prw_ref_renderer *r, const double o[3], const double d[3], double tnear, bool camera,
                      double spread, prw_ref_filter f, ref_rng *rng, double out[3], uint64_t *rays, bool *back_first);

/* Environment radiance towards world direction d (unit) and its sampling density (solid angle). */
/* The environment of the scene (se) as a light: a uniform colour, or the EXR map read with the
 * reader's limits and the memory budget counting the sampling tables (28 bytes per pixel) with it,
 * plus its luminance x sin(theta) distribution.  A black map yields no light (kind 0).  Free with
 * ref_env_free (safe on a zeroed env). */
bool ref_env_build(const prw_environment *se, ref_env *env, prw_error *e);
void ref_env_free(ref_env *env);
void ref_env_eval(const ref_env *env, const double d[3], double L[3], double *pdf);
/* Samples a direction; returns false when there is nothing to sample. */
bool ref_env_sample(const ref_env *env, double u1, double u2, double d[3], double L[3], double *pdf);

#endif
