/* iges_writer — a small IGES 5.3 writer for tests: entities are added as parameter strings
 * (without the leading type number and record delimiter), and igw_finish lays out the S, G, D, P
 * and T sections in fixed 80-column records. */
#ifndef IGES_WRITER_H
#define IGES_WRITER_H

#include <stddef.h>

typedef struct igw_entity {
    int type, form, xform, colour, subord;
    char *params;
} igw_entity;

typedef struct igw {
    igw_entity *ents;
    int count;
    int unit_flag;       /* default 2 (mm) */
    const char *unit;    /* default "MM" */
    double scale;        /* model space scale, default 1 */
} igw;

void igw_init(igw *w);
void igw_free(igw *w);
/* DE number the next added entity gets. */
int igw_next(const igw *w);
/* Adds an entity; returns its DE number.  subord: 0 independent, 1 physically dependent. */
int igw_add(igw *w, int type, int form, int subord, int xform, int colour, const char *fmt, ...)
    __attribute__((format(printf, 7, 8)));
/* The whole file as a NUL-terminated string (caller frees). */
char *igw_finish(const igw *w, size_t *len);

#endif
