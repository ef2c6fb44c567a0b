#include "laser_features/building_axes.h"

namespace laser_features {

bool BuildingAxisEstimator::add(double normal, double variance, double length) {
  if (!std::isfinite(normal) || !std::isfinite(variance) || !std::isfinite(length)) return false;
  if (length < params_.min_line_length || variance > params_.max_alpha_sigma * params_.max_alpha_sigma) return false;
  c_ += length * std::cos(4.0 * normal);
  s_ += length * std::sin(4.0 * normal);
  total_ += length;
  return true;
}

double BuildingAxisEstimator::axis() const {
  if (total_ <= 0.0) return 0.0;
  // atan2 in (-pi, pi] gives an axis in (-pi/4, pi/4].
  return std::atan2(s_, c_) / 4.0;
}

double dominantAxis(const std::vector<double>& headings, const std::vector<double>& weights) {
  double c = 0.0, s = 0.0;
  for (size_t i = 0; i < headings.size() && i < weights.size(); ++i) {
    if (!std::isfinite(headings[i]) || !std::isfinite(weights[i]) || weights[i] <= 0.0) continue;
    c += weights[i] * std::cos(4.0 * headings[i]);
    s += weights[i] * std::sin(4.0 * headings[i]);
  }
  return (c == 0.0 && s == 0.0) ? 0.0 : std::atan2(s, c) / 4.0;
}

}  // namespace laser_features
