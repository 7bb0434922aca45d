/* graph — passes -> resources, order, barriers, culling (graph.h, prw_pass.h). */
#include "graph.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shadow_plan.h"

#define MAX_RES 64
#define MAX_USES 24
#define NAME_MAX_LEN 32

typedef struct graph_use {
    int res;
    int view; /* -1: the pass's view (VIEW scope) or every view of the frame (FRAME scope) */
    prw_use use;
} graph_use;

typedef struct graph_pass {
    const prw_pass *p;
    bool in_graph;
    char why_not[128]; /* not in the graph: the setup's reason */
    graph_use uses[MAX_USES];
    uint32_t nuses;
    void *state;
    bool created;
    /* per frame */
    bool needed_view[PRW_MAX_VIEWS];
    bool needed, live;
    char frame_reason[96];
} graph_pass;

/* Tracked access state of one image / buffer instance. */
typedef struct inst_state {
    VkImageLayout layout;          /* layout the graph last left it in */
    VkPipelineStageFlags2 w_stage; /* last writer */
    VkAccessFlags2 w_access;
    VkPipelineStageFlags2 r_stage; /* readers since the last write */
    VkPipelineStageFlags2 visible; /* stages the last write is visible to */
    VkAccessFlags2 visible_access;
} inst_state;

typedef struct graph_res {
    char name[NAME_MAX_LEN];
    bool is_buffer;
    VkBuffer buffer; /* imported */
    bool declared;   /* an image declared by a creator */
    prw_image_decl decl;
    int creator;
    bool optional, exported, dropped;
    int leader; /* optional_with: dropped with this resource (-1: none) */
    bool read_somewhere;
    VkImageUsageFlags usage;
    prw_gpu_image img[PRW_MAX_VIEWS]; /* shared: [0] */
    inst_state st[PRW_MAX_VIEWS];
    bool written; /* by a pass that ran in the current frame */
} graph_res;

struct prw_graph {
    const prw_render_env *env;
    graph_pass passes[PRW_MAX_PASSES];
    uint32_t npasses;
    graph_res res[MAX_RES];
    uint32_t nres;
    char error[PRW_ERROR_MAX];
    /* counters of the frame being recorded */
    uint32_t barriers, begins;
};

struct prw_setup {
    prw_graph *g;
    uint32_t pass;
};

/* ---- uses ---- */

typedef struct use_info {
    VkImageLayout layout; /* images; depth formats choose the depth layout below */
    VkPipelineStageFlags2 stage;
    VkAccessFlags2 access;
    bool write;
    VkImageUsageFlags usage;
} use_info;

#define FRAG_COMPUTE (VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)
#define DEPTH_TESTS (VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT)

static use_info info_of(prw_use u)
{
    switch (u) {
    case PRW_USE_COLOR:
        return (use_info){VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, true,
                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    case PRW_USE_COLOR_ADD:
        return (use_info){VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, true,
                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    case PRW_USE_RESOLVE:
        return (use_info){VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, true, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT};
    case PRW_USE_DEPTH:
        return (use_info){VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, DEPTH_TESTS,
                          VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                          true, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT};
    case PRW_USE_DEPTH_TEST:
        return (use_info){VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, DEPTH_TESTS,
                          VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, false,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT};
    case PRW_USE_SAMPLED:
        return (use_info){VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, FRAG_COMPUTE, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                          false, VK_IMAGE_USAGE_SAMPLED_BIT};
    case PRW_USE_STORAGE_READ:
        return (use_info){VK_IMAGE_LAYOUT_GENERAL, FRAG_COMPUTE, VK_ACCESS_2_SHADER_STORAGE_READ_BIT, false,
                          VK_IMAGE_USAGE_STORAGE_BIT};
    case PRW_USE_STORAGE_WRITE:
        return (use_info){VK_IMAGE_LAYOUT_GENERAL, FRAG_COMPUTE,
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, true,
                          VK_IMAGE_USAGE_STORAGE_BIT};
    case PRW_USE_TRANSFER_SRC:
        return (use_info){VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                          VK_ACCESS_2_TRANSFER_READ_BIT, false, VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    case PRW_USE_TRANSFER_DST:
        return (use_info){VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                          VK_ACCESS_2_TRANSFER_WRITE_BIT, true, VK_IMAGE_USAGE_TRANSFER_DST_BIT};
    case PRW_USE_INDIRECT:
        return (use_info){VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                          VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, false, 0};
    case PRW_USE_HOST_READ:
        return (use_info){VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT, false,
                          0};
    default: break;
    }
    return (use_info){0};
}

const char *prw_use_name(prw_use u)
{
    static const char *const names[PRW_USE_COUNT] = {
        "colour", "colour+=", "resolve", "depth", "depth-test", "sampled", "storage-read", "storage-write",
        "transfer-src", "transfer-dst", "indirect", "host-read"};
    return (unsigned)u < PRW_USE_COUNT ? names[u] : "?";
}

bool prw_use_writes(prw_use u) { return info_of(u).write; }

static VkImageLayout layout_for(const graph_res *r, prw_use u)
{
    VkImageLayout l = info_of(u).layout;
    bool stencil = r->decl.format == VK_FORMAT_D32_SFLOAT_S8_UINT || r->decl.format == VK_FORMAT_D24_UNORM_S8_UINT ||
                   r->decl.format == VK_FORMAT_D16_UNORM_S8_UINT;
    if (stencil && l == VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL) return VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    return l;
}

/* ---- setup ---- */

static void setup_error(prw_setup *s, const char *fmt, const char *a, const char *b)
{
    if (s->g->error[0]) return;
    char msg[256];
    snprintf(msg, sizeof msg, fmt, a, b);
    snprintf(s->g->error, sizeof s->g->error, "render graph: pass '%s': %s", s->g->passes[s->pass].p->name, msg);
}

static int find_res(const prw_graph *g, const char *name)
{
    for (uint32_t i = 0; i < g->nres; i++)
        if (strcmp(g->res[i].name, name) == 0) return (int)i;
    return -1;
}

static int get_res(prw_setup *s, const char *name)
{
    prw_graph *g = s->g;
    int i = find_res(g, name);
    if (i >= 0) return i;
    if (strlen(name) >= NAME_MAX_LEN) {
        setup_error(s, "resource name '%s' longer than %s characters", name, "31");
        return -1;
    }
    if (g->nres == MAX_RES) {
        setup_error(s, "more than %s resources (at '%s')", "64", name);
        return -1;
    }
    graph_res *r = &g->res[g->nres];
    memset(r, 0, sizeof *r);
    snprintf(r->name, sizeof r->name, "%s", name);
    r->creator = -1;
    r->leader = -1;
    return (int)g->nres++;
}

const prw_render_env *prw_setup_env(const prw_setup *s) { return s->g->env; }

void prw_setup_skip(prw_setup *s, const char *reason)
{
    graph_pass *p = &s->g->passes[s->pass];
    p->in_graph = false;
    snprintf(p->why_not, sizeof p->why_not, "%s", reason);
}

void prw_setup_image(prw_setup *s, const char *name, const prw_image_decl *d)
{
    int i = get_res(s, name);
    if (i < 0) return;
    graph_res *r = &s->g->res[i];
    if (r->declared || r->is_buffer) {
        setup_error(s, "'%s' is already created by another pass%s", name, "");
        return;
    }
    r->declared = true;
    r->decl = *d;
    r->creator = (int)s->pass;
}

void prw_setup_optional(prw_setup *s, const char *name)
{
    int i = find_res(s->g, name);
    if (i < 0 || s->g->res[i].creator != (int)s->pass) {
        setup_error(s, "optional '%s' is not an image this pass creates%s", name, "");
        return;
    }
    s->g->res[i].optional = true;
}

void prw_setup_optional_with(prw_setup *s, const char *name, const char *leader)
{
    int i = find_res(s->g, name), l = find_res(s->g, leader);
    if (i < 0 || l < 0 || s->g->res[i].creator != (int)s->pass) {
        setup_error(s, "optional '%s' (with '%s') is not an image this pass creates", name, leader);
        return;
    }
    s->g->res[i].optional = true;
    s->g->res[i].leader = l;
}

void prw_setup_use_view(prw_setup *s, const char *name, uint32_t view, prw_use use)
{
    graph_pass *p = &s->g->passes[s->pass];
    if ((unsigned)use >= PRW_USE_COUNT) {
        setup_error(s, "unknown use of '%s'%s", name, "");
        return;
    }
    if (p->nuses == MAX_USES) {
        setup_error(s, "more than %s uses (at '%s')", "24", name);
        return;
    }
    int i = get_res(s, name);
    if (i < 0) return;
    if (view != UINT32_MAX && view >= s->g->env->desc->max_views) {
        setup_error(s, "'%s': a use of a view beyond the renderer's max_views%s", name, "");
        return;
    }
    p->uses[p->nuses++] = (graph_use){i, view == UINT32_MAX ? -1 : (int)view, use};
}

void prw_setup_use(prw_setup *s, const char *name, prw_use use) { prw_setup_use_view(s, name, UINT32_MAX, use); }

void prw_setup_import_buffer(prw_setup *s, const char *name, VkBuffer buffer)
{
    int i = get_res(s, name);
    if (i < 0) return;
    graph_res *r = &s->g->res[i];
    if (r->declared) {
        setup_error(s, "'%s' is an image, not a buffer%s", name, "");
        return;
    }
    r->is_buffer = true;
    r->buffer = buffer;
    if (r->creator < 0) r->creator = (int)s->pass;
}

void prw_setup_export(prw_setup *s, const char *name)
{
    int i = get_res(s, name);
    if (i >= 0) s->g->res[i].exported = true;
}

/* ---- build ---- */

static void image_size(const prw_graph *g, const prw_image_decl *d, uint32_t *w, uint32_t *h, uint32_t *layers)
{
    const prw_render_desc *rd = g->env->desc;
    uint32_t ss = rd->quality.supersample ? rd->quality.supersample : 1;
    *layers = d->layers ? d->layers : 1;
    switch (d->size) {
    case PRW_SIZE_VIEW: *w = rd->width, *h = rd->height; break;
    case PRW_SIZE_INTERNAL: *w = rd->width * ss, *h = rd->height * ss; break;
    case PRW_SIZE_SCALED: {
        uint32_t k = d->scale ? d->scale : 1;
        *w = rd->width * ss * k, *h = rd->height * ss * k;
        break;
    }
    case PRW_SIZE_SHADOW:
        *w = *h = rd->quality.shadow_size;
        *layers = g->env->shadows->count ? g->env->shadows->count : 1;
        break;
    case PRW_SIZE_FIXED:
    default: *w = d->width, *h = d->height; break;
    }
}

static bool clear_image(prw_gpu *gpu, prw_gpu_image *img, prw_error *e)
{
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(gpu, &cmd, e)) return false;
    prw_cmd_transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkImageSubresourceRange range = {img->aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
    if (img->aspect & VK_IMAGE_ASPECT_DEPTH_BIT) {
        VkClearDepthStencilValue zero = {0.0f, 0};
        vkCmdClearDepthStencilImage(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &range);
    } else {
        VkClearColorValue zero = {{0, 0, 0, 0}};
        vkCmdClearColorImage(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &range);
    }
    prw_cmd_transition(cmd, img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    return prw_cmd_submit_wait(gpu, cmd, e);
}

static bool allocate(prw_graph *g, graph_res *r, prw_error *e)
{
    uint32_t w, h, layers;
    image_size(g, &r->decl, &w, &h, &layers);
    if (!w || !h) return prw_fail(e, "render graph: image '%s' has size %ux%u", r->name, w, h);
    prw_image_desc d = {
        .width = w,
        .height = h,
        .layers = layers,
        .format = r->decl.format,
        .samples = r->decl.msaa ? g->env->samples : VK_SAMPLE_COUNT_1_BIT,
        .usage = r->usage,
        .view_type = layers > 1 || r->decl.size == PRW_SIZE_SHADOW ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : 0,
    };
    if (r->decl.clear_at_create) d.usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    uint32_t n = r->decl.shared ? 1 : g->env->desc->max_views;
    for (uint32_t v = 0; v < n; v++) {
        if (!prw_image_create(g->env->gpu, &d, &r->img[v], e)) return prw_fail_wrap(e, "render graph: image '%s'", r->name);
        if (r->decl.clear_at_create && !clear_image(g->env->gpu, &r->img[v], e)) return false;
        /* a cleared image was last touched by another submission: its first barrier derives the source
         * scope from the layout (as for any change made outside the graph) */
        r->st[v] = (inst_state){.layout = r->decl.clear_at_create ? VK_IMAGE_LAYOUT_MAX_ENUM : r->img[v].layout};
    }
    return true;
}

static bool build(prw_graph *g, const prw_pass *const *table, const char *const *exports, prw_error *e)
{
    for (uint32_t i = 0; table[i]; i++) {
        if (g->npasses == PRW_MAX_PASSES) return prw_fail(e, "render graph: more than %d passes", PRW_MAX_PASSES);
        graph_pass *p = &g->passes[g->npasses];
        memset(p, 0, sizeof *p);
        p->p = table[i];
        p->in_graph = true;
        prw_setup s = {g, g->npasses};
        g->npasses++;
        if (p->p->setup) p->p->setup(&s);
        if (g->error[0]) return prw_fail(e, "%s", g->error);
        if (!p->in_graph) p->nuses = 0; /* a skipped pass's declarations do not count */
    }
    for (uint32_t i = 0; exports && exports[i]; i++) {
        int ri = find_res(g, exports[i]);
        if (ri < 0) return prw_fail(e, "render graph: export '%s': no pass declares it", exports[i]);
        g->res[ri].exported = true;
    }
    /* every use needs a creator in the graph; created images used by their creator */
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        if (!p->in_graph) continue;
        for (uint32_t k = 0; k < p->nuses; k++) {
            graph_res *r = &g->res[p->uses[k].res];
            bool ok = r->is_buffer || (r->declared && r->creator >= 0 && g->passes[r->creator].in_graph);
            if (!ok)
                return prw_fail(e, "render graph: pass '%s' uses '%s', which no pass in the graph creates", p->p->name,
                                r->name);
            if (r->is_buffer && info_of(p->uses[k].use).layout != VK_IMAGE_LAYOUT_UNDEFINED &&
                p->uses[k].use != PRW_USE_STORAGE_READ && p->uses[k].use != PRW_USE_STORAGE_WRITE &&
                p->uses[k].use != PRW_USE_TRANSFER_SRC && p->uses[k].use != PRW_USE_TRANSFER_DST)
                return prw_fail(e, "render graph: pass '%s': buffer '%s' used as %s", p->p->name, r->name,
                                prw_use_name(p->uses[k].use));
            if (!r->decl.shared || r->is_buffer) continue;
            if (p->uses[k].view >= 0)
                return prw_fail(e, "render graph: pass '%s': '%s' is shared, it has no per-view instances", p->p->name,
                                r->name);
        }
    }
    /* every read follows a write by an earlier pass in the graph (or of content made at allocation) */
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        if (!p->in_graph) continue;
        for (uint32_t k = 0; k < p->nuses; k++) {
            graph_res *r = &g->res[p->uses[k].res];
            bool rd = !info_of(p->uses[k].use).write || p->uses[k].use == PRW_USE_COLOR_ADD;
            if (!rd || r->is_buffer || r->decl.clear_at_create) continue;
            bool written = false;
            for (uint32_t q = 0; q < pi && !written; q++) {
                if (!g->passes[q].in_graph) continue;
                for (uint32_t j = 0; j < g->passes[q].nuses && !written; j++)
                    written = g->passes[q].uses[j].res == p->uses[k].res && info_of(g->passes[q].uses[j].use).write;
            }
            if (!written)
                return prw_fail(e, "render graph: pass '%s' reads '%s', which no earlier pass in the graph writes",
                                p->p->name, r->name);
        }
    }
    /* optional images: kept when a pass other than the creator reads them */
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        if (!p->in_graph) continue;
        for (uint32_t k = 0; k < p->nuses; k++) {
            graph_res *r = &g->res[p->uses[k].res];
            bool reads = !info_of(p->uses[k].use).write || p->uses[k].use == PRW_USE_COLOR_ADD;
            if ((int)pi != r->creator && reads) r->read_somewhere = true;
        }
    }
    for (uint32_t ri = 0; ri < g->nres; ri++) {
        graph_res *r = &g->res[ri];
        if (r->optional && r->leader < 0 && !r->read_somewhere && !r->exported) r->dropped = true;
    }
    for (uint32_t ri = 0; ri < g->nres; ri++) {
        graph_res *r = &g->res[ri];
        if (r->optional && r->leader >= 0) r->dropped = g->res[r->leader].dropped;
    }
    for (uint32_t pi = 0; pi < g->npasses; pi++) { /* drop the uses of dropped images */
        graph_pass *p = &g->passes[pi];
        uint32_t n = 0;
        for (uint32_t k = 0; k < p->nuses; k++)
            if (!g->res[p->uses[k].res].dropped) p->uses[n++] = p->uses[k];
        p->nuses = n;
    }
    /* usage = union of the uses; exported images can be read back */
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        if (!p->in_graph) continue;
        for (uint32_t k = 0; k < p->nuses; k++) g->res[p->uses[k].res].usage |= info_of(p->uses[k].use).usage;
    }
    for (uint32_t ri = 0; ri < g->nres; ri++) {
        graph_res *r = &g->res[ri];
        if (r->is_buffer || !r->declared || r->dropped || r->creator < 0 || !g->passes[r->creator].in_graph) continue;
        if (r->exported) r->usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        r->usage |= r->decl.usage;
        if (r->decl.transient && !(r->usage & ~(VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                                VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)))
            r->usage |= VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT;
        if (!allocate(g, r, e)) return false;
    }
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        if (!p->in_graph || !p->p->create) continue;
        prw_pass_init in = {g->env, g};
        p->created = true; /* destroy must run even when create fails half-way */
        if (!p->p->create(&in, &p->state, e)) return prw_fail_wrap(e, "pass '%s'", p->p->name);
    }
    return true;
}

bool prw_graph_create(const prw_render_env *env, const prw_pass *const *table, const char *const *exports,
                      prw_graph **out, prw_error *e)
{
    prw_graph *g = prw_calloc(1, sizeof *g);
    g->env = env;
    *out = NULL;
    if (!build(g, table, exports, e)) {
        prw_graph_destroy(g);
        return false;
    }
    *out = g;
    return true;
}

void prw_graph_destroy(prw_graph *g)
{
    if (!g) return;
    prw_error ignored;
    prw_gpu_wait_idle(g->env->gpu, &ignored);
    for (uint32_t pi = g->npasses; pi-- > 0;) {
        graph_pass *p = &g->passes[pi];
        prw_pass_init in = {g->env, g};
        if (p->created && p->p->destroy) p->p->destroy(&in, p->state);
    }
    for (uint32_t ri = 0; ri < g->nres; ri++)
        for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++) prw_image_destroy(g->env->gpu, &g->res[ri].img[v]);
    free(g);
}

/* ---- frame ---- */

prw_gpu_image *prw_graph_image(prw_graph *g, const char *name, uint32_t view)
{
    int i = find_res(g, name);
    if (i < 0) return NULL;
    graph_res *r = &g->res[i];
    if (r->is_buffer || r->dropped) return NULL;
    uint32_t v = r->decl.shared ? 0 : view;
    if (v >= PRW_MAX_VIEWS || !r->img[v].image) return NULL;
    return &r->img[v];
}

bool prw_graph_written(const prw_graph *g, const char *name)
{
    int i = find_res(g, name);
    return i >= 0 && g->res[i].written;
}

void prw_pass_begin_rendering(const prw_pass_ctx *c, const VkRenderingInfo *ri)
{
    c->graph->begins++;
    vkCmdBeginRendering(c->cmd, ri);
}

void prw_pass_end_rendering(const prw_pass_ctx *c) { vkCmdEndRendering(c->cmd); }

void prw_pass_barrier(const prw_pass_ctx *c, const VkDependencyInfo *d)
{
    c->graph->barriers++;
    vkCmdPipelineBarrier2(c->cmd, d);
}

void prw_pass_transition(const prw_pass_ctx *c, prw_gpu_image *img, VkImageLayout layout)
{
    c->graph->barriers++;
    prw_cmd_transition(c->cmd, img, layout);
}

void prw_pass_memory_barrier(const prw_pass_ctx *c, VkPipelineStageFlags2 src, VkAccessFlags2 src_access,
                             VkPipelineStageFlags2 dst, VkAccessFlags2 dst_access)
{
    VkMemoryBarrier2 mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                           .srcStageMask = src,
                           .srcAccessMask = src_access,
                           .dstStageMask = dst,
                           .dstAccessMask = dst_access};
    VkDependencyInfo di = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1, .pMemoryBarriers = &mb};
    prw_pass_barrier(c, &di);
}

typedef struct barrier_batch {
    VkImageMemoryBarrier2 img[MAX_USES * PRW_MAX_VIEWS];
    uint32_t nimg;
    VkMemoryBarrier2 mem;
    bool has_mem;
} barrier_batch;

/* Adds what instance (r, v) needs before `use` and updates its state. */
static void need(barrier_batch *b, graph_res *r, uint32_t v, prw_use use)
{
    use_info u = info_of(use);
    inst_state *st = &r->st[v];
    VkPipelineStageFlags2 src_stage = 0;
    VkAccessFlags2 src_access = 0;
    bool transition = false;
    VkImageLayout new_layout = VK_IMAGE_LAYOUT_UNDEFINED, old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (!r->is_buffer) {
        prw_gpu_image *img = &r->img[v];
        new_layout = layout_for(r, use);
        old_layout = img->layout;
        if (old_layout != st->layout) {
            /* changed outside the graph (readback, upload): whatever that layout allows */
            VkAccessFlags2 reads;
            prw_layout_access(old_layout, img->aspect, &st->w_stage, &reads, &st->w_access);
            st->r_stage = st->w_stage;
            st->visible = 0;
            st->layout = old_layout;
        }
        transition = old_layout != new_layout;
    }
    if (transition || u.write) {
        /* layout transitions and writes wait for every earlier access (WAR, WAW, RAW) */
        src_stage = st->w_stage | st->r_stage;
        src_access = st->w_access;
    } else if (st->w_stage && !((st->visible & u.stage) == u.stage && (st->visible_access & u.access) == u.access)) {
        src_stage = st->w_stage; /* read after a write not yet visible here */
        src_access = st->w_access;
    }
    bool needed = transition || src_stage != 0;
    if (needed) {
        if (!src_stage) src_stage = VK_PIPELINE_STAGE_2_NONE;
        if (r->is_buffer) {
            b->mem.srcStageMask |= src_stage;
            b->mem.srcAccessMask |= src_access;
            b->mem.dstStageMask |= u.stage;
            b->mem.dstAccessMask |= u.access;
            b->has_mem = true;
        } else {
            prw_gpu_image *img = &r->img[v];
            b->img[b->nimg++] = (VkImageMemoryBarrier2){
                .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
                .srcStageMask = src_stage,
                .srcAccessMask = src_access,
                .dstStageMask = u.stage,
                .dstAccessMask = u.access,
                .oldLayout = old_layout,
                .newLayout = new_layout,
                .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .image = img->image,
                .subresourceRange = {img->aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS},
            };
            img->layout = new_layout;
            st->layout = new_layout;
        }
    }
    if (u.write) {
        st->w_stage = u.stage;
        st->w_access = u.access & (VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
        st->r_stage = 0;
        st->visible = 0;
        st->visible_access = 0;
    } else {
        st->r_stage |= u.stage;
        if (needed) {
            st->visible |= u.stage;
            st->visible_access |= u.access;
        }
    }
}

static void flush_batch(prw_graph *g, VkCommandBuffer cmd, barrier_batch *b)
{
    if (!b->nimg && !b->has_mem) return;
    if (b->has_mem) b->mem.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2;
    VkDependencyInfo di = {
        .sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
        .memoryBarrierCount = b->has_mem ? 1 : 0,
        .pMemoryBarriers = &b->mem,
        .imageMemoryBarrierCount = b->nimg,
        .pImageMemoryBarriers = b->img,
    };
    vkCmdPipelineBarrier2(cmd, &di);
    g->barriers++;
}

/* The instances of use k of pass p for this frame, into vs[] (count returned). */
static uint32_t use_views(const prw_graph *g, const graph_pass *p, const graph_use *u, const prw_frame *f,
                          uint32_t *vs)
{
    const graph_res *r = &g->res[u->res];
    if (r->is_buffer || r->decl.shared) {
        vs[0] = 0;
        return 1;
    }
    if (u->view >= 0) {
        if ((uint32_t)u->view >= f->view_count) return 0;
        vs[0] = (uint32_t)u->view;
        return 1;
    }
    uint32_t n = 0;
    for (uint32_t v = 0; v < f->view_count; v++)
        if (p->p->scope == PRW_SCOPE_FRAME || p->needed_view[v]) vs[n++] = v;
    return n;
}

static bool reads(prw_use u) { return !prw_use_writes(u) || u == PRW_USE_COLOR_ADD; }

static void decide(prw_graph *g, prw_frame *f, prw_pass_ctx *c)
{
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        p->needed = p->live = false;
        p->frame_reason[0] = '\0';
        if (!p->in_graph) continue;
        const char *why = NULL;
        c->state = p->state;
        if (p->p->scope == PRW_SCOPE_VIEW) {
            for (uint32_t v = 0; v < f->view_count; v++) {
                c->view = v;
                const char *w = NULL;
                p->needed_view[v] = !p->p->needed || p->p->needed(c, &w);
                p->needed = p->needed || p->needed_view[v];
                if (!p->needed_view[v] && !why) why = w;
            }
            if (!f->view_count) why = "no views";
        } else {
            c->view = 0;
            p->needed = !p->p->needed || p->p->needed(c, &why);
        }
        if (!p->needed) snprintf(p->frame_reason, sizeof p->frame_reason, "%s", why ? why : "not needed");
    }
    /* liveness, backwards: exported or read by a later live pass */
    bool read_later[MAX_RES] = {false};
    for (uint32_t ri = 0; ri < g->nres; ri++) read_later[ri] = g->res[ri].exported;
    for (uint32_t pi = g->npasses; pi-- > 0;) {
        graph_pass *p = &g->passes[pi];
        if (!p->needed) continue;
        bool live = (p->p->flags & PRW_PASS_KEEP) != 0;
        for (uint32_t k = 0; k < p->nuses && !live; k++)
            if (prw_use_writes(p->uses[k].use) && read_later[p->uses[k].res]) live = true;
        p->live = live;
        if (!live) {
            snprintf(p->frame_reason, sizeof p->frame_reason, "culled: nothing reads its outputs");
            continue;
        }
        for (uint32_t k = 0; k < p->nuses; k++)
            if (reads(p->uses[k].use)) read_later[p->uses[k].res] = true;
    }
}

bool prw_graph_execute(prw_graph *g, prw_frame *f, prw_graph_exec *x, prw_frame_stats *stats, prw_error *e)
{
    prw_pass_ctx c = {.env = g->env, .frame = f, .graph = g, .cmd = x->cmd};
    g->barriers = g->begins = 0;
    for (uint32_t ri = 0; ri < g->nres; ri++) g->res[ri].written = false;
    decide(g, f, &c);
    memset(stats, 0, sizeof *stats);
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        graph_pass *p = &g->passes[pi];
        if (!p->in_graph) continue;
        prw_pass_stat *s = &stats->passes[stats->pass_count++];
        s->name = p->p->name;
        s->flags = p->p->flags;
        s->gpu_ms = -1.0;
        s->timer_scope = UINT32_MAX;
        s->skipped = !p->live;
        if (s->skipped) {
            snprintf(s->reason, sizeof s->reason, "%s", p->frame_reason);
            continue;
        }
        bool host = p->p->queue == PRW_QUEUE_HOST;
        if (host && !x->split) {
            s->skipped = true;
            snprintf(s->reason, sizeof s->reason, "a host stage: runs in prw_renderer_render only");
            continue;
        }
        bool host_timed = (p->p->queue == PRW_QUEUE_COMPUTE && x->split && x->time_compute) || host;
        double ms = 0;
        c.cmd = x->cmd;
        barrier_batch b;
        b.nimg = 0;
        b.has_mem = false;
        memset(&b.mem, 0, sizeof b.mem);
        for (uint32_t k = 0; k < p->nuses; k++) {
            uint32_t vs[PRW_MAX_VIEWS], n = use_views(g, p, &p->uses[k], f, vs);
            for (uint32_t i = 0; i < n; i++) need(&b, &g->res[p->uses[k].res], vs[i], p->uses[k].use);
        }
        flush_batch(g, c.cmd, &b);
        /* host-timed passes start from an empty queue: what came before is submitted (and waited for) */
        if (host_timed && !x->split(x->user, &x->cmd, &ms, e)) return false;
        double t_host = prw_now();
        c.cmd = host ? VK_NULL_HANDLE : x->cmd;
        bool timed = x->timer && !host_timed;
        uint32_t scope = timed ? prw_timer_begin(c.cmd, x->timer, p->p->name) : 0;
        c.state = p->state;
        if (p->p->scope == PRW_SCOPE_VIEW) {
            for (uint32_t v = 0; v < f->view_count; v++) {
                if (!p->needed_view[v]) continue;
                c.view = v;
                if (!p->p->record(&c, e)) return prw_fail_wrap(e, "pass '%s' (view %u)", p->p->name, v);
            }
        } else {
            c.view = 0;
            if (!p->p->record(&c, e)) return prw_fail_wrap(e, "pass '%s'", p->p->name);
        }
        if (timed) {
            prw_timer_end(c.cmd, x->timer, scope);
            s->timer_scope = scope;
        }
        for (uint32_t k = 0; k < p->nuses; k++)
            if (prw_use_writes(p->uses[k].use)) g->res[p->uses[k].res].written = true;
        if (host) {
            s->gpu_ms = 1e3 * (prw_now() - t_host);
            s->host_clock = true;
        } else if (host_timed) {
            if (!x->split(x->user, &x->cmd, &ms, e)) return false;
            s->gpu_ms = ms;
            s->host_clock = true;
        }
        c.cmd = x->cmd;
    }
    /* exported buffers: the host reads them after the frame */
    barrier_batch b;
    b.nimg = 0;
    b.has_mem = false;
    memset(&b.mem, 0, sizeof b.mem);
    for (uint32_t ri = 0; ri < g->nres; ri++) {
        graph_res *r = &g->res[ri];
        if (r->is_buffer && r->exported && r->written) need(&b, r, 0, PRW_USE_HOST_READ);
    }
    flush_batch(g, x->cmd, &b);
    stats->triangles = f->triangles;
    stats->draws = f->draws;
    stats->barriers = g->barriers;
    stats->begins = g->begins;
    return true;
}

/* ---- description ---- */

static const char *size_name(prw_size_class s)
{
    switch (s) {
    case PRW_SIZE_VIEW: return "view";
    case PRW_SIZE_INTERNAL: return "view x ss";
    case PRW_SIZE_SCALED: return "view x ss x k";
    case PRW_SIZE_SHADOW: return "shadow atlas";
    default: return "fixed";
    }
}

static const char *format_name(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_R16G16B16A16_SFLOAT: return "RGBA16F";
    case VK_FORMAT_R32G32B32A32_SFLOAT: return "RGBA32F";
    case VK_FORMAT_R8G8B8A8_UNORM: return "RGBA8";
    case VK_FORMAT_D32_SFLOAT: return "D32F";
    case VK_FORMAT_D32_SFLOAT_S8_UINT: return "D32F_S8";
    case VK_FORMAT_R32_UINT: return "R32U";
    case VK_FORMAT_R32_SFLOAT: return "R32F";
    default: return "other";
    }
}

void prw_graph_describe(const prw_graph *g, char *buf, size_t cap)
{
    size_t n = strlen(buf);
#define OUT(...)                                                                  \
    do {                                                                          \
        if (n < cap) n += (size_t)snprintf(buf + n, cap - n, __VA_ARGS__);        \
    } while (0)
    OUT("passes (in order):\n");
    for (uint32_t pi = 0; pi < g->npasses; pi++) {
        const graph_pass *p = &g->passes[pi];
        OUT("  %-14s %-5s %-8s", p->p->name, p->p->scope == PRW_SCOPE_VIEW ? "view" : "frame",
            p->p->queue == PRW_QUEUE_COMPUTE ? "compute" : p->p->queue == PRW_QUEUE_HOST ? "host" : "graphics");
        if (!p->in_graph) {
            OUT(" not in the graph: %s\n", p->why_not);
            continue;
        }
        for (uint32_t k = 0; k < p->nuses; k++) {
            const graph_use *u = &p->uses[k];
            if (u->view >= 0) OUT("%s %s[%d]:%s", k ? "," : "", g->res[u->res].name, u->view, prw_use_name(u->use));
            else OUT("%s %s:%s", k ? "," : "", g->res[u->res].name, prw_use_name(u->use));
        }
        OUT("\n");
    }
    OUT("resources:\n");
    for (uint32_t ri = 0; ri < g->nres; ri++) {
        const graph_res *r = &g->res[ri];
        if (r->is_buffer) {
            OUT("  %-14s buffer (imported)%s\n", r->name, r->exported ? ", read by the host" : "");
            continue;
        }
        if (!r->declared || r->creator < 0 || !g->passes[r->creator].in_graph) continue;
        if (r->dropped) {
            OUT("  %-14s %s, %s: dropped (optional; no pass reads it)\n", r->name, format_name(r->decl.format),
                size_name(r->decl.size));
            continue;
        }
        const prw_gpu_image *img = &r->img[0];
        char layers[24] = "";
        if (img->layers > 1) snprintf(layers, sizeof layers, " x %u layers", img->layers);
        OUT("  %-14s %s %ux%u%s, %s, %s%s%s, created by %s\n", r->name, format_name(r->decl.format), img->width,
            img->height, layers, size_name(r->decl.size),
            r->decl.shared ? "shared" : "per view", r->decl.msaa && img->samples > 1 ? ", multisampled" : "",
            r->exported ? ", exported" : "", g->passes[r->creator].p->name);
    }
#undef OUT
}

uint32_t prw_graph_pass_count(const prw_graph *g) { return g->npasses; }
const char *prw_graph_pass_name(const prw_graph *g, uint32_t i) { return i < g->npasses ? g->passes[i].p->name : NULL; }

bool prw_graph_pass_in_graph(const prw_graph *g, uint32_t i, const char **why_not)
{
    if (i >= g->npasses) return false;
    if (why_not) *why_not = g->passes[i].why_not;
    return g->passes[i].in_graph;
}

uint32_t prw_graph_resource_count(const prw_graph *g) { return g->nres; }

const char *prw_graph_resource(const prw_graph *g, uint32_t i, bool *allocated, bool *shared,
                               VkImageUsageFlags *usage)
{
    if (i >= g->nres) return NULL;
    const graph_res *r = &g->res[i];
    if (allocated) *allocated = r->is_buffer || (r->img[0].image != VK_NULL_HANDLE);
    if (shared) *shared = r->is_buffer || r->decl.shared;
    if (usage) *usage = r->usage;
    return r->name;
}

void *prw_graph_pass_state(const prw_graph *g, const char *pass)
{
    for (uint32_t i = 0; i < g->npasses; i++)
        if (g->passes[i].in_graph && strcmp(g->passes[i].p->name, pass) == 0) return g->passes[i].state;
    return NULL;
}
