/* The BTF codecs (materials/btf/prw_btf_codec.h), on BTFs of known structure:
 *  - svd:        the truncated SVD of an exactly rank-3 matrix gives its singular values and rebuilds it;
 *  - fmf:        the closed-form tensor is rank 2 as a (direction, channel) x texel matrix: FMF with 2
 *                components rebuilds it to half precision, with 1 it cannot;
 *  - cluster:    a BTF of 6 distinct ABRDFs: 6 clusters without components rebuild it; a BTF whose
 *                clusters vary along one direction each: 3 clusters x 1 component;
 *  - pvf:        per view a mean plus one varying pattern: 1 component per view;
 *  - sparse:     one ABRDF everywhere plus 4 spikes (2 texels x 2 direction pairs, "flakes"): the
 *                residual after 1 cluster lives on 4 pairs x 30 texels, so 4 entries per texel rebuild it;
 *                4 entries in all keep exactly the 4 spikes and (the mean refitted without them) rebuild it;
 *                3 cannot (a spike is lost);
 *  - errors:     the three figures on a 2-texel BTF computed by hand (rms, varying, mean abs);
 *  - file:       every codec's file round-trips exactly; truncations, a bad cluster index and SPARSE
 *                entries out of order refused. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "btf_linalg.h"
#include "btf_samples.h"
#include "prw_btf_codec.h"
#include "prw_test.h"

static uint64_t st = 99;
static double rnd(void)
{
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(st >> 11) * 0x1.0p-53;
}

static void test_svd(void)
{
    /* A = sum_k s_k a_k b_k^T with orthonormal a (40), b (30) from Gram-Schmidt of random vectors */
    enum { M = 40, N = 30, R = 3 };
    double a[R][M], b[R][N], s[R] = {5, 2, 0.5};
    for (int k = 0; k < R; k++) {
        for (int i = 0; i < M; i++) a[k][i] = rnd() - 0.5;
        for (int j = 0; j < N; j++) b[k][j] = rnd() - 0.5;
        for (int p = 0; p < k; p++) {
            double da = 0, db = 0;
            for (int i = 0; i < M; i++) da += a[k][i] * a[p][i];
            for (int j = 0; j < N; j++) db += b[k][j] * b[p][j];
            for (int i = 0; i < M; i++) a[k][i] -= da * a[p][i];
            for (int j = 0; j < N; j++) b[k][j] -= db * b[p][j];
        }
        double na = 0, nb = 0;
        for (int i = 0; i < M; i++) na += a[k][i] * a[k][i];
        for (int j = 0; j < N; j++) nb += b[k][j] * b[k][j];
        for (int i = 0; i < M; i++) a[k][i] /= sqrt(na);
        for (int j = 0; j < N; j++) b[k][j] /= sqrt(nb);
    }
    float mat[M * N];
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++) {
            double v = 0;
            for (int k = 0; k < R; k++) v += s[k] * a[k][i] * b[k][j];
            mat[i * N + j] = (float)v;
        }
    btf_mat m = {.base = mat, .m = M, .n = N, .rd = 1, .r1 = N, .r2 = 0, .cd = 1, .c1 = 1, .c2 = 0};
    double u[M * 4], sv[4], v[N * 4];
    prw_error e;
    CHECK_OK(btf_svd(&m, 4, 5, 2, 1, 2, u, sv, v, &e), &e);
    for (int k = 0; k < R; k++) CHECK_NEAR(sv[k], s[k], 1e-5);
    CHECK(sv[3] < 1e-5);
    double worst = 0;
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++) {
            double r = 0;
            for (int k = 0; k < 4; k++) r += u[i * 4 + k] * sv[k] * v[j * 4 + k];
            worst = fmax(worst, fabs(r - mat[i * N + j]));
        }
    CHECK_MSG(worst < 1e-5, "rebuilt to %.3g", worst);
    printf("svd: singular values %.6f %.6f %.6f %.2g, rebuilt to %.2g\n", sv[0], sv[1], sv[2], sv[3], worst);
}

/* the closed-form tensor as a container */
static void tensor_btf(uint32_t V, uint32_t L, uint32_t W, uint32_t H, prw_btf *b)
{
    prw_btf_ubo u;
    prw_error e;
    btf_sample_tensor_file(PRW_BTF_UBO_BDI, V, L, W, H, &u);
    if (!prw_btf_from_ubo(&u, b, &e)) fprintf(stderr, "%s\n", e.msg);
    prw_btf_ubo_free(&u);
}

static double g_sparse = 2; /* SPARSE: entries per texel for run() */

static prw_btf_error run(const prw_btf *b, prw_btf_codec codec, uint32_t comps, uint32_t clusters, prw_btf_packed *out)
{
    prw_btf_codec_params p = {.codec = codec, .components = comps, .clusters = clusters, .sparse_per_texel = g_sparse,
                              .seed = 3, .threads = 2};
    prw_error e;
    prw_btf_error r = {0};
    if (!prw_btf_compress(b, &p, out, &e)) {
        fprintf(stderr, "compress: %s\n", e.msg);
        r.rms_pct = 1e9;
        return r;
    }
    prw_btf_errors(b, out, 2, &r);
    printf("codec %d, %u components, %u clusters: %llu bytes, rms %.4f %%, varying %.4f %%, mean abs %.3g\n", (int)codec,
           comps, clusters, (unsigned long long)prw_btf_packed_bytes(out), r.rms_pct, r.varying_pct, r.mean_abs);
    return r;
}

static void test_fmf(void)
{
    prw_btf b;
    tensor_btf(3, 4, 6, 5, &b);
    prw_btf_packed p;
    prw_btf_error r2 = run(&b, PRW_BTF_CODEC_FMF, 2, 0, &p);
    CHECK_MSG(r2.rms_pct < 0.1, "2 components: rms %.4f %%", r2.rms_pct); /* half precision: ~0.05 % */
    prw_btf_packed_free(&p);
    prw_btf_error r1 = run(&b, PRW_BTF_CODEC_FMF, 1, 0, &p);
    CHECK_MSG(r1.rms_pct > 1, "1 component: rms %.4f %% (the tensor is rank 2)", r1.rms_pct);
    prw_btf_packed_free(&p);
    prw_btf_free(&b);
}

/* 6 x 5 texels; texel t's ABRDF is pattern pat(t) (+ amp(t) x direction(pattern)) */
static void patterned(prw_btf *b, int npat, bool vary)
{
    prw_error e;
    prw_btf_create(6, 5, 3, 4, b, &e);
    double pat[8][36], dir[8][36];
    for (int i = 0; i < npat; i++)
        for (int d = 0; d < 36; d++) pat[i][d] = rnd(), dir[i][d] = rnd() - 0.5;
    for (uint32_t y = 0; y < 5; y++)
        for (uint32_t x = 0; x < 6; x++) {
            int i = (int)((x * 7 + y * 3) % (uint32_t)npat);
            double amp = vary ? rnd() - 0.5 : 0;
            for (uint32_t v = 0; v < 3; v++)
                for (uint32_t l = 0; l < 4; l++)
                    for (uint32_t c = 0; c < 3; c++) {
                        int d = (int)((v * 4 + l) * 3 + c);
                        b->rgb[prw_btf_at(b, v, l, x, y) + c] = (float)(pat[i][d] + amp * dir[i][d]);
                    }
        }
}

static void test_cluster(void)
{
    prw_btf b;
    prw_btf_packed p;
    patterned(&b, 6, false);
    prw_btf_error r = run(&b, PRW_BTF_CODEC_CLUSTER, 0, 6, &p);
    CHECK_MSG(r.rms_pct < 0.1, "6 patterns, 6 clusters: rms %.4f %%", r.rms_pct);
    prw_btf_packed_free(&p);
    r = run(&b, PRW_BTF_CODEC_CLUSTER, 0, 3, &p);
    CHECK_MSG(r.rms_pct > 1, "6 patterns, 3 clusters: rms %.4f %%", r.rms_pct);
    prw_btf_packed_free(&p);
    prw_btf_free(&b);
    patterned(&b, 3, true);
    r = run(&b, PRW_BTF_CODEC_CLUSTER, 1, 3, &p);
    CHECK_MSG(r.rms_pct < 0.1, "3 varying patterns, 3 clusters x 1 component: rms %.4f %%", r.rms_pct);
    prw_btf_packed_free(&p);
    r = run(&b, PRW_BTF_CODEC_CLUSTER, 0, 3, &p);
    CHECK_MSG(r.rms_pct > 1, "the same without components: rms %.4f %%", r.rms_pct);
    prw_btf_packed_free(&p);
    prw_btf_free(&b);
}

static void test_pvf(void)
{
    prw_btf b;
    prw_error e;
    prw_btf_create(6, 5, 3, 4, &b, &e);
    for (uint32_t v = 0; v < 3; v++) {
        double mean[12], dir[12], w[30];
        for (int i = 0; i < 12; i++) mean[i] = rnd(), dir[i] = rnd() - 0.5;
        for (int t = 0; t < 30; t++) w[t] = rnd() - 0.5;
        for (uint32_t l = 0; l < 4; l++)
            for (uint32_t t = 0; t < 30; t++)
                for (uint32_t c = 0; c < 3; c++)
                    b.rgb[prw_btf_at(&b, v, l, t % 6, t / 6) + c] = (float)(mean[l * 3 + c] + w[t] * dir[l * 3 + c]);
    }
    prw_btf_packed p;
    prw_btf_error r = run(&b, PRW_BTF_CODEC_PVF, 1, 0, &p);
    CHECK_MSG(r.rms_pct < 0.1, "pvf 1 component: rms %.4f %%", r.rms_pct);
    prw_btf_packed_free(&p);
    prw_btf_free(&b);
}

/* 6 x 5 texels, 3 views x 4 lights: one random ABRDF, texels 7 and 22 with a spike of 20 at two pairs each */
static const uint32_t spike_t[4] = {7, 7, 22, 22}, spike_q[4] = {1, 9, 4, 9};
static void spiky(prw_btf *b)
{
    prw_error e;
    prw_btf_create(6, 5, 3, 4, b, &e);
    double base[36];
    for (int d = 0; d < 36; d++) base[d] = 0.2 + 0.5 * rnd();
    for (uint32_t q = 0; q < 12; q++)
        for (uint32_t t = 0; t < 30; t++)
            for (uint32_t c = 0; c < 3; c++) b->rgb[(q * 30 + t) * 3 + c] = (float)base[q * 3 + c];
    for (int s = 0; s < 4; s++)
        for (uint32_t c = 0; c < 3; c++) b->rgb[(spike_q[s] * 30 + spike_t[s]) * 3 + c] += (float)(20.0 + c);
}

/* SPARSE as the first codec work of a process (its own ctest): its residuals are taken against the
 * decode before anything else has decoded (a half table filled only on first decode read zeros there) */
static void test_sparse_first(void)
{
    prw_btf b;
    spiky(&b);
    prw_btf_packed p;
    g_sparse = 4;
    prw_btf_error r = run(&b, PRW_BTF_CODEC_SPARSE, 0, 1, &p);
    CHECK_MSG(r.rms_pct < 0.1 && p.sparse_count == 120, "4 entries per texel, first in the process: rms %.4f %%, %u entries",
              r.rms_pct, p.sparse_count);
    prw_btf_packed_free(&p);
    g_sparse = 2;
    prw_btf_free(&b);
}

static void test_sparse(void)
{
    prw_btf b;
    spiky(&b);
    prw_btf_packed p;
    prw_btf_error r0 = run(&b, PRW_BTF_CODEC_CLUSTER, 0, 1, &p);
    prw_btf_packed_free(&p);
    g_sparse = 4;
    prw_btf_error r = run(&b, PRW_BTF_CODEC_SPARSE, 0, 1, &p);
    CHECK_MSG(r.rms_pct < 0.1 && p.sparse_count == 120, "4 entries per texel: rms %.4f %%, %u entries", r.rms_pct, p.sparse_count);
    prw_btf_packed_free(&p);
    g_sparse = 4.0 / 30;
    r = run(&b, PRW_BTF_CODEC_SPARSE, 0, 1, &p);
    bool spikes = p.sparse_count == 4;
    for (int s = 0; spikes && s < 4; s++) {
        uint32_t t = spike_t[s], j = p.sp_start[t] + (s & 1);
        spikes = p.sp_start[t + 1] - p.sp_start[t] == 2 && p.sp_pair[j] == spike_q[s];
    }
    CHECK_MSG(spikes, "4 entries in all: not the 4 spikes");
    /* the mean refitted without the spikes: exact to half precision */
    CHECK_MSG(r.rms_pct < 0.1 && r0.rms_pct > 50, "4 spikes kept: rms %.4f %% against %.4f %% without", r.rms_pct, r0.rms_pct);
    prw_btf_packed_free(&p);
    g_sparse = 3.0 / 30;
    prw_btf_error r3 = run(&b, PRW_BTF_CODEC_SPARSE, 0, 1, &p);
    CHECK_MSG(r3.rms_pct > 2 * r.rms_pct && r3.rms_pct > 1, "3 entries: rms %.4f %% (a spike is lost)", r3.rms_pct);
    prw_btf_packed_free(&p);
    g_sparse = 2;
    prw_btf_free(&b);
}

static void test_errors(void)
{
    /* 1 view, 1 light, 2 texels; A = (1, 3) in every channel, Ahat = FMF... take a 1-cluster VQ: the mean 2 */
    prw_btf b;
    prw_error e;
    prw_btf_create(2, 1, 1, 1, &b, &e);
    for (int c = 0; c < 3; c++) b.rgb[c] = 1, b.rgb[3 + c] = 3;
    prw_btf_packed p;
    prw_btf_error r = run(&b, PRW_BTF_CODEC_CLUSTER, 0, 1, &p);
    /* |A|^2 = 3 (1 + 9) = 30, |A - Abar|^2 = 3 (1 + 1) = 6, |A - Ahat| = |A - Abar| */
    CHECK_NEAR(r.rms_pct, 100 * sqrt(6.0 / 30.0), 1e-9);
    CHECK_NEAR(r.varying_pct, 100.0, 1e-9);
    CHECK_NEAR(r.mean_abs, 1.0, 1e-12);
    CHECK_NEAR(prw_btf_varying_fraction(&b), sqrt(6.0 / 30.0), 1e-12);
    prw_btf_packed_free(&p);
    prw_btf_free(&b);
}

static bool same_packed(const prw_btf_packed *a, const prw_btf_packed *b)
{
    if (a->codec != b->codec || a->width != b->width || a->height != b->height || a->views != b->views ||
        a->lights != b->lights || a->components != b->components || a->clusters != b->clusters)
        return false;
    for (uint32_t v = 0; v < a->views; v++)
        for (uint32_t l = 0; l < a->lights; l++)
            for (uint32_t y = 0; y < a->height; y++)
                for (uint32_t x = 0; x < a->width; x++)
                    for (uint32_t c = 0; c < 3; c++)
                        if (prw_btf_packed_value(a, v, l, x, y, c) != prw_btf_packed_value(b, v, l, x, y, c)) return false;
    return memcmp(a->view_dirs, b->view_dirs, 8 * a->views) == 0 && memcmp(a->light_dirs, b->light_dirs, 8 * a->lights) == 0;
}

static void test_file(void)
{
    prw_btf b;
    patterned(&b, 3, true);
    const prw_btf_codec codecs[4] = {PRW_BTF_CODEC_FMF, PRW_BTF_CODEC_CLUSTER, PRW_BTF_CODEC_PVF, PRW_BTF_CODEC_SPARSE};
    prw_error e;
    for (int i = 0; i < 4; i++) {
        prw_btf_packed p, q;
        run(&b, codecs[i], 2, 3, &p);
        char name[32];
        snprintf(name, sizeof name, "c%d.btfc", i);
        char *path = prw_test_path(name);
        CHECK_OK(prw_btf_packed_write(path, &p, &e), &e);
        CHECK_OK(prw_btf_packed_read(path, &q, &e), &e);
        CHECK_MSG(same_packed(&p, &q), "codec %d: the file does not round-trip", (int)codecs[i]);
        prw_btf_packed_free(&q);
        char *data;
        size_t n;
        CHECK_OK(prw_read_file(path, &data, &n, &e), &e);
        CHECK(n == prw_btf_packed_bytes(&p));
        int accepted = 0;
        for (size_t len = 0; len < n; len++) {
            if (prw_btf_packed_read_memory(data, len, "cut.btfc", &q, &e)) {
                accepted++;
                prw_btf_packed_free(&q);
            } else if (strncmp(e.msg, "cut.btfc: ", 10) != 0) {
                accepted += 1000;
            }
        }
        CHECK_MSG(accepted == 0, "codec %d: %d truncations accepted or misnamed", (int)codecs[i], accepted);
        if (codecs[i] == PRW_BTF_CODEC_CLUSTER) {
            size_t idx = 8 + 36 + 8 * (3 + 4); /* the first cluster index */
            data[idx] = 9;
            CHECK(!prw_btf_packed_read_memory(data, n, "bad.btfc", &q, &e) && strstr(e.msg, "cluster 9 of 3"));
            printf("refused: %s\n", e.msg);
        }
        if (codecs[i] == PRW_BTF_CODEC_SPARSE) {
            /* the last entry's pair: beyond the 12 pairs, then equal to its predecessor (out of order) */
            size_t pair = n - (p.has_average ? 28 : 0) - 6 * (size_t)p.sparse_count - 2; /* before the average */
            uint16_t prev = p.sp_pair[p.sparse_count - 2];
            CHECK(p.sp_start[29] <= p.sparse_count - 2); /* the last two entries are the last texel's */
            data[pair] = 12, data[pair + 1] = 0;
            CHECK(!prw_btf_packed_read_memory(data, n, "bad.btfc", &q, &e) && strstr(e.msg, "pair 12 out of range"));
            printf("refused: %s\n", e.msg);
            data[pair] = (char)(prev & 0xff), data[pair + 1] = (char)(prev >> 8);
            CHECK(!prw_btf_packed_read_memory(data, n, "bad.btfc", &q, &e) && strstr(e.msg, "out of range or order"));
            printf("refused: %s\n", e.msg);
        }
        free(data);
        prw_btf_packed_free(&p);
    }
    prw_btf_free(&b);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"svd", test_svd}, {"fmf", test_fmf},       {"cluster", test_cluster},
        {"pvf", test_pvf}, {"sparse", test_sparse}, {"errors", test_errors}, {"file", test_file},
        {"sparse_first", test_sparse_first},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
