/* bench_ref — the benchmark's references: the content-addressed cache, the child process that renders
 * them, and loading them back (phase 1 of prw bench, before anything is timed).
 *
 * Cache: <cache>/refs/<key>.exr (+ <key>.var.exr, the variance the tracer writes beside it), where
 * <cache> is $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else $HOME/.cache/prw.  The key (32 hex digits,
 * two FNV-1a 64 hashes of one byte string) covers the full key of DESIGN.md §5: the scene hash, the
 * material-header hash, the camera pose and frustum (bit patterns of the view matrix, eye, frustum
 * tangents, near plane), the exposure, the resolution, spp, seed, the light-path filter, and the git
 * hash of the build.  The git hash (not a tracer format version) is the choice because DESIGN.md §5
 * names it and the tracer has no version of its own: any commit invalidates the cache, which is
 * conservative (a stale reference can never be reused; an uncommitted change to the tracer is not
 * seen, so run with --no-ref-cache while editing it).  Entries are written atomically by the child
 * (temporary name + rename); an entry that cannot be read back, or whose prw:bench_key attribute
 * differs, is rendered again.
 *
 * Child: `/proc/self/exe [--threads N] bench SCENE --path P --size WxH --ref-spp N --ref-child
 * FRAME:SEED:KEY,... --ref-dir DIR` (posix_spawn; the parent waits).  The child recomputes every
 * view and key from the same inputs and refuses a job whose key differs.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_internal.h"
#include "prw_reference.h"

extern char **environ;

#define BENCH_REF_KEY_VERSION "prw-bench-ref-key 1"

/* The output directory is made and probed before any work, so an unwritable --out is reported
 * first, not after the references and the timed runs. */
bool bench_mkdirs(const char *dir, prw_error *e)
{
    return prw_check_writable_dir(dir, true, e) && prw_mkdirs(dir, e) && prw_check_writable_dir(dir, false, e);
}

bool bench_cache_dir(char *buf, size_t cap, prw_error *e)
{
    return prw_cache_dir("refs", "reference cache", true, buf, cap, e);
}

typedef struct key_buf {
    unsigned char b[512];
    size_t n;
} key_buf;

static void put(key_buf *k, const void *p, size_t n)
{
    if (k->n + n <= sizeof k->b) memcpy(k->b + k->n, p, n);
    k->n += n;
}

void bench_ref_key(const prw_scene *s, const prw_view *v, uint64_t spp, uint64_t seed, char out[33])
{
    key_buf k = {.n = 0};
    const char *tag = BENCH_REF_KEY_VERSION, *git = prw_ref_git_hash();
    put(&k, tag, strlen(tag) + 1);
    put(&k, git, strlen(git) + 1);
    uint64_t h[2] = {prw_scene_hash(s), prw_ref_material_hash()};
    put(&k, h, sizeof h);
    put(&k, v->view.m, sizeof v->view.m); /* doubles: their bit patterns */
    put(&k, &v->eye, sizeof v->eye);
    double f[6] = {v->tan_left, v->tan_right, v->tan_bottom, v->tan_top, v->znear, v->ev100};
    put(&k, f, sizeof f);
    uint32_t size[2] = {v->width, v->height};
    put(&k, size, sizeof size);
    uint64_t ss[2] = {spp, seed};
    put(&k, ss, sizeof ss);
    int32_t filter[2] = {PRW_REF_ALL, 0}; /* light-path filter: the benchmark compares full images */
    put(&k, filter, sizeof filter);
    uint64_t a = prw_hash64(k.b, k.n, 0), b = prw_hash64(k.b, k.n, 0x9e3779b97f4a7c15ull);
    snprintf(out, 33, "%016llx%016llx", (unsigned long long)a, (unsigned long long)b);
}

typedef struct ref_job {
    uint32_t frame;
    uint32_t seed;
    char key[33];
} ref_job;

static void entry_path(char *buf, size_t cap, const char *dir, const char *key)
{
    snprintf(buf, cap, "%s/%s.exr", dir, key);
}

/* Loads an entry; false (quietly) when missing, unreadable or for another key. */
static bool load_entry(const char *dir, const char *key, uint32_t w, uint32_t h, prw_image *out)
{
    char path[4200], attr[64];
    entry_path(path, sizeof path, dir, key);
    prw_error e;
    if (access(path, R_OK) != 0) return false;
    if (!prw_exr_read_attr(path, "prw:bench_key", attr, sizeof attr, &e) || strcmp(attr, key) != 0 ||
        !prw_exr_read(path, NULL, out, &e)) {
        prw_log(PRW_LOG_WARN, "bench: reference cache entry %s is unreadable or stale: rendering it again", path);
        return false;
    }
    if (out->width != (int)w || out->height != (int)h) {
        prw_image_free(out);
        return false;
    }
    return true;
}

static bool spawn_child(const bench_ctx *c, const ref_job *jobs, uint32_t n, const char *dir, prw_error *e)
{
    size_t cap = (size_t)n * 48 + 16, len = 0;
    char *list = prw_malloc(cap);
    list[0] = '\0';
    for (uint32_t i = 0; i < n; i++)
        len += (size_t)snprintf(list + len, cap - len, "%s%u:%u:%s", i ? "," : "", jobs[i].frame, jobs[i].seed,
                                jobs[i].key);
    char threads[16], size[32], spp[24], limit[24];
    snprintf(threads, sizeof threads, "%d", prw_threads_get());
    snprintf(size, sizeof size, "%ux%u", c->o.width, c->o.height);
    snprintf(spp, sizeof spp, "%ld", c->o.ref_spp);
    snprintf(limit, sizeof limit, "%u", c->frame_count);
    char *argv[] = {"prw", "--threads", threads, "--log-level", "warn", "bench",
                    (char *)(c->o.scene_path ? c->o.scene_path : "demo"), "--path", (char *)c->o.path_spec,
                    "--size", size, "--ref-spp", spp, "--frames-limit", limit, "--ref-child", list,
                    "--ref-dir", (char *)dir, NULL};
    pid_t pid;
    int err = posix_spawn(&pid, "/proc/self/exe", NULL, NULL, argv, environ);
    free(list);
    if (err != 0) return prw_fail(e, "bench: cannot start the reference child process: %s", strerror(err));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return prw_fail(e, "bench: waiting for the reference child: %s", strerror(errno));
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return prw_fail(e, "bench: the reference child process failed (%s %d; see its message above)",
                        WIFEXITED(status) ? "exit code" : "signal",
                        WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
    return true;
}

bool bench_references(bench_ctx *c, prw_error *e)
{
    char dir[4096];
    if (c->o.no_ref_cache) {
        bench_join(dir, sizeof dir, c->o.out_dir, "refs");
        if (!bench_mkdirs(dir, e)) return false;
    } else if (!bench_cache_dir(dir, sizeof dir, e)) {
        return false;
    }
    uint32_t nref = 0;
    for (uint32_t i = 0; i < c->nframes; i++) nref += c->is_ref[c->frames[i]];
    ref_job *jobs = prw_calloc((size_t)nref * 2 + 1, sizeof *jobs);
    prw_image *imgs = prw_calloc((size_t)nref * 2 + 1, sizeof *imgs);
    uint32_t nj = 0;
    bool ok = true;
    for (uint32_t i = 0; ok && i < c->nframes; i++) {
        uint32_t k = c->frames[i];
        if (!c->is_ref[k]) continue;
        prw_view v;
        ok = bench_frame_view(c, k, &v, e);
        for (uint32_t s = 0; ok && s < 2; s++) {
            jobs[nj].frame = k;
            jobs[nj].seed = s ? BENCH_REF_SEED_B : BENCH_REF_SEED_A;
            bench_ref_key(c->scene, &v, (uint64_t)c->o.ref_spp, jobs[nj].seed, jobs[nj].key);
            nj++;
        }
    }
    /* Up to two rounds: render what is missing, then load; a second failure to load is an error. */
    for (int round = 0; ok && round < 2; round++) {
        ref_job *todo = prw_calloc(nj + 1, sizeof *todo);
        uint32_t nt = 0;
        for (uint32_t j = 0; j < nj; j++) {
            if (imgs[j].rgba) continue;
            bool reuse = round > 0 || !c->o.no_ref_cache;
            if (!reuse || !load_entry(dir, jobs[j].key, c->o.width, c->o.height, &imgs[j])) todo[nt++] = jobs[j];
        }
        if (nt == 0) {
            free(todo);
            break;
        }
        if (round == 1) {
            ok = prw_fail(e, "bench: reference %s/%s.exr (frame %u, seed %u) unreadable after rendering it", dir,
                          todo[0].key, todo[0].frame, todo[0].seed);
        } else {
            fprintf(stderr, "bench: %u of %u reference images to render (%ld spp, %ux%u) in a child process; %s\n",
                    nt, nj, c->o.ref_spp, c->o.width, c->o.height, dir);
            ok = spawn_child(c, todo, nt, dir, e);
        }
        free(todo);
    }
    if (ok) {
        fprintf(stderr, "bench: %u reference images ready (%s)\n", nj, c->o.no_ref_cache ? "cache not read" : dir);
        c->ref_a = prw_calloc(c->frame_count, sizeof *c->ref_a);
        c->noise = prw_calloc(c->frame_count, sizeof *c->noise);
        for (uint32_t j = 0; ok && j + 1 < nj; j += 2) {
            uint32_t k = jobs[j].frame;
            prw_compare_opts co = {.ev100 = c->ev100};
            prw_compare_metrics m;
            ok = prw_compare_images(&imgs[j + 1], &imgs[j], &co, &m, NULL, NULL, e);
            c->noise[k] = (bench_err){m.ldr_flip.mean, m.hdr_flip.mean, m.basic.psnr, m.ssim};
            c->ref_a[k] = imgs[j];
            imgs[j] = (prw_image){0};
        }
    }
    for (uint32_t j = 0; j < nj; j++) prw_image_free(&imgs[j]);
    free(imgs);
    free(jobs);
    return ok;
}

/* ---- the child ---- */

typedef struct child_progress {
    uint32_t index, count;
    uint32_t frame, seed;
    double t_start, per_job; /* per_job: mean seconds of the finished jobs (0: none yet) */
} child_progress;

static void child_progress_cb(void *user, const prw_ref_progress *p)
{
    const child_progress *cp = user;
    double frac = p->total ? (double)p->done / (double)p->total : 1.0;
    double eta = -1;
    if (p->eta_s >= 0) {
        double per = cp->per_job > 0 ? cp->per_job : p->elapsed_s / (frac > 0 ? frac : 1);
        eta = p->eta_s + per * (double)(cp->count - cp->index - 1);
    }
    char etas[32] = "?";
    if (eta >= 0) snprintf(etas, sizeof etas, "%.0f s", eta);
    fprintf(stderr, "\rreference %u/%u: frame %u seed %u  %5.1f %%  ETA %s    ", cp->index + 1, cp->count, cp->frame,
            cp->seed, 100.0 * frac, etas);
    fflush(stderr);
}

static bool parse_jobs(const char *text, ref_job **out, uint32_t *n, prw_error *e)
{
    uint32_t cap = 1;
    for (const char *p = text; *p; p++) cap += *p == ',';
    ref_job *jobs = prw_calloc(cap, sizeof *jobs);
    uint32_t count = 0;
    const char *p = text;
    while (*p) {
        unsigned f, s;
        char key[33];
        int used = 0;
        if (sscanf(p, "%u:%u:%32[0-9a-f]%n", &f, &s, key, &used) != 3 || strlen(key) != 32 ||
            (p[used] != ',' && p[used] != '\0')) {
            free(jobs);
            return prw_fail(e, "--ref-child: malformed job list at '%.40s'", p);
        }
        jobs[count].frame = f, jobs[count].seed = s;
        memcpy(jobs[count].key, key, 33);
        count++;
        p += used + (p[used] == ',');
    }
    *out = jobs;
    *n = count;
    return true;
}

int bench_ref_child(bench_ctx *c)
{
    prw_error e = {{0}};
    ref_job *jobs = NULL;
    uint32_t n = 0;
    bool ok = c->o.ref_dir ? parse_jobs(c->o.ref_child, &jobs, &n, &e) : prw_fail(&e, "--ref-child needs --ref-dir");
    double t0 = prw_now();
    for (uint32_t i = 0; ok && i < n; i++) {
        prw_view v;
        char key[33];
        if (jobs[i].frame >= c->frame_count) {
            ok = prw_fail(&e, "reference child: frame %u outside the path (%u frames)", jobs[i].frame, c->frame_count);
            break;
        }
        if (!bench_frame_view(c, jobs[i].frame, &v, &e)) ok = false;
        if (ok) bench_ref_key(c->scene, &v, (uint64_t)c->o.ref_spp, jobs[i].seed, key);
        if (ok && strcmp(key, jobs[i].key) != 0)
            ok = prw_fail(&e, "reference child: key of frame %u seed %u is %s, the parent expected %s", jobs[i].frame,
                          jobs[i].seed, key, jobs[i].key);
        if (!ok) break;
        prw_ref_renderer *r = NULL;
        prw_ref_acc acc = {0};
        prw_ref_stats st;
        child_progress cp = {i, n, jobs[i].frame, jobs[i].seed, prw_now(), i ? (prw_now() - t0) / i : 0};
        prw_ref_desc d = {.s0 = 0, .s1 = (uint64_t)c->o.ref_spp, .seed = jobs[i].seed,
                          .filter = {PRW_REF_ALL, 0}, .progress = child_progress_cb, .user = &cp};
        ok = prw_ref_create(c->scene, v.eye, prw_threads_get(), &r, &e) && prw_ref_render(r, &v, &d, &acc, &st, &e);
        if (ok) {
            char path[4200], frame[16];
            entry_path(path, sizeof path, c->o.ref_dir, key);
            snprintf(frame, sizeof frame, "%u", jobs[i].frame);
            const char *extra[] = {"prw:bench_key", key, "prw:scene", c->scene->source, "prw:bench_path",
                                   c->o.path_spec, "prw:bench_frame", frame};
            ok = prw_ref_write_exr(path, &acc, extra, 4, &e);
        }
        prw_ref_acc_free(&acc);
        prw_ref_destroy(r);
    }
    if (n) fprintf(stderr, "\rreference %u/%u done in %.1f s%30s\n", n, n, prw_now() - t0, "");
    free(jobs);
    if (!ok) fprintf(stderr, "prw bench (reference child): error: %s\n", e.msg);
    return ok ? 0 : 1;
}
