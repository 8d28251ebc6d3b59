/* stab_cost.c - cost of one stability evaluation (stability.h) of a study
 * in the face-pose formulation, by method: the flat sheet (poses lifted
 * from zero fold coordinates), at p = 0 and at p = 1 (the full load on
 * the flat sheet: not an equilibrium, but HL then holds every load term;
 * the cost of a factorisation depends on the pattern, not on the values).
 * Prints one line per method: coordinates, rows, rank, Morse index,
 * eigenvalues found, CPU seconds (CLOCK_PROCESS_CPUTIME_ID, the machine
 * being shared) of the first evaluation (with the symbolic analysis and,
 * for the inertia, the rank-revealing QR) and per evaluation of the next
 * R - 1 at the same point (what a point of a path costs while the pattern
 * and the independent rows stay: sstab_rows.h), and for the inertia how
 * the independent rows were found (QRs, reuses).  Built and run by bench/stab-cost.sh; not part of
 * make check.
 * usage: stab_cost STUDY METHOD[,METHOD...] [R] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "equilibrium.h"
#include "equilibrium_poses.h"
#include "scene.h"
#include "sstab.h"
#include "stability.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: stab_cost STUDY METHOD[,METHOD...] [R]\n");
        return 2;
    }
    int reps = argc > 3 ? atoi(argv[3]) : 3;
    if (reps < 1) reps = 1;
    const char *sets[] = {"solver.formulation=\"poses\""};
    sf_scene sc;
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(&sc, argv[1], 1, sets, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        sf_scene_close(&sc);
        return 1;
    }
    int ptype, gi, pi, ci;
    sf_equil eq;
    if (sf_equil_parse_param(&sc.study, &ptype, &gi, &pi, &ci, &err) ||
        sf_equil_init(&eq, &sc.model, ptype, gi, pi, ci, 0.0, &err) ||
        sf_equil_use_poses(&eq, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        sf_scene_close(&sc);
        return 1;
    }
    double *y = calloc((size_t)eq.n + 1, sizeof(double));
    if (!y) return 1;
    sf_equil_poses_lift(&eq, y);
    char *list = strdup(argv[2]);
    int rc = 0;
    for (char *m = strtok(list, ","); m && !rc; m = strtok(NULL, ",")) {
        int meth = strcmp(m, "dense") == 0     ? SF_EIG_DENSE
                   : strcmp(m, "arpack") == 0  ? SF_EIG_ARPACK
                   : strcmp(m, "inertia") == 0 ? SF_EIG_INERTIA
                                               : SF_EIG_AUTO;
        for (int ip = 0; ip < 2 && !rc; ip++) {
            double p = ip;
            sf_stab st;
            if (sf_stab_init(&st, &eq, meth, 4, &err)) {
                fprintf(stderr, "%s\n", err.msg);
                rc = 1;
                break;
            }
            double t0 = now(), t1 = t0;
            for (int r = 0; r < reps && !rc; r++) {
                if (sf_stab_eval(&st, &eq, y, p, &err)) {
                    fprintf(stderr, "%s: %s\n", m, err.msg);
                    rc = 1;
                }
                if (r == 0) t1 = now();
            }
            double first = t1 - t0, next = reps > 1 ? (now() - t1) / (reps - 1) : 0.0;
            const sf_sstab_result *S = st.sp ? sf_sstab_get(st.sp) : NULL;
            if (!rc)
                printf("%s p=%g method=%s coordinates=%d rows=%d rank=%d morse=%d stable=%d "
                       "eigenvalues=%d eig1=%.6g cpu_first=%.4f cpu_next=%.4f rank_qr=%d "
                       "rank_reused=%d\n", sc.study.name, p, sf_stab_method_name(st.res.method),
                       eq.nq, eq.ncon, st.res.rank, st.res.morse, st.res.stable, st.res.neig,
                       st.res.neig > 0 ? st.res.eig[0] : 0.0, first, next, S ? S->rank_qr : 0,
                       S ? S->rank_reused : 0);
            fflush(stdout);
            sf_stab_free(&st);
        }
    }
    free(list);
    free(y);
    sf_equil_free(&eq);
    sf_scene_close(&sc);
    return rc;
}
