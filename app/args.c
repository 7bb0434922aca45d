#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"

bool prw_args_init(prw_args *a, int argc, char **argv, prw_error *e)
{
    memset(a, 0, sizeof *a);
    a->argc = argc;
    a->argv = argv;
    a->used = prw_calloc((size_t)argc + 1, sizeof(bool));
    (void)e; /* values are claimed lazily by prw_args_value */
    return true;
}

void prw_args_free(prw_args *a) { free(a->used); }

static bool name_matches(const char *arg, const char *name, const char **inline_value)
{
    size_t n = strlen(name);
    if (strncmp(arg, "--", 2) != 0 || strncmp(arg + 2, name, n) != 0) return false;
    if (arg[2 + n] == '\0') {
        *inline_value = NULL;
        return true;
    }
    if (arg[2 + n] == '=') {
        *inline_value = arg + 3 + n;
        return true;
    }
    return false;
}

const char *prw_args_value(prw_args *a, const char *name, prw_error *e, bool *bad)
{
    const char *found = NULL;
    for (int i = 0; i < a->argc; i++) {
        const char *iv;
        if (a->used[i] || !name_matches(a->argv[i], name, &iv)) continue;
        a->used[i] = true;
        if (iv) {
            found = iv;
            continue;
        }
        if (i + 1 >= a->argc) {
            *bad = true;
            prw_fail(e, "option --%s needs a value", name);
            return NULL;
        }
        a->used[i + 1] = true;
        found = a->argv[++i];
    }
    return found;
}

bool prw_args_flag(prw_args *a, const char *name)
{
    bool found = false;
    for (int i = 0; i < a->argc; i++) {
        const char *iv;
        if (!a->used[i] && name_matches(a->argv[i], name, &iv) && !iv) {
            a->used[i] = true;
            found = true;
        }
    }
    return found;
}

bool prw_args_finish(prw_args *a, prw_error *e)
{
    a->positional_count = 0;
    for (int i = 0; i < a->argc; i++) {
        if (a->used[i]) continue;
        if (strncmp(a->argv[i], "--", 2) == 0 || (a->argv[i][0] == '-' && a->argv[i][1] != '\0'))
            return prw_fail(e, "unknown option '%s' (see --help)", a->argv[i]);
        if (a->positional_count >= (int)PRW_ARRAY_LEN(a->positional)) return prw_fail(e, "too many arguments");
        a->positional[a->positional_count++] = a->argv[i];
    }
    return true;
}

bool prw_parse_size(const char *s, uint32_t *w, uint32_t *h, prw_error *e)
{
    unsigned long a, b;
    char x, tail;
    if (sscanf(s, "%lu%c%lu%c", &a, &x, &b, &tail) != 3 || (x != 'x' && x != 'X') || a == 0 || b == 0 ||
        a > 16384 || b > 16384)
        return prw_fail(e, "--size '%s': expected WxH with 1..16384 pixels each", s);
    *w = (uint32_t)a;
    *h = (uint32_t)b;
    return true;
}

bool prw_parse_int(const char *s, const char *what, long lo, long hi, long *out, prw_error *e)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end != '\0' || v < lo || v > hi)
        return prw_fail(e, "%s '%s': expected an integer in %ld..%ld", what, s, lo, hi);
    *out = v;
    return true;
}

bool prw_parse_double(const char *s, const char *what, double lo, double hi, double *out, prw_error *e)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end != '\0' || !isfinite(v) || v < lo || v > hi)
        return prw_fail(e, "%s '%s': expected a number in %g..%g", what, s, lo, hi);
    *out = v;
    return true;
}
