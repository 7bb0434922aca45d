/* bench_out — the result table of prw bench and its files.
 *
 * frames.csv and passes.csv start with '#' lines "# key: value" (machine facts, run settings, one
 * "# config N: label | knobs" line per configuration), then a header row and one row per
 * (config, frame), sorted by config then frame.  Numbers are written with %.17g, so reading a file
 * back gives the same doubles bit for bit (bench-merge relies on it); an empty field is "not
 * measured" (no reference at that frame, or a pass that was skipped).  summary.json is computed from
 * the rows alone, so a merge of shards recomputes it exactly.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bench_internal.h"
#include "prw_build_info.h"

#ifndef PRW_BUILD_TYPE
#define PRW_BUILD_TYPE "unknown"
#endif

static const char *const k_frame_cols =
    "config,frame,t_s,frame_ms,cpu_ms,triangles,draws,mem_used_bytes,ref,ldr_flip,hdr_flip,psnr_db,ssim,"
    "noise_ldr_flip,noise_hdr_flip,noise_psnr_db,noise_ssim";

void bench_join(char *buf, size_t cap, const char *dir, const char *name) { snprintf(buf, cap, "%s/%s", dir, name); }

void bench_meta_add(bench_meta *m, const char *key, const char *fmt, ...)
{
    if (m->count >= BENCH_MAX_META) return;
    snprintf(m->key[m->count], sizeof m->key[0], "%s", key);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m->value[m->count], sizeof m->value[0], fmt, ap);
    va_end(ap);
    for (char *p = m->value[m->count]; *p; p++)
        if (*p == '\n' || *p == '\r') *p = ' ';
    m->count++;
}

const char *bench_meta_get(const bench_meta *m, const char *key)
{
    for (int i = 0; i < m->count; i++)
        if (strcmp(m->key[i], key) == 0) return m->value[i];
    return NULL;
}

static void cpu_model(char *buf, size_t cap)
{
    snprintf(buf, cap, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            const char *c = strchr(line, ':');
            if (c) {
                c++;
                while (*c == ' ' || *c == '\t') c++;
                snprintf(buf, cap, "%s", c);
                buf[strcspn(buf, "\n")] = '\0';
            }
            break;
        }
    fclose(f);
}

void bench_machine_meta(bench_meta *m, prw_gpu *gpu)
{
    char cpu[256];
    cpu_model(cpu, sizeof cpu);
    bench_meta_add(m, "cpu", "%s", cpu);
    bench_meta_add(m, "driver", "%s", prw_gpu_driver_info(gpu));
    bench_meta_add(m, "device", "%s", prw_gpu_device_name(gpu));
    bench_meta_add(m, "threads", "%d (LP_NUM_THREADS %s)", prw_threads_get(),
                   getenv("LP_NUM_THREADS") ? getenv("LP_NUM_THREADS") : "unset");
    bench_meta_add(m, "git", "%s", prw_build_git_hash());
    bench_meta_add(m, "build", "%s", PRW_BUILD_TYPE);
}

void bench_row_init(bench_row *row, uint32_t config, uint32_t frame)
{
    memset(row, 0, sizeof *row);
    row->config = config;
    row->frame = frame;
    row->t_s = row->frame_ms = row->cpu_ms = NAN;
    row->err = row->noise = (bench_err){NAN, NAN, NAN, NAN};
    for (int i = 0; i < BENCH_MAX_PASS_NAMES; i++) row->pass_ms[i] = NAN;
    row->base_ms = row->floor_ms = NAN;
}

void bench_print_base_floor(const bench_result *r)
{
    double *v = prw_calloc(3 * (r->row_count + 1), sizeof(double));
    for (uint32_t ci = 0; ci < r->config_count; ci++) {
        size_t n = 0, cap = r->row_count + 1;
        for (size_t i = 0; i < r->row_count; i++) {
            const bench_row *w = &r->rows[i];
            if (w->config != ci || !(w->floor_ms > 0) || isnan(w->base_ms)) continue;
            v[n] = w->floor_ms, v[cap + n] = w->base_ms, v[2 * cap + n] = w->base_ms / w->floor_ms;
            n++;
        }
        if (n == 0) continue;
        /* floor and base are timed in the same frames: the ratio is the median of per-frame ratios */
        printf("config %u (%s): floor ms %.3f, base ms %.3f, base/floor %.2f (medians of %zu frames, both in every "
               "frame%s)\n",
               ci, r->configs[ci].label, prw_stats_median(v, n), prw_stats_median(v + cap, n),
               prw_stats_median(v + 2 * cap, n), n, n < 30 ? "; 30 frames or more for a figure" : "");
    }
    free(v);
}

bench_row *bench_result_row(bench_result *r, uint32_t config, uint32_t frame)
{
    for (size_t i = r->row_count; i-- > 0;)
        if (r->rows[i].config == config && r->rows[i].frame == frame) return &r->rows[i];
    if (r->row_count == r->row_cap) {
        r->row_cap = r->row_cap ? 2 * r->row_cap : 64;
        r->rows = prw_realloc(r->rows, r->row_cap * sizeof *r->rows);
    }
    bench_row *row = &r->rows[r->row_count++];
    bench_row_init(row, config, frame);
    return row;
}

void bench_result_free(bench_result *r)
{
    free(r->rows);
    free(r->configs);
    memset(r, 0, sizeof *r);
}

static int cmp_row(const void *a, const void *b)
{
    const bench_row *x = a, *y = b;
    if (x->config != y->config) return x->config < y->config ? -1 : 1;
    return (x->frame > y->frame) - (x->frame < y->frame);
}

void bench_result_sort(bench_result *r)
{
    if (r->row_count > 1) qsort(r->rows, r->row_count, sizeof *r->rows, cmp_row);
}

/* ---- CSV ---- */

static void put_num(FILE *f, double v)
{
    if (isnan(v)) fputc(',', f);
    else fprintf(f, ",%.17g", v);
}

static void write_header(FILE *f, const bench_result *r, const char *what)
{
    fprintf(f, "# prw-bench: %s v1\n", what);
    for (int i = 0; i < r->meta.count; i++) fprintf(f, "# %s: %s\n", r->meta.key[i], r->meta.value[i]);
}

static bool close_or_fail(FILE *f, const char *tmp, const char *path, prw_error *e)
{
    bool ok = !ferror(f);
    if (fclose(f) != 0) ok = false;
    if (ok && rename(tmp, path) != 0) ok = false;
    if (!ok) {
        remove(tmp);
        return prw_fail(e, "%s: write failed", path);
    }
    return true;
}

static FILE *open_tmp(const char *path, char *tmp, size_t cap, prw_error *e)
{
    snprintf(tmp, cap, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) prw_fail(e, "%s: cannot write", tmp);
    return f;
}

static bool write_frames(const bench_result *r, const char *path, prw_error *e)
{
    char tmp[4300];
    FILE *f = open_tmp(path, tmp, sizeof tmp, e);
    if (!f) return false;
    write_header(f, r, "frames");
    fprintf(f, "%s\n", k_frame_cols);
    for (size_t i = 0; i < r->row_count; i++) {
        const bench_row *w = &r->rows[i];
        fprintf(f, "%u,%u", w->config, w->frame);
        put_num(f, w->t_s);
        put_num(f, w->frame_ms);
        put_num(f, w->cpu_ms);
        fprintf(f, ",%llu,%u,%llu,%d", (unsigned long long)w->triangles, w->draws, (unsigned long long)w->mem_used,
                w->ref ? 1 : 0);
        const double v[8] = {w->err.ldr_flip,   w->err.hdr_flip,   w->err.psnr,   w->err.ssim,
                             w->noise.ldr_flip, w->noise.hdr_flip, w->noise.psnr, w->noise.ssim};
        for (int k = 0; k < 8; k++) put_num(f, v[k]);
        fputc('\n', f);
    }
    return close_or_fail(f, tmp, path, e);
}

static bool write_passes(const bench_result *r, const char *path, prw_error *e)
{
    char tmp[4300];
    FILE *f = open_tmp(path, tmp, sizeof tmp, e);
    if (!f) return false;
    write_header(f, r, "passes (timestamped run; empty = skipped or not in this config's graph)");
    fprintf(f, "config,frame");
    for (uint32_t p = 0; p < r->pass_count; p++) fprintf(f, ",%s_ms", r->pass_names[p]);
    fputc('\n', f);
    for (size_t i = 0; i < r->row_count; i++) {
        const bench_row *w = &r->rows[i];
        fprintf(f, "%u,%u", w->config, w->frame);
        for (uint32_t p = 0; p < r->pass_count; p++) put_num(f, w->pass_ms[p]);
        fputc('\n', f);
    }
    return close_or_fail(f, tmp, path, e);
}

/* ---- summary ---- */

static void err_stats(const double *v, uint32_t n, bool larger_worse, bench_err_stats *out)
{
    out->mean = out->worst = NAN;
    if (!n) return;
    double sum = 0, worst = v[0];
    for (uint32_t i = 0; i < n; i++) {
        sum += v[i];
        worst = larger_worse ? fmax(worst, v[i]) : fmin(worst, v[i]);
    }
    out->mean = sum / n;
    out->worst = worst;
}

void bench_config_summary(const bench_result *r, uint32_t config, bench_config_stats *out)
{
    memset(out, 0, sizeof *out);
    size_t n = 0;
    double *fm = prw_malloc((r->row_count + 1) * sizeof(double)), *cm = prw_malloc((r->row_count + 1) * sizeof(double));
    double *ev[8];
    for (int k = 0; k < 8; k++) ev[k] = prw_malloc((r->row_count + 1) * sizeof(double));
    double *pv = prw_malloc((r->row_count + 1) * sizeof(double));
    uint32_t nref = 0;
    for (size_t i = 0; i < r->row_count; i++) {
        const bench_row *w = &r->rows[i];
        if (w->config != config) continue;
        fm[n] = w->frame_ms;
        cm[n] = w->cpu_ms;
        n++;
        out->peak_mem = PRW_MAX(out->peak_mem, w->mem_used);
        out->triangles_max = PRW_MAX(out->triangles_max, w->triangles);
        if (w->ref && !isnan(w->err.ldr_flip)) {
            const double v[8] = {w->err.ldr_flip,   w->err.hdr_flip,   w->err.psnr,   w->err.ssim,
                                 w->noise.ldr_flip, w->noise.hdr_flip, w->noise.psnr, w->noise.ssim};
            for (int k = 0; k < 8; k++) ev[k][nref] = v[k];
            nref++;
        }
    }
    prw_stats_summarize(fm, n, &out->frame_ms);
    prw_stats_summarize(cm, n, &out->cpu_ms);
    out->ref_frames = nref;
    for (int k = 0; k < 4; k++) {
        bool larger_worse = k < 2; /* FLIP: larger is worse; PSNR, SSIM: smaller is worse */
        err_stats(ev[k], nref, larger_worse, &out->err[k]);
        err_stats(ev[k + 4], nref, larger_worse, &out->noise[k]);
    }
    /* "below reference noise": error < 2 x noise (FLIP), 1 - SSIM < 2 (1 - SSIM_noise),
     * PSNR > PSNR_noise - 20 log10 2 (prw_compare_verdict's rules, on the means) */
    out->below_noise[0] = out->err[0].mean < 2 * out->noise[0].mean;
    out->below_noise[1] = out->err[1].mean < 2 * out->noise[1].mean;
    out->below_noise[2] = out->err[2].mean > out->noise[2].mean - 20 * log10(2.0);
    out->below_noise[3] = 1 - out->err[3].mean < 2 * (1 - out->noise[3].mean);
    for (uint32_t p = 0; p < r->pass_count; p++) {
        size_t m = 0;
        for (size_t i = 0; i < r->row_count; i++)
            if (r->rows[i].config == config && !isnan(r->rows[i].pass_ms[p])) pv[m++] = r->rows[i].pass_ms[p];
        out->pass_p50[p] = m ? prw_stats_median(pv, m) : NAN;
    }
    free(fm);
    free(cm);
    for (int k = 0; k < 8; k++) free(ev[k]);
    free(pv);
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\') fprintf(f, "\\%c", ch);
        else if (ch < 0x20) fprintf(f, "\\u%04x", ch);
        else fputc(ch, f);
    }
    fputc('"', f);
}

static void json_num(FILE *f, double v)
{
    if (isfinite(v)) fprintf(f, "%.17g", v);
    else fprintf(f, "null");
}

static void json_summary(FILE *f, const char *name, const prw_stats_summary *s)
{
    fprintf(f, "      \"%s\": {\"p50\": ", name);
    json_num(f, s->p50);
    fprintf(f, ", \"p95\": ");
    json_num(f, s->p95);
    fprintf(f, ", \"p99\": ");
    json_num(f, s->p99);
    fprintf(f, ", \"low_1pct\": ");
    json_num(f, s->low_1pct);
    fprintf(f, ", \"low_0_1pct\": ");
    json_num(f, s->low_01pct);
    fprintf(f, ", \"mean\": ");
    json_num(f, s->mean);
    fprintf(f, ", \"max\": ");
    json_num(f, s->max);
    fprintf(f, "},\n");
}

static void json_errs(FILE *f, const char *name, const bench_err_stats *e)
{
    static const char *const names[4] = {"ldr_flip", "hdr_flip", "psnr_db", "ssim"};
    static const char *const worst[4] = {"max", "max", "min", "min"};
    fprintf(f, "      \"%s\": {", name);
    for (int k = 0; k < 4; k++) {
        fprintf(f, "%s\"%s\": {\"mean\": ", k ? ", " : "", names[k]);
        json_num(f, e[k].mean);
        fprintf(f, ", \"%s\": ", worst[k]);
        json_num(f, e[k].worst);
        fputc('}', f);
    }
    fprintf(f, "},\n");
}

static bool write_summary(const bench_result *r, const char *path, prw_error *e)
{
    char tmp[4300];
    FILE *f = open_tmp(path, tmp, sizeof tmp, e);
    if (!f) return false;
    fprintf(f, "{\n  \"prw_bench_summary\": 1,\n");
    for (int i = 0; i < r->meta.count; i++) {
        if (strncmp(r->meta.key[i], "config ", 7) == 0) continue;
        fprintf(f, "  ");
        json_str(f, r->meta.key[i]);
        fprintf(f, ": ");
        json_str(f, r->meta.value[i]);
        fprintf(f, ",\n");
    }
    fprintf(f, "  \"definitions\": {\"frame_ms\": \"wall time from a frame's start to the next frame's start, "
               "timed run (timestamps off)\", \"cpu_ms\": \"the renderer's record + submit + wait on the CPU\", "
               "\"percentiles\": \"linear interpolation between order statistics\", \"low_1pct\": \"mean of the "
               "slowest ceil(1 %% of n) frame times (at least one), ms\", \"low_0_1pct\": \"mean of the slowest "
               "ceil(0.1 %% of n) frame times (at least one), ms\", \"error\": \"raster HDR against reference A at "
               "the sampled frames; mean and worst over those frames of each frame's figure (FLIP: pooled mean)\", "
               "\"reference_noise\": \"the same metrics between reference B and reference A (other seed, same "
               "spp)\", \"below_reference_noise\": \"error < 2 x noise (FLIP, 1 - SSIM); PSNR > noise PSNR - 6.02 "
               "dB; on the means\", \"peak_memory_bytes\": \"largest live bytes of the GPU allocator's own "
               "accounting, sampled after each timed frame\"},\n");
    fprintf(f, "  \"configs\": [\n");
    for (uint32_t c = 0; c < r->config_count; c++) {
        bench_config_stats s;
        bench_config_summary(r, c, &s);
        fprintf(f, "    {\n      \"index\": %u,\n      \"label\": ", c);
        json_str(f, r->configs[c].label);
        fprintf(f, ",\n      \"knobs\": ");
        json_str(f, r->configs[c].knobs);
        fprintf(f, ",\n      \"frames\": %zu,\n", s.frame_ms.n);
        json_summary(f, "frame_ms", &s.frame_ms);
        json_summary(f, "cpu_ms", &s.cpu_ms);
        fprintf(f, "      \"peak_memory_bytes\": %llu,\n      \"triangles_max\": %llu,\n      \"reference_frames\": %u,\n",
                (unsigned long long)s.peak_mem, (unsigned long long)s.triangles_max, s.ref_frames);
        json_errs(f, "error", s.err);
        json_errs(f, "reference_noise", s.noise);
        fprintf(f, "      \"below_reference_noise\": {\"ldr_flip\": %s, \"hdr_flip\": %s, \"psnr_db\": %s, \"ssim\": %s},\n",
                s.below_noise[0] ? "true" : "false", s.below_noise[1] ? "true" : "false",
                s.below_noise[2] ? "true" : "false", s.below_noise[3] ? "true" : "false");
        fprintf(f, "      \"pass_ms_p50\": {");
        for (uint32_t p = 0; p < r->pass_count; p++) {
            fprintf(f, "%s", p ? ", " : "");
            json_str(f, r->pass_names[p]);
            fprintf(f, ": ");
            json_num(f, s.pass_p50[p]);
        }
        fprintf(f, "}\n    }%s\n", c + 1 < r->config_count ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    return close_or_fail(f, tmp, path, e);
}

bool bench_write_outputs(const bench_result *r, const char *dir, prw_error *e)
{
    char p1[4200], p2[4200], p3[4200];
    bench_join(p1, sizeof p1, dir, "frames.csv");
    bench_join(p2, sizeof p2, dir, "passes.csv");
    bench_join(p3, sizeof p3, dir, "summary.json");
    if (!write_frames(r, p1, e) || !write_passes(r, p2, e) || !write_summary(r, p3, e)) return false;
    printf("wrote %s, %s, %s\n", p1, p2, p3);
    return true;
}

/* ---- reading back ---- */

/* Splits line at ',' in place; returns the field count (at most cap). */
static int split(char *line, char **fields, int cap)
{
    line[strcspn(line, "\r\n")] = '\0';
    int n = 0;
    for (char *p = line;;) {
        if (n < cap) fields[n] = p;
        n++;
        char *comma = strchr(p, ',');
        if (!comma) break;
        *comma = '\0';
        p = comma + 1;
    }
    return n;
}

static bool num_field(const char *s, double *out)
{
    if (!*s) {
        *out = NAN;
        return true;
    }
    char *end = NULL;
    *out = strtod(s, &end);
    return end != s && *end == '\0';
}

static bool uint_field(const char *s, uint64_t *out)
{
    char *end = NULL;
    if (!*s || *s == '-') return false;
    *out = strtoull(s, &end, 10);
    return *end == '\0';
}

static int cmp_key(const void *key, const void *elem)
{
    const bench_row *k = key, *r = elem;
    if (k->config != r->config) return k->config < r->config ? -1 : 1;
    return (k->frame > r->frame) - (k->frame < r->frame);
}

#define LINE_MAX_BYTES 65536
/* Shortest line that adds to memory: a frames row ("0,0,,,,0,0,0,0,,,,,,,,\n", 23 bytes) or a
 * "# config N: " line (12 bytes); the file's size bounds the rows and configurations it can hold. */
#define MIN_LINE_BYTES 12

/* Reads the '#' lines into meta/configs (frames.csv only) and the column header line.  Rows must
 * come sorted by config then frame, as bench_write_outputs writes them (checked, so duplicates are
 * found in one pass and passes.csv rows are matched by binary search). */
static bool read_table(const char *path, bench_result *r, bool frames, prw_error *e)
{
    FILE *f = fopen(path, "r");
    if (!f) return prw_fail(e, "%s: cannot open", path);
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return prw_fail(e, "%s: cannot open: not a regular file", path);
    }
    uint64_t most = (uint64_t)st.st_size / MIN_LINE_BYTES + 1;
    if (!prw_mem_check(prw_mul_sat(most, PRW_MAX(sizeof(bench_row), sizeof(bench_config))), path,
                       "the rows this table can hold", e)) {
        fclose(f);
        return false;
    }
    char *line = prw_malloc(LINE_MAX_BYTES);
    bool ok = true, header = false;
    long lineno = 0;
    while (ok && fgets(line, LINE_MAX_BYTES, f)) {
        lineno++;
        size_t len = strlen(line);
        if (len == LINE_MAX_BYTES - 1 && line[len - 1] != '\n') {
            ok = prw_fail(e, "%s:%ld: line longer than %d bytes", path, lineno, LINE_MAX_BYTES - 2);
            break;
        }

        if (line[0] == '#') {
            if (!frames) continue;
            char *colon = strstr(line, ": ");
            if (!colon || lineno == 1) continue;
            *colon = '\0';
            char *value = colon + 2;
            value[strcspn(value, "\r\n")] = '\0';
            const char *key = line + 2;
            bench_meta_add(&r->meta, key, "%s", value);
            unsigned ci;
            if (sscanf(key, "config %u", &ci) == 1) {
                if (ci != r->config_count) {
                    ok = prw_fail(e, "%s:%ld: config %u out of order", path, lineno, ci);
                    break;
                }
                r->configs = prw_realloc(r->configs, (ci + 1) * sizeof *r->configs);
                bench_config *bc = &r->configs[ci];
                memset(bc, 0, sizeof *bc);
                char *bar = strstr(value, " | ");
                if (bar) *bar = '\0';
                snprintf(bc->label, sizeof bc->label, "%s", value);
                snprintf(bc->knobs, sizeof bc->knobs, "%s", bar ? bar + 3 : "");
                r->config_count = ci + 1;
            }
            continue;
        }
        char *fl[64];
        int n = split(line, fl, 64);
        if (!header) {
            header = true;
            if (frames) {
                if (n != 17 || strcmp(fl[0], "config") != 0 || strcmp(fl[16], "noise_ssim") != 0)
                    ok = prw_fail(e, "%s:%ld: not a prw bench frames table", path, lineno);
            } else {
                if (n < 2 || n - 2 > BENCH_MAX_PASS_NAMES) {
                    ok = prw_fail(e, "%s:%ld: not a prw bench passes table", path, lineno);
                    break;
                }
                r->pass_count = (uint32_t)(n - 2);
                for (int p = 2; p < n; p++) {
                    size_t len = strlen(fl[p]);
                    if (len > 3 && strcmp(fl[p] + len - 3, "_ms") == 0) fl[p][len - 3] = '\0';
                    snprintf(r->pass_names[p - 2], sizeof r->pass_names[0], "%s", fl[p]);
                }
            }
            continue;
        }
        uint64_t cfg, frame;
        if (n < 2 || !uint_field(fl[0], &cfg) || !uint_field(fl[1], &frame) || cfg >= r->config_count ||
            frame > UINT32_MAX) {
            ok = prw_fail(e, "%s:%ld: bad config or frame index", path, lineno);
            break;
        }
        if (frames) {
            uint64_t tri, draws, mem, ref;
            double v[11];
            bool good = n == 17 && uint_field(fl[5], &tri) && uint_field(fl[6], &draws) && uint_field(fl[7], &mem) &&
                        uint_field(fl[8], &ref);
            const int numcols[11] = {2, 3, 4, 9, 10, 11, 12, 13, 14, 15, 16};
            for (int k = 0; good && k < 11; k++) good = num_field(fl[numcols[k]], &v[k]);
            if (!good) {
                ok = prw_fail(e, "%s:%ld: malformed row", path, lineno);
                break;
            }
            if (r->row_count) {
                const bench_row *last = &r->rows[r->row_count - 1];
                bench_row key = {.config = (uint32_t)cfg, .frame = (uint32_t)frame};
                int c = cmp_key(&key, last);
                if (c == 0)
                    ok = prw_fail(e, "%s:%ld: config %llu frame %llu appears twice", path, lineno,
                                  (unsigned long long)cfg, (unsigned long long)frame);
                else if (c < 0)
                    ok = prw_fail(e, "%s:%ld: config %llu frame %llu out of order (rows are sorted by config, then frame)",
                                  path, lineno, (unsigned long long)cfg, (unsigned long long)frame);
            }
            if (!ok) break;
            if (r->row_count == r->row_cap) {
                r->row_cap = r->row_cap ? 2 * r->row_cap : 64;
                r->rows = prw_realloc(r->rows, r->row_cap * sizeof *r->rows);
            }
            bench_row *w = &r->rows[r->row_count++];
            bench_row_init(w, (uint32_t)cfg, (uint32_t)frame);
            w->t_s = v[0], w->frame_ms = v[1], w->cpu_ms = v[2];
            w->triangles = tri, w->draws = (uint32_t)draws, w->mem_used = mem, w->ref = ref != 0;
            w->err = (bench_err){v[3], v[4], v[5], v[6]};
            w->noise = (bench_err){v[7], v[8], v[9], v[10]};
        } else {
            if (n != (int)r->pass_count + 2) {
                ok = prw_fail(e, "%s:%ld: %d fields, expected %u", path, lineno, n, r->pass_count + 2);
                break;
            }
            bench_row key = {.config = (uint32_t)cfg, .frame = (uint32_t)frame};
            bench_row *w = r->row_count ? bsearch(&key, r->rows, r->row_count, sizeof *r->rows, cmp_key) : NULL;
            if (!w) {
                ok = prw_fail(e, "%s:%ld: config %llu frame %llu is not in frames.csv", path, lineno,
                              (unsigned long long)cfg, (unsigned long long)frame);
                break;
            }
            for (uint32_t p = 0; ok && p < r->pass_count; p++)
                if (!num_field(fl[p + 2], &w->pass_ms[p])) ok = prw_fail(e, "%s:%ld: malformed pass time", path, lineno);
        }
    }
    if (ok && !header) ok = prw_fail(e, "%s: no table", path);
    free(line);
    fclose(f);
    return ok;
}

bool bench_read_outputs(const char *dir, bench_result *r, prw_error *e)
{
    char p1[4200], p2[4200];
    bench_join(p1, sizeof p1, dir, "frames.csv");
    bench_join(p2, sizeof p2, dir, "passes.csv");
    memset(r, 0, sizeof *r);
    return read_table(p1, r, true, e) && read_table(p2, r, false, e);
}
