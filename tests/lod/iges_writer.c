/* Test-only IGES writer (see iges_writer.h). */
#include "iges_writer.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void igw_init(igw *w)
{
    memset(w, 0, sizeof *w);
    w->unit_flag = 2;
    w->unit = "MM";
    w->scale = 1;
}

void igw_free(igw *w)
{
    for (int i = 0; i < w->count; i++) free(w->ents[i].params);
    free(w->ents);
    memset(w, 0, sizeof *w);
}

int igw_next(const igw *w) { return 2 * w->count + 1; }

int igw_add(igw *w, int type, int form, int subord, int xform, int colour, const char *fmt, ...)
{
    char buf[65536];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    w->ents = realloc(w->ents, sizeof *w->ents * (size_t)(w->count + 1));
    igw_entity *e = &w->ents[w->count++];
    e->type = type;
    e->form = form;
    e->subord = subord;
    e->xform = xform;
    e->colour = colour;
    size_t n = strlen(buf) + 16;
    e->params = malloc(n);
    snprintf(e->params, n, "%d,%s;", type, buf);
    return 2 * (w->count - 1) + 1;
}

typedef struct out {
    char *p;
    size_t n, cap;
} out;

static void put(out *o, const char *s, size_t n)
{
    if (o->n + n + 1 > o->cap) {
        o->cap = (o->n + n + 1) * 2;
        o->p = realloc(o->p, o->cap);
    }
    memcpy(o->p + o->n, s, n);
    o->n += n;
    o->p[o->n] = 0;
}

static void record(out *o, const char *data, int width, char sec, int seq)
{
    char line[96];
    snprintf(line, sizeof line, "%-*.*s", width, width, data);
    char tail[16];
    snprintf(tail, sizeof tail, "%c%7d\n", sec, seq);
    put(o, line, (size_t)width);
    put(o, tail, strlen(tail));
}

/* Splits text into chunks of at most `width` columns, preferring to break after a delimiter. */
static int chunks(const char *t, int width, char sec, int seq0, out *o, int de)
{
    int n = (int)strlen(t), pos = 0, seq = seq0;
    while (pos < n) {
        int len = n - pos < width ? n - pos : width;
        if (pos + len < n) {
            int k = len;
            while (k > 0 && t[pos + k - 1] != ',' && t[pos + k - 1] != ';') k--;
            if (k > 8) len = k;
        }
        char buf[96];
        if (de) {
            char d[80];
            snprintf(d, sizeof d, "%.*s", len, t + pos);
            snprintf(buf, sizeof buf, "%-64s %7d", d, de);
            record(o, buf, 72, sec, seq++);
        } else {
            snprintf(buf, sizeof buf, "%.*s", len, t + pos);
            record(o, buf, 72, sec, seq++);
        }
        pos += len;
    }
    return seq - seq0;
}

char *igw_finish(const igw *w, size_t *len)
{
    out o = {0};
    record(&o, "prw test model", 72, 'S', 1);
    char g[1024];
    snprintf(g, sizeof g,
             "1H,,1H;,7Hprwtest,8Htest.igs,3Hprw,3H0.1,32,38,6,308,15,7Hprwtest,%.17g,%d,%zuH%s,1,0.1,"
             "15H20240101.120000,1.0E-8,1000.0,3Hprw,3Hprw,11,0,15H20240101.120000;",
             w->scale, w->unit_flag, strlen(w->unit), w->unit);
    int gl = chunks(g, 72, 'G', 1, &o, 0);
    /* parameter section first (into a separate buffer) to know the pointers */
    out p = {0};
    int *pstart = calloc((size_t)w->count + 1, sizeof(int)), *pcount = calloc((size_t)w->count + 1, sizeof(int));
    int pseq = 1;
    for (int i = 0; i < w->count; i++) {
        pstart[i] = pseq;
        pcount[i] = chunks(w->ents[i].params, 64, 'P', pseq, &p, 2 * i + 1);
        pseq += pcount[i];
    }
    for (int i = 0; i < w->count; i++) {
        const igw_entity *e = &w->ents[i];
        char l1[96], l2[96];
        snprintf(l1, sizeof l1, "%8d%8d%8d%8d%8d%8d%8d%8d%02d%02d%02d%02d", e->type, pstart[i], 0, 1, 0, 0, e->xform, 0, 0,
                 e->subord, 0, 0);
        snprintf(l2, sizeof l2, "%8d%8d%8d%8d%8d%8s%8s%8s%8d", e->type, 0, e->colour, pcount[i], e->form, "", "", "", 0);
        record(&o, l1, 72, 'D', 2 * i + 1);
        record(&o, l2, 72, 'D', 2 * i + 2);
    }
    put(&o, p.p ? p.p : "", p.n);
    char t[80];
    snprintf(t, sizeof t, "S%07dG%07dD%07dP%07d", 1, gl, 2 * w->count, pseq - 1);
    record(&o, t, 72, 'T', 1);
    free(p.p);
    free(pstart);
    free(pcount);
    if (len) *len = o.n;
    return o.p;
}
