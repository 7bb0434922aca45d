/* prw_btf_interp.h — THE interpolation of a BTF between its measured directions, one source for C17
 * (prw_btf_eval.h, the path tracer) and GLSL 4.50 (the base pass, later).  A scalar header in the style
 * of prw_btf_decode.h: the includer defines the fetches of a direction table (prw_btf_dirtab, built by
 * prw_btf_dirtab_build):
 *   PRW_BTF_TRI_INV(i)   float i of the triangles' inverse vertex matrices (9 per triangle, row-major),
 *   PRW_BTF_TRI_VERT(i)  vertex i of the triangles (3 per triangle, PRW_BTF_UINT): a measured direction's
 *                        index, or PRW_BTF_HORIZON | index for a horizon vertex standing for that index,
 *   PRW_BTF_DT_PARAMS / PRW_BTF_DT_ARGS  leading parameters the fetches use (e.g. "const prw_btf_dirtab *t,"),
 *   PRW_BTF_DIR_COS(i)   cos theta of measured direction i (float),
 *   PRW_BTF_GRID(i)      word i of the lookup grid: cell c's PRW_BTF_GRID_C candidate triangles in words
 *                        2 c and 2 c + 1, 16 bits each, the lower first (prw_btf_interp_cell),
 *
 * The method: the measured directions, plus horizon vertices (the outermost ring's azimuths at theta
 * 90 degrees) and the south pole, are unit points whose convex hull is triangulated (coplanar facets
 * fanned canonically); a direction d (local frame, z up) is interpolated inside the hull triangle its
 * ray from the centre crosses: d = a A + b B + c C, weights (a, b, c) / (a + b + c) — the planar
 * barycentrics of the ray's crossing, exact (weight 1) at a measured direction and a partition of unity.
 * Only the upper triangles (no pole) are stored; z is clamped to >= 1e-6 first.  A horizon vertex stands
 * for the measured direction of its azimuth on the outermost ring (the value is held beyond the cone).
 * Views interpolate the stored value.  Lights interpolate the reflectance: the BTF stores f cos theta_l
 * (prw_btf_synth.h, the Bonn data), so a light weight is w_k cos theta_l / cos theta_k
 * (prw_btf_interp_light): exact for a Lambertian sample, still exact at measured directions, and the
 * value vanishes at the horizon as cos theta_l does. */
#ifndef PRW_BTF_INTERP_H
#define PRW_BTF_INTERP_H

#ifdef GL_core_profile
#define PRW_BTF_IUINT uint
#define PRW_BTF_IFN
#define PRW_BTF_IOUT out
#define PRW_BTF_IINOUT inout
#define PRW_BTF_IMAX max
#define PRW_BTF_IMIN min
#define PRW_BTF_IBOOL bool
#define PRW_BTF_IFLOOR floor
#define PRW_BTF_ITOF(v) float(v)
#define PRW_BTF_ITOU(v) uint(v)
#define PRW_BTF_IACOS acos
#define PRW_BTF_IATAN2(y, x) atan(y, x)
#else
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#define PRW_BTF_IUINT uint32_t
#define PRW_BTF_IFN static inline
#define PRW_BTF_IOUT
#define PRW_BTF_IINOUT
#define PRW_BTF_IMAX(a, b) ((a) > (b) ? (a) : (b)) /* finite arguments: no libm call */
#define PRW_BTF_IMIN(a, b) ((a) < (b) ? (a) : (b))
#define PRW_BTF_IBOOL bool
#define PRW_BTF_IFLOOR floorf
#define PRW_BTF_ITOF(v) ((float)(v))
#define PRW_BTF_ITOU(v) ((uint32_t)(v))
#define PRW_BTF_IACOS acosf
#define PRW_BTF_IATAN2 atan2f
#endif

#define PRW_BTF_HORIZON 0x80000000u
/* The lookup grid: theta in [0, 90] degrees x phi in [-180, 180) degrees, cells of equal angles; each
 * cell lists PRW_BTF_GRID_C triangles that cover it (the most covering first, repeats fill a short
 * list).  2 words per cell. */
#define PRW_BTF_GRID_T 16u
#define PRW_BTF_GRID_P 64u
#define PRW_BTF_GRID_C 4u
#define PRW_BTF_GRID_WORDS (PRW_BTF_GRID_T * PRW_BTF_GRID_P * 2u)
/* A crossing this close to a triangle's edge counts as inside it (the weights are clamped below). */
#define PRW_BTF_INSIDE_EPS 1e-6f

/* The grid cell of the unit direction (x, y, z) (z clamped to >= 0). */
PRW_BTF_IFN PRW_BTF_IUINT prw_btf_interp_cell(float x, float y, float z)
{
    float t = PRW_BTF_IACOS(PRW_BTF_IMIN(PRW_BTF_IMAX(z, 0.0f), 1.0f)) * (2.0f / 3.14159265f);
    float p = (PRW_BTF_IATAN2(y, x) * (0.5f / 3.14159265f) + 0.5f);
    PRW_BTF_IUINT i = PRW_BTF_ITOU(PRW_BTF_IMAX(t * PRW_BTF_ITOF(PRW_BTF_GRID_T), 0.0f));
    PRW_BTF_IUINT j = PRW_BTF_ITOU(PRW_BTF_IMAX(p * PRW_BTF_ITOF(PRW_BTF_GRID_P), 0.0f));
    return PRW_BTF_IMIN(i, PRW_BTF_GRID_T - 1u) * PRW_BTF_GRID_P + PRW_BTF_IMIN(j, PRW_BTF_GRID_P - 1u);
}

/* The 3 measured directions around the unit direction (x, y, z) and their weights (a partition of unity;
 * zero weights come with a valid index).  ntri: the table's triangle count (> 0).  The grid cell's
 * candidates are tried first (a fixed count: no data-dependent loop, which a SIMD shader pays for its
 * slowest lane); only when none holds the crossing (within PRW_BTF_INSIDE_EPS) are all triangles tried
 * in order, the first holding it winning (at a shared edge or vertex the neighbours' weights agree),
 * else the one it is least outside of. */
PRW_BTF_IFN void prw_btf_interp_dir(PRW_BTF_DT_PARAMS float x, float y, float z, PRW_BTF_IUINT ntri,
                                    PRW_BTF_IOUT PRW_BTF_IUINT idx[3], PRW_BTF_IOUT float w[3])
{
    PRW_BTF_IUINT cell = prw_btf_interp_cell(x, y, z);
    z = PRW_BTF_IMAX(z, 1e-6f);
    PRW_BTF_IUINT best = 0u;
    float best_min = -3.0e38f, ba = 1.0f, bb = 0.0f, bc = 0.0f;
    for (PRW_BTF_IUINT k = 0u; k < PRW_BTF_GRID_C + ntri; k++) {
        PRW_BTF_IUINT t;
        if (k < PRW_BTF_GRID_C) t = (PRW_BTF_GRID(2u * cell + (k >> 1u)) >> ((k & 1u) * 16u)) & 0xffffu;
        else {
            if (best_min >= -PRW_BTF_INSIDE_EPS) break; /* a candidate holds it */
            t = k - PRW_BTF_GRID_C;
        }
        t = PRW_BTF_IMIN(t, ntri - 1u);
        float a = PRW_BTF_TRI_INV(t * 9u + 0u) * x + PRW_BTF_TRI_INV(t * 9u + 1u) * y + PRW_BTF_TRI_INV(t * 9u + 2u) * z;
        float b = PRW_BTF_TRI_INV(t * 9u + 3u) * x + PRW_BTF_TRI_INV(t * 9u + 4u) * y + PRW_BTF_TRI_INV(t * 9u + 5u) * z;
        float c = PRW_BTF_TRI_INV(t * 9u + 6u) * x + PRW_BTF_TRI_INV(t * 9u + 7u) * y + PRW_BTF_TRI_INV(t * 9u + 8u) * z;
        float s = a + b + c;
        if (!(s > 0.0f)) continue; /* the triangle's plane lies behind the centre on this ray */
        float m = PRW_BTF_IMIN(a, PRW_BTF_IMIN(b, c)) / s;
        if (m > best_min) {
            best_min = m, best = t, ba = a / s, bb = b / s, bc = c / s;
            if (k >= PRW_BTF_GRID_C && m >= -PRW_BTF_INSIDE_EPS) break; /* inside: the crossing is in this triangle */
        }
    }
    /* rounding at an edge: the weights clamped to >= 0 and renormalised */
    ba = PRW_BTF_IMAX(ba, 0.0f), bb = PRW_BTF_IMAX(bb, 0.0f), bc = PRW_BTF_IMAX(bc, 0.0f);
    float s = ba + bb + bc;
    w[0] = ba / s, w[1] = bb / s, w[2] = bc / s;
    for (PRW_BTF_IUINT k = 0u; k < 3u; k++) idx[k] = PRW_BTF_TRI_VERT(best * 3u + k) & ~PRW_BTF_HORIZON;
}

/* Light weights from prw_btf_interp_dir's: times cos theta_l / cos theta_k (z: the light's, unit). */
PRW_BTF_IFN void prw_btf_interp_light(PRW_BTF_DT_PARAMS float z, PRW_BTF_IUINT idx[3], PRW_BTF_IINOUT float w[3])
{
    z = PRW_BTF_IMAX(z, 0.0f);
    for (PRW_BTF_IUINT k = 0u; k < 3u; k++) w[k] *= z / PRW_BTF_DIR_COS(idx[k]);
}

/* Continuous texel coordinates (x, y) (texel centres at integer + 0.5, wrap: the BTF tiles) of a
 * width x height BTF: the 4 texels of the bilinear filter and their weights.  Float: callers with
 * large coordinates wrap them into [0, width) x [0, height) first (in double on the CPU). */
PRW_BTF_IFN void prw_btf_interp_texel(float x, float y, PRW_BTF_IUINT width, PRW_BTF_IUINT height,
                                      PRW_BTF_IOUT PRW_BTF_IUINT tx[2], PRW_BTF_IOUT PRW_BTF_IUINT ty[2],
                                      PRW_BTF_IOUT float wx[2], PRW_BTF_IOUT float wy[2])
{
    float fx = x - 0.5f, fy = y - 0.5f;
    float x0 = PRW_BTF_IFLOOR(fx), y0 = PRW_BTF_IFLOOR(fy);
    wx[1] = fx - x0, wx[0] = 1.0f - wx[1];
    wy[1] = fy - y0, wy[0] = 1.0f - wy[1];
    float W = PRW_BTF_ITOF(width), H = PRW_BTF_ITOF(height);
    x0 = x0 - W * PRW_BTF_IFLOOR(x0 / W);
    y0 = y0 - H * PRW_BTF_IFLOOR(y0 / H);
    tx[0] = PRW_BTF_ITOU(PRW_BTF_IMAX(x0, 0.0f)) % width, ty[0] = PRW_BTF_ITOU(PRW_BTF_IMAX(y0, 0.0f)) % height;
    tx[1] = (tx[0] + 1u) % width, ty[1] = (ty[0] + 1u) % height;
}

#endif
