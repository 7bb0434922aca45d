/* libFuzzer target (replayed by ctest as stereo_fuzz_hmd_replay): the HMD-profile parser on arbitrary
 * bytes.  Beyond "no crash": a failure is one line starting with the file name; a success passes
 * prw_hmd_validate, its eye FOVs are finite and mirrored, and the lens inverse round-trips the eye's
 * panel-half corners and edge midpoints. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_hmd.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void die(const char *what, const char *msg)
{
    fprintf(stderr, "fuzz_hmd: contract violated: %s: %s\n", what, msg);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/hmd.json";
    prw_error e = {{0}};
    prw_hmd h;
    if (!prw_hmd_parse((const char *)data, size, name, &h, &e)) {
        if (strncmp(e.msg, name, strlen(name)) != 0 || strchr(e.msg, '\n')) die("error message", e.msg);
        return 0;
    }
    if (!prw_hmd_validate(&h, name, &e)) die("validate after parse", e.msg);
    prw_fov f[2];
    prw_hmd_eye_fov(&h, 0, &f[0]);
    prw_hmd_eye_fov(&h, 1, &f[1]);
    if (!(isfinite(f[0].angle_left) && isfinite(f[0].angle_up) && f[0].angle_left == -f[1].angle_right))
        die("fov", h.name);
    double R = prw_hmd_lens_unit(&h);
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 9; k++) {
            double X = -0.5 * h.screen_width * (k % 3) / 2.0, Y = 0.5 * h.screen_height * ((k / 3) - 1);
            double px = (X - prw_hmd_lens_centre_x(&h, 0)) / R, py = Y / R, qx, qy, rx, ry;
            prw_lens_forward(&h, c, px, py, &qx, &qy);
            if (!prw_lens_inverse(&h, c, qx, qy, &rx, &ry) || !(hypot(rx - px, ry - py) <= 1e-9 * (1 + hypot(px, py))))
                die("lens inverse", h.name);
        }
    return 0;
}
