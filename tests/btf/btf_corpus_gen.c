/* btf_corpus_gen DIR — writes the seed corpus of fuzz_btf_ubo (tests/fuzz_readers/corpus_btf_ubo):
 * every sample kind of btf_samples.h and the closed-form tensor in each format, at small sizes.
 * Regenerate: build/tests/btf/btf_corpus_gen tests/fuzz_readers/corpus_btf_ubo */
#include <stdio.h>
#include <stdlib.h>

#include "btf_samples.h"

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
    if (argc != 2) {
        fprintf(stderr, "usage: btf_corpus_gen DIR\n");
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
    return rc;
}
