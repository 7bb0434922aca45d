/* bench_plot — PNG plots of a bench result, drawn by gnuplot (Debian: gnuplot-nox) in a child process.
 *
 * Writes plain data files and a script (plots.gp) beside the results, then runs `gnuplot plots.gp`:
 *   frame_time.png  frame time (timed run) along the path, one line per configuration;
 *   error.png       LDR-FLIP against the reference at the sampled frames, one line per configuration,
 *                   with the reference noise (dashed);
 *   pareto.png      (more than one configuration) median frame time against mean LDR-FLIP, one point
 *                   per configuration, the Pareto front (lower time and lower error are better) as a
 *                   line through its points.  pareto.dat holds the numbers.
 * Without gnuplot on PATH the plots are skipped with a note on stderr; plotting never fails a run.
 */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_internal.h"

extern char **environ;

static bool have_gnuplot(void)
{
    const char *path = getenv("PATH");
    if (!path) return false;
    char *copy = prw_strdup(path), *save = NULL;
    bool found = false;
    for (char *d = strtok_r(copy, ":", &save); d && !found; d = strtok_r(NULL, ":", &save)) {
        char p[4200];
        snprintf(p, sizeof p, "%s/gnuplot", d);
        found = access(p, X_OK) == 0;
    }
    free(copy);
    return found;
}

static void quote_label(char *out, size_t cap, const char *label)
{
    size_t n = 0;
    for (const char *s = label; *s && n + 2 < cap; s++)
        if (*s != '"' && *s != '\\') out[n++] = *s == '_' ? '-' : *s; /* '_' would be a subscript */
    out[n] = '\0';
}

static bool write_data(const bench_result *r, const char *dir)
{
    char p[4200];
    bench_join(p, sizeof p, dir, "frame_time.dat");
    FILE *ft = fopen(p, "w");
    bench_join(p, sizeof p, dir, "error.dat");
    FILE *fe = fopen(p, "w");
    if (!ft || !fe) {
        if (ft) fclose(ft);
        if (fe) fclose(fe);
        return false;
    }
    fprintf(ft, "# frame frame_ms (one block per config)\n");
    fprintf(fe, "# frame ldr_flip noise_ldr_flip hdr_flip noise_hdr_flip (one block per config)\n");
    for (uint32_t c = 0; c < r->config_count; c++) {
        for (size_t i = 0; i < r->row_count; i++) {
            const bench_row *w = &r->rows[i];
            if (w->config != c) continue;
            fprintf(ft, "%u %.9g\n", w->frame, w->frame_ms);
            if (w->ref && !isnan(w->err.ldr_flip))
                fprintf(fe, "%u %.9g %.9g %.9g %.9g\n", w->frame, w->err.ldr_flip, w->noise.ldr_flip, w->err.hdr_flip,
                        w->noise.hdr_flip);
        }
        fprintf(ft, "\n\n");
        fprintf(fe, "\n\n");
    }
    fclose(ft);
    fclose(fe);
    return true;
}

/* pareto.dat: p50_ms mean_ldr_flip on_front index; the front sorted by time in pareto_front.dat */
static uint32_t write_pareto(const bench_result *r, const char *dir)
{
    uint32_t n = r->config_count;
    double *x = prw_calloc(n, sizeof *x), *y = prw_calloc(n, sizeof *y);
    bool *front = prw_calloc(n, sizeof *front);
    for (uint32_t c = 0; c < n; c++) {
        bench_config_stats s;
        bench_config_summary(r, c, &s);
        x[c] = s.frame_ms.p50;
        y[c] = s.err[0].mean;
    }
    size_t nf = prw_stats_pareto(x, y, n, front);
    char p[4200];
    bench_join(p, sizeof p, dir, "pareto.dat");
    FILE *f = fopen(p, "w");
    if (f) {
        fprintf(f, "# p50_frame_ms mean_ldr_flip on_front config label\n");
        for (uint32_t c = 0; c < n; c++) {
            char lab[128];
            quote_label(lab, sizeof lab, r->configs[c].label);
            fprintf(f, "%.9g %.9g %d %u \"%s\"\n", x[c], y[c], front[c] ? 1 : 0, c, lab);
        }
        fclose(f);
    }
    bench_join(p, sizeof p, dir, "pareto_front.dat");
    f = fopen(p, "w");
    if (f) {
        /* front points by increasing time (their error then decreases) */
        bool *done = prw_calloc(n, sizeof *done);
        for (size_t k = 0; k < nf; k++) {
            int best = -1;
            for (uint32_t c = 0; c < n; c++)
                if (front[c] && !done[c] && (best < 0 || x[c] < x[best] || (x[c] == x[best] && y[c] < y[best])))
                    best = (int)c;
            done[best] = true;
            fprintf(f, "%.9g %.9g\n", x[best], y[best]);
        }
        free(done);
        fclose(f);
    }
    printf("Pareto front (median frame time, mean LDR-FLIP; lower is better in both):\n");
    for (uint32_t c = 0; c < n; c++)
        printf("  %s config %2u  %9.2f ms  FLIP %.4f  %s\n", front[c] ? "*" : " ", c, x[c], y[c], r->configs[c].label);
    free(x);
    free(y);
    free(front);
    return (uint32_t)nf;
}

static bool write_script(const bench_result *r, const char *dir, const char *script)
{
    FILE *f = fopen(script, "w");
    if (!f) return false;
    const char *size = bench_meta_get(&r->meta, "size");
    fprintf(f, "# generated by prw bench\nset terminal pngcairo size 1100,650 noenhanced\nset grid\nset key outside right\n");
    fprintf(f, "cd '%s'\n", dir);
    fprintf(f, "set output 'frame_time.png'\nset title 'frame time along the path (%s, timed run)'\n"
               "set xlabel 'frame'\nset ylabel 'frame time [ms]'\n", size ? size : "");
    fprintf(f, "plot ");
    for (uint32_t c = 0; c < r->config_count; c++) {
        char lab[128];
        quote_label(lab, sizeof lab, r->configs[c].label);
        fprintf(f, "%s'frame_time.dat' index %u using 1:2 with lines title '%u: %s'", c ? ", \\\n     " : "", c, c, lab);
    }
    fprintf(f, "\nset output 'error.png'\nset title 'error against the path-traced reference at the sampled frames'\n"
               "set ylabel 'LDR-FLIP (mean over the image)'\nset yrange [0:*]\nplot ");
    for (uint32_t c = 0; c < r->config_count; c++) {
        char lab[128];
        quote_label(lab, sizeof lab, r->configs[c].label);
        fprintf(f, "'error.dat' index %u using 1:2 with linespoints title '%u: %s', \\\n     ", c, c, lab);
    }
    fprintf(f, "'error.dat' index 0 using 1:3 with linespoints dashtype 2 lc rgb 'black' title 'reference noise'\n");
    if (r->config_count > 1) {
        fprintf(f, "set output 'pareto.png'\nset title 'time against error: one point per configuration; "
                   "the line is the Pareto front (down-left is better)'\n"
                   "set xlabel 'median frame time [ms]'\nset ylabel 'mean LDR-FLIP at the sampled frames'\n"
                   "set yrange [*:*]\nset key inside top right\n"
                   "plot 'pareto.dat' using 1:2 with points pt 7 ps 1.2 title 'configurations', \\\n"
                   "     'pareto_front.dat' using 1:2 with linespoints lw 2 pt 6 ps 2 title 'Pareto front', \\\n"
                   "     'pareto.dat' using 1:2:(sprintf('%%d', $4)) with labels offset 1.2,0.6 notitle\n");
    }
    fclose(f);
    return true;
}

static bool run_gnuplot(const char *script)
{
    char *argv[] = {"gnuplot", (char *)script, NULL};
    pid_t pid;
    if (posix_spawnp(&pid, "gnuplot", NULL, NULL, argv, environ) != 0) return false;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return false;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void bench_plots(const bench_result *r, const char *dir)
{
    if (r->config_count > 1) write_pareto(r, dir);
    if (!have_gnuplot()) {
        fprintf(stderr, "bench: gnuplot not found: plots skipped (install the Debian package gnuplot-nox)\n");
        return;
    }
    char abs_dir[4096], script[4200];
    if (!realpath(dir, abs_dir)) snprintf(abs_dir, sizeof abs_dir, "%s", dir);
    bench_join(script, sizeof script, abs_dir, "plots.gp");
    if (!write_data(r, abs_dir) || !write_script(r, abs_dir, script) || !run_gnuplot(script)) {
        fprintf(stderr, "bench: gnuplot failed: plots incomplete (script %s)\n", script);
        return;
    }
    printf("wrote %s/frame_time.png, %s/error.png%s%s%s\n", abs_dir, abs_dir, r->config_count > 1 ? ", " : "",
           r->config_count > 1 ? abs_dir : "", r->config_count > 1 ? "/pareto.png" : "");
}
