/* walk_path_compare A.json B.json POS_TOL_M ANG_TOL_DEG MIN_MATCHES MIN_MOVE_M
 * Must-show 5 checker: for every keyframe time t of path A inside B's time range, B evaluated at t
 * (prw_camera_path_eval: B's own keyframe when t is one of its times) must be within POS_TOL_M
 * metres and ANG_TOL_DEG degrees of A's keyframe.  At least MIN_MATCHES times must be compared and
 * A must move by at least MIN_MOVE_M metres and turn by at least 5 degrees (a still path would pass
 * trivially).  Prints the largest differences; exit 0 when within tolerance. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "prw_camera_path.h"

static double angle_deg(prw_dquat a, prw_dquat b)
{
    /* rotation angle 4 atan2(|a - s b|, |a + s b|), s = sign(a.b): accurate for tiny angles (acos is not) */
    double s = (a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w) < 0 ? -1.0 : 1.0;
    double dx = a.x - s * b.x, dy = a.y - s * b.y, dz = a.z - s * b.z, dw = a.w - s * b.w;
    double px = a.x + s * b.x, py = a.y + s * b.y, pz = a.z + s * b.z, pw = a.w + s * b.w;
    return 4.0 * atan2(sqrt(dx * dx + dy * dy + dz * dz + dw * dw), sqrt(px * px + py * py + pz * pz + pw * pw)) *
           180.0 / 3.14159265358979323846;
}

int main(int argc, char **argv)
{
    if (argc != 7) {
        fprintf(stderr, "usage: walk_path_compare A.json B.json POS_TOL_M ANG_TOL_DEG MIN_MATCHES MIN_MOVE_M\n");
        return 2;
    }
    prw_camera_path a = {0}, b = {0};
    prw_error e;
    if (!prw_camera_path_load(argv[1], &a, &e) || !prw_camera_path_load(argv[2], &b, &e)) {
        fprintf(stderr, "walk_path_compare: %s\n", e.msg);
        return 1;
    }
    double pos_tol = atof(argv[3]), ang_tol = atof(argv[4]), min_move = atof(argv[6]);
    int min_matches = atoi(argv[5]), n = 0;
    double max_dp = 0, max_da = 0, t_dp = 0, t_da = 0, moved = 0, turned = 0;
    double b0 = b.keys[0].t, b1 = b.keys[b.count - 1].t;
    for (uint32_t i = 0; i < a.count; i++) {
        const prw_camera_keyframe *k = &a.keys[i];
        moved = fmax(moved, prw_v3_len(prw_v3_sub(k->position, a.keys[0].position)));
        turned = fmax(turned, angle_deg(k->orientation, a.keys[0].orientation));
        if (k->t < b0 - 1e-9 || k->t > b1 + 1e-9) continue;
        prw_camera_sample s = prw_camera_path_eval(&b, k->t);
        double dp = prw_v3_len(prw_v3_sub(s.position, k->position)), da = angle_deg(s.orientation, k->orientation);
        if (dp > max_dp) max_dp = dp, t_dp = k->t;
        if (da > max_da) max_da = da, t_da = k->t;
        n++;
    }
    printf("compared %d poses at equal times: max position difference %.3g m (t = %.3f s), max angle %.3g deg "
           "(t = %.3f s); path A moves %.3f m, turns %.1f deg\n",
           n, max_dp, t_dp, max_da, t_da, moved, turned);
    int rc = 0;
    if (n < min_matches) fprintf(stderr, "FAIL: only %d common times (want >= %d)\n", n, min_matches), rc = 1;
    if (moved < min_move || turned < 5) fprintf(stderr, "FAIL: path A barely moves (%.3f m, %.2f deg)\n", moved, turned), rc = 1;
    if (!(max_dp <= pos_tol)) fprintf(stderr, "FAIL: position differs by %.3g m > %.3g m\n", max_dp, pos_tol), rc = 1;
    if (!(max_da <= ang_tol)) fprintf(stderr, "FAIL: orientation differs by %.3g deg > %.3g deg\n", max_da, ang_tol), rc = 1;
    prw_camera_path_free(&a);
    prw_camera_path_free(&b);
    return rc;
}
