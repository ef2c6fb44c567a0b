// Test worlds of wall segments for the exploration tests: distances, ray casts and line-of-sight
// against the walls (the laser models of each test are built on raycast()).
#pragma once

#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace exploration {
namespace test {

struct Segment {
  Eigen::Vector2d a, b;
};

struct SegmentWorld {
  std::vector<Segment> walls;

  void wall(double x0, double y0, double x1, double y1) { walls.push_back({{x0, y0}, {x1, y1}}); }
  void box(double x0, double y0, double x1, double y1) {
    wall(x0, y0, x1, y0);
    wall(x1, y0, x1, y1);
    wall(x1, y1, x0, y1);
    wall(x0, y1, x0, y0);
  }

  /// Distance from p to the nearest wall.
  double clearance(const Eigen::Vector2d& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const Segment& s : walls) {
      const Eigen::Vector2d ab = s.b - s.a;
      const double t = std::clamp((p - s.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (s.a + t * ab - p).norm());
    }
    return d;
  }

  /// Range along the unit ray o + t u; +inf when nothing is hit.
  double raycast(const Eigen::Vector2d& o, const Eigen::Vector2d& u) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : walls) {
      const Eigen::Vector2d e = s.b - s.a;
      const double denom = laser_features::cross2(u, e);
      if (std::abs(denom) < 1e-12) continue;
      const Eigen::Vector2d w = s.a - o;
      const double t = laser_features::cross2(w, e) / denom;
      const double v = laser_features::cross2(w, u) / denom;
      if (t > 0.0 && v >= 0.0 && v <= 1.0) best = std::min(best, t);
    }
    return best;
  }

  /// Whether the segment p-q crosses a wall.
  bool blocked(const Eigen::Vector2d& p, const Eigen::Vector2d& q) const {
    const double len = (q - p).norm();
    if (len < 1e-12) return false;
    return raycast(p, (q - p) / len) < len;
  }
};

}  // namespace test
}  // namespace exploration
