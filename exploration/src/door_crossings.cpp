#include "exploration/door_crossings.h"

#include <algorithm>
#include <cmath>

namespace exploration {

bool DoorCrossings::validate(const Params& p, std::string* why) {
  if (!(p.memory > 0.0)) {
    if (why) *why = "crossing_memory must be > 0";
    return false;
  }
  if (!(p.edge_margin >= 0.0)) {
    if (why) *why = "crossing_edge_margin must be >= 0";
    return false;
  }
  return true;
}

DoorSighting inRobotFrame(const Pose2D& sensor, const DoorSighting& d) {
  const Eigen::Vector2d l = laser_features::transformPoint(sensor, Eigen::Vector2d(d.left_x, d.left_y));
  const Eigen::Vector2d r = laser_features::transformPoint(sensor, Eigen::Vector2d(d.right_x, d.right_y));
  return {l.x(), l.y(), r.x(), r.y()};
}

std::optional<DoorCrossing> DoorCrossings::update(const Pose2D& odom, const std::vector<DoorSighting>& doors) {
  if (!std::isfinite(odom.x) || !std::isfinite(odom.y) || !std::isfinite(odom.theta)) return std::nullopt;
  std::optional<DoorCrossing> out;
  if (have_pose_) {
    const Eigen::Vector2d a(last_.x, last_.y), b(odom.x, odom.y), step = b - a;
    travel_ += step.norm();
    Eigen::Vector2d centre = Eigen::Vector2d::Zero(), normal = Eigen::Vector2d::Zero();
    double width = 0.0;
    int n = 0;
    // Sightings of the crossed door are used up; others are kept for `memory` metres (in place: no
    // allocation per scan).
    seen_.erase(std::remove_if(seen_.begin(), seen_.end(), [&](const Seen& s) {
      const Eigen::Vector2d edge = s.right - s.left;
      const double w = edge.norm();
      const double da = laser_features::cross2(edge, a - s.left), db = laser_features::cross2(edge, b - s.left);
      if (w > 0.0 && da * db < 0.0) {
        // Where the step meets the door's line, as a fraction along the door from its left edge.
        const Eigen::Vector2d meet = a + da / (da - db) * step;
        const double u = (meet - s.left).dot(edge) / (w * w), margin = params_.edge_margin / w;
        if (u >= -margin && u <= 1.0 + margin) {
          centre += 0.5 * (s.left + s.right);
          width += w;
          // The door's normal, turned to point the way the robot went.
          const Eigen::Vector2d across(-edge.y() / w, edge.x() / w);
          normal += across.dot(step) < 0.0 ? -across : across;
          ++n;
          return true;
        }
      }
      return travel_ - s.travel > params_.memory;
    }), seen_.end());
    if (n > 0) {
      DoorCrossing c;
      c.door_odom = Pose2D{centre.x() / n, centre.y() / n, std::atan2(normal.y(), normal.x())};
      c.width = width / n;
      c.sightings = n;
      out = c;
    }
  }
  last_ = odom;
  have_pose_ = true;
  for (const DoorSighting& d : doors) {
    const Eigen::Vector2d l = laser_features::transformPoint(odom, Eigen::Vector2d(d.left_x, d.left_y));
    const Eigen::Vector2d r = laser_features::transformPoint(odom, Eigen::Vector2d(d.right_x, d.right_y));
    if (!l.allFinite() || !r.allFinite()) continue;
    seen_.push_back({l, r, travel_});
  }
  return out;
}

}  // namespace exploration
