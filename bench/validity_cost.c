/* validity_cost.c - CPU time of one physical-validity check
 * (src/analysis/validity/validity.h) of a study's sheet: every fold at 0.3 rad
 * with the sign of its assignment or rest angle (a gently folded sheet,
 * loops nearly closed: no crossings), the tree's pairs and, below a
 * size, every pair of parts (brute force).  Usage:
 *   validity_cost STUDY.cfg REPEATS BRUTE(0|1)
 * Prints: parts, triangles, part pairs the tree gave, triangle pairs
 * tested, seconds per check (tree), seconds per check (all pairs). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "scene.h"
#include "validity.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 4) return 2;
    int reps = atoi(argv[2]), brute = atoi(argv[3]);
    sf_scene sc;
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(&sc, argv[1], 0, NULL, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    const sf_model *m = &sc.model;
    double *q = calloc((size_t)m->nq, sizeof(double));
    for (int i = 0; i < m->nfolds; i++) {
        const sf_fold_def *f = &sc.study.folds[i];
        double sgn = f->rest_angle < 0 ? -1 : 1;
        if (f->group >= 0) sgn = sc.study.groups[f->group].rest_angle < 0 ? -1 : 1;
        q[m->qoff[i]] = 0.05 * sgn;
    }
    sf_validity *v = NULL;
    if (sf_validity_create(m, sc.study.samples, &v, &err)) return 1;
    sf_validity_report rep;
    double t0 = cpu();
    for (int k = 0; k < reps; k++)
        if (sf_validity_check(v, q, 0, &rep, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
    double tt = (cpu() - t0) / reps;
    double tb = -1;
    if (brute) {
        t0 = cpu();
        sf_validity_report rb;
        if (sf_validity_check(v, q, 1, &rb, &err)) return 1;
        tb = cpu() - t0;
        if (rb.ncross != rep.ncross) fprintf(stderr, "brute force disagrees\n");
    }
    printf("%d\t%d\t%ld\t%ld\t%ld\t%ld\t%.4g\t%.4g\n", m->nfolds, m->nfaces + m->nfolds,
           sf_validity_ntriangles(v), rep.part_pairs, rep.tri_tests, rep.ncross, tt, tb);
    sf_validity_free(v);
    free(q);
    sf_scene_close(&sc);
    return 0;
}
