// (A + A^T) / 2, for the translation units of StochasticMap (src/stochastic_map*.cpp); not installed.
#pragma once

#include <Eigen/Core>

namespace ekf_local_map {

/// (A + A^T) / 2 of a small fixed-size matrix.
template <int N>
Eigen::Matrix<double, N, N> symmetric(const Eigen::Matrix<double, N, N>& A) {
  return 0.5 * (A + A.transpose());
}

}  // namespace ekf_local_map
