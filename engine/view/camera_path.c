/* camera_path.c — camera-path files (cJSON), the recorder, interpolation and fixed-step playback.
 * The interpolation scheme is stated in prw_camera_path.h; this file follows it. */
#define _POSIX_C_SOURCE 200809L
#include "prw_camera_path.h"
#include "prw_strbuf.h"
#include "prw_json_doc.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_scene.h" /* prw_quat_from_axes: the scene's camera frame */

#define COORD_LIMIT 1e9 /* metres */
#define TIME_LIMIT 1e9  /* seconds */
#define FPS_MAX 1000.0
#define YFOV_MAX_DEG 180.0
#define IPD_MAX_M 0.2
#define QUAT_UNIT_TOL 1e-3
#define PLACE_MAX 160

/* ---------------------------------------------------------------- quaternions */

static prw_dquat q_make(double x, double y, double z, double w)
{
    prw_dquat q = {x, y, z, w};
    return q;
}

static prw_dquat q_mul(prw_dquat a, prw_dquat b)
{
    return q_make(a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                  a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}

static prw_dquat q_conj(prw_dquat a) { return q_make(-a.x, -a.y, -a.z, a.w); }
static double q_dot(prw_dquat a, prw_dquat b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }

/* log of a unit quaternion: the pure quaternion v * theta (theta in [0, pi]) as a vector. */
static prw_dvec3 q_log(prw_dquat q)
{
    double s = sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(s > 0)) return prw_v3(0, 0, 0);
    double k = atan2(s, q.w) / s;
    return prw_v3(q.x * k, q.y * k, q.z * k);
}

static prw_dquat q_exp(prw_dvec3 v)
{
    double a = prw_v3_len(v);
    if (!(a > 0)) return q_make(0, 0, 0, 1);
    double k = sin(a) / a;
    return q_make(v.x * k, v.y * k, v.z * k, cos(a));
}

/* a * exp(w * log(a^-1 b)): the geodesic from a (w = 0, exactly a) to b, no hemisphere flip. */
static prw_dquat q_slerp(prw_dquat a, prw_dquat b, double w)
{
    return q_mul(a, q_exp(prw_v3_scale(q_log(q_mul(q_conj(a), b)), w)));
}

static prw_dquat q_normalize(prw_dquat q)
{
    double n = sqrt(q_dot(q, q));
    if (!(n > 0) || !isfinite(n)) return q_make(0, 0, 0, 1);
    return q_make(q.x / n, q.y / n, q.z / n, q.w / n);
}

/* ---------------------------------------------------------------- keyframes */

void prw_camera_path_init(prw_camera_path *p, double fps)
{
    memset(p, 0, sizeof *p);
    p->fps = fps;
}

void prw_camera_path_free(prw_camera_path *p)
{
    free(p->keys);
    memset(p, 0, sizeof *p);
}

static bool vec_ok(prw_dvec3 v, double lim)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z) && fabs(v.x) <= lim && fabs(v.y) <= lim &&
           fabs(v.z) <= lim;
}

/* Checks k (the index-th keyframe, prev its predecessor or NULL).  On failure names the field and
 * the reason. */
static bool key_valid(const prw_camera_keyframe *k, const prw_camera_keyframe *prev, const char **field,
                      char *reason, size_t cap)
{
    if (!(isfinite(k->t) && fabs(k->t) <= TIME_LIMIT)) {
        *field = "t";
        snprintf(reason, cap, "must be a finite number with |t| <= %g s", TIME_LIMIT);
        return false;
    }
    if (prev && !(k->t - prev->t >= PRW_CAMERA_PATH_MIN_DT)) {
        *field = "t";
        snprintf(reason, cap, "%.17g must exceed the previous keyframe's time %.17g by at least %g s", k->t,
                 prev->t, PRW_CAMERA_PATH_MIN_DT);
        return false;
    }
    if (!vec_ok(k->position, COORD_LIMIT)) {
        *field = "position";
        snprintf(reason, cap, "must be 3 finite numbers with |x| <= %g", COORD_LIMIT);
        return false;
    }
    prw_dquat q = k->orientation;
    double n = sqrt(q_dot(q, q));
    if (!(isfinite(n) && fabs(n - 1.0) <= QUAT_UNIT_TOL)) {
        *field = "orientation";
        snprintf(reason, cap, "must be a unit quaternion [x, y, z, w] (|q| within %g of 1)", QUAT_UNIT_TOL);
        return false;
    }
    if (!(isfinite(k->yfov_deg) && k->yfov_deg > 0 && k->yfov_deg < YFOV_MAX_DEG)) {
        *field = "yfov_deg";
        snprintf(reason, cap, "must be a finite number > 0 and < %g", YFOV_MAX_DEG);
        return false;
    }
    if (!(isfinite(k->ipd_m) && k->ipd_m >= 0 && k->ipd_m <= IPD_MAX_M)) {
        *field = "ipd_m";
        snprintf(reason, cap, "must be a finite number >= 0 and <= %g", IPD_MAX_M);
        return false;
    }
    return true;
}

/* Appends an already validated keyframe: renormalise (only when not unit to rounding, so a saved and
 * reloaded path is bit-identical) and flip into the predecessor's hemisphere. */
static void push_key(prw_camera_path *p, const prw_camera_keyframe *k)
{
    if (p->count == p->capacity) {
        uint32_t cap = p->capacity ? p->capacity * 2 : 16;
        p->keys = prw_realloc(p->keys, (size_t)cap * sizeof *p->keys);
        p->capacity = cap;
    }
    prw_camera_keyframe c = *k;
    if (fabs(q_dot(c.orientation, c.orientation) - 1.0) > 1e-14) c.orientation = q_normalize(c.orientation);
    if (p->count && q_dot(p->keys[p->count - 1].orientation, c.orientation) < 0)
        c.orientation = q_make(-c.orientation.x, -c.orientation.y, -c.orientation.z, -c.orientation.w);
    p->keys[p->count++] = c;
}

bool prw_camera_path_append(prw_camera_path *p, const prw_camera_keyframe *k, const char *who, prw_error *e)
{
    if (!who) who = "camera path";
    if (p->count >= PRW_CAMERA_PATH_MAX_KEYS)
        return prw_fail(e, "%s:keyframe %u: too many keyframes (at most %u)", who, p->count,
                        PRW_CAMERA_PATH_MAX_KEYS);
    const char *field = "";
    char reason[256];
    if (!key_valid(k, p->count ? &p->keys[p->count - 1] : NULL, &field, reason, sizeof reason))
        return prw_fail(e, "%s:keyframe %u.%s: %s", who, p->count, field, reason);
    push_key(p, k);
    return true;
}

bool prw_camera_path_record(prw_camera_path *p, double t, prw_dvec3 position, prw_dquat orientation, double yfov,
                            prw_error *e)
{
    prw_camera_keyframe k;
    k.t = t;
    k.position = position;
    k.orientation = orientation;
    k.yfov_deg = yfov * (180.0 / PRW_PI);
    k.ipd_m = p->count ? p->keys[p->count - 1].ipd_m : PRW_CAMERA_PATH_DEFAULT_IPD_M;
    return prw_camera_path_append(p, &k, "recorder", e);
}

bool prw_camera_orientation_look_at(prw_dvec3 position, prw_dvec3 target, prw_dvec3 up, prw_dquat *out,
                                    prw_error *e)
{
    prw_dvec3 z = prw_v3_sub(position, target); /* the camera looks down -Z */
    double lz = prw_v3_len(z);
    if (!(lz > 1e-9 * (1.0 + prw_v3_len(position))) || !isfinite(lz))
        return prw_fail(e, "look_at: the target must differ from the position");
    z = prw_v3_scale(z, 1.0 / lz);
    double lu = prw_v3_len(up);
    if (!(lu > 0) || !isfinite(lu)) return prw_fail(e, "look_at: 'up' must be a non-zero finite vector");
    prw_dvec3 x = prw_v3_cross(prw_v3_scale(up, 1.0 / lu), z);
    double lx = prw_v3_len(x);
    if (!(lx >= 1e-6)) return prw_fail(e, "look_at: 'up' must not be parallel to the view direction");
    x = prw_v3_scale(x, 1.0 / lx);
    prw_dvec3 y = prw_v3_cross(z, x);
    *out = prw_quat_from_axes(x, y, z);
    return true;
}

/* ---------------------------------------------------------------- parsing */

typedef prw_json_ctx ctx;


static const cJSON *item(const cJSON *obj, const char *key) { return cJSON_GetObjectItemCaseSensitive(obj, key); }

/* Optional number in (lo, hi) / [lo, hi]; *present tells whether it was there. */
static bool get_num(ctx *c, const cJSON *obj, const char *key, const char *place, double *out, bool required,
                    double lo, bool lo_open, double hi, bool hi_open)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    if (!v) return required ? prw_json_fail_at(c, p, "missing (required)") : true;
    double x = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    bool ok = isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    if (!ok)
        return prw_json_fail_at(c, p, "must be a finite number %s %g and %s %g", lo_open ? ">" : ">=", lo,
                       hi_open ? "<" : "<=", hi);
    *out = x;
    return true;
}

static bool get_vec(ctx *c, const cJSON *obj, const char *key, const char *place, double *out, int n, double lim,
                    bool *present)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    *present = v != NULL;
    if (!v) return true;
    bool ok = cJSON_IsArray(v) && cJSON_GetArraySize(v) == n;
    int i = 0;
    for (const cJSON *it = ok ? v->child : NULL; it && ok; it = it->next, i++) {
        double x = cJSON_IsNumber(it) ? it->valuedouble : NAN;
        ok = isfinite(x) && fabs(x) <= lim;
        out[i] = x;
    }
    if (!ok) return prw_json_fail_at(c, p, "must be an array of %d finite numbers with |x| <= %g", n, lim);
    return true;
}

static bool parse_key(ctx *c, const cJSON *o, const char *pl, const prw_camera_keyframe *prev,
                      prw_camera_keyframe *k)
{
    static const char *const keys[] = {"t", "position", "orientation", "look_at", "up", "yfov_deg", "ipd_m"};
    char p[PLACE_MAX];
    if (!prw_json_check_keys(c, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
    k->yfov_deg = prev ? prev->yfov_deg : PRW_CAMERA_PATH_DEFAULT_YFOV_DEG;
    k->ipd_m = prev ? prev->ipd_m : PRW_CAMERA_PATH_DEFAULT_IPD_M;
    if (!get_num(c, o, "t", pl, &k->t, true, -TIME_LIMIT, false, TIME_LIMIT, false)) return false;
    if (prev && !(k->t - prev->t >= PRW_CAMERA_PATH_MIN_DT)) {
        prw_json_join(p, PLACE_MAX, pl, "t");
        return prw_json_fail_at(c, p, "%.17g must exceed the previous keyframe's time %.17g by at least %g s", k->t, prev->t,
                       PRW_CAMERA_PATH_MIN_DT);
    }
    double pos[3], q[4], at[3], up[3] = {0, 1, 0};
    bool has_pos, has_q, has_at, has_up;
    if (!get_vec(c, o, "position", pl, pos, 3, COORD_LIMIT, &has_pos)) return false;
    if (!has_pos) {
        prw_json_join(p, PLACE_MAX, pl, "position");
        return prw_json_fail_at(c, p, "missing (required)");
    }
    k->position = prw_v3(pos[0], pos[1], pos[2]);
    if (!get_vec(c, o, "orientation", pl, q, 4, 2.0, &has_q)) return false;
    if (!get_vec(c, o, "look_at", pl, at, 3, COORD_LIMIT, &has_at)) return false;
    if (!get_vec(c, o, "up", pl, up, 3, COORD_LIMIT, &has_up)) return false;
    if (has_q && has_at) return prw_json_fail_at(c, pl, "give either 'orientation' or 'look_at', not both");
    if (!has_q && !has_at) return prw_json_fail_at(c, pl, "needs 'orientation' or 'look_at'");
    if (has_up && !has_at) {
        prw_json_join(p, PLACE_MAX, pl, "up");
        return prw_json_fail_at(c, p, "only applies together with 'look_at'");
    }
    if (has_q) {
        double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(fabs(n - 1.0) <= QUAT_UNIT_TOL)) {
            prw_json_join(p, PLACE_MAX, pl, "orientation");
            return prw_json_fail_at(c, p, "must be a unit quaternion [x, y, z, w] (|q| = %.9g, not within %g of 1)", n,
                           QUAT_UNIT_TOL);
        }
        k->orientation = q_make(q[0], q[1], q[2], q[3]);
    } else {
        prw_error le;
        if (!prw_camera_orientation_look_at(k->position, prw_v3(at[0], at[1], at[2]), prw_v3(up[0], up[1], up[2]),
                                            &k->orientation, &le)) {
            prw_json_join(p, PLACE_MAX, pl, strstr(le.msg, "'up'") ? "up" : "look_at");
            const char *reason = strchr(le.msg, ':');
            return prw_json_fail_at(c, p, "%s", reason ? reason + 2 : le.msg);
        }
    }
    if (!get_num(c, o, "yfov_deg", pl, &k->yfov_deg, false, 0, true, YFOV_MAX_DEG, true)) return false;
    if (!get_num(c, o, "ipd_m", pl, &k->ipd_m, false, 0, false, IPD_MAX_M, false)) return false;
    return true;
}

static bool parse_root(ctx *c, const cJSON *root, prw_camera_path *out)
{
    static const char *const keys[] = {"prw_camera_path", "fps", "keyframes"};
    if (!cJSON_IsObject(root)) return prw_json_fail_at(c, "", "top level must be a JSON object");
    if (!prw_json_check_keys(c, root, "", keys, (int)PRW_ARRAY_LEN(keys))) return false;
    const cJSON *v = item(root, "prw_camera_path");
    if (!v) return prw_json_fail_at(c, "prw_camera_path", "missing (required; this reader understands version 1)");
    if (!cJSON_IsNumber(v) || v->valuedouble != (double)PRW_CAMERA_PATH_VERSION)
        return prw_json_fail_at(c, "prw_camera_path", "unsupported version (this reader understands 1)");
    double fps = 0;
    if (!get_num(c, root, "fps", "", &fps, false, 0, true, FPS_MAX, false)) return false;
    out->fps = fps;
    const cJSON *arr = item(root, "keyframes");
    if (!arr) return prw_json_fail_at(c, "keyframes", "missing (required)");
    if (!cJSON_IsArray(arr)) return prw_json_fail_at(c, "keyframes", "must be an array of objects");
    int n = cJSON_GetArraySize(arr);
    if (n < 2) return prw_json_fail_at(c, "keyframes", "needs at least 2 keyframes (has %d)", n);
    if ((unsigned)n > PRW_CAMERA_PATH_MAX_KEYS)
        return prw_json_fail_at(c, "keyframes", "too many keyframes (%d; at most %u)", n, PRW_CAMERA_PATH_MAX_KEYS);
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        char pl[PLACE_MAX];
        snprintf(pl, sizeof pl, "keyframes[%d]", i);
        if (!cJSON_IsObject(it)) return prw_json_fail_at(c, pl, "must be an object");
        prw_camera_keyframe k;
        if (!parse_key(c, it, pl, out->count ? &out->keys[out->count - 1] : NULL, &k)) return false;
        const char *field = "";
        char reason[256];
        if (!key_valid(&k, out->count ? &out->keys[out->count - 1] : NULL, &field, reason, sizeof reason)) {
            char p[PLACE_MAX];
            prw_json_join(p, PLACE_MAX, pl, field);
            return prw_json_fail_at(c, p, "%s", reason);
        }
        push_key(out, &k);
    }
    return true;
}

bool prw_camera_path_parse(const char *text, size_t size, const char *name, prw_camera_path *out, prw_error *e)
{
    ctx c = {name ? name : "(camera path)", e};
    prw_camera_path_init(out, 0);
    if (!text) return prw_json_fail_at(&c, "", "no camera-path text");
    cJSON *root = prw_json_doc_parse(text, size, c.file, e);
    if (!root) return false;
    bool ok = parse_root(&c, root, out);
    cJSON_Delete(root);
    if (!ok) prw_camera_path_free(out);
    return ok;
}

bool prw_camera_path_load(const char *path, prw_camera_path *out, prw_error *e)
{
    prw_camera_path_init(out, 0);
    char *text = NULL;
    size_t size = 0;
    /* no fixed limit (10^6 keyframes are allowed): the JSON tree must fit the memory budget */
    if (!prw_read_file_bounded(path, 0, PRW_JSON_MEMORY_PER_BYTE, "a camera path", &text, &size, e)) return false;
    bool ok = prw_camera_path_parse(text, size, path, out, e);
    free(text);
    return ok;
}

/* ---------------------------------------------------------------- writing */

bool prw_camera_path_to_json(const prw_camera_path *p, char **text, size_t *size, prw_error *e)
{
    if (p->count < 2) return prw_fail(e, "camera path: needs at least 2 keyframes to save (has %u)", p->count);
    prw_strbuf b = {prw_malloc(4096), 0, 4096};
    b.p[0] = '\0';
    prw_strbuf_printf(&b, "{\n  \"prw_camera_path\": %d,\n", PRW_CAMERA_PATH_VERSION);
    if (p->fps != 0) prw_strbuf_printf(&b, "  \"fps\": %.17g,\n", p->fps);
    prw_strbuf_printf(&b, "  \"keyframes\": [\n");
    for (uint32_t i = 0; i < p->count; i++) {
        const prw_camera_keyframe *k = &p->keys[i];
        prw_strbuf_printf(&b,
                  "    {\"t\": %.17g, \"position\": [%.17g, %.17g, %.17g], "
                  "\"orientation\": [%.17g, %.17g, %.17g, %.17g], \"yfov_deg\": %.17g, \"ipd_m\": %.17g}%s\n",
                  k->t, k->position.x, k->position.y, k->position.z, k->orientation.x, k->orientation.y,
                  k->orientation.z, k->orientation.w, k->yfov_deg, k->ipd_m, i + 1 < p->count ? "," : "");
    }
    prw_strbuf_printf(&b, "  ]\n}\n");
    *text = b.p;
    if (size) *size = b.n;
    return true;
}

bool prw_camera_path_save(const prw_camera_path *p, const char *path, prw_error *e)
{
    char *text = NULL;
    size_t n = 0;
    if (!prw_camera_path_to_json(p, &text, &n, e)) return prw_fail_wrap(e, "%s", path);
    bool ok = prw_write_file_atomic(path, text, n, e);
    free(text);
    return ok;
}

/* ---------------------------------------------------------------- interpolation */

double prw_camera_path_duration(const prw_camera_path *p)
{
    return p->count >= 2 ? p->keys[p->count - 1].t - p->keys[0].t : 0.0;
}

/* Velocity at an interior keyframe i (0 < i < n-1): centripetal Catmull-Rom dP/du times the mean
 * adjacent du/dt.  With A = P_i - P_i-1, B = P_i+1 - P_i, d0 = |A|^.5, d1 = |B|^.5 the Barry-Goldman
 * derivative A/d0 - (A+B)/(d0+d1) + B/d1 is written without cancellation. */
static prw_dvec3 interior_velocity(const prw_camera_keyframe *k, uint32_t i)
{
    prw_dvec3 A = prw_v3_sub(k[i].position, k[i - 1].position);
    prw_dvec3 B = prw_v3_sub(k[i + 1].position, k[i].position);
    double d0 = sqrt(prw_v3_len(A)), d1 = sqrt(prw_v3_len(B));
    if (!(d0 > 0) || !(d1 > 0)) return prw_v3(0, 0, 0);
    double s = d0 + d1;
    prw_dvec3 m = prw_v3_add(prw_v3_scale(A, d1 / (d0 * s)), prw_v3_scale(B, d0 / (d1 * s)));
    double rate = 0.5 * (d0 / (k[i].t - k[i - 1].t) + d1 / (k[i + 1].t - k[i].t));
    return prw_v3_scale(m, rate);
}

static prw_dvec3 key_velocity(const prw_camera_path *p, uint32_t i)
{
    const prw_camera_keyframe *k = p->keys;
    uint32_t n = p->count;
    if (n == 2) return prw_v3_scale(prw_v3_sub(k[1].position, k[0].position), 1.0 / (k[1].t - k[0].t));
    if (i > 0 && i < n - 1) return interior_velocity(k, i);
    /* natural end: zero acceleration at the end keyframe */
    uint32_t a = i == 0 ? 0 : n - 2, b = a + 1;
    prw_dvec3 chord = prw_v3_scale(prw_v3_sub(k[b].position, k[a].position), 3.0 / (k[b].t - k[a].t));
    prw_dvec3 other = interior_velocity(k, i == 0 ? 1 : n - 2);
    return prw_v3_scale(prw_v3_sub(chord, other), 0.5);
}

/* Segment index i (0 <= i <= n-2) holding t: t_i <= t < t_i+1 (side >= 0) or t_i < t <= t_i+1. */
static uint32_t find_segment(const prw_camera_path *p, double t, int side)
{
    uint32_t lo = 0, hi = p->count - 1; /* answer in [lo, hi - 1] */
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        bool right = side >= 0 ? p->keys[mid].t <= t : p->keys[mid].t < t;
        if (right) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* Intermediate squad quaternion at key i for the segment on its right (+1) or left (-1). */
static prw_dquat squad_control(const prw_camera_path *p, uint32_t i, int side)
{
    const prw_camera_keyframe *k = p->keys;
    if (i == 0 || i == p->count - 1) return k[i].orientation;
    prw_dquat qi = k[i].orientation, inv = q_conj(qi);
    prw_dvec3 lp = q_log(q_mul(inv, k[i + 1].orientation));
    prw_dvec3 lm = q_log(q_mul(inv, k[i - 1].orientation));
    double dtm = k[i].t - k[i - 1].t, dtp = k[i + 1].t - k[i].t;
    prw_dvec3 T = prw_v3_scale(prw_v3_sub(lp, lm), 1.0 / (dtm + dtp));
    prw_dvec3 x = side > 0 ? prw_v3_scale(prw_v3_sub(prw_v3_scale(T, dtp), lp), 0.5)
                           : prw_v3_scale(prw_v3_add(lm, prw_v3_scale(T, dtm)), -0.5);
    return q_mul(qi, q_exp(x));
}

static prw_dquat orientation_in(const prw_camera_path *p, uint32_t i, double h)
{
    prw_dquat q0 = p->keys[i].orientation, q1 = p->keys[i + 1].orientation;
    prw_dquat s0 = squad_control(p, i, +1), s1 = squad_control(p, i + 1, -1);
    return q_normalize(q_slerp(q_slerp(q0, q1, h), q_slerp(s0, s1, h), 2.0 * h * (1.0 - h)));
}

static prw_dvec3 position_in(const prw_camera_path *p, uint32_t i, double h)
{
    const prw_camera_keyframe *a = &p->keys[i], *b = &p->keys[i + 1];
    if (h == 0) return a->position; /* bit-exact at the keyframe (also keeps -0.0) */
    double dt = b->t - a->t, h2 = h * h, h3 = h2 * h;
    double h10 = h3 - 2 * h2 + h, h01 = -2 * h3 + 3 * h2, h11 = h3 - h2;
    prw_dvec3 v0 = key_velocity(p, i), v1 = key_velocity(p, i + 1);
    prw_dvec3 off = prw_v3_add(prw_v3_scale(prw_v3_sub(b->position, a->position), h01),
                               prw_v3_scale(prw_v3_add(prw_v3_scale(v0, h10), prw_v3_scale(v1, h11)), dt));
    return prw_v3_add(a->position, off);
}

static prw_dvec3 velocity_in(const prw_camera_path *p, uint32_t i, double h)
{
    const prw_camera_keyframe *a = &p->keys[i], *b = &p->keys[i + 1];
    double dt = b->t - a->t, h2 = h * h;
    double d10 = 3 * h2 - 4 * h + 1, d01 = 6 * h - 6 * h2, d11 = 3 * h2 - 2 * h;
    prw_dvec3 v0 = key_velocity(p, i), v1 = key_velocity(p, i + 1);
    prw_dvec3 r = prw_v3_scale(prw_v3_sub(b->position, a->position), d01 / dt);
    return prw_v3_add(r, prw_v3_add(prw_v3_scale(v0, d10), prw_v3_scale(v1, d11)));
}

/* Segment and local parameter for t, clamped to the path. */
static uint32_t locate(const prw_camera_path *p, double t, int side, double *h)
{
    uint32_t n = p->count;
    if (!(t > p->keys[0].t)) {
        *h = 0;
        return 0;
    }
    if (!(t < p->keys[n - 1].t)) {
        *h = 1;
        return n - 2;
    }
    uint32_t i = find_segment(p, t, side);
    *h = (t - p->keys[i].t) / (p->keys[i + 1].t - p->keys[i].t);
    if (*h > 1) *h = 1;
    if (*h < 0) *h = 0;
    return i;
}

prw_dvec3 prw_camera_path_position(const prw_camera_path *p, double t)
{
    if (p->count == 0) return prw_v3(0, 0, 0);
    if (p->count == 1) return p->keys[0].position;
    if (!(t < p->keys[p->count - 1].t)) return p->keys[p->count - 1].position;
    double h;
    uint32_t i = locate(p, t, +1, &h);
    return position_in(p, i, h);
}

prw_dquat prw_camera_path_orientation(const prw_camera_path *p, double t)
{
    if (p->count == 0) return q_make(0, 0, 0, 1);
    if (p->count == 1) return p->keys[0].orientation;
    if (!(t < p->keys[p->count - 1].t)) return p->keys[p->count - 1].orientation;
    double h;
    uint32_t i = locate(p, t, +1, &h);
    return orientation_in(p, i, h);
}

prw_dvec3 prw_camera_path_velocity(const prw_camera_path *p, double t, int side)
{
    if (p->count < 2) return prw_v3(0, 0, 0);
    double t0 = p->keys[0].t, t1 = p->keys[p->count - 1].t;
    if (t < t0 || t > t1 || isnan(t)) return prw_v3(0, 0, 0);
    double h;
    uint32_t i = locate(p, t, side, &h);
    return velocity_in(p, i, h);
}

prw_camera_sample prw_camera_path_eval(const prw_camera_path *p, double t)
{
    prw_camera_sample s;
    const prw_camera_keyframe *last = p->count ? &p->keys[p->count - 1] : NULL;
    s.t = t;
    s.position = prw_camera_path_position(p, t);
    s.orientation = prw_camera_path_orientation(p, t);
    s.velocity = prw_camera_path_velocity(p, t, +1);
    if (p->count < 2) {
        s.yfov = (p->count ? last->yfov_deg : PRW_CAMERA_PATH_DEFAULT_YFOV_DEG) * (PRW_PI / 180.0);
        s.ipd_m = p->count ? last->ipd_m : PRW_CAMERA_PATH_DEFAULT_IPD_M;
        return s;
    }
    double h;
    uint32_t i = locate(p, t, +1, &h);
    const prw_camera_keyframe *a = &p->keys[i], *b = &p->keys[i + 1];
    double fov = a->yfov_deg + (b->yfov_deg - a->yfov_deg) * h, ipd = a->ipd_m + (b->ipd_m - a->ipd_m) * h;
    if (!(t < last->t)) {
        fov = last->yfov_deg;
        ipd = last->ipd_m;
    }
    s.yfov = fov * (PRW_PI / 180.0);
    s.ipd_m = ipd;
    return s;
}

/* ---------------------------------------------------------------- playback */

double prw_camera_path_fps(const prw_camera_path *p) { return p->fps > 0 ? p->fps : PRW_CAMERA_PATH_DEFAULT_FPS; }

uint64_t prw_camera_path_frame_count(const prw_camera_path *p)
{
    if (p->count < 2) return 0;
    double x = prw_camera_path_duration(p) * prw_camera_path_fps(p);
    return (uint64_t)floor(x + 1e-9) + 1;
}

double prw_camera_path_frame_time(const prw_camera_path *p, uint64_t k)
{
    if (p->count == 0) return 0.0;
    double t = p->keys[0].t + (double)k / prw_camera_path_fps(p);
    double end = p->keys[p->count - 1].t;
    return t < end ? t : end;
}

prw_view prw_camera_sample_view(const prw_camera_sample *s, uint32_t width, uint32_t height, double znear,
                                double ev100, int eye)
{
    prw_dmat4 r = prw_dm4_trs(prw_v3(0, 0, 0), s->orientation, prw_v3(1, 1, 1));
    prw_dvec3 x = prw_v3(r.m[0], r.m[1], r.m[2]), y = prw_v3(r.m[4], r.m[5], r.m[6]),
              z = prw_v3(r.m[8], r.m[9], r.m[10]);
    prw_dvec3 pos = s->position;
    if (eye) pos = prw_v3_add(pos, prw_v3_scale(x, (eye < 0 ? -0.5 : 0.5) * s->ipd_m));
    prw_view v;
    memset(&v, 0, sizeof v);
    v.eye = pos;
    v.view = prw_dm4_identity();
    v.view.m[0] = x.x; v.view.m[4] = x.y; v.view.m[8] = x.z;
    v.view.m[1] = y.x; v.view.m[5] = y.y; v.view.m[9] = y.z;
    v.view.m[2] = z.x; v.view.m[6] = z.y; v.view.m[10] = z.z;
    v.view.m[12] = -prw_v3_dot(x, pos);
    v.view.m[13] = -prw_v3_dot(y, pos);
    v.view.m[14] = -prw_v3_dot(z, pos);
    double ty = tan(0.5 * s->yfov);
    double tx = ty * (double)width / (double)height;
    v.tan_left = -tx;
    v.tan_right = tx;
    v.tan_bottom = -ty;
    v.tan_top = ty;
    v.znear = znear;
    v.width = width;
    v.height = height;
    v.ev100 = ev100;
    return v;
}

bool prw_camera_path_frame_view(const prw_camera_path *p, uint64_t k, uint32_t width, uint32_t height,
                                double znear, double ev100, int eye, prw_view *out, prw_error *e)
{
    uint64_t n = prw_camera_path_frame_count(p);
    if (k >= n)
        return prw_fail(e, "camera path: frame %llu does not exist (the path has %llu frames)", (unsigned long long)k,
                        (unsigned long long)n);
    if (width == 0 || height == 0) return prw_fail(e, "camera path: image size %ux%u is empty", width, height);
    if (!(znear > 0) || !isfinite(znear)) return prw_fail(e, "camera path: znear %g must be > 0", znear);
    prw_camera_sample s = prw_camera_path_eval(p, prw_camera_path_frame_time(p, k));
    *out = prw_camera_sample_view(&s, width, height, znear, ev100, eye);
    return true;
}

bool prw_camera_path_sniff(const char *path)
{
    char *text = NULL;
    size_t size = 0;
    prw_error ignored;
    if (!path || !prw_read_file_bounded(path, 0, PRW_JSON_MEMORY_PER_BYTE, "a camera path", &text, &size, &ignored))
        return false;
    cJSON *root = cJSON_ParseWithLength(text, size);
    /* a document that does not parse still counts when it names the key: its reader reports the error */
    bool yes = root ? cJSON_IsObject(root) && cJSON_GetObjectItemCaseSensitive(root, "prw_camera_path") != NULL
                    : strstr(text, "\"prw_camera_path\"") != NULL;
    cJSON_Delete(root);
    free(text);
    return yes;
}
