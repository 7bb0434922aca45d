/* fuzz_btf_packed — libFuzzer target for the reader of our compressed BTF file (PRWBTFC1,
 * materials/btf/prw_btf_codec.h): from memory and through a scratch file.  A failure is one line
 * naming the input and leaves nothing allocated; a file that reads decodes to finite values at the
 * corners of the tensor and writes back to the same bytes. */
#include <math.h>

#include "fuzz_common.h"
#include "prw_btf_codec.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *name = "fuzz/a.btfc";
    static bool init = false;
    if (!init) {
        prw_mem_set_budget((uint64_t)256 << 20);
        init = true;
    }
    prw_error e = {{0}};
    prw_btf_packed p;
    bool ok = prw_btf_packed_read_memory(data, size, name, &p, &e);
    char path[600];
    fuzz_scratch("a.btfc", path, sizeof path);
    if (!ok) {
        fuzz_check_error("fuzz_btf_packed", &e, name);
        if (p.u || p.w || p.mean || p.basis || p.index || p.view_dirs) fuzz_die("fuzz_btf_packed", "arrays left after a failure", e.msg);
    } else {
        for (uint32_t c = 0; c < 3; c++) {
            float a = prw_btf_packed_value(&p, 0, 0, 0, 0, c);
            float b = prw_btf_packed_value(&p, p.views - 1, p.lights - 1, p.width - 1, p.height - 1, c);
            if (isnan(a) || isnan(b)) fuzz_die("fuzz_btf_packed", "NaN value", name);
        }
        if (!prw_btf_packed_write(path, &p, &e)) fuzz_die("fuzz_btf_packed", "a file that reads does not write", e.msg);
        char *back = NULL;
        size_t n = 0;
        if (!prw_read_file(path, &back, &n, &e) || n != size || memcmp(back, data, n) != 0)
            fuzz_die("fuzz_btf_packed", "writing back changed the bytes", name);
        free(back);
        prw_btf_packed_free(&p);
    }
    fuzz_write(path, data, size);
    prw_btf_packed q;
    bool ok2 = prw_btf_packed_read(path, &q, &e);
    if (ok2) prw_btf_packed_free(&q);
    else fuzz_check_error("fuzz_btf_packed", &e, path);
    if (ok2 != ok) fuzz_die("fuzz_btf_packed", "file and memory readers disagree", e.msg);
    return 0;
}
