/* fuzz_btf_ubo — libFuzzer target for the Bonn BTF binaries' reader (materials/btf/prw_btf_ubo.h):
 * prw_btf_ubo_read_memory and, through a scratch file, prw_btf_ubo_read.  A failure is one line
 * naming the input and leaves nothing allocated; a BTF that reads encodes back to the same bytes
 * and its values at the corners of the tensor are finite. */
#include <math.h>

#include "fuzz_common.h"
#include "prw_btf_ubo.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/a.btf";
    static bool init = false;
    if (!init) {
        prw_mem_set_budget((uint64_t)256 << 20); /* no single input may ask for more */
        init = true;
    }
    prw_error e = {{0}};
    prw_btf_ubo b;
    bool ok = prw_btf_ubo_read_memory(data, size, name, &b, &e);
    if (!ok) {
        fuzz_check_error("fuzz_btf_ubo", &e, name);
        if (b.factors || b.view_dirs || b.bdi || b.mask || b.xml) fuzz_die("fuzz_btf_ubo", "arrays left after a failure", e.msg);
    } else {
        uint8_t *out = NULL;
        size_t n = 0;
        if (!prw_btf_ubo_encode(&b, &out, &n, &e)) fuzz_die("fuzz_btf_ubo", "a BTF that reads does not encode", e.msg);
        if (n != size || memcmp(out, data, n) != 0) fuzz_die("fuzz_btf_ubo", "re-encoding changed the bytes", name);
        free(out);
        for (uint32_t c = 0; c < b.channels; c++) {
            double v0 = prw_btf_ubo_raw(&b, c, 0, 0, 0, 0);
            double v1 = prw_btf_ubo_raw(&b, c, b.views - 1, b.lights - 1, b.width - 1, b.height - 1);
            /* sums of finite products may overflow to Inf for absurd doubles; NaN never */
            if (isnan(v0) || isnan(v1)) fuzz_die("fuzz_btf_ubo", "NaN value", name);
        }
        prw_btf_ubo_free(&b);
    }
    char path[600];
    fuzz_write(fuzz_scratch("a.btf", path, sizeof path), data, size);
    prw_btf_ubo f;
    bool ok2 = prw_btf_ubo_read(path, &f, &e);
    if (ok2) prw_btf_ubo_free(&f);
    else fuzz_check_error("fuzz_btf_ubo", &e, path);
    if (ok2 != ok) fuzz_die("fuzz_btf_ubo", "file and memory readers disagree", e.msg);
    return 0;
}
