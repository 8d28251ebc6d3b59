/* run_output.c - `smoothfold run`: the files of an equilibrium path, written
 * from the rows gathered point by point (run_point.c): DIR/branch.tsv,
 * stats.csv, special.tsv, reactions.tsv, shapes.pvd, folded.fold, study.cfg
 * and the reference comparison (docs/reference/output-files.md). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "equilibrium_poses.h"
#include "run_impl.h"
#include "study.h"

double run_cpu_seconds(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0.0;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int run_write_outputs(run_ctx *r)
{
    const sf_study *s = &r->sc->study;
    sf_error *err = r->err;
    char path[1200];
    sf_outbuf out = {0};
#define WRITE(name, buf)                                                           \
    do {                                                                           \
        if ((buf).oom) return sf_fail(err, SF_ENOMEM, "out of memory");            \
        snprintf(path, sizeof path, "%s/%s", r->dir, name);                        \
        if (sf_write_atomic(path, sf_outbuf_fill, &(buf), err)) return err->code;       \
    } while (0)
    /* branch.tsv: comments, column names, rows */
    sf_outbuf_printf(&out, "%s", r->header.s ? r->header.s : "");
    if (r->bnotes.n) sf_outbuf_printf(&out, "%.*s", (int)r->bnotes.n, r->bnotes.s);
    if (r->do_stab)
        sf_outbuf_printf(&out, "# stability: %ld points by the dense LAPACK method, %ld by ARPACK, "
                         "%ld by the MUMPS inertia (eigenvalues at %ld of them) "
                         "(analysis.eigensolver)\n", r->neig_method[SF_EIG_DENSE],
                         r->neig_method[SF_EIG_ARPACK], r->neig_method[SF_EIG_INERTIA],
                         r->neig_inertia);
    if (r->eq.pz && sf_peq_rows_dropped(&r->eq))
        sf_outbuf_printf(&out, "# pose rows: %d of %d fold rows kept, %d dropped as identities "
                         "(dependent at a generic state, solver.pose_rows); largest residual of a "
                         "dropped row %.3g over the points written, %ld point%s above the Newton "
                         "tolerance\n", r->eq.nloop, 6 * r->eq.m->nfolds,
                         sf_peq_rows_dropped(&r->eq), r->drop_max, r->drop_bad,
                         r->drop_bad == 1 ? "" : "s");
    else if (r->eq.pz && sf_peq_rows_rank(&r->eq) >= 0 && sf_peq_rows_rank(&r->eq) < 6 * r->eq.m->nfolds)
        sf_outbuf_printf(&out, "# pose rows: all %d fold rows kept: at a generic state they have "
                         "rank %d = the unknowns, so the dependent ones are equations of their own "
                         "(more rows than unknowns), not identities (docs/design/model.md)\n",
                         6 * r->eq.m->nfolds, sf_peq_rows_rank(&r->eq));
    char vline[1500];
    run_validity_summary(r, vline, sizeof vline);
    if (vline[0]) sf_outbuf_printf(&out, "# warning: %s\n", vline);
    if (r->do_stab && r->step_bound)
        sf_outbuf_printf(&out, "# step bound: %ld steps shortened to end between two predicted "
                         "eigenvalue crossings (analysis.step_bound)\n", r->nbound);
    sf_outbuf_printf(&out, "# units: s, p, load: as the parameter (load factor, actuation factor, or m); "
                    "probe*: m; energy: J; residual_rot: 1; residual_tra: m; eig*: J per unit "
                    "of the coordinates (rad, mode amplitude); theta*: rad\n");
    if (r->bif.nbranches > 1)
        sf_outbuf_printf(&out, "# %d branches, each a block after two blank lines (gnuplot index 0..%d)\n",
                  r->bif.nbranches, r->bif.nbranches - 1);
    sf_outbuf_printf(&out, "point\tbranch\ts\tp\tload");
    sf_outbuf_probe_columns(&out, s->nprobes);
    sf_outbuf_printf(&out, "\tenergy\tresidual\tresidual_rot\tresidual_tra\tnewton\tstable\tmorse");
    sf_outbuf_numbered_columns(&out, "eig", r->nev);
    sf_outbuf_printf(&out, "\ttype");
    sf_outbuf_numbered_columns(&out, "theta", s->nfolds);
    sf_outbuf_printf(&out, "\twarning\n");
    if (r->rows.n) sf_outbuf_printf(&out, "%.*s", (int)r->rows.n, r->rows.s);
    WRITE("branch.tsv", out);
    out.n = 0;
    sf_outbuf_printf(&out, "# smoothfold %s per-step solver statistics for %s\n", PACKAGE_VERSION, s->name);
    if (r->cpu_path0 > 0)
        sf_outbuf_printf(&out, "# CPU time: start %.3f s (reading, set-up and the start up to the path's "
                         "first point), path %.3f s (the path after it: corrector, stability, "
                         "special points, output)\n", r->cpu_path0, run_cpu_seconds() - r->cpu_path0);
    cont_factor_stats fs;
    if (r->solver && cont_get_factor_stats(r->solver, &fs) == 0)
        sf_outbuf_printf(&out, "# corrector's last factorisation (MUMPS): %s of order %ld, %.0f entries "
                         "in its factors, %.4g Mflop, %ld delayed pivots\n",
                         fs.ldlt ? "LDL^T of Jy" : "LU of the bordered matrix", fs.n, fs.entries,
                         1e-6 * fs.flops, fs.delayed);
    sf_outbuf_printf(&out, "point,branch,p,ds,newton,residual_evals,jacobian_evals,retries,locate_points,wall_s,factorisations\n");
    if (r->stats.n) sf_outbuf_printf(&out, "%.*s", (int)r->stats.n, r->stats.s);
    WRITE("stats.csv", out);
    out.n = 0;
    sf_outbuf_printf(&out, "%s", r->header.s ? r->header.s : "");
    sf_outbuf_printf(&out, "point\tbranch\ttype\tp\ts");
    sf_outbuf_probe_columns(&out, s->nprobes);
    sf_outbuf_printf(&out, "\tstable\tmorse");
    sf_outbuf_numbered_columns(&out, "eig", r->nev);
    sf_outbuf_printf(&out, "\tloc_err\n");
    if (r->special.n) sf_outbuf_printf(&out, "%.*s", (int)r->special.n, r->special.s);
    WRITE("special.tsv", out);
    free(out.s);
#undef WRITE
    if (r->eq.nsup) {
        snprintf(path, sizeof path, "%s/reactions.tsv", r->dir);
        if (sf_reactions_write(&r->reac, &r->eq, path, r->header.s, err)) return err->code;
    }
    if (r->nshapes > 0 && sf_pvd_write(&r->pvd, err)) return err->code;
    snprintf(path, sizeof path, "%s/folded.fold", r->dir);
    if (sf_foldrec_write(&r->foldrec, path, err)) return err->code;
    snprintf(path, sizeof path, "%s/study.cfg", r->dir);
    char hdr[256];
    snprintf(hdr, sizeof hdr, "merged study run by smoothfold %s (after --set overrides)",
             PACKAGE_VERSION);
    if (sf_study_write(s, path, hdr, err)) return err->code;
    if (r->compared && sf_compare_write(r->cmp, r->dir, r->header.s, err)) return err->code;
    return SF_OK;
}
