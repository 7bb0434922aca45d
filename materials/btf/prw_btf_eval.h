/* prw_btf_eval — a BTF's value at any texel position, view and light direction (CPU): the direction
 * tables of prw_btf_interp.h and the evaluation the path tracer uses.
 *
 * Promises:
 *  - prw_btf_dirtab_build triangulates a direction set (theta, phi pairs as in prw_btf.h) as
 *    prw_btf_interp.h describes; it refuses (naming the direction) a set of 0 or more than 256
 *    directions, a non-finite angle, theta outside [0, 89.9] degrees and two equal directions.
 *  - prw_btf_eval / prw_btf_packed_eval: the value at continuous texel coordinates (x, y) (any real
 *    numbers: the BTF tiles, bilinear between the 4 nearest texel centres), view direction wv and
 *    light direction wl (unit or not, in the BTF's frame: x along the texel columns, y along the rows,
 *    z the normal): sum over the 3 x 3 (view, light) directions of prw_btf_interp_dir of
 *    w_view w_light value, value = the raw BTF's or prw_btf_packed_value (the one decode), the light
 *    weights those of prw_btf_interp_light (the reflectance is interpolated, the cosine is exact).
 *    The value is what the BTF stores: for prw_btf_synth and the Bonn data, reflectance x cos theta_l
 *    (radiance per lux of normal illuminance).  Exact at measured directions and texel centres.
 *  - prw_btf_packed_dirtabs builds the view and light tables of a packed BTF (one table when the two
 *    direction sets are equal).
 */
#ifndef PRW_BTF_EVAL_H
#define PRW_BTF_EVAL_H

#include <stdbool.h>
#include <stdint.h>

#include "prw_btf.h"
#include "prw_btf_codec.h"
#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_BTF_DIRS_MAX 256u

typedef struct prw_btf_dirtab {
    uint32_t count;      /* measured directions */
    uint32_t tri_count;  /* upper triangles */
    float *tri_inv;      /* 9 per triangle */
    float *cos_theta;    /* per measured direction */
    uint32_t *grid;      /* PRW_BTF_GRID_WORDS: each cell's candidate triangles (prw_btf_interp.h) */
    uint32_t *tri_vert;  /* 3 per triangle (PRW_BTF_HORIZON flag: a horizon vertex) */
} prw_btf_dirtab;

bool prw_btf_dirtab_build(const float *dirs, uint32_t n, prw_btf_dirtab *out, prw_error *e);
void prw_btf_dirtab_free(prw_btf_dirtab *t);

/* The 3 directions and weights around direction d (prw_btf_interp_dir; light: then prw_btf_interp_light). */
void prw_btf_dirtab_weights(const prw_btf_dirtab *t, const double d[3], bool light, uint32_t idx[3], float w[3]);

/* A packed BTF with its direction tables (lights == views when the sets are equal). */
typedef struct prw_btf_material {
    prw_btf_packed p;
    prw_btf_dirtab views, lights;
    bool shared; /* lights is views */
} prw_btf_material;

/* Reads a PRWBTFC1 file and builds its tables; errors name the file. */
bool prw_btf_material_load(const char *path, prw_btf_material *out, prw_error *e);
/* Takes ownership of *p (zeroed on return, also on failure, when it is freed). */
bool prw_btf_material_from_packed(prw_btf_packed *p, const char *name, prw_btf_material *out, prw_error *e);
void prw_btf_material_free(prw_btf_material *m);

void prw_btf_eval(const prw_btf *b, const prw_btf_dirtab *views, const prw_btf_dirtab *lights, double x, double y,
                  const double wv[3], const double wl[3], float rgb[3]);
void prw_btf_material_eval(const prw_btf_material *m, double x, double y, const double wv[3], const double wl[3],
                           float rgb[3]);

#ifdef __cplusplus
}
#endif
#endif
