/* prw_core — the base layer every other folder may include.
 *
 * Promises:
 *  - prw_error: the one way errors travel.  A function that can fail returns bool (true = ok)
 *    and, on failure, fills a caller-owned prw_error with one line: "<file>:<place>: <reason>".
 *    Nothing below app/ prints errors itself.
 *  - prw_log: leveled logging to stderr (app/ and progress output use it), level set once.
 *  - prw_threads: one thread budget (--threads) that feeds every pool: LP_NUM_THREADS for
 *    lavapipe, TBB/Embree and OpenMP read it from here.
 *  - prw_mem: one memory budget (--max-memory, else the available memory) that every size coming
 *    from an input or an option is checked against before it is allocated (prw_mem.c).
 *  - small helpers: checked allocation, whole-file reads (bounded ones for untrusted inputs),
 *    atomic file writes, output writability checks made before any work.
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
/* prw_read_file after a size check on the open file, before anything is allocated: fails with
 * "<path>: file of N bytes exceeds the limit of M bytes for <what>" when it is larger than max_bytes
 * (0 = no fixed limit), or when size x expansion (the bytes the caller builds per byte read, e.g. a
 * JSON tree) exceeds the memory budget (prw_mem_check). */
bool prw_read_file_bounded(const char *path, uint64_t max_bytes, uint64_t expansion, const char *what, char **data,
                           size_t *size, prw_error *e);
/* Worst-case memory of a parsed JSON tree per byte of text (cJSON: an 80-byte node, allocator
 * overhead included, for every 2 bytes such as "0,"; keys and strings are copied): the expansion
 * the JSON readers pass to prw_read_file_bounded. */
#define PRW_JSON_MEMORY_PER_BYTE 48u

/* Whether an output file can be written, checked before any work: its directory exists (or, with
 * create_parents, the nearest existing ancestor is a directory) and accepts a new file, and path
 * is not a directory.  Probes by creating and removing "<path>.tmp-<pid>" (the name the atomic
 * writers use), so nothing is left behind.  Errors: "<path>: cannot write: <reason>". */
bool prw_check_writable(const char *path, bool create_parents, prw_error *e);
/* The same for an output directory: an existing one is probed with "<dir>/.prw-probe-<pid>"; a
 * missing one (with create: the command makes it and its parents later) needs a nearest existing
 * ancestor that takes new entries.  Nothing is created. */
bool prw_check_writable_dir(const char *dir, bool create, prw_error *e);
/* Creates dir and its missing parents (mode 0755); existing ones are fine. */
bool prw_mkdirs(const char *dir, prw_error *e);
/* The project's cache directory for one kind of entry: $PRW_CACHE_DIR/<sub>, else
 * $XDG_CACHE_HOME/prw/<sub>, else $HOME/.cache/prw/<sub>; created when create is true.  `who`
 * prefixes the errors (e.g. "LOD cache").  Part of the cache store (core/cache.c, prw_cache.h:
 * keys, entry paths, atomic stores, clearing). */
bool prw_cache_dir(const char *sub, const char *who, bool create, char *buf, size_t cap, prw_error *e);

/* Memory budget: how many bytes one decision to allocate may count on.  Set by the global option
 * --max-memory (prw_mem_set_budget); otherwise the memory available now: MemAvailable from
 * /proc/meminfo (sysconf(_SC_AVPHYS_PAGES) when that cannot be read), lowered to the cgroup v2
 * limit memory.max - memory.current when the process runs under one.  Readers and commands check
 * sizes against it before allocating, so a too-large input is refused with a message instead of
 * an out-of-memory abort. */
void prw_mem_set_budget(uint64_t bytes); /* 0: back to the available memory */
uint64_t prw_mem_budget(void);
/* "where the budget comes from": "--max-memory" or "available memory". */
const char *prw_mem_budget_source(void);
/* Parses a byte count: an integer or decimal with an optional K, M, G, T suffix (powers of 1024,
 * optionally followed by "iB" or "B"), e.g. "512M", "1.5G", "4GiB", "1048576". */
bool prw_mem_parse(const char *s, uint64_t *out, prw_error *e);
/* "1.50 GiB", "640 KiB", "12 B". */
void prw_mem_format(uint64_t bytes, char *buf, size_t cap);
/* true when bytes fit the budget; else "<who>: <what> needs <X>, more than the memory budget of <Y>
 * (<source>; see --max-memory)".  bytes = UINT64_MAX stands for "does not fit in 64 bits". */
bool prw_mem_check(uint64_t bytes, const char *who, const char *what, prw_error *e);
/* a * b, or UINT64_MAX on overflow (so the result fails any budget check). */
uint64_t prw_mul_sat(uint64_t a, uint64_t b);
uint64_t prw_add_sat(uint64_t a, uint64_t b);

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
