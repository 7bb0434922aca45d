/* The content-addressed cache around a bake: bake_entry.h. */
#include "bake_entry.h"

#include <stdio.h>
#include <sys/stat.h>

#include "prw_cache.h"
#include "prw_core.h"

bool prw_bake_entry_read(const char *kind, const char *key, const char *ext, char *path, size_t path_cap, char **data,
                         size_t *n, char *warning, size_t warning_cap)
{
    prw_error ce = {{0}};
    *data = NULL;
    *n = 0;
    if (!prw_cache_path(kind, key, ext, false, path, path_cap, &ce)) {
        snprintf(warning, warning_cap, "cache disabled: %.900s", ce.msg);
        path[0] = 0;
        return false;
    }
    struct stat st;
    if (stat(path, &st) != 0) return false; /* no entry: nothing to say */
    if (prw_read_file(path, data, n, &ce)) return true; /* on failure *data stays NULL */
    prw_bake_entry_rejected(&ce, warning, warning_cap);
    return false;
}

void prw_bake_entry_rejected(const prw_error *why, char *warning, size_t warning_cap)
{
    snprintf(warning, warning_cap, "cache entry unreadable, rebuilt: %.900s", why->msg);
}

bool prw_bake_entry_store(const char *kind, const char *key, const char *ext, const uint8_t *data, size_t n, char *path,
                          size_t path_cap, char *warning, size_t warning_cap)
{
    prw_error we = {{0}};
    if (prw_cache_store(kind, key, ext, data, n, path, path_cap, &we)) return true;
    snprintf(warning, warning_cap, "cache not written: %.900s", we.msg);
    return false;
}
