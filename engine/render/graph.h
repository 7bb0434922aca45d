/* graph — the render graph of DESIGN.md §4: a table of passes (prw_pass.h) turned into allocated
 * resources, an order, derived barriers and per-frame culling.
 *
 * Promises:
 *  - Build (prw_graph_create): every pass's setup runs in table order; passes that skip themselves are
 *    listed with their reason; a use of a resource that no pass in the graph creates (or imports), two
 *    creators of one name, or a view index beyond max_views fails the build with a message naming the
 *    pass and the resource.  Optional images nobody else reads are dropped.  Images are allocated with
 *    the union of every declared usage; then the passes' create run in table order.
 *  - Frame (prw_graph_execute): needed() is asked per pass (per view for VIEW passes); a needed pass
 *    is live when it is flagged KEEP, writes an exported resource, or writes a resource a later live
 *    pass reads; the rest is culled.  Before each live pass, ONE barrier command holds every layout
 *    transition and memory dependency its declared uses need (from the resources' tracked state,
 *    which persists across frames); exported buffers get one barrier to the host at the end.  A
 *    skipped or culled pass records nothing.
 *  - Timing: with a timer, every live graphics pass is bracketed by GPU timestamps; with a split
 *    callback and time_compute, every live compute pass is recorded into a command buffer of its own,
 *    submitted and timed by the host clock; host stages are always host-timed.
 *  - Host stages (PRW_QUEUE_HOST) run only with a split callback: what was recorded before them is
 *    submitted and waited for first.
 *  - The counts of barrier commands and render-pass begins it and the passes recorded are in the
 *    frame stats.
 */
#ifndef PRW_GRAPH_H
#define PRW_GRAPH_H

#include "prw_pass.h"

typedef struct prw_graph_exec {
    VkCommandBuffer cmd;
    prw_timer *timer; /* NULL: no GPU timestamps */
    /* Submits what was recorded into *cmd and begins a new buffer; *ms: the submit's wall time.  NULL:
     * host stages are skipped and compute passes are not timed separately. */
    bool (*split)(void *user, VkCommandBuffer *cmd, double *ms, prw_error *e);
    void *user;
    bool time_compute; /* with split: every compute pass in a submission of its own, host-timed */
} prw_graph_exec;

/* exports: NULL-terminated names the caller reads back after frames (kept, their producers live); may be NULL. */
bool prw_graph_create(const prw_render_env *env, const prw_pass *const *table, const char *const *exports,
                      prw_graph **out, prw_error *e);
void prw_graph_destroy(prw_graph *g);
/* Records the frame; fills stats (passes, skipped with reasons, times filled in later by the caller for
 * timestamps: stats->passes[i].timer_scope). */
bool prw_graph_execute(prw_graph *g, prw_frame *f, prw_graph_exec *x, prw_frame_stats *stats, prw_error *e);

/* Description for `prw info`: one line per pass (in the graph or skipped, with reasons and the
 * resources it uses) and one per resource (format, size, views, usage).  Appends to buf. */
void prw_graph_describe(const prw_graph *g, char *buf, size_t cap);
/* Introspection (tests): passes in the graph, resources allocated. */
uint32_t prw_graph_pass_count(const prw_graph *g);
const char *prw_graph_pass_name(const prw_graph *g, uint32_t i);
bool prw_graph_pass_in_graph(const prw_graph *g, uint32_t i, const char **why_not);
uint32_t prw_graph_resource_count(const prw_graph *g);
/* Resource i: name, whether it is allocated (images) or imported (buffers), shared, its usage flags. */
const char *prw_graph_resource(const prw_graph *g, uint32_t i, bool *allocated, bool *shared,
                               VkImageUsageFlags *usage);
/* The state a pass created (NULL when none or not in the graph). */
void *prw_graph_pass_state(const prw_graph *g, const char *pass);

#endif
