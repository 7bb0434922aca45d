/* gpu_timer.c — named GPU time scopes from timestamp queries (two queries per scope). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

#define NAME_LEN 48

struct prw_timer {
    VkQueryPool pool;
    uint32_t max_scopes, count;
    char (*names)[NAME_LEN];
    const char **name_ptrs; /* what prw_timer_read hands out */
    double *ms;
    double period_ns;
    uint64_t mask; /* timestampValidBits: higher bits are garbage */
};

bool prw_timer_create(prw_gpu *gpu, uint32_t max_scopes, prw_timer **out, prw_error *e)
{
    *out = NULL;
    if (gpu->timestamp_valid_bits == 0)
        return prw_fail(e, "gpu: timer: the queue family does not support timestamps (timestampValidBits = 0)");
    if (max_scopes == 0) return prw_fail(e, "gpu: timer with 0 scopes");
    prw_timer *t = prw_calloc(1, sizeof *t);
    VkQueryPoolCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
        .queryType = VK_QUERY_TYPE_TIMESTAMP,
        .queryCount = 2 * max_scopes,
    };
    if (!prw_vk_check(vkCreateQueryPool(gpu->device, &ci, NULL, &t->pool), "gpu: vkCreateQueryPool", e)) {
        free(t);
        return false;
    }
    t->max_scopes = max_scopes;
    t->names = prw_calloc(max_scopes, sizeof *t->names);
    t->name_ptrs = prw_calloc(max_scopes, sizeof *t->name_ptrs);
    t->ms = prw_calloc(max_scopes, sizeof *t->ms);
    t->period_ns = gpu->props.limits.timestampPeriod;
    t->mask = gpu->timestamp_valid_bits >= 64 ? UINT64_MAX : (((uint64_t)1 << gpu->timestamp_valid_bits) - 1);
    for (uint32_t i = 0; i < max_scopes; i++) t->name_ptrs[i] = t->names[i];
    *out = t;
    return true;
}

void prw_timer_destroy(prw_gpu *gpu, prw_timer *t)
{
    if (!t) return;
    vkDestroyQueryPool(gpu->device, t->pool, NULL);
    free(t->names);
    free(t->name_ptrs);
    free(t->ms);
    free(t);
}

void prw_timer_reset(VkCommandBuffer cmd, prw_timer *t)
{
    vkCmdResetQueryPool(cmd, t->pool, 0, 2 * t->max_scopes);
    t->count = 0;
}

uint32_t prw_timer_begin(VkCommandBuffer cmd, prw_timer *t, const char *name)
{
    if (t->count >= t->max_scopes) return UINT32_MAX; /* full: prw_timer_end ignores it */
    uint32_t s = t->count++;
    snprintf(t->names[s], NAME_LEN, "%s", name ? name : "");
    /* ALL_COMMANDS: the stamp is written once everything before it is done, so a scope measures
     * exactly the work recorded between begin and end. */
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, t->pool, 2 * s);
    return s;
}

void prw_timer_end(VkCommandBuffer cmd, prw_timer *t, uint32_t scope)
{
    if (scope >= t->count) return;
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, t->pool, 2 * scope + 1);
}

bool prw_timer_read(prw_gpu *gpu, prw_timer *t, uint32_t *count, const char *const **names, const double **ms,
                    prw_error *e)
{
    *count = 0;
    if (t->count) {
        /* Value + availability per query; no WAIT flag, so a missing result is an error, not a hang. */
        uint64_t *q = prw_calloc(4 * (size_t)t->count, sizeof *q);
        VkResult r = vkGetQueryPoolResults(gpu->device, t->pool, 0, 2 * t->count, 4 * t->count * sizeof *q, q,
                                           2 * sizeof *q,
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
        if (r != VK_SUCCESS && r != VK_NOT_READY) {
            free(q);
            return prw_vk_check(r, "gpu: vkGetQueryPoolResults", e);
        }
        for (uint32_t s = 0; s < t->count; s++) {
            uint64_t b = q[4 * s], b_ok = q[4 * s + 1], en = q[4 * s + 2], en_ok = q[4 * s + 3];
            if (!b_ok || !en_ok) {
                free(q);
                return prw_fail(e, "gpu: timer scope '%s' has no result (not ended, or its submit has not completed)",
                                t->names[s]);
            }
            /* Masked difference survives a wrap of the valid bits. */
            t->ms[s] = (double)((en - b) & t->mask) * t->period_ns * 1e-6;
        }
        free(q);
    }
    *count = t->count;
    *names = t->name_ptrs;
    *ms = t->ms;
    return true;
}
