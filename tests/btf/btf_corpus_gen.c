/* btf_corpus_gen UBO_DIR PACKED_DIR RAW_DIR — writes the seed corpora of fuzz_btf_ubo
 * (tests/fuzz_readers/corpus_btf_ubo: every sample kind of btf_samples.h and the closed-form tensor in
 * each format, at small sizes) and of fuzz_btf_packed (tests/fuzz_readers/corpus_btf_packed: the
 * tensor compressed by each codec, and the FMF one with an average: version 2) and of fuzz_btf_raw (tests/fuzz_readers/corpus_btf_raw: the tensor's
 * raw dump).  regress_* files in the corpora are fuzzer finds, kept by hand.
 * Regenerate: build/tests/btf/btf_corpus_gen tests/fuzz_readers/corpus_btf_ubo tests/fuzz_readers/corpus_btf_packed \
 *             tests/fuzz_readers/corpus_btf_raw */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#include "btf_samples.h"
#include "prw_btf_codec.h"

static int put(const char *dir, const char *name, prw_btf_ubo *b)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    prw_error e;
    int rc = prw_btf_ubo_write(path, b, &e) ? 0 : (fprintf(stderr, "%s\n", e.msg), 1);
    prw_btf_ubo_free(b);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: btf_corpus_gen UBO_DIR PACKED_DIR RAW_DIR\n");
        return 2;
    }
    static const char *names[BTF_SAMPLE_KIND_COUNT] = {"dfmf_r_v4.btf", "dfmf_v1.btf", "fmf_ext.btf", "fmf_plain.btf",
                                                       "bdi_sparse.bdi"};
    int rc = 0;
    prw_btf_ubo b;
    for (int k = 0; k < BTF_SAMPLE_KIND_COUNT; k++) {
        btf_sample((btf_sample_kind)k, 2, 3, 3, 2, 5, &b);
        rc |= put(argv[1], names[k], &b);
    }
    btf_sample_tensor_file(PRW_BTF_UBO_DFMF, 2, 2, 2, 2, &b);
    rc |= put(argv[1], "tensor_dfmf.btf", &b);
    btf_sample_tensor_file(PRW_BTF_UBO_FMF, 2, 2, 2, 2, &b);
    rc |= put(argv[1], "tensor_fmf.btf", &b);
    btf_sample_tensor_file(PRW_BTF_UBO_BDI, 2, 2, 2, 2, &b);
    rc |= put(argv[1], "tensor_bdi.bdi", &b);
    prw_btf t;
    prw_error e;
    btf_sample_tensor_file(PRW_BTF_UBO_DFMF, 2, 3, 3, 2, &b);
    if (!prw_btf_from_ubo(&b, &t, &e)) return fprintf(stderr, "%s\n", e.msg), 1;
    prw_btf_ubo_free(&b);
    const prw_btf_codec codecs[4] = {PRW_BTF_CODEC_FMF, PRW_BTF_CODEC_CLUSTER, PRW_BTF_CODEC_PVF, PRW_BTF_CODEC_SPARSE};
    const char *pn[4] = {"fmf.btfc", "cluster.btfc", "pvf.btfc", "sparse.btfc"};
    for (int i = 0; i < 4; i++) {
        prw_btf_codec_params p = {.codec = codecs[i], .components = i == 3 ? 1 : 2, .clusters = 2, .sparse_per_texel = 2,
                                  .seed = 1, .threads = 1};
        prw_btf_packed pk;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", argv[2], pn[i]);
        bool ok = prw_btf_compress(&t, &p, &pk, &e);
        pk.has_average = false; /* these four: version 1 */
        if (!ok || !prw_btf_packed_write(path, &pk, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            rc = 1;
        }
        if (ok && i == 0) { /* version 2: the FMF file with the scale rule's average */
            pk.has_average = true;
            pk.average = (prw_btf_average){{0.5f, 0.25f, 0.125f}, 0.0f, 0.5f, 1.0f, 2.5f};
            snprintf(path, sizeof path, "%s/fmf_average.btfc", argv[2]);
            if (!prw_btf_packed_write(path, &pk, &e)) {
                fprintf(stderr, "%s\n", e.msg);
                rc = 1;
            }
        }
        prw_btf_packed_free(&pk);
    }
    char raw[1024];
    snprintf(raw, sizeof raw, "%s/tensor.raw", argv[3]);
    if (!prw_btf_write_raw(raw, &t, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        rc = 1;
    }
    prw_btf_free(&t);
    return rc;
}
