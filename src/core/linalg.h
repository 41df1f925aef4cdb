/* Small dense linear algebra in double, row-major, for matrices of a few
 * dozen rows (the bake's compact basis: the latent dimension, 32, and K <= 8).
 * O(n^3) and single-threaded: no BLAS, so results are bit-identical on every
 * machine for the same inputs. */
#ifndef NBRDF_CORE_LINALG_H
#define NBRDF_CORE_LINALG_H

/* Eigen-decomposition of the symmetric n x n matrix a (destroyed) by cyclic
 * Jacobi rotations: eigenvalues in ev[n] (unordered), the matching
 * orthonormal eigenvectors in the columns of v[n x n], so that
 * a = v diag(ev) vᵀ. Stops when the off-diagonal mass is below 1e-24 of the
 * diagonal's (squared entries) or after 100 sweeps. */
void core_linalg_symmetric_eigen(double *a, int n, double *ev, double *v);

/* Inverts the n x n matrix a (destroyed) into inv[n x n] by Gauss-Jordan
 * elimination with partial pivoting. Returns 1, or 0 when a pivot's magnitude
 * is not above 1e-12 (singular or nearly so; inv is then undefined). */
int core_linalg_invert(double *a, int n, double *inv);

#endif
