/* ref_acc.c — accumulation files, merging, images and the EXR output; filter names; build hashes.
 *
 * File format (little-endian), version 1:
 *   offset  0  char[8]  "PRWACC01"
 *           8  u32      version (1)
 *          12  u32      header size (136)
 *          16  u32 x6   width, height, x0, y0, x1, y1
 *          40  u64 x5   s0, s1, seed, scene hash, material hash
 *          80  u32      filter kind;  84 i32 filter depth
 *          88  u64      non-finite samples dropped
 *          96  u64      payload bytes = (x1-x0)(y1-y0) * 3 channels * 32
 *         104  u64      FNV-1a 64 of the payload
 *         112  f64      ev100 of the view (IEEE-754 bits)
 *         120  u64 x2   reserved (0)
 *         136  payload: per tile pixel (row-major), per channel: sum (lo u64, hi u64), sum of squares
 *                       (lo u64, hi u64), two's complement 128-bit fixed point (prw_reference.h).
 * The reader checks every field and the exact file size before it allocates anything. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "prw_image.h"
#include "ref_build_info.h"
#include "ref_internal.h"

#define HDR_SIZE 136u
#define ACC_VERSION 1u
static const char k_magic[8] = {'P', 'R', 'W', 'A', 'C', 'C', '0', '1'};

/* ---- build info ---- */

const char *prw_ref_material_hash_hex(void) { return PRW_REF_BRDF_SHA256; }
uint64_t prw_ref_material_hash(void) { return strtoull(PRW_REF_BRDF_SHA256_16, NULL, 16); }
const char *prw_ref_git_hash(void) { return PRW_REF_GIT_HASH; }

/* ---- cameras ---- */

bool prw_ref_view_for_camera(const prw_scene *s, const char *camera, uint32_t width, uint32_t height, prw_view *out,
                             prw_error *e)
{
    int c = prw_scene_find_camera(s, camera);
    if (c < 0) {
        if (s->camera_count == 0) return prw_fail(e, "%s: the scene has no camera", s->source[0] ? s->source : "(scene)");
        char list[512] = "";
        size_t o = 0;
        for (uint32_t i = 0; i < s->camera_count && o + 70 < sizeof list; i++)
            o += (size_t)snprintf(list + o, sizeof list - o, "%s'%s'", i ? ", " : "", s->cameras[i].name);
        return prw_fail(e, "%s: no camera named '%.64s' (cameras: %s)", s->source[0] ? s->source : "(scene)", camera,
                        list);
    }
    return prw_view_from_camera(s, c, width, height, out, e);
}

/* ---- filters ---- */

static const char *const k_filter_names[PRW_REF_FILTER_COUNT] = {
    "all", "emission", "direct", "indirect", "diffuse-last", "glossy-last", "depth", "maxdepth",
    "indirect-diffuse-last", "indirect-glossy-last", "environment-direct", "mindepth"};

bool prw_ref_filter_parse(const char *s, prw_ref_filter *out, prw_error *e)
{
    out->kind = PRW_REF_ALL;
    out->depth = 0;
    for (int k = 0; k < PRW_REF_FILTER_COUNT; k++)
        if (k != PRW_REF_DEPTH && k != PRW_REF_MAX_DEPTH && k != PRW_REF_MIN_DEPTH && strcmp(s, k_filter_names[k]) == 0) {
            out->kind = (prw_ref_filter_kind)k;
            return true;
        }
    const char *num = NULL;
    if (strncmp(s, "depth:", 6) == 0) out->kind = PRW_REF_DEPTH, num = s + 6;
    else if (strncmp(s, "maxdepth:", 9) == 0) out->kind = PRW_REF_MAX_DEPTH, num = s + 9;
    else if (strncmp(s, "mindepth:", 9) == 0) out->kind = PRW_REF_MIN_DEPTH, num = s + 9;
    if (num) {
        char *end = NULL;
        long v = *num ? strtol(num, &end, 10) : -1;
        if (end && *end == '\0' && v >= 0 && v <= 1000000) {
            out->depth = (int)v;
            return true;
        }
    }
    return prw_fail(e, "filter '%.64s': expected all|emission|direct|indirect|diffuse-last|glossy-last|"
                       "indirect-diffuse-last|indirect-glossy-last|environment-direct|depth:N|maxdepth:N|mindepth:N "
                       "(N in 0..1000000)", s);
}

void prw_ref_filter_name(prw_ref_filter f, char *buf, size_t cap)
{
    if ((unsigned)f.kind >= PRW_REF_FILTER_COUNT) snprintf(buf, cap, "invalid(%d)", (int)f.kind);
    else if (f.kind == PRW_REF_DEPTH || f.kind == PRW_REF_MAX_DEPTH || f.kind == PRW_REF_MIN_DEPTH) snprintf(buf, cap, "%s:%d", k_filter_names[f.kind], f.depth);
    else snprintf(buf, cap, "%s", k_filter_names[f.kind]);
}

/* ---- little-endian helpers ---- */

static void put32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static void put64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static uint32_t get32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v |= (uint32_t)p[i] << (8 * i);
    return v;
}
static uint64_t get64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= (uint64_t)p[i] << (8 * i);
    return v;
}
static void put128(uint8_t *p, prw_ref_fixed v)
{
    unsigned __int128 u = (unsigned __int128)v;
    put64(p, (uint64_t)u);
    put64(p + 8, (uint64_t)(u >> 64));
}
static prw_ref_fixed get128(const uint8_t *p)
{
    unsigned __int128 u = ((unsigned __int128)get64(p + 8) << 64) | get64(p);
    return (prw_ref_fixed)u;
}

static size_t tile_pixels(const prw_ref_acc *a) { return (size_t)(a->x1 - a->x0) * (a->y1 - a->y0); }

bool prw_ref_acc_write(const char *path, const prw_ref_acc *a, prw_error *e)
{
    size_t np = tile_pixels(a), payload = np * 3 * 32;
    uint8_t *buf = prw_calloc(HDR_SIZE + payload, 1);
    uint8_t *q = buf + HDR_SIZE;
    for (size_t i = 0; i < 3 * np; i++, q += 32) {
        put128(q, a->sum[i]);
        put128(q + 16, a->sq[i]);
    }
    memcpy(buf, k_magic, 8);
    put32(buf + 8, ACC_VERSION);
    put32(buf + 12, HDR_SIZE);
    const uint32_t dims[6] = {a->width, a->height, a->x0, a->y0, a->x1, a->y1};
    for (int i = 0; i < 6; i++) put32(buf + 16 + 4 * i, dims[i]);
    const uint64_t ids[5] = {a->s0, a->s1, a->seed, a->scene_hash, a->material_hash};
    for (int i = 0; i < 5; i++) put64(buf + 40 + 8 * i, ids[i]);
    put32(buf + 80, (uint32_t)a->filter.kind);
    put32(buf + 84, (uint32_t)a->filter.depth);
    put64(buf + 88, a->nonfinite);
    put64(buf + 96, payload);
    put64(buf + 104, prw_hash64(buf + HDR_SIZE, payload, 0));
    uint64_t evb;
    memcpy(&evb, &a->ev100, 8);
    put64(buf + 112, evb);
    bool ok = prw_write_file_atomic(path, buf, HDR_SIZE + payload, e);
    free(buf);
    return ok;
}

/* Checks the header (the first HDR_SIZE bytes of p, of a file of `size` bytes) and the file size
 * against it; fills every header field of *a (no arrays).  Nothing is allocated. */
static bool parse_header(const uint8_t *p, size_t avail, uint64_t size, const char *name, prw_ref_acc *a,
                         uint64_t *payload_out, uint64_t *sum_out, prw_error *e)
{
    if (avail < 16 || memcmp(p, k_magic, 8) != 0) {
        if (avail >= 8 && memcmp(p, k_magic, 6) == 0) {
            char rev[3]; /* printable or '?': the message stays one clean line */
            for (int i = 0; i < 2; i++) rev[i] = p[6 + i] >= 0x20 && p[6 + i] < 0x7f ? (char)p[6 + i] : '?';
            rev[2] = '\0';
            return prw_fail(e, "%s: header: unsupported format revision '%s' (this reader knows '01')", name, rev);
        }
        return prw_fail(e, "%s: header: not a prw accumulation file (wrong magic)", name);
    }
    uint32_t version = get32(p + 8), hsize = get32(p + 12);
    if (version != ACC_VERSION) return prw_fail(e, "%s: header: unsupported version %u (this reader knows 1)", name, version);
    if (hsize != HDR_SIZE) return prw_fail(e, "%s: header: header size %u (expected %u)", name, hsize, HDR_SIZE);
    if (avail < HDR_SIZE)
        return prw_fail(e, "%s: offset %zu: truncated header (%zu of %u bytes)", name, avail, avail, HDR_SIZE);
    memset(a, 0, sizeof *a);
    a->width = get32(p + 16), a->height = get32(p + 20);
    a->x0 = get32(p + 24), a->y0 = get32(p + 28), a->x1 = get32(p + 32), a->y1 = get32(p + 36);
    a->s0 = get64(p + 40), a->s1 = get64(p + 48), a->seed = get64(p + 56);
    a->scene_hash = get64(p + 64), a->material_hash = get64(p + 72);
    uint32_t fk = get32(p + 80);
    a->filter.depth = (int32_t)get32(p + 84);
    a->nonfinite = get64(p + 88);
    uint64_t payload = get64(p + 96);
    *sum_out = get64(p + 104);
    if (a->width == 0 || a->height == 0 || (uint64_t)a->width * a->height > ((uint64_t)1 << 28))
        return prw_fail(e, "%s: header: image size %ux%u is empty or too large", name, a->width, a->height);
    if (!(a->x0 < a->x1 && a->y0 < a->y1 && a->x1 <= a->width && a->y1 <= a->height))
        return prw_fail(e, "%s: header: tile %u,%u,%u,%u is empty or outside the %ux%u image", name, a->x0, a->y0, a->x1,
                        a->y1, a->width, a->height);
    if (!(a->s1 > a->s0) || a->s1 - a->s0 > PRW_REF_MAX_SPP)
        return prw_fail(e, "%s: header: sample range [%llu, %llu) is empty or larger than %llu", name,
                        (unsigned long long)a->s0, (unsigned long long)a->s1, (unsigned long long)PRW_REF_MAX_SPP);
    if (fk >= PRW_REF_FILTER_COUNT) return prw_fail(e, "%s: header: unknown filter %u", name, fk);
    a->filter.kind = (prw_ref_filter_kind)fk;
    bool depth_kind = a->filter.kind == PRW_REF_DEPTH || a->filter.kind == PRW_REF_MAX_DEPTH ||
                      a->filter.kind == PRW_REF_MIN_DEPTH;
    if (a->filter.depth < 0 || a->filter.depth > 1000000 || (!depth_kind && a->filter.depth != 0))
        return prw_fail(e, "%s: header: filter depth %d is invalid", name, a->filter.depth);
    uint64_t evb = get64(p + 112);
    memcpy(&a->ev100, &evb, 8);
    if (!isfinite(a->ev100) || fabs(a->ev100) > 100) return prw_fail(e, "%s: header: ev100 is not a finite number in [-100, 100]", name);
    for (int i = 0; i < 2; i++)
        if (get64(p + 120 + 8 * i) != 0) return prw_fail(e, "%s: header: reserved field %d is not zero", name, i);
    uint64_t expect = (uint64_t)tile_pixels(a) * 3 * 32;
    if (payload != expect)
        return prw_fail(e, "%s: header: payload size %llu does not match the tile (%llu bytes expected)", name,
                        (unsigned long long)payload, (unsigned long long)expect);
    if (size - HDR_SIZE < payload)
        return prw_fail(e, "%s: offset %llu: truncated (file has %llu bytes, %llu expected)", name,
                        (unsigned long long)size, (unsigned long long)size, (unsigned long long)(HDR_SIZE + payload));
    if (size - HDR_SIZE > payload)
        return prw_fail(e, "%s: offset %llu: %llu unexpected bytes after the payload", name,
                        (unsigned long long)(HDR_SIZE + payload), (unsigned long long)(size - HDR_SIZE - payload));
    *payload_out = payload;
    return true;
}

bool prw_ref_acc_read_memory(const void *data, size_t size, const char *name, prw_ref_acc *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    const uint8_t *p = data;
    if (!name) name = "(accumulation)";
    prw_ref_acc a;
    uint64_t payload = 0, sum = 0;
    if (!parse_header(p, size, size, name, &a, &payload, &sum, e)) return false;
    if (prw_hash64(p + HDR_SIZE, payload, 0) != sum)
        return prw_fail(e, "%s: payload: checksum mismatch (corrupt file)", name);
    size_t n = 3 * tile_pixels(&a);
    if (!prw_mem_check(prw_mul_sat(n, 2 * sizeof(prw_ref_fixed)), name, "the accumulation", e)) return false;
    a.sum = prw_malloc(n * sizeof(prw_ref_fixed));
    a.sq = prw_malloc(n * sizeof(prw_ref_fixed));
    const uint8_t *q = p + HDR_SIZE;
    for (size_t i = 0; i < n; i++, q += 32) {
        a.sum[i] = get128(q);
        a.sq[i] = get128(q + 16);
        if (a.sq[i] < 0) {
            prw_ref_acc_free(&a);
            return prw_fail(e, "%s: offset %zu: negative sum of squares (corrupt file)", name, (size_t)(q + 16 - p));
        }
    }
    *out = a;
    return true;
}

bool prw_ref_acc_read(const char *path, prw_ref_acc *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    /* the header first: its sizes are checked against the file's before the payload is read */
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return prw_fail(e, "%s: cannot open: not a regular file", path);
    }
    uint8_t hdr[HDR_SIZE];
    size_t got = fread(hdr, 1, sizeof hdr, f);
    fclose(f);
    prw_ref_acc a;
    uint64_t payload = 0, sum = 0;
    if (!parse_header(hdr, got, (uint64_t)st.st_size, path, &a, &payload, &sum, e)) return false;
    /* file bytes + the two 128-bit arrays */
    if (!prw_mem_check(prw_add_sat((uint64_t)st.st_size, payload), path, "reading the accumulation", e)) return false;
    char *data = NULL;
    size_t size = 0;
    if (!prw_read_file_bounded(path, (uint64_t)st.st_size, 1, "an accumulation file", &data, &size, e)) return false;
    bool ok = prw_ref_acc_read_memory(data, size, path, out, e);
    free(data);
    return ok;
}

/* ---- merge ---- */

bool prw_ref_acc_merge(const prw_ref_acc *const *in, const char *const *names, int count, prw_ref_acc *out,
                       prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (count < 1) return prw_fail(e, "merge: no accumulations");
    const prw_ref_acc *a0 = in[0];
    const char *n0 = names ? names[0] : "input 0";
    for (int i = 1; i < count; i++) {
        const prw_ref_acc *a = in[i];
        const char *ni = names ? names[i] : "input";
        char f0[32], f1[32];
        prw_ref_filter_name(a0->filter, f0, sizeof f0);
        prw_ref_filter_name(a->filter, f1, sizeof f1);
        if (a->width != a0->width || a->height != a0->height)
            return prw_fail(e, "%s: merge: image size %ux%u differs from %s (%ux%u)", ni, a->width, a->height, n0,
                            a0->width, a0->height);
        if (a->seed != a0->seed)
            return prw_fail(e, "%s: merge: seed %llu differs from %s (%llu)", ni, (unsigned long long)a->seed, n0,
                            (unsigned long long)a0->seed);
        if (a->scene_hash != a0->scene_hash)
            return prw_fail(e, "%s: merge: scene hash %016llx differs from %s (%016llx)", ni,
                            (unsigned long long)a->scene_hash, n0, (unsigned long long)a0->scene_hash);
        if (a->material_hash != a0->material_hash)
            return prw_fail(e, "%s: merge: material hash %016llx differs from %s (%016llx)", ni,
                            (unsigned long long)a->material_hash, n0, (unsigned long long)a0->material_hash);
        if (strcmp(f0, f1) != 0) return prw_fail(e, "%s: merge: filter '%s' differs from %s ('%s')", ni, f1, n0, f0);
        if (a->ev100 != a0->ev100)
            return prw_fail(e, "%s: merge: ev100 %g differs from %s (%g): another camera?", ni, a->ev100, n0, a0->ev100);
    }
    /* overlapping sample ranges on a shared pixel would count samples twice */
    for (int i = 0; i < count; i++)
        for (int k = i + 1; k < count; k++) {
            const prw_ref_acc *a = in[i], *b = in[k];
            bool share = a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
            bool overlap = a->s0 < b->s1 && b->s0 < a->s1;
            if (share && overlap)
                return prw_fail(e, "%s: merge: samples [%llu, %llu) overlap those of %s [%llu, %llu) on shared pixels",
                                names ? names[k] : "input", (unsigned long long)b->s0, (unsigned long long)b->s1,
                                names ? names[i] : "input", (unsigned long long)a->s0, (unsigned long long)a->s1);
        }
    size_t np = (size_t)a0->width * a0->height;
    if (!prw_mem_check(prw_mul_sat(np, sizeof(uint64_t) + 6 * sizeof(prw_ref_fixed)), n0, "merging the accumulations", e))
        return false;
    uint64_t *cnt = prw_calloc(np, sizeof(uint64_t));
    prw_ref_acc m;
    memset(&m, 0, sizeof m);
    m.width = a0->width, m.height = a0->height;
    m.x1 = m.width, m.y1 = m.height;
    m.seed = a0->seed, m.scene_hash = a0->scene_hash, m.material_hash = a0->material_hash, m.filter = a0->filter;
    m.ev100 = a0->ev100;
    m.sum = prw_calloc(3 * np, sizeof(prw_ref_fixed));
    m.sq = prw_calloc(3 * np, sizeof(prw_ref_fixed));
    uint64_t lo = UINT64_MAX, hi = 0;
    for (int i = 0; i < count; i++) {
        const prw_ref_acc *a = in[i];
        uint32_t tw = a->x1 - a->x0;
        for (uint32_t y = a->y0; y < a->y1; y++)
            for (uint32_t x = a->x0; x < a->x1; x++) {
                size_t di = (size_t)y * m.width + x, si = (size_t)(y - a->y0) * tw + (x - a->x0);
                for (int c = 0; c < 3; c++) {
                    m.sum[3 * di + c] += a->sum[3 * si + c];
                    m.sq[3 * di + c] += a->sq[3 * si + c];
                }
                cnt[di] += a->s1 - a->s0;
            }
        m.nonfinite += a->nonfinite;
        lo = PRW_MIN(lo, a->s0);
        hi = PRW_MAX(hi, a->s1);
    }
    size_t missing = 0, first_missing = 0, uneven = np;
    for (size_t i = 0; i < np; i++) {
        if (cnt[i] == 0 && missing++ == 0) first_missing = i;
        if (cnt[i] != cnt[0] && uneven == np) uneven = i;
    }
    uint64_t n = cnt[0];
    free(cnt);
    if (missing) {
        prw_ref_acc_free(&m);
        return prw_fail(e, "merge: %zu pixels are not covered by any tile (first: %zu,%zu)", missing,
                        first_missing % a0->width, first_missing / a0->width);
    }
    if (uneven != np) {
        prw_ref_acc_free(&m);
        return prw_fail(e, "merge: pixels have different sample counts (pixel %zu,%zu differs from pixel 0,0)",
                        uneven % a0->width, uneven / a0->width);
    }
    if (n > PRW_REF_MAX_SPP) {
        prw_ref_acc_free(&m);
        return prw_fail(e, "merge: %llu samples per pixel exceed %llu", (unsigned long long)n,
                        (unsigned long long)PRW_REF_MAX_SPP);
    }
    /* one interval when the ranges tile [lo, hi) exactly, else [0, n) */
    if (hi - lo == n) m.s0 = lo, m.s1 = hi;
    else m.s0 = 0, m.s1 = n;
    *out = m;
    return true;
}

/* ---- images and EXR ---- */

bool prw_ref_acc_images(const prw_ref_acc *a, float **mean_rgba, float **var_rgba, prw_error *e)
{
    *mean_rgba = NULL;
    if (var_rgba) *var_rgba = NULL;
    if (a->x0 != 0 || a->y0 != 0 || a->x1 != a->width || a->y1 != a->height)
        return prw_fail(e, "reference: tile %u,%u,%u,%u is not the whole %ux%u image (merge tiles first)", a->x0, a->y0,
                        a->x1, a->y1, a->width, a->height);
    size_t np = (size_t)a->width * a->height;
    if (!prw_mem_check(prw_mul_sat(np, (var_rgba ? 2 : 1) * 4 * sizeof(float)), "reference", "the mean and variance images", e))
        return false;
    double n = (double)(a->s1 - a->s0);
    float *m = prw_malloc(np * 4 * sizeof(float));
    float *v = var_rgba ? prw_malloc(np * 4 * sizeof(float)) : NULL;
    for (size_t i = 0; i < np; i++) {
        for (int c = 0; c < 3; c++) {
            double mean = (double)a->sum[3 * i + c] / PRW_REF_SUM_SCALE / n;
            m[4 * i + c] = (float)mean;
            if (v) {
                double ex2 = (double)a->sq[3 * i + c] / PRW_REF_SQ_SCALE / n;
                double var = n > 1 ? fmax(0.0, ex2 - mean * mean) * n / (n - 1) : 0;
                v[4 * i + c] = (float)(var / n);
            }
        }
        m[4 * i + 3] = 1.0f;
        if (v) v[4 * i + 3] = (float)n;
    }
    *mean_rgba = m;
    if (var_rgba) *var_rgba = v;
    return true;
}

void prw_ref_var_path(const char *path, char *buf, size_t cap)
{
    size_t n = strlen(path);
    if (n > 4 && strcmp(path + n - 4, ".exr") == 0) n -= 4;
    snprintf(buf, cap, "%.*s.var.exr", (int)n, path);
}

bool prw_ref_write_exr(const char *path, const prw_ref_acc *a, const char *const *extra_kv,
                       int extra_count, prw_error *e)
{
    float *mean = NULL, *var = NULL;
    if (!prw_ref_acc_images(a, &mean, &var, e)) return false;
    char spp[32], seed[32], sh[32], ev[32], filt[32], samples[64], nonf[32];
    snprintf(spp, sizeof spp, "%llu", (unsigned long long)(a->s1 - a->s0));
    snprintf(seed, sizeof seed, "%llu", (unsigned long long)a->seed);
    snprintf(sh, sizeof sh, "%016llx", (unsigned long long)a->scene_hash);
    snprintf(ev, sizeof ev, "%.4f", a->ev100);
    snprintf(samples, sizeof samples, "%llu,%llu", (unsigned long long)a->s0, (unsigned long long)a->s1);
    snprintf(nonf, sizeof nonf, "%llu", (unsigned long long)a->nonfinite);
    prw_ref_filter_name(a->filter, filt, sizeof filt);
    enum { BASE = 11 };
    prw_kv *kv = prw_calloc((size_t)BASE + 1 + (extra_count > 0 ? (size_t)extra_count : 0), sizeof(prw_kv));
    const prw_kv base[BASE] = {
        {"prw:spp", spp},         {"prw:seed", seed},       {"prw:scene_hash", sh},
        {"prw:material_hash", prw_ref_material_hash_hex()}, {"prw:git", prw_ref_git_hash()},
        {"prw:filter", filt},     {"prw:ev100", ev},        {"prw:samples", samples},
        {"prw:nonfinite", nonf},  {"prw:units", "cd/m^2, linear Rec.709"},
        {"prw:pixel_filter", "box over the pixel square [i,i+1)x[j,j+1)"},
    };
    int nkv = 0;
    for (int i = 0; i < BASE; i++) kv[nkv++] = base[i];
    for (int i = 0; i < extra_count; i++) kv[nkv++] = (prw_kv){extra_kv[2 * i], extra_kv[2 * i + 1]};
    prw_image img = {(int)a->width, (int)a->height, mean};
    bool ok = prw_exr_write(path, &img, kv, nkv, e);
    if (ok) {
        char vp[2048];
        prw_ref_var_path(path, vp, sizeof vp);
        kv[nkv++] = (prw_kv){"prw:content", "RGB = variance of the mean per channel ((cd/m^2)^2), A = samples"};
        img.rgba = var;
        ok = prw_exr_write(vp, &img, kv, nkv, e);
        if (!ok) remove(path); /* both files or none */
    }
    free(kv);
    free(mean);
    free(var);
    return ok;
}
