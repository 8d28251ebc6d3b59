/* lmi.h - max over |mu| <= rho emax / amax of the smallest eigenvalue of
 * H0 + sum_k mu_k A_k (d x d, row-major; H0 may be NULL: zero), by DSDP.
 * emax scales H0 (its largest |eigenvalue|; 1 when H0 is NULL), amax the
 * A_k (their largest Frobenius norm).  mu (k values) receives DSDP's
 * maximiser, *t_lo its value (a lower bound only once checked by the
 * caller), *t_up (may be NULL) an upper bound that holds for any X DSDP
 * returns.  Returns 0 when DSDP ran, else its error code (-1: out of
 * memory).  DSDP's trace of a failed solve is kept off stdout. */
#ifndef SF_LMI_H
#define SF_LMI_H

int sf_lmi_max_min_eig(int d, const double *H0, int k, const double *A, double emax, double amax,
                       double rho, double *mu, double *t_lo, double *t_up);

/* v^T M v for the d x d row-major M (the forms of the LMIs and their
 * callers). */
double sf_quad_form(int d, const double *M, const double *v);

#endif
