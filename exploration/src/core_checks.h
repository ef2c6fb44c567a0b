// Small helpers the exploration core's sources share (internal: not part of the package's
// interface): validate()'s refusal, finiteness of points and poses, a grid cell's neighbours.
#pragma once

#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <cmath>
#include <string>

namespace exploration {
namespace core {

/// Sets *error (when given) to `why` and returns false: how every validate() refuses.
inline bool fail(std::string* error, const char* why) {
  if (error) *error = why;
  return false;
}

inline bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }
inline bool finite(const laser_features::Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

/// The 8 neighbours of a grid cell: the 4 orthogonal ones first.
inline constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
inline constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

}  // namespace core
}  // namespace exploration
