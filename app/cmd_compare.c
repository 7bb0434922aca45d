/* prw compare — how far a test image is from a reference, next to the reference's own noise.
 *
 * EXR pairs (linear radiance; engine/metrics): RMSE, relMSE, PSNR on linear RGB; SSIM and LDR-FLIP
 * on the frozen metric tone map, whose exposure is --ev100, else REF's prw:ev100 attribute, else
 * derived from REF (prw_compare_derive_ev100: its log-average luminance to middle grey; printed so
 * that --ev100 reproduces the figures); HDR-FLIP on linear RGB with its own exposure bracket.
 * PNG pairs (display values, e.g. from another renderer or a screenshot): LDR-FLIP on the sRGB-
 * decoded display values as the FLIP tool does, the other metrics as prw_compare_images_ldr says.
 * The kind is taken from the files' signatures; an EXR and a PNG are not compared.  With --ref2 (a second
 * reference rendered with another seed) each metric is also computed between the two references,
 * and an error below twice that reads "below reference noise".
 * Exit codes: 0 ok, 1 bad input (unreadable file, NaN/Inf pixels, size mismatch, failed write),
 * 2 usage (bad options, missing EV100).  Errors are one line on stderr; on any error nothing is
 * printed on stdout and no heat map is written.
 */
#define _POSIX_C_SOURCE 200809L
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "prw_image.h"
#include "prw_metrics.h"

int prw_cmd_compare(int argc, char **argv);

static void compare_usage(void)
{
    printf("usage: prw compare REF TEST [options]\n"
           "  REF, TEST          two EXR images (linear Rec.709, cd/m^2) or two PNG images (sRGB display\n"
           "                     values) of the same size; REF is the reference\n"
           "  --ref2 REF_B       a second reference rendered with another seed: the metrics between REF\n"
           "                     and REF_B are the reference noise, printed beside each error\n"
           "  --heatmap FILE     write the HDR-FLIP error map as a magma-coloured PNG\n"
           "  --json             print one JSON object instead of text\n"
           "  --ppd N            FLIP viewing condition in pixels per degree (default %g)\n"
           "  --ev100 X          EXR: exposure of the metric tone map (default: REF's prw:ev100 attribute,\n"
           "                     else derived from REF: the EV100 that maps its log-average luminance to\n"
           "                     middle grey 0.18, printed so that --ev100 reproduces the figures)\n"
           "  --peak P           PSNR peak (default: REF's largest R/G/B value; PNG: 1)\n"
           "metrics (EXR): RMSE, relMSE (eps %g) and PSNR on linear RGB; SSIM and LDR-FLIP on the metric\n"
           "tone map v%d (1.2*2^EV100 cd/m^2 -> 1, sRGB OETF, clamp); HDR-FLIP on linear RGB.\n"
           "metrics (PNG): LDR-FLIP on the display values decoded with the sRGB EOTF (as the FLIP tool);\n"
           "RMSE, relMSE, PSNR on those linear display values; SSIM on the encoded luma; no HDR-FLIP.\n",
           PRW_FLIP_DEFAULT_PPD, PRW_RELMSE_EPSILON, PRW_METRIC_TONEMAP_VERSION);
}

typedef struct compare_job {
    const char *ref, *test, *ref2, *heatmap;
    bool json, has_ev, has_peak;
    double ppd, ev100, peak;
    const char *ev_source;
    prw_compare_kind kind;
    bool ev_derived;
    double log_avg;     /* REF's log-average luminance when the exposure is derived */
    char ev_text[320];  /* ev_source when derived */
} compare_job;

/* ---- text ------------------------------------------------------------------------------- */

static void fmt_psnr(char *buf, size_t n, double psnr)
{
    if (isinf(psnr)) snprintf(buf, n, "inf");
    else if (isnan(psnr)) snprintf(buf, n, "undefined");
    else snprintf(buf, n, "%.3f", psnr);
}

static void print_row(const char *name, const char *err, const char *noise, bool has_noise, bool below,
                      double ratio)
{
    if (!has_noise) {
        printf("  %-22s %14s\n", name, err);
        return;
    }
    char verdict[64];
    if (below) snprintf(verdict, sizeof verdict, "below reference noise");
    else if (isfinite(ratio)) snprintf(verdict, sizeof verdict, "%.2fx reference noise", ratio);
    else snprintf(verdict, sizeof verdict, "above reference noise");
    printf("  %-22s %14s %16s   %s\n", name, err, noise, verdict);
}

static double ratio(double err, double noise) { return noise > 0 ? err / noise : INFINITY; }

static void print_stats(const char *name, const prw_flip_stats *s)
{
    printf("  %-15s mean %.6f  weighted median %.6f  weighted quartiles %.6f / %.6f  min %.6f  max %.6f\n", name,
           s->mean, s->weighted_median, s->weighted_q1, s->weighted_q3, s->min, s->max);
}

static void print_text(const compare_job *job, int w, int h, const prw_compare_metrics *m,
                       const prw_compare_metrics *noise, const prw_flip_exposures *x)
{
    bool hn = noise != NULL;
    prw_compare_verdicts v = {0};
    if (hn) prw_compare_verdict(m, noise, &v);
    bool png = job->kind == PRW_COMPARE_PNG;
    printf("reference  %s (%dx%d)\n", job->ref, w, h);
    printf("test       %s\n", job->test);
    if (hn) printf("reference noise: %s vs %s\n", job->ref2, job->ref);
    else printf("reference noise: unknown (pass --ref2)\n");
    if (png) {
        printf("inputs: PNG display values (8-bit sRGB codes decoded with the sRGB EOTF to linear display values in [0, 1])\n");
        printf("computed on: LDR-FLIP on the linear display values (as the FLIP tool does for LDR images); RMSE, relMSE,\n"
               "  PSNR on the linear display values; SSIM on the luma of the encoded values; HDR-FLIP: not computed\n"
               "  (display values have no HDR range)\n");
        printf("PSNR peak: %.6g (%s)\n", m->basic.peak, job->has_peak ? "--peak" : "the display range");
        printf("FLIP: %g pixels per degree\n", job->ppd);
    } else {
        printf("metric tone map v%d: EV100 %.4f (%s), %.6g cd/m^2 -> 1.0, sRGB OETF, clamp to [0,1]\n",
               PRW_METRIC_TONEMAP_VERSION, job->ev100, job->ev_source, 1.0 / prw_metric_tonemap_scale(job->ev100));
        printf("PSNR peak: %.6g (%s)\n", m->basic.peak, job->has_peak ? "--peak" : "reference's largest R/G/B value");
        printf("FLIP: %g pixels per degree; HDR-FLIP tone mapper %s, exposures %.4f to %.4f stops, %d exposures\n",
               job->ppd, PRW_HDRFLIP_TONEMAPPER, x->start, x->stop, x->count);
    }
    printf("\n");
    if (hn) printf("  %-22s %14s %16s   %s\n", "metric", "error", "reference noise", "verdict");
    else printf("  %-22s %14s\n", "metric", "error");
    char a[64], b[64];
    const prw_compare_metrics *n = noise;
#define NV(expr) (hn ? (expr) : 0.0)
    snprintf(a, sizeof a, "%.6g", m->basic.rmse), snprintf(b, sizeof b, "%.6g", NV(n->basic.rmse));
    print_row("RMSE", a, b, hn, v.rmse, NV(ratio(m->basic.rmse, n->basic.rmse)));
    snprintf(a, sizeof a, "%.6g", m->basic.relmse), snprintf(b, sizeof b, "%.6g", NV(n->basic.relmse));
    print_row("relMSE (eps 0.01)", a, b, hn, v.relmse, NV(ratio(m->basic.relmse, n->basic.relmse)));
    fmt_psnr(a, sizeof a, m->basic.psnr);
    fmt_psnr(b, sizeof b, NV(n->basic.psnr));
    print_row("PSNR (dB)", a, b, hn, v.psnr, NV(ratio(m->basic.rmse, n->basic.rmse)));
    snprintf(a, sizeof a, "%.6f", m->ssim), snprintf(b, sizeof b, "%.6f", NV(n->ssim));
    print_row("SSIM", a, b, hn, v.ssim, NV(ratio(1.0 - m->ssim, 1.0 - n->ssim)));
    snprintf(a, sizeof a, "%.6f", m->ldr_flip.mean), snprintf(b, sizeof b, "%.6f", NV(n->ldr_flip.mean));
    print_row("LDR-FLIP (mean)", a, b, hn, v.ldr_flip, NV(ratio(m->ldr_flip.mean, n->ldr_flip.mean)));
    if (png) {
        printf("  %-22s %14s\n", "HDR-FLIP (mean)", "n/a");
    } else {
        snprintf(a, sizeof a, "%.6f", m->hdr_flip.mean), snprintf(b, sizeof b, "%.6f", NV(n->hdr_flip.mean));
        print_row("HDR-FLIP (mean)", a, b, hn, v.hdr_flip, NV(ratio(m->hdr_flip.mean, n->hdr_flip.mean)));
    }
#undef NV
    printf("\nFLIP error distribution (weighted = each pixel weighted by its error, %d-bin histogram):\n",
           PRW_FLIP_HIST_BINS);
    print_stats("LDR-FLIP", &m->ldr_flip);
    if (!png) print_stats("HDR-FLIP", &m->hdr_flip);
    if (hn) {
        print_stats("LDR-FLIP noise", &n->ldr_flip);
        if (!png) print_stats("HDR-FLIP noise", &n->hdr_flip);
    }
    printf("versions: metrics %d, metric tone map %d\n", PRW_METRICS_VERSION, PRW_METRIC_TONEMAP_VERSION);
    if (job->heatmap)
        printf("wrote %s (%s error, magma, 0 = black .. 1 = pale yellow)\n", job->heatmap, png ? "LDR-FLIP" : "HDR-FLIP");
}

/* ---- JSON ------------------------------------------------------------------------------- */

static void json_psnr(cJSON *o, const char *key, double psnr)
{
    if (isinf(psnr)) cJSON_AddStringToObject(o, key, "inf"); /* JSON has no infinity */
    else if (isnan(psnr)) cJSON_AddNullToObject(o, key);
    else cJSON_AddNumberToObject(o, key, psnr);
}

static cJSON *json_stats(const prw_flip_stats *s)
{
    if (isnan(s->mean)) return cJSON_CreateNull(); /* not computed (HDR-FLIP of PNGs) */
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "mean", s->mean);
    cJSON_AddNumberToObject(o, "weighted_median", s->weighted_median);
    cJSON_AddNumberToObject(o, "weighted_q1", s->weighted_q1);
    cJSON_AddNumberToObject(o, "weighted_q3", s->weighted_q3);
    cJSON_AddNumberToObject(o, "min", s->min);
    cJSON_AddNumberToObject(o, "max", s->max);
    return o;
}

static cJSON *json_metrics(const prw_compare_metrics *m)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "rmse", m->basic.rmse);
    cJSON_AddNumberToObject(o, "relmse", m->basic.relmse);
    json_psnr(o, "psnr", m->basic.psnr);
    cJSON_AddNumberToObject(o, "ssim", m->ssim);
    cJSON_AddItemToObject(o, "ldr_flip", json_stats(&m->ldr_flip));
    cJSON_AddItemToObject(o, "hdr_flip", json_stats(&m->hdr_flip));
    return o;
}

static void print_json(const compare_job *job, int w, int h, const prw_compare_metrics *m,
                       const prw_compare_metrics *noise, const prw_flip_exposures *x)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "metrics_version", PRW_METRICS_VERSION);
    cJSON_AddStringToObject(root, "reference", job->ref);
    cJSON_AddStringToObject(root, "test", job->test);
    bool png = job->kind == PRW_COMPARE_PNG;
    cJSON_AddStringToObject(root, "inputs", png ? "png: sRGB display values, decoded to linear display values"
                                                : "exr: linear radiance");
    if (job->ref2) cJSON_AddStringToObject(root, "ref2", job->ref2);
    else cJSON_AddNullToObject(root, "ref2");
    cJSON_AddNumberToObject(root, "width", w);
    cJSON_AddNumberToObject(root, "height", h);
    if (png) {
        cJSON_AddNullToObject(root, "metric_tonemap");
    } else {
        cJSON *tm = cJSON_AddObjectToObject(root, "metric_tonemap");
        cJSON_AddNumberToObject(tm, "version", PRW_METRIC_TONEMAP_VERSION);
        cJSON_AddNumberToObject(tm, "ev100", job->ev100);
        cJSON_AddStringToObject(tm, "ev100_source", job->ev_source);
        if (job->ev_derived) cJSON_AddNumberToObject(tm, "reference_log_average_cd_m2", job->log_avg);
        cJSON_AddNumberToObject(tm, "white_cd_m2", 1.0 / prw_metric_tonemap_scale(job->ev100));
    }
    cJSON *ps = cJSON_AddObjectToObject(root, "psnr_peak");
    cJSON_AddNumberToObject(ps, "value", m->basic.peak);
    cJSON_AddStringToObject(ps, "source", job->has_peak ? "--peak" : png ? "display range" : "reference max R/G/B");
    cJSON_AddNumberToObject(root, "relmse_epsilon", PRW_RELMSE_EPSILON);
    cJSON_AddNumberToObject(root, "ppd", job->ppd);
    if (png) {
        cJSON_AddNullToObject(root, "hdr_flip_exposures");
    } else {
        cJSON *hf = cJSON_AddObjectToObject(root, "hdr_flip_exposures");
        cJSON_AddStringToObject(hf, "tone_mapper", PRW_HDRFLIP_TONEMAPPER);
        cJSON_AddNumberToObject(hf, "start", x->start);
        cJSON_AddNumberToObject(hf, "stop", x->stop);
        cJSON_AddNumberToObject(hf, "count", x->count);
    }
    cJSON_AddStringToObject(root, "weighted_quantiles", "error-weighted histogram, 1000 bins on [0,1]");
    cJSON_AddItemToObject(root, "error", json_metrics(m));
    if (noise) {
        cJSON_AddItemToObject(root, "reference_noise", json_metrics(noise));
        prw_compare_verdicts v;
        prw_compare_verdict(m, noise, &v);
        cJSON *b = cJSON_AddObjectToObject(root, "below_reference_noise");
        cJSON_AddBoolToObject(b, "rmse", v.rmse);
        cJSON_AddBoolToObject(b, "relmse", v.relmse);
        cJSON_AddBoolToObject(b, "psnr", v.psnr);
        cJSON_AddBoolToObject(b, "ssim", v.ssim);
        cJSON_AddBoolToObject(b, "ldr_flip", v.ldr_flip);
        if (png) cJSON_AddNullToObject(b, "hdr_flip");
        else cJSON_AddBoolToObject(b, "hdr_flip", v.hdr_flip);
    } else {
        cJSON_AddNullToObject(root, "reference_noise");
        cJSON_AddNullToObject(root, "below_reference_noise");
    }
    if (job->heatmap) cJSON_AddStringToObject(root, "heatmap", job->heatmap);
    else cJSON_AddNullToObject(root, "heatmap");
    char *s = cJSON_Print(root);
    printf("%s\n", s);
    free(s);
    cJSON_Delete(root);
}

/* ---- run -------------------------------------------------------------------------------- */

static const char *kind_name(prw_compare_kind k) { return k == PRW_COMPARE_PNG ? "a PNG" : "an OpenEXR"; }

/* The same kind as REF (two EXRs or two PNGs). */
static bool same_kind(const char *path, prw_compare_kind k, const compare_job *job, prw_error *e)
{
    prw_compare_kind o;
    if (!prw_compare_sniff(path, &o, e)) return false;
    if (o != k)
        return prw_fail(e, "%s: %s file, but REF %s is %s file: compare two EXRs (linear radiance) or two PNGs (display values)",
                        path, kind_name(o), job->ref, kind_name(k));
    return true;
}

static bool load(const compare_job *job, const char *path, prw_image *out, prw_error *e)
{
    return job->kind == PRW_COMPARE_PNG ? prw_compare_load_png(path, out, e) : prw_compare_load(path, out, e);
}

/* EXR: --ev100, else REF's prw:ev100, else derived from REF. */
static bool exposure(compare_job *job, const prw_image *ref, prw_error *e)
{
    if (job->has_ev) return true;
    if (prw_compare_read_ev100(job->ref, &job->ev100, e)) {
        job->ev_source = "prw:ev100 of REF";
        return true;
    }
    if (e->msg[0]) return false; /* present but unreadable */
    job->ev100 = prw_compare_derive_ev100(ref, &job->log_avg);
    job->ev_derived = true;
    snprintf(job->ev_text, sizeof job->ev_text,
             "derived: REF has no prw:ev100; its log-average luminance %.6g cd/m^2 maps to middle grey %.2f; "
             "--ev100 %.4f reproduces these figures",
             job->log_avg, PRW_COMPARE_EV_KEY, job->ev100);
    job->ev_source = job->ev_text;
    return true;
}

/* Returns the exit code; prints the one error line itself. */
static int compare_run(compare_job *job)
{
    prw_error e = {{0}};
    prw_image ref = {0}, test = {0}, ref2 = {0};
    float *map = NULL;
    int rc = 1;
    if (job->heatmap && !prw_check_writable(job->heatmap, false, &e)) goto done; /* before any work */
    if (!prw_compare_sniff(job->ref, &job->kind, &e) || !same_kind(job->test, job->kind, job, &e) ||
        (job->ref2 && !same_kind(job->ref2, job->kind, job, &e)))
        goto done;
    bool png = job->kind == PRW_COMPARE_PNG;
    if (png && job->has_ev) {
        prw_fail(&e, "--ev100: PNG inputs are display values; the metric tone map applies to EXR inputs only");
        rc = 2;
        goto done;
    }
    if (!load(job, job->ref, &ref, &e) || !load(job, job->test, &test, &e)) goto done;
    if (job->ref2 && !load(job, job->ref2, &ref2, &e)) goto done;
    if (!prw_compare_check_sizes(&test, &ref, job->test, job->ref, &e)) goto done;
    if (job->ref2 && !prw_compare_check_sizes(&ref2, &ref, job->ref2, job->ref, &e)) goto done;
    if (!png && !exposure(job, &ref, &e)) goto done;
    prw_compare_opts o = {.ppd = job->ppd, .ev100 = job->ev100, .peak = job->has_peak ? job->peak : 0.0};
    prw_compare_metrics m, noise;
    prw_flip_exposures x = {0};
    map = prw_malloc((size_t)ref.width * (size_t)ref.height * sizeof(float));
    bool ok = png ? prw_compare_images_ldr(&test, &ref, &o, &m, map, &e) : prw_compare_images(&test, &ref, &o, &m, map, &x, &e);
    if (!ok) {
        prw_fail_wrap(&e, "%s", job->test);
        goto done;
    }
    ok = !job->ref2 || (png ? prw_compare_images_ldr(&ref2, &ref, &o, &noise, NULL, &e)
                            : prw_compare_images(&ref2, &ref, &o, &noise, NULL, NULL, &e));
    if (!ok) {
        prw_fail_wrap(&e, "%s", job->ref2);
        goto done;
    }
    if (job->heatmap && !prw_heatmap_write_png(job->heatmap, map, ref.width, ref.height, &e)) goto done;
    if (job->json) print_json(job, ref.width, ref.height, &m, job->ref2 ? &noise : NULL, &x);
    else print_text(job, ref.width, ref.height, &m, job->ref2 ? &noise : NULL, &x);
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw compare: error: %s\n", e.msg[0] ? e.msg : "comparison failed");
    free(map);
    prw_image_free(&ref);
    prw_image_free(&test);
    prw_image_free(&ref2);
    return rc;
}

int prw_cmd_compare(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        compare_usage();
        prw_args_free(&a);
        return 0;
    }
    compare_job job = {.ppd = PRW_FLIP_DEFAULT_PPD, .ev_source = "--ev100"};
    const char *v;
    job.ref2 = prw_args_value(&a, "ref2", &e, &bad);
    job.heatmap = prw_args_value(&a, "heatmap", &e, &bad);
    job.json = prw_args_flag(&a, "json");
    if ((v = prw_args_value(&a, "ppd", &e, &bad)) && !prw_parse_double(v, "--ppd", 1, 1000, &job.ppd, &e)) bad = true;
    if ((v = prw_args_value(&a, "ev100", &e, &bad))) {
        job.has_ev = prw_parse_double(v, "--ev100", -20, 40, &job.ev100, &e);
        bad = bad || !job.has_ev;
    }
    if ((v = prw_args_value(&a, "peak", &e, &bad))) {
        job.has_peak = prw_parse_double(v, "--peak", 1e-30, 1e30, &job.peak, &e);
        bad = bad || !job.has_peak;
    }
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count != 2)
        bad = true, prw_fail(&e, "compare takes REF and TEST, got %d file(s) (see prw compare --help)", a.positional_count);
    if (bad) {
        fprintf(stderr, "prw compare: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    job.ref = a.positional[0];
    job.test = a.positional[1];
    int rc = compare_run(&job);
    prw_args_free(&a);
    return rc;
}
