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

namespace {

// An undirected line's direction modulo pi, as the sense nearer `reference`.
double senseNear(double direction, double reference) {
  double d = normalizeAngle(direction - reference);
  if (d > 0.5 * kPi) d -= kPi;
  if (d < -0.5 * kPi) d += kPi;
  return reference + d;
}

}  // namespace

std::optional<double> hallwayWallsDirection(const std::vector<LineSegment>& lines, double reference, double max_turn,
                                            const HallwayWallsParams& params) {
  struct Wall {
    double direction, lateral, length;
  };
  std::vector<Wall> left, right;
  for (const LineSegment& l : lines) {
    const double len = l.length();
    if (!(len >= params.min_length)) continue;
    const Eigen::Vector2d d = (l.end - l.start) / len;
    const double dir = senseNear(std::atan2(d.y(), d.x()), reference);
    if (std::abs(dir - reference) > max_turn) continue;
    const Eigen::Vector2d u(std::cos(dir), std::sin(dir)), n(-u.y(), u.x());
    const double a0 = l.start.dot(u), a1 = l.end.dot(u);
    if (std::max(a0, a1) < -params.behind || std::min(a0, a1) > params.ahead) continue;
    const double lateral = 0.5 * (l.start + l.end).dot(n);
    if (std::abs(lateral) < params.min_lateral || std::abs(lateral) > params.max_width) continue;
    (lateral > 0.0 ? left : right).push_back({dir, lateral, len});
  }
  std::optional<double> best;
  double best_width = 0.0, best_turn = 0.0;
  for (const Wall& a : left) {
    for (const Wall& b : right) {
      if (std::abs(a.direction - b.direction) > params.parallel_tolerance) continue;
      const double dir = (a.length * a.direction + b.length * b.direction) / (a.length + b.length);
      const double width = a.lateral - b.lateral;
      if (width > params.max_width) continue;
      const double turn = std::abs(dir - reference);
      if (!best || width < best_width - 1e-6 || (width < best_width + 1e-6 && turn < best_turn)) {
        best = normalizeAngle(dir);
        best_width = width;
        best_turn = turn;
      }
    }
  }
  return best;
}

BinnedDirection followWalls(const HeadingBins& bins, const BinnedDirection& current, double walls, double tolerance) {
  BinnedDirection d{current.bin, normalizeAngle(walls - bins.heading(current.bin))};
  if (std::abs(d.offset) <= tolerance) d.offset = 0.0;
  if (std::abs(d.offset) > 0.5 * bins.width() + 0.5 * tolerance) {
    d.bin = bins.bin(walls);
    d.offset = normalizeAngle(walls - bins.heading(d.bin));
  }
  return d;
}

}  // namespace laser_features
