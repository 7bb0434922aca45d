/* fuzz_btf_raw — libFuzzer target for the raw BTF dump reader (materials/btf/prw_btf.h
 * prw_btf_read_raw, what prw btf-compress --btf reads), through a scratch file.  A failure is one line
 * naming the file and leaves nothing allocated; a dump that reads writes back to the same bytes. */
#include "fuzz_common.h"
#include "prw_btf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static bool init = false;
    if (!init) {
        prw_mem_set_budget((uint64_t)256 << 20);
        init = true;
    }
    char path[600], back[600];
    fuzz_write(fuzz_scratch("a.raw", path, sizeof path), data, size);
    prw_error e = {{0}};
    prw_btf b;
    if (!prw_btf_read_raw(path, &b, &e)) {
        fuzz_check_error("fuzz_btf_raw", &e, path);
        if (b.rgb || b.view_dirs || b.light_dirs) fuzz_die("fuzz_btf_raw", "arrays left after a failure", e.msg);
        return 0;
    }
    if (!prw_btf_write_raw(fuzz_scratch("b.raw", back, sizeof back), &b, &e)) fuzz_die("fuzz_btf_raw", "cannot write back", e.msg);
    char *again = NULL;
    size_t n = 0;
    if (!prw_read_file(back, &again, &n, &e) || n != size || memcmp(again, data, n) != 0)
        fuzz_die("fuzz_btf_raw", "writing back changed the bytes", path);
    free(again);
    prw_btf_free(&b);
    return 0;
}
