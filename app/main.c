/* prw — predictive-rendering walkthrough.  Global options, then a subcommand. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "prw_build_info.h"


static void usage(FILE *f)
{
    fprintf(f,
            "usage: prw [global options] [command] [command options]\n"
            "\n"
            "Predictive-rendering walkthrough: renders scenes in physical units (cd/m^2) and says how\n"
            "far the image is from a physically based reference.  With no command, runs the built-in\n"
            "demo: a window when a display exists, otherwise a headless render to prw-out/.\n"
            "\n"
            "commands:\n"
            "  render [SCENE]   render a still to EXR (linear cd/m^2) + PNG (display-encoded)\n"
            "  walk [SCENE]     open a window and walk through the scene\n"
            "  info SCENE       print the scene's content and the passes it needs\n"
            "  compare REF TEST error of TEST against reference REF (RMSE, relMSE, PSNR, SSIM, LDR-/HDR-FLIP)\n"
            "  reference [SCENE] path-traced reference EXR (cd/m^2) + variance EXR, same camera and pixels\n"
            "  reference-merge A.acc B.acc ... --out ref.exr   merge tiles / sample batches bit-exactly\n"
            "  bench [SCENE] [PATH.json]   camera-path benchmark: frame/pass times, memory, error vs references\n"
            "  bench-merge DIR1 DIR2 ... --out DIR   join the outputs of bench --shard runs bit-exactly\n"
            "  tmbench         selective vs full local tone mapping: quality and speed of the passes alone\n"
            "  bake MODEL      build / cache the LOD hierarchy of a trimmed-NURBS model (.igs, .iges, .json)\n"
            "  cache clear [KIND]  remove cached entries (LOD hierarchies, references, ...); rebuilt on demand\n"
            "  btf-compress    compress a BTF (synthetic or a Bonn binary) by each codec point: size against error\n"
            "  btf-bench [SCENE]  frame time with the BTF materials over their fitted analytic averages, interleaved\n"
            "  SCENE is a manifest (.json), a model (.gltf, .glb, .igs, .iges) or 'demo' (the default).  'prw COMMAND --help' for options.\n"
            "\n"
            "global options:\n"
            "  --threads N      thread budget for every pool (lavapipe, Embree/TBB, OpenMP); default: all cores\n"
            "  --device D       Vulkan device index or name substring (also PRW_DEVICE)\n"
            "  --validation     enable the Vulkan validation layer (also PRW_VALIDATION=1)\n"
            "  --log-level L    error | warn | info | debug (default info)\n"
            "  --max-memory B   memory budget for inputs and image sizes, e.g. 4G (default: the available\n"
            "                   memory); larger inputs are refused before anything is allocated\n"
            "  --version        print the version, git hash and Vulkan driver\n"
            "  --help           this text\n");
}

static int print_version(void)
{
    printf("prw %s (git %s)\n", PRW_VERSION, prw_build_git_hash());
    prw_gpu *gpu;
    prw_error e;
    prw_threads_set(g_prw_opts.threads);
    if (!prw_app_create_gpu(false, &gpu, &e)) {
        printf("vulkan: unavailable (%s)\n", e.msg);
        return 0;
    }
    printf("vulkan: %s, driver %s\n", prw_gpu_device_name(gpu), prw_gpu_driver_info(gpu));
    prw_gpu_destroy(gpu);
    return 0;
}

int main(int argc, char **argv)
{
    int i = 1;
    for (; i < argc; i++) {
        const char *a = argv[i];
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        prw_error e;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--version") == 0) {
            return print_version();
        } else if (strcmp(a, "--validation") == 0) {
            g_prw_opts.validation = true;
        } else if (strcmp(a, "--threads") == 0 || strcmp(a, "--device") == 0 || strcmp(a, "--log-level") == 0 ||
                   strcmp(a, "--max-memory") == 0) {
            if (!next) {
                fprintf(stderr, "prw: error: %s needs a value\n", a);
                return 2;
            }
            i++;
            if (strcmp(a, "--threads") == 0) {
                long n;
                if (!prw_parse_int(next, "--threads", 1, 1024, &n, &e)) {
                    fprintf(stderr, "prw: error: %s\n", e.msg);
                    return 2;
                }
                g_prw_opts.threads = (int)n;
            } else if (strcmp(a, "--device") == 0) {
                g_prw_opts.device = next;
            } else if (strcmp(a, "--max-memory") == 0) {
                uint64_t b;
                if (!prw_mem_parse(next, &b, &e)) {
                    fprintf(stderr, "prw: error: %s\n", e.msg);
                    return 2;
                }
                prw_mem_set_budget(b);
            } else {
                prw_log_level lvl;
                if (!prw_log_parse_level(next, &lvl)) {
                    fprintf(stderr, "prw: error: --log-level '%s': expected error|warn|info|debug\n", next);
                    return 2;
                }
                prw_log_set_level(lvl);
            }
        } else if (a[0] == '-') {
            fprintf(stderr, "prw: error: unknown global option '%s' (see prw --help)\n", a);
            return 2;
        } else {
            break;
        }
    }
    /* Before any Vulkan call: lavapipe reads LP_NUM_THREADS at device creation. */
    prw_threads_set(g_prw_opts.threads);
    if (i >= argc) return prw_run_demo();
    const char *cmd = argv[i];
    int sub_argc = argc - i - 1;
    char **sub_argv = argv + i + 1;
    if (strcmp(cmd, "render") == 0) return prw_cmd_render(sub_argc, sub_argv);
    if (strcmp(cmd, "walk") == 0) return prw_cmd_walk(sub_argc, sub_argv);
    if (strcmp(cmd, "info") == 0) return prw_cmd_info(sub_argc, sub_argv);
    if (strcmp(cmd, "compare") == 0) return prw_cmd_compare(sub_argc, sub_argv);
    if (strcmp(cmd, "reference") == 0) return prw_cmd_reference(sub_argc, sub_argv);
    if (strcmp(cmd, "reference-merge") == 0) return prw_cmd_reference_merge(sub_argc, sub_argv);
    if (strcmp(cmd, "bench") == 0) return prw_cmd_bench(sub_argc, sub_argv);
    if (strcmp(cmd, "bench-merge") == 0) return prw_cmd_bench_merge(sub_argc, sub_argv);
    if (strcmp(cmd, "tmbench") == 0) return prw_cmd_tmbench(sub_argc, sub_argv);
    if (strcmp(cmd, "bake") == 0) return prw_cmd_bake(sub_argc, sub_argv);
    if (strcmp(cmd, "cache") == 0) return prw_cmd_cache(sub_argc, sub_argv);
    if (strcmp(cmd, "btf-compress") == 0) return prw_cmd_btf_compress(sub_argc, sub_argv);
    if (strcmp(cmd, "btf-bench") == 0) return prw_cmd_btf_bench(sub_argc, sub_argv);
    if (strcmp(cmd, "help") == 0) {
        usage(stdout);
        return 0;
    }
    fprintf(stderr, "prw: error: unknown command '%s' (see prw --help)\n", cmd);
    return 2;
}
