/* gpu_device.c — instance, physical-device choice, logical device with the features prw relies on,
 * and the gpu's lifetime (create / destroy) plus its accessors. */
#define _GNU_SOURCE /* dl_iterate_phdr, RTLD_NODELETE (sanitizer builds only) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

#ifdef PRW_SANITIZE_BUILD
#include <dlfcn.h>
#include <link.h>

static int pin_module(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size, (void)data;
    if (info->dlpi_name && info->dlpi_name[0]) dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
    return 0;
}

/* LeakSanitizer names a leak's module when the process exits; by then the Vulkan loader has
 * dlclosed the driver and the layers, their frames read "<unknown module>" and the suppressions
 * (tests/sanitizer/lsan.supp, by library) cannot match.  Keep every module loaded so far mapped. */
static void pin_loaded_modules(void) { dl_iterate_phdr(pin_module, NULL); }
#else
static void pin_loaded_modules(void) {}
#endif

#define PRW_VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"

static bool env_flag(const char *name)
{
    const char *v = getenv(name);
    return v && *v && strcmp(v, "0") != 0;
}

static bool has_instance_layer(const char *name)
{
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, NULL);
    VkLayerProperties *layers = prw_calloc(n, sizeof *layers);
    vkEnumerateInstanceLayerProperties(&n, layers);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++) found = strcmp(layers[i].layerName, name) == 0;
    free(layers);
    return found;
}

static bool create_instance(prw_gpu *gpu, bool validation, const char **extra_ext, uint32_t extra_count,
                            VkInstance *out, prw_error *e)
{
    const char *exts[16];
    uint32_t ext_count = 0;
    for (uint32_t i = 0; i < extra_count && ext_count < 14; i++) exts[ext_count++] = extra_ext[i];
    const char *layers[1] = {PRW_VALIDATION_LAYER};
    VkDebugUtilsMessengerCreateInfoEXT msg_info;
    if (validation) {
        if (!has_instance_layer(PRW_VALIDATION_LAYER))
            return prw_fail(e, "gpu: validation requested (desc.validation or PRW_VALIDATION=1) but %s is not "
                               "installed (install the Vulkan validation layers or unset PRW_VALIDATION)",
                            PRW_VALIDATION_LAYER);
        exts[ext_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        prw_validation_messenger_info(gpu, &msg_info);
    }
    /* PRW_VALIDATION_SYNC=1 adds the layer's synchronization checks (hazards between commands):
     * slow, so off by default, but the way to prove barriers right. */
    VkValidationFeatureEnableEXT sync_enable = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = &sync_enable,
    };
    if (validation && env_flag("PRW_VALIDATION_SYNC")) {
        features.pNext = msg_info.pNext;
        msg_info.pNext = &features;
        exts[ext_count++] = VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME;
    }
    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "prw",
        .applicationVersion = 1,
        .pEngineName = "prw",
        .engineVersion = 1,
        .apiVersion = VK_API_VERSION_1_3,
    };
    VkInstanceCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        /* Chaining the messenger info also reports problems inside vkCreate/DestroyInstance. */
        .pNext = validation ? &msg_info : NULL,
        .pApplicationInfo = &app,
        .enabledLayerCount = validation ? 1 : 0,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = ext_count,
        .ppEnabledExtensionNames = exts,
    };
    VkResult r = vkCreateInstance(&ci, NULL, out);
    if (r == VK_SUCCESS) pin_loaded_modules();
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        return prw_fail(e, "gpu: no Vulkan 1.3 driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER)");
    return prw_vk_check(r, "gpu: vkCreateInstance", e);
}

static void driver_string(VkPhysicalDevice pd, char *buf, size_t cap)
{
    VkPhysicalDeviceDriverProperties drv = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &drv};
    vkGetPhysicalDeviceProperties2(pd, &p2);
    if (drv.driverInfo[0]) snprintf(buf, cap, "%s", drv.driverInfo);
    else snprintf(buf, cap, "%s", drv.driverName);
}

static void list_devices(VkInstance inst, char *buf, size_t cap)
{
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(inst, &n, NULL);
    VkPhysicalDevice *pds = prw_calloc(n, sizeof *pds);
    vkEnumeratePhysicalDevices(inst, &n, pds);
    size_t len = 0;
    if (cap) buf[0] = '\0';
    for (uint32_t i = 0; i < n && len < cap; i++) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pds[i], &p);
        char drv[512];
        driver_string(pds[i], drv, sizeof drv);
        int w = snprintf(buf + len, cap - len, "%s%u: %s (%s)", i ? "\n" : "", i, p.deviceName, drv);
        if (w < 0) break;
        len += (size_t)w;
    }
    if (n == 0 && cap) snprintf(buf, cap, "(none)");
    free(pds);
}

bool prw_gpu_list_devices(char *buf, size_t cap, prw_error *e)
{
    VkInstance inst;
    if (!create_instance(NULL, false, NULL, 0, &inst, e)) return false;
    list_devices(inst, buf, cap);
    vkDestroyInstance(inst, NULL);
    return true;
}

/* Same one-line list as prw_gpu_list_devices, for error messages: "0: a (x); 1: b (y)". */
static void device_list_inline(VkInstance inst, char *buf, size_t cap)
{
    list_devices(inst, buf, cap);
    for (char *p = buf; *p; p++)
        if (*p == '\n') *p = ';';
}

static bool pick_device(prw_gpu *gpu, const prw_gpu_desc *desc, prw_error *e)
{
    uint32_t n = 0;
    VkResult r = vkEnumeratePhysicalDevices(gpu->instance, &n, NULL);
    if (!prw_vk_check(r, "gpu: vkEnumeratePhysicalDevices", e)) return false;
    if (n == 0) return prw_fail(e, "gpu: no Vulkan devices found");
    VkPhysicalDevice *pds = prw_calloc(n, sizeof *pds);
    vkEnumeratePhysicalDevices(gpu->instance, &n, pds);

    /* Resolve the request: desc name > desc index > PRW_DEVICE (index or name) > first device. */
    const char *name = desc->device_name;
    long index = desc->device_index;
    const char *source = name ? "desc.device_name" : "desc.device_index";
    if (!name && index < 0) {
        const char *env = getenv("PRW_DEVICE");
        index = 0;
        source = "default";
        if (env && *env) {
            source = "PRW_DEVICE";
            char *end;
            long v = strtol(env, &end, 10);
            if (*end == '\0' && end != env) index = v;
            else name = env;
        }
    }
    long chosen = -1;
    if (name) {
        for (uint32_t i = 0; i < n && chosen < 0; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(pds[i], &p);
            if (strstr(p.deviceName, name)) chosen = i;
        }
    } else if (index >= 0 && index < (long)n) {
        chosen = index;
    }
    if (chosen < 0) {
        char list[2048];
        device_list_inline(gpu->instance, list, sizeof list);
        free(pds);
        if (name) return prw_fail(e, "gpu: no device name contains '%s' (%s); available: %s", name, source, list);
        return prw_fail(e, "gpu: device index %ld out of range (%s); available: %s", index, source, list);
    }
    gpu->physical = pds[chosen];
    free(pds);
    vkGetPhysicalDeviceProperties(gpu->physical, &gpu->props);
    vkGetPhysicalDeviceMemoryProperties(gpu->physical, &gpu->mem_props);
    driver_string(gpu->physical, gpu->driver_info, sizeof gpu->driver_info);
    if (gpu->props.apiVersion < VK_API_VERSION_1_3)
        return prw_fail(e, "gpu: device '%s' supports Vulkan %u.%u, prw needs 1.3", gpu->props.deviceName,
                        VK_API_VERSION_MAJOR(gpu->props.apiVersion), VK_API_VERSION_MINOR(gpu->props.apiVersion));
    return true;
}

static bool pick_queue(prw_gpu *gpu, prw_error *e)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(gpu->physical, &n, NULL);
    VkQueueFamilyProperties *q = prw_calloc(n, sizeof *q);
    vkGetPhysicalDeviceQueueFamilyProperties(gpu->physical, &n, q);
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++) {
        if ((q[i].queueFlags & need) == need) {
            gpu->queue_family = i;
            gpu->timestamp_valid_bits = q[i].timestampValidBits;
            found = true;
        }
    }
    free(q);
    if (!found) return prw_fail(e, "gpu: device '%s' has no graphics+compute queue", gpu->props.deviceName);
    return true;
}

static bool has_device_extension(VkPhysicalDevice pd, const char *name)
{
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, NULL, &n, NULL);
    VkExtensionProperties *ext = prw_calloc(n, sizeof *ext);
    vkEnumerateDeviceExtensionProperties(pd, NULL, &n, ext);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++) found = strcmp(ext[i].extensionName, name) == 0;
    free(ext);
    return found;
}

static bool create_device(prw_gpu *gpu, prw_error *e)
{
    VkPhysicalDeviceVulkan13Features f13 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceVulkan11Features f11 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
                                            .pNext = &f13};
    VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f11};
    vkGetPhysicalDeviceFeatures2(gpu->physical, &f2);
    /* maintenance4: glslang's vulkan1.3 target emits SPIR-V 1.6 with LocalSizeId, which needs it. */
    const char *missing = !f13.dynamicRendering ? "dynamicRendering"
                          : !f13.synchronization2 ? "synchronization2"
                          : !f13.maintenance4     ? "maintenance4"
                                                  : NULL;
    if (missing) return prw_fail(e, "gpu: device '%s' lacks the Vulkan 1.3 feature %s", gpu->props.deviceName, missing);

    /* Enable only what prw uses; optional ones are recorded in gpu->features for callers to check. */
    VkPhysicalDeviceVulkan13Features e13 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
                                            .dynamicRendering = VK_TRUE,
                                            .synchronization2 = VK_TRUE,
                                            .maintenance4 = VK_TRUE};
    VkPhysicalDeviceVulkan11Features e11 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
                                            .pNext = &e13,
                                            .multiview = f11.multiview,
                                            .shaderDrawParameters = f11.shaderDrawParameters};
    VkPhysicalDeviceFeatures2 e2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &e11};
    e2.features.fillModeNonSolid = f2.features.fillModeNonSolid;
    e2.features.independentBlend = f2.features.independentBlend;
    e2.features.shaderFloat64 = f2.features.shaderFloat64;
    e2.features.shaderClipDistance = f2.features.shaderClipDistance;
    e2.features.samplerAnisotropy = VK_FALSE; /* lavapipe has none; the samplers never use it */
    gpu->features.multiview = f11.multiview;
    gpu->features.shader_draw_parameters = f11.shaderDrawParameters;
    gpu->features.fill_mode_non_solid = f2.features.fillModeNonSolid;
    gpu->features.independent_blend = f2.features.independentBlend;
    gpu->features.shader_float64 = f2.features.shaderFloat64;
    gpu->features.clip_distance = f2.features.shaderClipDistance;

    const char *exts[1];
    uint32_t ext_count = 0;
    if (gpu->present) {
        if (!has_device_extension(gpu->physical, VK_KHR_SWAPCHAIN_EXTENSION_NAME))
            return prw_fail(e, "gpu: device '%s' cannot present (no %s)", gpu->props.deviceName,
                            VK_KHR_SWAPCHAIN_EXTENSION_NAME);
        exts[ext_count++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    }
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = gpu->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &prio,
    };
    VkDeviceCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &e2,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &qci,
        .enabledExtensionCount = ext_count,
        .ppEnabledExtensionNames = exts,
    };
    if (!prw_vk_check(vkCreateDevice(gpu->physical, &ci, NULL, &gpu->device), "gpu: vkCreateDevice", e))
        return false;
    vkGetDeviceQueue(gpu->device, gpu->queue_family, 0, &gpu->queue);
    return true;
}

static bool create_messenger(prw_gpu *gpu, prw_error *e)
{
    PFN_vkCreateDebugUtilsMessengerEXT create =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(gpu->instance, "vkCreateDebugUtilsMessengerEXT");
    if (!create) return prw_fail(e, "gpu: vkCreateDebugUtilsMessengerEXT not available");
    VkDebugUtilsMessengerCreateInfoEXT info;
    prw_validation_messenger_info(gpu, &info);
    return prw_vk_check(create(gpu->instance, &info, NULL, &gpu->messenger), "gpu: vkCreateDebugUtilsMessengerEXT",
                        e);
}

static double timeout_from_env(void)
{
    const char *v = getenv("PRW_GPU_TIMEOUT_S");
    if (v && *v) {
        char *end;
        double t = strtod(v, &end);
        if (*end == '\0' && t > 0) return t;
        prw_log(PRW_LOG_WARN, "ignoring PRW_GPU_TIMEOUT_S='%s' (not a positive number)", v);
    }
    return 120.0;
}

bool prw_gpu_create(const prw_gpu_desc *desc_in, prw_gpu **out, prw_error *e)
{
    *out = NULL;
    prw_gpu_desc defaults = {.device_index = -1};
    const prw_gpu_desc *desc = desc_in ? desc_in : &defaults;
    prw_gpu *gpu = prw_calloc(1, sizeof *gpu);
    gpu->validation = desc->validation || env_flag("PRW_VALIDATION");
    gpu->present = desc->present;
    gpu->timeout_s = timeout_from_env();
    prw_mem_init(gpu);

    bool ok = true;
    const char *suppress = desc->suppress_file ? desc->suppress_file : getenv("PRW_VALIDATION_SUPPRESS");
    if (gpu->validation && suppress && *suppress) ok = prw_validation_load_suppressions(gpu, suppress, e);

    const char **present_ext = NULL;
    uint32_t present_count = 0;
    if (ok && gpu->present) {
        present_ext = prw_swapchain_instance_extensions(&present_count, e);
        ok = present_ext != NULL;
    }
    ok = ok && create_instance(gpu, gpu->validation, present_ext, present_count, &gpu->instance, e);
    ok = ok && (!gpu->validation || create_messenger(gpu, e));
    ok = ok && pick_device(gpu, desc, e);
    ok = ok && pick_queue(gpu, e);
    ok = ok && create_device(gpu, e);
    ok = ok && prw_cmd_init(gpu, e);
    ok = ok && prw_samplers_init(gpu, e);
    ok = ok && prw_pipeline_cache_init(gpu, desc->cache_dir, e);
    if (!ok) {
        prw_gpu_destroy(gpu);
        return false;
    }
    *out = gpu;
    return true;
}

void prw_gpu_destroy(prw_gpu *gpu)
{
    if (!gpu) return;
    if (gpu->device) {
        /* vkDeviceWaitIdle has no timeout; a hung GPU at exit is preferable to freeing live memory. */
        vkDeviceWaitIdle(gpu->device);
        prw_pipe_memo_shutdown(gpu);
        prw_pipeline_cache_shutdown(gpu);
        prw_desc_shutdown(gpu);
        prw_samplers_shutdown(gpu);
        prw_cmd_shutdown(gpu);
        prw_mem_shutdown(gpu);
        vkDestroyDevice(gpu->device, NULL);
    }
    if (gpu->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            gpu->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (destroy) destroy(gpu->instance, gpu->messenger, NULL);
    }
    if (gpu->instance) vkDestroyInstance(gpu->instance, NULL);
    prw_validation_free(gpu);
    free(gpu->cache_dir);
    free(gpu->cache_path);
    free(gpu);
}

const char *prw_gpu_device_name(const prw_gpu *gpu) { return gpu->props.deviceName; }
const char *prw_gpu_driver_info(const prw_gpu *gpu) { return gpu->driver_info; }
const prw_gpu_features *prw_gpu_features_enabled(const prw_gpu *gpu) { return &gpu->features; }
VkInstance prw_gpu_instance(const prw_gpu *gpu) { return gpu->instance; }
VkPhysicalDevice prw_gpu_physical(const prw_gpu *gpu) { return gpu->physical; }
VkDevice prw_gpu_device(const prw_gpu *gpu) { return gpu->device; }
VkQueue prw_gpu_queue(const prw_gpu *gpu) { return gpu->queue; }
uint32_t prw_gpu_queue_family(const prw_gpu *gpu) { return gpu->queue_family; }
VkPipelineCache prw_gpu_pipeline_cache(const prw_gpu *gpu) { return gpu->pipeline_cache; }
const VkPhysicalDeviceProperties *prw_gpu_properties(const prw_gpu *gpu) { return &gpu->props; }
