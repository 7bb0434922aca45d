/* fuzz_acc — libFuzzer target for the reference accumulation reader (prw_ref_acc_read_memory and,
 * through a scratch file, prw_ref_acc_read with its header-first size checks).  A failure is one line
 * naming the file and leaves no arrays; an accumulation that reads has a consistent tile, and a
 * whole-image one turns into finite mean and variance images. */
#include <math.h>

#include "fuzz_common.h"
#include "prw_reference.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/a.acc";
    static bool init = false;
    if (!init) {
        prw_mem_set_budget((uint64_t)256 << 20); /* no single input may ask for more */
        init = true;
    }
    prw_error e = {{0}};
    prw_ref_acc a;
    bool ok = prw_ref_acc_read_memory(data, size, name, &a, &e);
    if (!ok) {
        fuzz_check_error("fuzz_acc", &e, name);
        if (a.sum || a.sq) fuzz_die("fuzz_acc", "arrays left after a failure", e.msg);
    } else {
        if (!(a.x0 < a.x1 && a.y0 < a.y1 && a.x1 <= a.width && a.y1 <= a.height && a.s1 > a.s0))
            fuzz_die("fuzz_acc", "inconsistent tile", name);
        float *mean = NULL, *var = NULL;
        if (a.x0 == 0 && a.y0 == 0 && a.x1 == a.width && a.y1 == a.height && prw_ref_acc_images(&a, &mean, &var, &e)) {
            size_t n = (size_t)a.width * a.height * 4;
            for (size_t i = 0; i < n; i++)
                if (!isfinite(mean[i]) || !isfinite(var[i]) || var[i] < 0) fuzz_die("fuzz_acc", "image not finite", name);
        }
        free(mean);
        free(var);
        prw_ref_acc_free(&a);
    }
    /* the path reader: same verdict */
    char path[600];
    fuzz_write(fuzz_scratch("a.acc", path, sizeof path), data, size);
    prw_ref_acc b;
    bool ok2 = prw_ref_acc_read(path, &b, &e);
    if (ok2) prw_ref_acc_free(&b);
    else fuzz_check_error("fuzz_acc", &e, path);
    if (ok2 != ok) fuzz_die("fuzz_acc", "file and memory readers disagree", e.msg);
    return 0;
}
