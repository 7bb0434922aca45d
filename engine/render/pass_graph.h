/* pass_graph — the frame's passes, in order, each declaring what it reads and writes and when it is
 * needed (DESIGN.md §4).
 *
 * Promises:
 *  - prw_pass_graph_add() rejects a pass that reads a resource no earlier pass writes (unless the
 *    resource is marked external), so the order is checked once when the graph is built.
 *  - prw_pass_graph_execute() asks each pass needed(ctx); a skipped pass records nothing at all — no
 *    begin/end, barrier or timestamp.  Stats list every pass, skipped ones included.
 */
#ifndef PRW_PASS_GRAPH_H
#define PRW_PASS_GRAPH_H

#include "prw_gpu.h"

#define PRW_MAX_PASSES 16

typedef struct prw_frame_ctx prw_frame_ctx; /* owned by the renderer */

typedef struct prw_pass {
    const char *name;
    uint32_t reads, writes; /* resource bit masks (renderer-defined) */
    bool (*needed)(const prw_frame_ctx *ctx);
    bool (*record)(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e);
} prw_pass;

typedef struct prw_pass_stat {
    const char *name;
    bool skipped;
    double gpu_ms; /* < 0 when not timed */
} prw_pass_stat;

typedef struct prw_pass_graph {
    prw_pass passes[PRW_MAX_PASSES];
    uint32_t count;
    uint32_t external; /* resources valid before the first pass */
} prw_pass_graph;

void prw_pass_graph_init(prw_pass_graph *g, uint32_t external_resources);
bool prw_pass_graph_add(prw_pass_graph *g, const prw_pass *p, prw_error *e);
/* Records the needed passes into cmd; timer may be NULL.  stats has room for g->count entries. */
bool prw_pass_graph_execute(const prw_pass_graph *g, prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_timer *timer,
                            uint32_t *timer_scopes, prw_pass_stat *stats, prw_error *e);

#endif
