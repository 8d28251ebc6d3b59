/* bifurcation.c - bifurcation bookkeeping along equilibrium paths (see
 * bifurcation.h): Morse index between points, eigenvalue crossings located
 * at fixed p, BP refinement, branch switching. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bifurcation.h"
#include "multibp.h"

void sf_bif_init(sf_bif *b, sf_equil *eq, sf_stab *st, double tol, int max_depth,
                 const long *nrows, const sf_bif_hooks *h)
{
    memset(b, 0, sizeof *b);
    b->eq = eq;
    b->stab = st;
    b->tol = tol;
    b->max_depth = max_depth;
    b->nrows = nrows;
    b->h = *h;
    b->branch = 1;
    b->nbranches = 1;
}

void sf_bif_free(sf_bif *b)
{
    if (b->aux) cont_free(b->aux);
    free(b->prev_y);
    for (int i = 0; i < b->nbp; i++) {
        free(b->bp[i].y);
        free(b->bp[i].ty);
    }
    free(b->bp);
    memset(b, 0, sizeof *b);
}

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void sf_bif_note(sf_bif *b, const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (b->h.note) b->h.note(b->h.ctx, line);
}

/* Remember a branch point for switching, unless it is one already known
 * (a branch may run into a point it started from). */
int sf_bif_add_bp(sf_bif *b, const cont_point *pt, sf_error *err)
{
    sf_equil *eq = b->eq;
    int n = eq->n;
    int mult = 1;
    if (!strncmp(pt->label, "BP", 2) && pt->label[2]) mult = atoi(pt->label + 2);
    if ((!pt->ty && mult < 2) || b->depth >= b->max_depth) return 0;
    for (int i = 0; i < b->nbp; i++) {
        const sf_bif_bp *k = &b->bp[i];
        double d = fabs(k->p - pt->p) / (1.0 + fabs(pt->p));
        for (int j = 0; j < eq->nq; j++) d = fmax(d, fabs(k->y[j] - pt->y[j]) / (1.0 + fabs(pt->y[j])));
        if (d < 1e-6) return 0;
    }
    if (b->nbp == b->capbp) {
        int cap = b->capbp ? 2 * b->capbp : 8;
        sf_bif_bp *nb = realloc(b->bp, (size_t)cap * sizeof *nb);
        if (!nb) return sf_fail(err, SF_ENOMEM, "out of memory");
        b->bp = nb;
        b->capbp = cap;
    }
    sf_bif_bp *k = &b->bp[b->nbp];
    memset(k, 0, sizeof *k);
    k->y = malloc(sizeof(double) * (size_t)n);
    k->ty = malloc(sizeof(double) * (size_t)n);
    if (!k->y || !k->ty) {
        free(k->y);
        free(k->ty);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    memcpy(k->y, pt->y, sizeof(double) * (size_t)n);
    if (pt->ty) memcpy(k->ty, pt->ty, sizeof(double) * (size_t)n);
    else memset(k->ty, 0, sizeof(double) * (size_t)n);
    k->p = pt->p;
    k->tp = pt->ty ? pt->tp : 0.0;
    k->mult = mult;
    k->depth = b->depth;
    k->branch = b->branch;
    k->point = *b->nrows;
    b->nbp++;
    return 0;
}

/* Bounds on the index at a point: lo..hi negative eigenvalues, allowing
 * for the one at zero of an LP/BP the engine located. */
void sf_bif_morse_bounds(const sf_stab_result *R, const cont_point *pt, int at_bp, int *lo, int *hi)
{
    /* the index from the signs of the eigenvalues when all the negative
     * ones are among those computed (ARPACK's inertia count and its
     * eigenvalues may disagree about one at round-off distance from 0) */
    int neg = R->morse;
    if (R->neig > R->morse) {
        neg = 0;
        for (int i = 0; i < R->neig; i++) neg += R->eig[i] < 0;
    }
    *lo = *hi = neg;
    int located = at_bp || strcmp(pt->label, "LP") == 0 || strcmp(pt->label, "BP") == 0;
    if (located && R->neig > 0) {
        int k = 0;
        for (int i = 1; i < R->neig; i++)
            if (fabs(R->eig[i]) < fabs(R->eig[k])) k = i;
        if (R->eig[k] < 0) (*lo)--;
        else (*hi)++;
    }
}

/* The previous point's state and the bracket ends of the locating
 * functions; 0 or SF_ENOMEM. */
static int buffers(sf_bif *b)
{
    int n = b->eq->n;
    if (!b->prev_y) {
        b->prev_y = malloc(sizeof(double) * (size_t)(4 * n + b->stab->nev + 1));
        if (!b->prev_y) return SF_ENOMEM;
        b->ya = b->prev_y + n;
        b->yb = b->ya + n;
        b->yt = b->yb + n;
        b->prev_eig = b->yt + n;
    }
    return SF_OK;
}

/* The solver of the fixed-p solves; 0 or SF_ENUMERIC. */
static int aux_solver(sf_bif *b)
{
    if (!b->aux) {
        if (sf_equil_create_solver(b->eq, &b->aux) != CONT_OK) return SF_ENUMERIC;
        cont_set_newton(b->aux, b->tol, 12, 0);
    }
    return SF_OK;
}

int sf_bif_prepare(sf_bif *b)
{
    if (buffers(b)) return SF_ENOMEM;
    return aux_solver(b);
}

static void remember_prev(sf_bif *b, const cont_point *pt, double sarc)
{
    const sf_stab_result *R = &b->stab->res;
    int n = b->eq->n;
    if (buffers(b)) { b->prev_ok = 0; return; }
    memcpy(b->prev_y, pt->y, sizeof(double) * (size_t)n);
    b->prev_p = pt->p;
    b->prev_sarc = sarc;
    /* the first point of a switched branch is the branch point it starts from */
    sf_bif_morse_bounds(R, pt, pt->index == 0 && b->branch > 1, &b->prev_lo, &b->prev_hi);
    b->prev_dim = R->dim;
    b->prev_neig = R->neig;
    for (int i = 0; i < R->neig && i < b->stab->nev; i++) b->prev_eig[i] = R->eig[i];
    b->prev_row = *b->nrows - 1;
    b->prev_ok = 1;
}

void sf_bif_point_written(sf_bif *b, const cont_point *pt, double sarc)
{
    /* a point whose index is unknown is no bracket end: the next point is
     * compared with the last one whose index is known */
    if (b->stab && !b->in_check && !b->stab->res.morse_unknown) remember_prev(b, pt, sarc);
}

/* Solve at fixed p from the guess interpolated between the bracket ends
 * (ya at pa, yb at pb) into yt, then its stability.  Fails (returns 1)
 * when Newton fails or leaves that stretch of the branch. */
static int solve_at(sf_bif *b, double pa, double pb, double p)
{
    int n = b->eq->n;
    double t = (p - pa) / (pb - pa), span = 0.0, dist = 0.0;
    for (int i = 0; i < n; i++) {
        b->yt[i] = b->ya[i] + t * (b->yb[i] - b->ya[i]);
        span = fmax(span, fabs(b->yb[i] - b->ya[i]) * b->eq->yscale[i]);
    }
    const double *g = b->yt;    /* the guess */
    double *y = malloc(sizeof(double) * (size_t)n);
    if (!y) return 1;
    memcpy(y, g, sizeof(double) * (size_t)n);
    int ok = cont_solve_fixed(b->aux, y, p) == CONT_OK;
    for (int i = 0; ok && i < n; i++) {
        if (!isfinite(y[i])) ok = 0;
        else dist = fmax(dist, fabs(y[i] - g[i]) * b->eq->yscale[i]);
    }
    if (ok && dist > span + 1e-8) ok = 0;
    if (ok) memcpy(b->yt, y, sizeof(double) * (size_t)n);
    free(y);
    if (!ok) return 1;
    sf_error e;
    sf_error_clear(&e);
    return sf_stab_eval(b->stab, b->eq, b->yt, p, &e) != SF_OK;
}

/* The j-th smallest eigenvalue (1-based) at the last solve_at, or, when
 * the method did not compute that many, the sign of the index test. */
static double eig_j(const sf_bif *b, int j, int *exact)
{
    const sf_stab_result *R = &b->stab->res;
    *exact = j <= R->neig;
    if (*exact) return R->eig[j - 1];
    return R->morse >= j ? -1.0 : 1.0;
}

/* (bifurcation.h) */
double sf_bif_locate_eig(sf_bif *b, const double *ya, double pa, double fa, int known_a,
                         const double *yb, double pb, int j, double *p_out)
{
    int n = b->eq->n;
    double pa0 = pa, pb0 = pb;
    memmove(b->ya, ya, sizeof(double) * (size_t)n);
    memmove(b->yb, yb, sizeof(double) * (size_t)n);
    int known_b = 0, side = 0;
    double fb = fa > 0 ? -1.0 : 1.0;
    double tol = 1e-10 * (1.0 + fabs(pa) + fabs(pb));
    int hit = 0;
    for (int it = 0; it < 100 && fabs(pb - pa) > tol; it++) {
        double p = known_a && known_b && fa != fb ? pb - fb * (pb - pa) / (fb - fa) : 0.5 * (pa + pb);
        if (!(p > fmin(pa, pb) && p < fmax(pa, pb))) p = 0.5 * (pa + pb);
        int failed = solve_at(b, pa, pb, p);
        if (failed && p != 0.5 * (pa + pb)) {
            /* the secant point may sit on the singular point itself */
            p = 0.5 * (pa + pb);
            failed = solve_at(b, pa, pb, p);
        }
        if (failed) break;
        int exact;
        double f = eig_j(b, j, &exact);
        if (f == 0.0) { pa = pb = p; hit = 1; break; }
        if ((f > 0) == (fa > 0)) {
            pa = p; fa = f; known_a = exact;
            memcpy(b->ya, b->yt, sizeof(double) * (size_t)n);
            if (side == -1) fb *= 0.5;   /* the same end moved twice: Illinois */
            side = -1;
        } else {
            pb = p; fb = f; known_b = exact;
            memcpy(b->yb, b->yt, sizeof(double) * (size_t)n);
            if (side == 1) fa *= 0.5;
            side = 1;
        }
    }
    *p_out = 0.5 * (pa + pb);
    if (hit || !solve_at(b, pa, pb, *p_out)) return fabs(pb - pa);
    /* Newton at fixed p fails next to a singular point (the Jacobian is
     * singular where the eigenvalue vanishes): keep the bracket reached,
     * if any, with its end nearer the zero (one solved here, not a or b) */
    if (side == 0) return -1.0;
    int use_a = known_a && known_b ? fabs(fa) <= fabs(fb) : side == -1;
    if (use_a && pa == pa0) use_a = 0;
    if (!use_a && pb == pb0) use_a = 1;
    memcpy(b->yt, use_a ? b->ya : b->yb, sizeof(double) * (size_t)n);
    *p_out = use_a ? pa : pb;
    sf_error e;
    sf_error_clear(&e);
    if (sf_stab_eval(b->stab, b->eq, b->yt, *p_out, &e)) return -1.0;
    return fabs(pb - pa);
}

/* (bifurcation.h) */
double sf_bif_step_bound(const sf_stab_result *R, sf_stab *st2, sf_equil *eq, const cont_point *pt,
                         double ds_next)
{
    int n = eq->n, ne = R->neig;
    if (!pt->ty || ne < 2 || ne > 256) return 0.0;
    double h = 1e-6, d[256], mu[256];
    for (int j = 0; j < ne; j++) mu[j] = R->eig[j];
    double *y = malloc(sizeof(double) * (size_t)n);
    if (!y) return 0.0;
    for (int i = 0; i < n; i++) y[i] = pt->y[i] + h * pt->ty[i];
    sf_error e;
    sf_error_clear(&e);
    int bad = sf_stab_eval(st2, eq, y, pt->p + h * pt->tp, &e) || st2->res.neig < ne;
    free(y);
    if (bad) return 0.0;
    /* over h an eigenvalue moves by about h times its slope, a tiny part
     * of the spectrum's scale; a larger change means the two evaluations
     * returned different eigenvalues (the bounded ARPACK attempt of large
     * sheets can miss one: Miura 16x16 cells), whose differences predict
     * crossings at the distance h and collapsed the step to 1e-6 */
    double scale = 0.0;
    for (int j = 0; j < ne; j++) scale = fmax(scale, fabs(mu[j]));
    for (int j = 0; j < ne; j++)
        if (fabs(st2->res.eig[j] - mu[j]) > 1e-2 * scale) return 0.0;
    int nd = 0;
    for (int j = 0; j < ne; j++) {
        double slope = (st2->res.eig[j] - mu[j]) / h;
        if (mu[j] * slope < 0) d[nd++] = -mu[j] / slope;
    }
    qsort(d, (size_t)nd, sizeof *d, cmp_dbl);
    for (int i = 0; i + 1 < nd; i++) {
        if (d[i + 1] >= ds_next) break;
        if (d[i + 1] - d[i] > 1e-3 * d[i + 1]) return 0.5 * (d[i] + d[i + 1]);
    }
    return 0.0;
}

int sf_bif_check(sf_bif *b, const cont_point *pt, double s_offset, int first, sf_error *err)
{
    if (!b->stab) return SF_OK;
    const sf_stab_result *R = &b->stab->res;
    if (R->morse_unknown) return SF_OK;
    int lo, hi;
    sf_bif_morse_bounds(R, pt, 0, &lo, &hi);
    /* a tangent space of another dimension (the rank of the rows changed)
     * makes the two indices incomparable; a dimension not computed (-1, a
     * point certified stable from the corrector's matrix, stability.c)
     * does not stop the check */
    if (!b->prev_ok || first || b->in_check ||
        (R->dim >= 0 && b->prev_dim >= 0 && R->dim != b->prev_dim))
        return 0;
    int up = lo - b->prev_hi, down = b->prev_lo - hi;
    if (up <= 0 && down <= 0) return 0;
    int j0 = up > 0 ? b->prev_hi + 1 : hi + 1, j1 = up > 0 ? lo : b->prev_lo;
    int n = b->eq->n, morse_b = R->morse;
    long row_a = b->prev_row;
    double pa = b->prev_p, pb = pt->p, sa = b->prev_sarc, sb = pt->s + s_offset;
    if (fabs(pb - pa) <= 1e-12 * (1.0 + fabs(pa))) {
        sf_bif_note(b, "stability changes between rows %ld and %ld (branch %d, p = %.10g): the "
                    "Morse index goes from %d to %d, not located (p does not change there)",
                    row_a, *b->nrows, b->branch, pb, b->prev_lo, morse_b);
        return 0;
    }
    if (aux_solver(b)) return 0;
    /* every crossing eigenvalue, then the crossings grouped by place */
    int nc = j1 - j0 + 1;
    double *pc = malloc(sizeof(double) * (size_t)nc * (size_t)(n + 2));
    if (!pc) return sf_fail(err, SF_ENOMEM, "out of memory");
    double *wc = pc + nc, *yc = wc + nc;
    int nloc = 0;
    b->in_check = 1;
    for (int j = j0; j <= j1; j++) {
        /* at a the eigenvalue has not crossed yet: negative iff j <= lo(a) */
        int known_a = j <= b->prev_neig;
        double fa = known_a ? b->prev_eig[j - 1] : (j <= b->prev_lo ? -1.0 : 1.0);
        double w = sf_bif_locate_eig(b, b->prev_y, pa, fa, known_a, pt->y, pb, j, &pc[nloc]);
        if (w < 0) continue;
        wc[nloc] = w;
        memcpy(yc + (size_t)nloc * n, b->yt, sizeof(double) * (size_t)n);
        nloc++;
    }
    /* sort by distance from a */
    for (int i = 1; i < nloc; i++)
        for (int k = i; k > 0 && fabs(pc[k] - pa) < fabs(pc[k - 1] - pa); k--) {
            double t = pc[k]; pc[k] = pc[k - 1]; pc[k - 1] = t;
            t = wc[k]; wc[k] = wc[k - 1]; wc[k - 1] = t;
            for (int i2 = 0; i2 < n; i2++) {
                t = yc[(size_t)k * n + i2];
                yc[(size_t)k * n + i2] = yc[(size_t)(k - 1) * n + i2];
                yc[(size_t)(k - 1) * n + i2] = t;
            }
        }
    int rc = SF_OK;
    for (int i = 0; i < nloc && !rc;) {
        int k = i + 1;
        while (k < nloc && fabs(pc[k] - pc[i]) <= fmax(1e-7 * (1.0 + fabs(pc[i])), wc[i] + wc[k])) k++;
        int mult = k - i;
        /* the group's point: the solution of its first eigenvalue */
        const double *y = yc + (size_t)i * n;
        sf_error e;
        sf_error_clear(&e);
        if (sf_stab_eval(b->stab, b->eq, y, pc[i], &e)) { i = k; continue; }
        cont_point q;
        memset(&q, 0, sizeof q);
        double t = (pc[i] - pa) / (pb - pa), sarc = sa + t * (sb - sa);
        q.index = -1;
        q.y = y;
        q.p = pc[i];
        q.s = sarc - s_offset;
        q.ds = sarc - sa;
        q.loc_err = fabs(wc[i] / (pb - pa) * (sb - sa));
        if (mult == 1) snprintf(q.label, sizeof q.label, "BP");
        else snprintf(q.label, sizeof q.label, "BP%d", mult);
        /* a simple one: the secant of the branch as its tangent, for switching */
        double *ty = NULL;
        if (mult == 1 && (ty = malloc(sizeof(double) * (size_t)n))) {
            double nn = (pb - pa) * (pb - pa);
            for (int i2 = 0; i2 < n; i2++) {
                ty[i2] = pt->y[i2] - b->prev_y[i2];
                if (i2 < b->eq->nq) nn += ty[i2] * ty[i2];
            }
            nn = sqrt(nn);
            for (int i2 = 0; i2 < n; i2++) ty[i2] /= nn;
            q.ty = ty;
            q.tp = (pb - pa) / nn;
        }
        long row = *b->nrows;
        rc = b->h.emit ? b->h.emit(b->h.ctx, &q) : SF_OK;
        free(ty);
        sf_bif_note(b, "%s at row %ld (branch %d, p = %.10g) located from the Morse index "
                    "(%d eigenvalue%s of H_c cross%s zero there, between rows %ld and %ld, in one "
                    "step of the path; the determinant test cannot see %s)%s; located to within "
                    "%.3g in arclength%s", q.label, row,
                    b->branch, q.p, mult, mult > 1 ? "s" : "", mult > 1 ? "" : "es", row_a,
                    row + 1, mult > 1 ? "a multiple one" : "two crossings in one step",
                    mult > 1 ? "; a multiple branch point (its branches: from the reduced equations, "
                               "multibp.h, within analysis.branch_depth)" : "",
                    q.loc_err, q.loc_err > 1e-6 * (1.0 + fabs(q.p))
                                   ? " (Newton at fixed p does not converge closer to the singular point)"
                                   : "");
        i = k;
    }
    if (nloc < nc)
        sf_bif_note(b, "stability changes between rows %ld and %ld (branch %d, p from %.10g to "
                    "%.10g): %d of %d eigenvalue crossings could not be located (Newton at fixed "
                    "p failed or left the branch)", row_a, *b->nrows, b->branch, pa, pb,
                    nc - nloc, nc);
    free(pc);
    b->in_check = 0;
    if (rc) return rc;
    /* back to the point itself */
    if (sf_stab_eval(b->stab, b->eq, pt->y, pt->p, err)) return err->code;
    return SF_OK;
}

/* (bifurcation.h) */
int sf_bif_refine(sf_bif *b, const cont_point *pt, double s_offset, int first, cont_point *q,
                  double *ybuf)
{
    if (!b->stab) return 0;
    const sf_stab_result *R = &b->stab->res;
    if (strcmp(pt->label, "BP") != 0 || pt->loc_err <= 1e-6 * (1.0 + fabs(pt->p)) ||
        !b->prev_ok || first || R->neig < 1 || pt->p == b->prev_p)
        return 0;
    int j = 1;
    for (int i = 1; i < R->neig; i++)
        if (fabs(R->eig[i]) < fabs(R->eig[j - 1])) j = i + 1;
    if (j > b->prev_neig) return 0;
    if (aux_solver(b)) return 0;
    int n = b->eq->n, exact;
    double *w2 = malloc(sizeof(double) * 2 * (size_t)n);
    if (!w2) return 0;
    double *ybp = w2, *yc = w2 + n;
    memcpy(ybp, pt->y, sizeof(double) * (size_t)n);
    double fbp = R->eig[j - 1], fa = b->prev_eig[j - 1], pa = b->prev_p, pbp = pt->p, pz = pbp;
    double w = -1.0;
    b->in_check = 1;
    if ((fa > 0) != (fbp > 0)) {
        w = sf_bif_locate_eig(b, b->prev_y, pa, fa, 1, ybp, pbp, j, &pz);
    } else {
        double pc = pbp + (pbp - pa);
        memcpy(b->ya, b->prev_y, sizeof(double) * (size_t)n);
        memcpy(b->yb, ybp, sizeof(double) * (size_t)n);
        if (!solve_at(b, pa, pbp, pc)) {
            double fc = eig_j(b, j, &exact);
            if (exact && (fc > 0) != (fbp > 0)) {
                memcpy(yc, b->yt, sizeof(double) * (size_t)n);
                w = sf_bif_locate_eig(b, ybp, pbp, fbp, 1, yc, pc, j, &pz);
            }
        }
    }
    b->in_check = 0;
    double sarc = pt->s + s_offset, dsdp = fabs((sarc - b->prev_sarc) / (pbp - pa));
    if (w < 0 || w * dsdp > pt->loc_err) {
        free(w2);
        sf_error e;
        sf_error_clear(&e);
        sf_stab_eval(b->stab, b->eq, pt->y, pt->p, &e);
        return 0;
    }
    *q = *pt;
    q->index = -1;        /* not the engine's location (no note from write_point) */
    memcpy(ybuf, b->yt, sizeof(double) * (size_t)n);
    q->y = ybuf;
    q->p = pz;
    q->s = pt->s + (pz - pbp) * (sarc - b->prev_sarc) / (pbp - pa);
    q->loc_err = w * dsdp;
    sf_bif_note(b, "BP at row %ld (branch %d): the determinant location stopped %.3g (arclength) "
                "from it; located again on eigenvalue %d, to within %.3g, at p = %.10g%s",
                *b->nrows, b->branch, pt->loc_err, j, q->loc_err, pz,
                q->loc_err > 1e-6 * (1.0 + fabs(pz))
                    ? " (Newton at fixed p does not converge closer to the singular point)" : "");
    free(w2);
    return 1;
}

static int failed(const sf_bif *b) { return b->h.failed && b->h.failed(b->h.ctx); }

/* What identifies a branch up to the sheet's symmetries, at its first
 * point: p, the energy, the coordinates' magnitudes sorted. */
typedef struct bif_sig {
    int branch;
    double p, Pi;
    double *y, *mag;      /* state (n), sorted |q| (nq) */
} bif_sig;

static int sig_close(const bif_sig *a, const bif_sig *b, int nq, int n, int same_state)
{
    double tol = 1e-6;
    if (fabs(a->p - b->p) > tol * (1.0 + fabs(a->p))) return 0;
    if (same_state) {
        for (int i = 0; i < n; i++)
            if (fabs(a->y[i] - b->y[i]) > tol * (1.0 + fabs(a->y[i]))) return 0;
        return 1;
    }
    if (fabs(a->Pi - b->Pi) > tol * (1e-12 + fabs(a->Pi))) return 0;
    for (int i = 0; i < nq; i++)
        if (fabs(a->mag[i] - b->mag[i]) > tol * (1e-3 + fabs(a->mag[i]))) return 0;
    return 1;
}

/* The branches through a multiple branch point (multibp.h). */
static int switch_multi(sf_bif *b, cont_solver *cs, const sf_bif_bp *bp, sf_error *err)
{
    sf_equil *eq = b->eq;
    int n = eq->n, nq = eq->nq, rc = SF_OK;
    sf_mbp M;
    sf_error e;
    sf_error_clear(&e);
    if (sf_mbp_directions(eq, bp->y, bp->p, bp->mult, 0.02, 0.05 * (1.0 + fabs(bp->p)), &M, &e)) {
        sf_bif_note(b, "BP%d at row %ld (branch %d, p = %.10g): no switching: %s", bp->mult, bp->point,
             bp->branch, bp->p, e.msg);
        sf_mbp_free(&M);
        return SF_OK;
    }
    sf_bif_note(b, "BP%d at row %ld (branch %d, p = %.10g): Lyapunov-Schmidt reduction onto its "
         "two-dimensional kernel (eigenvalues of Jy %.3g and %.3g, next %.3g); %s reduced "
         "bifurcation equations (largest quadratic coefficient %.3g, cubic %.3g): %d isolated "
         "solutions (rays), branches %d..%d", bp->mult, bp->point, bp->branch, bp->p, M.eig[0],
         M.eig[1], M.eig[2], M.order == 2 ? "quadratic + cubic" : "cubic", M.bnorm, M.cnorm, M.ndir,
         b->nbranches + 1, b->nbranches + M.ndir);
    bif_sig *sig = calloc((size_t)M.ndir, sizeof *sig);
    double *sbuf = malloc(sizeof(double) * (size_t)M.ndir * (size_t)(n + nq + 1));
    int *cls = calloc((size_t)M.ndir + 1, sizeof(int)), ns = 0;
    if (!sig || !sbuf || !cls) {
        free(sig); free(sbuf); free(cls); sf_mbp_free(&M);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int k = 0; k < M.ndir && !rc; k++) {
        if (b->nbranches >= SF_BIF_MAX_BRANCHES) {
            sf_bif_note(b, "more than %d branches: not following the rest", SF_BIF_MAX_BRANCHES);
            break;
        }
        if (b->h.begin_branch && (rc = b->h.begin_branch(b->h.ctx, bp, b->nbranches + 1))) break;
        b->nbranches++;
        b->branch = b->nbranches;
        b->depth = bp->depth + 1;
        long first = *b->nrows;
        int st = cont_start_tangent(cs, M.y + (size_t)k * n, M.p[k], M.ty + (size_t)k * n, M.tp[k]);
        if (failed(b)) { rc = err->code; break; }
        if (st != CONT_OK) {
            sf_bif_note(b, "branch %d (from the BP%d at row %ld, ray at %.6f rad in its kernel) did not "
                 "start: %s", b->branch, bp->mult, bp->point, M.theta[k], cont_errmsg(cs));
            continue;
        }
        const cont_point *pt = cont_get_point(cs);
        bif_sig *g = &sig[ns];
        g->branch = b->branch;
        g->p = pt->p;
        g->y = sbuf + (size_t)ns * (n + nq + 1);
        g->mag = g->y + n;
        memcpy(g->y, pt->y, sizeof(double) * (size_t)n);
        for (int i = 0; i < nq; i++) g->mag[i] = fabs(pt->y[i]);
        qsort(g->mag, (size_t)nq, sizeof(double), cmp_dbl);
        double rr, rt;
        sf_equil_report(eq, pt->y, pt->p, &g->Pi, &rr, &rt);
        int dup = -1;
        for (int j = 0; j < ns && dup < 0; j++)
            if (sig_close(&sig[j], g, nq, n, 1)) dup = j;
        if (dup >= 0) {
            sf_bif_note(b, "branch %d (from the BP%d at row %ld) duplicates branch %d: not followed",
                 b->branch, bp->mult, bp->point, sig[dup].branch);
            continue;
        }
        cls[ns] = ns;
        for (int j = 0; j < ns; j++)
            if (sig_close(&sig[j], g, nq, n, 0)) { cls[ns] = cls[j]; break; }
        ns++;
        st = cont_run(cs);
        if (failed(b)) { rc = err->code; break; }
        if (st != CONT_OK && st != CONT_DONE)
            sf_bif_note(b, "branch %d (from the BP%d at row %ld) stopped after %ld points: %s", b->branch,
                 bp->mult, bp->point, *b->nrows - first, cont_errmsg(cs));
    }
    if (!rc && ns > 0) {
        char line[900];
        int len = 0, ncls = 0;
        for (int c = 0; c < ns; c++) {
            if (cls[c] != c) continue;
            ncls++;
            len += snprintf(line + len, sizeof line - (size_t)len, " [");
            for (int j = c; j < ns && len < (int)sizeof line - 16; j++)
                if (cls[j] == c) len += snprintf(line + len, sizeof line - (size_t)len, "%s%d",
                                                 line[len - 1] == '[' ? "" : " ", sig[j].branch);
            len += snprintf(line + len, sizeof line - (size_t)len, "]");
        }
        sf_bif_note(b, "BP%d at row %ld: %d distinct branches in %d classes of symmetric images (same "
             "p, energy and sorted |q| at their first points):%s", bp->mult, bp->point, ns, ncls, line);
    }
    free(sig);
    free(sbuf);
    free(cls);
    sf_mbp_free(&M);
    return rc;
}

/* (bifurcation.h) */
int sf_bif_switch(sf_bif *b, cont_solver *cs, sf_error *err)
{
    sf_equil *eq = b->eq;
    int n = eq->n;
    double *t2 = malloc(sizeof(double) * (size_t)(n + 1));
    if (!t2) return sf_fail(err, SF_ENOMEM, "out of memory");
    int rc = SF_OK;
    while (!rc && b->nextbp < b->nbp) {
        sf_bif_bp bp = b->bp[b->nextbp++];
        double tp2;
        if (bp.mult >= 2) {
            rc = switch_multi(b, cs, &bp, err);
            b->bp[b->nextbp - 1].switched = 1;
            continue;
        }
        if (cont_branch_direction(cs, bp.y, bp.p, bp.ty, bp.tp, t2, &tp2) != CONT_OK) {
            sf_bif_note(b, "branch point at row %ld (branch %d, p = %.10g): no switching: %s",
                        bp.point, bp.branch, bp.p, cont_errmsg(cs));
            continue;
        }
        for (int sgn = 1; sgn >= -1 && !rc; sgn -= 2) {
            if (b->nbranches >= SF_BIF_MAX_BRANCHES) {
                sf_bif_note(b, "more than %d branches: not following the rest", SF_BIF_MAX_BRANCHES);
                free(t2);
                return SF_OK;
            }
            double *t = malloc(sizeof(double) * (size_t)n);
            if (!t) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
            for (int i = 0; i < n; i++) t[i] = sgn * t2[i];
            if (b->h.begin_branch && (rc = b->h.begin_branch(b->h.ctx, &bp, b->nbranches + 1))) {
                free(t);
                break;
            }
            b->nbranches++;
            b->branch = b->nbranches;
            b->depth = bp.depth + 1;
            long first = *b->nrows;
            int st = cont_start_tangent(cs, bp.y, bp.p, t, sgn * tp2);
            if (st == CONT_OK && !failed(b)) st = cont_run(cs);
            free(t);
            if (failed(b)) { rc = err->code; break; }
            if (st != CONT_OK && st != CONT_DONE)
                sf_bif_note(b, "branch %d (from the branch point at row %ld, %s side) stopped "
                            "after %ld points: %s", b->branch, bp.point, sgn > 0 ? "+" : "-",
                            *b->nrows - first, cont_errmsg(cs));
        }
        b->bp[b->nextbp - 1].switched = 1;
    }
    free(t2);
    return rc;
}
