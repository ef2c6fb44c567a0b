// Test support shared by the packages that check Jacobians of the shared geometry (laser_features,
// ekf_local_map): central differences with angle-aware output differences.
#pragma once

#include <Eigen/Core>

#include "laser_features/geometry.h"

namespace laser_features {
namespace testing {

constexpr double kJacobianStep = 1e-6;  // finite-difference step

inline Eigen::Vector3d toVector(const Pose2D& p) { return {p.x, p.y, p.theta}; }
inline Pose2D toPose(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// Difference of two (x, y, theta) with the angle wrapped.
inline Eigen::Vector3d poseDifference(const Pose2D& a, const Pose2D& b) {
  return {a.x - b.x, a.y - b.y, normalizeAngle(a.theta - b.theta)};
}
/// Difference of two (alpha, r) with the angle wrapped.
inline Eigen::Vector2d lineParamDifference(const Line& a, const Line& b) {
  return {normalizeAngle(a.alpha - b.alpha), a.r - b.r};
}

/// Central-difference Jacobian of f: R^N -> R^M; `diff` subtracts outputs (wrapping angles).
template <int M, int N, typename F, typename Diff>
Eigen::Matrix<double, M, N> numericJacobian(F f, Diff diff, const Eigen::Matrix<double, N, 1>& x) {
  Eigen::Matrix<double, M, N> J;
  for (int k = 0; k < N; ++k) {
    Eigen::Matrix<double, N, 1> plus = x, minus = x;
    plus(k) += kJacobianStep;
    minus(k) -= kJacobianStep;
    J.col(k) = diff(f(plus), f(minus)) / (2.0 * kJacobianStep);
  }
  return J;
}

}  // namespace testing
}  // namespace laser_features
