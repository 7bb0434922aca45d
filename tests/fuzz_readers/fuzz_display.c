/* fuzz_display — libFuzzer target for the display-profile reader (prw_display_parse).  Beyond "no
 * crash": a failure is one line naming the file; a profile that parses passes prw_display_validate,
 * and its model gives finite luminances and signals over the whole signal range. */
#include <math.h>

#include "fuzz_common.h"
#include "prw_display.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/display.json";
    prw_error e = {{0}};
    prw_display d;
    if (!prw_display_parse((const char *)data, size, name, &d, &e)) {
        fuzz_check_error("fuzz_display", &e, name);
        return 0;
    }
    if (!prw_display_validate(&d, name, &e)) fuzz_die("fuzz_display", "validate after parse", e.msg);
    double prev = -INFINITY;
    for (int i = 0; i <= 16; i++) {
        double v = i / 16.0, L = prw_display_luminance(&d, v), s = prw_display_signal(&d, L);
        if (!isfinite(L) || !isfinite(s) || s < 0 || s > 1) fuzz_die("fuzz_display", "model not finite", d.name);
        if (L < prev - 1e-9 * fabs(prev)) fuzz_die("fuzz_display", "luminance not monotonic in the signal", d.name);
        prev = L;
    }
    double m[9];
    prw_display_matrix(&d, m);
    for (int i = 0; i < 9; i++)
        if (!isfinite(m[i])) fuzz_die("fuzz_display", "primaries matrix not finite", d.name);
    return 0;
}
