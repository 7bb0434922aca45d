/* fuzz_envmap — libFuzzer target for the environment-map path of the reference: the input is the
 * EXR file a manifest's "environment": {"file": ...} names, read with the EXR reader's limits and the
 * sampling tables counted against the memory budget (ref_env_build), then evaluated and sampled.
 * A failure is one line naming the file; a map that loads gives finite radiance and pdfs, and
 * samples whose pdf matches the evaluation in the same direction. */
#include <math.h>

#include "fuzz_common.h"
#include "ref_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static bool init = false;
    if (!init) {
        prw_mem_set_budget((uint64_t)256 << 20);
        init = true;
    }
    prw_environment se;
    memset(&se, 0, sizeof se);
    fuzz_scratch("env.exr", se.file, sizeof se.file);
    fuzz_write(se.file, data, size);
    se.present = true;
    se.scale = 1;
    se.rotation = size ? (data[0] / 255.0) * 6.283185307179586 : 0;
    prw_error e = {{0}};
    ref_env env;
    if (!ref_env_build(&se, &env, &e)) {
        fuzz_check_error("fuzz_envmap", &e, se.file);
        return 0;
    }
    for (int k = 0; k < 16; k++) {
        double u1 = (k + 0.37) / 16.0, u2 = fmod(k * 0.618034, 1.0), d[3], L[3], pdf = 0, L2[3], pdf2 = 0;
        if (ref_env_sample(&env, u1, u2, d, L, &pdf)) {
            if (!(pdf > 0) || !isfinite(pdf)) fuzz_die("fuzz_envmap", "sample pdf", se.file);
            ref_env_eval(&env, d, L2, &pdf2);
            if (!isfinite(pdf2) || pdf2 < 0) fuzz_die("fuzz_envmap", "eval pdf", se.file);
        }
        double dir[3] = {cos(k), sin(3.0 * k), cos(5.0 * k)};
        ref_env_eval(&env, dir, L2, &pdf2);
        for (int c = 0; c < 3; c++)
            if (!isfinite(L2[c]) || L2[c] < 0) fuzz_die("fuzz_envmap", "radiance not finite", se.file);
        if (!isfinite(pdf2) || pdf2 < 0) fuzz_die("fuzz_envmap", "eval pdf", se.file);
    }
    ref_env_free(&env);
    return 0;
}
