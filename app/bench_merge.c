/* bench_merge — prw bench-merge: the output directories of `prw bench --shard i/n` runs -> one result.
 *
 * Checks: every shard comes from the same run settings (scene, path, size, exposure, reference
 * settings, warm-up, git hash, configurations, pass columns) and the shards are exactly 0..n-1 of one
 * n; machine facts that differ (CPU, driver, threads: a cluster's nodes) are joined with " | " and a
 * warning.  Rows are copied as read (%.17g round-trips), sorted by config then frame, and the summary
 * is recomputed from them: the merged files equal a single run's, timing columns aside.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"

static const char *const k_same[] = {"scene", "path", "size", "exposure", "reference", "warmup", "git", "build"};
static const char *const k_machine[] = {"cpu", "driver", "device", "threads"};

static bool check_same(const bench_result *a, const bench_result *b, const char *name, prw_error *e)
{
    for (size_t i = 0; i < PRW_ARRAY_LEN(k_same); i++) {
        const char *x = bench_meta_get(&a->meta, k_same[i]), *y = bench_meta_get(&b->meta, k_same[i]);
        if (!x || !y || strcmp(x, y) != 0)
            return prw_fail(e, "%s: '%s' is '%s', the first shard has '%s'", name, k_same[i], y ? y : "(absent)",
                            x ? x : "(absent)");
    }
    if (a->config_count != b->config_count) return prw_fail(e, "%s: %u configs, the first shard has %u", name, b->config_count, a->config_count);
    for (uint32_t c = 0; c < a->config_count; c++)
        if (strcmp(a->configs[c].knobs, b->configs[c].knobs) != 0 || strcmp(a->configs[c].label, b->configs[c].label) != 0)
            return prw_fail(e, "%s: config %u differs from the first shard's", name, c);
    if (a->pass_count != b->pass_count) return prw_fail(e, "%s: pass columns differ from the first shard's", name);
    for (uint32_t p = 0; p < a->pass_count; p++)
        if (strcmp(a->pass_names[p], b->pass_names[p]) != 0)
            return prw_fail(e, "%s: pass columns differ from the first shard's", name);
    return true;
}

/* "i/n" with 0 <= i < n <= 100000 (the limit of bench --shard, so the table of seen shards stays small). */
static bool shard_of(const bench_result *r, const char *name, long *i, long *n, prw_error *e)
{
    const char *s = bench_meta_get(&r->meta, "shard");
    char *end = NULL;
    if (s && *s >= '0' && *s <= '9') {
        errno = 0;
        *i = strtol(s, &end, 10);
        if (!errno && *end == '/' && end[1] >= '0' && end[1] <= '9') {
            const char *b = end + 1;
            *n = strtol(b, &end, 10);
            if (!errno && *end == '\0' && *n >= 1 && *i < *n) {
                if (*n > 100000)
                    return prw_fail(e, "%s: shard %ld/%ld: more than 100000 shards (the limit of bench --shard)", name,
                                    *i, *n);
                return true;
            }
        }
    }
    return prw_fail(e, "%s: no valid '# shard: i/n' line in frames.csv", name);
}

bool bench_merge_dirs(const char *const *dirs, int n, const char *out, prw_error *e)
{
    if (!prw_check_writable_dir(out, true, e)) return false; /* before reading the shards */
    bench_result *in = prw_calloc((size_t)n, sizeof *in);
    bench_result merged = {0};
    bool ok = true;
    long total = 0;
    bool *seen = NULL;
    for (int d = 0; ok && d < n; d++) {
        ok = bench_read_outputs(dirs[d], &in[d], e);
        long si = 0, sn = 0;
        if (ok) ok = shard_of(&in[d], dirs[d], &si, &sn, e);
        if (ok && d == 0) {
            total = sn;
            seen = prw_calloc((size_t)sn, sizeof *seen);
        }
        if (ok && sn != total) ok = prw_fail(e, "%s: shard %ld/%ld, the first directory is of %ld shards", dirs[d], si, sn, total);
        if (ok && seen[si]) ok = prw_fail(e, "%s: shard %ld/%ld given twice", dirs[d], si, sn);
        if (ok) seen[si] = true;
        if (ok && d > 0) ok = check_same(&in[0], &in[d], dirs[d], e);
    }
    for (long s = 0; ok && s < total; s++)
        if (!seen[s]) ok = prw_fail(e, "shard %ld/%ld is missing", s, total);
    if (ok) {
        merged.meta = in[0].meta;
        for (int k = 0; k < merged.meta.count; k++) {
            char *v = merged.meta.value[k];
            if (strcmp(merged.meta.key[k], "shard") == 0) snprintf(v, sizeof merged.meta.value[0], "merged %ld/%ld", total, total);
            for (size_t m = 0; m < PRW_ARRAY_LEN(k_machine); m++) {
                if (strcmp(merged.meta.key[k], k_machine[m]) != 0) continue;
                for (int d = 1; d < n; d++) {
                    const char *o = bench_meta_get(&in[d].meta, k_machine[m]);
                    if (o && !strstr(v, o) && strlen(v) + strlen(o) + 4 < sizeof merged.meta.value[0]) {
                        prw_log(PRW_LOG_WARN, "bench-merge: %s differs between shards: '%s' and '%s'", k_machine[m], v, o);
                        strcat(v, " | ");
                        strcat(v, o);
                    }
                }
            }
        }
        merged.config_count = in[0].config_count;
        merged.configs = prw_malloc(merged.config_count * sizeof *merged.configs + 1);
        memcpy(merged.configs, in[0].configs, merged.config_count * sizeof *merged.configs);
        merged.pass_count = in[0].pass_count;
        memcpy(merged.pass_names, in[0].pass_names, sizeof merged.pass_names);
        for (int d = 0; d < n; d++)
            for (size_t i = 0; i < in[d].row_count; i++) {
                if (merged.row_count == merged.row_cap) {
                    merged.row_cap = merged.row_cap ? 2 * merged.row_cap : 64;
                    merged.rows = prw_realloc(merged.rows, merged.row_cap * sizeof *merged.rows);
                }
                merged.rows[merged.row_count++] = in[d].rows[i];
            }
        bench_result_sort(&merged);
        for (size_t i = 1; ok && i < merged.row_count; i++)
            if (merged.rows[i].config == merged.rows[i - 1].config && merged.rows[i].frame == merged.rows[i - 1].frame)
                ok = prw_fail(e, "config %u frame %u appears in two shards", merged.rows[i].config, merged.rows[i].frame);
    }
    if (ok) ok = bench_mkdirs(out, e) && bench_write_outputs(&merged, out, e);
    if (ok) {
        bench_plots(&merged, out);
        printf("bench-merge: %zu rows from %d shards\n", merged.row_count, n);
    }
    for (int d = 0; d < n; d++) bench_result_free(&in[d]);
    bench_result_free(&merged);
    free(in);
    free(seen);
    return ok;
}
