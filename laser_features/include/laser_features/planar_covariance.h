// A planar pose's covariance over (x, y, theta) in the 6 x 6 row-major covariance of ROS messages
// (x, y, z, roll, pitch, yaw): the nodes of every package read and write it here, one index map.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>

namespace laser_features {

/// Rows and columns of x, y and yaw in a ROS 6 x 6 pose covariance.
constexpr std::array<int, 3> kPlanarCovarianceIndex{0, 1, 5};

/// The (x, y, theta) block of a ROS 6 x 6 pose covariance (any container indexable by 0..35).
template <typename Covariance36>
Eigen::Matrix3d planarCovariance(const Covariance36& c) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m(i, j) = c[size_t(6 * kPlanarCovarianceIndex[i] + kPlanarCovarianceIndex[j])];
  }
  return m;
}

/// Writes `m` into a ROS 6 x 6 pose covariance, zero elsewhere.
template <typename Covariance36>
void setPlanarCovariance(const Eigen::Matrix3d& m, Covariance36* c) {
  for (size_t k = 0; k < 36; ++k) (*c)[k] = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) (*c)[size_t(6 * kPlanarCovarianceIndex[i] + kPlanarCovarianceIndex[j])] = m(i, j);
  }
}

}  // namespace laser_features
