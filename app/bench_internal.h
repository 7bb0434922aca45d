/* bench_internal — what the files of `prw bench` / `prw bench-merge` share.  Not a public header.
 *
 *   cmd_bench.c    options, the order of the phases (references, timed run, timestamped run, output)
 *   bench_ref.c    reference cache (key, directory), the child process that renders references
 *   bench_run.c    the timed run and the timestamped run (per-pass times, errors at sampled frames)
 *   bench_ab.c     A/B mode: two configurations interleaved frame by frame
 *   bench_out.c    frames.csv / passes.csv (write and read back), summary.json
 *   bench_plot.c   PNG plots through gnuplot (skipped with a note when gnuplot is missing)
 *   bench_merge.c  prw bench-merge: shards -> one result, bit-exactly
 */
#ifndef PRW_BENCH_INTERNAL_H
#define PRW_BENCH_INTERNAL_H

#include "app.h"
#include "lightmaps.h"
#include "prw_camera_path.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_quality.h"
#include "prw_render.h"
#include "prw_stats.h"

#define BENCH_REF_SEED_A 1u /* the reference errors are measured against */
#define BENCH_REF_SEED_B 2u /* the second reference: its distance to A is the reference noise */
#define BENCH_MAX_META 96
#define BENCH_MAX_PASS_NAMES 24

typedef struct bench_opts {
    const char *scene_path; /* NULL: demo */
    const char *path_spec;  /* camera-path file, or "demo" */
    uint32_t width, height;
    const char *preset;     /* NULL: default ("high") */
    const char *sweep;
    const char *vs;
    const char *views_backend; /* --views 2: loop | multiview | auto */
    const char *stereo_reuse;  /* --views 2: off | reproject (the stereo_reuse knob; NULL = the preset's) */
    long views, reference_every, ref_spp, frames_limit, warmup;
    const char *out_dir;
    long shard_i, shard_n;
    bool no_ref_cache;
    bool no_bake;             /* --no-bake: no GI light maps */
    const char *ref_child, *ref_dir; /* hidden: this process is the reference child */
} bench_opts;

typedef struct bench_config {
    prw_quality q;
    char label[600];  /* preset name, plus the knobs a sweep changes */
    char knobs[1024]; /* prw_quality_format */
} bench_config;

/* One metric set of one frame: error against reference A and the noise (B against A). */
typedef struct bench_err {
    double ldr_flip, hdr_flip, psnr, ssim;
} bench_err;

typedef struct bench_row {
    uint32_t config, frame;
    double t_s;
    double frame_ms, cpu_ms;   /* timing columns */
    uint64_t triangles;
    uint32_t draws;
    uint64_t mem_used;
    bool ref;
    bench_err err, noise;      /* NaN unless ref */
    double pass_ms[BENCH_MAX_PASS_NAMES]; /* timestamped run; NaN = skipped or not in the graph */
    double base_ms, floor_ms;  /* timestamped run, same frame (prw_frame_stats_base_floor); NaN = none.
                                  Printed by the run, not written to the CSV */
} bench_row;

/* Header facts, in output order ("key: value"). */
typedef struct bench_meta {
    int count;
    char key[BENCH_MAX_META][32];
    char value[BENCH_MAX_META][1200];
} bench_meta;

typedef struct bench_result {
    bench_meta meta;
    bench_config *configs;
    uint32_t config_count;
    char pass_names[BENCH_MAX_PASS_NAMES][32];
    uint32_t pass_count;
    bench_row *rows;
    size_t row_count, row_cap;
} bench_result;

typedef struct bench_ctx {
    bench_opts o;
    prw_scene *scene;
    prw_camera_path path;
    uint32_t frame_count;     /* playback frames after --frames-limit */
    double znear, ev100;
    uint32_t *frames;         /* this shard's frame indices, ascending */
    uint32_t nframes;
    bool *is_ref;             /* [frame_count] */
    uint32_t ref_every;
    prw_image *ref_a;         /* [frame_count], loaded for this shard's reference frames */
    bench_err *noise;         /* [frame_count] */
    bench_result res;
    prw_app_lightmaps *lightmaps; /* the scene's GI bake (NULL: none, or --no-bake) */
} bench_ctx;

/* bench_out.c: prints "floor ms F, base ms B, base/floor R" per config, medians over the rows of
 * the timestamped run (nothing when no row has a floor). */
void bench_print_base_floor(const bench_result *r);

/* cmd_bench.c */
bool bench_frame_view(const bench_ctx *c, uint32_t frame, prw_view *out, prw_error *e);

/* bench_ref.c */
bool bench_cache_dir(char *buf, size_t cap, prw_error *e);
bool bench_mkdirs(const char *dir, prw_error *e);
/* 32 hex digits over the full key of DESIGN.md §5. */
void bench_ref_key(const prw_scene *s, const prw_view *v, uint64_t spp, uint64_t seed, char out[33]);
/* Phase 1: makes sure every reference of this shard exists (child process), loads A, computes noise. */
bool bench_references(bench_ctx *c, prw_error *e);
/* The child: renders the jobs of --ref-child into --ref-dir. */
int bench_ref_child(bench_ctx *c);

/* bench_run.c */
bool bench_run_timed(bench_ctx *c, prw_gpu *gpu, prw_error *e);
bool bench_run_timestamped(bench_ctx *c, prw_gpu *gpu, prw_error *e);

/* bench_ab.c */
bool bench_run_ab(bench_ctx *c, prw_gpu *gpu, const prw_quality *a, const prw_quality *b, const char *b_text,
                  prw_error *e);

/* bench_stereo.c: --views 2 -- mono, naive and shared stereo interleaved (issue 5) */
bool bench_run_stereo(bench_ctx *c, prw_gpu *gpu, const prw_quality *q, const char *views_backend, prw_error *e);

/* bench_lod.c: --lod [MODEL] -- NURBS LOD triangles, update time, 1 vs 100 instances (issue 7) */
int bench_lod_main(prw_args *a);

/* bench_out.c */
void bench_meta_add(bench_meta *m, const char *key, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
const char *bench_meta_get(const bench_meta *m, const char *key);
void bench_machine_meta(bench_meta *m, prw_gpu *gpu);
bench_row *bench_result_row(bench_result *r, uint32_t config, uint32_t frame); /* finds or appends */
void bench_result_free(bench_result *r);
void bench_result_sort(bench_result *r);
bool bench_write_outputs(const bench_result *r, const char *dir, prw_error *e);
/* Reads frames.csv + passes.csv of a bench output dir. */
bool bench_read_outputs(const char *dir, bench_result *r, prw_error *e);
void bench_row_init(bench_row *row, uint32_t config, uint32_t frame);
/* Joins dir and name into buf. */
void bench_join(char *buf, size_t cap, const char *dir, const char *name);

/* Per-configuration figures computed from the rows only (summary.json, plots, merge). */
typedef struct bench_err_stats {
    double mean, worst; /* worst: max for FLIP, min for PSNR and SSIM */
} bench_err_stats;
typedef struct bench_config_stats {
    prw_stats_summary frame_ms, cpu_ms;
    uint64_t peak_mem, triangles_max;
    uint32_t ref_frames;
    bench_err_stats err[4], noise[4]; /* ldr_flip, hdr_flip, psnr, ssim */
    bool below_noise[4];
    double pass_p50[BENCH_MAX_PASS_NAMES]; /* NaN: never ran */
} bench_config_stats;
void bench_config_summary(const bench_result *r, uint32_t config, bench_config_stats *out);

/* bench_merge.c: joins shard output directories into out (created). */
bool bench_merge_dirs(const char *const *dirs, int n, const char *out, prw_error *e);

/* bench_plot.c: frame_time.png, error.png, and pareto.png for more than one config. */
void bench_plots(const bench_result *r, const char *dir);

/* The renderer description of a config at the bench's size (one view, timestamps off). */
/* The renderer of one config: the bench's size and the scene's light maps (every config draws the bake of
 * the first config's radiosity_size). */
static inline prw_render_desc bench_desc(const bench_ctx *c, const prw_quality *q)
{
    return (prw_render_desc){.width = c->o.width, .height = c->o.height, .quality = *q,
                             .lightmaps = prw_app_lightmaps_get(c->lightmaps),
                             .environment = prw_app_lightmaps_env(c->lightmaps),
                             .probes = prw_app_lightmaps_probes(c->lightmaps)};
}

#endif
