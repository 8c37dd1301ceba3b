#include "surface_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace mf::effects {

namespace {

// Below this reciprocal condition number of the normal equations a term is not determined.
constexpr Real kMinRcond = 1e-7;

/// The factorisation succeeded and every term is determined: no pivot vanishes against the
/// largest, and the condition number is moderate.
template <class Ldlt>
bool determined(const Ldlt& ldlt) {
  if (ldlt.info() != Eigen::Success) return false;
  const auto d = ldlt.vectorD().cwiseAbs();
  return d.minCoeff() > kMinRcond * d.maxCoeff() && ldlt.rcond() > kMinRcond;
}

/// The principal curvatures of the graph w(u, v) at the origin from its slopes (b1, b2) and
/// second derivatives: the eigenvalues of the shape operator I^-1 II.
PrincipalCurvatures fromGraph(Real b1, Real b2, Real wuu, Real wuv, Real wvv) {
  const Real g = 1 + b1 * b1 + b2 * b2;  // det I
  const Real scale = 1 / std::sqrt(g);   // II = Hessian / sqrt(det I)
  const Real I11 = 1 + b1 * b1, I12 = b1 * b2, I22 = 1 + b2 * b2;
  const Real trace = scale * (I22 * wuu - 2 * I12 * wuv + I11 * wvv) / g;
  const Real det = scale * scale * (wuu * wvv - wuv * wuv) / g;
  const Real half = trace / 2, disc = std::sqrt(std::max<Real>(0, half * half - det));
  return {true, half - disc, half + disc};
}

}  // namespace

PrincipalCurvatures fitSurfaceCurvatures(const Vec3& inward, const SurfacePoint* points, size_t count, Real length) {
  if (count < 4) return {};
  // A tangent frame: t1 along the axis least aligned with the normal, made orthogonal.
  const Vec3 axis = std::fabs(inward.x) < 0.6 ? Vec3(1, 0, 0) : (std::fabs(inward.y) < 0.6 ? Vec3(0, 1, 0) : Vec3(0, 0, 1));
  const Vec3 t1 = normalize(axis - inward * dot(axis, inward)), t2 = cross(inward, t1);
  const Real inv = 1 / length;
  using Mat6 = Eigen::Matrix<Real, 6, 6>;
  using Vec6 = Eigen::Matrix<Real, 6, 1>;
  Mat6 A = Mat6::Zero();
  Vec6 rhs = Vec6::Zero();
  for (size_t k = 0; k < count; ++k) {
    const Vec3 r = points[k].offset * inv;
    const Real u = dot(r, t1), v = dot(r, t2), w = dot(r, inward);
    Vec6 phi;
    phi << 1, u, v, u * u, u * v, v * v;
    A.selfadjointView<Eigen::Lower>().rankUpdate(phi, points[k].weight);
    rhs += phi * (points[k].weight * w);
  }
  A = A.selfadjointView<Eigen::Lower>();
  if (count >= 6) {
    const Eigen::LDLT<Mat6> ldlt(A);
    if (determined(ldlt)) {
      const Vec6 c = ldlt.solve(rhs);  // w = c0 + c1 u + c2 v + c3 u^2 + c4 u v + c5 v^2
      PrincipalCurvatures k = fromGraph(c(1), c(2), 2 * c(3), c(4), 2 * c(5));
      k.k1 *= inv, k.k2 *= inv;  // back from coordinates scaled by 1/length
      return k;
    }
  }
  // The isotropic quadric: w = c0 + c1 u + c2 v + m (u^2 + v^2), its normal equations folded
  // from the full ones (the quadratic column is phi3 + phi5).
  Eigen::Matrix<Real, 4, 4> B;
  Eigen::Matrix<Real, 4, 1> rb;
  const int map[6] = {0, 1, 2, 3, -1, 3};  // phi4 = u v does not enter
  B.setZero();
  rb.setZero();
  for (int a = 0; a < 6; ++a) {
    if (map[a] < 0) continue;
    rb(map[a]) += rhs(a);
    for (int b = 0; b < 6; ++b)
      if (map[b] >= 0) B(map[a], map[b]) += A(a, b);
  }
  const Eigen::LDLT<Eigen::Matrix<Real, 4, 4>> ldlt(B);
  if (!determined(ldlt)) return {};
  const Eigen::Matrix<Real, 4, 1> c = ldlt.solve(rb);
  PrincipalCurvatures k = fromGraph(c(1), c(2), 2 * c(3), 0, 2 * c(3));
  k.k1 *= inv, k.k2 *= inv;
  return k;
}

}  // namespace mf::effects
