/* IGES 5.3 record layer: fixed 80-column records, section order, Global section delimiters and
 * units, Directory Entry pairs, Parameter Data fields (Hollerith strings, reals with E/D
 * exponents).  Every failure names the file line. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_iges_internal.h"

typedef struct line {
    const char *p;
    int len;
    int no; /* 1-based file line */
} line;

/* A run of text assembled from record columns, with the file line of every character. */
typedef struct src {
    char *t;
    int *ln;
    int n, cap;
} src;

/* Appends one tolerated inconsistency to f->note ("; "-separated, cut at its size). */
static void add_note(iges_file *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void add_note(iges_file *f, const char *fmt, ...)
{
    size_t n = strlen(f->note);
    if (n + 3 >= sizeof f->note) return;
    if (n) n += (size_t)snprintf(f->note + n, sizeof f->note - n, "; ");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(f->note + n, sizeof f->note - n, fmt, ap);
    va_end(ap);
}

static void src_add(src *s, const char *p, int n, int lineno)
{
    if (s->n + n + 1 > s->cap) {
        s->cap = (s->n + n + 1) * 2;
        s->t = prw_realloc(s->t, (size_t)s->cap);
        s->ln = prw_realloc(s->ln, sizeof(int) * (size_t)s->cap);
    }
    memcpy(s->t + s->n, p, (size_t)n);
    for (int i = 0; i < n; i++) s->ln[s->n + i] = lineno;
    s->n += n;
    s->t[s->n] = 0;
}

static void src_free(src *s)
{
    free(s->t);
    free(s->ln);
    memset(s, 0, sizeof *s);
}

static int src_line(const src *s, int pos, int fallback)
{
    if (s->n == 0) return fallback;
    return s->ln[pos < s->n ? pos : s->n - 1];
}

void iges_file_free(iges_file *f)
{
    free(f->de);
    free(f->tok);
    free(f->ptext);
    memset(f, 0, sizeof *f);
}

static int add_text(iges_file *f, const char *p, int n)
{
    if (f->plen + n + 1 > f->pcap) {
        f->pcap = (f->plen + n + 1) * 2;
        f->ptext = prw_realloc(f->ptext, (size_t)f->pcap);
    }
    int off = f->plen;
    memcpy(f->ptext + off, p, (size_t)n);
    f->plen += n;
    f->ptext[f->plen] = 0;
    return off;
}

static iges_tok *add_tok(iges_file *f)
{
    if (f->ntok == f->tokcap) {
        f->tokcap = f->tokcap ? 2 * f->tokcap : 1024;
        f->tok = prw_realloc(f->tok, sizeof(iges_tok) * (size_t)f->tokcap);
    }
    iges_tok *t = &f->tok[f->ntok++];
    memset(t, 0, sizeof *t);
    return t;
}

/* Fortran-style real or integer: [+-]digits[.digits][(E|D)[+-]digits]; false if not a number. */
static bool parse_number(const char *p, int n, double *out)
{
    char buf[64];
    if (n <= 0 || n >= (int)sizeof buf) return false;
    int i = 0, digits = 0;
    if (p[i] == '+' || p[i] == '-') i++;
    while (i < n && isdigit((unsigned char)p[i])) i++, digits++;
    if (i < n && p[i] == '.') {
        i++;
        while (i < n && isdigit((unsigned char)p[i])) i++, digits++;
    }
    if (!digits) return false;
    if (i < n && (p[i] == 'E' || p[i] == 'e' || p[i] == 'D' || p[i] == 'd')) {
        i++;
        if (i < n && (p[i] == '+' || p[i] == '-')) i++;
        int ed = 0;
        while (i < n && isdigit((unsigned char)p[i])) i++, ed++;
        if (!ed) return false;
    }
    if (i != n) return false;
    for (int k = 0; k < n; k++) buf[k] = (p[k] == 'D' || p[k] == 'd') ? 'E' : p[k];
    buf[n] = 0;
    double v = strtod(buf, NULL);
    if (!isfinite(v)) return false;
    *out = v;
    return true;
}

/* Parses fields from s->t[*pos] up to and including the record delimiter. */
static bool parse_fields(iges_file *f, const src *s, int *pos, char pd, char rd, int fallback_line, prw_error *e)
{
    int i = *pos;
    for (;;) {
        while (i < s->n && s->t[i] == ' ') i++;
        if (i >= s->n)
            return prw_fail(e, "%s:%d: missing record delimiter '%c'", f->name, src_line(s, i, fallback_line), rd);
        iges_tok *t = add_tok(f);
        t->line = src_line(s, i, fallback_line);
        /* Hollerith: digits 'H' */
        int j = i, n = 0;
        bool holl = false;
        while (j < s->n && isdigit((unsigned char)s->t[j]) && n < 100000000) n = n * 10 + (s->t[j++] - '0');
        if (j > i && j < s->n && s->t[j] == 'H') {
            holl = true;
            if (n > s->n - j - 1)
                return prw_fail(e, "%s:%d: Hollerith string %dH runs past the end of the parameters", f->name, t->line, n);
            t->kind = TOK_STR;
            t->off = add_text(f, s->t + j + 1, n);
            t->len = n;
            i = j + 1 + n;
            while (i < s->n && s->t[i] == ' ') i++;
            if (i >= s->n || (s->t[i] != pd && s->t[i] != rd))
                return prw_fail(e, "%s:%d: expected '%c' or '%c' after a Hollerith string", f->name,
                                src_line(s, i, fallback_line), pd, rd);
        }
        if (!holl) {
            j = i;
            while (j < s->n && s->t[j] != pd && s->t[j] != rd) j++;
            if (j >= s->n)
                return prw_fail(e, "%s:%d: missing record delimiter '%c'", f->name, src_line(s, j, fallback_line), rd);
            int a = i, b = j;
            while (b > a && s->t[b - 1] == ' ') b--;
            t->off = add_text(f, s->t + a, b - a);
            t->len = b - a;
            if (b == a) t->kind = TOK_EMPTY;
            else t->kind = parse_number(s->t + a, b - a, &t->num) ? TOK_NUM : TOK_BAD;
            i = j;
        }
        char d = s->t[i++];
        if (d == rd) break;
    }
    *pos = i;
    return true;
}

int iges_de_index(const iges_file *f, int ptr)
{
    if (ptr < 1 || ptr % 2 == 0 || (ptr - 1) / 2 >= f->nde) return -1;
    return (ptr - 1) / 2;
}

/* Integer in an 8-column DE field (blank = 0). */
static bool de_field(const iges_file *f, const line *l, int k, int *out, prw_error *e)
{
    const char *p = l->p + 8 * k;
    int a = 0, b = 8;
    while (a < b && p[a] == ' ') a++;
    while (b > a && p[b - 1] == ' ') b--;
    if (a == b) {
        *out = 0;
        return true;
    }
    int i = a;
    bool neg = false;
    if (p[i] == '-' || p[i] == '+') neg = p[i++] == '-';
    if (i == b) return prw_fail(e, "%s:%d: directory field %d '%.8s' is not an integer", f->name, l->no, k + 1, p);
    long v = 0;
    for (; i < b; i++) {
        if (!isdigit((unsigned char)p[i]))
            return prw_fail(e, "%s:%d: directory field %d '%.8s' is not an integer", f->name, l->no, k + 1, p);
        v = v * 10 + (p[i] - '0');
    }
    *out = (int)(neg ? -v : v);
    return true;
}

static const struct {
    const char *name;
    double m;
} unit_names[] = {{"IN", 0.0254},   {"INCH", 0.0254}, {"MM", 1e-3},    {"FT", 0.3048}, {"MI", 1609.344},
                  {"M", 1.0},       {"KM", 1e3},      {"MIL", 2.54e-5}, {"UM", 1e-6},  {"CM", 1e-2},
                  {"UIN", 2.54e-8}, {"MICRON", 1e-6}};
static const double unit_flags[12] = {0, 0.0254, 1e-3, 0, 0.3048, 1609.344, 1.0, 1e3, 2.54e-5, 1e-6, 1e-2, 2.54e-8};

static bool read_global(iges_file *f, const src *g, int gline, prw_error *e)
{
    f->pdelim = ',';
    f->rdelim = ';';
    int i = 0;
    const char *t = g->t;
    /* fields 1 and 2 define the delimiters: default (empty) or 1Hc */
    for (int field = 0; field < 2; field++) {
        while (i < g->n && t[i] == ' ') i++;
        if (i < g->n && t[i] == f->pdelim) { /* default, field ends */
            i++;
            continue;
        }
        if (i < g->n && t[i] == f->rdelim && field == 1) break; /* record ends after the defaults */
        if (i + 3 > g->n || t[i] != '1' || t[i + 1] != 'H')
            return prw_fail(e, "%s:%d: global parameter %d must be empty or 1H followed by the delimiter", f->name,
                            src_line(g, i, gline), field + 1);
        char c = t[i + 2];
        if (c == ' ' || isdigit((unsigned char)c) || c == '+' || c == '-' || c == '.' || c == 'H' || c == 'E' || c == 'D')
            return prw_fail(e, "%s:%d: '%c' cannot be a delimiter", f->name, src_line(g, i, gline), c);
        if (field == 0) f->pdelim = c;
        else f->rdelim = c;
        i += 3;
        while (i < g->n && t[i] == ' ') i++;
        if (i >= g->n || (t[i] != f->pdelim && t[i] != f->rdelim))
            return prw_fail(e, "%s:%d: expected a delimiter after global parameter %d", f->name, src_line(g, i, gline),
                            field + 1);
        if (t[i] == f->rdelim && field == 0)
            return prw_fail(e, "%s:%d: global section ends after parameter 1", f->name, src_line(g, i, gline));
        if (t[i++] == f->rdelim) break;
    }
    if (f->pdelim == f->rdelim)
        return prw_fail(e, "%s:%d: parameter and record delimiters are both '%c'", f->name, gline, f->pdelim);
    int t0 = f->ntok;
    if (i < g->n && !parse_fields(f, g, &i, f->pdelim, f->rdelim, gline, e)) return false;
    int nt = f->ntok - t0;
    /* fields 13 (model scale), 14 (unit flag), 15 (unit name) are tokens 10, 11, 12 */
    f->model_scale = 1.0;
    f->unit_flag = 1;
    const iges_tok *tk = f->tok + t0;
    if (nt > 10 && tk[10].kind != TOK_EMPTY) {
        if (tk[10].kind != TOK_NUM || !(tk[10].num > 0))
            return prw_fail(e, "%s:%d: global parameter 13 (model space scale) must be a positive number", f->name,
                            tk[10].line);
        f->model_scale = tk[10].num;
    }
    if (nt > 11 && tk[11].kind != TOK_EMPTY) {
        bool no_name = nt <= 12 || tk[12].kind == TOK_EMPTY || (tk[12].kind == TOK_STR && tk[12].len == 0);
        if (tk[11].kind == TOK_NUM && tk[11].num == 0 && no_name) {
            /* flag 0 and no unit name (an old Rhino writer): nothing says another unit than the
             * default; OpenCASCADE reads such files too: noted, not refused */
            add_note(f, "line %d: unit flag 0 and no unit name, inches (the default) assumed", tk[11].line);
        } else if (tk[11].kind != TOK_NUM || tk[11].num != floor(tk[11].num) || tk[11].num < 1 || tk[11].num > 11) {
            return prw_fail(e, "%s:%d: global parameter 14 (unit flag) must be an integer 1..11", f->name, tk[11].line);
        } else {
            f->unit_flag = (int)tk[11].num;
        }
    }
    f->unit_m = unit_flags[f->unit_flag];
    if (f->unit_flag == 3) {
        f->unit_m = 0;
        if (nt > 12 && tk[12].kind == TOK_STR) {
            char name[16] = {0};
            int n = tk[12].len < 15 ? tk[12].len : 15;
            for (int k = 0; k < n; k++) name[k] = (char)toupper((unsigned char)f->ptext[tk[12].off + k]);
            for (size_t k = 0; k < PRW_ARRAY_LEN(unit_names); k++)
                if (!strcmp(name, unit_names[k].name)) f->unit_m = unit_names[k].m;
        }
        if (f->unit_m == 0)
            return prw_fail(e, "%s:%d: unit flag 3 needs a known unit name in global parameter 15", f->name,
                            nt > 12 ? tk[12].line : gline);
    }
    f->ntok = t0; /* global tokens are not kept */
    return true;
}

static int section_index(char c)
{
    switch (c) {
    case 'S': return 0;
    case 'G': return 1;
    case 'D': return 2;
    case 'P': return 3;
    case 'T': return 4;
    default: return -1;
    }
}

bool iges_read_records(iges_file *f, const char *data, size_t size, prw_error *e)
{
    const char *name = f->name;
    if (size > (size_t)1 << 30) return prw_fail(e, "%s:1: file larger than 1 GiB", name);
    /* split into lines */
    line *lines = NULL;
    int nl = 0, cap = 0;
    /* Lines, or a bare run of 80-column records: no line end before the second record (a single
     * trailing line end, or line ends only between some records, are allowed there) and column 73
     * holding a section letter.  Records of a bare file are numbered 1, 2, ... in messages. */
    const char *first_nl = memchr(data, '\n', size);
    size_t first_len = first_nl ? (size_t)(first_nl - data) : size;
    bool bare = first_len >= 160 && section_index(data[72]) >= 0;
    size_t pos = 0;
    int lineno = 0;
    while (pos < size) {
        size_t end;
        if (bare) {
            while (pos < size && (data[pos] == '\n' || data[pos] == '\r')) pos++;
            if (pos >= size) break;
            end = pos + 80 < size ? pos + 80 : size;
            const char *q = memchr(data + pos, '\n', end - pos); /* a short last record */
            if (q) end = (size_t)(q - data);
        } else {
            const char *q = memchr(data + pos, '\n', size - pos);
            end = q ? (size_t)(q - data) : size;
        }
        int len = (int)(end - pos);
        if (len > 0 && data[pos + len - 1] == '\r') len--;
        lineno++;
        if (nl == cap) {
            cap = cap ? 2 * cap : 256;
            lines = prw_realloc(lines, sizeof(line) * (size_t)cap);
        }
        lines[nl++] = (line){data + pos, len, lineno};
        pos = bare ? end : end + 1;
    }
    while (nl > 0) { /* trailing blank lines */
        const line *l = &lines[nl - 1];
        bool blank = true;
        for (int k = 0; k < l->len && blank; k++) blank = l->p[k] == ' ' || l->p[k] == '\t' || l->p[k] == 0x1a;
        if (!blank) break;
        nl--;
    }
    f->lines = nl;
    bool ok = false;
    src g = {0}, ptmp = {0};
    int counts[5] = {0};
    int first[5] = {-1, -1, -1, -1, -1};
    if (nl == 0) {
        prw_fail(e, "%s:1: empty file", name);
        goto done;
    }
    int cur = 0;
    for (int i = 0; i < nl; i++) {
        line *l = &lines[i];
        if (l->len < 80) {
            prw_fail(e, "%s:%d: record has %d columns, expected 80 (section letter in column 73, sequence number in 74-80)",
                     name, l->no, l->len);
            goto done;
        }
        for (int k = 80; k < l->len; k++)
            if (l->p[k] != ' ' && l->p[k] != '\t') {
                prw_fail(e, "%s:%d: record longer than 80 columns", name, l->no);
                goto done;
            }
        char c = l->p[72];
        if (i == 0 && (c == 'B' || c == 'C')) {
            prw_fail(e, "%s:%d: binary or compressed IGES is not supported", name, l->no);
            goto done;
        }
        int s = section_index(c);
        if (s < 0) {
            prw_fail(e, "%s:%d: column 73 holds '%c', expected a section letter S, G, D, P or T", name, l->no,
                     isprint((unsigned char)c) ? c : '?');
            goto done;
        }
        if (s < cur) {
            prw_fail(e, "%s:%d: %c record after the %c section (order must be S, G, D, P, T)", name, l->no, c,
                     "SGDPT"[cur]);
            goto done;
        }
        if (cur == 4 && counts[4] > 0) {
            prw_fail(e, "%s:%d: record after the Terminate record", name, l->no);
            goto done;
        }
        cur = s;
        int seq = 0;
        for (int k = 73; k < 80; k++) {
            char d = l->p[k];
            if (d == ' ' && seq == 0) continue;
            if (!isdigit((unsigned char)d)) {
                prw_fail(e, "%s:%d: sequence number '%.7s' in columns 74-80 is not a number", name, l->no, l->p + 73);
                goto done;
            }
            seq = seq * 10 + (d - '0');
        }
        if (seq != counts[s] + 1) {
            prw_fail(e, "%s:%d: sequence number %d, expected %d", name, l->no, seq, counts[s] + 1);
            goto done;
        }
        if (first[s] < 0) first[s] = i;
        counts[s]++;
    }
    if (counts[4] != 1) {
        prw_fail(e, "%s:%d: missing Terminate (T) record", name, lines[nl - 1].no);
        goto done;
    }
    if (counts[1] == 0) {
        prw_fail(e, "%s:%d: missing Global (G) section", name, lines[nl - 1].no);
        goto done;
    }
    if (counts[2] % 2) {
        prw_fail(e, "%s:%d: odd number of Directory Entry records (%d): entries are pairs", name,
                 lines[first[2] + counts[2] - 1].no, counts[2]);
        goto done;
    }
    {
        /* Terminate: S0000001G0000004D0000010P0000020 */
        const line *t = &lines[first[4]];
        static const char letters[4] = {'S', 'G', 'D', 'P'};
        for (int k = 0; k < 4; k++) {
            const char *q = t->p + 8 * k;
            int v = 0;
            bool num = q[0] == letters[k];
            for (int m = 1; m < 8 && num; m++) {
                if (q[m] == ' ' && v == 0) continue;
                num = isdigit((unsigned char)q[m]);
                if (num) v = v * 10 + (q[m] - '0');
            }
            if (num && v != counts[k] && k < 2) {
                /* a miscounted Start or Global section loses nothing (the sections are delimited by
                 * their letters); OpenCASCADE reads such files too: noted, not refused */
                add_note(f, "line %d: Terminate record counts %d %c records, the file has %d",
                         t->no, v, letters[k], counts[k]);
                continue;
            }
            if (!num || v != counts[k]) {
                prw_fail(e, "%s:%d: Terminate record field %d ('%.8s') does not match the %d %c records", name, t->no,
                         k + 1, q, counts[k], letters[k]);
                goto done;
            }
        }
    }
    /* Global */
    for (int i = 0; i < counts[1]; i++) src_add(&g, lines[first[1] + i].p, 72, lines[first[1] + i].no);
    if (!read_global(f, &g, lines[first[1]].no, e)) goto done;

    /* Directory */
    f->nde = counts[2] / 2;
    f->de = prw_calloc((size_t)f->nde + 1, sizeof(iges_de));
    for (int k = 0; k < f->nde; k++) {
        const line *a = &lines[first[2] + 2 * k], *b = a + 1;
        iges_de *d = &f->de[k];
        int v[9], w[9];
        for (int m = 0; m < 9; m++) {
            if (m == 8) { /* status: four 2-digit numbers */
                v[8] = 0;
                continue;
            }
            if (!de_field(f, a, m, &v[m], e)) goto done;
        }
        for (int m = 0; m < 9; m++) {
            if (m >= 5) { /* reserved fields, entity label (text) and subscript: not used */
                w[m] = 0;
                continue;
            }
            if (!de_field(f, b, m, &w[m], e)) goto done;
        }
        const char *st = a->p + 64;
        int digits[8];
        for (int m = 0; m < 8; m++) {
            if (st[m] == ' ') digits[m] = 0;
            else if (isdigit((unsigned char)st[m])) digits[m] = st[m] - '0';
            else {
                prw_fail(e, "%s:%d: status number '%.8s' (columns 65-72) is not numeric", name, a->no, st);
                goto done;
            }
        }
        d->seq = 2 * k + 1;
        d->line = a->no;
        d->type = v[0];
        d->pd_ptr = v[1];
        d->xform = v[6];
        d->subord = digits[2] * 10 + digits[3];
        d->colour = w[2];
        d->pd_count = w[3];
        d->form = w[4];
        if (w[0] != v[0]) {
            prw_fail(e, "%s:%d: entity type %d in the second directory record differs from %d in the first", name, b->no,
                     w[0], v[0]);
            goto done;
        }
        if (d->type < 0 || d->type > 9999) {
            prw_fail(e, "%s:%d: entity type %d is not valid", name, a->no, d->type);
            goto done;
        }
        if (d->subord > 3) {
            prw_fail(e, "%s:%d: subordinate entity switch %02d is not 00..03", name, a->no, d->subord);
            goto done;
        }
        if (d->type == 0) continue; /* null entity */
        if (d->pd_ptr >= 1 && d->pd_ptr <= counts[3] && (d->pd_count < 1 || d->pd_count > counts[3] - d->pd_ptr + 1)) {
            d->pd_count = -d->pd_count - 1; /* recounted from the back pointers below, or refused there */
            continue;
        }
        if (d->pd_ptr < 1 || d->pd_count < 1 || d->pd_ptr > counts[3] || d->pd_count > counts[3] - d->pd_ptr + 1) {
            prw_fail(e, "%s:%d: parameter data pointer %d with %d records lies outside the P section (%d records)", name,
                     a->no, d->pd_ptr, d->pd_count, counts[3]);
            goto done;
        }
    }
    /* Parameters */
    int recounted = 0;
    for (int k = 0; k < f->nde; k++) {
        iges_de *d = &f->de[k];
        if (d->type == 0) continue;
        ptmp.n = 0;
        /* the records from the pointer on that point back to this entry; when the count in the
         * directory disagrees and they hold a whole record (its delimiter), they are taken, with a
         * note (OpenCASCADE reads such files: its bad_header.igs) */
        int run = 0, declared = d->pd_count < 0 ? -d->pd_count - 1 : d->pd_count;
        bool whole = false;
        while (d->pd_ptr - 1 + run < counts[3]) {
            const line *l = &lines[first[3] + d->pd_ptr - 1 + run];
            int back = 0;
            for (int q = 64; q < 72; q++) back = isdigit((unsigned char)l->p[q]) ? back * 10 + (l->p[q] - '0') : back;
            if (back != d->seq) break;
            whole = memchr(l->p, f->rdelim, 64) != NULL;
            run++;
        }
        if (run >= 1 && run != declared && whole) {
            if (recounted++ == 0)
                add_note(f, "line %d: directory entry %d counts %d parameter records, it has %d", d->line, d->seq,
                         declared, run);
            d->pd_count = run;
        } else if (d->pd_count < 0) {
            prw_fail(e, "%s:%d: parameter data pointer %d with %d records lies outside the P section (%d records)", name,
                     d->line, d->pd_ptr, declared, counts[3]);
            goto done;
        }
        for (int m = 0; m < d->pd_count; m++) {
            const line *l = &lines[first[3] + d->pd_ptr - 1 + m];
            int back = 0;
            bool okb = true;
            for (int q = 64; q < 72; q++) {
                char c = l->p[q];
                if (c == ' ' && back == 0) continue;
                if (!isdigit((unsigned char)c)) okb = false;
                else back = back * 10 + (c - '0');
            }
            if (!okb || back != d->seq) {
                prw_fail(e, "%s:%d: parameter record points back to DE '%.8s', expected %d", name, l->no, l->p + 64, d->seq);
                goto done;
            }
            src_add(&ptmp, l->p, 64, l->no);
            d->last_line = l->no;
        }
        int i = 0;
        int t0 = f->ntok;
        if (!parse_fields(f, &ptmp, &i, f->pdelim, f->rdelim, d->last_line, e)) goto done;
        const iges_tok *tt = &f->tok[t0];
        if (tt->kind != TOK_NUM || tt->num != d->type) {
            prw_fail(e, "%s:%d: parameter data starts with '%.*s', the directory entry says type %d", name, tt->line,
                     tt->len > 16 ? 16 : tt->len, f->ptext + tt->off, d->type);
            goto done;
        }
        d->tok0 = t0 + 1;
        d->ntok = f->ntok - t0 - 1;
    }
    if (recounted > 1) add_note(f, "%d more entries recounted so", recounted - 1);
    ok = true;
done:
    src_free(&g);
    src_free(&ptmp);
    free(lines);
    return ok;
}

bool iges_fail(const iges_file *f, const iges_de *d, int i, prw_error *e, const char *fmt, ...)
{
    char reason[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    int line = d->line;
    if (i >= 1 && i <= d->ntok) line = f->tok[d->tok0 + i - 1].line;
    else if (i > d->ntok) line = d->last_line;
    if (i >= 1) return prw_fail(e, "%s:%d: entity %d (DE %d) parameter %d: %s", f->name, line, d->type, d->seq, i, reason);
    return prw_fail(e, "%s:%d: entity %d (DE %d): %s", f->name, line, d->type, d->seq, reason);
}

bool iges_need(const iges_file *f, const iges_de *d, int count, prw_error *e)
{
    if (count < 0 || d->ntok < count)
        return prw_fail(e, "%s:%d: entity %d (DE %d): parameter count too small: %d, needs %d", f->name, d->last_line,
                        d->type, d->seq, d->ntok, count);
    return true;
}

bool iges_real(const iges_file *f, const iges_de *d, int i, double dflt, double *out, prw_error *e)
{
    if (!iges_need(f, d, i, e)) return false;
    const iges_tok *t = &f->tok[d->tok0 + i - 1];
    if (t->kind == TOK_EMPTY) {
        *out = dflt;
        return true;
    }
    if (t->kind != TOK_NUM)
        return iges_fail(f, d, i, e, "'%.*s' is not a number", t->len > 24 ? 24 : t->len, f->ptext + t->off);
    *out = t->num;
    return true;
}

bool iges_int(const iges_file *f, const iges_de *d, int i, int dflt, int *out, prw_error *e)
{
    double v = 0; /* set whenever iges_real succeeds; gcc -O3 cannot see it through iges_fail */
    if (!iges_real(f, d, i, dflt, &v, e)) return false;
    if (v != floor(v) || fabs(v) > 1e9) return iges_fail(f, d, i, e, "%g is not an integer", v);
    *out = (int)v;
    return true;
}

bool iges_ptr(const iges_file *f, const iges_de *d, int i, bool allow_null, int *out, prw_error *e)
{
    int v = 0; /* as in iges_int */
    if (!iges_int(f, d, i, 0, &v, e)) return false;
    if (v == 0) {
        if (!allow_null) return iges_fail(f, d, i, e, "null pointer where an entity is required");
        *out = -1;
        return true;
    }
    int k = iges_de_index(f, v < 0 ? -v : v);
    if (k < 0) return iges_fail(f, d, i, e, "pointer %d to a non-existent directory entry", v);
    *out = k;
    return true;
}
