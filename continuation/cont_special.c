/* cont_special.c - special points (cont.h, ALGORITHM): evaluation of a
 * corrected point (Jacobian, tangent, determinant sign, user test
 * functions), the test-function values (LP, BP, user tests, p - p_b), the
 * location of their zeros between two points (Illinois regula falsi with
 * a branch-jump guard), and landing on p = p_b at the end of the range. */
#include "cont_impl.h"

#include <stdlib.h>
#include <string.h>

/* At the corrected point q->x: Jacobian, bordered matrix [Jy Fp; c^T],
 * determinant, tangent (unless keep_t: q->t already holds it and
 * c = W q->t), test functions.
 * Returns 0, -1 (numerical failure: reason in s->why) or CONT_EUSER (a user
 * test function failed: fatal). */
int ci_eval_point(cont_solver *s, cpt *q, const double *c, int dir, int keep_t)
{
    long n = s->n, m = s->m;
    if (ci_call_jacobian(s, q->x, q->x[n]) != 0) return -1;
    int sg = 0;
    double ld = 0.0;
    /* the corrector's last factors, refined, or a factorisation here
     * (always with cont_set_point_inertia: its inertia goes with the point) */
    int fr = -1, reused = 0;
    q->pub.jy_inertia = 0;
    if (s->point_inertia) s->rgen = -1;
    else reused = !keep_t && ci_tangent_reuse(s, c, &sg, &ld) == 0;
    if (!reused) {
        if (ci_bm_build(s, &s->bt, c) != 0) return -1;
        fr = ci_bm_factor(s, &s->bt, &sg, &ld);
        if (fr == 0 && s->point_inertia && s->bt.blk_active) {
            ci_blk_inertia(&s->bt, &q->pub.jy_neg, &q->pub.jy_null);
            q->pub.jy_inertia = q->pub.jy_neg >= 0;
        }
    }
    if (keep_t) {
        q->det_valid = fr == 0;
        q->pub.det_sign = fr == 0 ? sg : 0;
        q->pub.log_abs_det = fr == 0 ? ld : -HUGE_VAL;
    } else {
        if (!reused) {
            if (fr != 0) return -1;
            N_VConst(0.0, s->vb);
            NV_Ith_S(s->vb, n) = 1.0;
            if (ci_bm_solve(s, &s->bt, s->vx, s->vb) != 0) return -1;
        }
        double *v = N_VGetArrayPointer(s->vx);
        double nv = sqrt(ci_dotw(s, v, v));
        if (!(nv > 0) || !isfinite(nv)) {
            ci_why(s, "tangent has zero or non-finite norm");
            return -1;
        }
        for (long i = 0; i < m; i++) q->t[i] = dir * v[i] / nv;
        /* det [A; (W t)^T] = dir |v|_W det [A; c^T]  (see cont.h) */
        q->det_valid = 1;
        q->pub.det_sign = dir * sg;
        q->pub.log_abs_det = ld + log(nv);
    }
    ci_pt_sync(s, q);
    if (s->prob.ntest > 0) {
        int r = s->prob.test(q->x, q->x[n], q->t, q->t[n], q->test, s->prob.user);
        if (r != 0)
            return ci_fail(s, CONT_EUSER, "test function returned %d at p = %.10g", r, q->x[n]);
        if (!ci_all_finite(q->test, s->prob.ntest))
            return ci_fail(s, CONT_EUSER, "test function produced a non-finite value at p = %.10g",
                        q->x[n]);
    }
    return 0;
}

/* Value of test `id` at q; ref is the log|det| scale for TEST_BP. */
double ci_test_value(const cont_solver *s, int id, const cpt *q, double ref, double pb)
{
    if (id == TEST_LP) return q->t[s->n];
    if (id == TEST_PB) return q->x[s->n] - pb;
    if (id == TEST_BP) {
        double e = q->pub.log_abs_det - ref;
        if (e > 700) e = 700;
        if (e < -700) e = -700;
        return q->pub.det_sign * exp(e);
    }
    return q->test[id];
}

/* Locate the zero of test `id` between the step base b (h = 0) and xe
 * (h = he).  *res receives a new point (caller owns).  Returns 0, -1 (no
 * point could be corrected: *res NULL) or CONT_EUSER. */
int ci_locate(cont_solver *s, int id, const cpt *b, const cpt *xe, double he,
              double pb, cpt **res)
{
    long n = s->n, m = s->m;
    cpt *lo = s->lw[0], *hi = s->lw[1], *tr = s->lw[2];
    double *c = s->cw;
    ci_weigh(s, b->t, c);
    ci_pt_copy(s, lo, b);
    ci_pt_copy(s, hi, xe);
    lo->h = 0.0;
    hi->h = he;
    double ref = b->pub.log_abs_det;
    double fa = ci_test_value(s, id, lo, ref, pb), fb = ci_test_value(s, id, hi, ref, pb);
    double fa_true = fa, fb_true = fb;
    int side = 0, nit = 0, it;
    double ha = 0.0, hb = he;
    cpt *zero = NULL;
    for (it = 0; it < LOC_MAXIT; it++) {
        double tol = s->loc_tol * (1.0 + s->theta * fabs(hi->x[n]));
        if (hb - ha <= tol) break;
        double h = (fa * hb - fb * ha) / (fa - fb);
        if (!(h > ha && h < hb)) h = 0.5 * (ha + hb);
        int r = -1;
        for (int attempt = 0; attempt < 2 && r != 0; attempt++) {
            if (attempt == 1) h = 0.5 * (ha + hb);
            double w = (h - ha) / (hb - ha);
            for (long i = 0; i < m; i++) tr->x[i] = lo->x[i] + w * (hi->x[i] - lo->x[i]);
            double fn;
            s->stp.nlocate++;
            r = s->anchor_first ? ci_correct_step(s, tr->x, c, b->x, h, &nit, &fn)
                                : ci_correct(s, tr->x, c, b->x, h, s->max_newton, s->strategy, &nit, &fn);
            if (r == 0) {
                r = ci_eval_point(s, tr, c, +1, 0);
                if (r == CONT_EUSER) return r;
                tr->pub.resnorm = fn;
            }
            if (r == 0) {
                /* Branch guard: near a branch point the hyperplane also cuts
                 * the other branch and Newton may converge there.  Along one
                 * smooth branch the tangent turns by about the angle between
                 * the bracket ends, so a trial tangent turned further away
                 * from either end marks a jump. */
                double lim = acos(fmax(-1.0, fmin(1.0, ci_dotw(s, lo->t, hi->t)))) + GUARD_ANGLE;
                double al = acos(fmax(-1.0, fmin(1.0, ci_dotw(s, tr->t, lo->t))));
                double ah = acos(fmax(-1.0, fmin(1.0, ci_dotw(s, tr->t, hi->t))));
                if (al > lim || ah > lim) {
                    ci_why(s, "locating: trial point jumped to another branch");
                    r = -1;
                }
            }
        }
        if (r != 0) break;          /* give up: keep the best end */
        tr->pub.newton_iters = nit;
        tr->h = h;
        double ft = ci_test_value(s, id, tr, ref, pb);
        if (ft == 0.0) {
            zero = tr;
            break;
        }
        if (!ci_differ(ft, fb_true)) {
            cpt *tmp = hi; hi = tr; tr = tmp;
            hb = h; fb = fb_true = ft;
            if (side == -1) fa *= 0.5;
            side = -1;
        } else {
            cpt *tmp = lo; lo = tr; tr = tmp;
            ha = h; fa = fa_true = ft;
            if (side == +1) fb *= 0.5;
            side = +1;
        }
    }
    /* restore the scratch ring (pointers were swapped) */
    s->lw[0] = lo; s->lw[1] = hi; s->lw[2] = tr;
    const cpt *best = zero ? zero : (fabs(fa_true) <= fabs(fb_true) ? lo : hi);
    cpt *q = ci_pt_dup(s, best);
    if (!q) return ci_fail(s, CONT_ENOMEM, "out of memory");
    q->pub.loc_err = zero ? 0.0 : hb - ha;
    q->pub.ds = q->h;
    q->terminal = 0;
    *res = q;
    return 0;
}

/* Land on p = pb between the base b and x1 (which lies beyond pb).  *res
 * gets the new point.  0, -1 or CONT_EUSER. */
int ci_land(cont_solver *s, const cpt *b, const cpt *x1, double pb, cpt **res)
{
    long n = s->n, m = s->m;
    *res = NULL;
    cpt *q = ci_pt_new(s);
    if (!q) return ci_fail(s, CONT_ENOMEM, "out of memory");
    double lam = (pb - b->x[n]) / (x1->x[n] - b->x[n]);
    if (!isfinite(lam)) lam = 1.0;
    for (long i = 0; i < m; i++) q->x[i] = b->x[i] + lam * (x1->x[i] - b->x[i]);
    q->x[n] = pb;
    double *c = calloc((size_t)m, sizeof(double));
    double *xa = malloc((size_t)m * sizeof(double));
    if (!c || !xa) {
        free(c); free(xa); ci_pt_free(q);
        return ci_fail(s, CONT_ENOMEM, "out of memory");
    }
    c[n] = 1.0;
    memcpy(xa, q->x, (size_t)m * sizeof(double));
    int nit;
    double fn;
    int r = s->anchor_first ? ci_correct_step(s, q->x, c, xa, 0.0, &nit, &fn)
                            : ci_correct(s, q->x, c, xa, 0.0, s->max_newton, s->strategy, &nit, &fn);
    free(c);
    free(xa);
    if (r == 0) {
        q->x[n] = pb;   /* exactly */
        ci_weigh(s, b->t, s->cw);
        r = ci_eval_point(s, q, s->cw, +1, 0);
        if (r == CONT_EUSER) {
            ci_pt_free(q);
            return r;
        }
    }
    if (r == 0) {
        q->h = ci_dotw(s, b->t, q->x) - ci_dotw(s, b->t, b->x);
        /* the solution at p = pb must lie within the step, not on another
         * part of the solution set */
        if (!(q->h >= -1e-9 * x1->h && q->h <= 2.0 * x1->h)) r = -1;
    }
    if (r == 0) {
        q->pub.newton_iters = nit;
        q->pub.resnorm = fn;
        q->pub.ds = q->h;
        *res = q;
        return 0;
    }
    /* Fallback (Jy singular at pb?): locate p - pb on the branch. */
    ci_pt_free(q);
    r = ci_locate(s, TEST_PB, b, x1, x1->h, pb, res);
    if (r != 0) return r;
    if (fabs((*res)->x[n] - pb) > 1e-8 * (1.0 + fabs(pb))) {
        ci_pt_free(*res);
        *res = NULL;
        return -1;
    }
    return 0;
}
