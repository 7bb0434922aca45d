/* prw btf-compress — BTF compression over knob points (issue "BTF materials", must-show 2): a
 * synthetic BTF (engine/bake/prw_btf_synth.h) or a Bonn binary (materials/btf/prw_btf_ubo.h) is
 * compressed by each codec point (materials/btf/prw_btf_codec.h); every point's file is written and
 * measured against the input: size, RMS %, varying-part %, mean abs; a CSV and a PNG of the curve. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "app.h"
#include "prw_btf.h"
#include "prw_btf_codec.h"
#include "prw_btf_synth.h"
#include "prw_strbuf.h"

static void help(void)
{
    printf("usage: prw btf-compress (--synthetic fabric|leather|flakes|brushed | --btf DUMP | FILE) [options]\n"
           "  Compresses a BTF by each codec point, writes each point's file, prints per point\n"
           "    btf: size X MB, RMS Y %%, varying Z %%, mean abs W   (codec, knobs, seconds, peak memory)\n"
           "  and writes DIR/<name>.csv and DIR/<name>.png (size against RMS; the PNG needs gnuplot).\n"
           "  FILE: a Bonn BTF binary (DFMF, FMF or sparse BDI; 3 channels).\n"
           "  --synthetic P     the generator's preset, measured by the path tracer on the 81 x 81 Bonn directions\n"
           "  --size N          synthetic: texels a side (default 256)\n"
           "  --spp N           synthetic: samples per ray (default 1: direct light is exact per sample)\n"
           "  --rays N          synthetic: stratified rays per texel side (default 1: the texel centre)\n"
           "  --dirs N          synthetic: the first N of the 81 directions (default 81; fewer for quick looks)\n"
           "  --codec C         fmf | cluster | pvf | sparse (default: every codec)\n"
           "  --points LIST     knob points: components for fmf / pvf (\"4,8,16\"), clusters x components for\n"
           "                    cluster (\"16x0,32x4\"), clusters x components + residual entries per texel for sparse\n"
           "                    (\"16x0+4\"); default fmf 4,8,16,32; cluster 16x0,64x0,16x4,32x4; pvf 1,2,4;\n"
           "                    sparse 4x0+1,8x0+2,16x0+4,64x0+0\n"
           "  --out DIR         output directory (default prw-out/btf)\n"
           "  --seed N          generator and codec seed (default 1)\n"
           "  --save-btf F      also write the input BTF to F as a raw dump (\"PRWBTFR1\", u32 width, height, views,\n"
           "                    lights, f32 (theta, phi) per view and light, f32 RGB in prw_btf's layout; the host's\n"
           "                    byte order: little-endian on x86-64 and arm64)\n"
           "  --btf F           read the input from such a raw dump instead of synthesising it\n"
           "Threads: the global --threads budget.  Memory: the BTF is held as float RGB (256^2 x 81^2: 5.2 GB);\n"
           "the global --max-memory budget is checked before allocating.\n");
}

static double peak_gb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / (1024.0 * 1024.0); /* KiB -> GiB */
}

/* user + system CPU seconds of the process so far (every thread): on a shared machine the wall time
 * depends on the load, these do much less */
static double cpu_s(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_utime.tv_sec + ru.ru_utime.tv_usec * 1e-6 + (double)ru.ru_stime.tv_sec + ru.ru_stime.tv_usec * 1e-6;
}

typedef struct prog {
    const char *what;
    int last;
    double t0;
} prog;

static void synth_progress(void *user, double f)
{
    prog *p = user;
    int pct = (int)(f * 100);
    if (pct / 5 > p->last / 5 || pct == 100) {
        fprintf(stderr, "prw: %s: %3d %% (%.0f s)\n", p->what, pct, prw_now() - p->t0);
        p->last = pct;
    }
}

static void codec_progress(void *user, const char *stage, double f)
{
    prog *p = user;
    int pct = (int)(f * 100);
    if (strcmp(stage, p->what) != 0) p->what = stage, p->last = -100;
    if (prw_now() - p->t0 < 2.0) return; /* quick points stay quiet */
    if (pct / 25 > p->last / 25) {
        fprintf(stderr, "prw:   %s %3d %% (%.0f s)\n", stage, pct, prw_now() - p->t0);
        p->last = pct;
    }
}


typedef struct point {
    prw_btf_codec codec;
    uint32_t comps, clusters;
    double sparse;
} point;

static const char *codec_name(prw_btf_codec c)
{
    return c == PRW_BTF_CODEC_FMF ? "fmf" : c == PRW_BTF_CODEC_CLUSTER ? "cluster" : c == PRW_BTF_CODEC_SPARSE ? "sparse" : "pvf";
}

/* The points of one codec: from --points or the defaults. */
static bool points_of(prw_btf_codec c, const char *list, point *out, int *n, prw_error *e)
{
    static const char *defaults[5] = {NULL, "4,8,16,32", "16x0,64x0,16x4,32x4", "1,2,4", "4x0+1,8x0+2,16x0+4,64x0+0"};
    const char *s = list ? list : defaults[c];
    char buf[512];
    snprintf(buf, sizeof buf, "%s", s);
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        if (*n >= 32) return prw_fail(e, "--points: at most 32 points");
        long a = 0, b = 0;
        char *x = strchr(tok, 'x');
        if (c == PRW_BTF_CODEC_CLUSTER || c == PRW_BTF_CODEC_SPARSE) {
            char *plus = strchr(tok, '+');
            if (!x || (c == PRW_BTF_CODEC_SPARSE) != !!plus)
                return prw_fail(e, "--points '%s': cluster points are CLUSTERSxCOMPONENTS, e.g. 32x4; sparse points "
                                   "CLUSTERSxCOMPONENTS+ENTRIES (residual entries per texel), e.g. 16x0+4", tok);
            *x = 0;
            double sp = 0;
            if (plus) {
                *plus = 0;
                char *end = NULL;
                sp = strtod(plus + 1, &end);
                if (end == plus + 1 || *end || !(sp >= 0 && sp <= 65535))
                    return prw_fail(e, "--points '%s': entries per texel: a number in [0, 65535]", plus + 1);
            }
            if (!prw_parse_int(tok, "--points clusters", 1, 1 << 20, &a, e) ||
                !prw_parse_int(x + 1, "--points components", 0, 4096, &b, e))
                return false;
            out[(*n)++] = (point){c, (uint32_t)b, (uint32_t)a, sp};
        } else {
            if (x || !prw_parse_int(tok, "--points components", 1, 4096, &a, e))
                return prw_fail(e, "--points '%s': %s points are component counts, e.g. 8", tok, codec_name(c));
            out[(*n)++] = (point){c, (uint32_t)a, 0, 0};
        }
    }
    return true;
}

static int fail(const char *msg, prw_args *a, int rc)
{
    fprintf(stderr, "prw btf-compress: error: %s\n", msg);
    prw_args_free(a);
    return rc;
}

int prw_cmd_btf_compress(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    if (!prw_args_init(&a, argc, argv, &e)) return fprintf(stderr, "prw btf-compress: error: %s\n", e.msg), 2;
    if (prw_args_flag(&a, "help")) {
        help();
        prw_args_free(&a);
        return 0;
    }
    bool bad = false;
    const char *synthetic = prw_args_value(&a, "synthetic", &e, &bad);
    const char *size_s = prw_args_value(&a, "size", &e, &bad), *spp_s = prw_args_value(&a, "spp", &e, &bad);
    const char *rays_s = prw_args_value(&a, "rays", &e, &bad), *dirs_s = prw_args_value(&a, "dirs", &e, &bad);
    const char *codec_s = prw_args_value(&a, "codec", &e, &bad), *points_s = prw_args_value(&a, "points", &e, &bad);
    const char *out_s = prw_args_value(&a, "out", &e, &bad), *seed_s = prw_args_value(&a, "seed", &e, &bad);
    const char *save_s = prw_args_value(&a, "save-btf", &e, &bad), *raw_s = prw_args_value(&a, "btf", &e, &bad);
    if (bad || !prw_args_finish(&a, &e)) return fail(e.msg, &a, 2);
    if ((!!synthetic + !!raw_s + (a.positional_count == 1)) != 1 || a.positional_count > 1)
        return fail("give one of --synthetic PRESET, --btf DUMP or a BTF file (see prw btf-compress --help)", &a, 2);
    prw_btf_synth_params sp = {.size = 256, .rays = 1, .spp = 1, .dirs = 81, .seed = 1};
    long v;
    if (synthetic && !prw_btf_synth_parse(synthetic, &sp.kind)) {
        snprintf(e.msg, sizeof e.msg, "--synthetic '%s': expected fabric, leather, flakes or brushed", synthetic);
        return fail(e.msg, &a, 2);
    }
    if ((size_s && (!prw_parse_int(size_s, "--size", 1, 4096, &v, &e) || !((sp.size = (uint32_t)v)))) ||
        (spp_s && (!prw_parse_int(spp_s, "--spp", 1, 1 << 16, &v, &e) || !((sp.spp = (uint32_t)v)))) ||
        (rays_s && (!prw_parse_int(rays_s, "--rays", 1, 16, &v, &e) || !((sp.rays = (uint32_t)v)))) ||
        (dirs_s && (!prw_parse_int(dirs_s, "--dirs", 1, 81, &v, &e) || !((sp.dirs = (uint32_t)v)))) ||
        (seed_s && (!prw_parse_int(seed_s, "--seed", 0, 1L << 30, &v, &e) || ((sp.seed = (uint64_t)v), false))))
        return fail(e.msg, &a, 2);
    point pts[96];
    int np = 0;
    prw_btf_codec only = 0;
    if (codec_s) {
        if (strcmp(codec_s, "fmf") == 0) only = PRW_BTF_CODEC_FMF;
        else if (strcmp(codec_s, "cluster") == 0) only = PRW_BTF_CODEC_CLUSTER;
        else if (strcmp(codec_s, "pvf") == 0) only = PRW_BTF_CODEC_PVF;
        else if (strcmp(codec_s, "sparse") == 0) only = PRW_BTF_CODEC_SPARSE;
        else return fail("--codec: expected fmf, cluster, pvf or sparse", &a, 2);
    } else if (points_s) {
        return fail("--points needs --codec (its knobs differ per codec)", &a, 2);
    }
    for (int c = PRW_BTF_CODEC_FMF; c <= PRW_BTF_CODEC_SPARSE; c++)
        if ((!only || (int)only == c) && !points_of((prw_btf_codec)c, points_s, pts, &np, &e)) return fail(e.msg, &a, 2);
    const char *dir = out_s ? out_s : "prw-out/btf";
    if (!prw_check_writable_dir(dir, true, &e) || !prw_mkdirs(dir, &e)) return fail(e.msg, &a, 1);

    /* the input */
    char name[256];
    prw_btf btf;
    double t0 = prw_now(), c0 = cpu_s();
    if (raw_s) {
        const char *base = strrchr(raw_s, '/');
        snprintf(name, sizeof name, "%s", base ? base + 1 : raw_s);
        if (!prw_btf_read_raw(raw_s, &btf, &e)) return fail(e.msg, &a, 1);
    } else if (synthetic) {
        snprintf(name, sizeof name, "%s-%u", synthetic, sp.size);
        char what[128];
        snprintf(what, sizeof what, "btf synth %s %u^2 x %u^2 directions", synthetic, sp.size, sp.dirs);
        prog pg = {what, -100, t0};
        sp.progress = synth_progress, sp.user = &pg, sp.threads = g_prw_opts.threads;
        if (!prw_btf_synthesize(&sp, &btf, &e)) return fail(e.msg, &a, 1);
    } else {
        const char *path = a.positional[0], *base = strrchr(path, '/');
        snprintf(name, sizeof name, "%s", base ? base + 1 : path);
        prw_btf_ubo u;
        if (!prw_btf_ubo_read(path, &u, &e)) return fail(e.msg, &a, 1);
        bool ok = prw_btf_from_ubo(&u, &btf, &e);
        prw_btf_ubo_free(&u);
        if (!ok) return fail(e.msg, &a, 1);
    }
    if (save_s) {
        if (!prw_btf_write_raw(save_s, &btf, &e)) {
            prw_btf_free(&btf);
            return fail(e.msg, &a, 1);
        }
        printf("wrote %s\n", save_s);
    }
    double t_in = prw_now() - t0, c_in = cpu_s() - c0, raw_mb = 12.0 * btf.width * btf.height * btf.views * btf.lights / 1e6;
    printf("btf input: %s, %u x %u texels, %u x %u directions, %.1f MB as float RGB, %.1f s (%.1f CPU-s), |A - Abar| / |A| = "
           "%.3f, peak memory %.2f GB\n",
           name, btf.width, btf.height, btf.views, btf.lights, raw_mb, t_in, c_in, prw_btf_varying_fraction(&btf),
           peak_gb());
    fflush(stdout);

    char csv_path[4096];
    snprintf(csv_path, sizeof csv_path, "%s/%s.csv", dir, name);
    prw_strbuf csv = {0};
    prw_strbuf_printf(&csv, "codec,clusters,components,sparse_entries,size_mb,rms_pct,varying_pct,mean_abs,seconds,peak_gb,file\n");
    int rc = 0;
    for (int i = 0; i < np; i++) {
        prw_btf_codec_params cp = {.codec = pts[i].codec, .components = pts[i].comps, .clusters = pts[i].clusters,
                                   .sparse_per_texel = pts[i].sparse,
                                   .seed = sp.seed, .threads = g_prw_opts.threads};
        prog pg = {"", -100, prw_now()};
        cp.progress = codec_progress, cp.user = &pg;
        prw_btf_packed pk;
        double t1 = prw_now();
        if (!prw_btf_compress(&btf, &cp, &pk, &e)) {
            fprintf(stderr, "prw btf-compress: %s %ux%u: %s\n", codec_name(pts[i].codec), pts[i].clusters, pts[i].comps, e.msg);
            rc = 1;
            continue;
        }
        double secs = prw_now() - t1;
        char file[4096];
        char extra[32] = "";
        if (pts[i].codec == PRW_BTF_CODEC_SPARSE) snprintf(extra, sizeof extra, "+%g", pts[i].sparse);
        snprintf(file, sizeof file, "%s/%s-%s-%ux%u%s.btfc", dir, name, codec_name(pts[i].codec), pts[i].clusters,
                 pts[i].comps, extra);
        if (!prw_btf_packed_write(file, &pk, &e)) {
            fprintf(stderr, "prw btf-compress: %s\n", e.msg);
            prw_btf_packed_free(&pk);
            rc = 1;
            continue;
        }
        prw_btf_error r;
        prw_btf_errors(&btf, &pk, g_prw_opts.threads, &r);
        double mb = (double)prw_btf_packed_bytes(&pk) / 1e6;
        printf("btf: size %.3f MB, RMS %.3f %%, varying %.3f %%, mean abs %.4g   (%s, %u clusters, %u components, %u "
               "residual entries; %.1f s; peak memory %.2f GB; %s)\n",
               mb, r.rms_pct, r.varying_pct, r.mean_abs, codec_name(pts[i].codec), pts[i].clusters, pts[i].comps,
               pk.sparse_count, secs, peak_gb(), file);
        fflush(stdout);
        prw_strbuf_printf(&csv, "%s,%u,%u,%u,%.6f,%.6f,%.6f,%.6g,%.2f,%.3f,%s\n", codec_name(pts[i].codec), pts[i].clusters,
                          pts[i].comps, pk.sparse_count, mb, r.rms_pct, r.varying_pct, r.mean_abs, secs, peak_gb(), file);
        prw_btf_packed_free(&pk);
    }
    if (!prw_write_file_atomic(csv_path, csv.p, csv.n, &e)) {
        fprintf(stderr, "prw btf-compress: %s\n", e.msg);
        rc = 1;
    } else {
        printf("wrote %s\n", csv_path);
        /* the curve: size against RMS per codec (gnuplot, as the bench plots; skipped without it) */
        char gp[4096 + 64], png[4096];
        snprintf(png, sizeof png, "%s/%s.png", dir, name);
        snprintf(gp, sizeof gp, "%s/%s.gp", dir, name);
        FILE *f = fopen(gp, "w");
        if (f) {
            fprintf(f, "set terminal pngcairo size 800,500 noenhanced\nset output '%s'\nset datafile separator ','\n"
                       "set key autotitle columnhead\nset xlabel 'size (MB)'\nset ylabel 'RMS (%%)'\nset logscale x\n"
                       "set title '%s: size against error'\n"
                       "plot for [c in 'fmf cluster pvf sparse'] '%s' using 5:(strcol(1) eq c ? $6 : 1/0) with linespoints title c\n",
                    png, name, csv_path);
            fclose(f);
            char cmd[8400];
            snprintf(cmd, sizeof cmd, "gnuplot '%s' 2>/dev/null", gp);
            if (system(cmd) == 0) printf("wrote %s\n", png);
            else fprintf(stderr, "prw btf-compress: note: no plot (gnuplot missing or failed); the CSV has the curve\n");
        }
    }
    free(csv.p);
    prw_btf_free(&btf);
    prw_args_free(&a);
    return rc;
}
