/* compare_write.c - results of the comparison (compare_impl.h):
 * compare.tsv (summary and points), the terminal summary, the tolerance
 * check (exit status 6). */
#include "compare_impl.h"

#include <math.h>
#include <stdio.h>

#include "vtk.h"

static const char *measure_name(int m)
{
    return m == M_SCALED ? "scaled" : m == M_RELATIVE ? "relative" : "absolute";
}

static const char *norm_name(int n) { return n == N_MAX ? "max" : n == N_RMS ? "rms" : "end"; }

static void write_header(const sf_compare *c, FILE *f, const char *header)
{
    if (header) fputs(header, f);
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        fprintf(f, "# reference %s: %s (%d rows)\n", r->name, r->path, r->nrow);
        fprintf(f, "#   kind: %s\n#   source: %s\n#   units: %s\n", r->kind, r->source, r->units);
        fprintf(f, "#   abscissa: column %s x %.12g = %s; %d rows solved at that value, %d at computed "
                "points, %d interpolated, %d outside the path\n",
                r->colname[r->xcol], r->xscale, c->qname[r->xq], r->nsolved, r->npoint, r->ninterp,
                r->noutside);
    }
}

static int fill_summary(void *ctx, void *vf)
{
    const sf_compare *c = ((const void **)ctx)[0];
    const char *header = ((const void **)ctx)[1];
    FILE *f = vf;
    write_header(c, f, header);
    fprintf(f, "# error d = computed - scale x reference; measure scaled: |d| / max |reference column|, "
               "relative: |d| / |reference| (rows with a zero reference skipped), absolute: |d|; "
               "max, rms, end (last compared row) in that measure; *_abs: |d| in the quantity's unit\n");
    fprintf(f, "reference\tcolumn\tquantity\tmeasure\tpoints\toutside\tmax\trms\tend\tx_at_max\t"
               "max_abs\trms_abs\tend_abs\tnorm\ttolerance\tstatus\n");
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) {
            const cmp_col *col = &r->cols[k];
            fprintf(f, "%s\t%s\t%s\t%s\t%d\t%d\t%.6e\t%.6e\t%.6e\t%.10g\t%.6e\t%.6e\t%.6e\t%s\t",
                    r->name, col->column, c->qname[col->q], measure_name(col->measure), col->npts,
                    r->noutside, col->emax, col->erms, col->eend, col->xmax, col->amax, col->arms, col->aend,
                    norm_name(col->norm));
            if (col->has_tol) fprintf(f, "%.6g\t%s\n", col->tol, col->pass > 0 ? "ok" : "FAIL");
            else fprintf(f, "-\t-\n");
        }
    }
    return ferror(f) ? SF_EIO : SF_OK;
}

static int fill_points(void *ctx, void *vf)
{
    const sf_compare *c = ((const void **)ctx)[0];
    const char *header = ((const void **)ctx)[1];
    FILE *f = vf;
    write_header(c, f, header);
    fprintf(f, "# one row per reference row placed on the path; blocks (blank-line separated) per "
               "compared column; method: point (a computed point), solved (equilibrium solved at x), "
               "interpolated\n");
    fprintf(f, "reference\tcolumn\tquantity\tline\tx\treference_value\tcomputed\tdifference\terror\tmethod\n");
    int first = 1;
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) {
            const cmp_col *col = &r->cols[k];
            if (!first) fputc('\n', f);
            first = 0;
            for (int row = 0; row < r->nrow; row++) {
                char m = r->method[row];
                if (m == 'o') continue;
                double ref = col->scale * r->v[(size_t)row * r->ncol + col->ccol];
                double d = col->comp[row] - ref;
                double e = col->measure == M_ABSOLUTE ? fabs(d)
                         : col->measure == M_SCALED ? fabs(d) / col->refmax
                         : (ref != 0.0 && fabs(ref) > 1e-9 * col->refmax) ? fabs(d) / fabs(ref) : 0.0;
                fprintf(f, "%s\t%s\t%s\t%d\t%.15g\t%.15g\t%.15g\t%.6e\t%.6e\t%s\n", r->name, col->column,
                        c->qname[col->q], r->line[row], r->x[row], ref, col->comp[row], d, e, m == 'p' ? "point" : m == 's' ? "solved" : "interpolated");
            }
        }
    }
    return ferror(f) ? SF_EIO : SF_OK;
}

int sf_compare_write(const sf_compare *c, const char *dir, const char *header, sf_error *err)
{
    if (!c) return SF_OK;
    const void *ctx[2] = {c, header};
    char path[1200];
    snprintf(path, sizeof path, "%s/compare.tsv", dir);
    if (sf_write_atomic(path, fill_summary, (void *)ctx, err)) return err->code;
    snprintf(path, sizeof path, "%s/compare-points.tsv", dir);
    if (sf_write_atomic(path, fill_points, (void *)ctx, err)) return err->code;
    return SF_OK;
}

void sf_compare_print_files(const sf_compare *c, FILE *f)
{
    if (!c) return;
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        fprintf(f, "reference %s: %s (%d rows, %d columns compared; %.60s)\n", r->name, r->path,
                r->nrow, r->ncols, r->kind);
    }
}

void sf_compare_print(const sf_compare *c, FILE *f)
{
    if (!c) return;
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) {
            const cmp_col *col = &r->cols[k];
            double v = col->norm == N_MAX ? col->emax : col->norm == N_RMS ? col->erms : col->eend;
            fprintf(f, "compare %s %s: %s %s error %.3g over %d rows", r->name, col->column,
                    norm_name(col->norm), measure_name(col->measure), v, col->npts);
            if (r->noutside) fprintf(f, " (%d outside the path)", r->noutside);
            if (col->has_tol) fprintf(f, ", tolerance %.3g: %s", col->tol, col->pass > 0 ? "ok" : "EXCEEDED");
            fputc('\n', f);
        }
    }
}

int sf_compare_check(const sf_compare *c, sf_error *err)
{
    if (!c) return SF_OK;
    int nfail = 0;
    const cmp_ref *fr = NULL;
    const cmp_col *fc = NULL;
    for (int i = 0; i < c->nref; i++)
        for (int k = 0; k < c->refs[i].ncols; k++)
            if (c->refs[i].cols[k].pass == 0) {
                if (!nfail) { fr = &c->refs[i]; fc = &c->refs[i].cols[k]; }
                nfail++;
            }
    if (!nfail) return SF_OK;
    char more[64] = "";
    if (nfail > 1) snprintf(more, sizeof more, " (and %d more)", nfail - 1);
    if (fc->npts == 0)
        return sf_study_fail(c->s, err, SF_ETOLERANCE, fc->key, "%s against %s: no reference row lies on "
                             "the computed path, so the tolerance cannot be checked%s", c->qname[fc->q],
                             fr->name, more);
    double v = fc->norm == N_MAX ? fc->emax : fc->norm == N_RMS ? fc->erms : fc->eend;
    return sf_study_fail(c->s, err, SF_ETOLERANCE, fc->key, "%s against %s column %s: %s %s error %.4g "
                         "exceeds the tolerance %.4g%s", c->qname[fc->q], fr->name, fc->column,
                         norm_name(fc->norm), measure_name(fc->measure), v, fc->tol, more);
}
