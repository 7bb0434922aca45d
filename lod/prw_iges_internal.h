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
    bool in_subfigure; /* a member of a 308 subfigure definition (drawn only through instances) */
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
    char note[256]; /* tolerated inconsistencies of the records (section counts, unit flag 0, parameter record
                     * counts), "; "-separated, for the warning */
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
    int unsupported;    /* set with the failure when a face needs an entity type this reader lacks:
                           the driver then skips that face (counted) instead of failing the file */
} iges_ctx;

/* Fails like iges_fail and marks the failure as "unsupported entity type" (x->unsupported). */
bool iges_unsupported(iges_ctx *x, const iges_de *d, const char *what);

/* A list of curves (one entity may give several: 102), each with its IGES parameter range
 * [it0, it1] (110: [0, 1]; 100: the angles; 126 / 112: the curve's own) and whether that
 * parameter is an angle on a circular arc (our arc's parameter is not linear in it). */
typedef struct iges_clist {
    prw_nurbs_curve *c;
    double *it0, *it1;
    unsigned char *arc;
    int n, cap;
} iges_clist;
void iges_clist_push(iges_clist *l, prw_nurbs_curve *c); /* takes ownership of *c */
void iges_clist_free(iges_clist *l);

typedef enum { IGES_MAP_IDENTITY, IGES_MAP_REVOLUTION, IGES_MAP_NONE } iges_param_map;

/* A converted surface and how IGES parameter-space curves map onto its (u, v). */
typedef struct iges_surf {
    prw_nurbs_surface s;
    iges_param_map map;
    double th0, th1;    /* IGES_MAP_REVOLUTION: v in [0, 1] <-> theta in [th0, th1] */
    iges_clist gen;     /* IGES_MAP_REVOLUTION: the generatrix pieces (ranges only, no curves) */
    bool gen_joined;    /* pieces joined: piece i is u in [i, i + 1] */
} iges_surf;
void iges_surf_free_map(iges_surf *S);

/* Every curve piece of entity k (a 102 gives several) in `dim` dimensions, transformed by
 * parent · own. */
bool iges_curves(iges_ctx *x, int k, int dim, const prw_dmat4 *parent, iges_clist *out);
/* Conic arc 104 as an exact rational quadratic (prw_iges_conic.c); untransformed. */
bool iges_curve_104(iges_ctx *x, const iges_de *d, int dim, prw_nurbs_curve *c);
/* Parametric spline surface 114 as an exact bicubic B-spline (prw_iges_spline.c); untransformed. */
bool iges_surface_114(iges_ctx *x, const iges_de *d, prw_nurbs_surface *s);
/* Entity k as a surface; hint: model-space points a plane (108) must cover. */
bool iges_surface(iges_ctx *x, int k, const prw_dvec3 *hint, int nhint, iges_surf *out);
/* The entity's own 124 chain (identity when none). */
bool iges_own_xform(iges_ctx *x, const iges_de *d, prw_dmat4 *m);
/* Projects the model-space curves of one boundary (in order, end to end) onto t->surface into a
 * new loop of t (uv polylines unwrapped across the seams of a closed surface — prw_trim_wrap.h —
 * and, for the first loop of a face that straddles a seam, the surface re-seated; model curves
 * kept); `d`/`param` name the entity and parameter in messages.  Takes the curves out of *model. */
bool iges_project_loop(iges_ctx *x, const iges_de *d, int param, iges_clist *model, prw_trimmed_surface *t);
/* Appends the control points of every curve in l to *pts (plane extents). */
void iges_hint_points(const iges_clist *l, prw_dvec3 **pts, int *n);

/* B-rep (prw_iges_brep.c): face 510 with its loops 508 (edges from 504 / 502), as a trimmed
 * surface; flip: the shell / solid orientation says the face's normal is opposite the surface's
 * (the face's own flag is combined by the caller). */
bool iges_brep_face(iges_ctx *x, int k, bool flip, prw_trimmed_surface *t);
/* Bounded surface 143 with its 141 boundaries. */
bool iges_bounded_surface(iges_ctx *x, int k, prw_trimmed_surface *t);

/* Converts an independent (or logically dependent) 144 / surface entity into t, in file units,
 * with the entity's transformation applied; the driver scales to metres. */
bool iges_trimmed_surface(iges_ctx *x, int k, prw_trimmed_surface *t);
bool iges_plain_surface(iges_ctx *x, int k, prw_trimmed_surface *t);
/* Colour from the DE colour field (palette 1..8 or a 314 pointer); false = none. */
bool iges_colour(iges_ctx *x, const iges_de *d, float rgb[3], bool *has);
bool iges_is_surface_type(int type);

#endif
