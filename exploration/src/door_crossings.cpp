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

namespace {
// z of (q - o) x (p - o): which side of the line o -> q the point p lies on.
double side(double ox, double oy, double qx, double qy, double px, double py) {
  return (qx - ox) * (py - oy) - (qy - oy) * (px - ox);
}
}  // namespace

DoorSighting inRobotFrame(const Pose2D& sensor, const DoorSighting& d) {
  const Eigen::Vector2d l = laser_features::transformPoint(sensor, Eigen::Vector2d(d.left_x, d.left_y));
  const Eigen::Vector2d r = laser_features::transformPoint(sensor, Eigen::Vector2d(d.right_x, d.right_y));
  return {l.x(), l.y(), r.x(), r.y()};
}

std::optional<DoorCrossing> DoorCrossings::update(const Pose2D& odom, const std::vector<DoorSighting>& doors) {
  if (!std::isfinite(odom.x) || !std::isfinite(odom.y) || !std::isfinite(odom.theta)) return std::nullopt;
  std::optional<DoorCrossing> out;
  if (have_pose_) {
    const double ax = last_.x, ay = last_.y, bx = odom.x, by = odom.y;
    travel_ += std::hypot(bx - ax, by - ay);
    double cx = 0.0, cy = 0.0, width = 0.0, nx = 0.0, ny = 0.0;
    int n = 0;
    std::vector<Seen> kept;
    kept.reserve(seen_.size());
    for (const Seen& s : seen_) {
      const double w = std::hypot(s.rx - s.lx, s.ry - s.ly);
      const double da = side(s.lx, s.ly, s.rx, s.ry, ax, ay), db = side(s.lx, s.ly, s.rx, s.ry, bx, by);
      bool crossed = false;
      if (w > 0.0 && da * db < 0.0) {
        // Where the step meets the door's line, as a fraction along the door from one edge.
        const double f = da / (da - db);
        const double ix = ax + f * (bx - ax), iy = ay + f * (by - ay);
        const double u = ((ix - s.lx) * (s.rx - s.lx) + (iy - s.ly) * (s.ry - s.ly)) / (w * w);
        const double margin = params_.edge_margin / w;
        crossed = u >= -margin && u <= 1.0 + margin;
        if (crossed) {
          cx += 0.5 * (s.lx + s.rx);
          cy += 0.5 * (s.ly + s.ry);
          width += w;
          // The door's normal, turned to point the way the robot went.
          double ux = -(s.ry - s.ly) / w, uy = (s.rx - s.lx) / w;
          if (ux * (bx - ax) + uy * (by - ay) < 0.0) ux = -ux, uy = -uy;
          nx += ux;
          ny += uy;
          ++n;
        }
      }
      if (!crossed && travel_ - s.travel <= params_.memory) kept.push_back(s);
    }
    seen_.swap(kept);
    if (n > 0) {
      DoorCrossing c;
      c.door_odom.x = cx / n;
      c.door_odom.y = cy / n;
      c.door_odom.theta = std::atan2(ny, nx);
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
    seen_.push_back({l.x(), l.y(), r.x(), r.y(), travel_});
  }
  return out;
}

}  // namespace exploration
