/* test_sstab_cost.c - the two cost rules of the bounded effort of sstab.h
 * (docs/design/linear-algebra.md, "Cost"), against closed forms:
 *  - a tangent space of dimension 50 whose smallest eigenvalue has 12
 *    exact copies (a flat sheet's cluster of bending modes in miniature):
 *    the one bounded ARPACK attempt gets a subspace as large as the
 *    tangent space and finds the 4 smallest, all 1 (before: ncv 21, it
 *    missed copies: the Sturm count showed 9 missed, no eigenvalues);
 *  - constraint rows of full rank n (no tangent space), one of them 1e-8
 *    from the span of the others: the check whether the rows of the last
 *    QR still span C fails on its round-off, so the next 7 points skip it
 *    and the QR decides (after the 2nd and 3rd failure in a row, the next
 *    15 and 31); rank, stability and Morse index are those of a fresh
 *    object (a QR at every point) at every point;
 *  - constraint rows with a tangent space, one of them 6e-11 from the span
 *    of the others (below the QR's cut 1e-9, above the check's bound
 *    1e-11): every check fails; after f failures in a row the next
 *    2^(f-1) - 1 checks (at most 7) are left out: 5 checks in 20 points
 *    (19 before); rank, Morse index and eigenvalues those of a fresh
 *    object at every point.
 *  - the step bound's second evaluation (sf_sstab_follow_rows): an object
 *    that follows another takes its independent rows at a point 1e-6
 *    away, with no QR or check of its own; rank, Morse index and
 *    eigenvalues those of a fresh object there; the lead's results those
 *    of a twin without a follower, to the last bit; a row of the lead's
 *    set that is zero at the new point: the follower decides itself (a
 *    QR).
 * Runs in well under a second. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sf_test.h"
#include "ldlt.h"
#include "sstab.h"

#define NC 60     /* coordinates of the cluster case */
#define PIN 10    /* coordinates 0..PIN-1 pinned */
#define COPIES 12 /* copies of the eigenvalue 1 */

static void test_cluster_bounded(void **state)
{
    (void)state;
    /* HL: diagonal, -5 on the pinned coordinates (H_c does not see them),
     * then 1 (COPIES times), 2, 3, ... on the free ones; C: e_i, i < PIN,
     * and a copy 2 e_0 (redundant) */
    static int cp[NC + 1], ri[NC], ccp[NC + 1], cri[PIN + 1];
    static double v[NC], cv[PIN + 1];
    int t = 0;
    for (int j = 0; j < NC; j++) {
        cp[j] = j;
        ri[j] = j;
        v[j] = j < PIN ? -5.0 : j < PIN + COPIES ? 1.0 : (double)(j - PIN - COPIES + 2);
        ccp[j] = t;
        if (j == 0) {
            cri[t] = 0;
            cv[t++] = 1.0;
            cri[t] = PIN;
            cv[t++] = 2.0;
        } else if (j < PIN) {
            cri[t] = j;
            cv[t++] = 1.0;
        }
    }
    cp[NC] = NC;
    ccp[NC] = t;
    sf_csc H = {NC, NC, cp, ri, v}, C = {PIN + 1, NC, ccp, cri, cv};
    sf_sstab *st;
    sf_error err;
    sf_error_clear(&err);
    sf_sstab_opts o = {.nev = 4, .effort = SF_SSTAB_EIG_BOUNDED};
    assert_int_equal(sf_sstab_create(&st, NC, PIN + 1, &o, &err), SF_OK);
    assert_int_equal(sf_sstab_eval(st, &H, &C, &err), SF_OK);
    const sf_sstab_result *R = sf_sstab_get(st);
    print_message("# cluster of %d: rank %d, dim %d, Morse index %d, %d eigenvalues (%.15g ...), "
                  "%d solves %s\n", COPIES, R->rank, R->dim, R->morse, R->neig,
                  R->neig ? R->eig[0] : 0.0, R->nop, R->reason);
    assert_int_equal(R->status, SF_SSTAB_OK);
    assert_int_equal(R->rank, PIN);
    assert_int_equal(R->dim, NC - PIN);
    assert_int_equal(R->morse, 0);
    assert_int_equal(R->stable, 1);
    assert_int_equal(R->neig, 4);
    for (int i = 0; i < 4; i++) assert_true(fabs(R->eig[i] - 1.0) < 1e-9);
    /* a few restarts of a subspace of the tangent dimension */
    assert_true(R->nop <= 10 * (NC - PIN));
    sf_sstab_free(st);
}

#define NS 40 /* coordinates of the square case */

/* Evaluate st (the path's object, reusing rows) at (H, C) and a fresh
 * object (*ref, deciding with a QR) at the same point; their rank and
 * verdicts must agree.  Returns st's result, *F the fresh one (free *ref). */
static const sf_sstab_result *eval_against_fresh(sf_sstab *st, const sf_csc *H, const sf_csc *C,
                                                 const sf_sstab_opts *o, sf_sstab **ref,
                                                 const sf_sstab_result **F)
{
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_sstab_eval(st, H, C, &err), SF_OK);
    const sf_sstab_result *R = sf_sstab_get(st);
    assert_int_equal(sf_sstab_create(ref, H->ncol, C->nrow, o, &err), SF_OK);
    assert_int_equal(sf_sstab_eval(*ref, H, C, &err), SF_OK);
    *F = sf_sstab_get(*ref);
    assert_int_equal(R->rank, (*F)->rank);
    assert_int_equal(R->stable, (*F)->stable);
    assert_int_equal(R->morse, (*F)->morse);
    assert_int_equal(R->status, (*F)->status);
    return R;
}

/* The lower triangle of HL = tridiag(off, diag, off) (NS x NS) and the
 * dense nc x NS matrix Cd, both into CSC arrays. */
static void pack_case(int nc, const double (*Cd)[NS], double diag, double off, int *cp, int *ri,
                      double *v, int *ccp, int *cri, double *cv)
{
    int t = 0, u = 0;
    for (int j = 0; j < NS; j++) {
        cp[j] = t;
        ri[t] = j;
        v[t++] = diag;
        if (j + 1 < NS) {
            ri[t] = j + 1;
            v[t++] = off;
        }
        ccp[j] = u;
        for (int i = 0; i < nc; i++)
            if (Cd[i][j] != 0.0) {
                cri[u] = i;
                cv[u++] = Cd[i][j];
            }
    }
    cp[NS] = t;
    ccp[NS] = u;
}

/* C (NS + 1 rows): rows 0..NS-2 r_i = e_i + 0.3 sin(i) e_{i+1} + 0.7 cos(i)
 * e_{(i+5) mod NS} (independent), row NS-1 = r_3 + r_17 + 1e-8 a e_{NS-1}
 * (as a unit row about 1e-8 a from the span of the others, above the
 * QR's cut 1e-9: rank NS), row NS = 3 r_0 (redundant).  HL: -1 on the
 * diagonal and next to it (indefinite, but H_c is empty). */
static void square_case(double a, int *cp, int *ri, double *v, int *ccp, int *cri, double *cv)
{
    static double Cd[NS + 1][NS];
    memset(Cd, 0, sizeof Cd);
    for (int i = 0; i < NS - 1; i++) {
        Cd[i][i] += 1.0;
        Cd[i][i + 1] += 0.3 * sin(i);
        Cd[i][(i + 5) % NS] += 0.7 * cos(i);
    }
    for (int j = 0; j < NS; j++) {
        Cd[NS - 1][j] = Cd[3][j] + Cd[17][j];
        Cd[NS][j] = 3.0 * Cd[0][j];
    }
    Cd[NS - 1][NS - 1] += 1e-8 * a;
    pack_case(NS + 1, Cd, -1.0, -1.0, cp, ri, v, ccp, cri, cv);
}

static void test_square_rows(void **state)
{
    (void)state;
    static int cp[NS + 1], ri[2 * NS], ccp[NS + 1], cri[8 * NS];
    static double v[2 * NS], cv[8 * NS];
    sf_sstab *st;
    sf_error err;
    sf_error_clear(&err);
    sf_sstab_opts o = {.nev = 2, .effort = SF_SSTAB_EIG_BOUNDED};
    assert_int_equal(sf_sstab_create(&st, NS, NS + 1, &o, &err), SF_OK);
    int npts = 30;
    for (int k = 0; k < npts; k++) {
        double a = 1.0 + 0.01 * k;
        square_case(a, cp, ri, v, ccp, cri, cv);
        sf_csc H = {NS, NS, cp, ri, v}, C = {NS + 1, NS, ccp, cri, cv};
        sf_sstab *ref;
        const sf_sstab_result *F, *R = eval_against_fresh(st, &H, &C, &o, &ref, &F);
        print_message("# square, point %d: rank %d (fresh %d), stable %d, %d QRs, %d checks, "
                      "%d reused\n", k, R->rank, F->rank, R->stable, R->rank_qr, R->rank_checks,
                      R->rank_reused);
        assert_int_equal(R->rank, NS);
        assert_int_equal(R->dim, 0);
        /* point 0: a QR; point 1: a check (fails on round-off); points 2..8:
         * no check, a QR each; point 9: a check again (fails: 2 in a row);
         * points 10..24 none; point 25 a check (3 in a row), then every 32nd */
        assert_int_equal(R->rank_reused, 0);
        assert_int_equal(R->rank_qr, k + 1);
        int checks = k == 0 ? 0 : k < 9 ? 1 : k < 25 ? 2 : 3 + (k - 25) / 32;
        assert_int_equal(R->rank_checks, checks);
        sf_sstab_free(ref);
    }
    sf_sstab_free(st);
}

/* C (NT + 1 rows): rows 0..NT-1 r_i = e_i + 0.3 sin(i) e_{i+1} + 0.7
 * cos(i) e_{(i+5) mod NS} (independent), row NT = r_3 + r_17 + 1e-10 a
 * e_{NS-1} (as a unit row about 6e-11 a from the span of the others: the
 * QR drops it, the check's bound 1e-11 sees it).  HL: tridiag(-0.5, 2 +
 * 0.1 a, -0.5), positive definite: stable, tangent space NS - NT. */
#define NT 30
static double streak_eps = 1e-10; /* test_follow_rows: also 3e-9, a weak row (K_w) */
static void streak_case(double a, int *cp, int *ri, double *v, int *ccp, int *cri, double *cv)
{
    static double Cd[NT + 1][NS];
    memset(Cd, 0, sizeof Cd);
    for (int i = 0; i < NT; i++) {
        Cd[i][i] += 1.0;
        Cd[i][i + 1] += 0.3 * sin(i);
        Cd[i][(i + 5) % NS] += 0.7 * cos(i);
    }
    for (int j = 0; j < NS; j++) Cd[NT][j] = Cd[3][j] + Cd[17][j];
    Cd[NT][NS - 1] += streak_eps * a;
    pack_case(NT + 1, Cd, 2.0 + 0.1 * a, -0.5, cp, ri, v, ccp, cri, cv);
}

static void test_streak_rows(void **state)
{
    (void)state;
    static int cp[NS + 1], ri[2 * NS], ccp[NS + 1], cri[8 * NS];
    static double v[2 * NS], cv[8 * NS];
    sf_sstab *st;
    sf_error err;
    sf_error_clear(&err);
    sf_sstab_opts o = {.nev = 2, .effort = SF_SSTAB_EIG_BOUNDED};
    assert_int_equal(sf_sstab_create(&st, NS, NT + 1, &o, &err), SF_OK);
    const int npts = 20;
    for (int k = 0; k < npts; k++) {
        double a = 1.0 + 0.01 * k;
        streak_case(a, cp, ri, v, ccp, cri, cv);
        sf_csc H = {NS, NS, cp, ri, v}, C = {NT + 1, NS, ccp, cri, cv};
        sf_sstab *ref;
        const sf_sstab_result *F, *R = eval_against_fresh(st, &H, &C, &o, &ref, &F);
        print_message("# streak, point %d: rank %d (fresh %d), stable %d, eig1 %.15g (fresh "
                      "%.15g), %d QRs, %d checks, %d reused\n", k, R->rank, F->rank, R->stable,
                      R->neig ? R->eig[0] : NAN, F->neig ? F->eig[0] : NAN, R->rank_qr,
                      R->rank_checks, R->rank_reused);
        assert_int_equal(R->rank, NT);
        assert_int_equal(R->stable, 1);
        assert_int_equal(R->neig, 2);
        assert_int_equal(R->neig, F->neig);
        for (int i = 0; i < R->neig; i++)
            CHECK_CLOSE(R->eig[i], F->eig[i], 1e-10 * fabs(F->eig[i]), "eigenvalue");
        /* checks at points 1, 2, 4, 8, 16 (f failures in a row leave out
         * the next 2^(f-1) - 1, at most 7); a QR at every point */
        assert_int_equal(R->rank_reused, 0);
        assert_int_equal(R->rank_qr, k + 1);
        int checks = k == 0 ? 0 : k < 2 ? 1 : k < 4 ? 2 : k < 8 ? 3 : k < 16 ? 4 : 5;
        assert_int_equal(R->rank_checks, checks);
        sf_sstab_free(ref);
    }
    sf_sstab_free(st);
}

static void follow_case(double eps);

static void test_follow_rows(void **state)
{
    (void)state;
    follow_case(1e-10);
    follow_case(3e-9);
    streak_eps = 1e-10;
}

/* eps 1e-10: the near-dependent row is dropped; 3e-9: it is kept as a
 * weak row (Heath residual below 1e-8), K_w at every point */
static void follow_case(double eps)
{
    streak_eps = eps;
    int nt = eps < 1e-9 ? NT : NT + 1; /* the rank */
    static int cp[NS + 1], ri[2 * NS], ccp[NS + 1], cri[8 * NS];
    static double v[2 * NS], cv[8 * NS];
    sf_sstab *lead, *fol;
    sf_error err;
    sf_error_clear(&err);
    sf_sstab_opts o = {.nev = 2, .effort = SF_SSTAB_EIG_BOUNDED};
    assert_int_equal(sf_sstab_create(&lead, NS, NT + 1, &o, &err), SF_OK);
    assert_int_equal(sf_sstab_create(&fol, NS, NT + 1, &o, &err), SF_OK);
    sf_sstab *alone; /* the lead's twin without a follower: the lead's results must be its */
    assert_int_equal(sf_sstab_create(&alone, NS, NT + 1, &o, &err), SF_OK);
    sf_sstab_follow_rows(fol, lead);
    for (int k = 0; k < 4; k++) {
        double a = 1.0 + 0.01 * k;
        streak_case(a, cp, ri, v, ccp, cri, cv);
        sf_csc H = {NS, NS, cp, ri, v}, C = {NT + 1, NS, ccp, cri, cv};
        assert_int_equal(sf_sstab_eval(lead, &H, &C, &err), SF_OK);
        assert_int_equal(sf_sstab_eval(alone, &H, &C, &err), SF_OK);
        const sf_sstab_result *L = sf_sstab_get(lead), *A = sf_sstab_get(alone);
        assert_int_equal(L->neig, A->neig);
        for (int i = 0; i < L->neig; i++) assert_true(L->eig[i] == A->eig[i]);
        assert_int_equal(L->analyses, A->analyses);
        assert_int_equal(L->nop, A->nop);
        int lead_qr = L->rank_qr, lead_checks = L->rank_checks;
        streak_case(a + 1e-6, cp, ri, v, ccp, cri, cv);
        if (k == 3)
            for (int t = 0; t < ccp[NS]; t++)
                if (cri[t] == 5) cv[t] = 0.0; /* a row of the lead's set is zero here */
        sf_sstab *ref;
        const sf_sstab_result *F, *R = eval_against_fresh(fol, &H, &C, &o, &ref, &F);
        print_message("# follow (eps %g), point %d: rank %d (fresh %d), eig1 %.15g (fresh %.15g), "
                      "%d QRs, %d checks (lead: %d, %d), %d analyses; %s\n", eps, k, R->rank,
                      F->rank, R->neig ? R->eig[0] : NAN, F->neig ? F->eig[0] : NAN, R->rank_qr,
                      R->rank_checks, L->rank_qr, L->rank_checks, R->analyses, R->reason);
        assert_int_equal(R->stable, 1);
        assert_int_equal(R->neig, F->neig);
        for (int i = 0; i < R->neig; i++)
            CHECK_CLOSE(R->eig[i], F->eig[i], 1e-10 * fabs(F->eig[i]), "eigenvalue");
        /* the lead's rows: no QR or check of its own; the lead untouched.
         * Point 3: its own decision, a check of the set it last took
         * (fails: a row is zero) and a QR */
        assert_int_equal(R->rank, k < 3 ? nt : nt - 1);
        assert_int_equal(R->rank_qr, k < 3 ? 0 : 1);
        assert_int_equal(R->rank_checks, k < 3 ? 0 : 1);
        assert_int_equal(L->rank_qr, lead_qr);
        assert_int_equal(L->rank_checks, lead_checks);
        sf_sstab_free(ref);
    }
    sf_sstab_free(fol);
    sf_sstab_free(lead);
    sf_sstab_free(alone);
    /* the workspace relaxation: MUMPS's 20 % until set */
    sf_ldlt *f;
    assert_int_equal(sf_ldlt_create(&f, 0.0, &err), SF_OK);
    assert_int_equal(sf_ldlt_relaxation(f), 20);
    sf_ldlt_set_relaxation(f, 160);
    assert_int_equal(sf_ldlt_relaxation(f), 160);
    sf_ldlt_set_relaxation(f, 40);
    assert_int_equal(sf_ldlt_relaxation(f), 40);
    sf_ldlt_free(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cluster_bounded),
        cmocka_unit_test(test_square_rows),
        cmocka_unit_test(test_streak_rows),
        cmocka_unit_test(test_follow_rows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
