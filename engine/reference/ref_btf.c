/* ref_btf.c — the BTF materials of the scene, loaded for the path tracer (the BTF kind's evaluation is
 * in ref_trace.c through prw_btf_eval.h). */
#include <stdlib.h>
#include <string.h>

#include "ref_internal.h"

bool ref_btf_load(prw_ref_renderer *r, prw_error *e)
{
    const prw_scene *s = r->scene;
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->material_count; i++) n += s->materials[i].kind == PRW_MATERIAL_BTF;
    if (!n) return true;
    r->btf_of = prw_calloc(s->material_count, sizeof *r->btf_of);
    r->btf_owned = prw_calloc(n, sizeof *r->btf_owned);
    uint32_t *owner = prw_calloc(s->material_count, sizeof *owner); /* material -> index in btf_owned */
    bool ok = true;
    for (uint32_t i = 0; i < s->material_count && ok; i++) {
        const prw_material *m = &s->materials[i];
        if (m->kind != PRW_MATERIAL_BTF) continue;
        uint32_t j = 0;
        for (; j < i; j++)
            if (s->materials[j].kind == PRW_MATERIAL_BTF && strcmp(s->materials[j].btf_file, m->btf_file) == 0) break;
        if (j < i) {
            r->btf_of[i] = &r->btf_owned[owner[j]];
            owner[i] = owner[j];
            continue;
        }
        char *bytes = NULL;
        size_t size = 0;
        prw_btf_packed p;
        prw_error fe;
        ok = prw_read_file_bounded(m->btf_file, 0, 1, "a compressed BTF", &bytes, &size, &fe);
        if (ok && prw_hash64(bytes, size, 0x6274662d66696c65ull) != m->btf_hash)
            ok = prw_fail(&fe, "%s: changed since the scene was loaded", m->btf_file);
        ok = ok && prw_btf_packed_read_memory(bytes, size, m->btf_file, &p, &fe);
        free(bytes);
        ok = ok && prw_btf_material_from_packed(&p, m->btf_file, &r->btf_owned[r->btf_count], &fe);
        if (!ok) {
            prw_fail(e, "reference: material '%s': %s", m->name, fe.msg);
            break;
        }
        owner[i] = r->btf_count;
        r->btf_of[i] = &r->btf_owned[r->btf_count++];
    }
    free(owner);
    return ok;
}

void ref_btf_free(prw_ref_renderer *r)
{
    for (uint32_t i = 0; i < r->btf_count; i++) prw_btf_material_free(&r->btf_owned[i]);
    free(r->btf_owned);
    free(r->btf_of);
    r->btf_owned = NULL, r->btf_of = NULL, r->btf_count = 0;
}

const prw_btf_material *ref_btf_of(const prw_ref_renderer *r, const ref_inst *in)
{
    if (!r->btf_of || in->mat->kind != PRW_MATERIAL_BTF) return NULL;
    ptrdiff_t i = in->mat - r->scene->materials;
    return i >= 0 && (uint32_t)i < r->scene->material_count ? r->btf_of[i] : NULL;
}
