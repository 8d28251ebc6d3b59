/* reactions.c - support reactions along a path (reactions.h). */
#include "reactions.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vtk.h"

void sf_equil_reactions(const sf_equil *q, const double *y, double *out)
{
    for (int r = 0; r < q->nsup; r++) out[r] = -y[q->nq + q->nloop + r];
}

void sf_reaction_name(const sf_equil *q, int probe, int r, char *buf, size_t size)
{
    static const char axis[3] = {'x', 'y', 'z'};
    if (r == q->disp_row) {
        snprintf(buf, size, "probe%d_f%c", probe + 1, axis[q->rowc[r]]);
        return;
    }
    /* the support rows come in study order, then component order */
    const sf_study *s = q->m->study;
    int row = 0;
    for (int i = 0; i < s->nsupports; i++)
        for (int c = 0; c < 3; c++) {
            if (!s->supports[i].dof[c]) continue;
            if (row++ == r) {
                snprintf(buf, size, "support%d_%c", i + 1, axis[c]);
                return;
            }
        }
    snprintf(buf, size, "row%d", r + 1);
}

void sf_reactions_init(sf_reactions *t, int probe)
{
    memset(t, 0, sizeof *t);
    t->probe = probe;
}

int sf_reactions_add(sf_reactions *t, const sf_equil *q, long point, const double *y,
                     double p, double load, sf_error *err)
{
    char name[64];
    if (sf_need_finite(err, p, "p at reactions.tsv point %ld", point) ||
        sf_need_finite(err, load, "load at reactions.tsv point %ld (p = %.10g)", point, p))
        return err->code;
    for (int r = 0; r < q->nsup; r++) {
        if (isfinite(y[q->nq + q->nloop + r])) continue;
        sf_reaction_name(q, t->probe, r, name, sizeof name);
        return sf_need_finite(err, y[q->nq + q->nloop + r], "reaction %s at point %ld (p = %.10g)",
                              name, point, p);
    }
    sf_outbuf_printf(&t->rows, "%ld\t%.12g\t%.12g", point, p, load);
    for (int r = 0; r < q->nsup; r++) sf_outbuf_printf(&t->rows, "\t%.12g", -y[q->nq + q->nloop + r] + 0.0);
    sf_outbuf_printf(&t->rows, "\n");
    return SF_OK;
}

typedef struct fill_ctx {
    const sf_reactions *t;
    const sf_equil *q;
    const char *header;
} fill_ctx;

static int fill(void *vctx, void *vf)
{
    fill_ctx *c = vctx;
    FILE *f = vf;
    if (c->header) fputs(c->header, f);
    fputs("# reactions: force [N] exerted on the sheet by each support along the named "
          "global axis (minus the multiplier of its row)", f);
    if (c->q->disp_row >= 0)
        fputs("; probe*_f*: the force that holds the prescribed displacement", f);
    fputs("\npoint\tp\tload", f);
    char name[64];
    for (int r = 0; r < c->q->nsup; r++) {
        sf_reaction_name(c->q, c->t->probe, r, name, sizeof name);
        fprintf(f, "\t%s", name);
    }
    fputc('\n', f);
    if (c->t->rows.n && fwrite(c->t->rows.s, 1, c->t->rows.n, f) != c->t->rows.n) return SF_EIO;
    return ferror(f) ? SF_EIO : SF_OK;
}

int sf_reactions_write(const sf_reactions *t, const sf_equil *q, const char *path,
                       const char *header, sf_error *err)
{
    if (t->rows.oom) return sf_fail(err, SF_ENOMEM, "out of memory");
    fill_ctx c = {t, q, header};
    return sf_write_atomic(path, fill, &c, err);
}

void sf_reactions_free(sf_reactions *t)
{
    sf_outbuf_free(&t->rows);
    memset(t, 0, sizeof *t);
}
