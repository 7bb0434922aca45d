/* gpu_pipeline_memo.c — pipelines shared within a process (prw_gpu.h, "pipelines are shared").
 *
 * lavapipe's VkPipelineCache stores nothing, so every renderer compiled every pipeline again (NIR
 * passes in the driver: ~0.15-0.3 s each; a test making 8 renderers spent half its time there).
 * The memo keys a pipeline by a 128-bit hash of everything that defines it: SPIR-V bytes,
 * specialisation constants, fixed-function state and the *content* of its pipeline layout (the
 * bindings of each set layout made by prw_desc_layout_create and the push range), never a handle a
 * renderer owns.  Vulkan allows a pipeline to be bound with any compatible layout and its layout to
 * be destroyed once it is created, so a pipeline made for one renderer serves the next.
 * PRW_PIPELINE_MEMO=0 turns it off (every call compiles; release destroys), for A/B figures. */
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

void prw_hash128_init(prw_hash128 *h)
{
    h->a = 0xcbf29ce484222325ull; /* FNV-1a 64 offset basis */
    h->b = 0x9e3779b97f4a7c15ull;
}

void prw_hash128_add(prw_hash128 *h, const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t a = h->a, b = h->b;
    for (size_t i = 0; i < n; i++) {
        a = (a ^ p[i]) * 0x100000001b3ull; /* FNV-1a */
        b = (b + p[i] + 1) * 0xff51afd7ed558ccdull;
        b ^= b >> 29;
    }
    /* the length too, so that concatenations of different splits differ */
    uint64_t len = n;
    for (int i = 0; i < 8; i++, len >>= 8) a = (a ^ (len & 0xff)) * 0x100000001b3ull;
    h->a = a, h->b = b;
}

bool prw_pipe_memo_enabled(prw_gpu *gpu)
{
    if (gpu->memo_state == 0) {
        const char *v = getenv("PRW_PIPELINE_MEMO");
        gpu->memo_state = (v && strcmp(v, "0") == 0) ? 2 : 1;
    }
    return gpu->memo_state == 1;
}

/* ---- pipeline layouts by content ---- */

void prw_playout_note(prw_gpu *gpu, VkPipelineLayout layout, const prw_hash128 *sig)
{
    for (uint32_t i = 0; i < gpu->playout_count; i++)
        if (gpu->playouts[i].layout == layout) { /* a handle value reused after a destroy */
            gpu->playouts[i].sig = *sig;
            return;
        }
    if (gpu->playout_count == gpu->playout_cap) {
        gpu->playout_cap = gpu->playout_cap ? 2 * gpu->playout_cap : 32;
        gpu->playouts = prw_realloc(gpu->playouts, gpu->playout_cap * sizeof *gpu->playouts);
    }
    gpu->playouts[gpu->playout_count++] = (prw_playout_sig){.layout = layout, .sig = *sig};
}

void prw_playout_hash(prw_gpu *gpu, VkPipelineLayout layout, prw_hash128 *h)
{
    for (uint32_t i = 0; i < gpu->playout_count; i++)
        if (gpu->playouts[i].layout == layout) {
            prw_hash128_add(h, &gpu->playouts[i].sig, sizeof gpu->playouts[i].sig);
            return;
        }
    /* not made by prw_pipeline_layout_create*: its handle is its identity (no sharing, still right) */
    prw_hash128_add(h, &layout, sizeof layout);
}

/* ---- the memo ---- */

bool prw_pipe_memo_find(prw_gpu *gpu, const prw_hash128 *key, VkPipeline *out)
{
    for (uint32_t i = 0; i < gpu->memo_count; i++)
        if (gpu->memo[i].key.a == key->a && gpu->memo[i].key.b == key->b) {
            gpu->memo[i].refs++;
            gpu->memo_hits++;
            *out = gpu->memo[i].pipe;
            return true;
        }
    return false;
}

void prw_pipe_memo_add(prw_gpu *gpu, const prw_hash128 *key, VkPipeline pipe)
{
    if (gpu->memo_count == gpu->memo_cap) {
        gpu->memo_cap = gpu->memo_cap ? 2 * gpu->memo_cap : 64;
        gpu->memo = prw_realloc(gpu->memo, gpu->memo_cap * sizeof *gpu->memo);
    }
    gpu->memo[gpu->memo_count++] = (prw_pipe_memo_entry){.key = *key, .pipe = pipe, .refs = 1};
}

void prw_pipeline_release(prw_gpu *gpu, VkPipeline pipe)
{
    if (!pipe) return;
    for (uint32_t i = 0; i < gpu->memo_count; i++)
        if (gpu->memo[i].pipe == pipe) {
            if (gpu->memo[i].refs) gpu->memo[i].refs--;
            return; /* kept for the next renderer; destroyed with the gpu */
        }
    vkDestroyPipeline(gpu->device, pipe, NULL);
}

void prw_pipeline_memo_stats(const prw_gpu *gpu, uint32_t *pipelines, uint64_t *hits)
{
    if (pipelines) *pipelines = gpu->memo_count;
    if (hits) *hits = gpu->memo_hits;
}

void prw_pipe_memo_shutdown(prw_gpu *gpu)
{
    for (uint32_t i = 0; i < gpu->memo_count; i++) vkDestroyPipeline(gpu->device, gpu->memo[i].pipe, NULL);
    free(gpu->memo);
    free(gpu->playouts);
    gpu->memo = NULL, gpu->playouts = NULL;
    gpu->memo_count = gpu->memo_cap = gpu->playout_count = gpu->playout_cap = 0;
}
