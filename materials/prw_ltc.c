/* prw_ltc — see prw_ltc.h.  Each step mirrors shaders/ltc.glsl and the polygon code of
 * shaders/lights.glsl (lambert_edge, clip_edge) operation by operation. */
#include "prw_ltc.h"

#include <math.h>
#include <stddef.h>

_Static_assert(PRW_LTC_N == 64, "shaders/ltc.glsl assumes a 64 x 64 table (PRW_LTC_TABLE_N)");

const float *prw_ltc_table_texels(void) { return prw_ltc_table_data; }

static float clamp01(float x) { return fminf(fmaxf(x, 0.0f), 1.0f); }

/* texture(sampler2DArray, (u, v, layer)) with linear filtering, clamp to edge */
static void fetch(int layer, float u, float v, float out[4])
{
    const int n = PRW_LTC_N;
    float x = u * (float)n - 0.5f, y = v * (float)n - 0.5f;
    float fx = floorf(x), fy = floorf(y);
    float ax = x - fx, ay = y - fy;
    int x0 = (int)fx, y0 = (int)fy;
    int xs[2] = {x0 < 0 ? 0 : x0 > n - 1 ? n - 1 : x0, x0 + 1 < 0 ? 0 : x0 + 1 > n - 1 ? n - 1 : x0 + 1};
    int ys[2] = {y0 < 0 ? 0 : y0 > n - 1 ? n - 1 : y0, y0 + 1 < 0 ? 0 : y0 + 1 > n - 1 ? n - 1 : y0 + 1};
    const float *t = prw_ltc_table_data + (size_t)layer * n * n * 4;
    for (int k = 0; k < 4; k++) {
        float a = t[(ys[0] * n + xs[0]) * 4 + k], b = t[(ys[0] * n + xs[1]) * 4 + k];
        float c = t[(ys[1] * n + xs[0]) * 4 + k], d = t[(ys[1] * n + xs[1]) * 4 + k];
        out[k] = (a * (1.0f - ax) + b * ax) * (1.0f - ay) + (c * (1.0f - ax) + d * ax) * ay;
    }
}

void prw_ltc_lookup(float roughness, float NoV, float minv[4], float fres[4])
{
    const float n = (float)PRW_LTC_N;
    float u = (clamp01(roughness) * (n - 1.0f) + 0.5f) / n;
    float v = (sqrtf(1.0f - clamp01(NoV)) * (n - 1.0f) + 0.5f) / n;
    fetch(0, u, v, minv);
    fetch(1, u, v, fres);
}

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void lambert_edge(const float a[3], const float b[3], float out[3])
{
    float la = 1.0f / sqrtf(dot3(a, a)), lb = 1.0f / sqrtf(dot3(b, b));
    float v0[3] = {a[0] * la, a[1] * la, a[2] * la}, v1[3] = {b[0] * lb, b[1] * lb, b[2] * lb};
    float cr[3] = {v0[1] * v1[2] - v0[2] * v1[1], v0[2] * v1[0] - v0[0] * v1[2], v0[0] * v1[1] - v0[1] * v1[0]};
    float l = sqrtf(dot3(cr, cr));
    float s = l > 1e-9f ? atan2f(l, dot3(v0, v1)) / l : 0.0f;
    for (int i = 0; i < 3; i++) out[i] = cr[i] * s;
}

/* clip_edge with n = +z: the z component of the edge term is all the caller needs */
static void clip_edge_z(const float a[3], const float b[3], float *sum, float exit_pt[3], float entry_pt[3], int *above,
                        int absolute)
{
    float da = a[2], db = b[2];
    int ua = da > 0.0f, ub = db > 0.0f;
    float t = da / (da - db), cut[3];
    for (int i = 0; i < 3; i++) cut[i] = a[i] + (b[i] - a[i]) * t;
    if (ua) (*above)++;
    if (ua && !ub)
        for (int i = 0; i < 3; i++) exit_pt[i] = cut[i];
    if (!ua && ub)
        for (int i = 0; i < 3; i++) entry_pt[i] = cut[i];
    if (ua || ub) {
        float e[3];
        lambert_edge(ua ? a : cut, ub ? b : cut, e);
        *sum += absolute ? fabsf(e[2]) : e[2];
    }
}

static float rect_ggx(const float p[3], const float n[3], const float v[3], const float c[3], const float du[3],
                      const float dv[3], float roughness, float fres_out[4], int absolute)
{
    float NoV = fminf(fmaxf(dot3(n, v), 1e-4f), 1.0f);
    float m[4], f[4];
    prw_ltc_lookup(roughness, NoV, m, f);
    for (int i = 0; i < 4; i++) fres_out[i] = f[i];
    /* the frame (t1, t2, n) */
    float nv = dot3(n, v);
    float t1[3] = {v[0] - n[0] * nv, v[1] - n[1] * nv, v[2] - n[2] * nv};
    float l2 = dot3(t1, t1);
    if (l2 > 1e-12f) {
        float s = 1.0f / sqrtf(l2);
        for (int i = 0; i < 3; i++) t1[i] *= s;
    } else {
        /* v along n: any tangent (the lobe is symmetric about n there) */
        float a[3] = {fabsf(n[0]) < 0.9f ? 1.0f : 0.0f, fabsf(n[0]) < 0.9f ? 0.0f : 1.0f, 0.0f};
        float an = dot3(a, n);
        for (int i = 0; i < 3; i++) t1[i] = a[i] - n[i] * an;
        float s = 1.0f / sqrtf(dot3(t1, t1));
        for (int i = 0; i < 3; i++) t1[i] *= s;
    }
    float t2[3] = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
    float q[4][3];
    const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; k++) {
        float d[3];
        for (int i = 0; i < 3; i++) d[i] = c[i] + du[i] * su[k] + dv[i] * sv[k] - p[i];
        float x = dot3(t1, d), y = dot3(t2, d), z = dot3(n, d);
        q[k][0] = m[0] * x + m[1] * z;
        q[k][1] = y;
        q[k][2] = m[2] * x + m[3] * z;
    }
    float sum = 0.0f, exit_pt[3] = {0, 0, 0}, entry_pt[3] = {0, 0, 0};
    int above = 0;
    clip_edge_z(q[0], q[1], &sum, exit_pt, entry_pt, &above, absolute);
    clip_edge_z(q[1], q[2], &sum, exit_pt, entry_pt, &above, absolute);
    clip_edge_z(q[2], q[3], &sum, exit_pt, entry_pt, &above, absolute);
    clip_edge_z(q[3], q[0], &sum, exit_pt, entry_pt, &above, absolute);
    if (above == 0) return 0.0f;
    if (above < 4) {
        float e[3];
        lambert_edge(exit_pt, entry_pt, e);
        sum += absolute ? fabsf(e[2]) : e[2];
    }
    return fabsf(sum) * (0.5f / 3.14159265358979323846f) * f[0];
}

float prw_ltc_rect_ggx(const float p[3], const float n[3], const float v[3], const float c[3], const float du[3],
                       const float dv[3], float roughness, float fres_out[4])
{
    return rect_ggx(p, n, v, c, du, dv, roughness, fres_out, 0);
}

float prw_ltc_rect_ggx_scale(const float p[3], const float n[3], const float v[3], const float c[3], const float du[3],
                             const float dv[3], float roughness)
{
    float f[4];
    return rect_ggx(p, n, v, c, du, dv, roughness, f, 1);
}

void prw_ltc_rect_specular(const float p[3], const float n[3], const float v[3], const float c[3], const float du[3],
                           const float dv[3], const float base[3], float metallic, float roughness, float specular,
                           float out[3])
{
    float f[4];
    float I = prw_ltc_rect_ggx(p, n, v, c, du, dv, roughness, f);
    float m = clamp01(metallic);
    float diel = (1.0f - m) * clamp01(specular) * f[2];
    for (int i = 0; i < 3; i++) out[i] = I * (diel + m * (base[i] + (1.0f - base[i]) * f[1]));
}
