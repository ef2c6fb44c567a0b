#include "laser_features/building_axes.h"

namespace laser_features {

bool BuildingAxisEstimator::add(double normal, double variance, double length) {
  if (!std::isfinite(normal) || !std::isfinite(variance) || !std::isfinite(length)) return false;
  if (length < params_.min_line_length || variance > params_.max_alpha_sigma * params_.max_alpha_sigma) return false;
  lines_.emplace_back(normalizeAngle(4.0 * normal), length);
  total_ += length;
  return true;
}

BuildingAxisEstimator::Estimate BuildingAxisEstimator::estimate() const {
  Estimate best;
  const double width = 4.0 * params_.cluster_width;  // in 4 beta
  for (const auto& centre : lines_) {  // a few hundred lines at most: every line as a candidate centre
    double c = 0.0, s = 0.0, along = 0.0;
    for (const auto& l : lines_) {
      if (std::abs(normalizeAngle(l.first - centre.first)) > width) continue;
      c += l.second * std::cos(l.first);
      s += l.second * std::sin(l.first);
      along += l.second;
    }
    if (along > best.along) {
      best.along = along;
      best.axis = std::atan2(s, c) / 4.0;  // atan2 in (-pi, pi]: an axis in (-pi/4, pi/4]
    }
  }
  best.agreement = total_ > 0.0 ? best.along / total_ : 0.0;
  return best;
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
