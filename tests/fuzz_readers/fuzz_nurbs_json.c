/* fuzz_nurbs_json — libFuzzer target for the NURBS JSON model reader (prw_nurbs_json_parse).  A
 * failure is one line naming the file and leaves an empty model; a model that parses has valid
 * surfaces (prw_nurbs_surface_validate) whose points are finite over their domains. */
#include <math.h>

#include "fuzz_common.h"
#include "prw_nurbs_json.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/model.json";
    prw_error e = {{0}};
    prw_nurbs_model m;
    if (!prw_nurbs_json_parse((const char *)data, size, name, &m, &e)) {
        fuzz_check_error("fuzz_nurbs_json", &e, name);
        if (m.count != 0 || m.surfaces) fuzz_die("fuzz_nurbs_json", "model left after a failure", e.msg);
        return 0;
    }
    for (size_t i = 0; i < m.count; i++) {
        const prw_nurbs_surface *s = &m.surfaces[i].surface;
        if (!prw_nurbs_surface_validate(s, &e)) fuzz_die("fuzz_nurbs_json", "surface invalid after parse", e.msg);
        double u0, u1, v0, v1;
        prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
        for (int k = 0; k < 9; k++) {
            prw_dvec3 p = prw_nurbs_surface_eval(s, u0 + (u1 - u0) * (k % 3) / 2.0, v0 + (v1 - v0) * (k / 3) / 2.0);
            if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) fuzz_die("fuzz_nurbs_json", "surface point not finite", name);
        }
    }
    prw_nurbs_model_free(&m);
    return 0;
}
