/* fuzz_views_cache — libFuzzer target for the views-backend cache entry reader of
 * engine/render/views_backend.c (its static cache_read, reached by including the file: the render
 * module exports no parse entry point; see tests/fuzz_readers/CMakeLists.txt).  An entry that
 * reads has a valid backend consistent with the decision rule and finite figures. */
#include <math.h>

#include "fuzz_common.h"

#include "../../engine/render/views_backend.c"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[600];
    fuzz_write(fuzz_scratch("views.json", path, sizeof path), data, size);
    prw_views_choice c;
    memset(&c, 0, sizeof c);
    if (cache_read(path, &c)) {
        if (c.backend != PRW_VIEWS_LOOP && c.backend != PRW_VIEWS_MULTIVIEW) fuzz_die("fuzz_views_cache", "backend", path);
        if (!isfinite(c.multiview_rel_l1) || !isfinite(c.loop_ms) || !isfinite(c.multiview_ms))
            fuzz_die("fuzz_views_cache", "figures not finite", path);
        if (c.backend == PRW_VIEWS_MULTIVIEW && !c.multiview_ok) fuzz_die("fuzz_views_cache", "multiview chosen but not ok", path);
    }
    return 0;
}
