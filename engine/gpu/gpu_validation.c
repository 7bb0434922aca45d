/* gpu_validation.c — the debug-utils messenger that counts validation messages, and the
 * suppression list of known false positives. */
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

/* Survives prw_gpu_destroy: leak reports arrive during vkDestroyDevice, when nobody can ask the gpu. */
static atomic_uint g_validation_total;

uint32_t prw_gpu_validation_total(void) { return atomic_load(&g_validation_total); }

uint32_t prw_gpu_validation_count(const prw_gpu *gpu)
{
    return gpu ? atomic_load(&((prw_gpu *)gpu)->validation_count) : 0;
}

static bool is_suppressed(const prw_gpu *gpu, const char *id)
{
    if (!id) return false;
    for (uint32_t i = 0; i < gpu->suppress_count; i++)
        if (strcmp(gpu->suppress[i], id) == 0) return true;
    return false;
}

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT types,
                                                 const VkDebugUtilsMessengerCallbackDataEXT *data, void *user)
{
    prw_gpu *gpu = user;
    /* The messenger is created with exactly the severities and types we count, but the layer may
     * still deliver e.g. GENERAL messages through the instance-creation messenger: filter again. */
    bool counted_sev = severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT);
    bool counted_type = types & (VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT);
    if (!counted_sev || !counted_type) return VK_FALSE;
    if (is_suppressed(gpu, data->pMessageIdName)) return VK_FALSE;
    atomic_fetch_add(&gpu->validation_count, 1);
    atomic_fetch_add(&g_validation_total, 1);
    prw_log(PRW_LOG_ERROR, "vulkan %s [%s]: %s",
            severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
            data->pMessageIdName ? data->pMessageIdName : "?", data->pMessage ? data->pMessage : "");
    return VK_FALSE; /* never abort the call: we want to see what the driver does */
}

void prw_validation_messenger_info(prw_gpu *gpu, VkDebugUtilsMessengerCreateInfoEXT *info)
{
    memset(info, 0, sizeof *info);
    info->sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
    info->messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info->messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info->pfnUserCallback = on_message;
    info->pUserData = gpu;
}

/* Lines: "<VUID-or-messageIdName> <reason>"; '#' starts a comment line; blank lines ignored.
 * An entry without a reason is rejected: every suppression must say why. */
bool prw_validation_load_suppressions(prw_gpu *gpu, const char *path, prw_error *e)
{
    char *text;
    size_t size;
    if (!prw_read_file(path, &text, &size, e)) return prw_fail_wrap(e, "gpu: validation suppressions");
    int line_no = 0;
    for (char *line = text; line && *line;) {
        char *next = strchr(line, '\n');
        if (next) *next++ = '\0';
        line_no++;
        while (*line == ' ' || *line == '\t' || *line == '\r') line++;
        if (*line && *line != '#') {
            size_t id_len = strcspn(line, " \t\r");
            const char *reason = line + id_len;
            while (*reason == ' ' || *reason == '\t') reason++;
            if (*reason == '\0' || *reason == '\r') {
                bool r = prw_fail(e, "gpu: %s:%d: suppression '%.*s' has no reason", path, line_no, (int)id_len,
                                  line);
                free(text);
                return r;
            }
            line[id_len] = '\0';
            gpu->suppress = prw_realloc(gpu->suppress, (gpu->suppress_count + 1) * sizeof *gpu->suppress);
            gpu->suppress[gpu->suppress_count++] = prw_strdup(line);
        }
        line = next;
    }
    free(text);
    return true;
}

void prw_validation_free(prw_gpu *gpu)
{
    for (uint32_t i = 0; i < gpu->suppress_count; i++) free(gpu->suppress[i]);
    free(gpu->suppress);
    gpu->suppress = NULL;
    gpu->suppress_count = 0;
}
