// MotionController in closed loop with a small kinematic simulator: a unicycle integrated at 20 Hz,
// a 360-beam laser at 10 Hz ray-cast against segments and circles, and a check of every command
// against the speed and acceleration limits.
#include "exploration/motion_controller.h"
#include "exploration/grid_planner.h"
#include "exploration/occupancy_grid.h"
#include "exploration/path_driver.h"
#include "exploration/waypoint_follower.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

// The program-wide counting operator new of this binary (include in exactly one file).
#include "laser_features/testing/counting_allocator.h"

namespace exploration {
namespace {

using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using Eigen::Vector2d;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::ostream& operator<<(std::ostream& os, MotionStatus s) { return os << toString(s); }

namespace {

// ---------------------------------------------------------------------------------------------
// The world and the simulator

struct Segment {
  Vector2d a, b;
};
struct Circle {
  Vector2d c;
  double r;
};

struct World {
  std::vector<Segment> segments;
  std::vector<Circle> circles;

  void wall(double x0, double y0, double x1, double y1) { segments.push_back({{x0, y0}, {x1, y1}}); }
  void box(double cx, double cy, double hx, double hy) {
    wall(cx - hx, cy - hy, cx + hx, cy - hy);
    wall(cx + hx, cy - hy, cx + hx, cy + hy);
    wall(cx + hx, cy + hy, cx - hx, cy + hy);
    wall(cx - hx, cy + hy, cx - hx, cy - hy);
  }
  void pillar(double cx, double cy, double r) { circles.push_back({{cx, cy}, r}); }

  /// Distance from p to the nearest obstacle surface.
  double clearance(const Vector2d& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments) {
      const Vector2d ab = s.b - s.a;
      const double t = std::clamp((p - s.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (s.a + t * ab - p).norm());
    }
    for (const Circle& c : circles) d = std::min(d, (p - c.c).norm() - c.r);
    return d;
  }

  /// Range along the unit ray o + t u; +infinity when nothing is hit.
  double raycast(const Vector2d& o, const Vector2d& u) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments) {
      const Vector2d e = s.b - s.a;
      const double denom = laser_features::cross2(u, e);
      if (std::abs(denom) < 1e-12) continue;
      const Vector2d w = s.a - o;
      const double t = laser_features::cross2(w, e) / denom;
      const double q = laser_features::cross2(w, u) / denom;
      if (t > 0.0 && q >= 0.0 && q <= 1.0) best = std::min(best, t);
    }
    for (const Circle& c : circles) {
      const Vector2d w = o - c.c;
      const double b = w.dot(u), disc = b * b - (w.squaredNorm() - c.r * c.r);
      if (disc < 0.0) continue;
      const double t = -b - std::sqrt(disc);
      if (t > 0.0) best = std::min(best, t);
    }
    return best;
  }
};

/// A square room of half-size h around the origin: something for the laser to see.
World room(double h = 6.0) {
  World w;
  w.box(0.0, 0.0, h, h);
  return w;
}

struct Sim {
  Sim(World world, const MotionParams& params = MotionParams()) : world(std::move(world)), mc(params), p(params) {}

  World world;
  MotionController mc;
  MotionParams p;
  Pose2D pose;
  double t = 0.0;
  double dt = 0.05;
  int step_count = 0;
  bool scans = true;
  bool bumper = false;
  double latency = 0.0;  // s, a scan is delivered this late (stamped when measured)
  std::mt19937 rng{7};

  Command cmd;
  int limit_violations = 0;
  double min_clearance = std::numeric_limits<double>::infinity();
  double max_speed = 0.0;
  std::string first_violation;

  // A latency-delayed scan waits here.
  std::vector<Vector2d> scan, pending;
  double pending_stamp = -1.0;

  void measure(std::vector<Vector2d>* points) {
    std::normal_distribution<double> noise(0.0, 0.005);
    points->clear();
    for (int i = 0; i < 360; ++i) {
      const double bearing = -kPi + i * (2.0 * kPi / 360.0);
      const double range = world.raycast(pose.translation(), laser_features::unitVector(pose.theta + bearing));
      if (range > 10.0) continue;
      const double r = range + noise(rng);
      points->push_back(r * laser_features::unitVector(bearing));
    }
  }

  void step() {
    if (scans && step_count % 2 == 0) {  // 10 Hz
      if (latency <= 0.0) {
        measure(&scan);
        mc.setScan(scan, t);
      } else {
        if (pending_stamp >= 0.0 && t - pending_stamp >= latency - 1e-9) {
          mc.setScan(pending, pending_stamp);
          pending_stamp = -1.0;
        }
        if (pending_stamp < 0.0) {
          measure(&pending);
          pending_stamp = t;
        }
      }
    }
    const Command last = cmd;
    cmd = mc.update(pose, t, dt, bumper);
    checkLimits(last);
    integrate();
    t += dt;
    ++step_count;
    min_clearance = std::min(min_clearance, world.clearance(pose.translation()));
  }

  void checkLimits(const Command& last) {
    const double eps = 1e-9;
    std::string why;
    if (!std::isfinite(cmd.v) || !std::isfinite(cmd.w)) why = "non-finite";
    if (std::abs(cmd.v) > p.max_linear + eps) why = "|v| above max_linear";
    if (std::abs(cmd.w) > p.max_angular + eps) why = "|w| above max_angular";
    if (!bumper && std::abs(cmd.v - last.v) > p.max_linear_accel * dt + eps) why = "linear acceleration";
    if (!bumper && std::abs(cmd.w - last.w) > p.max_angular_accel * dt + eps) why = "angular acceleration";
    if (!why.empty()) {
      if (limit_violations++ == 0)
        first_violation = why + " at t=" + std::to_string(t) + ": (" + std::to_string(last.v) + ", " +
                          std::to_string(last.w) + ") -> (" + std::to_string(cmd.v) + ", " + std::to_string(cmd.w) + ")";
    }
    max_speed = std::max(max_speed, std::abs(cmd.v));
  }

  void integrate() {
    const double v = cmd.v, w = cmd.w, th = pose.theta;
    if (std::abs(w) < 1e-9) {
      pose.x += v * dt * std::cos(th);
      pose.y += v * dt * std::sin(th);
    } else {
      pose.x += v / w * (std::sin(th + w * dt) - std::sin(th));
      pose.y += v / w * (std::cos(th) - std::cos(th + w * dt));
    }
    pose.theta = normalizeAngle(th + w * dt);
  }

  /// Steps while the controller is Moving (or until `max_time`); returns the time taken.
  double runWhileMoving(double max_time) {
    const double start = t;
    do {
      step();
    } while (mc.status() == MotionStatus::Moving && t - start < max_time);
    return t - start;
  }
  void runFor(double duration) {
    const double end = t + duration - 1e-9;
    while (t < end) step();
  }
  double distanceTo(double x, double y) const { return std::hypot(x - pose.x, y - pose.y); }
};

#define EXPECT_WITHIN_LIMITS(sim) \
  EXPECT_EQ((sim).limit_violations, 0) << (sim).first_violation

// ---------------------------------------------------------------------------------------------
// Reaching goals in free space

struct GoalCase {
  double x, y;
  std::optional<double> theta;
};

void PrintTo(const GoalCase& g, std::ostream* os) {
  *os << "(" << g.x << ", " << g.y << (g.theta ? ", " + std::to_string(*g.theta) : std::string()) << ")";
}

class FreeGoal : public ::testing::TestWithParam<GoalCase> {};

TEST_P(FreeGoal, ReachesWithinToleranceAndTime) {
  const GoalCase g = GetParam();
  Sim sim(room());
  ASSERT_TRUE(sim.mc.setGoal(g.x, g.y, g.theta));
  // Straight-line time at max_linear and turning at max_angular, plus 4 s of accelerating and slowing
  // down (3.2 s for a uniform slow-down over slow_down_distance).
  const double turn = std::abs(std::atan2(g.y, g.x)) + (g.theta ? std::abs(normalizeAngle(*g.theta - std::atan2(g.y, g.x))) : 0.0);
  const double budget = std::hypot(g.x, g.y) / sim.p.max_linear + turn / sim.p.max_angular + 4.0;
  const double took = sim.runWhileMoving(60.0);
  ASSERT_EQ(sim.mc.status(), MotionStatus::Reached) << sim.mc.statusText();
  EXPECT_LT(took, budget);
  EXPECT_LE(sim.distanceTo(g.x, g.y), sim.p.goal_tolerance + 0.005);
  if (g.theta) {
    EXPECT_LE(std::abs(normalizeAngle(*g.theta - sim.pose.theta)), sim.p.heading_tolerance + 0.01);
  }
  // Then it stays there, stopped.
  const Pose2D at_reach = sim.pose;
  sim.runFor(2.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached);
  EXPECT_EQ(sim.cmd.v, 0.0);
  EXPECT_EQ(sim.cmd.w, 0.0);
  EXPECT_LT(std::hypot(sim.pose.x - at_reach.x, sim.pose.y - at_reach.y), 0.005);
  EXPECT_LE(sim.distanceTo(g.x, g.y), sim.p.goal_tolerance + 0.005);
  EXPECT_FALSE(sim.mc.hasGoal());
  EXPECT_WITHIN_LIMITS(sim);
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
}

INSTANTIATE_TEST_SUITE_P(Goals, FreeGoal,
                         ::testing::Values(GoalCase{3.0, 1.0, std::nullopt},     // ahead, slightly left
                                           GoalCase{-2.0, 1.5, -2.0},            // behind, with heading
                                           GoalCase{0.0, -3.0, std::nullopt},    // to the right
                                           GoalCase{1.5, 0.0, kPi},              // ahead, arrive facing back
                                           GoalCase{0.3, 0.2, 1.0},              // close
                                           GoalCase{0.0, 0.0, -kPi / 2},         // turn on the spot only
                                           GoalCase{4.5, -4.0, 0.5}));

TEST(MotionController, ReachesWithTheDesignBaseLimits) {
  MotionParams p;
  p.max_linear = 0.6;
  p.max_angular = 1.5;
  Sim sim(room(), p);
  sim.mc.setGoal(4.0, 3.0, kPi / 2);
  sim.runWhileMoving(60.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached) << sim.mc.statusText();
  EXPECT_LE(sim.distanceTo(4.0, 3.0), p.goal_tolerance + 0.005);
  EXPECT_GT(sim.max_speed, 0.55);  // it did use the higher limit
  EXPECT_WITHIN_LIMITS(sim);
}

// The last centimetres of a mission: a goal a few centimetres behind, with the robot's own
// heading, is reached backwards without turning round (straight back when it lies straight behind;
// turning less than a quarter circle for one a little to the side), within a 5 mm tolerance. Beyond reverse_distance, or with reverse_distance 0, it turns round.
double maxHeadingDeviation(Sim* sim, double max_time) {
  double worst = 0.0;
  const double start = sim->t;
  do {
    sim->step();
    worst = std::max(worst, std::abs(normalizeAngle(sim->pose.theta)));
  } while (sim->mc.status() == MotionStatus::Moving && sim->t - start < max_time);
  return worst;
}

TEST(MotionController, GoalAFewCentimetresBehindIsReachedBackwards) {
  for (const Vector2d goal : {Vector2d(-0.03, 0.0), Vector2d(-0.06, 0.01), Vector2d(-0.02, -0.015)}) {
    Sim sim(room());
    ASSERT_TRUE(sim.mc.setGoal(goal.x(), goal.y(), 0.0, std::make_pair(0.005, 0.02)));
    const double worst = maxHeadingDeviation(&sim, 20.0);
    ASSERT_EQ(sim.mc.status(), MotionStatus::Reached) << sim.mc.statusText();
    EXPECT_LE(sim.distanceTo(goal.x(), goal.y()), 0.006) << goal.transpose();
    EXPECT_LE(std::abs(sim.pose.theta), 0.03) << goal.transpose();
    EXPECT_LT(worst, goal.y() == 0.0 ? 0.05 : kPi / 2) << goal.transpose();
    EXPECT_LT(sim.t, 5.0) << goal.transpose();
    EXPECT_WITHIN_LIMITS(sim);
  }
  MotionParams never;
  never.reverse_distance = 0.0;
  Sim sim(room(), never);
  ASSERT_TRUE(sim.mc.setGoal(-0.03, 0.0, 0.0, std::make_pair(0.005, 0.02)));
  EXPECT_GT(maxHeadingDeviation(&sim, 30.0), 2.0);  // turned round to it and back
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached) << sim.mc.statusText();
}

TEST(MotionController, NoBackingUpIntoAWallBehind) {
  World w = room();
  w.wall(-0.30, -1.0, -0.30, 1.0);  // 5 cm behind the robot's back (radius 0.25)
  Sim sim(w);
  ASSERT_TRUE(sim.mc.setGoal(-0.04, 0.0, 0.0, std::make_pair(0.005, 0.02)));
  sim.runWhileMoving(20.0);
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
  EXPECT_WITHIN_LIMITS(sim);
}

TEST(MotionController, NewGoalReplacesThePreviousOne) {
  Sim sim(room());
  sim.mc.setGoal(4.0, 0.0, std::nullopt);
  sim.runFor(2.0);
  ASSERT_EQ(sim.mc.status(), MotionStatus::Moving);
  sim.mc.setGoal(-2.0, 2.0, std::nullopt);  // behind: it has to brake and turn
  sim.runWhileMoving(40.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached);
  EXPECT_LE(sim.distanceTo(-2.0, 2.0), sim.p.goal_tolerance + 0.005);
  EXPECT_WITHIN_LIMITS(sim);
}

TEST(MotionController, CancelStopsWithinLimits) {
  Sim sim(room());
  sim.mc.setGoal(5.0, 0.0, std::nullopt);
  sim.runFor(2.0);
  ASSERT_GT(sim.cmd.v, 0.3);
  sim.mc.cancel();
  sim.step();
  EXPECT_EQ(sim.mc.status(), MotionStatus::Idle);
  EXPECT_GT(sim.cmd.v, 0.0);  // ramping down, not a jump
  sim.runFor(1.0);
  EXPECT_EQ(sim.cmd.v, 0.0);
  EXPECT_EQ(sim.cmd.w, 0.0);
  EXPECT_WITHIN_LIMITS(sim);
}

// ---------------------------------------------------------------------------------------------
// Limits in every cycle, under goals that keep changing (including behind the robot) among pillars

TEST(MotionController, LimitsHoldInEveryCycle) {
  for (const bool design_limits : {false, true}) {
    MotionParams p;
    if (design_limits) {
      p.max_linear = 0.6;
      p.max_angular = 1.5;
    }
    World w = room(5.0);
    w.pillar(1.5, 1.5, 0.3);
    w.pillar(-2.0, 0.5, 0.4);
    w.box(0.5, -2.5, 0.5, 0.3);
    Sim sim(w, p);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-3.5, 3.5);
    std::uniform_real_distribution<double> th(-kPi, kPi);
    double max_w = 0.0;
    for (int i = 0; i < 25; ++i) {
      Vector2d g;
      do g = {u(rng), u(rng)}; while (w.clearance(g) < 0.6);
      sim.mc.setGoal(g.x(), g.y(), i % 2 ? std::optional<double>(th(rng)) : std::nullopt);
      for (int k = 0; k < 60; ++k) {  // 3 s, often not enough: the goal changes mid-course
        sim.step();
        max_w = std::max(max_w, std::abs(sim.cmd.w));
      }
    }
    EXPECT_WITHIN_LIMITS(sim);
    // The limits were reached, so the check above meant something.
    EXPECT_GT(sim.max_speed, 0.9 * p.max_linear);
    EXPECT_GT(max_w, 0.9 * p.max_angular);
    EXPECT_GT(sim.min_clearance, p.robot_radius);
  }
}

// ---------------------------------------------------------------------------------------------
// Avoidance

struct ObstacleCase {
  const char* name;
  World world;
  double latency;
};

void PrintTo(const ObstacleCase& c, std::ostream* os) { *os << c.name; }

class AroundObstacle : public ::testing::TestWithParam<ObstacleCase> {};

TEST_P(AroundObstacle, ReachesTheGoalWithoutTouching) {
  Sim sim(GetParam().world);
  sim.latency = GetParam().latency;
  sim.mc.setGoal(4.0, 0.0, std::nullopt);
  double closest = std::numeric_limits<double>::infinity();
  bool avoided = false;
  // (With late scans, the first cycles have none yet: NoScan.)
  while ((sim.mc.status() == MotionStatus::Moving || sim.mc.status() == MotionStatus::NoScan) && sim.t < 40.0) {
    sim.step();
    closest = std::min(closest, sim.min_clearance);
    avoided |= std::abs(sim.pose.y) > 0.3;  // it did leave the straight line
  }
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached) << sim.mc.statusText();
  EXPECT_LE(sim.distanceTo(4.0, 0.0), sim.p.goal_tolerance + 0.005);
  EXPECT_TRUE(avoided);
  // The robot's circle never touched an obstacle (the margin may be eaten a little on the arcs).
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius) << GetParam().name;
  EXPECT_LT(sim.t, 25.0);
  EXPECT_WITHIN_LIMITS(sim);
  std::printf("[          ] %s: min clearance %.3f m, %.1f s\n", GetParam().name, sim.min_clearance, sim.t);
}

World withBox(double cy, double hx, double hy) {
  World w = room();
  w.box(2.0, cy, hx, hy);
  return w;
}
World withPillar() {
  World w = room();
  w.pillar(2.0, 0.05, 0.35);
  return w;
}
World withWall() {  // a thin wall across the way
  World w = room();
  w.wall(2.0, -0.9, 2.0, 1.0);
  return w;
}
World slalom() {  // each box across the straight line, a 1 m gap between them
  World w = room();
  w.box(1.3, 0.6, 0.3, 0.7);
  w.box(2.9, -0.6, 0.3, 0.7);
  return w;
}

INSTANTIATE_TEST_SUITE_P(Obstacles, AroundObstacle,
                         ::testing::Values(ObstacleCase{"centred box", withBox(0.0, 0.4, 0.4), 0.0},
                                           ObstacleCase{"offset box", withBox(0.15, 0.4, 0.5), 0.0},
                                           ObstacleCase{"box, late scans", withBox(0.0, 0.4, 0.4), 0.1},
                                           ObstacleCase{"pillar", withPillar(), 0.0},
                                           ObstacleCase{"thin wall", withWall(), 0.0},
                                           ObstacleCase{"slalom", slalom(), 0.0}));

// ---------------------------------------------------------------------------------------------
// Along a grid path (GridPlanner + WaypointFollower, as a room visit drives to a door or a goal)

/// The grid a room visit would have of `world` within `bounds`: the cells within half a cell of an
/// obstacle Occupied, the others Free.
OccupancyGrid gridOf(const World& world, const GridBounds& bounds) {
  OccupancyGrid grid(OccupancyGridParams(), bounds);
  const double half = 0.5 * grid.resolution();
  const CellIndex lo = grid.worldToCell({bounds.min_x + half, bounds.min_y + half});
  const CellIndex hi = grid.worldToCell({bounds.max_x - half, bounds.max_y - half});
  for (int iy = lo.y; iy <= hi.y; ++iy)
    for (int ix = lo.x; ix <= hi.x; ++ix)
      grid.setCell(ix, iy, world.clearance(grid.cellCenter(ix, iy)) < half ? CellState::Occupied : CellState::Free);
  return grid;
}

/// Plans from the sim's pose to `goal` and drives the path one waypoint at a time (the last one
/// the goal). Returns the sim time the goal took, or +inf when not reached within `max_time`.
double followPath(Sim* sim, const OccupancyGrid& grid, const Vector2d& goal, double max_time) {
  GridPlanner planner;
  planner.setMap(grid);
  const std::optional<Path> path = planner.plan(sim->pose.translation(), goal);
  if (!path) return std::numeric_limits<double>::infinity();
  WaypointFollower follower;
  follower.set(path->waypoints);
  std::size_t sent = path->waypoints.size();
  const double start = sim->t;
  while (sim->t - start < max_time) {
    follower.advance(sim->pose.translation(), planner);
    if (follower.done()) return sim->t - start;
    if (follower.index() != sent) {  // a new goal for each waypoint, as the exploration node sends
      sent = follower.index();
      sim->mc.setGoal(follower.current().x(), follower.current().y(), std::nullopt);
    }
    sim->step();
  }
  return std::numeric_limits<double>::infinity();
}

// A path bends round a table's corner into the lane between the table and a wall, 0.88 m wide:
// 0.18 m more than the robot with its margin. A robot that turned for the next waypoint as soon as
// it was near the bend would head across the table's corner, find no free heading into the lane
// and turn to and fro (a mission once spun for 600 s so, beside a table, and never left the room).
TEST(WaypointFollower, ABendRoundAnObstacleIsDrivenToBeforeTheWayOnIsTaken) {
  World world = room();
  world.wall(-4.0, 1.0, 4.0, 1.0);        // the wall along the lane
  world.box(-0.75, -0.94, 0.75, 1.06);    // the table: x in [-1.5, 0], y in [-2.0, 0.12]
  Sim sim(world);
  sim.pose = Pose2D{0.9, -1.5, kPi / 2.0};
  const OccupancyGrid grid = gridOf(world, GridBounds{-5.0, -5.0, 5.0, 0.98});
  const Vector2d goal(-2.5, 0.55);
  const double took = followPath(&sim, grid, goal, 60.0);
  EXPECT_LT(took, 30.0) << "stopped at (" << sim.pose.x << ", " << sim.pose.y << "): " << sim.mc.statusText();
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
  EXPECT_WITHIN_LIMITS(sim);
  std::printf("[          ] round the table's corner in %.1f s, min clearance %.3f m\n", took, sim.min_clearance);
}

TEST(WaypointFollower, AWaypointIsPassedNearItWhereTheWayOnIsClearAndOnItOtherwise) {
  World world = room();
  world.box(0.0, 0.0, 0.5, 0.5);  // a block: the path from below-right to above-left bends round it
  const OccupancyGrid grid = gridOf(world, GridBounds{-3.0, -3.0, 3.0, 3.0});
  GridPlanner planner;
  planner.setMap(grid);
  const Vector2d start(1.5, -1.5), goal(-1.5, 1.5);
  const std::optional<Path> path = planner.plan(start, goal);
  ASSERT_TRUE(path.has_value());
  const std::vector<Vector2d>& w = path->waypoints;
  // A bend k of the path where the robot a quarter metre short of it, on the way to it, has the
  // block's corner between itself and the next waypoint.
  std::size_t k = 1;
  const auto shortOf = [&](std::size_t i) { return Vector2d(w[i] + 0.25 * (w[i - 1] - w[i]).normalized()); };
  while (k + 1 < w.size() && !((w[k - 1] - w[k]).norm() > 0.25 && !planner.clearLine(shortOf(k), w[k + 1]))) ++k;
  ASSERT_LT(k + 1, w.size()) << "no bend round the block's corner";
  const std::vector<Vector2d> from_bend(w.begin() + long(k), w.end());

  WaypointFollower follower;
  follower.set(from_bend);
  follower.advance(shortOf(k), planner);  // within kPassRadius, but the way on is not clear
  EXPECT_EQ(follower.index(), 0u);
  follower.advance(w[k] + Vector2d(0.05, 0.0), planner);  // on the bend (within kOnWaypoint): passed
  EXPECT_EQ(follower.index(), 1u);
  // Near the bend on its outer side (away from the block at the origin), the way on clear: passed
  // without driving onto it.
  const Vector2d outside = w[k] + 0.25 * w[k].normalized();
  ASSERT_TRUE(planner.clearLine(outside, w[k + 1]));
  follower.set(from_bend);
  follower.advance(outside, planner);
  EXPECT_EQ(follower.index(), 1u);
  // Far from the first waypoint nothing is passed; near the last one the path is done.
  follower.set(w);
  follower.advance(goal + Vector2d(0.2, 0.0), planner);
  EXPECT_EQ(follower.index(), 0u);
  follower.set({goal});
  follower.advance(goal + Vector2d(0.2, 0.0), planner);
  EXPECT_TRUE(follower.done());
}

// What is left of a path is clear in a planner's snapshot only where no obstacle lies on the way
// from the robot to the waypoint headed for and on; legs already driven do not count (SuiteVisit
// keeps the path it follows while its rest stays clear of the scan's returns).
TEST(WaypointFollower, TheRestOfAPathIsClearWhereNothingLiesOnItFromTheRobotOn) {
  World world = room();
  world.box(0.0, 0.0, 0.5, 0.5);
  const OccupancyGrid grid = gridOf(world, GridBounds{-3.0, -3.0, 3.0, 3.0});
  GridPlanner planner;
  planner.setMap(grid);
  const std::optional<Path> path = planner.plan(Vector2d(1.5, -1.5), Vector2d(-1.5, 1.5));
  ASSERT_TRUE(path.has_value());
  const std::vector<Vector2d>& w = path->waypoints;
  ASSERT_GE(w.size(), 3u);
  WaypointFollower follower;
  follower.set(w);
  follower.advance(w[0], planner);  // at the start: its waypoint passed, the first leg is driven
  ASSERT_EQ(follower.index(), 1u);
  EXPECT_TRUE(follower.restClear(w[0], planner));
  const Vector2d on_first_leg = 0.5 * (w[0] + w[1]);
  planner.addObstacles({on_first_leg + 0.2 * (w[1] - w[0]).normalized()});  // ahead on the first leg
  EXPECT_FALSE(follower.restClear(w[0], planner));
  follower.set(std::vector<Vector2d>(w.begin() + 1, w.end()));  // the first leg driven: behind
  EXPECT_TRUE(follower.restClear(w[1], planner));
}

TEST(MotionController, DeadEndEndsBlocked) {
  // A corridor 1.6 m wide, closed ahead, open behind; the goal is behind its end wall.
  World w = room(8.0);
  w.wall(-4.0, 0.8, 1.2, 0.8);
  w.wall(-4.0, -0.8, 1.2, -0.8);
  w.wall(1.2, -0.8, 1.2, 0.8);
  Sim sim(w);
  sim.mc.setGoal(2.5, 0.0, std::nullopt);
  sim.runWhileMoving(60.0);
  ASSERT_EQ(sim.mc.status(), MotionStatus::Blocked) << sim.mc.statusText();
  EXPECT_NE(sim.mc.statusText().find("no progress"), std::string::npos) << sim.mc.statusText();
  EXPECT_LT(sim.t, 20.0);
  EXPECT_FALSE(sim.mc.hasGoal());
  // Stopped for good: zero within the deceleration time, then nothing moves.
  sim.runFor(sim.p.max_linear / sim.p.max_linear_accel + 0.05);
  EXPECT_EQ(sim.cmd.v, 0.0);
  EXPECT_EQ(sim.cmd.w, 0.0);
  const Pose2D stopped = sim.pose;
  for (int i = 0; i < 60; ++i) {
    sim.step();
    ASSERT_EQ(sim.cmd.v, 0.0);
    ASSERT_EQ(sim.cmd.w, 0.0);
  }
  EXPECT_EQ(sim.pose.x, stopped.x);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Blocked);
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
  EXPECT_WITHIN_LIMITS(sim);
}

// The narrowest door (0.7 m, config/building.yaml) leaves a 0.25 m robot 0.1 m a side: the whole
// safety margin. Approached from off its axis (up to 0.3 m aside, 1 rad off) towards goals up to
// 0.3 m aside behind it, a 0.72 m door is passed from every start once the controller is told it
// passes a door that wide (it keeps half the slack); with the full margin it is blocked from most.
TEST(MotionController, TheNarrowestDoorIsPassedWithAClearanceThatFitsIt) {
  int starts = 0, blocked_with_full_margin = 0;
  for (const double y0 : {0.0, 0.1, 0.2, 0.3}) {
    for (const double heading : {0.0, 0.3, 0.6, 1.0}) {
      for (const double goal_y : {0.0, 0.3, -0.3}) {
        for (const bool passage : {false, true}) {
          World w = room(8.0);
          w.wall(0.0, -4.0, 0.0, -0.36);  // a wall across the room with the door in it
          w.wall(0.0, 0.36, 0.0, 4.0);
          Sim sim(w);
          sim.pose = Pose2D{-0.6, y0, heading};
          if (passage) sim.mc.setPassageWidth(0.72);
          sim.mc.setGoal(0.8, goal_y, std::nullopt);
          sim.runWhileMoving(60.0);
          if (!passage) {
            ++starts;
            if (sim.mc.status() == MotionStatus::Blocked) ++blocked_with_full_margin;
            continue;
          }
          SCOPED_TRACE(testing::Message() << "from y " << y0 << ", heading " << heading << " to y " << goal_y);
          EXPECT_EQ(sim.mc.status(), MotionStatus::Reached) << sim.mc.statusText();
          EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
          EXPECT_WITHIN_LIMITS(sim);
        }
      }
    }
  }
  EXPECT_GT(blocked_with_full_margin, starts / 2) << "the full margin should not fit this door";
}

TEST(MotionController, ClosedRoomGoalOutsideEndsBlocked) {
  World w;
  w.box(0.0, 0.0, 1.2, 1.0);
  Sim sim(w);
  sim.mc.setGoal(3.0, 0.5, std::nullopt);
  sim.runWhileMoving(60.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Blocked) << sim.mc.statusText();
  // Every new best distance (by progress_distance) restarts the stuck timer, so wandering in the room
  // lasts a few stuck_time at most: the best distance is bounded by the walls.
  EXPECT_LT(sim.t, 30.0);
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
  EXPECT_WITHIN_LIMITS(sim);
}

TEST(MotionController, SlowsDownBeforeAnObstacleAhead) {
  // A goal just in front of a wall, inside the margin: the robot stops short instead of touching.
  World w = room();
  w.wall(2.0, -2.0, 2.0, 2.0);
  Sim sim(w);
  sim.mc.setGoal(1.8, 0.0, std::nullopt);
  sim.runWhileMoving(30.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Blocked);
  EXPECT_GT(sim.min_clearance, sim.p.robot_radius);
  EXPECT_LT(sim.pose.x, 2.0 - sim.p.robot_radius);
  EXPECT_WITHIN_LIMITS(sim);
}

// ---------------------------------------------------------------------------------------------
// Watchdog

TEST(MotionController, WatchdogStopsWithoutScansAndResumes) {
  Sim sim(room());
  sim.mc.setGoal(5.0, 0.0, std::nullopt);
  sim.runFor(2.0);
  ASSERT_EQ(sim.mc.status(), MotionStatus::Moving);
  ASSERT_GT(sim.cmd.v, 0.45);  // full speed when the scans stop
  sim.scans = false;
  const double last_scan = sim.t - 2 * sim.dt;  // the last step of runFor() was an odd one
  double detected = -1.0, stopped = -1.0;
  while (sim.t < 4.0) {
    sim.step();
    const double now = sim.t - sim.dt;  // the time of the cycle just run
    if (detected < 0.0 && sim.mc.status() == MotionStatus::NoScan) detected = now;
    if (detected >= 0.0 && stopped < 0.0 && sim.cmd.v == 0.0 && sim.cmd.w == 0.0) stopped = now;
    if (detected < 0.0) {
      EXPECT_EQ(sim.mc.status(), MotionStatus::Moving);
    }
    if (stopped >= 0.0) {
      ASSERT_EQ(sim.cmd.v, 0.0);
      ASSERT_EQ(sim.cmd.w, 0.0);
    }
  }
  ASSERT_GE(detected, 0.0);
  ASSERT_GE(stopped, 0.0);
  EXPECT_GT(detected, last_scan + sim.p.scan_timeout - 1e-9);
  EXPECT_LE(detected, last_scan + sim.p.scan_timeout + sim.dt + 1e-9);
  EXPECT_LE(stopped - detected, 0.5 + 1e-9);
  EXPECT_EQ(sim.mc.status(), MotionStatus::NoScan);
  EXPECT_NE(sim.mc.statusText().find("scan"), std::string::npos);
  EXPECT_TRUE(sim.mc.hasGoal());
  // Scans return: it drives on to the goal.
  sim.scans = true;
  for (int i = 0; i < 2 && sim.mc.status() == MotionStatus::NoScan; ++i) sim.step();  // scans at 10 Hz
  EXPECT_EQ(sim.mc.status(), MotionStatus::Moving);
  sim.runWhileMoving(30.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached);
  EXPECT_LE(sim.distanceTo(5.0, 0.0), sim.p.goal_tolerance + 0.005);
  EXPECT_WITHIN_LIMITS(sim);
}

TEST(MotionController, NoScanAtAllNeverMoves) {
  Sim sim(room());
  sim.scans = false;
  sim.mc.setGoal(2.0, 0.0, std::nullopt);
  for (int i = 0; i < 40; ++i) {
    sim.step();
    ASSERT_EQ(sim.cmd.v, 0.0);
    ASSERT_EQ(sim.cmd.w, 0.0);
    ASSERT_EQ(sim.mc.status(), MotionStatus::NoScan);
  }
}

// ---------------------------------------------------------------------------------------------
// Bumper

TEST(MotionController, BumperStopsAtOnceUntilANewGoal) {
  Sim sim(room());
  sim.mc.setGoal(5.0, 1.0, std::nullopt);
  sim.runFor(2.0);
  ASSERT_GT(sim.cmd.v, 0.45);
  sim.bumper = true;
  sim.step();
  EXPECT_EQ(sim.cmd.v, 0.0);
  EXPECT_EQ(sim.cmd.w, 0.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Bumped);
  sim.bumper = false;  // released: still stopped
  for (int i = 0; i < 40; ++i) {
    sim.step();
    ASSERT_EQ(sim.cmd.v, 0.0);
    ASSERT_EQ(sim.cmd.w, 0.0);
    ASSERT_EQ(sim.mc.status(), MotionStatus::Bumped);
  }
  EXPECT_FALSE(sim.mc.hasGoal());
  sim.mc.setGoal(5.0, 1.0, std::nullopt);
  sim.runWhileMoving(30.0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached);
  EXPECT_WITHIN_LIMITS(sim);  // the bump cycle is exempt
}

TEST(MotionController, CancelClearsABump) {
  Sim sim(room());
  sim.bumper = true;
  sim.step();
  EXPECT_EQ(sim.mc.status(), MotionStatus::Bumped);
  sim.bumper = false;
  sim.mc.cancel();
  sim.step();
  EXPECT_EQ(sim.mc.status(), MotionStatus::Idle);
}

// ---------------------------------------------------------------------------------------------
// Non-finite inputs

TEST(MotionController, NonFiniteGoalIsRefused) {
  for (const GoalCase g : {GoalCase{kNaN, 1.0, std::nullopt}, GoalCase{1.0, INFINITY, std::nullopt},
                           GoalCase{1.0, 1.0, kNaN}}) {
    Sim sim(room());
    EXPECT_FALSE(sim.mc.setGoal(g.x, g.y, g.theta));
    EXPECT_EQ(sim.mc.status(), MotionStatus::Invalid);
    EXPECT_NE(sim.mc.statusText().find("goal"), std::string::npos) << sim.mc.statusText();
    EXPECT_FALSE(sim.mc.hasGoal());
    for (int i = 0; i < 20; ++i) {
      sim.step();
      ASSERT_EQ(sim.cmd.v, 0.0);
      ASSERT_EQ(sim.cmd.w, 0.0);
    }
    EXPECT_EQ(sim.mc.status(), MotionStatus::Invalid);
  }
  // A bad goal also cancels a good one being driven to.
  Sim sim(room());
  sim.mc.setGoal(5.0, 0.0, std::nullopt);
  sim.runFor(2.0);
  EXPECT_FALSE(sim.mc.setGoal(kNaN, kNaN, std::nullopt));
  sim.runFor(1.0);
  EXPECT_EQ(sim.cmd.v, 0.0);
  EXPECT_WITHIN_LIMITS(sim);
}

TEST(MotionController, NonFinitePoseIsRefused) {
  MotionController mc;
  const std::vector<Vector2d> scan = {{3.0, 0.0}, {0.0, 3.0}};
  mc.setScan(scan, 0.0);
  mc.setGoal(2.0, 0.0, std::nullopt);
  Command c = mc.update(Pose2D{kNaN, 0.0, 0.0}, 0.0, 0.05, false);
  EXPECT_EQ(c.v, 0.0);
  EXPECT_EQ(c.w, 0.0);
  EXPECT_EQ(mc.status(), MotionStatus::Invalid);
  EXPECT_NE(mc.statusText().find("pose"), std::string::npos) << mc.statusText();
  c = mc.update(Pose2D{0.0, 0.0, INFINITY}, 0.05, 0.05, false);
  EXPECT_EQ(c.v, 0.0);
  EXPECT_EQ(mc.status(), MotionStatus::Invalid);
  c = mc.update(Pose2D{}, kNaN, 0.05, false);  // the time
  EXPECT_EQ(c.v, 0.0);
  EXPECT_EQ(mc.status(), MotionStatus::Invalid);
  EXPECT_NE(mc.statusText().find("time"), std::string::npos) << mc.statusText();
  // The goal survives a bad pose: the next good one drives on.
  EXPECT_TRUE(mc.hasGoal());
  mc.update(Pose2D{}, 0.1, 0.05, false);
  EXPECT_EQ(mc.status(), MotionStatus::Moving);
}

TEST(MotionController, NonFinitePoseWhileMovingStopsWithinLimits) {
  Sim sim(room());
  sim.mc.setGoal(5.0, 0.0, std::nullopt);
  sim.runFor(2.0);
  ASSERT_GT(sim.cmd.v, 0.45);
  Command last = sim.cmd;
  for (int i = 0; i < 20; ++i) {
    const Command c = sim.mc.update(Pose2D{kNaN, kNaN, kNaN}, sim.t, sim.dt, false);
    sim.t += sim.dt;
    ASSERT_TRUE(std::isfinite(c.v) && std::isfinite(c.w));
    EXPECT_LE(std::abs(c.v - last.v), sim.p.max_linear_accel * sim.dt + 1e-9);
    EXPECT_LE(c.v, last.v);
    EXPECT_EQ(sim.mc.status(), MotionStatus::Invalid);
    last = c;
  }
  EXPECT_EQ(last.v, 0.0);  // 1 s is enough to stop from 0.5 m/s
  sim.cmd = last;
  sim.runWhileMoving(30.0);  // good poses again (the scans too)
  EXPECT_EQ(sim.mc.status(), MotionStatus::Reached);
  EXPECT_WITHIN_LIMITS(sim);
}

TEST(MotionController, NonFiniteDtHoldsTheCommand) {
  Sim sim(room());
  sim.mc.setGoal(5.0, 0.0, std::nullopt);
  sim.runFor(1.0);
  const Command before = sim.cmd;
  const Command c = sim.mc.update(sim.pose, sim.t, kNaN, false);
  EXPECT_EQ(c.v, before.v);
  EXPECT_EQ(c.w, before.w);
  const Command d = sim.mc.update(sim.pose, sim.t, -1.0, false);
  EXPECT_EQ(d.v, before.v);
}

TEST(MotionController, NonFiniteScanPointsAreSkipped) {
  MotionController mc;
  std::vector<Vector2d> scan;
  for (int i = 0; i < 20; ++i) scan.emplace_back(0.8, -0.5 + 0.05 * i);  // a wall 0.8 m ahead
  scan.emplace_back(kNaN, 0.0);
  scan.emplace_back(INFINITY, 1.0);
  scan.emplace_back(0.5, -INFINITY);
  EXPECT_TRUE(mc.setScan(scan, 0.0));
  EXPECT_EQ(mc.scanSize(), 20u);
  EXPECT_FALSE(mc.setScan(scan, kNaN));
  mc.setGoal(3.0, 0.0, std::nullopt);
  const Command c = mc.update(Pose2D{}, 0.0, 0.05, false);
  EXPECT_TRUE(std::isfinite(c.v) && std::isfinite(c.w));
  EXPECT_EQ(mc.status(), MotionStatus::Moving);
  // The good points count: the wall 0.8 m ahead leaves 0.8 - 0.35 m of travel.
  EXPECT_NEAR(mc.freeDistanceAhead(), 0.8 - 0.35, 1e-6);
  EXPECT_GT(std::abs(normalizeAngle(mc.targetHeading())), 0.1);  // straight ahead is not free
}

TEST(MotionController, RefusesBadParams) {
  MotionParams p;
  p.max_linear = 0.0;
  EXPECT_THROW(MotionController{p}, std::invalid_argument);
  p = MotionParams();
  p.candidate_headings = 2;
  EXPECT_THROW(MotionController{p}, std::invalid_argument);
  p = MotionParams();
  p.safety_margin = kNaN;
  std::string why;
  EXPECT_FALSE(MotionController::validate(p, &why));
  EXPECT_NE(why.find("safety_margin"), std::string::npos);
  p = MotionParams();
  p.reverse_distance = p.safety_margin + 0.01;  // the rear is checked against the current scan only
  EXPECT_FALSE(MotionController::validate(p, &why));
  EXPECT_NE(why.find("reverse_distance"), std::string::npos);
  EXPECT_TRUE(MotionController::validate(MotionParams()));
}

// ---------------------------------------------------------------------------------------------
// Motion compensation of late scans

TEST(MotionController, LateScanIsPlacedWithThePoseAtItsStamp) {
  // The robot drives along x at 0.5 m/s; a wall 1 m ahead measured 0.5 s ago is 0.75 m ahead now.
  MotionController mc;
  mc.setGoal(10.0, 0.0, std::nullopt);
  std::vector<Vector2d> scan;
  for (int i = -10; i <= 10; ++i) scan.emplace_back(1.0, 0.05 * i);
  for (int i = 0; i <= 8; ++i) mc.update(Pose2D{0.05 * i, 0.0, 0.0}, 0.1 * i, 0.1, false);
  mc.setScan(scan, 0.4);  // measured at x = 0.2
  mc.update(Pose2D{0.45, 0.0, 0.0}, 0.9, 0.1, false);
  EXPECT_NEAR(mc.freeDistanceAhead(), 1.2 - 0.45 - 0.35, 1e-6);
  mc.setScan(scan, 0.85);  // between two poses: x = 0.425
  mc.update(Pose2D{0.5, 0.0, 0.0}, 1.0, 0.1, false);
  EXPECT_NEAR(mc.freeDistanceAhead(), 1.425 - 0.5 - 0.35, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Allocation

TEST(MotionController, SteadyStateCyclesDoNotAllocate) {
  World w = room();
  w.box(2.0, 0.0, 0.4, 0.4);
  Sim sim(w);
  sim.mc.setGoal(4.0, 0.0, std::nullopt);
  sim.runFor(0.5);  // warm-up: the buffers grow to the scan size
  // Scans prepared before counting, replayed with their stamps.
  std::vector<std::vector<Vector2d>> scans(20);
  std::vector<Pose2D> poses;
  Pose2D pose = sim.pose;
  for (auto& s : scans) {
    Sim probe(w);
    probe.pose = pose;
    probe.measure(&s);
    s.resize(300);  // same size each time
    poses.push_back(pose);
    pose.x += 0.02;
  }
  const long before = laser_features::testing::allocationCount();
  double t = sim.t;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    sim.mc.setScan(scans[i], t);
    sim.mc.update(poses[i], t, 0.05, false);
    t += 0.05;
    sim.mc.update(poses[i], t, 0.05, false);
    t += 0.05;
  }
  EXPECT_EQ(laser_features::testing::allocationCount() - before, 0);
  EXPECT_EQ(sim.mc.status(), MotionStatus::Moving) << sim.mc.statusText();
}

// PathDriver (the frontier baseline's goal along its planned path): each waypoint in turn, the
// goal's end reported once, as reached.
TEST(PathDriver, AGoalIsDrivenAlongItsPathAndEndsReachedOnce) {
  Sim sim(room(8.0));
  const PathDriverParams params;
  PathDriver driver(sim.p, params);
  const Vector2d corner(1.5, 0.0), goal(1.5, 1.5);
  driver.follow({sim.pose.translation(), corner, goal}, sim.pose.translation());
  int replans = 0, warnings = 0;
  double nearest_corner = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 1200 && replans == 0; ++i) {
    if (i % 2 == 0) {
      sim.measure(&sim.scan);
      driver.setScan(sim.scan, sim.t);
    }
    const PathDriver::Step step = driver.update(sim.pose, sim.t, sim.dt, false);
    sim.cmd = step.command;
    sim.integrate();
    sim.t += sim.dt;
    replans += step.replan;
    warnings += step.warn;
    nearest_corner = std::min(nearest_corner, (sim.pose.translation() - corner).norm());
  }
  EXPECT_EQ(replans, 1);
  EXPECT_EQ(warnings, 0);
  EXPECT_LE(nearest_corner, params.waypoint_tolerance + 0.05) << "the corner was cut";
  EXPECT_LE((sim.pose.translation() - goal).norm(), params.goal_reach_tolerance + 0.05);
  bool reached = false, stopped = true;
  driver.takeEnds(&reached, &stopped);
  EXPECT_TRUE(reached);
  EXPECT_FALSE(stopped);
  driver.takeEnds(&reached, &stopped);  // taken: cleared
  EXPECT_FALSE(reached);
}

// A controller that gives up (no way through a wall across the room) ends the goal stopped, with a
// warning; stop() leaves the controller idle, asking for nothing.
TEST(PathDriver, AControllerThatGivesUpEndsTheGoalStopped) {
  World w = room(8.0);
  w.wall(1.0, -4.0, 1.0, 4.0);
  Sim sim(w);
  PathDriver driver(sim.p, PathDriverParams());
  driver.follow({sim.pose.translation(), Vector2d(3.0, 0.0)}, sim.pose.translation());
  PathDriver::Step step;
  for (int i = 0; i < 1200 && !step.replan; ++i) {
    if (i % 2 == 0) {
      sim.measure(&sim.scan);
      driver.setScan(sim.scan, sim.t);
    }
    step = driver.update(sim.pose, sim.t, sim.dt, false);
    sim.cmd = step.command;
    sim.integrate();
    sim.t += sim.dt;
  }
  ASSERT_TRUE(step.replan);
  EXPECT_EQ(step.status, MotionStatus::Blocked) << driver.statusText();
  EXPECT_TRUE(step.warn);
  bool reached = true, stopped = false;
  driver.takeEnds(&reached, &stopped);
  EXPECT_FALSE(reached);
  EXPECT_TRUE(stopped);
  driver.stop();
  for (int i = 0; i < 40; ++i) {
    step = driver.update(sim.pose, sim.t, sim.dt, false);
    sim.t += sim.dt;
    EXPECT_FALSE(step.replan);
  }
  EXPECT_EQ(step.status, MotionStatus::Idle);
}

}  // namespace
}  // namespace exploration
