/* gpu_pipeline_table.c — pipelines by key (prw_gpu.h): a small table searched linearly; a renderer
 * holds a few dozen pipelines, created on first use. */
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

typedef struct entry {
    unsigned char key[PRW_PIPELINE_KEY_MAX];
    size_t size;
    VkPipeline pipe;
} entry;

struct prw_pipeline_table {
    prw_gpu *gpu;
    entry *e;
    uint32_t count, cap;
};

bool prw_pipeline_table_create(prw_gpu *gpu, prw_pipeline_table **out, prw_error *e)
{
    (void)e;
    prw_pipeline_table *t = prw_calloc(1, sizeof *t);
    t->gpu = gpu;
    *out = t;
    return true;
}

void prw_pipeline_table_destroy(prw_pipeline_table *t)
{
    if (!t) return;
    for (uint32_t i = 0; i < t->count; i++) prw_pipeline_release(t->gpu, t->e[i].pipe);
    free(t->e);
    free(t);
}

VkPipeline prw_pipeline_table_find(const prw_pipeline_table *t, const void *key, size_t size)
{
    for (uint32_t i = 0; i < t->count; i++)
        if (t->e[i].size == size && memcmp(t->e[i].key, key, size) == 0) return t->e[i].pipe;
    return VK_NULL_HANDLE;
}

bool prw_pipeline_table_add(prw_pipeline_table *t, const void *key, size_t size, VkPipeline pipe, prw_error *e)
{
    if (size > PRW_PIPELINE_KEY_MAX) {
        prw_pipeline_release(t->gpu, pipe);
        return prw_fail(e, "gpu: pipeline key of %zu bytes (at most %d)", size, PRW_PIPELINE_KEY_MAX);
    }
    if (t->count == t->cap) {
        t->cap = t->cap ? 2 * t->cap : 16;
        t->e = prw_realloc(t->e, t->cap * sizeof *t->e);
    }
    entry *x = &t->e[t->count++];
    memset(x->key, 0, sizeof x->key);
    memcpy(x->key, key, size);
    x->size = size;
    x->pipe = pipe;
    return true;
}

void prw_pipeline_table_remove(prw_pipeline_table *t, bool (*match)(const void *key, size_t size, void *user),
                               void *user)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < t->count; i++) {
        if (match(t->e[i].key, t->e[i].size, user)) prw_pipeline_release(t->gpu, t->e[i].pipe);
        else t->e[k++] = t->e[i];
    }
    t->count = k;
}

uint32_t prw_pipeline_table_count(const prw_pipeline_table *t) { return t->count; }
