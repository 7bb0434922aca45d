#include "pass_graph.h"

#include <string.h>

void prw_pass_graph_init(prw_pass_graph *g, uint32_t external_resources)
{
    memset(g, 0, sizeof *g);
    g->external = external_resources;
}

bool prw_pass_graph_add(prw_pass_graph *g, const prw_pass *p, prw_error *e)
{
    if (g->count >= PRW_MAX_PASSES) return prw_fail(e, "pass graph: more than %d passes", PRW_MAX_PASSES);
    uint32_t available = g->external;
    for (uint32_t i = 0; i < g->count; i++) available |= g->passes[i].writes;
    uint32_t missing = p->reads & ~available;
    if (missing)
        return prw_fail(e, "pass graph: pass '%s' reads resources 0x%x that no earlier pass writes", p->name, missing);
    g->passes[g->count++] = *p;
    return true;
}

bool prw_pass_graph_execute(const prw_pass_graph *g, prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_timer *timer,
                            uint32_t *timer_scopes, prw_pass_stat *stats, prw_error *e)
{
    for (uint32_t i = 0; i < g->count; i++) {
        const prw_pass *p = &g->passes[i];
        stats[i].name = p->name;
        stats[i].gpu_ms = -1.0;
        stats[i].skipped = !p->needed(ctx);
        if (timer_scopes) timer_scopes[i] = UINT32_MAX;
        if (stats[i].skipped) continue;
        uint32_t scope = timer ? prw_timer_begin(cmd, timer, p->name) : 0;
        if (!p->record(ctx, cmd, e)) return prw_fail_wrap(e, "pass '%s'", p->name);
        if (timer) {
            prw_timer_end(cmd, timer, scope);
            if (timer_scopes) timer_scopes[i] = scope;
        }
    }
    return true;
}
