// The frontier-exploration baseline (OccupancyGrid, GridPlanner, FrontierExplorer) on synthetic
// worlds: walls as segments, a 360-beam laser ray-cast against them (+inf beyond its range), and a
// point robot teleported along the planned paths.
#include "exploration/frontier_explorer.h"
#include "exploration/frontier_goal.h"
#include "exploration/occupancy_grid.h"

#include <gtest/gtest.h>

#include "segment_world.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
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
// The world and the laser

using test::Segment;

using World = test::SegmentWorld;

struct Laser {
  int beams = 360;
  double range = 8.0;  // m, +inf beyond
  double angle_min = -kPi;
  double increment() const { return 2.0 * kPi / beams; }

  std::vector<double> scan(const World& world, const Pose2D& pose) const {
    std::vector<double> ranges(static_cast<std::size_t>(beams));
    for (int i = 0; i < beams; ++i) {
      const double a = pose.theta + angle_min + i * increment();
      const double r = world.raycast(pose.translation(), laser_features::unitVector(a));
      ranges[static_cast<std::size_t>(i)] = r <= range ? r : kInf;
    }
    return ranges;
  }
};

bool insert(OccupancyGrid* grid, const World& world, const Laser& laser, const Pose2D& pose) {
  std::string why;
  const bool ok = grid->insertScan(pose, laser.scan(world, pose), laser.angle_min, laser.increment(), &why);
  EXPECT_TRUE(ok) << why;
  return ok;
}

/// Calls f(ix, iy) for every cell of the grid.
template <typename F>
void forEachCell(const OccupancyGrid& grid, F f) {
  for (int iy = grid.minY(); iy < grid.minY() + grid.height(); ++iy)
    for (int ix = grid.minX(); ix < grid.minX() + grid.width(); ++ix) f(ix, iy);
}

bool insideBox(const Vector2d& p, double x0, double y0, double x1, double y1) {
  return p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1;
}

// Walls off the cell lattice (a wall exactly on a cell boundary is a special case, not the rule).
constexpr double kOff = 0.013;

// ---------------------------------------------------------------------------------------------
// (a) One scan in a closed rectangular room

TEST(OccupancyGrid, OneScanInClosedRoom) {
  const double x0 = kOff, y0 = kOff, x1 = 6.0 + kOff, y1 = 4.0 + kOff;
  World world;
  world.box(x0, y0, x1, y1);
  OccupancyGrid grid;
  const double res = grid.resolution();
  ASSERT_TRUE(insert(&grid, world, Laser(), {2.2, 1.7, 0.3}));

  std::size_t occupied = 0, occupied_far = 0, interior = 0, interior_not_free = 0, outside_observed = 0,
              free_outside = 0;
  forEachCell(grid, [&](int ix, int iy) {
    const Vector2d c = grid.cellCenter(ix, iy);
    const double d = world.clearance(c);
    const CellState s = grid.cellState(ix, iy);
    const bool inside = insideBox(c, x0, y0, x1, y1);
    if (s == CellState::Occupied) {
      ++occupied;
      if (d > res) ++occupied_far;  // an occupied cell more than one cell from a wall
    }
    if (inside && d >= 2.0 * res) {
      ++interior;
      if (s != CellState::Free) ++interior_not_free;
    }
    if (!inside && d > res && grid.observed(ix, iy)) ++outside_observed;
    if (!inside && s == CellState::Free) ++free_outside;
  });
  // The walls: every point along them has an occupied cell within one cell.
  std::size_t wall_samples = 0, wall_covered = 0;
  for (const Segment& s : world.walls) {
    const double len = (s.b - s.a).norm();
    for (double t = 0.0; t <= len; t += 0.5 * res) {
      const CellIndex c = grid.worldToCell(s.a + (s.b - s.a) * (t / len));
      bool near = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) near = near || grid.cellState(c.x + dx, c.y + dy) == CellState::Occupied;
      ++wall_samples;
      wall_covered += near ? 1 : 0;
    }
  }
  std::printf("[ room ] %zu occupied (%zu farther than a cell from a wall), walls covered %zu/%zu, interior "
              "not free %zu/%zu, observed outside %zu\n",
              occupied, occupied_far, wall_covered, wall_samples, interior_not_free, interior, outside_observed);
  EXPECT_EQ(occupied_far, 0u);
  EXPECT_GE(wall_covered, static_cast<std::size_t>(0.95 * static_cast<double>(wall_samples)));
  EXPECT_GT(interior, 8000u);  // the room is 24 m^2: ~9000 cells at 5 cm
  EXPECT_EQ(interior_not_free, 0u);
  EXPECT_EQ(outside_observed, 0u);
  EXPECT_EQ(free_outside, 0u);
  EXPECT_EQ(grid.scansInserted(), 1u);
}

// Without the wedges, far cells between beams stay unknown (holes that would be frontiers): what
// fill_gaps is for. With them, at most a strip along a wall seen so grazing that its returns are
// more than max_surface_gap apart may stay unknown (here: none).
TEST(OccupancyGrid, GapFillingClosesHolesBetweenFarBeams) {
  World world;
  world.box(kOff, kOff, 12.0 + kOff, 8.0 + kOff);
  const Laser laser{360, 15.0};
  std::size_t interior = 0, not_free[2] = {0, 0};
  double farthest_hole = 0.0;  // m, from the walls, with the wedges
  for (int fill = 0; fill < 2; ++fill) {
    OccupancyGridParams p;
    p.fill_gaps = fill == 1;
    OccupancyGrid grid(p);
    ASSERT_TRUE(insert(&grid, world, laser, {1.0, 1.0, 0.0}));
    interior = 0;
    forEachCell(grid, [&](int ix, int iy) {
      const Vector2d c = grid.cellCenter(ix, iy);
      const double d = world.clearance(c);
      if (!insideBox(c, kOff, kOff, 12.0 + kOff, 8.0 + kOff) || d < 2.0 * grid.resolution()) return;
      ++interior;
      if (grid.cellState(ix, iy) == CellState::Free) return;
      ++not_free[fill];
      if (fill == 1) farthest_hole = std::max(farthest_hole, d);
    });
  }
  std::printf("[ gaps ] interior cells not free: %zu without the wedges, %zu with (of %zu; farthest %.3f m "
              "from a wall)\n",
              not_free[0], not_free[1], interior, farthest_hole);
  EXPECT_GT(not_free[0], interior / 5);
  EXPECT_LT(not_free[1], interior / 1000);
  EXPECT_LE(farthest_hole, 4.0 * 0.05);
}

// The binary Bayes filter: an obstacle seen many times saturates; when it is gone, the cell turns
// free after about (l_max - logit(free_threshold)) / |l_free| misses.
TEST(OccupancyGrid, ObstacleRemovedTurnsFreeAfterEnoughMisses) {
  World with, without;
  with.box(kOff, kOff, 6.0 + kOff, 4.0 + kOff);
  without = with;
  with.wall(3.0 + kOff, 1.0, 3.0 + kOff, 3.0);  // a panel in front of the sensor
  OccupancyGrid grid;
  const Laser laser;
  const Pose2D pose{1.5, 2.0, 0.0};
  for (int i = 0; i < 20; ++i) insert(&grid, with, laser, pose);
  const CellIndex c = grid.worldToCell({3.0 + kOff, 2.0});
  ASSERT_EQ(grid.cellState(c.x, c.y), CellState::Occupied);
  EXPECT_NEAR(grid.probability(c.x, c.y), 1.0 / (1.0 + std::exp(-grid.params().l_max)), 0.01);
  int misses = 0;
  while (grid.cellState(c.x, c.y) != CellState::Free && misses < 100) {
    insert(&grid, without, laser, pose);
    ++misses;
  }
  const OccupancyGridParams& p = grid.params();
  const double expected =
      std::ceil((p.l_max - std::log(p.free_threshold / (1.0 - p.free_threshold))) / -p.l_free);
  std::printf("[ bayes ] free after %d misses (expected about %.0f)\n", misses, expected);
  EXPECT_NEAR(misses, expected, 1.0);
}

// ---------------------------------------------------------------------------------------------
// (b) Frontier detection in a room with a door

World roomWithDoor(bool door_open) {
  World w;
  const double x0 = kOff, y0 = kOff, x1 = 5.0 + kOff, y1 = 4.0 + kOff;
  w.wall(x0, y0, x1, y0);
  w.wall(x1, y1, x0, y1);
  w.wall(x0, y1, x0, y0);
  if (door_open) {  // the right wall with a 0.9 m door, y in [1.6, 2.5]; nothing beyond
    w.wall(x1, y0, x1, 1.6);
    w.wall(x1, 2.5, x1, y1);
  } else {
    w.wall(x1, y0, x1, y1);
  }
  return w;
}

TEST(FrontierExplorer, RoomWithDoorHasExactlyTheDoorsFrontier) {
  const World world = roomWithDoor(true);
  const Vector2d robot(2.0, 2.05);
  OccupancyGrid grid;
  ASSERT_TRUE(insert(&grid, world, Laser(), {robot.x(), robot.y(), 0.0}));

  FrontierExplorer explorer;
  const std::vector<Frontier> frontiers = findFrontiers(grid, explorer.params().min_frontier_size);
  ASSERT_EQ(frontiers.size(), 1u);
  // Every cell of it is at or beyond the door's plane (within two cells: the jambs' cells), inside
  // the cone the door lets the laser see.
  const double res = grid.resolution(), door_x = 5.0 + kOff;
  const double lo = std::atan2(1.6 - robot.y(), door_x - robot.x());
  const double hi = std::atan2(2.5 - robot.y(), door_x - robot.x());
  std::size_t outside_cone = 0;
  for (const CellIndex& c : frontiers[0].cells) {
    const Vector2d p = grid.cellCenter(c);
    const double a = std::atan2(p.y() - robot.y(), p.x() - robot.x());
    const double slack = 1.5 * res / (p - robot).norm();
    if (p.x() < door_x - 2.0 * res || a < lo - slack || a > hi + slack) ++outside_cone;
  }
  EXPECT_EQ(outside_cone, 0u);
  // It spans the door: some cell within 3 cells of each jamb's end (the unknown cells touching the
  // jambs' occupied cells are the jambs' unseen sides, not frontier).
  bool at_upper = false, at_lower = false;
  for (const CellIndex& c : frontiers[0].cells) {
    at_upper = at_upper || (grid.cellCenter(c) - Vector2d(door_x, 2.5)).norm() < 3.5 * res;
    at_lower = at_lower || (grid.cellCenter(c) - Vector2d(door_x, 1.6)).norm() < 3.5 * res;
  }
  EXPECT_TRUE(at_upper);
  EXPECT_TRUE(at_lower);

  // The goal is beyond the door, and the path goes through the door.
  const auto goal = explorer.nextGoal(grid, robot);
  ASSERT_TRUE(goal.has_value()) << toString(explorer.status());
  EXPECT_EQ(explorer.status(), ExplorerStatus::Goal);
  EXPECT_GT(goal->x(), door_x);
  const Path& path = explorer.goalPath();
  ASSERT_GE(path.waypoints.size(), 2u);
  EXPECT_TRUE(path.waypoints.front().isApprox(robot));
  EXPECT_TRUE(path.waypoints.back().isApprox(*goal));
  bool through_door = false;
  for (std::size_t i = 1; i < path.waypoints.size(); ++i) {
    const Vector2d a = path.waypoints[i - 1], b = path.waypoints[i];
    EXPECT_FALSE(world.blocked(a, b)) << "leg " << i;
    if ((a.x() - door_x) * (b.x() - door_x) <= 0.0 && a.x() != b.x()) {
      const double y = a.y() + (b.y() - a.y()) * (door_x - a.x()) / (b.x() - a.x());
      through_door = through_door || (y > 1.6 + 0.25 && y < 2.5 - 0.25);  // the robot's body fits
    }
  }
  EXPECT_TRUE(through_door);
  EXPECT_GT(path.length, (*goal - robot).norm() - 1e-9);

  // The same room closed: no frontier, exploration complete.
  OccupancyGrid closed;
  ASSERT_TRUE(insert(&closed, roomWithDoor(false), Laser(), {robot.x(), robot.y(), 0.0}));
  EXPECT_TRUE(findFrontiers(closed, explorer.params().min_frontier_size).empty());
  EXPECT_FALSE(explorer.nextGoal(closed, robot).has_value());
  EXPECT_EQ(explorer.status(), ExplorerStatus::Complete);
}

// ---------------------------------------------------------------------------------------------
// (c) A full exploration of a small floor

/// Two rooms above a hallway, with a door each, a closed box in room A; a closed building. Walls
/// of zero thickness (one row of cells between two spaces: the harder case for the map) or
/// `thickness` thick (as the project's worlds: 0.1 m), centred on the same lines; the doors are
/// 0.9 m between the walls' ends.
World smallFloor(double thickness = 0.0) {
  World w;
  const double h = 0.5 * thickness;
  // An axis-aligned wall along its centre line, extended by h at the ends flagged (corners).
  const auto wall = [&](double x0, double y0, double x1, double y1, bool extend) {
    if (thickness <= 0.0) return w.wall(x0, y0, x1, y1);
    const double e = extend ? h : 0.0;
    if (y0 == y1) {
      w.box(std::min(x0, x1) - e, y0 - h, std::max(x0, x1) + e, y0 + h);
    } else {
      w.box(x0 - h, std::min(y0, y1) - e, x0 + h, std::max(y0, y1) + e);
    }
  };
  const double X = 10.0 + kOff, Y = 6.0 + kOff, H = 1.6 + kOff, M = 5.0 + kOff;
  wall(kOff, kOff, X, kOff, true);
  wall(X, kOff, X, Y, true);
  wall(X, Y, kOff, Y, true);
  wall(kOff, Y, kOff, kOff, true);
  // The hallway's upper wall with the doors x in [1.5, 2.4] (room A) and [7.0, 7.9] (room B).
  wall(kOff, H, 1.5, H, false);
  wall(2.4, H, 7.0, H, false);
  wall(7.9, H, X, H, false);
  wall(M, H, M, Y, false);  // between the rooms
  w.box(2.5, 3.6, 3.2, 4.3);  // a cupboard in room A
  return w;
}

void exploreFloor(const World& world, const char* name) {
  const Laser laser;
  OccupancyGrid grid;
  FrontierExplorer explorer;
  const double res = grid.resolution(), robot_radius = explorer.planner().params().robot_radius;
  Pose2D pose{1.0, 0.8, 0.0};
  ASSERT_TRUE(insert(&grid, world, laser, pose));

  double travelled = 0.0, min_clearance = kInf;
  int goals = 0, blacklisted = 0, scans = 1;
  std::optional<Vector2d> previous_goal;
  const int kMaxGoals = 100;
  while (goals < kMaxGoals) {
    const auto goal = explorer.nextGoal(grid, pose.translation());
    if (!goal) break;
    ++goals;
    // The caller's blacklist: a goal that comes back once the robot stood on it is unobservable.
    if (previous_goal && (*goal - *previous_goal).norm() < 2.0 * res &&
        (pose.translation() - *goal).norm() < 2.0 * res) {
      explorer.blacklist(*goal, 0.5);
      ++blacklisted;
      continue;
    }
    previous_goal = goal;
    const Path path = explorer.goalPath();
    ASSERT_GE(path.waypoints.size(), 2u);
    // Teleport along the path, scanning every 0.25 m (heading along the leg).
    double since_scan = 0.0;
    for (std::size_t i = 1; i < path.waypoints.size(); ++i) {
      const Vector2d a = path.waypoints[i - 1], b = path.waypoints[i];
      const double len = (b - a).norm();
      ASSERT_FALSE(world.blocked(a, b)) << "goal " << goals << " leg " << i;
      if (len > 1e-9) pose.theta = std::atan2(b.y() - a.y(), b.x() - a.x());
      for (double t = 0.0; t < len;) {
        const double step = std::min(0.05, len - t);
        t += step;
        since_scan += step;
        const Vector2d p = a + (b - a) * (t / len);
        pose.x = p.x();
        pose.y = p.y();
        min_clearance = std::min(min_clearance, world.clearance(p));
        if (since_scan >= 0.25) {
          insert(&grid, world, laser, pose);
          ++scans;
          since_scan = 0.0;
        }
      }
    }
    insert(&grid, world, laser, pose);
    ++scans;
    travelled += path.length;
  }
  EXPECT_EQ(explorer.status(), ExplorerStatus::Complete);
  EXPECT_LT(goals, kMaxGoals);

  // Ground truth: the free space of the building the start is connected to, 2 cells from walls
  // (the box's inside is not reachable); a flood fill over the true geometry.
  const int nx = static_cast<int>(std::ceil(10.1 / res)), ny = static_cast<int>(std::ceil(6.1 / res));
  std::vector<int> label(static_cast<std::size_t>(nx * ny), 0);  // 0 unvisited, 1 free reachable, 2 other
  const auto centre = [&](int x, int y) { return Vector2d((x + 0.5) * res, (y + 0.5) * res); };
  std::vector<int> stack{static_cast<int>(0.8 / res) * nx + static_cast<int>(1.0 / res)};
  label[static_cast<std::size_t>(stack[0])] = 1;
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    const int x = i % nx, y = i / nx;
    for (int k = 0; k < 4; ++k) {
      const int qx = x + (k == 0) - (k == 1), qy = y + (k == 2) - (k == 3);
      if (qx < 0 || qy < 0 || qx >= nx || qy >= ny) continue;
      const int q = qy * nx + qx;
      if (label[q] != 0) continue;
      const bool open = world.clearance(centre(qx, qy)) > 0.5 * res && !world.blocked(centre(x, y), centre(qx, qy));
      label[q] = open ? 1 : 2;
      if (open) stack.push_back(q);
    }
  }
  std::size_t truth = 0, found = 0, free_outside = 0;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const Vector2d c = centre(x, y);
      const CellState s = grid.stateAt(c);
      if (label[static_cast<std::size_t>(y * nx + x)] == 1 && world.clearance(c) >= 2.0 * res) {
        ++truth;
        found += s == CellState::Free ? 1 : 0;
      }
      if (s == CellState::Free && insideBox(c, 2.5, 3.6, 3.2, 4.3) && world.clearance(c) > res) ++free_outside;
    }
  }
  const double coverage = static_cast<double>(found) / static_cast<double>(truth);
  std::printf("[ explore %s ] %d goals (%d blacklisted), %d scans, path %.1f m, coverage %.2f%% of %zu cells, "
              "min clearance %.3f m, map %zu bytes (%d x %d)\n",
              name, goals, blacklisted, scans, travelled, 100.0 * coverage, truth, min_clearance, grid.bytes(),
              grid.width(), grid.height());
  ::testing::Test::RecordProperty("path_length_m", std::to_string(travelled));
  ::testing::Test::RecordProperty("coverage", std::to_string(coverage));
  EXPECT_GT(truth, 14000u);  // ~45 m^2 of floor
  EXPECT_GE(coverage, 0.95);
  EXPECT_EQ(free_outside, 0u);  // nothing inside the closed box
  EXPECT_GE(min_clearance, robot_radius);
  EXPECT_GT(travelled, 10.0);  // both rooms are entered: the doors are 5.5 m apart
  EXPECT_LT(travelled, 200.0);
}

TEST(FrontierExplorer, ExploresSmallFloorCompletelyThinWalls) { exploreFloor(smallFloor(0.0), "thin walls"); }

TEST(FrontierExplorer, ExploresSmallFloorCompletelyThickWalls) { exploreFloor(smallFloor(0.1), "0.1 m walls"); }

// ---------------------------------------------------------------------------------------------
// (d) The planner

TEST(GridPlanner, PathsKeepClearOfInflatedObstacles) {
  World world;
  world.box(kOff, kOff, 8.0 + kOff, 6.0 + kOff);
  world.box(2.0, 2.0, 2.6, 4.5);         // a shelf
  world.box(5.0, 1.0, 5.4, 1.4);         // a pillar
  world.wall(4.0, 6.0 + kOff, 4.0, 3.15);  // a partition from the top wall...
  world.wall(4.0, 2.6, 4.0, kOff);         // ...with a 0.55 m gap at y in [2.6, 3.15]: too narrow for
                                           // 2 x 0.35 m (0.7 m would be the limit, left to the cells)
  OccupancyGrid grid;
  const Laser laser;
  for (const Pose2D& p : {Pose2D{1.0, 1.0, 0.0}, Pose2D{1.0, 5.0, 0.0}, Pose2D{3.2, 3.0, 0.0},
                          Pose2D{6.0, 3.0, 0.0}, Pose2D{6.5, 0.6, 0.0}, Pose2D{6.5, 5.4, 0.0}})
    insert(&grid, world, laser, p);

  GridPlanner planner;
  planner.setMap(grid);
  const double res = grid.resolution(), inflation = planner.inflationRadius();
  // The test's own check against the grid: no sample of the path is nearer than the controller's
  // clearance to an Occupied cell's centre. The inflation adds half a cell's diagonal to it
  // (GridPlanner::inflationRadius): a line-of-sight segment passes that much nearer to an obstacle
  // than the centres of the cells it touches, and the controller, which needs the clearance along
  // its heading, turned to and fro before a passage planned by less (a robot among a table's legs,
  // for 360 s).
  EXPECT_NEAR(inflation, planner.clearance() + 0.5 * std::sqrt(2.0) * res, 1e-9);
  const int reach = static_cast<int>(std::ceil(inflation / res)) + 1;
  const auto tooClose = [&](const Vector2d& p) {
    const CellIndex c = grid.worldToCell(p);
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx)
        if (grid.cellState(c.x + dx, c.y + dy) == CellState::Occupied &&
            (grid.cellCenter(c.x + dx, c.y + dy) - p).norm() < planner.clearance() - 1e-9)
          return true;
    return false;
  };

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.1, 7.9), uy(0.1, 5.9);
  const auto randomTraversable = [&]() {
    while (true) {
      const Vector2d p(ux(rng), uy(rng));
      const CellIndex c = grid.worldToCell(p);
      if (planner.traversable(c.x, c.y)) return p;
    }
  };
  int planned = 0, refused = 0, violations = 0, same_side_refused = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Vector2d s = randomTraversable(), g = randomTraversable();
    const auto path = planner.plan(s, g);
    const bool same_side = (s.x() < 4.0) == (g.x() < 4.0);  // the gap is too narrow: sides apart
    if (!path) {
      ++refused;
      same_side_refused += same_side ? 1 : 0;
      continue;
    }
    ++planned;
    EXPECT_TRUE(same_side) << "a path through the 0.55 m gap";
    EXPECT_TRUE(path->waypoints.front().isApprox(s));
    EXPECT_TRUE(path->waypoints.back().isApprox(g));
    EXPECT_GE(path->length, (g - s).norm() - 1e-9);
    for (std::size_t i = 1; i < path->waypoints.size(); ++i) {
      const Vector2d a = path->waypoints[i - 1], b = path->waypoints[i];
      EXPECT_LE((b - a).norm(), planner.params().max_segment_length + res);
      const double len = (b - a).norm();
      for (double t = 0.0; t <= len; t += 0.25 * res) {
        const Vector2d p = len > 0.0 ? Vector2d(a + (b - a) * (t / len)) : a;
        if (tooClose(p) || world.clearance(p) < planner.params().robot_radius) ++violations;
      }
    }
  }
  std::printf("[ planner ] %d planned, %d refused (%d on the same side)\n", planned, refused, same_side_refused);
  EXPECT_EQ(violations, 0);
  EXPECT_GT(planned, 20);
  EXPECT_GT(refused, 5);
  EXPECT_EQ(same_side_refused, 0);
}

// A 6 x 4 m room mapped from (1, 2) and (5, 2): free all the way between them (the table legs'
// tests: the legs are given to the planner, the grid has lost them).
OccupancyGrid roomMappedFromTwoPoses() {
  World world;
  world.box(kOff, kOff, 6.0 + kOff, 4.0 + kOff);
  OccupancyGrid grid;
  const Laser laser;
  for (const Pose2D& p : {Pose2D{1.0, 2.0, 0.0}, Pose2D{5.0, 2.0, 0.0}}) insert(&grid, world, laser, p);
  return grid;
}

// A table's legs (2-5 cm) are lost by a log-odds grid (the beams passing beside a leg through its
// cell mark it free) but seen in every scan, and the motion controller keeps its clearance from
// them: the latest scan's returns block the plan's snapshot, so that no path runs between two legs
// the robot will not drive between.
TEST(GridPlanner, ObstaclesOfTheScanTheGridLostAreKeptClearOf) {
  const OccupancyGrid grid = roomMappedFromTwoPoses();
  // Two legs 0.65 m apart across the straight way from (1, 2) to (5, 2), not in the grid.
  const std::vector<Vector2d> legs = {{3.0, 1.675}, {3.0, 2.325}};
  GridPlanner planner;
  planner.setMap(grid);
  const auto nearest = [&](const Path& path) {
    double d = 1e9;
    for (std::size_t i = 1; i < path.waypoints.size(); ++i) {
      const Vector2d a = path.waypoints[i - 1], b = path.waypoints[i];
      for (double t = 0.0; t <= 1.0; t += 0.01)
        for (const Vector2d& l : legs) d = std::min(d, (a + t * (b - a) - l).norm());
    }
    return d;
  };
  const auto blind = planner.plan({1.0, 2.0}, {5.0, 2.0});
  ASSERT_TRUE(blind);
  EXPECT_LT(nearest(*blind), planner.inflationRadius()) << "the grid alone leads between the legs";
  planner.addObstacles(legs);
  const auto seen = planner.plan({1.0, 2.0}, {5.0, 2.0});
  ASSERT_TRUE(seen);
  EXPECT_GE(nearest(*seen), planner.clearance() - 1e-9);
  EXPECT_FALSE(planner.clearLine({1.0, 2.0}, {5.0, 2.0}));
}

// A seen point covers every cell whose centre lies within the inflation radius (0.385 m) of
// the point itself: two legs 0.750 m apart (less than twice the radius) whose cells' centres are
// 0.80 m apart leave no way between them, as the controller, which measures its clearance from the
// points, leaves none.
TEST(GridPlanner, ASeenPointInflatesFromWhereItIsNotFromItsCell) {
  const OccupancyGrid grid = roomMappedFromTwoPoses();
  const std::vector<Vector2d> legs = {{3.0, 1.6499}, {3.0, 2.4001}};  // each at its cell's edge facing the other
  GridPlanner planner;
  planner.setMap(grid);
  ASSERT_LT((legs[1] - legs[0]).norm(), 2.0 * planner.inflationRadius());
  // The cell centred at (2.975, 2.025): 0.376 m from each leg, 0.403 m from each leg's cell centre.
  const int ix = 59, iy = 40;
  ASSERT_TRUE(planner.traversable(ix, iy));
  planner.addObstacles(legs);
  EXPECT_FALSE(planner.traversable(ix, iy)) << "inflated from the legs' cells, not from the legs";
  const auto path = planner.plan({1.0, 2.025}, {5.0, 2.025});
  ASSERT_TRUE(path);
  for (std::size_t i = 1; i < path->waypoints.size(); ++i) {
    const Vector2d a = path->waypoints[i - 1], b = path->waypoints[i];
    if ((a.x() - 3.0) * (b.x() - 3.0) >= 0.0) continue;  // does not cross x = 3
    const double y = a.y() + (b.y() - a.y()) * (3.0 - a.x()) / (b.x() - a.x());
    EXPECT_FALSE(y > legs[0].y() && y < legs[1].y()) << "between the legs at y = " << y;
  }
}

// The motion controller lets a robot within its clearance of a scan point move only away from it
// (its free distance towards the point is zero): a start within a leg's inflation leaves it that
// way, never nearer to that leg nor into another leg's inflation, and then keeps clear of both.
TEST(GridPlanner, AStartNearASeenPointLeavesItOnlyMovingAway) {
  const OccupancyGrid grid = roomMappedFromTwoPoses();
  const std::vector<Vector2d> legs = {{3.0, 1.675}, {3.0, 2.325}};
  GridPlanner planner;
  planner.setMap(grid);
  planner.addObstacles(legs);
  const double r = planner.inflationRadius();
  const Vector2d start(2.85, 1.85);  // 0.23 m from the first leg, 0.50 m from the second
  ASSERT_LT((start - legs[0]).norm(), r);
  ASSERT_GT((start - legs[1]).norm(), r);
  const auto path = planner.plan(start, {5.0, 2.0});
  ASSERT_TRUE(path);
  std::vector<double> last = {(start - legs[0]).norm(), (start - legs[1]).norm()};
  bool left = false;  // out of every leg's inflation
  for (std::size_t i = 1; i < path->waypoints.size(); ++i) {
    const Vector2d a = path->waypoints[i - 1], b = path->waypoints[i];
    for (double t = 0.0; t <= 1.0; t += 0.01) {
      const Vector2d q = a + t * (b - a);
      for (std::size_t k = 0; k < legs.size(); ++k) {
        const double d = (q - legs[k]).norm();
        if (left) {
          EXPECT_GE(d, planner.clearance()) << "back near leg " << k << " at " << q.transpose();
        } else if (d < r) {
          EXPECT_GE(d, last[k] - 1e-9) << "nearer to leg " << k << " at " << q.transpose();
        }
        last[k] = d;
      }
      left = left || (std::min(last[0], last[1]) >= r);
    }
  }
  EXPECT_TRUE(left);
  // Without the points, the straight way between the legs.
  planner.setMap(grid);
  const auto blind = planner.plan(start, {5.0, 2.0});
  ASSERT_TRUE(blind);
  EXPECT_LT(blind->length, path->length);
}

TEST(GridPlanner, NoPathToAnEnclosedGoal) {
  OccupancyGrid grid(OccupancyGridParams(), GridBounds{0.0, 0.0, 6.0, 6.0});
  const double res = grid.resolution();
  forEachCell(grid, [&](int ix, int iy) { grid.setCell(ix, iy, CellState::Free); });
  const Vector2d start(0.5, 0.5), goal(3.0, 3.0);
  GridPlanner planner;
  planner.setMap(grid);
  const auto open_path = planner.plan(start, goal);
  ASSERT_TRUE(open_path.has_value());
  EXPECT_NEAR(open_path->length, (goal - start).norm(), 2.0 * res);  // open floor: nearly straight

  // A one-cell ring around [2, 4]^2: the goal's cell stays free and traversable, but enclosed.
  const CellIndex lo = grid.worldToCell({2.0, 2.0}), hi = grid.worldToCell({4.0, 4.0});
  for (int i = lo.x; i <= hi.x; ++i) {
    grid.setCell(i, lo.y, CellState::Occupied);
    grid.setCell(i, hi.y, CellState::Occupied);
    grid.setCell(lo.x, i, CellState::Occupied);
    grid.setCell(hi.x, i, CellState::Occupied);
  }
  planner.setMap(grid);
  const CellIndex gc = grid.worldToCell(goal);
  ASSERT_TRUE(planner.traversable(gc.x, gc.y));
  EXPECT_FALSE(planner.plan(start, goal).has_value());
  EXPECT_GT(planner.expandedCells(), 1000u);  // the search did look (the whole outside)
  // A diagonal hole in the ring (one corner cell): no corner cutting, still enclosed...
  grid.setCell(lo.x, lo.y, CellState::Free);
  planner.setMap(grid);
  EXPECT_FALSE(planner.plan(start, goal).has_value());
  // ...a 0.5 m gap is too narrow for the inflated robot, a 1 m gap is not.
  const CellIndex g0 = grid.worldToCell({2.75, 2.0}), g1 = grid.worldToCell({3.25, 2.0});
  for (int i = g0.x; i < g1.x; ++i) grid.setCell(i, lo.y, CellState::Free);
  planner.setMap(grid);
  EXPECT_FALSE(planner.plan(start, goal).has_value());
  const CellIndex g2 = grid.worldToCell({2.5, 2.0}), g3 = grid.worldToCell({3.5, 2.0});
  for (int i = g2.x; i < g3.x; ++i) grid.setCell(i, lo.y, CellState::Free);
  planner.setMap(grid);
  const auto through = planner.plan(start, goal);
  ASSERT_TRUE(through.has_value());
  EXPECT_GT(through->length, open_path->length);

  // With the goal enclosed, Dijkstra leaves it unreachable too.
  OccupancyGrid ring = grid;
  for (int i = g2.x; i < g3.x; ++i) ring.setCell(i, lo.y, CellState::Occupied);
  planner.setMap(ring);
  ASSERT_TRUE(planner.computeDistances(start));
  EXPECT_TRUE(std::isinf(planner.distance(gc.x, gc.y)));
  EXPECT_FALSE(planner.pathTo(goal).has_value());
  EXPECT_NEAR(planner.distance(grid.worldToCell(start).x, grid.worldToCell(start).y), 0.0, 1e-9);
}

TEST(GridPlanner, StartInsideTheInflationEscapes) {
  World world;
  world.box(kOff, kOff, 4.0 + kOff, 3.0 + kOff);
  OccupancyGrid grid;
  insert(&grid, world, Laser(), {2.0, 1.5, 0.0});
  GridPlanner planner;
  planner.setMap(grid);
  const Vector2d start(0.3, 1.5);  // 0.29 m from the wall: inside the 0.35 m inflation
  const CellIndex sc = grid.worldToCell(start);
  ASSERT_FALSE(planner.traversable(sc.x, sc.y));
  const auto path = planner.plan(start, {3.0, 1.5});
  ASSERT_TRUE(path.has_value());
  ASSERT_GE(path->waypoints.size(), 2u);
  // The first leg leaves the inflation; every later waypoint is traversable.
  for (std::size_t i = 1; i < path->waypoints.size(); ++i) {
    const CellIndex c = grid.worldToCell(path->waypoints[i]);
    EXPECT_TRUE(planner.traversable(c.x, c.y)) << i;
  }
  EXPECT_LE((path->waypoints[1] - start).norm(), planner.params().start_escape_distance + grid.resolution());
  // With no escape allowed, there is no path.
  PlannerParams strict;
  strict.start_escape_distance = 0.0;
  GridPlanner stuck(strict);
  stuck.setMap(grid);
  EXPECT_FALSE(stuck.plan(start, {3.0, 1.5}).has_value());
}

TEST(GridPlanner, NoCornerCuttingThroughADiagonalWall) {
  // A point robot (no inflation) and a diagonal wall of 8-connected occupied cells across a free
  // square: the cells touch only at their corners, and no path may slip between them.
  OccupancyGrid grid(OccupancyGridParams(), GridBounds{0.0, 0.0, 2.0, 2.0});
  forEachCell(grid, [&](int ix, int iy) { grid.setCell(ix, iy, CellState::Free); });
  for (int i = grid.minX(); i < grid.minX() + grid.width(); ++i)
    grid.setCell(i, grid.minY() + (i - grid.minX()), CellState::Occupied);
  PlannerParams point;
  point.robot_radius = 0.0;
  point.safety_margin = 0.0;
  GridPlanner planner(point);
  planner.setMap(grid);
  EXPECT_FALSE(planner.plan({1.5, 0.3}, {0.3, 1.5}).has_value());
  EXPECT_TRUE(planner.plan({1.5, 0.3}, {1.9, 1.2}).has_value());  // same side
}

// ---------------------------------------------------------------------------------------------
// The cost: potential_scale * path length - gain_scale * size

/// A 10 m x 2 m corridor of free cells walled in, with openings in its upper wall onto the unknown.
OccupancyGrid corridorWithOpenings(const std::vector<std::pair<double, double>>& openings) {
  OccupancyGrid grid(OccupancyGridParams(), GridBounds{-1.0, -1.0, 11.0, 4.0});
  const CellIndex lo = grid.worldToCell({0.0, 0.0}), hi = grid.worldToCell({10.0, 2.0});
  for (int iy = lo.y - 1; iy <= hi.y; ++iy) {
    for (int ix = lo.x - 1; ix <= hi.x; ++ix) {
      const bool wall = iy == lo.y - 1 || iy == hi.y || ix == lo.x - 1 || ix == hi.x;
      grid.setCell(ix, iy, wall ? CellState::Occupied : CellState::Free);
    }
  }
  for (const auto& [x0, x1] : openings)
    for (int ix = grid.worldToCell({x0, 0.0}).x; ix < grid.worldToCell({x1, 0.0}).x; ++ix)
      grid.setCell(ix, hi.y, CellState::Free);
  return grid;
}

TEST(FrontierExplorer, CostPrefersNearAndLargeFrontiers) {
  FrontierExplorer explorer;
  // Same size: the nearer one.
  const OccupancyGrid two = corridorWithOpenings({{1.0, 2.0}, {8.0, 9.0}});
  auto goal = explorer.nextGoal(two, {1.5, 1.0});
  ASSERT_TRUE(goal.has_value());
  EXPECT_LT(goal->x(), 3.0);
  ASSERT_EQ(explorer.frontiers().size(), 2u);
  EXPECT_LT(explorer.frontiers()[0].cost, explorer.frontiers()[1].cost);
  goal = explorer.nextGoal(two, {8.5, 1.0});
  ASSERT_TRUE(goal.has_value());
  EXPECT_GT(goal->x(), 7.0);
  // Same distance: the larger one (a 2 m opening against a 1 m one, the robot midway).
  const OccupancyGrid sizes = corridorWithOpenings({{2.0, 3.0}, {6.5, 8.5}});
  goal = explorer.nextGoal(sizes, {5.0, 1.0});
  ASSERT_TRUE(goal.has_value());
  EXPECT_GT(goal->x(), 6.0);
  const auto& f = explorer.frontiers();
  ASSERT_EQ(f.size(), 2u);
  EXPECT_GT(f[0].size, f[1].size);
  const FrontierParams& fp = explorer.params();
  EXPECT_NEAR(f[0].cost, fp.potential_scale * f[0].path_length - fp.gain_scale * f[0].size, 1e-9);
  EXPECT_NEAR(f[0].path_length, f[1].path_length, 0.5);  // midway indeed
  // Off the middle, the nearer one wins; unless the gain weighs ten times more.
  goal = explorer.nextGoal(sizes, {4.0, 1.0});
  ASSERT_TRUE(goal.has_value());
  EXPECT_LT(goal->x(), 4.0);
  FrontierParams greedy;
  greedy.gain_scale = 10.0;
  FrontierExplorer for_size(greedy);
  goal = for_size.nextGoal(sizes, {4.0, 1.0});
  ASSERT_TRUE(goal.has_value());
  EXPECT_GT(goal->x(), 6.0);
}

// ---------------------------------------------------------------------------------------------
// Blacklist

TEST(FrontierExplorer, BlacklistedFrontierIsSkipped) {
  const World world = roomWithDoor(true);
  const Vector2d robot(2.0, 2.05);
  OccupancyGrid grid;
  insert(&grid, world, Laser(), {robot.x(), robot.y(), 0.0});
  FrontierExplorer explorer;
  const auto goal = explorer.nextGoal(grid, robot);
  ASSERT_TRUE(goal.has_value());
  explorer.blacklist(*goal, 0.3);
  EXPECT_EQ(explorer.blacklistSize(), 1u);
  EXPECT_FALSE(explorer.nextGoal(grid, robot).has_value());  // the only frontier
  EXPECT_EQ(explorer.status(), ExplorerStatus::Complete);
  ASSERT_EQ(explorer.frontiers().size(), 1u);
  EXPECT_TRUE(explorer.frontiers()[0].blacklisted);
  explorer.clearBlacklist();
  EXPECT_TRUE(explorer.nextGoal(grid, robot).has_value());
}

// ---------------------------------------------------------------------------------------------
// Goal keeping (FrontierGoal, explore_lite's)

constexpr int64_t kSecond = 1000000000;

// The held goal is given up (blacklisted) when no planned path to it got shorter by a cell for
// the timeout, not before: explore_lite's progress_timeout.
TEST(FrontierGoal, AGoalWithoutProgressForTheTimeoutIsBlacklisted) {
  const OccupancyGrid grid = corridorWithOpenings({{1.0, 2.0}, {8.0, 9.0}});
  FrontierExplorer explorer;
  const Vector2d robot(1.5, 1.0);
  explorer.nextGoal(grid, robot);
  FrontierGoalParams params;
  params.timeout = 30.0;
  FrontierGoal goal(params);
  bool is_new = false;
  ASSERT_TRUE(goal.choose(robot, 0, &explorer, &is_new, nullptr));
  EXPECT_TRUE(is_new);
  const Vector2d first = *goal.goal();
  EXPECT_LT(first.x(), 3.0);  // the nearer opening
  goal.progress(4.0, grid.resolution(), 0);
  goal.progress(3.0, grid.resolution(), 10 * kSecond);  // shorter: progress at 10 s
  goal.progress(3.0, grid.resolution(), 20 * kSecond);  // no shorter: none
  EXPECT_EQ(goal.review(robot, false, false, 40 * kSecond, &explorer), FrontierGoal::End::Held);  // exactly 30 s
  EXPECT_EQ(goal.review(robot, false, false, 40 * kSecond + 1, &explorer), FrontierGoal::End::NoProgress);
  EXPECT_FALSE(goal.goal().has_value());
  // Blacklisted: the next goal is the other opening.
  explorer.nextGoal(grid, robot);
  ASSERT_TRUE(goal.choose(robot, 41 * kSecond, &explorer, &is_new, nullptr));
  EXPECT_TRUE(is_new);
  EXPECT_GT(goal.goal()->x(), 7.0);
}

// A goal ends reached within reach_tolerance (or when the controller says so), and is given up when
// the motion controller stopped (blocked or bumped).
TEST(FrontierGoal, AGoalEndsReachedOrGivenUpWhenTheControllerStopped) {
  const OccupancyGrid grid = corridorWithOpenings({{1.0, 2.0}, {8.0, 9.0}});
  FrontierExplorer explorer;
  const Vector2d robot(5.0, 1.0);
  explorer.nextGoal(grid, robot);
  FrontierGoal goal;
  bool is_new = false;
  ASSERT_TRUE(goal.choose(robot, 0, &explorer, &is_new, nullptr));
  const Vector2d target = *goal.goal();
  EXPECT_EQ(goal.review(target + Vector2d(0.3, 0.0), false, false, kSecond, &explorer), FrontierGoal::End::Reached);
  EXPECT_EQ(explorer.blacklistSize(), 0u);
  ASSERT_TRUE(goal.choose(robot, kSecond, &explorer, &is_new, nullptr));
  EXPECT_EQ(goal.review(robot, true, false, 2 * kSecond, &explorer), FrontierGoal::End::Reached);
  ASSERT_TRUE(goal.choose(robot, 2 * kSecond, &explorer, &is_new, nullptr));
  EXPECT_EQ(goal.review(robot, false, true, 3 * kSecond, &explorer), FrontierGoal::End::Stopped);
  EXPECT_EQ(explorer.blacklistSize(), 1u);
}

// The held goal follows its frontier as the grid changes, and is dropped for the cheapest one when
// its frontier is gone; a frontier whose goal is where the robot stands cannot be seen from there:
// blacklisted, not taken.
TEST(FrontierGoal, TheGoalFollowsItsFrontierAndAFrontierUnderTheRobotIsBlacklisted) {
  FrontierExplorer explorer;
  const Vector2d robot(5.0, 1.0);
  explorer.nextGoal(corridorWithOpenings({{1.0, 2.0}, {8.0, 9.0}}), robot);
  FrontierGoal goal;
  bool is_new = false;
  ASSERT_TRUE(goal.choose(robot, 0, &explorer, &is_new, nullptr));
  const bool left = goal.goal()->x() < 5.0;
  // The same frontier, grown by half a metre: still held.
  explorer.nextGoal(corridorWithOpenings({{0.5, 2.0}, {8.0, 9.5}}), robot);
  ASSERT_TRUE(goal.choose(robot, kSecond, &explorer, &is_new, nullptr));
  EXPECT_FALSE(is_new);
  EXPECT_EQ(goal.goal()->x() < 5.0, left);
  // Its frontier gone: the other one.
  explorer.nextGoal(left ? corridorWithOpenings({{8.0, 9.0}}) : corridorWithOpenings({{1.0, 2.0}}), robot);
  ASSERT_TRUE(goal.choose(robot, 2 * kSecond, &explorer, &is_new, nullptr));
  EXPECT_TRUE(is_new);
  EXPECT_NE(goal.goal()->x() < 5.0, left);
  // The robot at the only frontier's goal: blacklisted, and no goal is left.
  const Vector2d at = *goal.goal();
  goal.drop();
  const OccupancyGrid last = left ? corridorWithOpenings({{8.0, 9.0}}) : corridorWithOpenings({{1.0, 2.0}});
  explorer.nextGoal(last, at);
  std::vector<Vector2d> unobservable;
  EXPECT_FALSE(goal.choose(at, 3 * kSecond, &explorer, &is_new, &unobservable));
  EXPECT_EQ(unobservable.size(), 1u);
  EXPECT_EQ(explorer.blacklistSize(), 1u);
}

// ---------------------------------------------------------------------------------------------
// (e) Bad input

TEST(OccupancyGrid, BadInputWritesNothing) {
  const World world = roomWithDoor(false);
  const Laser laser;
  const std::vector<double> good = laser.scan(world, {2.0, 2.0, 0.0});
  OccupancyGrid grid;
  std::string why;
  EXPECT_FALSE(grid.insertScan({kNaN, 2.0, 0.0}, good, laser.angle_min, laser.increment(), &why));
  EXPECT_FALSE(why.empty());
  EXPECT_FALSE(grid.insertScan({2.0, 2.0, kNaN}, good, laser.angle_min, laser.increment()));
  EXPECT_FALSE(grid.insertScan({2.0, 2.0, 0.0}, good, kNaN, laser.increment()));
  EXPECT_FALSE(grid.insertScan({2.0, 2.0, 0.0}, good, laser.angle_min, kInf));
  EXPECT_FALSE(grid.insertScan({1e12, 2.0, 0.0}, good, laser.angle_min, laser.increment()));
  EXPECT_EQ(grid.cellCount(), 0u);
  EXPECT_EQ(grid.scansInserted(), 0u);

  // Ranges that are no measurement: skipped; the scan is accepted but writes nothing.
  std::vector<double> bad(360);
  const double no_measurement[4] = {kNaN, -kInf, 0.0, -1.0};
  for (std::size_t i = 0; i < bad.size(); ++i) bad[i] = no_measurement[i % 4];
  EXPECT_TRUE(grid.insertScan({2.0, 2.0, 0.0}, bad, laser.angle_min, laser.increment()));
  EXPECT_EQ(grid.cellCount(), 0u);
  std::vector<float> bad_f(bad.begin(), bad.end());
  EXPECT_TRUE(grid.insertScan({2.0, 2.0, 0.0}, bad_f, laser.angle_min, laser.increment()));
  EXPECT_EQ(grid.cellCount(), 0u);

  // A fixed grid: nothing observed after the same.
  OccupancyGrid fixed(OccupancyGridParams(), GridBounds{-1.0, -1.0, 6.0, 5.0});
  EXPECT_FALSE(fixed.insertScan({kNaN, kNaN, kNaN}, good, laser.angle_min, laser.increment()));
  EXPECT_TRUE(fixed.insertScan({2.0, 2.0, 0.0}, bad, laser.angle_min, laser.increment()));
  EXPECT_EQ(fixed.count(CellState::Unknown), fixed.cellCount());

  // One valid beam among NaNs (straight ahead, +x): only the cells along it are written, no gap
  // filling towards the invalid neighbours.
  std::vector<double> one(360, kNaN);
  const std::size_t ahead = 180;  // angle_min = -pi: beam 180 is at 0 rad
  one[ahead] = good[ahead];
  ASSERT_TRUE(fixed.insertScan({2.0, 2.0, 0.0}, one, laser.angle_min, laser.increment()));
  std::size_t observed = 0, off_beam = 0;
  forEachCell(fixed, [&](int ix, int iy) {
    if (!fixed.observed(ix, iy)) return;
    ++observed;
    if (std::abs(fixed.cellCenter(ix, iy).y() - 2.0) > fixed.resolution()) ++off_beam;
  });
  EXPECT_NEAR(static_cast<double>(observed), good[ahead] / fixed.resolution() + 1.0, 2.0);
  EXPECT_EQ(off_beam, 0u);

  // The explorer and the planner refuse non-finite positions.
  FrontierExplorer explorer;
  EXPECT_FALSE(explorer.nextGoal(fixed, {kNaN, 1.0}).has_value());
  EXPECT_EQ(explorer.status(), ExplorerStatus::Invalid);
  EXPECT_FALSE(explorer.nextGoal(fixed, {100.0, 100.0}).has_value());  // outside the map
  EXPECT_EQ(explorer.status(), ExplorerStatus::Invalid);
  GridPlanner planner;
  planner.setMap(fixed);
  EXPECT_FALSE(planner.plan({kNaN, 2.0}, {3.0, 2.0}).has_value());
  EXPECT_FALSE(planner.plan({2.0, 2.0}, {3.0, kInf}).has_value());
  explorer.blacklist({kNaN, 0.0}, 1.0);
  EXPECT_EQ(explorer.blacklistSize(), 0u);
}

TEST(Params, InvalidParamsAreRefused) {
  OccupancyGridParams g;
  g.free_threshold = 0.7;  // above occupied_threshold
  EXPECT_FALSE(OccupancyGrid::validate(g));
  EXPECT_THROW(OccupancyGrid{g}, std::invalid_argument);
  g = OccupancyGridParams();
  g.resolution = 0.0;
  EXPECT_FALSE(OccupancyGrid::validate(g));
  g = OccupancyGridParams();
  g.l_free = 0.1;
  EXPECT_FALSE(OccupancyGrid::validate(g));
  EXPECT_THROW(OccupancyGrid(OccupancyGridParams(), GridBounds{0.0, 0.0, kNaN, 1.0}), std::invalid_argument);
  EXPECT_THROW(OccupancyGrid(OccupancyGridParams(), GridBounds{0.0, 0.0, 1e4, 1e4}), std::invalid_argument);
  PlannerParams p;
  p.robot_radius = -1.0;
  EXPECT_THROW(GridPlanner{p}, std::invalid_argument);
  FrontierParams f;
  f.gain_scale = kNaN;
  EXPECT_THROW(FrontierExplorer{f}, std::invalid_argument);
  EXPECT_TRUE(OccupancyGrid::validate(OccupancyGridParams()));
  EXPECT_TRUE(GridPlanner::validate(PlannerParams()));
  EXPECT_TRUE(FrontierExplorer::validate(FrontierParams()));
}

// ---------------------------------------------------------------------------------------------
// (f) Memory

TEST(OccupancyGrid, BytesAreOnePerCellAndGrowthKeepsTheMap) {
  const World world = smallFloor();
  const Laser laser;
  OccupancyGrid grid;
  EXPECT_EQ(grid.bytes(), 0u);
  insert(&grid, world, laser, {1.0, 0.8, 0.0});
  EXPECT_EQ(grid.bytes(), grid.cellCount());
  EXPECT_EQ(grid.bytes(), static_cast<std::size_t>(grid.width()) * static_cast<std::size_t>(grid.height()));
  const std::size_t before = grid.bytes();
  // A snapshot of the states, by global index.
  std::vector<std::pair<CellIndex, CellState>> states;
  forEachCell(grid, [&](int ix, int iy) { states.push_back({{ix, iy}, grid.cellState(ix, iy)}); });

  insert(&grid, world, laser, {8.5, 4.5, 0.0});  // room B: the grid grows
  EXPECT_GT(grid.bytes(), before);
  EXPECT_EQ(grid.bytes(), static_cast<std::size_t>(grid.width()) * static_cast<std::size_t>(grid.height()));
  std::size_t changed_far = 0;  // cells the second scan cannot see keep their state
  for (const auto& [c, s] : states) {
    if (world.blocked({8.5, 4.5}, grid.cellCenter(c)) && world.clearance(grid.cellCenter(c)) > 0.2 &&
        grid.cellState(c) != s)
      ++changed_far;
  }
  EXPECT_EQ(changed_far, 0u);
  std::vector<std::int8_t> data;
  grid.toOccupancyData(&data);
  EXPECT_EQ(data.size(), grid.bytes());
  EXPECT_EQ(static_cast<std::size_t>(std::count(data.begin(), data.end(), std::int8_t{-1})),
            grid.cellCount() - [&] {
              std::size_t n = 0;
              forEachCell(grid, [&](int ix, int iy) { n += grid.observed(ix, iy) ? 1 : 0; });
              return n;
            }());

  // A fixed grid: its extent in cells, whatever is inserted.
  OccupancyGrid fixed(OccupancyGridParams(), GridBounds{-0.5, -0.5, 10.5, 6.5});
  const std::size_t expected = static_cast<std::size_t>(std::ceil(10.5 / 0.05) - std::floor(-0.5 / 0.05)) *
                               static_cast<std::size_t>(std::ceil(6.5 / 0.05) - std::floor(-0.5 / 0.05));
  EXPECT_EQ(fixed.bytes(), expected);
  insert(&fixed, world, laser, {1.0, 0.8, 0.0});
  EXPECT_EQ(fixed.bytes(), expected);
  EXPECT_EQ(fixed.bytes(), fixed.cellCount());

  // A growing grid refuses a scan that would need more than max_cells.
  OccupancyGridParams small;
  small.max_cells = 10000;
  OccupancyGrid capped(small);
  EXPECT_FALSE(capped.insertScan({1.0, 0.8, 0.0}, laser.scan(world, {1.0, 0.8, 0.0}), laser.angle_min,
                                 laser.increment()));
  EXPECT_EQ(capped.cellCount(), 0u);
}

}  // namespace
}  // namespace exploration
