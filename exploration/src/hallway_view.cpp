#include "exploration/hallway_view.h"

#include "laser_features/geometry.h"

#include <algorithm>
#include <cmath>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;

double freeDistance(const std::vector<Eigen::Vector2d>& points, double bearing, double half_width,
                    double range_cap, const Eigen::Vector2d& origin) {
  double best = range_cap;
  for (const Eigen::Vector2d& q : points) {
    const Eigen::Vector2d p = q - origin;
    const double r = p.norm();
    if (!(r < best)) continue;
    if (std::abs(normalizeAngle(std::atan2(p.y(), p.x()) - bearing)) <= half_width) best = r;
  }
  return best;
}

HallwayView viewHallway(const std::vector<Eigen::Vector2d>& points,
                        const std::vector<laser_features::LineSegment>& lines, double direction,
                        const HallwayViewParams& params, double range_cap) {
  HallwayView v;
  v.free_ahead = freeDistance(points, direction, params.ahead_sector, range_cap);
  v.free_left = freeDistance(points, direction + 0.5 * kPi, params.side_sector, range_cap);
  v.free_right = freeDistance(points, direction - 0.5 * kPi, params.side_sector, range_cap);
  v.free_back = freeDistance(points, direction + kPi, params.ahead_sector, range_cap);
  v.open_left = v.free_left >= params.side_open_distance;
  v.open_right = v.free_right >= params.side_open_distance;

  const Eigen::Vector2d u(std::cos(direction), std::sin(direction));
  const Eigen::Vector2d n(-u.y(), u.x());  // left
  double weight = 0.0, sin_sum = 0.0, cos_sum = 0.0;
  for (const auto& l : lines) {
    const double len = l.length();
    if (len < params.wall_min_length) continue;
    const Eigen::Vector2d d = (l.end - l.start) / len;
    // Direction difference modulo pi (a wall has no orientation).
    double diff = normalizeAngle(std::atan2(d.y(), d.x()) - direction);
    if (diff > 0.5 * kPi) diff -= kPi;
    if (diff < -0.5 * kPi) diff += kPi;
    if (std::abs(diff) > params.wall_parallel_tolerance) continue;
    // The wall must run beside the robot (not only far ahead or behind).
    const double a0 = l.start.dot(u), a1 = l.end.dot(u);
    if (std::max(a0, a1) < -1.0 || std::min(a0, a1) > 2.5) continue;
    const double lateral = 0.5 * (l.start + l.end).dot(n);
    if (std::abs(lateral) > params.wall_max_lateral || std::abs(lateral) < 0.2) continue;
    if (lateral > 0.0 && (!v.left_wall || lateral < v.left_lateral)) {
      v.left_wall = true;
      v.left_lateral = lateral;
    }
    if (lateral < 0.0 && (!v.right_wall || lateral > v.right_lateral)) {
      v.right_wall = true;
      v.right_lateral = lateral;
    }
    // Mean of the doubled angles: undirected lines average without the pi ambiguity.
    sin_sum += len * std::sin(2.0 * diff);
    cos_sum += len * std::cos(2.0 * diff);
    weight += len;
  }
  // How far the walls reach ahead: every line along the direction at either wall's lateral offset.
  for (const auto& l : lines) {
    const double len = l.length();
    if (len < params.wall_min_length) continue;
    const Eigen::Vector2d d = (l.end - l.start) / len;
    if (std::abs(d.dot(n)) > std::sin(params.wall_parallel_tolerance)) continue;
    const double lateral = 0.5 * (l.start + l.end).dot(n);
    const double reach = std::max(l.start.dot(u), l.end.dot(u));
    if (v.left_wall && std::abs(lateral - v.left_lateral) < params.wall_same_lateral) v.left_reach = std::max(v.left_reach, reach);
    if (v.right_wall && std::abs(lateral - v.right_lateral) < params.wall_same_lateral)
      v.right_reach = std::max(v.right_reach, reach);
  }
  if (weight > 0.0) {
    v.wall_direction = normalizeAngle(direction + 0.5 * std::atan2(sin_sum, cos_sum));
    v.wall_direction_valid = true;
  }
  if (v.left_wall && v.right_wall) {
    v.centre_offset = 0.5 * (v.left_lateral + v.right_lateral);
  } else if (v.left_wall) {
    v.centre_offset = std::min(0.0, v.left_lateral - params.min_wall_clearance);
  } else if (v.right_wall) {
    v.centre_offset = std::max(0.0, v.right_lateral + params.min_wall_clearance);
  }
  const double half_width = v.left_wall && v.right_wall ? 0.5 * v.width() : 1.0;
  const Eigen::Vector2d centre = std::max(0.0, v.free_ahead - half_width) * u + v.centre_offset * n;
  v.end_open_left = freeDistance(points, direction + 0.5 * kPi, params.side_sector, range_cap, centre) >=
                    params.side_open_distance;
  v.end_open_right = freeDistance(points, direction - 0.5 * kPi, params.side_sector, range_cap, centre) >=
                     params.side_open_distance;
  return v;
}

Lane freestLane(const std::vector<Eigen::Vector2d>& points, double direction, const HallwayView& view,
                double clearance, double range_cap) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  const double lo = view.right_wall ? view.right_lateral + clearance : view.centre_offset;
  const double hi = view.left_wall ? view.left_lateral - clearance : view.centre_offset;
  Lane best{view.centre_offset, -1.0};
  for (double lateral = lo; lateral <= hi + 1e-9; lateral += 0.1) {
    double free = range_cap;
    for (const Eigen::Vector2d& q : points) {
      const double along = q.dot(u);
      if (along > 0.0 && along < free && std::abs(q.dot(n) - lateral) <= clearance) free = along;
    }
    const bool nearer = std::abs(lateral - view.centre_offset) < std::abs(best.lateral - view.centre_offset);
    if (free > best.free + 1e-6 || (std::abs(free - best.free) <= 1e-6 && nearer)) best = {lateral, free};
  }
  return best;
}

}  // namespace exploration
