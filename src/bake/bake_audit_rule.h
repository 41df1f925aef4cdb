/* The energy audit's angles and quadrature, on their own: the specialised fit's energy term
 * (bake_fit.c) measures with the same rule as the audit and the held-out check's guard, and
 * the fit is below the audit in the include order (bake_audit.c uses the compact level). */
#ifndef NBRDF_BAKE_AUDIT_RULE_H
#define NBRDF_BAKE_AUDIT_RULE_H

/* The audited θi (defined in bake_audit.c): 0, 30, 60, 80, 85, 89°. */
#define BAKE_AUDIT_N_THETA 6
extern const double bake_audit_theta_deg[BAKE_AUDIT_N_THETA];

/* The precise measurement's nodes per θi: the polar rule of albedo_quad.h with
 * 24 rings of 8 (193 decoder queries; the lattice of 1,024 directions before
 * it spread as much against brute force: bench/bench_audit_quad.c). */
#define BAKE_AUDIT_POLAR_RINGS 24
#define BAKE_AUDIT_POLAR_PHI 8

#endif
