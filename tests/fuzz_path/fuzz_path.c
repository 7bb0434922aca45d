/* libFuzzer target: the camera-path parser on arbitrary bytes.  Beyond "no crash / no leak / no UB"
 * it checks the contracts: a failure leaves an empty path and a one-line message starting with the
 * file name; a success gives >= 2 keyframes with strictly increasing times and unit,
 * hemisphere-consistent quaternions, the path evaluates to finite poses with unit quaternions
 * (exact at keyframes), the velocity is continuous at interior keyframes, and save -> parse
 * reproduces the path bit for bit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_camera_path.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void die(const char *what, const char *msg)
{
    fprintf(stderr, "fuzz_path: contract violated: %s: %s\n", what, msg);
    abort();
}

static bool finite3(prw_dvec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

static void check_sample(const prw_camera_path *p, double t)
{
    prw_camera_sample s = prw_camera_path_eval(p, t);
    prw_dquat q = s.orientation;
    double n = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!finite3(s.position) || !finite3(s.velocity) || !(fabs(n - 1) <= 1e-12)) die("sample", "not finite/unit");
    if (!(s.yfov > 0 && s.yfov < PRW_PI) || !(s.ipd_m >= 0 && s.ipd_m <= 0.2)) die("sample", "fov/ipd range");
    prw_view v = prw_camera_sample_view(&s, 64, 48, 0.05, 0, 1);
    for (int i = 0; i < 16; i++)
        if (!isfinite(v.view.m[i])) die("view", "not finite");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/path.json";
    static int verbose = -1;
    if (verbose < 0) verbose = getenv("PRW_FUZZ_VERBOSE") != NULL;
    prw_camera_path p;
    prw_error e;
    e.msg[0] = '\0';
    bool ok = prw_camera_path_parse((const char *)data, size, name, &p, &e);
    if (verbose) printf("%s\n", ok ? "accepted" : e.msg);
    if (!ok) {
        if (strncmp(e.msg, name, strlen(name)) != 0 || e.msg[strlen(name)] != ':')
            die("message does not start with the file", e.msg);
        if (strchr(e.msg, '\n')) die("message is not one line", e.msg);
        if (p.count || p.keys) die("failed parse left keyframes behind", e.msg);
        return 0;
    }
    if (p.count < 2) die("fewer than 2 keyframes", "");
    for (uint32_t i = 0; i < p.count; i++) {
        const prw_camera_keyframe *k = &p.keys[i];
        prw_dquat q = k->orientation;
        double n = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        if (!(fabs(n - 1) <= 1e-14)) die("keyframe quaternion not unit", "");
        if (i) {
            const prw_camera_keyframe *a = &p.keys[i - 1];
            if (!(k->t - a->t >= PRW_CAMERA_PATH_MIN_DT)) die("times not increasing", "");
            if (a->orientation.x * q.x + a->orientation.y * q.y + a->orientation.z * q.z + a->orientation.w * q.w < 0)
                die("hemisphere", "");
        }
        prw_camera_sample s = prw_camera_path_eval(&p, k->t);
        if (!(s.position.x == k->position.x && s.position.y == k->position.y && s.position.z == k->position.z))
            die("position not exact at keyframe", "");
        double d = fabs(s.orientation.x - q.x) + fabs(s.orientation.y - q.y) + fabs(s.orientation.z - q.z) +
                   fabs(s.orientation.w - q.w);
        if (!(d <= 1e-12)) die("orientation not exact at keyframe", "");
        check_sample(&p, k->t);
        if (i + 1 < p.count) {
            double dt = p.keys[i + 1].t - k->t;
            check_sample(&p, k->t + 0.5 * dt);
            check_sample(&p, k->t + 0.01 * dt);
        }
        if (i > 0 && i + 1 < p.count) {
            prw_dvec3 vl = prw_camera_path_velocity(&p, k->t, -1), vr = prw_camera_path_velocity(&p, k->t, +1);
            if (memcmp(&vl, &vr, sizeof vl) != 0) die("velocity jump at keyframe", "");
        }
    }
    check_sample(&p, -INFINITY);
    check_sample(&p, NAN);
    uint64_t frames = prw_camera_path_frame_count(&p);
    if (frames < 1) die("no frames", "");
    prw_view v;
    if (!prw_camera_path_frame_view(&p, frames - 1, 16, 16, 0.05, 0, -1, &v, &e)) die("last frame", e.msg);
    char *text = NULL;
    size_t n = 0;
    if (!prw_camera_path_to_json(&p, &text, &n, &e)) die("to_json", e.msg);
    prw_camera_path r;
    if (!prw_camera_path_parse(text, n, name, &r, &e)) die("reparse", e.msg);
    if (r.count != p.count || memcmp(&r.fps, &p.fps, sizeof r.fps) != 0 ||
        memcmp(r.keys, p.keys, p.count * sizeof *p.keys) != 0)
        die("round trip", "differs");
    free(text);
    prw_camera_path_free(&r);
    prw_camera_path_free(&p);
    return 0;
}
