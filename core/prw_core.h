/* prw_core — the base layer every other folder may include.
 *
 * Promises:
 *  - prw_error: the one way errors travel.  A function that can fail returns bool (true = ok)
 *    and, on failure, fills a caller-owned prw_error with one line: "<file>:<place>: <reason>".
 *    Nothing below app/ prints errors itself.
 *  - prw_log: leveled logging to stderr (app/ and progress output use it), level set once.
 *  - prw_threads: one thread budget (--threads) that feeds every pool: LP_NUM_THREADS for
 *    lavapipe, TBB/Embree and OpenMP read it from here.
 *  - small helpers: checked allocation, whole-file reads, atomic file writes.
 */
#ifndef PRW_CORE_H
#define PRW_CORE_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_ERROR_MAX 1024

typedef struct prw_error {
    char msg[PRW_ERROR_MAX];
} prw_error;

/* Sets e->msg (if e is not NULL) and returns false, so callers can write `return prw_fail(e, ...)`. */
bool prw_fail(prw_error *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prefixes an existing message: "<prefix>: <old message>". Returns false. */
bool prw_fail_wrap(prw_error *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

typedef enum prw_log_level {
    PRW_LOG_ERROR = 0,
    PRW_LOG_WARN = 1,
    PRW_LOG_INFO = 2,
    PRW_LOG_DEBUG = 3,
} prw_log_level;

void prw_log_set_level(prw_log_level level);
prw_log_level prw_log_get_level(void);
/* Parses "error|warn|info|debug"; returns false on anything else. */
bool prw_log_parse_level(const char *s, prw_log_level *out);
void prw_log(prw_log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Thread budget. n <= 0 means all cores. Must be called before the Vulkan instance is made,
 * because lavapipe reads LP_NUM_THREADS once at device creation. */
void prw_threads_set(int n);
int prw_threads_get(void);

/* Allocation that aborts with a message on exhaustion of host memory (an OOM of the process
 * is not a recoverable input error). */
void *prw_malloc(size_t n);
void *prw_calloc(size_t count, size_t size);
void *prw_realloc(void *p, size_t n);
char *prw_strdup(const char *s);

/* Reads a whole file. *data is NUL-terminated (not counted in *size). Caller frees. */
bool prw_read_file(const char *path, char **data, size_t *size, prw_error *e);
/* Writes via "<path>.tmp-<pid>" + rename, so a failure never leaves a partial file at path. */
bool prw_write_file_atomic(const char *path, const void *data, size_t size, prw_error *e);
/* Creates dir and its missing parents (mode 0755); existing ones are fine. */
bool prw_mkdirs(const char *dir, prw_error *e);
/* The project's cache directory for one kind of entry: $PRW_CACHE_DIR/<sub>, else
 * $XDG_CACHE_HOME/prw/<sub>, else $HOME/.cache/prw/<sub>; created when create is true.  `who`
 * prefixes the errors (e.g. "LOD cache").  Part of the cache store (core/cache.c, prw_cache.h:
 * keys, entry paths, atomic stores, clearing). */
bool prw_cache_dir(const char *sub, const char *who, bool create, char *buf, size_t cap, prw_error *e);

/* Monotonic clock in seconds. */
double prw_now(void);

/* 64-bit FNV-1a (prime 1099511628211) from the offset basis 1469598103934665603 XOR seed — one digit
 * short of the published basis 14695981039346656037; kept, since every cache key and .lod checksum
 * depends on it.  For cache keys and content hashes. */
uint64_t prw_hash64(const void *data, size_t n, uint64_t seed);

#define PRW_ARRAY_LEN(a) (sizeof(a) / sizeof((a)[0]))
#define PRW_MIN(a, b) ((a) < (b) ? (a) : (b))
#define PRW_MAX(a, b) ((a) > (b) ? (a) : (b))

#ifdef __cplusplus
}
#endif
#endif
