#include "implicit_viscosity.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <cmath>
#include <vector>

namespace mf::effects {
namespace {

/// w_ij of eq. 9 between fluid particles i and j at distance rl (symmetric, >= 0).
inline Real pairWeight(const ParticleSet& ps, const SphKernels& K, size_t i, uint32_t j, Real rl) {
  return ps.volume[i] * ps.volume[j] * 0.5 * (ps.viscosity[i] + ps.viscosity[j]) * K.viscosityLaplacian(rl);
}

/// c_i: the no-slip walls' drag on particle i (wall_friction f), summed over its wall samples.
inline Real wallWeight(const StepContext& ctx, const ParticleSet& ps, size_t i, Real wallFriction) {
  if (wallFriction <= 0) return 0;
  const Real scale = wallFriction * ps.viscosity[i] * ps.restDensity[i] / ps.density[i];
  Real c = 0;
  for (uint64_t k = ctx.boundaryNeighbors.begin(i), e = ctx.boundaryNeighbors.end(i); k < e; ++k) {
    const uint32_t b = ctx.boundaryNeighbors.indices[k];
    const Real rl = std::sqrt(lengthSquared(ctx.periodic.separation(ps.position[i], ctx.boundary.position[b])));
    c += ps.volume[i] * ctx.boundary.volume[b] * scale * ctx.kernels.viscosityLaplacian(rl);
  }
  return c;
}

// A x for one velocity component, from the neighbour lists: Eigen's matrix-free interface.
class ViscousOperator;

}  // namespace
}  // namespace mf::effects

namespace Eigen::internal {
template <>
struct traits<mf::effects::ViscousOperator> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace mf::effects {
namespace {

class ViscousOperator : public Eigen::EigenBase<ViscousOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };

  ViscousOperator(const StepContext& ctx, const ParticleSet& ps, Real dt, Real wallFriction) : ctx_(ctx), ps_(ps), dt_(dt) {
    const size_t n = ps.size();
    const SphKernels& K = ctx.kernels;
    rowStart_.assign(n + 1, 0);
    for (size_t i = 0; i < n; ++i) rowStart_[i + 1] = rowStart_[i] + ctx.fluidNeighbors.count(i);
    weight_.resize(rowStart_[n]);
    diagonal_.resize(Eigen::Index(n));
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Vec3 xi = ps.position[i];
        Real sum = 0;
        uint64_t w = rowStart_[i];
        for (uint64_t k = ctx.fluidNeighbors.begin(i), e = ctx.fluidNeighbors.end(i); k < e; ++k, ++w) {
          const uint32_t j = ctx.fluidNeighbors.indices[k];
          const Real rl = std::sqrt(lengthSquared(ctx.periodic.separation(xi, ps.position[j])));
          weight_[w] = pairWeight(ps, K, i, j, rl);
          sum += weight_[w];
        }
        diagonal_[Eigen::Index(i)] = inertialMass(ctx, ps, i) + dt * (sum + wallWeight(ctx, ps, i, wallFriction));
      }
    });
  }

  Eigen::Index rows() const { return diagonal_.size(); }
  Eigen::Index cols() const { return diagonal_.size(); }
  const Eigen::VectorXd& diagonal() const { return diagonal_; }

  template <typename Rhs>
  Eigen::Product<ViscousOperator, Rhs, Eigen::AliasFreeProduct> operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<ViscousOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

  /// y += alpha A x.
  template <typename X, typename Y>
  void multiplyAdd(const X& x, Y& y, double alpha) const {
    const size_t n = size_t(rows());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        double off = 0;
        uint64_t w = rowStart_[i];
        for (uint64_t k = ctx_.fluidNeighbors.begin(i), e = ctx_.fluidNeighbors.end(i); k < e; ++k, ++w)
          off += weight_[w] * x[Eigen::Index(ctx_.fluidNeighbors.indices[k])];
        y[Eigen::Index(i)] += alpha * (diagonal_[Eigen::Index(i)] * x[Eigen::Index(i)] - dt_ * off);
      }
    });
  }

 private:
  const StepContext& ctx_;
  const ParticleSet& ps_;
  Real dt_;
  std::vector<uint64_t> rowStart_;
  std::vector<Real> weight_;
  Eigen::VectorXd diagonal_;
};

/// Jacobi preconditioning for the matrix-free operator (Eigen's DiagonalPreconditioner needs
/// stored coefficients).
class JacobiPreconditioner {
 public:
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic };
  JacobiPreconditioner() = default;
  template <typename M>
  explicit JacobiPreconditioner(const M& m) {
    compute(m);
  }
  template <typename M>
  JacobiPreconditioner& analyzePattern(const M&) {
    return *this;
  }
  template <typename M>
  JacobiPreconditioner& factorize(const M& m) {
    return compute(m);
  }
  template <typename M>
  JacobiPreconditioner& compute(const M& m) {
    inverse_ = m.diagonal().cwiseInverse();
    return *this;
  }
  template <typename Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    return inverse_.cwiseProduct(b);
  }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  Eigen::VectorXd inverse_;
};

}  // namespace
}  // namespace mf::effects

namespace Eigen::internal {
template <typename Rhs>
struct generic_product_impl<mf::effects::ViscousOperator, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<mf::effects::ViscousOperator, Rhs,
                                generic_product_impl<mf::effects::ViscousOperator, Rhs>> {
  using Scalar = typename Product<mf::effects::ViscousOperator, Rhs>::Scalar;
  template <typename Dest>
  static void scaleAndAddTo(Dest& dst, const mf::effects::ViscousOperator& lhs, const Rhs& rhs, const Scalar& alpha) {
    lhs.multiplyAdd(rhs, dst, alpha);
  }
};
}  // namespace Eigen::internal

namespace mf::effects {

namespace {

/// The forward-Euler step of the same operator, and max theta_i; the new velocities are written
/// only where max theta_i <= 1/2 (each particle gathers from the old ones).
Real explicitViscosityStep(const StepContext& ctx, ParticleSet& ps, Real dt, Real wallFriction) {
  const size_t n = ps.size();
  const SphKernels& K = ctx.kernels;
  std::vector<Vec3> next(n);
  const Real theta = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 512), Real(0),
      [&](const tbb::blocked_range<size_t>& r, Real worst) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const Vec3 xi = ps.position[i], vi = ps.velocity[i];
          Real sum = 0;
          Vec3 pull;
          for (uint64_t k = ctx.fluidNeighbors.begin(i), e = ctx.fluidNeighbors.end(i); k < e; ++k) {
            const uint32_t j = ctx.fluidNeighbors.indices[k];
            const Real rl = std::sqrt(lengthSquared(ctx.periodic.separation(xi, ps.position[j])));
            const Real w = pairWeight(ps, K, i, j, rl);
            sum += w;
            pull += (ps.velocity[j] - vi) * w;
          }
          const Real c = wallWeight(ctx, ps, i, wallFriction);
          sum += c;
          pull -= vi * c;
          const Real m = inertialMass(ctx, ps, i);
          next[i] = vi + pull * (dt / m);
          worst = std::max(worst, dt * sum / m);
        }
        return worst;
      },
      [](Real a, Real b) { return std::max(a, b); });
  if (theta <= 0.5) ps.velocity.swap(next);
  return theta;
}

}  // namespace

ImplicitViscosityStats solveImplicitViscosity(const StepContext& ctx, ParticleSet& ps, Real dt, Real wallFriction,
                                              Real tolerance, int maxIterations) {
  ImplicitViscosityStats stats;
  const size_t n = ps.size();
  if (n == 0) return stats;
  stats.explicitStep = explicitViscosityStep(ctx, ps, dt, wallFriction) <= 0.5;
  if (stats.explicitStep) return stats;
  const ViscousOperator A(ctx, ps, dt, wallFriction);
  Eigen::ConjugateGradient<ViscousOperator, Eigen::Lower | Eigen::Upper, JacobiPreconditioner> cg;
  cg.setTolerance(tolerance);
  cg.setMaxIterations(maxIterations);
  cg.compute(A);
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n)), guess(static_cast<Eigen::Index>(n));
  // The residual is measured against the momentum of all three components: a component that is
  // all but zero (a stream falling straight down has |m v_x| ~ 1e-149) underflows Eigen's own
  // relative test, which then reports a failure after 0 iterations.
  Real momentum2 = 0;
  for (size_t i = 0; i < n; ++i) {
    const Real m = inertialMass(ctx, ps, i);
    momentum2 += lengthSquared(ps.velocity[i]) * m * m;
  }
  const Real momentum = std::sqrt(momentum2);
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < n; ++i) {
      rhs[Eigen::Index(i)] = inertialMass(ctx, ps, i) * ps.velocity[i][c];
      guess[Eigen::Index(i)] = ps.velocity[i][c];  // v* is close to the answer
    }
    const Eigen::VectorXd v = cg.solveWithGuess(rhs, guess);
    stats.iterations = std::max(stats.iterations, int(cg.iterations()));
    const Real error = momentum > 0 ? Real(cg.error()) * Real(rhs.norm()) / momentum : 0;
    stats.error = std::max(stats.error, error);
    stats.converged = stats.converged && (cg.info() == Eigen::Success || error <= tolerance);
    for (size_t i = 0; i < n; ++i) ps.velocity[i][c] = v[Eigen::Index(i)];
  }
  return stats;
}

}  // namespace mf::effects
