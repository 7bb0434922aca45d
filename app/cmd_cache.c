/* prw cache — the content-addressed cache store (core/prw_cache.h): `prw cache clear [KIND]`. */
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "prw_cache.h"

static void help(void)
{
    char root[4096];
    prw_error e;
    bool have = prw_cache_root(root, sizeof root, &e);
    printf("usage: prw cache clear [KIND]\n"
           "  Removes cached entries: of one KIND (a subdirectory of the cache, e.g. lod = LOD hierarchies\n"
           "  from prw bake and scene loading, refs = bench references, views = the views-backend choice),\n"
           "  or of every kind.  Only entry files (<key>.<ext>, and leftovers of interrupted writes) are\n"
           "  removed; anything else in the directory is left alone.  Every entry is rebuilt on demand.\n"
           "  Cache: $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else ~/.cache/prw — here: %s\n",
           have ? root : e.msg);
}

int prw_cmd_cache(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    if (!prw_args_init(&a, argc, argv, &e)) {
        fprintf(stderr, "prw cache: error: %s\n", e.msg);
        return 2;
    }
    if (prw_args_flag(&a, "help")) {
        help();
        prw_args_free(&a);
        return 0;
    }
    if (!prw_args_finish(&a, &e)) {
        fprintf(stderr, "prw cache: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    if (a.positional_count < 1 || strcmp(a.positional[0], "clear") != 0 || a.positional_count > 2) {
        fprintf(stderr, "prw cache: error: expected 'clear [KIND]' (see prw cache --help)\n");
        prw_args_free(&a);
        return 2;
    }
    const char *kind = a.positional_count == 2 ? a.positional[1] : NULL;
    prw_cache_clear_report r;
    bool ok = prw_cache_clear(kind, &r, &e);
    if (ok || r.files)
        printf("removed %llu entries (%.1f MB) from %s%s%s (%u kind%s)\n", (unsigned long long)r.files,
               (double)r.bytes / 1e6, r.root, kind ? "/" : "", kind ? kind : "", r.kinds, r.kinds == 1 ? "" : "s");
    prw_args_free(&a);
    if (!ok) {
        fprintf(stderr, "prw cache: error: %s\n", e.msg);
        return 1;
    }
    return 0;
}
