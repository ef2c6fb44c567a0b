// RoomExplorer (the metric mode of the coordinator: one room's coverage, Tomatis et al. 2001) on
// synthetic worlds: walls as segments, a 360-beam laser ray-cast against them (+inf beyond its
// range), a point robot that moves 0.3 m per second along the planned path, scanning after every
// step, and a door detector that reports the doors whose two edges it sees.
#include "exploration/room_explorer.h"

#include <gtest/gtest.h>

#include "segment_world.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace exploration {
namespace {

using Eigen::Vector2d;
using laser_features::kPi;
using laser_features::Pose2D;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// The world, the laser, the door detector

using test::Segment;

/// An axis-aligned rectangle.
struct Box {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  bool contains(const Vector2d& p) const { return p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1; }
  double area() const { return (x1 - x0) * (y1 - y0); }
};

struct World : test::SegmentWorld {
  std::vector<Segment> doors;  // edge points of the doors (what a door detector would report)
  Pose2D entry;                // the entry door's centre, into the room
  double entry_width = 1.0;    // m
  Box room;                    // the room to explore (inside its walls)
  std::vector<Box> solids;     // obstacles inside the room (their area is no free space)
};

struct Laser {
  int beams = 360;
  double range = 8.0;  // m, +inf beyond
  double angle_min = -kPi;
  double increment() const { return 2.0 * kPi / beams; }

  std::vector<float> scan(const World& world, const Pose2D& pose) const {
    std::vector<float> ranges(static_cast<std::size_t>(beams));
    for (int i = 0; i < beams; ++i) {
      const double a = pose.theta + angle_min + i * increment();
      const double r = world.raycast(pose.translation(), laser_features::unitVector(a));
      ranges[static_cast<std::size_t>(i)] = r <= range ? static_cast<float>(r) : std::numeric_limits<float>::infinity();
    }
    return ranges;
  }
};

// Walls off the cell lattice (a wall exactly on a cell boundary is a special case, not the rule).
constexpr double kOff = 0.013;

/// Room A (5 x 4 m, x in [0, 5], y in [0, 4]) above a hallway (y in [-2, 0], x in [-6, 12]), entered
/// by a 1 m door x in [1.5, 2.5] of their common wall. Inside: a partition y = 2.6 from the left wall
/// to x = 2.8 (a nook behind it, seen only from above it) and a cupboard. Its right wall has a 0.9 m
/// door (y in [2.5, 3.4]) to room C (x in [5, 9]), which has no other way out. Zero-thickness walls.
World roomWorld() {
  World w;
  const double o = kOff;
  // Hallway.
  w.wall(-6.0, -2.0 + o, 12.0, -2.0 + o);
  w.wall(-6.0 + o, -2.0 + o, -6.0 + o, o);
  w.wall(12.0 + o, -2.0 + o, 12.0 + o, o);
  w.wall(-6.0 + o, o, 1.5, o);  // ... the entry door x in [1.5, 2.5] ...
  w.wall(2.5, o, 12.0 + o, o);
  // Room A.
  w.wall(o, o, o, 4.0 + o);
  w.wall(o, 4.0 + o, 9.0 + o, 4.0 + o);  // room A's and room C's top wall
  w.wall(5.0 + o, o, 5.0 + o, 2.5);      // ... the door to room C y in [2.5, 3.4] ...
  w.wall(5.0 + o, 3.4, 5.0 + o, 4.0 + o);
  w.wall(o, 2.6 + o, 2.8, 2.6 + o);      // the partition
  w.box(3.7, 0.6 + o, 4.3, 1.4 + o);     // the cupboard
  // Room C.
  w.wall(9.0 + o, o, 9.0 + o, 4.0 + o);
  w.doors.push_back({{1.5, o}, {2.5, o}});
  w.doors.push_back({{5.0 + o, 2.5}, {5.0 + o, 3.4}});
  w.entry = {2.0, o, 0.5 * kPi};
  w.entry_width = 1.0;
  w.room = {o, o, 5.0 + o, 4.0 + o};
  w.solids.push_back({3.7, 0.6 + o, 4.3, 1.4 + o});
  return w;
}

/// The entry door of roomWorld(): centre, into the room (+y), 1 m.
const Pose2D kDoor{2.0, kOff, 0.5 * kPi};
constexpr double kDoorWidth = 1.0;

/// The true free area of a room (m^2): inside its walls, outside its obstacles.
double trueFreeArea(const World& w) {
  double a = w.room.area();
  for (const Box& b : w.solids) a -= b.area();
  return a;
}

struct RunOptions {
  bool detect_doors = true;   // the simulated door detector reports the doors it sees
  Vector2d door_error{0.04, -0.03};  // m, added to the reported edges (a detector is off a little)
  int max_steps = 1500;
};

struct RunResult {
  RoomStatus status = RoomStatus::Invalid;
  int steps = 0, goals = 0, goal_calls = 0;
  int goals_behind_entry = 0;     // goals with (g - door) . dir <= 0
  int goals_outside_room = 0;     // goals not in world.room (in the room beyond a door, say)
  int robot_outside_room = 0;     // robot positions outside world.room after having entered
  int steps_through_walls = 0;
  double min_clearance = kInf;
  double travelled = 0.0;
  int entering_goals = 0;
  bool wall_before_entry = false;  // the entry door's cell Occupied while Entering
  Vector2d robot = Vector2d::Zero();
  double time = 0.0;
  std::vector<Vector2d> goals_seen;
};

/// Drives the robot from the doorway until nextGoal() gives none: scan, detect doors, ask for the
/// goal, move 0.3 m along goalPath(), 1 s per step.
RunResult explore(RoomExplorer* rx, const World& world, const RunOptions& opt = RunOptions()) {
  RunResult r;
  const Laser laser;
  Pose2D pose = world.entry;  // in the doorway, facing into the room
  double t = 0.0;
  const Vector2d dir = laser_features::unitVector(world.entry.theta);
  EXPECT_TRUE(rx->start(world.entry, world.entry_width));
  for (; r.steps < opt.max_steps; ++r.steps) {
    std::string why;
    EXPECT_TRUE(rx->addScan(pose, laser.scan(world, pose), laser.angle_min, laser.increment(), &why)) << why;
    if (opt.detect_doors) {
      for (const Segment& d : world.doors) {
        // Seen when its middle is in line of sight within 6 m, less than 70 deg off its normal (a
        // detector needs to see into the gap).
        const Vector2d mid = 0.5 * (d.a + d.b), to = mid - pose.translation();
        const Vector2d along = (d.b - d.a).normalized(), normal(-along.y(), along.x());
        const bool seen = to.norm() < 6.0 && std::abs(to.normalized().dot(normal)) > std::cos(70.0 * kPi / 180.0) &&
                          !world.blocked(pose.translation(), mid);
        if (seen) rx->blockOpening(d.a + opt.door_error, d.b + opt.door_error);
      }
    }
    const auto goal = rx->nextGoal(pose.translation(), t);
    ++r.goal_calls;
    if (rx->status() == RoomStatus::Entering && rx->grid().stateAt(world.entry.translation()) == CellState::Occupied)
      r.wall_before_entry = true;
    if (!goal) break;
    if (rx->status() == RoomStatus::Entering) ++r.entering_goals;
    if ((*goal - world.entry.translation()).dot(dir) <= 0.0) ++r.goals_behind_entry;
    if (rx->status() == RoomStatus::Exploring && !world.room.contains(*goal)) ++r.goals_outside_room;
    if (r.goals_seen.empty() || (r.goals_seen.back() - *goal).norm() > 1e-9) r.goals_seen.push_back(*goal);
    // Move 0.3 m along the path (heading along the motion).
    const Path& path = rx->goalPath();
    EXPECT_GE(path.waypoints.size(), 2u);
    double left = 0.3;
    Vector2d p = pose.translation();
    for (std::size_t i = 1; i < path.waypoints.size() && left > 0.0; ++i) {
      const Vector2d a = i == 1 ? p : path.waypoints[i - 1], b = path.waypoints[i];
      const double len = (b - a).norm();
      if (len < 1e-12) continue;
      const double s = std::min(left, len);
      const Vector2d q = a + (b - a) * (s / len);
      if (world.blocked(p, q)) ++r.steps_through_walls;
      pose.theta = std::atan2(b.y() - a.y(), b.x() - a.x());
      r.travelled += (q - p).norm();
      p = q;
      left -= s;
    }
    pose.x = p.x();
    pose.y = p.y();
    t += 1.0;
    if (rx->entered()) {
      r.min_clearance = std::min(r.min_clearance, world.clearance(p));
      if (!world.room.contains(p)) ++r.robot_outside_room;
    }
  }
  r.status = rx->status();
  r.goals = rx->goalsIssued();
  r.robot = pose.translation();
  r.time = t;
  return r;
}

/// Area (m^2) of the room's cells (centres in world.room, outside its obstacles) at least
/// `clearance` from every wall; and the fraction of those the room grid has Free.
std::pair<double, double> roomCoverage(const RoomExplorer& rx, const World& world, double clearance) {
  const double res = rx.grid().resolution();
  std::size_t truth = 0, found = 0;
  for (double y = std::floor(world.room.y0 / res) * res + 0.5 * res; y < world.room.y1; y += res) {
    for (double x = std::floor(world.room.x0 / res) * res + 0.5 * res; x < world.room.x1; x += res) {
      const Vector2d c(x, y);
      if (!world.room.contains(c) || world.clearance(c) < clearance) continue;
      if (std::any_of(world.solids.begin(), world.solids.end(), [&](const Box& b) { return b.contains(c); })) continue;
      ++truth;
      found += rx.grid().stateAt(c) == CellState::Free ? 1 : 0;
    }
  }
  return {static_cast<double>(truth) * res * res, static_cast<double>(found) / static_cast<double>(truth)};
}

// ---------------------------------------------------------------------------------------------
// The full exploration of a room

/// Room R (8 x 6 m inside 0.1 m walls, centre lines x in [0, 8], y in [0, 6]) above a hallway, entered
/// by a 0.9 m door x in [3.0, 3.9]; a shelf, a table, a pillar, and a partition from the right wall
/// that makes a nook (x > 5.5, y > 4) with a 0.9 m door (x in [6.5, 7.4]) in the top wall to another
/// room above (y in [6, 10]).
World clutteredWorld() {
  World w;
  const double o = kOff, h = 0.05;
  // An axis-aligned wall of 0.1 m along its centre line (offset by kOff), as a closed box; `extend`
  // lengthens it by h at both ends (the corners).
  const auto wall = [&](double x0, double y0, double x1, double y1, bool extend) {
    const double e = extend ? h : 0.0;
    if (y0 == y1) {
      w.box(std::min(x0, x1) + o - e, y0 + o - h, std::max(x0, x1) + o + e, y0 + o + h);
    } else {
      w.box(x0 + o - h, std::min(y0, y1) + o - e, x0 + o + h, std::max(y0, y1) + o + e);
    }
  };
  const auto solid = [&](double x0, double y0, double x1, double y1) {
    w.box(x0 + o, y0 + o, x1 + o, y1 + o);
    w.solids.push_back({x0 + o, y0 + o, x1 + o, y1 + o});
  };
  // Hallway.
  wall(-4.0, -2.0, 12.0, -2.0, true);
  wall(-4.0, -2.0, -4.0, 0.0, true);
  wall(12.0, -2.0, 12.0, 0.0, true);
  w.box(-4.0 + o - h, o - h, 3.0 + o, o + h);  // ... the entry door x in [3.0, 3.9] ...
  w.box(3.9 + o, o - h, 12.0 + o + h, o + h);
  // Room R and the room above.
  wall(0.0, 0.0, 0.0, 10.0, true);
  wall(8.0, 0.0, 8.0, 10.0, true);
  wall(0.0, 10.0, 8.0, 10.0, true);
  w.box(o - h, 6.0 + o - h, 6.5 + o, 6.0 + o + h);  // ... the door x in [6.5, 7.4] ...
  w.box(7.4 + o, 6.0 + o - h, 8.0 + o + h, 6.0 + o + h);
  // Inside.
  solid(1.0, 1.0, 1.4, 4.0);        // shelf
  solid(5.0, 2.0, 6.5, 2.8);        // table
  solid(3.3, 4.6, 3.6, 4.9);        // pillar
  solid(5.5, 4.0 - h, 8.0 - h, 4.0 + h);  // the partition
  w.doors.push_back({{3.0 + o, o}, {3.9 + o, o}});
  w.doors.push_back({{6.5 + o, 6.0 + o}, {7.4 + o, 6.0 + o}});
  w.entry = {3.45 + o, o, 0.5 * kPi};
  w.entry_width = 0.9;
  w.room = {h + o, h + o, 8.0 - h + o, 6.0 - h + o};
  return w;
}

/// Explores world's room from its entry door with the door detector on, and checks: Done within a
/// bounded number of goals, the free area within 10 % of the truth, no goal behind the entry line or
/// outside the room, the second door blocked and reported, the way out.
void exploreAndCheck(const World& world, const char* name, int max_goals, int max_steps) {
  RoomExplorer rx;
  const RunResult r = explore(&rx, world);
  const double area = rx.freeArea(), truth = trueFreeArea(world);
  const auto [interior_area, interior_coverage] = roomCoverage(rx, world, 2.0 * rx.grid().resolution());
  std::printf("[ %s ] %s after %d steps (%.0f s, %.1f m): %d frontier goals, %d entering steps; free area "
              "%.2f m^2 of %.2f (%+.1f %%), interior coverage %.2f %% of %.2f m^2; min clearance %.3f m; grid %zu "
              "bytes; openings %zu\n",
              name, toString(r.status), r.steps, r.time, r.travelled, r.goals, r.entering_goals, area, truth,
              100.0 * (area - truth) / truth, 100.0 * interior_coverage, interior_area, r.min_clearance, rx.bytes(),
              rx.openings().size());
  ::testing::Test::RecordProperty("free_area_m2", std::to_string(area));
  ::testing::Test::RecordProperty("goals", std::to_string(r.goals));

  EXPECT_EQ(r.status, RoomStatus::Done);
  EXPECT_TRUE(rx.entered());
  EXPECT_GE(r.goals, 1);  // a corner behind an obstacle needs at least one frontier goal
  EXPECT_LE(r.goals, max_goals);
  EXPECT_LT(r.steps, max_steps);
  EXPECT_GT(r.entering_goals, 0);
  EXPECT_FALSE(r.wall_before_entry);
  EXPECT_EQ(rx.grid().stateAt(world.entry.translation()), CellState::Occupied);  // closed behind the robot
  // The coverage figure: within 10 % of the truth (the cells a wall's face runs through are
  // Occupied, not Free: a few % less).
  EXPECT_NEAR(area, truth, 0.10 * truth);
  EXPECT_GE(interior_coverage, 0.97);
  // Never out of the room: no goal behind the entry door or beyond the other door, the robot stays
  // inside, through no wall, clear of them.
  EXPECT_EQ(r.goals_behind_entry, 0);
  EXPECT_EQ(r.goals_outside_room, 0);
  EXPECT_EQ(r.robot_outside_room, 0);
  EXPECT_EQ(r.steps_through_walls, 0);
  EXPECT_GE(r.min_clearance, rx.params().planner.robot_radius);
  // The other door is blocked and reported (once), the entry door is not in openings().
  EXPECT_EQ(rx.openings().size(), 1u);
  if (!rx.openings().empty()) {
    const Vector2d centre = 0.5 * (rx.openings()[0].first + rx.openings()[0].second);
    EXPECT_LT((centre - 0.5 * (world.doors[1].a + world.doors[1].b)).norm(), 0.1);
  }
  // The grid: the fixed 24 m square at 5 cm.
  EXPECT_EQ(rx.bytes(), rx.grid().cellCount());
  EXPECT_NEAR(static_cast<double>(rx.bytes()), std::pow(2.0 * 12.0 / 0.05, 2), 2.0 * 2.0 * 12.0 / 0.05 + 4.0);

  // The way out: a path ending at the exit point, inside the room, through no wall; from there the
  // door is straight ahead.
  const auto exit = rx.pathToExit(r.robot);
  ASSERT_TRUE(exit.has_value());
  ASSERT_GE(exit->waypoints.size(), 2u);
  EXPECT_TRUE(exit->waypoints.front().isApprox(r.robot));
  const Vector2d into = laser_features::unitVector(world.entry.theta);
  const Vector2d exit_point = world.entry.translation() + 0.6 * into;
  EXPECT_TRUE(rx.exitPoint().isApprox(exit_point));
  EXPECT_LT((exit->waypoints.back() - exit_point).norm(), 0.1);
  for (std::size_t i = 1; i < exit->waypoints.size(); ++i) {
    EXPECT_FALSE(world.blocked(exit->waypoints[i - 1], exit->waypoints[i])) << "leg " << i;
    EXPECT_TRUE(world.room.contains(exit->waypoints[i])) << "waypoint " << i;
  }
  EXPECT_FALSE(world.blocked(exit->waypoints.back(), world.entry.translation() - 0.5 * into));
  std::printf("[ %s exit ] from (%.2f, %.2f): %zu waypoints, %.2f m, ends %.3f m from the exit point\n", name,
              r.robot.x(), r.robot.y(), exit->waypoints.size(), exit->length,
              (exit->waypoints.back() - exit_point).norm());
}

TEST(RoomExplorer, ExploresASmallRoomAndStaysInside) { exploreAndCheck(roomWorld(), "5 x 4 room", 10, 200); }

TEST(RoomExplorer, ExploresAClutteredRoomWithThickWalls) {
  exploreAndCheck(clutteredWorld(), "8 x 6 cluttered room", 25, 600);
}

// Without the door detector, room C is just more frontier: the explorer goes there. (What makes the
// check above able to fail.)
TEST(RoomExplorer, UnblockedSecondDoorIsExplored) {
  const World world = roomWorld();
  RoomExplorer rx;
  RunOptions opt;
  opt.detect_doors = false;
  const RunResult r = explore(&rx, world, opt);
  std::printf("[ no detector ] %s, %d goals, %d steps with a goal in room C, free area %.2f m^2\n",
              toString(r.status), r.goals, r.goals_outside_room, rx.freeArea());
  EXPECT_GT(r.goals_outside_room, 0);
  EXPECT_GT(rx.freeArea(), trueFreeArea(world) + 8.0);  // room C (16 m^2) counts now
  EXPECT_TRUE(rx.openings().empty());
  EXPECT_EQ(r.goals_behind_entry, 0);  // still never the hallway
}

/// Room A without its inside and room C, with an opening to the hallway nobody reports besides the
/// entry door: the bottom wall is open for x in [3.4, 4.6].
World roomWithUnreportedOpening() {
  World w;
  const double o = kOff;
  w.wall(-6.0, -2.0 + o, 12.0, -2.0 + o);
  w.wall(-6.0 + o, -2.0 + o, -6.0 + o, o);
  w.wall(12.0 + o, -2.0 + o, 12.0 + o, o);
  w.wall(-6.0 + o, o, 1.5, o);
  w.wall(2.5, o, 3.4, o);
  w.wall(4.6, o, 12.0 + o, o);
  w.box(o, o, 5.0 + o, 4.0 + o);
  w.walls.erase(w.walls.end() - 4);  // the box's bottom side: the hallway's wall above is the room's
  w.doors.push_back({{1.5, o}, {2.5, o}});
  w.entry = {2.0, o, 0.5 * kPi};
  w.entry_width = 1.0;
  w.room = {o, o, 5.0 + o, 4.0 + o};
  return w;
}

// The hallway is reachable through the unreported opening: only the side check keeps the goals in
// the room (the hallway's ends are beyond the laser's range: frontiers to spare).
TEST(RoomExplorer, NoGoalBehindTheEntryLineEvenThroughALeak) {
  const World world = roomWithUnreportedOpening();
  RoomExplorer rx;
  const RunResult r = explore(&rx, world);
  // The hallway's frontiers are on the grid, and the hallway is reachable from inside the room
  // (through the opening): without the side check, they would be goals.
  const std::vector<Frontier> frontiers = findFrontiers(rx.grid(), rx.params().frontier.min_frontier_size);
  int behind = 0;
  for (const Frontier& f : frontiers) behind += rx.depth(f.centroid) <= 0.0 ? 1 : 0;
  GridPlanner planner(rx.params().planner);
  planner.setMap(rx.grid());
  ASSERT_TRUE(planner.computeDistances(r.robot));
  const CellIndex hallway = rx.grid().worldToCell({4.0, -1.0});
  std::printf("[ leak ] %s, %d goals, %d behind the entry line; %d hallway frontiers left, hallway %.1f m away; "
              "free area %.2f m^2\n",
              toString(r.status), r.goals, r.goals_behind_entry, behind, planner.distance(hallway.x, hallway.y),
              rx.freeArea());
  EXPECT_EQ(r.status, RoomStatus::Done);
  EXPECT_EQ(r.goals_behind_entry, 0);
  EXPECT_GT(behind, 0);
  EXPECT_TRUE(std::isfinite(planner.distance(hallway.x, hallway.y)));
  EXPECT_NEAR(rx.freeArea(), 20.0, 2.0);  // the hallway does not count
}

// ---------------------------------------------------------------------------------------------
// Entering, holding, timeouts, bounds

TEST(RoomExplorer, EntersBeforeClosingTheDoor) {
  const World world = roomWorld();
  const Laser laser;
  RoomExplorer rx;
  EXPECT_EQ(rx.status(), RoomStatus::Invalid);
  ASSERT_TRUE(rx.start(kDoor, kDoorWidth));
  EXPECT_EQ(rx.status(), RoomStatus::Entering);
  const Vector2d dir = laser_features::unitVector(kDoor.theta);
  const Vector2d entry_goal = kDoor.translation() + (0.7 + 0.3) * dir;
  // In the doorway and 0.5 m in: the entering goal, no wall.
  for (double d : {0.0, 0.3, 0.69}) {
    const Pose2D pose{kDoor.x, kDoor.y + d, kDoor.theta};
    ASSERT_TRUE(rx.addScan(pose, laser.scan(world, pose), laser.angle_min, laser.increment()));
    const auto goal = rx.nextGoal(pose.translation(), d);
    ASSERT_TRUE(goal.has_value());
    EXPECT_TRUE(goal->isApprox(entry_goal)) << goal->transpose();
    EXPECT_EQ(rx.status(), RoomStatus::Entering);
    EXPECT_NE(rx.grid().stateAt(kDoor.translation()), CellState::Occupied);
    EXPECT_EQ(rx.goalsIssued(), 0);
  }
  // 0.75 m in: inside; the door is closed behind the robot and the goal is a frontier's, in the room.
  const Pose2D inside{kDoor.x, kDoor.y + 0.75, kDoor.theta};
  ASSERT_TRUE(rx.addScan(inside, laser.scan(world, inside), laser.angle_min, laser.increment()));
  const auto goal = rx.nextGoal(inside.translation(), 1.0);
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(rx.status(), RoomStatus::Exploring);
  EXPECT_TRUE(rx.entered());
  EXPECT_EQ(rx.goalsIssued(), 1);
  EXPECT_GT(rx.depth(*goal), 0.0);
  const Vector2d lateral(-dir.y(), dir.x());
  for (double s = -0.5; s <= 0.5; s += 0.05)  // the whole door, 2 cells thick
    EXPECT_EQ(rx.grid().stateAt(kDoor.translation() + s * lateral), CellState::Occupied) << s;
  // A scan through the door does not reopen it.
  const Pose2D low{kDoor.x, kDoor.y + 0.75, -0.5 * kPi};
  ASSERT_TRUE(rx.addScan(low, laser.scan(world, low), laser.angle_min, laser.increment()));
  EXPECT_EQ(rx.grid().stateAt(kDoor.translation()), CellState::Occupied);
  // The path starts at the robot and ends at the goal.
  ASSERT_GE(rx.goalPath().waypoints.size(), 2u);
  EXPECT_TRUE(rx.goalPath().waypoints.front().isApprox(inside.translation()));
  EXPECT_TRUE(rx.goalPath().waypoints.back().isApprox(*goal));
}

// The room explorer started at kDoor with one scan from 0.75 m inside it (returned).
Pose2D startedWithAScanFromJustInside(RoomExplorer* rx, const World& world) {
  const Laser laser;
  const Pose2D inside{kDoor.x, kDoor.y + 0.75, kDoor.theta};
  EXPECT_TRUE(rx->start(kDoor, kDoorWidth));
  EXPECT_TRUE(rx->addScan(inside, laser.scan(world, inside), laser.angle_min, laser.increment()));
  return inside;
}

TEST(RoomExplorer, AMissionGoalNotYetSeenRoundFurnitureHasAPath) {
  // From just inside the door the nook behind the partition (y > 2.6, x < 2.8) is unseen: the path
  // to a goal there goes round the partition's free end through the unseen part, not through it.
  const World world = roomWorld();
  RoomExplorer rx;
  const Pose2D inside = startedWithAScanFromJustInside(&rx, world);
  const Vector2d goal(1.0, 3.3);
  ASSERT_EQ(rx.grid().stateAt(goal), CellState::Unknown);
  const auto path = rx.pathTo(inside.translation(), goal);
  ASSERT_TRUE(path.has_value());
  EXPECT_TRUE(path->waypoints.back().isApprox(goal));
  const double clearance = RoomExplorerParams().planner.robot_radius;
  for (std::size_t i = 0; i + 1 < path->waypoints.size(); ++i) {
    const Vector2d a = path->waypoints[i], b = path->waypoints[i + 1];
    for (double t = 0.0; t <= 1.0; t += 0.02) {
      const Vector2d q = a + t * (b - a);
      EXPECT_GT(world.clearance(q), clearance) << q.transpose();
    }
  }
}

// The way out keeps clear of the scan's returns the grid lost (GridPlanner::addObstacles), unless
// they leave no way out: under a table, among four legs 0.6 m apart that the robot drove in
// between, every way out passes within the inflation of two legs; the grid's path is taken then.
TEST(RoomExplorer, AWayOutFromAmongTableLegsIsTheGridsWhenTheScanLeavesNone) {
  const World world = roomWorld();
  RoomExplorer rx;
  const Pose2D inside = startedWithAScanFromJustInside(&rx, world);
  const Vector2d robot = inside.translation() + Vector2d(0.0, 0.8);
  const std::vector<Vector2d> legs = {robot + Vector2d(0.3, 0.3), robot + Vector2d(-0.3, 0.3),
                                      robot + Vector2d(0.3, -0.3), robot + Vector2d(-0.3, -0.3)};
  const auto grid_only = rx.pathToExit(robot);
  ASSERT_TRUE(grid_only.has_value());
  const auto among = rx.pathToExit(robot, legs);
  ASSERT_TRUE(among.has_value()) << "no way out from under the table";
  EXPECT_NEAR(among->length, grid_only->length, 1e-9);
  // Two legs 0.60 m apart across the straight way out, not around the robot: kept clear of by the
  // planner's clearance (the robot's radius and safety margin), round them.
  const Vector2d from = robot + Vector2d(0.0, 0.3);
  const std::vector<Vector2d> across = {robot + Vector2d(0.30, -0.4), robot + Vector2d(-0.30, -0.4)};
  const auto straight = rx.pathToExit(from);
  ASSERT_TRUE(straight.has_value());
  EXPECT_EQ(straight->waypoints.size(), 2u) << "the grid alone: straight out between the legs";
  const auto around = rx.pathToExit(from, across);
  ASSERT_TRUE(around.has_value());
  EXPECT_GT(around->length, straight->length);
  const double clear = GridPlanner(RoomExplorerParams().planner).clearance();
  for (std::size_t i = 1; i < around->waypoints.size(); ++i) {
    const Vector2d a = around->waypoints[i - 1], b = around->waypoints[i];
    for (double t = 0.0; t <= 1.0; t += 0.02)
      for (const Vector2d& l : across) EXPECT_GE((a + t * (b - a) - l).norm(), clear) << (a + t * (b - a)).transpose();
  }
}

TEST(RoomExplorer, GoalIsHeldThenBlacklistedAfterTimeout) {
  const World world = roomWorld();
  const Laser laser;
  RoomExplorer rx;
  ASSERT_TRUE(rx.start(kDoor, kDoorWidth));
  const Pose2D pose{kDoor.x, kDoor.y + 0.8, kDoor.theta};
  ASSERT_TRUE(rx.addScan(pose, laser.scan(world, pose), laser.angle_min, laser.increment()));
  const auto g1 = rx.nextGoal(pose.translation(), 100.0);
  ASSERT_TRUE(g1.has_value());
  // The robot does not move: the goal is held (no dithering) until max_goal_time...
  for (double t = 101.0; t <= 140.0; t += 3.0) {
    const auto g = rx.nextGoal(pose.translation(), t);
    ASSERT_TRUE(g.has_value());
    EXPECT_LT((*g - *g1).norm(), 1e-9) << t;
  }
  EXPECT_EQ(rx.goalsIssued(), 1);
  // ...then given up: another goal, away from it, held in turn.
  const auto g2 = rx.nextGoal(pose.translation(), 140.5);
  std::printf("[ timeout ] g1 (%.2f, %.2f), after 40 s: ", g1->x(), g1->y());
  if (g2) {
    std::printf("g2 (%.2f, %.2f)\n", g2->x(), g2->y());
  } else {
    std::printf("none (%s)\n", toString(rx.status()));
  }
  ASSERT_TRUE(g2.has_value());  // the room has more than one frontier from here
  EXPECT_GT((*g2 - *g1).norm(), rx.params().blacklist_radius);
  EXPECT_EQ(rx.goalsIssued(), 2);
  const auto g3 = rx.nextGoal(pose.translation(), 150.0);
  ASSERT_TRUE(g3.has_value());
  EXPECT_LT((*g3 - *g2).norm(), 1e-9);
  // Reaching it ends it: the robot on the goal gets another one (or Done).
  const Pose2D there{g2->x(), g2->y(), 0.0};
  ASSERT_TRUE(rx.addScan(there, laser.scan(world, there), laser.angle_min, laser.increment()));
  const auto g4 = rx.nextGoal(there.translation(), 151.0);
  if (g4) {
    EXPECT_GT((*g4 - *g2).norm(), rx.params().goal_reach_tolerance);
  }
}

TEST(RoomExplorer, EnteringGivesUpAfterMaxGoalTime) {
  RoomExplorer rx;
  ASSERT_TRUE(rx.start(kDoor, kDoorWidth));
  const Vector2d stuck = kDoor.translation() - Vector2d(0.0, 0.3);  // a person in the door, say
  EXPECT_TRUE(rx.nextGoal(stuck, 0.0).has_value());
  EXPECT_TRUE(rx.nextGoal(stuck, 39.0).has_value());
  EXPECT_FALSE(rx.nextGoal(stuck, 41.0).has_value());
  EXPECT_EQ(rx.status(), RoomStatus::Done);
  EXPECT_FALSE(rx.entered());
}

TEST(RoomExplorer, MaxGoalsEndsTheRoom) {
  const World world = roomWorld();
  RoomExplorerParams p;
  p.max_goals = 1;
  RoomExplorer rx(p);
  const RunResult r = explore(&rx, world);
  RoomExplorer full;
  const RunResult rf = explore(&full, world);
  std::printf("[ max_goals 1 ] %s after %d goals, free area %.2f m^2 (all goals: %d, %.2f m^2)\n", toString(r.status),
              r.goals, rx.freeArea(), rf.goals, full.freeArea());
  EXPECT_EQ(r.status, RoomStatus::Done);
  EXPECT_EQ(r.goals, 1);
  if (rf.goals > 1) {
    EXPECT_LT(rx.freeArea(), full.freeArea());
  }
}

TEST(RoomExplorer, GridIsBoundedByMaxExtent) {
  const World world = roomWorld();
  RoomExplorerParams p;
  p.max_extent = 2.5;  // smaller than the room: what lies beyond is dropped, and Done all the same
  RoomExplorer rx(p);
  const RunResult r = explore(&rx, world);
  const double side = 2.0 * p.max_extent / p.grid.resolution;
  std::printf("[ max_extent 2.5 ] %s, %d goals, grid %d x %d = %zu bytes, free area %.2f m^2\n", toString(r.status),
              r.goals, rx.grid().width(), rx.grid().height(), rx.bytes(), rx.freeArea());
  EXPECT_EQ(r.status, RoomStatus::Done);
  EXPECT_LE(rx.bytes(), static_cast<std::size_t>((side + 1.0) * (side + 1.0)));
  EXPECT_GE(rx.bytes(), static_cast<std::size_t>(side * side));
  for (const Vector2d& g : r.goals_seen) {
    EXPECT_LE(std::abs(g.x() - kDoor.x), p.max_extent);
    EXPECT_LE(std::abs(g.y() - kDoor.y), p.max_extent);
  }
  EXPECT_LT(rx.freeArea(), 2.5 * 5.0 + 0.5);  // the part of the room within the square
}

// ---------------------------------------------------------------------------------------------
// Openings

TEST(RoomExplorer, BlockOpeningIgnoresTheEntryAndDuplicates) {
  RoomExplorer rx;
  EXPECT_FALSE(rx.blockOpening({5.0, 2.5}, {5.0, 3.4}));  // not started
  ASSERT_TRUE(rx.start(kDoor, kDoorWidth));
  EXPECT_FALSE(rx.blockOpening({1.5, kOff}, {2.5, kOff}));        // the entry door
  EXPECT_FALSE(rx.blockOpening({1.6, 0.1}, {2.6, 0.1}));          // the entry door, a bit off
  EXPECT_TRUE(rx.openings().empty());
  EXPECT_NE(rx.grid().stateAt(kDoor.translation()), CellState::Occupied);
  EXPECT_TRUE(rx.blockOpening({5.0, 2.5}, {5.0, 3.4}));
  EXPECT_FALSE(rx.blockOpening({5.1, 2.7}, {5.1, 3.5}));          // the same, seen again
  EXPECT_TRUE(rx.blockOpening({0.0, 1.0}, {0.0, 2.0}));           // another one
  EXPECT_FALSE(rx.blockOpening({kNaN, 1.0}, {0.0, 2.0}));
  EXPECT_FALSE(rx.blockOpening({3.0, 3.0}, {3.0, 3.0}));
  ASSERT_EQ(rx.openings().size(), 2u);
  // The virtual wall: the opening and door_wall_extension beyond each edge, no further.
  for (double y = 2.5 - 0.25; y <= 3.4 + 0.25; y += 0.05)
    EXPECT_EQ(rx.grid().stateAt({5.0, y}), CellState::Occupied) << y;
  EXPECT_NE(rx.grid().stateAt({5.0, 2.5 - 0.4}), CellState::Occupied);
  EXPECT_NE(rx.grid().stateAt({5.0, 3.4 + 0.4}), CellState::Occupied);
  EXPECT_NE(rx.grid().stateAt({5.2, 3.0}), CellState::Occupied);
  // A new room forgets them.
  ASSERT_TRUE(rx.start(kDoor, kDoorWidth));
  EXPECT_TRUE(rx.openings().empty());
  EXPECT_EQ(rx.grid().stateAt({5.0, 3.0}), CellState::Unknown);
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(RoomExplorer, BadParamsAreRefused) {
  EXPECT_TRUE(RoomExplorer::validate(RoomExplorerParams()));
  const auto refused = [](auto mutate) {
    RoomExplorerParams p;
    mutate(p);
    std::string why;
    const bool ok = RoomExplorer::validate(p, &why);
    EXPECT_FALSE(why.empty());
    EXPECT_THROW(RoomExplorer{p}, std::invalid_argument);
    return !ok;
  };
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.max_extent = 0.0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.max_extent = kNaN; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.max_extent = 1e4; }));  // more cells than grid.max_cells
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.entry_depth = 0.2; }));  // less than the robot's radius
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.entry_depth = kInf; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.door_wall_extension = -0.1; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.goal_reach_tolerance = 0.0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.max_goal_time = kNaN; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.blacklist_radius = -1.0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.max_goals = 0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.exit_depth = 0.0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.grid.free_threshold = 0.8; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.grid.resolution = 0.0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.planner.robot_radius = -1.0; }));
  EXPECT_TRUE(refused([](RoomExplorerParams& p) { p.frontier.gain_scale = kNaN; }));
}

TEST(RoomExplorer, BadInputIsRefused) {
  const World world = roomWorld();
  const Laser laser;
  RoomExplorer rx;
  const Pose2D pose{kDoor.x, kDoor.y + 0.8, kDoor.theta};
  const std::vector<float> ranges = laser.scan(world, pose);
  std::string why;
  EXPECT_FALSE(rx.addScan(pose, ranges, laser.angle_min, laser.increment(), &why));  // not started
  EXPECT_FALSE(why.empty());
  EXPECT_FALSE(rx.nextGoal(pose.translation(), 0.0).has_value());
  EXPECT_EQ(rx.status(), RoomStatus::Invalid);
  EXPECT_FALSE(rx.pathToExit(pose.translation()).has_value());
  EXPECT_EQ(rx.freeArea(), 0.0);

  // A bad door: Invalid.
  EXPECT_FALSE(rx.start({kNaN, 0.0, 0.0}, 1.0));
  EXPECT_EQ(rx.status(), RoomStatus::Invalid);
  EXPECT_FALSE(rx.start(kDoor, 0.0));
  EXPECT_FALSE(rx.start(kDoor, kInf));
  EXPECT_FALSE(rx.start({0.0, 0.0, kInf}, 1.0));

  ASSERT_TRUE(rx.start(kDoor, kDoorWidth));
  for (const Pose2D& bad : {Pose2D{kNaN, 1.0, 0.0}, Pose2D{2.0, kInf, 0.0}, Pose2D{2.0, 1.0, kNaN}}) {
    why.clear();
    EXPECT_FALSE(rx.addScan(bad, ranges, laser.angle_min, laser.increment(), &why));
    EXPECT_FALSE(why.empty());
  }
  EXPECT_FALSE(rx.addScan(pose, ranges, kNaN, laser.increment()));
  EXPECT_FALSE(rx.addScan(pose, ranges, laser.angle_min, kInf));
  EXPECT_EQ(rx.grid().scansInserted(), 0u);
  EXPECT_EQ(rx.grid().count(CellState::Unknown), rx.grid().cellCount());
  // A good scan after the bad ones.
  EXPECT_TRUE(rx.addScan(pose, ranges, laser.angle_min, laser.increment()));
  EXPECT_EQ(rx.grid().scansInserted(), 1u);
  // Non-finite robot or time: no goal, the status stays.
  EXPECT_FALSE(rx.nextGoal({kNaN, 1.0}, 0.0).has_value());
  EXPECT_FALSE(rx.nextGoal(pose.translation(), kNaN).has_value());
  EXPECT_EQ(rx.status(), RoomStatus::Entering);
  EXPECT_FALSE(rx.pathToExit({kInf, 0.0}).has_value());
  // Off the grid (30 m away): no goal, the status stays.
  EXPECT_TRUE(rx.nextGoal(pose.translation(), 0.0).has_value());  // inside now: Exploring
  EXPECT_EQ(rx.status(), RoomStatus::Exploring);
  EXPECT_FALSE(rx.nextGoal({30.0, 30.0}, 1.0).has_value());
  EXPECT_EQ(rx.status(), RoomStatus::Exploring);
}

}  // namespace
}  // namespace exploration
