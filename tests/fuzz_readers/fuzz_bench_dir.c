/* fuzz_bench_dir — libFuzzer target for the bench output reader that bench-merge uses
 * (bench_read_outputs: frames.csv + passes.csv of a `prw bench --shard` directory).  The input is
 * frames.csv, then a line "=passes=", then passes.csv (absent: an empty passes.csv).  A failure is
 * one line naming a file of the directory; tables that read have rows sorted by config then frame,
 * each config index below the config count, and summarise without trouble. */
#include "fuzz_common.h"
#include "bench_internal.h"
#include "prw_build_info.h"

/* the build's git hash is not part of the reader; bench_out.c only prints it */
const char *prw_build_git_hash(void) { return "fuzz"; }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char sep[] = "\n=passes=\n";
    const uint8_t *cut = NULL;
    for (size_t i = 0; i + sizeof sep - 1 <= size && !cut; i++)
        if (memcmp(data + i, sep, sizeof sep - 1) == 0) cut = data + i;
    size_t nf = cut ? (size_t)(cut - data) + 1 : size;
    char frames[600], passes[600], dir[600];
    fuzz_scratch("frames.csv", frames, sizeof frames);
    fuzz_scratch("passes.csv", passes, sizeof passes);
    fuzz_write(frames, data, nf);
    if (cut) fuzz_write(passes, cut + sizeof sep - 1, size - nf - (sizeof sep - 2));
    else fuzz_write(passes, data, 0);
    snprintf(dir, sizeof dir, "%.*s", (int)(strrchr(frames, '/') - frames), frames);
    bench_result *r = prw_calloc(1, sizeof *r);
    prw_error e = {{0}};
    if (!bench_read_outputs(dir, r, &e)) {
        fuzz_check_error("fuzz_bench_dir", &e, dir);
    } else {
        for (size_t i = 0; i < r->row_count; i++) {
            if (r->rows[i].config >= r->config_count) fuzz_die("fuzz_bench_dir", "config index", frames);
            if (i && (r->rows[i].config < r->rows[i - 1].config ||
                      (r->rows[i].config == r->rows[i - 1].config && r->rows[i].frame <= r->rows[i - 1].frame)))
                fuzz_die("fuzz_bench_dir", "rows not sorted", frames);
        }
        for (uint32_t c = 0; c < r->config_count && c < 64; c++) {
            bench_config_stats st;
            bench_config_summary(r, c, &st);
        }
    }
    bench_result_free(r);
    free(r);
    return 0;
}
