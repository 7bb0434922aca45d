/* bake_entry.h — the content-addressed cache around a bake (internal to engine/bake: prw_gi_run,
 * prw_probe_run).  Both halves only report through a warning string: a cache that cannot be used never
 * fails the bake, it is built instead.
 *  - prw_bake_entry_read: the bytes of the entry (kind, key, ext) when it exists and can be read (caller
 *    frees); otherwise false, with path[0] = 0 and a warning when the cache is disabled, a warning when
 *    the entry exists but cannot be read, nothing when there is no entry.  path receives the entry's path.
 *  - prw_bake_entry_rejected: the warning for an entry that was read but not taken (decoder's reason).
 *  - prw_bake_entry_store: writes the encoded bake to the entry at path (from the read); true when
 *    written, else false with a warning. */
#ifndef PRW_BAKE_ENTRY_H
#define PRW_BAKE_ENTRY_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "prw_core.h"

bool prw_bake_entry_read(const char *kind, const char *key, const char *ext, char *path, size_t path_cap, char **data,
                         size_t *n, char *warning, size_t warning_cap);
void prw_bake_entry_rejected(const prw_error *why, char *warning, size_t warning_cap);
bool prw_bake_entry_store(const char *kind, const char *key, const char *ext, const uint8_t *data, size_t n, char *path,
                          size_t path_cap, char *warning, size_t warning_cap);
#endif
