// Backward-Euler viscosity for the implicit solver (solver.pressure = "dfsph"): the operator of
// Mueller et al. 2005 eq. (9), integrated implicitly in time as Weiler et al. 2018 do, so that a
// viscous fluid (the lamp's 1.5-3 Pa s) no longer sets the step. Per particle,
//   m_i v_i + dt sum_j w_ij (v_i - v_j) + dt c_i v_i = m_i v*_i,
//   w_ij = V_i V_j (mu_i + mu_j)/2 lap W_visc(x_ij)  (symmetric, >= 0),
//   c_i  = V_i sum_b V_b f mu_i (rho0_i/rho_i) lap W_visc(x_ib)  (no-slip walls, f = wall_friction),
// a symmetric positive definite system, the same for the three components. Eigen's
// ConjugateGradient solves it matrix-free with a Jacobi preconditioner; the product runs in
// parallel per row and Eigen's dot products are serial, so the bits do not depend on threads.
#pragma once

#include "sim/effect.h"

namespace mf::effects {

struct ImplicitViscosityStats {
  bool explicitStep = false;  // taken by forward Euler: max theta_i <= 1/2 (below)
  int iterations = 0;  // the most any component needed
  Real error = 0;      // its relative residual
  bool converged = true;
};

/// Replaces ps.velocity (the predicted v*) by the solution; `tolerance` is CG's relative residual.
/// Where every particle has theta_i = dt (sum_j w_ij + c_i) / m_i <= 1/2, the step is taken by
/// forward Euler instead, m_i v_i = m_i v*_i - dt (sum_j w_ij (v*_i - v*_j) + c_i v*_i): by
/// Gershgorin dt lambda_max(M^-1 L) <= 2 max theta_i <= 1, so every mode decays without changing
/// sign, as backward Euler's do, at the cost of one pass instead of a solve per component.
ImplicitViscosityStats solveImplicitViscosity(const StepContext& ctx, ParticleSet& ps, Real dt, Real wallFriction,
                                              Real tolerance, int maxIterations);

}  // namespace mf::effects
