/* app — the prw command line: argument parsing helpers and what every subcommand shares
 * (global options, loading a scene or the demo, creating the GPU). */
#ifndef PRW_APP_H
#define PRW_APP_H

#include "prw_core.h"
#include "prw_gpu.h"
#include "prw_scene.h"

typedef struct prw_global_opts {
    int threads;          /* 0 = all cores */
    const char *device;   /* index or name substring, NULL = PRW_DEVICE or first */
    bool validation;
} prw_global_opts;

extern prw_global_opts g_prw_opts;

/* Simple option reader over argv[first..argc): "--name value" or "--name=value"; positional
 * arguments are collected in order. */
typedef struct prw_args {
    int argc;
    char **argv;
    bool *used;
    const char *positional[64];
    int positional_count;
} prw_args;

bool prw_args_init(prw_args *a, int argc, char **argv, prw_error *e);
void prw_args_free(prw_args *a);
/* Returns the value of --name (NULL when absent); *e set when the value is missing. */
const char *prw_args_value(prw_args *a, const char *name, prw_error *e, bool *bad);
bool prw_args_flag(prw_args *a, const char *name);
/* Fails on any --option not consumed by the calls above. Call after all lookups. */
bool prw_args_finish(prw_args *a, prw_error *e);

bool prw_parse_size(const char *s, uint32_t *w, uint32_t *h, prw_error *e);
bool prw_parse_int(const char *s, const char *what, long lo, long hi, long *out, prw_error *e);
bool prw_parse_double(const char *s, const char *what, double lo, double hi, double *out, prw_error *e);

/* Loads a manifest (path) or, for NULL/"demo", the built-in demo scene. */
bool prw_app_load_scene(const char *path, prw_scene **out, prw_error *e);
/* prw_app_load_scene for the commands that draw: also fails ("nothing to render", naming the file)
 * when the scene has no geometry. */
bool prw_app_load_renderable(const char *path, prw_scene **out, prw_error *e);
/* Makes a loaded scene ready for the renderer and the reference: the baker (engine/bake,
 * prw_bake_scene) attaches every NURBS entry's model and LOD hierarchy, from the cache or built;
 * one progress line per entry on stderr (log level info). */
bool prw_app_bake_scene(prw_scene *s, prw_error *e);
bool prw_app_create_gpu(bool present, prw_gpu **out, prw_error *e);


int prw_cmd_render(int argc, char **argv);
int prw_cmd_info(int argc, char **argv);
int prw_cmd_walk(int argc, char **argv);
int prw_cmd_compare(int argc, char **argv);
int prw_cmd_reference(int argc, char **argv);
int prw_cmd_reference_merge(int argc, char **argv);
int prw_cmd_bench(int argc, char **argv);
int prw_cmd_bench_merge(int argc, char **argv);
int prw_cmd_tmbench(int argc, char **argv);
int prw_cmd_bake(int argc, char **argv);
int prw_cmd_cache(int argc, char **argv);
int prw_cmd_btf_compress(int argc, char **argv);
int prw_cmd_btf_bench(int argc, char **argv);

/* The demo job: a window when a display exists, else a headless render to files. */
int prw_run_demo(void);

#endif
