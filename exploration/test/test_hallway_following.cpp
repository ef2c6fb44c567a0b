// The coordinator following hallways in a small simulation of walls: the scan is ray cast against
// wall segments, the lines are the segments themselves, and the robot drives to the coordinator's
// goals (turning on the spot, then straight). The pomdp_topo side is a frontier that never ends.
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "exploration/coordinator.h"

namespace {

using exploration::Coordinator;
using exploration::Decision;
using exploration::Perception;
using exploration::TopoMode;
using exploration::TopoView;
using laser_features::Pose2D;

constexpr double kPi = 3.14159265358979323846;

struct Segment {
  Eigen::Vector2d a, b;
};

// Where the ray from `o` along `u` first meets a wall, or `cap`.
double castRay(const std::vector<Segment>& walls, const Eigen::Vector2d& o, const Eigen::Vector2d& u, double cap) {
  double best = cap;
  for (const Segment& w : walls) {
    const Eigen::Vector2d e = w.b - w.a, d = w.a - o;
    const double den = u.x() * e.y() - u.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const double t = (d.x() * e.y() - d.y() * e.x()) / den;   // along the ray
    const double s = (d.x() * u.y() - d.y() * u.x()) / den;   // along the wall
    if (t > 0.0 && s >= 0.0 && s <= 1.0 && t < best) best = t;
  }
  return best;
}

Perception perceive(const std::vector<Segment>& walls, const Pose2D& pose, double stamp) {
  Perception p;
  p.stamp = stamp;
  p.odom = pose;
  const Eigen::Vector2d o(pose.x, pose.y);
  const Eigen::Rotation2Dd to_robot(-pose.theta);
  for (int k = 0; k < 720; ++k) {
    const double a = pose.theta + k * kPi / 360.0;
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    const double r = castRay(walls, o, u, 15.0);
    if (r < 15.0) p.points.push_back(to_robot * (r * u));
  }
  // The lines: each wall's part within the line extractor's 8 m horizon.
  constexpr double kHorizon = 8.0;
  for (const Segment& w : walls) {
    const Eigen::Vector2d a = to_robot * (w.a - o), e = to_robot * (w.b - o) - a;
    // a + t e on the horizon's circle: |a + t e|^2 = r^2.
    const double qa = e.squaredNorm(), qb = 2.0 * a.dot(e), qc = a.squaredNorm() - kHorizon * kHorizon;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc <= 0.0) continue;
    const double t0 = std::max(0.0, (-qb - std::sqrt(disc)) / (2.0 * qa));
    const double t1 = std::min(1.0, (-qb + std::sqrt(disc)) / (2.0 * qa));
    if (t1 <= t0) continue;
    laser_features::LineSegment l;
    l.start = a + t0 * e;
    l.end = a + t1 * e;
    p.lines.push_back(l);
  }
  return p;
}

// Drives `ticks` of 0.05 s: turns on the spot towards the goal (or its heading once there), then
// straight at 0.5 m/s. Returns the poses driven through.
std::vector<Pose2D> drive(Coordinator* c, const std::vector<Segment>& walls, Pose2D pose, int ticks) {
  TopoView topo;
  topo.valid = true;
  topo.mode = TopoMode::Frontier;
  topo.confident = true;
  topo.heading_valid = true;
  std::vector<Pose2D> poses;
  bool reached = false;
  for (int i = 0; i < ticks; ++i) {
    const Decision d = c->update(perceive(walls, pose, 0.05 * i), topo, reached, false);
    reached = false;
    if (d.has_goal) {
      const Eigen::Vector2d to(d.x - pose.x, d.y - pose.y);
      const bool there = to.norm() < 0.05;
      const double want = there ? d.theta.value_or(pose.theta) : std::atan2(to.y(), to.x());
      const double err = laser_features::normalizeAngle(want - pose.theta);
      pose.theta = laser_features::normalizeAngle(pose.theta + std::clamp(err, -0.075, 0.075));
      if (!there && std::abs(err) < 0.3) {
        const double step = std::min(0.025, to.norm());
        pose.x += step * std::cos(pose.theta);
        pose.y += step * std::sin(pose.theta);
      }
      reached = there && std::abs(err) < 0.02;
    }
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace

// A wing at 30-60 degrees to the building's axes, leaving the end of a 2 m hallway along x: the
// robot turns into it at the end (a way at an angle whose walls run along it, not a dead end) and
// follows its mid-line along its walls, not along the axes (which would zig-zag between them).
TEST(HallwayFollowing, AWingAtAnAngleIsTakenAtTheHallwaysEndAndFollowedAlongItsWalls) {
  for (const auto& [angle, width] : std::vector<std::pair<double, double>>{
           {-0.52, 2.0}, {-0.79, 2.0}, {-1.04, 2.0}, {0.79, 2.0}, {-0.68, 1.5}, {-0.68, 2.0}, {0.68, 1.5}}) {
    SCOPED_TRACE(std::to_string(angle) + " rad, " + std::to_string(width) + " m");
    const Eigen::Vector2d d(std::cos(angle), std::sin(angle)), n(-d.y(), d.x());
    // The wing's walls start where the hallway's walls end (the outer one a little beyond) and run on
    // past where the robot gets to (an open end would be an open area).
    const double side = angle < 0.0 ? 1.0 : -1.0;  // the hallway's wall on the outside of the bend
    const Eigen::Vector2d inner(0.5, -side), outer = inner + side * width * n;
    std::vector<Segment> walls = {{{-12.0, -side}, inner}, {inner, inner + 40.0 * d},
                                  {{-12.0, side}, {outer.x(), side}}, {{outer.x(), side}, outer},
                                  {outer, outer + 40.0 * d}, {{-12.0, -1.0}, {-12.0, 1.0}}};
    Coordinator c;
    const std::vector<Pose2D> poses = drive(&c, walls, Pose2D{-8.0, 0.0, 0.0}, 1400);
    // 12 m into the wing's mid-line.
    const Eigen::Vector2d mid = 0.5 * (inner + outer);
    const Eigen::Vector2d end(poses.back().x, poses.back().y);
    EXPECT_GT((end - mid).dot(d), 6.0) << c.state();
    EXPECT_EQ(c.stats().u_turns, 0) << c.state();
    // On the wing's mid-line, heading along it, once 2 m in.
    for (const Pose2D& p : poses) {
      const Eigen::Vector2d q = Eigen::Vector2d(p.x, p.y) - mid;
      if (q.dot(d) < 2.0) continue;
      EXPECT_LT(std::abs(q.dot(n)), 0.3) << "at " << p.x << " " << p.y;
      EXPECT_LT(std::abs(laser_features::normalizeAngle(p.theta - angle)), 0.25) << "at " << p.x << " " << p.y;
    }
  }
}

// A hallway opening into an open hall (10 x 10 m, wider than any hallway on both sides): the robot
// turns along the hall's wall it came in by and keeps to the hall's walls, where its doors and the
// hallways leaving it are, rather than crossing its middle, where it would see none of them.
TEST(HallwayFollowing, AnOpenHallIsFollowedAlongItsWallsNotCrossed) {
  // The 2 m hallway along x ends at x = 0 in the hall's west wall; the hall spans x 0-10, y -5-5,
  // with a 2 m hallway leaving its north wall at x 6-8.
  const std::vector<Segment> walls = {
      {{-12.0, 1.0}, {0.0, 1.0}},   {{-12.0, -1.0}, {0.0, -1.0}}, {{-12.0, -1.0}, {-12.0, 1.0}},
      {{0.0, 1.0}, {0.0, 5.0}},     {{0.0, -1.0}, {0.0, -5.0}},   {{0.0, -5.0}, {10.0, -5.0}},
      {{10.0, -5.0}, {10.0, 5.0}},  {{10.0, 5.0}, {8.0, 5.0}},    {{6.0, 5.0}, {0.0, 5.0}},
      {{8.0, 5.0}, {8.0, 15.0}},    {{6.0, 5.0}, {6.0, 15.0}}};
  Coordinator c;
  const std::vector<Pose2D> poses = drive(&c, walls, Pose2D{-8.0, 0.0, 0.0}, 2400);
  bool in_hall = false;
  for (const Pose2D& p : poses) {
    if (p.x < 0.5 || p.y > 5.0) continue;
    in_hall = true;
    const double to_wall = std::min({p.x, 10.0 - p.x, p.y + 5.0, 5.0 - p.y});
    EXPECT_LT(to_wall, 2.0) << "in the hall's middle at " << p.x << " " << p.y << ": " << c.state();
  }
  EXPECT_TRUE(in_hall);
  EXPECT_GE(c.stats().turns, 1);
}
