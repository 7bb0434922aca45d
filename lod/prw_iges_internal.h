/* prw_iges_internal — what the IGES record layer (prw_iges_records.c) hands to the entity layer
 * (prw_iges_entities.c) and the driver (prw_iges.c).  Not a public header. */
#ifndef PRW_IGES_INTERNAL_H
#define PRW_IGES_INTERNAL_H

#include "prw_iges.h"
#include "prw_nurbs.h"

typedef enum iges_tok_kind { TOK_EMPTY = 0, TOK_NUM, TOK_STR, TOK_BAD } iges_tok_kind;

typedef struct iges_tok {
    iges_tok_kind kind;
    double num;
    int line;        /* file line where the field starts */
    int off, len;    /* the field's text (string contents for TOK_STR) in iges_file.ptext */
} iges_tok;

typedef struct iges_de {
    int seq;  /* sequence number of the first D record */
    int line; /* file line of the first D record */
    int type, form;
    int pd_ptr, pd_count;
    int xform;   /* DE pointer of a 124, 0 = none */
    int colour;  /* < 0: pointer to a 314; 0..8: palette */
    int subord;  /* 0 independent, 1 physically, 2 logically, 3 both dependent */
    int tok0, ntok; /* parameters (after the type) in iges_file.tok */
    int last_line;  /* last P record of this entity */
    bool used_by_144;
} iges_de;

typedef struct iges_file {
    const char *name;
    char pdelim, rdelim;
    int unit_flag;
    double unit_m, model_scale;
    iges_de *de;
    int nde;
    iges_tok *tok;
    int ntok, tokcap;
    char *ptext; /* concatenated field texts */
    int plen, pcap;
    int lines;
} iges_file;

/* Record layer: splits the file, checks the layout, reads Global, Directory and Parameter data. */
bool iges_read_records(iges_file *f, const char *data, size_t size, prw_error *e);
void iges_file_free(iges_file *f);

/* DE pointer (odd sequence number) -> index in f->de, or -1 when not a valid DE. */
int iges_de_index(const iges_file *f, int ptr);

/* Parameter access (1-based index after the entity type); failures name the line and field. */
bool iges_need(const iges_file *f, const iges_de *d, int count, prw_error *e);
bool iges_real(const iges_file *f, const iges_de *d, int i, double dflt, double *out, prw_error *e);
bool iges_int(const iges_file *f, const iges_de *d, int i, int dflt, int *out, prw_error *e);
/* A DE pointer parameter: *out = index into f->de, or -1 for a null (0) pointer when allowed. */
bool iges_ptr(const iges_file *f, const iges_de *d, int i, bool allow_null, int *out, prw_error *e);
/* Fails with "<name>:<line of param i (or the DE)>: entity T (DE n): <reason>". */
bool iges_fail(const iges_file *f, const iges_de *d, int i, prw_error *e, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

/* Entity layer (prw_iges_entities.c). */
typedef struct iges_ctx {
    iges_file *f;
    prw_error *e;
    int depth;          /* nesting guard */
    long budget;        /* curve pieces + projected points left */
    double max_proj;    /* largest projection distance (file units) */
} iges_ctx;

/* Converts an independent (or logically dependent) 144 / surface entity into t, in file units,
 * with the entity's transformation applied; the driver scales to metres. */
bool iges_trimmed_surface(iges_ctx *x, int k, prw_trimmed_surface *t);
bool iges_plain_surface(iges_ctx *x, int k, prw_trimmed_surface *t);
/* Colour from the DE colour field (palette 1..8 or a 314 pointer); false = none. */
bool iges_colour(iges_ctx *x, const iges_de *d, float rgb[3], bool *has);
bool iges_is_surface_type(int type);

#endif
