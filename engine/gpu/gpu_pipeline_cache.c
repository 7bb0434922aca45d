/* gpu_pipeline_cache.c — the VkPipelineCache persisted as
 * <cache_dir>/pipeline-<vendor>-<device>-<driverVersion>.bin, so shader compilation (slow on
 * lavapipe: LLVM) is paid once per driver.  Loaded at create, saved atomically at destroy. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gpu_internal.h"

/* NULL when no directory can be derived (no HOME): the cache then lives in memory only. */
static char *resolve_dir(const char *desc_dir)
{
    if (desc_dir && *desc_dir) return prw_strdup(desc_dir);
    const char *v = getenv("PRW_CACHE_DIR");
    if (v && *v) return prw_strdup(v);
    char buf[4096];
    v = getenv("XDG_CACHE_HOME");
    if (v && *v) {
        snprintf(buf, sizeof buf, "%s/prw", v);
        return prw_strdup(buf);
    }
    v = getenv("HOME");
    if (v && *v) {
        snprintf(buf, sizeof buf, "%s/.cache/prw", v);
        return prw_strdup(buf);
    }
    return NULL;
}

/* mkdir -p */
static bool make_dirs(const char *path, prw_error *e)
{
    char *p = prw_strdup(path);
    bool ok = true;
    for (char *s = p + 1; ok; s++) {
        bool end = *s == '\0';
        if (*s == '/' || end) {
            *s = '\0';
            if (mkdir(p, 0755) != 0 && errno != EEXIST) ok = prw_fail(e, "%s: cannot create: %s", p, strerror(errno));
            if (end) break;
            *s = '/';
        }
    }
    free(p);
    return ok;
}

/* The header the spec puts in front of every cache blob (VkPipelineCacheHeaderVersionOne). */
static bool header_matches(const prw_gpu *gpu, const unsigned char *data, size_t size)
{
    if (size < 32) return false;
    uint32_t header_size, version, vendor, device;
    memcpy(&header_size, data, 4);
    memcpy(&version, data + 4, 4);
    memcpy(&vendor, data + 8, 4);
    memcpy(&device, data + 12, 4);
    return header_size >= 32 && header_size <= size && version == VK_PIPELINE_CACHE_HEADER_VERSION_ONE &&
           vendor == gpu->props.vendorID && device == gpu->props.deviceID &&
           memcmp(data + 16, gpu->props.pipelineCacheUUID, VK_UUID_SIZE) == 0;
}

bool prw_pipeline_cache_init(prw_gpu *gpu, const char *cache_dir, prw_error *e)
{
    gpu->cache_dir = resolve_dir(cache_dir);
    char *data = NULL;
    size_t size = 0;
    if (gpu->cache_dir) {
        size_t len = strlen(gpu->cache_dir) + 96;
        gpu->cache_path = prw_malloc(len);
        snprintf(gpu->cache_path, len, "%s/pipeline-%04x-%04x-%08x.bin", gpu->cache_dir, gpu->props.vendorID,
                 gpu->props.deviceID, gpu->props.driverVersion);
        struct stat st;
        if (stat(gpu->cache_path, &st) == 0) {
            prw_error ignored;
            if (!prw_read_file(gpu->cache_path, &data, &size, &ignored)) {
                prw_log(PRW_LOG_WARN, "pipeline cache not loaded: %s", ignored.msg);
            } else if (!header_matches(gpu, (unsigned char *)data, size)) {
                /* Another driver build or a damaged file: start empty, overwrite at exit. */
                prw_log(PRW_LOG_WARN, "pipeline cache %s does not match this device/driver; ignoring it",
                        gpu->cache_path);
                free(data);
                data = NULL;
                size = 0;
            }
        }
    }
    VkPipelineCacheCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO,
        .initialDataSize = size,
        .pInitialData = data,
    };
    VkResult r = vkCreatePipelineCache(gpu->device, &ci, NULL, &gpu->pipeline_cache);
    if (r != VK_SUCCESS && data) { /* the driver rejected the blob after all: start empty */
        ci.initialDataSize = 0;
        ci.pInitialData = NULL;
        r = vkCreatePipelineCache(gpu->device, &ci, NULL, &gpu->pipeline_cache);
    }
    free(data);
    return prw_vk_check(r, "gpu: vkCreatePipelineCache", e);
}

void prw_pipeline_cache_shutdown(prw_gpu *gpu)
{
    if (!gpu->pipeline_cache) return;
    if (gpu->cache_path) {
        size_t size = 0;
        void *data = NULL;
        prw_error err;
        bool ok = vkGetPipelineCacheData(gpu->device, gpu->pipeline_cache, &size, NULL) == VK_SUCCESS;
        if (ok && size) {
            data = prw_malloc(size);
            ok = vkGetPipelineCacheData(gpu->device, gpu->pipeline_cache, &size, data) == VK_SUCCESS;
        }
        /* Saving is an optimisation: failures are warnings, never errors. */
        if (ok && size) {
            if (!make_dirs(gpu->cache_dir, &err) || !prw_write_file_atomic(gpu->cache_path, data, size, &err))
                prw_log(PRW_LOG_WARN, "pipeline cache not saved: %s", err.msg);
        }
        free(data);
    }
    vkDestroyPipelineCache(gpu->device, gpu->pipeline_cache, NULL);
    gpu->pipeline_cache = VK_NULL_HANDLE;
}
