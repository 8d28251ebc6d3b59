/* flatswitch_follow.c - following the branches that flatswitch.c predicts
 * at the flat state (flatswitch.h, sf_flatsw_follow): each a new branch
 * of the run through bifurcation.h's hooks, duplicates recognised by
 * their first state. */
#include "flatswitch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failed(const sf_bif *b) { return b->h.failed && b->h.failed(b->h.ctx); }


static int same_state(const double *a, double pa, const double *b, double pb, int n)
{
    if (fabs(pa - pb) > 1e-6 * (1.0 + fabs(pa))) return 0;
    for (int i = 0; i < n; i++)
        if (fabs(a[i] - b[i]) > 1e-6 * (1.0 + fabs(a[i]))) return 0;
    return 1;
}

/* (flatswitch.h) */
int sf_flatsw_follow(sf_bif *b, cont_solver *cs, const sf_flatsw *F, double p0,
                     const double *known, double pknown, sf_error *err)
{
    int n = F->n, rc = SF_OK, nfirst = 0;
    if (F->nsol == 0) {
        sf_bif_note(b, "flat state (p = %.10g): no branch of the tangent cone found by the reduced "
             "equations (%d first-order motions, %d second-order forms, %d starts, %d converged)",
             p0, F->k, F->r, F->nstarts, F->nconv);
        return SF_OK;
    }
    sf_bif_note(b, "flat state (p = %.10g): %d solutions of the reduced second-order equations on the "
         "tangent cone (%d first-order motions, %d second-order forms; %d of %d Newton starts "
         "converged, then images under %d symmetries of the crease pattern), %d classes of "
         "symmetric images; %s", p0, F->nsol, F->k, F->r, F->nconv, F->nstarts, F->nsym - 1, F->ncls, F->homogeneous ? "each leaves the flat branch at its own p*, "
         "both halves followed" : "each followed from the flat state");
    for (int j = 0; j < F->nsol; j++)
        sf_bif_note(b, "  cone solution %d: p* = %.10g, energy %.6g, class %d, residual %.2g, "
             "isolation %.2g", j + 1, F->pstar[j], F->energy[j], F->cls[j] + 1, F->resid[j], F->isol[j]);
    double *first = malloc(sizeof(double) * ((size_t)F->ndir * n + 1));
    double *pf = malloc(sizeof(double) * ((size_t)F->ndir + 1));
    int *bno = malloc(sizeof(int) * ((size_t)F->ndir + 1));
    if (!first || !pf || !bno) {
        free(first); free(pf); free(bno);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    sf_bif_bp bp;
    memset(&bp, 0, sizeof bp);
    bp.branch = 1;
    bp.point = -1;
    bp.mult = F->k;
    for (int i = 0; i < F->ndir && !rc; i++) {
        if (b->nbranches >= SF_BIF_MAX_BRANCHES) {
            sf_bif_note(b, "more than %d branches: not following the rest", SF_BIF_MAX_BRANCHES);
            break;
        }
        int j = F->sol[i];
        if (!(F->isol[j] >= SF_FLATSW_ISOL_MIN)) {
            if (i == 0 || F->sol[i - 1] != j)
                sf_bif_note(b, "flat state, cone solution %d: not isolated (singular reduced Jacobian, "
                     "%.2g): one point of a continuum of solutions, not followed", j + 1, F->isol[j]);
            continue;
        }
        bp.p = F->pstar[j];
        if (b->h.begin_branch && (rc = b->h.begin_branch(b->h.ctx, &bp, b->nbranches + 1))) break;
        b->nbranches++;
        b->branch = b->nbranches;
        b->depth = 1;
        long row0 = *b->nrows;
        int st = cont_start_tangent(cs, F->y + (size_t)i * n, F->p[i], F->ty + (size_t)i * n, F->tp[i]);
        if (failed(b)) { rc = err->code; break; }
        if (st != CONT_OK) {
            sf_bif_note(b, "branch %d (flat state, cone solution %d%s) did not start: %s", b->branch, j + 1,
                 F->homogeneous ? (i % 2 ? ", - side" : ", + side") : "", cont_errmsg(cs));
            continue;
        }
        const cont_point *pt = cont_get_point(cs);
        int dup = known && same_state(known, pknown, pt->y, pt->p, n) ? 0 : -1;
        for (int c = 0; c < nfirst && dup < 0; c++)
            if (same_state(first + (size_t)c * n, pf[c], pt->y, pt->p, n)) dup = bno[c];
        if (dup >= 0) {
            sf_bif_note(b, "branch %d (flat state, cone solution %d) duplicates branch %d: not followed",
                 b->branch, j + 1, dup ? dup : 1);
            continue;
        }
        memcpy(first + (size_t)nfirst * n, pt->y, sizeof(double) * (size_t)n);
        pf[nfirst] = pt->p;
        bno[nfirst++] = b->branch;
        sf_bif_note(b, "branch %d: flat state, cone solution %d (class %d)%s, p* = %.10g", b->branch, j + 1,
             F->cls[j] + 1, F->homogeneous ? (i % 2 ? ", - side" : ", + side") : "", F->pstar[j]);
        st = cont_run(cs);
        if (failed(b)) { rc = err->code; break; }
        if (st != CONT_OK && st != CONT_DONE)
            sf_bif_note(b, "branch %d (flat state) stopped after %ld points: %s", b->branch,
                 *b->nrows - row0, cont_errmsg(cs));
    }
    free(first);
    free(pf);
    free(bno);
    return rc;
}
