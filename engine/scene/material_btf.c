/* material_btf.c — the scene's check of a BTF material's file (manifest and glTF extras): the file is
 * read once, validated by the compressed-BTF reader and the direction tables (what the renderers will
 * need), and hashed; the scene keeps only the path and the hash. */
#include <stdlib.h>
#include <sys/stat.h>

#include "prw_btf_eval.h"
#include "prw_scene.h"

bool prw_scene_btf_check(const char *path, uint64_t *hash, prw_error *e)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot open: not a regular file", path);
    char *bytes = NULL;
    size_t size = 0;
    if (!prw_read_file_bounded(path, 0, 1, "a compressed BTF", &bytes, &size, e)) return false;
    prw_btf_packed p;
    bool ok = prw_btf_packed_read_memory(bytes, size, path, &p, e);
    if (ok) {
        *hash = prw_hash64(bytes, size, 0x6274662d66696c65ull);
        prw_btf_material m;
        ok = prw_btf_material_from_packed(&p, path, &m, e);
        if (ok) prw_btf_material_free(&m);
    }
    free(bytes);
    return ok;
}
