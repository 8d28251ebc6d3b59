/* d4_test.h - the symmetry group D4 of a square sheet centred at the
 * origin, as permutations of its folds (include after cmocka.h and
 * sf_test.h).  Shared by test_multibp.c and test_flatswitch.c. */
#ifndef SF_D4_TEST_H
#define SF_D4_TEST_H

#include "study.h"

#define NG 8
#define MAXF 64

/* perm[g][f]: the fold that element g of D4 maps fold f to. */
static void d4_perms(const sf_study *s, int perm[NG][MAXF])
{
    assert_true(s->nfolds <= MAXF);
    for (int g = 0; g < NG; g++)
        for (int f = 0; f < s->nfolds; f++) {
            double e[2][2];
            for (int k = 0; k < 2; k++) {
                const double *x = s->vertices[k ? s->folds[f].b : s->folds[f].a].x;
                double X = x[0], Y = x[1];
                if (g >= 4) Y = -Y;                       /* reflection, then rotation */
                for (int r = 0; r < g % 4; r++) { double t = X; X = -Y; Y = t; }
                e[k][0] = X;
                e[k][1] = Y;
            }
            int found = -1;
            for (int h = 0; h < s->nfolds && found < 0; h++) {
                const double *a = s->vertices[s->folds[h].a].x, *b = s->vertices[s->folds[h].b].x;
                double d1 = fabs(a[0] - e[0][0]) + fabs(a[1] - e[0][1]) + fabs(b[0] - e[1][0]) + fabs(b[1] - e[1][1]);
                double d2 = fabs(a[0] - e[1][0]) + fabs(a[1] - e[1][1]) + fabs(b[0] - e[0][0]) + fabs(b[1] - e[0][1]);
                if (d1 < 1e-12 || d2 < 1e-12) found = h;
            }
            if (found < 0) {
                print_error("the sheet is not D4-symmetric: element %d maps fold %d to no fold\n", g, f + 1);
                fail();
            }
            perm[g][f] = found;
        }
}

#endif
