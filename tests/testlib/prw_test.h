/* prw_test — a minimal test harness: CHECK macros that count failures, PRW_TEST cases run by
 * prw_test_main(), and the closing line "N passed, N failed".  Each case prints its wall time. */
#ifndef PRW_TEST_H
#define PRW_TEST_H

#include <math.h>
#include <stdio.h>

#include "prw_core.h"

extern int prw_test_failures;

#define CHECK(cond)                                                                          \
    do {                                                                                     \
        if (!(cond)) {                                                                       \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);         \
            prw_test_failures++;                                                             \
        }                                                                                    \
    } while (0)

#define CHECK_MSG(cond, ...)                                                                 \
    do {                                                                                     \
        if (!(cond)) {                                                                       \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);         \
            fprintf(stderr, __VA_ARGS__);                                                    \
            fputc('\n', stderr);                                                             \
            prw_test_failures++;                                                             \
        }                                                                                    \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                \
    do {                                                                                     \
        double _a = (double)(a), _b = (double)(b), _t = (double)(tol);                       \
        if (!(fabs(_a - _b) <= _t)) {                                                        \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.17g, %s = %.17g, tol %.3g\n",  \
                    __FILE__, __LINE__, #a, _a, #b, _b, _t);                                 \
            prw_test_failures++;                                                             \
        }                                                                                    \
    } while (0)

/* Fails the case and returns from it when an error-returning call fails. */
#define CHECK_OK(call, err)                                                                  \
    do {                                                                                     \
        if (!(call)) {                                                                       \
            fprintf(stderr, "%s:%d: %s failed: %s\n", __FILE__, __LINE__, #call, (err)->msg); \
            prw_test_failures++;                                                             \
            return;                                                                          \
        }                                                                                    \
    } while (0)

typedef void (*prw_test_fn)(void);
typedef struct prw_test_case {
    const char *name;
    prw_test_fn fn;
} prw_test_case;

/* Runs the cases (all, or only those named in argv[1..]); returns the process exit code. */
int prw_test_main(int argc, char **argv, const prw_test_case *cases, int count);

/* PRW_ASAN is 1 where the including file is compiled with AddressSanitizer (gcc or clang): peak RSS
 * and address-space limits mean nothing there (shadow memory, quarantine). */
#if defined(__SANITIZE_ADDRESS__)
#define PRW_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PRW_ASAN 1
#endif
#endif

/* Light mode: true in sanitizer builds (PRW_SANITIZE, 3-10x slower), or when the environment sets
 * PRW_TEST_LIGHT=1 (PRW_TEST_LIGHT=0 forces the full workload).  Heavy cases then run fewer random
 * trials / samples over the same code paths and checks (prw_test_scale). */
bool prw_test_light(void);
/* n, or in light mode max(1, n / div). */
int prw_test_scale(int n, int div);

/* A scratch directory for this test binary (created on first use, under the build tree's cwd). */
const char *prw_test_tmpdir(void);
/* "<tmpdir>/<name>" in one of 8 rotating static buffers (valid until 8 more calls). */
char *prw_test_path(const char *name);
/* Writes n bytes to path; a failure counts as a failed CHECK. */
void prw_test_write_file(const char *path, const void *data, size_t n);

#endif
