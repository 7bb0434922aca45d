/* prw_cache — the content-addressed cache store: one directory per kind of entry, one file per key.
 * It knows paths, keys and atomic writes, never the entries' formats.
 *
 * Promises:
 *  - Layout: <cache>/<kind>/<key>.<ext>, <cache> = $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else
 *    $HOME/.cache/prw (prw_cache_root; prw_cache_dir in prw_core.h gives "<cache>/<kind>").  A kind
 *    is 1-32 of [a-z0-9_-], a key 1-64 lowercase hex digits, an extension 1-16 of [a-z0-9]; anything
 *    else is refused with a message, so a kind typed on the command line cannot name a path outside
 *    the cache.
 *  - Versioned keys (prw_cache_key_*): the caller writes a header — a tag naming the kind and its key
 *    version (e.g. "prw-lod-key"), then every parameter the entry depends on, in a fixed order — and
 *    the key is two 64-bit FNV-1a hashes of it, each continued over the input's bytes:
 *      a = H(input, H(header, 0)),  b = H(input, H(header, 0x9e3779b97f4a7c15)),  key = hex(a) hex(b)
 *    (H(data, seed) = prw_hash64, prw_core.h)
 *    (32 digits; with no input, a = H(header, 0) and b = H(header, ...)).  Whatever changes the
 *    stored result (an algorithm or format version) belongs in the header, so an old entry is never
 *    looked up again instead of being misread.  The header holds at most PRW_CACHE_KEY_HEADER_MAX
 *    bytes; more is a programming error (abort).
 *  - Writes are atomic (prw_write_file_atomic: temporary file + rename): a reader sees the old entry,
 *    the new one or none, never part of one.  prw_cache_store creates <cache>/<kind> when missing.
 *  - The store never validates an entry.  The caller reads an entry with its own strict reader; an
 *    entry that does not read back (truncated, bad checksum, another key inside) is REPORTED by the
 *    caller (a warning, not an error), rebuilt and stored over.  A cache that cannot be created or
 *    written only costs a rebuild: callers treat every cache failure as a warning.
 *  - prw_cache_clear removes the entries of one kind or of every kind: regular files named
 *    <key>.<ext> and leftovers of interrupted writes (<key>.<ext>.tmp-<pid>, <key>.<ext>.<pid>.tmp);
 *    nothing else (no other file, no directory, no symbolic link's target).
 * Nothing here prints.
 */
#ifndef PRW_CACHE_H
#define PRW_CACHE_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_CACHE_KEY_LEN 32 /* hex digits of a prw_cache_key_finish key */
#define PRW_CACHE_KEY_HEADER_MAX 1024

typedef struct prw_cache_key {
    uint8_t header[PRW_CACHE_KEY_HEADER_MAX];
    size_t n;
} prw_cache_key;

/* Starts a header with tag (its bytes and the terminating NUL). */
void prw_cache_key_begin(prw_cache_key *k, const char *tag);
void prw_cache_key_add(prw_cache_key *k, const void *data, size_t n);
void prw_cache_key_add_u64(prw_cache_key *k, uint64_t v); /* 8 bytes, little-endian */
void prw_cache_key_add_f64(prw_cache_key *k, double v);   /* the IEEE-754 bits as a u64 */
void prw_cache_key_add_str(prw_cache_key *k, const char *s); /* its bytes and the NUL */
/* key = 32 hex digits + NUL; input may be NULL when n is 0 (then the header alone is hashed). */
void prw_cache_key_finish(const prw_cache_key *k, const void *input, size_t n, char key[PRW_CACHE_KEY_LEN + 1]);

/* The cache root <cache> (not created). */
bool prw_cache_root(char *buf, size_t cap, prw_error *e);
/* true when kind / key / ext are valid names (see the layout above). */
bool prw_cache_kind_valid(const char *kind);
bool prw_cache_key_valid(const char *key);
/* "<cache>/<kind>/<key>.<ext>"; the kind's directory is created when create_dir is true. */
bool prw_cache_path(const char *kind, const char *key, const char *ext, bool create_dir, char *buf, size_t cap,
                    prw_error *e);
/* Writes data as the entry (atomically, directory created).  path (may be NULL) gets its path. */
bool prw_cache_store(const char *kind, const char *key, const char *ext, const void *data, size_t n, char *path,
                     size_t path_cap, prw_error *e);

typedef struct prw_cache_clear_report {
    char root[4096];   /* <cache> */
    uint32_t kinds;    /* kind directories visited */
    uint64_t files;    /* entries removed */
    uint64_t bytes;    /* their sizes */
} prw_cache_clear_report;
/* Removes the entries of kind (NULL: every kind directory under <cache>).  A missing cache is not
 * an error (nothing removed); a kind that is not a valid name, or has no directory, is, and the
 * message lists the kinds present.  A file that cannot be removed fails the call (after the
 * others were removed) with its path. */
bool prw_cache_clear(const char *kind, prw_cache_clear_report *r, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
