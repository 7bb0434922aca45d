/* prw_math — small vector/matrix types for the CPU side.
 *
 * Promises: world-space work in double (prw_dvec3, prw_dmat4, prw_dquat); prw_mat4 (float) is
 * only for what goes to the GPU, built camera-relative so floats stay precise far from the
 * origin.  Matrices are column-major (m[col*4+row]) as GLSL expects, acting on column vectors.
 * Projection: Vulkan clip space (y down in NDC, depth 0..1) with reversed Z (near -> 1, far -> 0).
 */
#ifndef PRW_MATH_H
#define PRW_MATH_H

#include <math.h>
#include <stdbool.h>
#include <string.h>

#define PRW_PI 3.14159265358979323846

typedef struct prw_dvec3 { double x, y, z; } prw_dvec3;
typedef struct prw_dquat { double x, y, z, w; } prw_dquat; /* unit quaternion, glTF order */
typedef struct prw_dmat4 { double m[16]; } prw_dmat4;
typedef struct prw_mat4 { float m[16]; } prw_mat4;

static inline prw_dvec3 prw_v3(double x, double y, double z) { prw_dvec3 r = {x, y, z}; return r; }
static inline prw_dvec3 prw_v3_add(prw_dvec3 a, prw_dvec3 b) { return prw_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline prw_dvec3 prw_v3_sub(prw_dvec3 a, prw_dvec3 b) { return prw_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline prw_dvec3 prw_v3_scale(prw_dvec3 a, double s) { return prw_v3(a.x * s, a.y * s, a.z * s); }
static inline double prw_v3_dot(prw_dvec3 a, prw_dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline prw_dvec3 prw_v3_cross(prw_dvec3 a, prw_dvec3 b)
{
    return prw_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double prw_v3_len(prw_dvec3 a) { return sqrt(prw_v3_dot(a, a)); }
static inline prw_dvec3 prw_v3_norm(prw_dvec3 a)
{
    double l = prw_v3_len(a);
    return l > 0 ? prw_v3_scale(a, 1.0 / l) : a;
}
static inline prw_dvec3 prw_v3_min(prw_dvec3 a, prw_dvec3 b)
{
    return prw_v3(fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z));
}
static inline prw_dvec3 prw_v3_max(prw_dvec3 a, prw_dvec3 b)
{
    return prw_v3(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z));
}

static inline prw_dmat4 prw_dm4_identity(void)
{
    prw_dmat4 r;
    memset(&r, 0, sizeof r);
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
    return r;
}

static inline prw_dmat4 prw_dm4_mul(prw_dmat4 a, prw_dmat4 b)
{
    prw_dmat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

static inline prw_dvec3 prw_dm4_point(prw_dmat4 a, prw_dvec3 p)
{
    return prw_v3(a.m[0] * p.x + a.m[4] * p.y + a.m[8] * p.z + a.m[12],
                  a.m[1] * p.x + a.m[5] * p.y + a.m[9] * p.z + a.m[13],
                  a.m[2] * p.x + a.m[6] * p.y + a.m[10] * p.z + a.m[14]);
}

static inline prw_dvec3 prw_dm4_dir(prw_dmat4 a, prw_dvec3 p)
{
    return prw_v3(a.m[0] * p.x + a.m[4] * p.y + a.m[8] * p.z, a.m[1] * p.x + a.m[5] * p.y + a.m[9] * p.z,
                  a.m[2] * p.x + a.m[6] * p.y + a.m[10] * p.z);
}

/* T * R * S, as glTF composes a node's local matrix. */
static inline prw_dmat4 prw_dm4_trs(prw_dvec3 t, prw_dquat q, prw_dvec3 s)
{
    double x = q.x, y = q.y, z = q.z, w = q.w;
    prw_dmat4 r = prw_dm4_identity();
    r.m[0] = (1 - 2 * (y * y + z * z)) * s.x;
    r.m[1] = (2 * (x * y + z * w)) * s.x;
    r.m[2] = (2 * (x * z - y * w)) * s.x;
    r.m[4] = (2 * (x * y - z * w)) * s.y;
    r.m[5] = (1 - 2 * (x * x + z * z)) * s.y;
    r.m[6] = (2 * (y * z + x * w)) * s.y;
    r.m[8] = (2 * (x * z + y * w)) * s.z;
    r.m[9] = (2 * (y * z - x * w)) * s.z;
    r.m[10] = (1 - 2 * (x * x + y * y)) * s.z;
    r.m[12] = t.x;
    r.m[13] = t.y;
    r.m[14] = t.z;
    return r;
}

/* General 4x4 inverse by cofactors; returns false when singular. */
static inline bool prw_dm4_inverse(prw_dmat4 a, prw_dmat4 *out)
{
    const double *m = a.m;
    double inv[16];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0.0 || !isfinite(det)) return false;
    for (int i = 0; i < 16; i++) out->m[i] = inv[i] / det;
    return true;
}

static inline prw_mat4 prw_m4_from_d(prw_dmat4 a)
{
    prw_mat4 r;
    for (int i = 0; i < 16; i++) r.m[i] = (float)a.m[i];
    return r;
}

/* View matrix (world -> eye, eye looks down -Z, +Y up) for an eye at `eye`, expressed relative to
 * `origin` (the camera-relative frame).  Passing origin = eye gives a rotation-only matrix. */
static inline prw_dmat4 prw_dm4_look_at(prw_dvec3 eye, prw_dvec3 target, prw_dvec3 up)
{
    prw_dvec3 f = prw_v3_norm(prw_v3_sub(target, eye));
    prw_dvec3 s = prw_v3_norm(prw_v3_cross(f, up));
    prw_dvec3 u = prw_v3_cross(s, f);
    prw_dmat4 r = prw_dm4_identity();
    r.m[0] = s.x; r.m[4] = s.y; r.m[8] = s.z;
    r.m[1] = u.x; r.m[5] = u.y; r.m[9] = u.z;
    r.m[2] = -f.x; r.m[6] = -f.y; r.m[10] = -f.z;
    r.m[12] = -prw_v3_dot(s, eye);
    r.m[13] = -prw_v3_dot(u, eye);
    r.m[14] = prw_v3_dot(f, eye);
    return r;
}

/* Off-axis perspective with reversed Z and infinite far plane, Vulkan conventions:
 * eye space (-Z forward, +Y up) -> clip with NDC y pointing down (row 0 of the image at the top)
 * and depth = near / z_eye_distance (1 at the near plane, -> 0 at infinity).
 * l,r,b,t are the frustum's tangents (tan of the half-angles, signed) at unit distance. */
static inline prw_dmat4 prw_dm4_frustum_rev_inf(double l, double r, double b, double t, double znear)
{
    prw_dmat4 m;
    memset(&m, 0, sizeof m);
    m.m[0] = 2.0 / (r - l);
    m.m[8] = (r + l) / (r - l);
    m.m[5] = -2.0 / (t - b);            /* flip y: Vulkan NDC +y is down */
    m.m[9] = -(t + b) / (t - b);
    m.m[10] = 0.0;
    m.m[14] = znear;
    m.m[11] = -1.0;
    return m;
}

/* Same with a finite far plane (reversed: near -> 1, far -> 0). */
static inline prw_dmat4 prw_dm4_frustum_rev(double l, double r, double b, double t, double znear, double zfar)
{
    prw_dmat4 m = prw_dm4_frustum_rev_inf(l, r, b, t, znear);
    m.m[10] = znear / (zfar - znear);
    m.m[14] = znear * zfar / (zfar - znear);
    return m;
}

/* Orthographic, reversed Z: eye z = -znear -> 1, z = -zfar -> 0. */
static inline prw_dmat4 prw_dm4_ortho_rev(double l, double r, double b, double t, double znear, double zfar)
{
    prw_dmat4 m = prw_dm4_identity();
    m.m[0] = 2.0 / (r - l);
    m.m[12] = -(r + l) / (r - l);
    m.m[5] = -2.0 / (t - b);
    m.m[13] = (t + b) / (t - b);
    m.m[10] = 1.0 / (zfar - znear);
    m.m[14] = zfar / (zfar - znear);
    return m;
}

#endif
