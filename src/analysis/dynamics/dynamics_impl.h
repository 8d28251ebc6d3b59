/* dynamics_impl.h - private to dynamics.c and dynamics_dae.c: the IDA
 * objects of a trajectory and the functions the two files share (prefix
 * dy_).  The public face is dynamics.h.
 *   dynamics.c      histories, time and parameters, IDA set-up and
 *                   callbacks, life cycle, start, steps, report
 *   dynamics_dae.c  the DAE: masses, inertia, kinetic energy, constraint
 *                   rows, residual and Jacobian (sf_dyn_residual,
 *                   sf_dyn_jacobian)
 */
#ifndef SF_DYNAMICS_IMPL_H
#define SF_DYNAMICS_IMPL_H

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>

#include "dynamics.h"

#define REG_EPS 1e-10

struct sf_dyn_ida {
    SUNContext ctx;
    void *mem;
    N_Vector y, yp, id, atol;
    SUNMatrix A, Aeq;
    SUNLinearSolver LS;
    SUNNonlinearSolver NLS;
    N_Vector ytry;       /* scratch: the Newton iterate */
    double ss, oldnrm;   /* convergence rate estimate of the Newton iteration */
    long nextra;         /* Newton iterations added for the constraint rows */
    long nchecks;        /* evaluations of the constraint rows in conv_test */
    double *stops;       /* kinks of the histories in (0, duration], then duration */
    int nstops, next;
    char msg[512];       /* last message of IDA */
};

/* dynamics_dae.c */
int dy_build_masses(sf_dyn *d, sf_error *err);
double dy_kinetic_energy(sf_dyn *d, const double *v);

#endif
