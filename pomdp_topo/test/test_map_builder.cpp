// FrontEnd + MapBuilder + PomdpLocalizer together on synthetic hallways: a robot drives along
// hallway centre lines; each scan gives the two hallway walls as lines and the doors and branches
// within range as openings (as laser_features would), with the odometry as the pose.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "pomdp_topo/front_end.h"
#include "pomdp_topo/map_builder.h"
#include "pomdp_topo/pomdp_localizer.h"

namespace pomdp_topo {
namespace {

using laser_features::kPi;
using laser_features::normalizeAngle;

struct Door {
  Eigen::Vector2d center;  // on the wall line
  double normal;           // direction from the hallway into the room (world)
  double width;
  int axis = -1;           // seen only while driving along x (0) or y (1); -1: always (a wall's door)
  bool room_behind = false;  // laser_features saw a room behind it (a double door's width needs it)
};

// A closed or open polyline of hallway centre lines (axis-aligned), half width 1.1 m, with doors.
struct SyntheticFloor {
  std::vector<Door> doors;
  std::vector<Eigen::Vector2d> corners;  // turn points of the drive: the branch opening is seen there
  double range = 5.0;
  std::mt19937 rng{7};

  void scan(const Pose2D& pose, int next_corner, const std::vector<Eigen::Vector2d>& path,
            std::vector<laser_features::LineSegment>* lines, std::vector<laser_features::Opening>* openings) {
    lines->clear();
    openings->clear();
    std::normal_distribution<double> noise(0.0, 0.02);
    // Walls parallel to the travel axis (the robot drives on axis-aligned centre lines).
    const double axis = std::round(pose.theta / (0.5 * kPi)) * 0.5 * kPi;
    for (double side : {1.0, -1.0}) {
      laser_features::LineSegment s;
      s.line.alpha = normalizeAngle(axis + side * 0.5 * kPi - pose.theta + 0.002 * noise(rng));
      s.line.r = 1.1;
      s.line.cov << 1e-4, 0, 0, 1e-4;
      const Eigen::Vector2d n = laser_features::unitVector(s.line.alpha), t(-n.y(), n.x());
      s.start = 1.1 * n - 3.0 * t;
      s.end = 1.1 * n + 3.0 * t;
      s.num_points = 100;
      lines->push_back(s);
    }
    auto add = [&](const Eigen::Vector2d& c, double normal, double width, bool room_behind = false) {
      const Eigen::Vector2d rel = c - Eigen::Vector2d(pose.x, pose.y);
      if (rel.norm() > range) return;
      laser_features::Opening o;
      const double cs = std::cos(-pose.theta), sn = std::sin(-pose.theta);
      o.center = Eigen::Vector2d(cs * rel.x() - sn * rel.y() + noise(rng), sn * rel.x() + cs * rel.y() + noise(rng));
      o.theta = normalizeAngle(normal - pose.theta);
      o.width = width;
      o.room_behind = room_behind;
      o.confidence = 0.8;
      openings->push_back(o);
    };
    const int travel_axis = std::abs(std::cos(pose.theta)) > 0.7 ? 0 : 1;
    for (const Door& d : doors) {
      if (d.axis < 0 || d.axis == travel_axis) add(d.center, d.normal, d.width, d.room_behind);
    }
    // The branch the robot is about to turn into: an opening beside the turn point.
    if (next_corner >= 1 && next_corner + 1 < int(path.size())) {
      const Eigen::Vector2d c = path[next_corner];
      const Eigen::Vector2d dir = (path[next_corner + 1] - c).normalized();
      add(c + 1.1 * dir, std::atan2(dir.y(), dir.x()), 2.0);
    }
  }
};

struct Drive {
  TopologicalMap map;
  PomdpLocalizer localizer;
  FrontEnd front_end;
  MapBuilder builder;
  size_t steps = 0, localized = 0, right = 0;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();   // true position - odometry (a kidnapping sets it)
  Eigen::Vector2d drift = Eigen::Vector2d::Zero();   // added to shift at every scan (odometry drift)
  double yaw = 0.0;  // rad, the floor's yaw in the odometry frame (a building at an angle to the start)
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> relocations;  // (map's position, truth)

  explicit Drive(const MapBuilderParams& params = MapBuilderParams()) : builder(&map, &localizer, params) {}

  /// The floor turned by `angle` in the odometry frame, and the building's axis known to be there.
  void turnFloor(double angle) {
    yaw = angle;
    front_end.setAxis(angle);
    builder.setAxis(angle);
    localizer.setAxis(angle);
  }
  /// A floor-frame point in the odometry (= map) frame.
  Eigen::Vector2d toOdom(const Eigen::Vector2d& p) const { return Eigen::Rotation2Dd(yaw) * p; }

  // Drives the path (straight segments, turns on the spot) and checks the belief against the
  // true position after every localized scan.
  void run(SyntheticFloor* floor, const std::vector<Eigen::Vector2d>& path, double start_theta) {
    Pose2D pose{path[0].x(), path[0].y(), start_theta};
    std::vector<laser_features::LineSegment> lines;
    std::vector<laser_features::Opening> openings;
    std::vector<laser_features::Corner> corners;
    std::vector<Action> actions;
    auto tick = [&](int next) {
      floor->scan(pose, next, path, &lines, &openings);
      actions.clear();
      shift += drift;
      const Eigen::Vector2d o = toOdom(Eigen::Vector2d(pose.x - shift.x(), pose.y - shift.y()));
      const Pose2D odometry{o.x(), o.y(), normalizeAngle(pose.theta + yaw)};
      ASSERT_TRUE(front_end.process(odometry, lines, corners, openings, &actions));
      if (steps++ == 0) builder.start(front_end);
      builder.process(actions, front_end.observation(), front_end.takePassed(), front_end);
      Eigen::Vector2d relocated;
      if (builder.takeRelocatedPosition(&relocated)) {  // as pomdp_topo_node does
        front_end.setPosition(relocated);
        relocations.push_back({relocated, Eigen::Vector2d(pose.x, pose.y)});
      }
      if (builder.mode() == MapBuilder::Mode::Localized && localizer.mostLikely() >= 0) {
        ++localized;
        const auto& st = localizer.state(size_t(localizer.mostLikely()));
        const Eigen::Vector2d p = position(st);
        // The map frame is the odometry frame at the first scan: here the floor's frame.
        const Eigen::Vector2d truth = toOdom(Eigen::Vector2d(pose.x, pose.y));
        if ((p - truth).norm() <= 1.0 && std::abs(normalizeAngle(st.heading - pose.theta - yaw)) < 0.5) ++right;
      }
    };
    for (size_t k = 1; k < path.size(); ++k) {
      const Eigen::Vector2d d = path[k] - Eigen::Vector2d(pose.x, pose.y);
      const double heading = std::atan2(d.y(), d.x());
      while (std::abs(normalizeAngle(heading - pose.theta)) > 1e-6) {
        const double turn = normalizeAngle(heading - pose.theta);
        pose.theta = normalizeAngle(pose.theta + std::copysign(std::min(0.12, std::abs(turn)), turn));
        tick(int(k) - 1);
      }
      for (int i = 0; i < 3; ++i) tick(int(k) - 1);  // settle
      const double length = d.norm();
      const int n = int(std::ceil(length / 0.05));
      const Eigen::Vector2d from(pose.x, pose.y);
      for (int i = 1; i <= n; ++i) {
        const Eigen::Vector2d p = from + d * (double(i) / n);
        pose.x = p.x();
        pose.y = p.y();
        tick(int(k));
      }
    }
  }

  Eigen::Vector2d nodePos(uint32_t id) const {
    const TopoNode* n = map.node(id);
    return {n->pose.x, n->pose.y};
  }
  Eigen::Vector2d position(const PomdpLocalizer::State& st) const {
    if (st.kind == PomdpLocalizer::State::Node) return nodePos(st.id);
    const TopoEdge* e = map.edge(st.id);
    const Eigen::Vector2d a = nodePos(e->source), b = nodePos(e->target);
    return a + (b - a) * (e->length > 0 ? st.offset / e->length : 0.0);
  }
  size_t count(NodeType type) const {
    size_t n = 0;
    for (const auto& kv : map.nodes()) n += kv.second.type == type;
    return n;
  }
};

// A straight hallway with five doors: driven east, U-turn, west past the start (off the known
// graph), U-turn, east again.
TEST(MapBuilder, StraightHallwayDoorsHallwayEndsAndLocalizationOnTheWayBack) {
  SyntheticFloor floor;
  const double xs[] = {4.0, 7.5, 9.0, 14.0, 17.0};
  for (int i = 0; i < 5; ++i) floor.doors.push_back({{xs[i], i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {-1.5, 0}, {20.0, 0}}, 0.0);
  EXPECT_EQ(drive.count(NodeType::Door), 5u);
  EXPECT_EQ(drive.count(NodeType::HallwayEnd), 2u);  // both U-turns
  EXPECT_EQ(drive.count(NodeType::Junction), 0u);
  // The doors are where they are (the map frame is the odometry frame, here the floor's).
  std::vector<double> found;
  for (const auto& kv : drive.map.nodes()) {
    if (kv.second.type == NodeType::Door) found.push_back(kv.second.pose.x);
  }
  std::sort(found.begin(), found.end());
  ASSERT_EQ(found.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(found[i], xs[i], 0.3) << "door " << i;
  // Back along the known hallway: localized, and right.
  EXPECT_GT(drive.localized, 300u);
  EXPECT_GE(double(drive.right) / drive.localized, 0.95) << drive.right << " of " << drive.localized;
  EXPECT_EQ(drive.builder.loopsClosed().size(), 0u);
}

// A robot that starts facing the way it will not go turns round at the start node before it has
// left it: the stretch is mapped from the start node the other way (it became 'localized' on the
// one-node map, and with the start node closed, as explore.launch runs it, never mapped again).
TEST(MapBuilder, AUTurnAtTheStartBeforeLeavingItMapsTheStretchTheOtherWay) {
  SyntheticFloor floor;
  const double xs[] = {4.0, 7.5, 9.0, 14.0, 17.0};
  for (int i = 0; i < 5; ++i) floor.doors.push_back({{xs[i], i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
  MapBuilderParams params;
  params.start_node_closed = true;  // as explore.launch runs it: the start node has no way but those recorded
  Drive drive(params);
  drive.run(&floor, {{1.5, 0}, {20.0, 0}}, kPi);  // facing west at the start, then east
  EXPECT_EQ(drive.count(NodeType::Door), 5u);
  EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Frontier);
}

// A building at 34 deg to the odometry frame, with its axis known (pomdp_topo_node finds it from the
// walls): the same graph as at 0 deg, turned, every edge along the axis, and localization as good.
TEST(MapBuilder, ABuildingAtAnAngleMapsAlongItsAxisLikeAnAlignedOne) {
  const double yaw = 34.0 * kPi / 180.0;
  SyntheticFloor floor;
  const double xs[] = {4.0, 7.5, 9.0, 14.0, 17.0};
  for (int i = 0; i < 5; ++i) floor.doors.push_back({{xs[i], i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
  Drive drive;
  drive.turnFloor(yaw);
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {-1.5, 0}, {20.0, 0}}, 0.0);
  EXPECT_EQ(drive.count(NodeType::Door), 5u);
  EXPECT_EQ(drive.count(NodeType::HallwayEnd), 2u);
  EXPECT_EQ(drive.count(NodeType::Junction), 0u);
  std::vector<double> along;  // door nodes' positions along the turned hallway
  for (const auto& kv : drive.map.nodes()) {
    const Eigen::Vector2d p = Eigen::Rotation2Dd(-yaw) * drive.nodePos(kv.first);
    EXPECT_LT(std::abs(p.y()), 1.5) << "node " << kv.first << " is off the hallway";
    if (kv.second.type == NodeType::Door) along.push_back(p.x());
  }
  std::sort(along.begin(), along.end());
  ASSERT_EQ(along.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(along[i], xs[i], 0.3) << "door " << i;
  for (const auto& kv : drive.map.edges())
    EXPECT_NEAR(std::abs(normalizeAngle(4.0 * (kv.second.heading - yaw))), 0.0, 1e-6) << "edge " << kv.first;
  EXPECT_GT(drive.localized, 300u);
  EXPECT_GE(double(drive.right) / drive.localized, 0.95) << drive.right << " of " << drive.localized;
}

// A door first seen on the second pass along a known hallway makes a door node on the known edge,
// where the dead reckoning agrees with the belief; with the dead reckoning 4 m off sideways (the
// belief, from the hallway's doors, still right) it is not added: a belief a node or two off must
// not put a phantom opening on the map (update_position_tolerance).
TEST(MapBuilder, ADoorOnAKnownHallwayIsAddedOnlyWhereTheDeadReckoningAgrees) {
  for (const bool drifting : {false, true}) {
    SyntheticFloor floor;
    for (double x : {4.0, 9.0, 16.0}) floor.doors.push_back({{x, 1.1}, 0.5 * kPi, 0.9});
    Drive drive;
    drive.run(&floor, {{1.5, 0}, {20.0, 0}, {1.5, 0}}, 0.0);
    ASSERT_EQ(drive.count(NodeType::Door), 3u);
    floor.doors.push_back({{12.5, -1.1}, -0.5 * kPi, 0.9});  // opened since
    if (drifting) drive.drift = Eigen::Vector2d(0.0, -4.0 / 200.0);  // 4 m north within the first 10 m
    drive.run(&floor, {{1.5, 0}, {20.0, 0}}, kPi);
    EXPECT_EQ(drive.count(NodeType::Door), drifting ? 3u : 4u) << (drifting ? "drifting" : "no drift");
    EXPECT_GE(double(drive.right) / std::max<size_t>(1, drive.localized), 0.9) << drive.right << " of " << drive.localized;
  }
}

// A belief put on the right node but heading the other way (as a look-alike U-turn can leave it):
// with the heading trusted (a map built in this run) the heading gate drops it at the next scan;
// without the gate it stays, and a stretch left along it would ignore every door passed.
TEST(MapBuilder, TheHeadingGateDropsABeliefHeadingOtherwiseThanTheRobot) {
  for (const bool gate : {true, false}) {
    SyntheticFloor floor;
    for (double x : {4.0, 9.0, 16.0}) floor.doors.push_back({{x, 1.1}, 0.5 * kPi, 0.9});
    MapBuilderParams params;
    params.heading_gate = gate;
    Drive drive(params);
    drive.run(&floor, {{1.5, 0}, {20.0, 0}, {12.0, 0}}, 0.0);  // back west, past the doors at 16 and 9
    uint32_t door = 0;
    for (const auto& kv : drive.map.nodes()) {
      if (kv.second.type == NodeType::Door && std::abs(kv.second.pose.x - 9.0) < 0.5) door = kv.first;
    }
    ASSERT_NE(door, 0u);
    ASSERT_TRUE(drive.localizer.resetToNode(door, 0.0));  // east, while the robot heads west
    drive.run(&floor, {{12.0, 0}, {11.5, 0}}, kPi);
    const int ml = drive.localizer.mostLikely();
    ASSERT_GE(ml, 0);
    const double heading = drive.localizer.state(size_t(ml)).heading;
    if (gate) {
      EXPECT_LT(std::abs(normalizeAngle(heading - kPi)), 0.1) << "the belief heads " << heading;
    } else {
      EXPECT_LT(std::abs(normalizeAngle(heading)), 0.1) << "without the gate the belief heads " << heading;
    }
  }
}

// A long hallway of look-alike doors (one every 5 m, alternating sides), mapped east and localized
// on the way back; then the belief is lost (uniform). The position gate keeps it within
// position_gate (+1 % of the travel) of the dead-reckoned position: no look-alike 40 m away gets
// any of it (which of the near look-alikes is right takes more than 10 m to tell in a periodic
// hallway). Without the gate the far look-alikes keep their share.
TEST(MapBuilder, ThePositionGateKeepsALostBeliefNearTheDeadReckonedPosition) {
  for (const double gate : {10.0, 0.0}) {
    SyntheticFloor floor;
    for (int i = 0; i < 11; ++i) {
      floor.doors.push_back({{4.0 + 5.0 * i, i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
    }
    MapBuilderParams params;
    params.position_gate = gate;
    Drive drive(params);
    drive.run(&floor, {{1.5, 0}, {58.0, 0}, {30.0, 0}}, 0.0);
    ASSERT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
    drive.localizer.setUniform();  // lost, at x = 30
    drive.localized = drive.right = 0;
    drive.run(&floor, {{30.0, 0}, {20.0, 0}}, kPi);
    const Eigen::Vector2d here(drive.front_end.pose().x, drive.front_end.pose().y);
    double far = 0.0;  // belief mass more than 25 m from the robot (the gate is 10 m + ~1 m)
    for (size_t s = 0; s < drive.localizer.belief().size(); ++s) {
      if ((drive.position(drive.localizer.state(s)) - here).norm() > 25.0) far += drive.localizer.belief()[s];
    }
    if (gate > 0.0) {
      EXPECT_EQ(far, 0.0);
      ASSERT_GE(drive.localizer.mostLikely(), 0);
      EXPECT_LE((drive.position(drive.localizer.state(size_t(drive.localizer.mostLikely()))) - here).norm(), 11.5);
    } else {
      EXPECT_GT(far, 1e-6) << "without the gate the far look-alikes keep some belief";
    }
  }
}

// A belief at a node heading where no edge leads (beyond the known map) stands for a robot on the
// way out of that node: there it explains whatever lies ahead as unexplored. Put at the start node
// facing west while the robot, 4.5 m east of it, drives west along the known hallway, it is gated
// out (the robot is not on that way out) and the belief finds the robot on the hallway; the map
// is not extended from the start node. Without the dead-reckoning checks
// (update_position_tolerance 0) the builder leaves the known graph there, a new stretch where the
// robot is not. The position gate is set wide (10 m) to leave this to the rule.
TEST(MapBuilder, ABeliefBeyondTheMapIsOnlyWhereTheRobotIsOnTheWayOutOfItsNode) {
  for (const double tolerance : {2.5, 0.0}) {
    SyntheticFloor floor;
    for (int i = 0; i < 4; ++i) {
      floor.doors.push_back({{4.0 + 4.5 * i, i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
    }
    MapBuilderParams params;
    params.position_gate = 10.0;
    params.update_position_tolerance = tolerance;
    Drive drive(params);
    drive.run(&floor, {{1.5, 0}, {20.0, 0}, {6.0, 0}}, 0.0);
    ASSERT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
    const size_t nodes = drive.map.nodeCount();
    uint32_t start = 0;
    for (const auto& [id, n] : drive.map.nodes()) {
      if (n.type == NodeType::Start) start = id;
    }
    ASSERT_TRUE(drive.localizer.resetToNode(start, kPi));
    drive.localized = drive.right = 0;
    drive.run(&floor, {{6.0, 0}, {3.0, 0}}, kPi);
    if (tolerance > 0.0) {
      EXPECT_EQ(drive.map.nodeCount(), nodes);
      EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
      ASSERT_GE(drive.localizer.mostLikely(), 0);
      const Eigen::Vector2d here(drive.front_end.pose().x, drive.front_end.pose().y);
      EXPECT_LE((drive.position(drive.localizer.state(size_t(drive.localizer.mostLikely()))) - here).norm(), 1.0);
    } else {
      EXPECT_TRUE(drive.map.nodeCount() > nodes || drive.builder.mode() != MapBuilder::Mode::Localized)
          << "without the checks the builder leaves the known graph at the start node";
    }
  }
}

// A belief that reaches a node late (it lagged behind on a stretch with nothing to place it by)
// leaves the known graph there when the robot is already well past it: the new stretch starts as
// far along as the dead reckoning puts the robot, so the next node lies at its true distance. Here
// the belief is put 3.5 m behind the robot on a featureless stretch before the start node; the
// robot drives on west 7.5 m past the start and turns round at the hallway's end.
TEST(MapBuilder, AStretchLeftLateStartsWhereTheRobotIs) {
  for (const double tolerance : {2.5, 0.0}) {
    SyntheticFloor floor;
    for (int i = 0; i < 3; ++i) {
      floor.doors.push_back({{10.0 + 3.5 * i, i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
    }
    MapBuilderParams params;
    params.update_position_tolerance = tolerance;
    Drive drive(params);
    drive.run(&floor, {{1.5, 0}, {20.0, 0}, {3.0, 0}}, 0.0);
    ASSERT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
    uint32_t start = 0;
    for (const auto& [id, n] : drive.map.nodes()) {
      if (n.type == NodeType::Start) start = id;
    }
    EdgeExit first;
    ASSERT_TRUE(drive.map.exitWithHeading(start, 0.0, 0.25 * kPi, &first));
    ASSERT_TRUE(drive.localizer.resetToEdge(first.edge, 5.0, false));  // x = 6.5: 3.5 m behind
    drive.run(&floor, {{3.0, 0}, {-6.0, 0}, {-3.0, 0}}, kPi);
    const TopoEdge* west = nullptr;
    for (const auto& [id, e] : drive.map.edges()) {
      const uint32_t other = e.source == start ? e.target : e.target == start ? e.source : start;
      if (other != start && drive.map.node(other)->pose.x < 0.0) west = &e;
    }
    ASSERT_NE(west, nullptr) << "a stretch west of the start node";
    if (tolerance > 0.0) {
      EXPECT_NEAR(west->length, 7.5, 0.6);
    } else {
      EXPECT_LT(west->length, 5.0) << "without the dead-reckoning checks the stretch starts where the belief is";
    }
  }
}

// Leaving the known graph at a node along a heading, the dead-reckoned position decides: on the
// way out within update_position_tolerance (2.5 m) of `s`, the stretch starts (s kept); farther
// along, it starts as far along as the robot is (the belief came late); on the way out but short
// of s by more than the tolerance (the belief leads: the robot circling near the node), not yet,
// s the robot's distance past the node; off the way out, or behind the node, never. Without the
// dead-reckoning checks it always starts.
TEST(MapBuilder, AStretchLeavesANodeWhereTheDeadReckoningPutsTheRobotOnItsWayOut) {
  for (const double tolerance : {2.5, 0.0}) {
    SyntheticFloor floor;
    floor.doors.push_back({{6.0, 1.1}, 0.5 * kPi, 0.9});
    MapBuilderParams params;
    params.update_position_tolerance = tolerance;
    Drive drive(params);
    drive.run(&floor, {{1.5, 0}, {10.0, 0}, {5.0, 0}}, 0.0);
    const TopoNode* start = nullptr;
    for (const auto& [id, n] : drive.map.nodes()) {
      if (n.type == NodeType::Start) start = &n;
    }
    ASSERT_NE(start, nullptr);
    const double x0 = start->pose.x, y0 = start->pose.y;
    using D = MapBuilder::Departure;
    auto at = [&](double along, double lateral, double s, double* out) {  // west of the start
      *out = s;
      return drive.builder.departure(*start, kPi, Pose2D{x0 - along, y0 + lateral, kPi}, out);
    };
    double s = 0.0;
    if (tolerance > 0.0) {
      EXPECT_EQ(at(1.2, 0.3, 1.0, &s), D::Here);
      EXPECT_DOUBLE_EQ(s, 1.0);
      EXPECT_EQ(at(7.0, 1.2, 1.0, &s), D::Here);
      EXPECT_DOUBLE_EQ(s, 7.0);
      EXPECT_EQ(at(-2.0, 0.0, 3.0, &s), D::NotYet);
      EXPECT_DOUBLE_EQ(s, 0.0);
      EXPECT_EQ(at(0.4, 0.0, 3.5, &s), D::NotYet);
      EXPECT_DOUBLE_EQ(s, 0.4);
      EXPECT_EQ(at(3.0, 3.0, 1.0, &s), D::Elsewhere);
      EXPECT_EQ(at(-4.0, 0.0, 1.0, &s), D::Elsewhere);
    } else {
      EXPECT_EQ(at(-4.0, 3.0, 1.0, &s), D::Here);
      EXPECT_DOUBLE_EQ(s, 1.0);
    }
  }
}

// institute's hall_north: doors facing each other across the hallway 0.9 m apart, driven there and
// back twice. Each door is one opening of one node: a door seen on the way back with the belief a
// little off along the short edge between them is not added to the other door's node.
TEST(MapBuilder, DoorsFacingEachOtherCloseTogetherAreNotAddedToEachOther) {
  SyntheticFloor floor;
  const double xs[] = {4.0, 7.1, 8.0, 11.5};
  const bool left[] = {true, false, true, false};
  for (int i = 0; i < 4; ++i) {
    floor.doors.push_back({{xs[i], left[i] ? 1.1 : -1.1}, left[i] ? 0.5 * kPi : -0.5 * kPi, i == 1 ? 1.2 : 0.9});
  }
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {14.0, 0}, {1.0, 0}, {14.0, 0}, {1.0, 0}}, 0.0);
  EXPECT_EQ(drive.count(NodeType::Door), 4u);
  for (const auto& [id, n] : drive.map.nodes()) {
    if (n.type == NodeType::Door) EXPECT_EQ(n.openings.size(), 1u) << "door node " << id;
  }
}

// A double door is a door node when laser_features saw a room behind it; an opening as wide with
// none seen (a narrow hallway's mouth) is a junction; a single door is a door by its width.
TEST(MapBuilder, ADoubleDoorWithARoomBehindIsADoorNodeAndOneAsWideWithoutAJunction) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 1.6, -1, true});
  floor.doors.push_back({{10.0, 1.1}, 0.5 * kPi, 1.6, -1, false});
  floor.doors.push_back({{16.0, -1.1}, -0.5 * kPi, 0.9, -1, false});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}}, 0.0);
  EXPECT_EQ(drive.count(NodeType::Door), 2u);
  EXPECT_EQ(drive.count(NodeType::Junction), 1u);
  for (const auto& [id, n] : drive.map.nodes()) {
    if (n.type == NodeType::Junction) EXPECT_NEAR(n.pose.x, 10.0, 1.0) << "junction node " << id;
  }
}

// large_floor: a door measured 0.66 m wide on the first pass and 1.28 m on a later one (seen from
// another angle after a U-turn) is the door its node has, not a second opening there or a new door
// node beside it.
TEST(MapBuilder, ADoorMeasuredAnotherWidthOnALaterPassIsTheKnownDoor) {
  SyntheticFloor floor;
  for (double x : {4.0, 9.0, 16.0}) floor.doors.push_back({{x, 1.1}, 0.5 * kPi, 0.9});
  floor.doors[1].width = 0.66;
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {1.5, 0}}, 0.0);
  ASSERT_EQ(drive.count(NodeType::Door), 3u);
  floor.doors[1].width = 1.28;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {1.5, 0}}, kPi);
  EXPECT_EQ(drive.count(NodeType::Door), 3u);
  for (const auto& [id, n] : drive.map.nodes()) {
    if (n.type == NodeType::Door) EXPECT_EQ(n.openings.size(), 1u) << "door node " << id;
  }
}

// large_floor: the route turned round 0.5 m past a door node (hall_3's room_6_09); the door across
// the hallway 1.66 m further on (room_7_08's, its own node's) was passed in the turn while the belief
// was at the first node, beyond the graph reach of the node that has it, and was added to the first
// node as a second opening: the known room was entered again. The door's dead-reckoned position
// finds its node.
TEST(MapBuilder, ADoorPassedInAUTurnBesideAKnownDoorNodeIsThatNodesDoor) {
  for (const double turn_x : {8.5, 8.2, 7.9}) {
    SyntheticFloor floor;
    floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9});
    floor.doors.push_back({{9.0, -1.1}, -0.5 * kPi, 0.9});
    floor.doors.push_back({{7.34, 1.1}, 0.5 * kPi, 1.2});
    floor.doors.push_back({{14.0, 1.1}, 0.5 * kPi, 0.9});
    Drive drive;
    drive.run(&floor, {{1.5, 0}, {20.0, 0}, {turn_x, 0}, {20.0, 0}}, 0.0);
    EXPECT_EQ(drive.count(NodeType::Door), 4u) << "turn at " << turn_x;
    size_t openings = 0;
    for (const auto& [id, n] : drive.map.nodes()) {
      if (n.type == NodeType::Door) openings += n.openings.size();
    }
    EXPECT_EQ(openings, 4u) << "turn at " << turn_x;
  }
}

// Up a stem from the south to a T with hallway x (at x = 10), west along it, and the door across
// the T (north) recorded at the T's junction, as the coordinator records a door it entered there.
void upTheStemAndIntoTheTsDoor(SyntheticFloor* floor, Drive* drive) {
  drive->run(floor, {{10.0, -8.0}, {10.0, 0.0}, {1.5, 0.0}}, 0.5 * kPi);
  int junction = -1;
  for (const auto& [id, n] : drive->map.nodes()) {
    if (n.type == NodeType::Junction && std::abs(n.pose.x - 10.0) < 0.5 && std::abs(n.pose.y) < 0.5) junction = int(id);
  }
  ASSERT_GE(junction, 0) << "no junction at the T";
  NodeOpening door;
  door.bearing = 0.5 * kPi;
  door.width = 0.9;
  door.explored = true;
  ASSERT_TRUE(drive->map.recordOpening(uint32_t(junction), door));
}

// A door beside the robot where it stopped on a new stretch, recorded before the front end passed
// it (the exploration enters a room there), is a node of its own where the robot stands, as passing
// it makes one: recorded at the node the stretch left, the door would be unexplored at the node its
// passing makes later, and the room mapped again. Within the last node's reach it joins that node.
TEST(MapBuilder, ADoorRecordedWhereTheRobotStoppedOnANewStretchIsANodeOfItsOwn) {
  SyntheticFloor floor;
  floor.doors.push_back({{6.0, 1.1}, 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{0.0, 0.0}, {6.15, 0.0}}, 0.0);  // stopped beside the door, not past it
  ASSERT_EQ(drive.builder.mode(), MapBuilder::Mode::Frontier);
  ASSERT_EQ(drive.count(NodeType::Door), 0u) << "the door was passed before the robot stopped";
  const uint32_t start = uint32_t(drive.builder.currentNode());
  NodeOpening door;
  door.bearing = 0.5 * kPi;
  door.width = 0.9;
  door.explored = true;
  const int id = drive.builder.nodeBesideRobot(door, drive.front_end);
  ASSERT_GE(id, 0);
  ASSERT_TRUE(drive.map.recordOpening(uint32_t(id), door));  // as pomdp_topo_node does
  EXPECT_NE(uint32_t(id), start);
  EXPECT_EQ(drive.map.node(uint32_t(id))->type, NodeType::Door);
  EXPECT_NEAR(drive.nodePos(uint32_t(id)).x(), 6.0, 0.08) << "not where the door is";
  drive.run(&floor, {{6.15, 0.0}, {12.0, 0.0}}, 0.0);  // back from the room, on along the hallway
  ASSERT_EQ(drive.count(NodeType::Door), 1u) << "passing the door made it a second node";
  for (const auto& [nid, n] : drive.map.nodes()) {
    for (const NodeOpening& o : n.openings) {
      if (std::abs(normalizeAngle(o.bearing - 0.5 * kPi)) > 0.3) continue;
      EXPECT_EQ(nid, uint32_t(id)) << "the door is an opening of node " << nid;
      EXPECT_TRUE(o.explored) << "the door is unexplored at node " << nid;
    }
  }
  // A door beside the start, within its reach: the start's.
  SyntheticFloor near;
  near.doors.push_back({{0.5, 1.1}, 0.5 * kPi, 0.9});
  Drive at_start;
  at_start.run(&near, {{0.0, 0.0}, {0.5, 0.0}}, 0.0);
  EXPECT_EQ(at_start.builder.nodeBesideRobot(door, at_start.front_end), at_start.builder.currentNode());
  EXPECT_EQ(at_start.map.nodes().size(), 1u);
}

// large_floor: a stem comes up to hall_3 at a T; the robot turns west there (a junction node) and
// enters room_7_14's door across the T, 0.95 m east of the stem's axis; the coordinator records the
// door at the junction. Later, on a new stretch east from the junction, the door is passed again
// 0.95 m from it: it is the junction's door, not a new door node (the room was entered again).
TEST(MapBuilder, ADoorRecordedAtAJunctionIsThatDoorWhenANewStretchFromThereSeesItAgain) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9, 0});
  floor.doors.push_back({{10.95, 1.1}, 0.5 * kPi, 0.9, 0});  // seen only along the crossing hallway
  Drive drive;
  upTheStemAndIntoTheTsDoor(&floor, &drive);
  if (::testing::Test::HasFatalFailure()) return;
  drive.run(&floor, {{1.5, 0.0}, {14.0, 0.0}}, kPi);
  bool left_graph = false;
  for (const auto& e : drive.builder.takeEvents()) left_graph |= e.kind == TopoEvent::Kind::NewStretch;
  ASSERT_TRUE(left_graph) << "no new stretch east of the junction";
  EXPECT_EQ(drive.count(NodeType::Door), 1u) << "the junction's door became a door node of its own";
  EXPECT_EQ(drive.count(NodeType::Junction), 1u);
}

// large_floor (stop 19 runs 6 and 8, stop 20 run 10): room_7_14's door lies 0.8 m east of the T
// where the robot entered it (the coordinator records it at the junction). Coming back west along
// hall_3 long after, the belief lagged: still at the door node 2.5 m east of the T when the door was
// passed, the door was added to that node as a new opening and the room explored again. Here the
// belief lags less (0.8 m): the door, 1.58 m along the edge from the T by the belief, beyond the
// graph reach, was made a new door node on the edge. Where the dead reckoning puts it, it is the
// junction's.
TEST(MapBuilder, AJunctionsDoorPassedWithTheBeliefStillAtTheNodeBeforeIsTheJunctions) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9, 0});
  floor.doors.push_back({{10.8, 1.1}, 0.5 * kPi, 0.9, 0});  // seen only along the crossing hallway
  floor.doors.push_back({{12.8, -1.1}, -0.5 * kPi, 1.1, 0});
  floor.doors.push_back({{17.0, 1.1}, 0.5 * kPi, 1.0, 0});
  Drive drive;
  upTheStemAndIntoTheTsDoor(&floor, &drive);
  if (::testing::Test::HasFatalFailure()) return;
  drive.run(&floor, {{1.5, 0.0}, {20.0, 0.0}, {1.5, 0.0}}, kPi);
  for (const auto& [id, n] : drive.map.nodes()) {
    if (n.type == NodeType::Door) EXPECT_EQ(n.openings.size(), 1u) << "door node " << id << " at x " << n.pose.x;
  }
  EXPECT_EQ(drive.count(NodeType::Door), 3u);
}

// institute's east end of hall_north: two doors facing each other 0.2 m apart, the robot turning
// round just past the first before passing the second. The second, passed on the way back while
// the belief is still at the door node, is added to that node.
TEST(MapBuilder, ADoorPassedOnlyAfterAUTurnAtItsNodeIsAddedToIt) {
  SyntheticFloor floor;
  floor.doors.push_back({{5.0, 1.1}, 0.5 * kPi, 0.9});
  floor.doors.push_back({{18.3, 1.1}, 0.5 * kPi, 0.9});
  floor.doors.push_back({{18.5, -1.1}, -0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {18.6, 0}, {10.0, 0}}, 0.0);
  size_t openings = 0;
  for (const auto& [id, n] : drive.map.nodes()) {
    if (n.type == NodeType::Door) openings += n.openings.size();
  }
  EXPECT_EQ(openings, 3u);
}

// institute's hall_link mouth: a 2.2 m wide branch seen as two openings 1 m apart. One junction.
TEST(MapBuilder, AWideBranchSeenTwiceIsOneJunction) {
  SyntheticFloor floor;
  floor.doors.push_back({{8.0, 1.1}, 0.5 * kPi, 2.1});
  floor.doors.push_back({{9.0, 1.1}, 0.5 * kPi, 2.1});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {15.0, 0}}, 0.0);
  EXPECT_EQ(drive.count(NodeType::Junction), 1u);
}

// A rectangular ring with two doors: two laps counter-clockwise. The first return to the start
// stretch is a loop: closed by merging, without a duplicate of any door.
TEST(MapBuilder, RingLoopIsClosedOnceAndTheSecondLapIsLocalized) {
  SyntheticFloor floor;
  floor.doors.push_back({{12.0, 2.1}, 0.5 * kPi, 1.0});    // on the left of the south stretch
  floor.doors.push_back({{4.0, 9.9}, -0.5 * kPi, 1.0});    // on the left of the north stretch
  Drive drive;
  const std::vector<Eigen::Vector2d> lap = {{15, 1}, {15, 11}, {1, 11}, {1, 1}};
  std::vector<Eigen::Vector2d> path = {{2, 1}};
  for (int k = 0; k < 2; ++k) path.insert(path.end(), lap.begin(), lap.end());
  path.push_back({6, 1});
  drive.run(&floor, path, 0.0);
  EXPECT_EQ(drive.builder.loopsClosed().size(), 1u);
  // The loop closes at the south door: that door, passed during the check, is the old node's own
  // (it once counted as unexpected, and the loop closed only by a hair at the corner's turn).
  std::string closed;
  for (const TopoEvent& e : drive.builder.takeEvents()) {
    if (e.kind == TopoEvent::Kind::LoopClosed) closed = e.text;
  }
  EXPECT_NE(closed.find("0 unexpected openings"), std::string::npos) << closed;
  EXPECT_EQ(drive.count(NodeType::Door), 2u);
  EXPECT_EQ(drive.count(NodeType::Junction), 4u);  // the four turns
  EXPECT_EQ(drive.map.nodeCount(), 7u);            // and the start
  // 96.8 % before merged loops cut the stretch that passes the start node (a duplicate hallway
  // C -> D beside S -> D); with the true graph (C -> S -> D) 93.8 %: the belief crosses S.
  EXPECT_GE(double(drive.right) / std::max<size_t>(1, drive.localized), 0.93)
      << drive.right << " of " << drive.localized;
}

// The same ring with one door (small_loop with a door closed): the four corners look alike and
// only the door tells them apart. Coming back to the first corner is a loop at a hallway end (no
// way straight on to verify against): closed there by position and the turn, not one door later
// with a duplicate of every corner in between.
TEST(MapBuilder, RingWithOneDoorIsClosedAtTheFirstCornerItComesBackTo) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 9.9}, -0.5 * kPi, 1.0});  // on the left of the north stretch
  Drive drive;
  const std::vector<Eigen::Vector2d> lap = {{15, 1}, {15, 11}, {1, 11}, {1, 1}};
  std::vector<Eigen::Vector2d> path = {{8, 1}};
  for (int k = 0; k < 2; ++k) path.insert(path.end(), lap.begin(), lap.end());
  path.push_back({6, 1});
  drive.run(&floor, path, 0.0);
  EXPECT_EQ(drive.builder.loopsClosed().size(), 1u);
  EXPECT_EQ(drive.count(NodeType::Door), 1u);
  EXPECT_EQ(drive.count(NodeType::Junction), 4u);
  EXPECT_EQ(drive.map.nodeCount(), 6u);  // and the start
  EXPECT_GE(double(drive.right) / std::max<size_t>(1, drive.localized), 0.9)
      << drive.right << " of " << drive.localized;
}

// Two hallways joined at both ends (a ring) and by a stem in the middle, as large_floor's ladder:
// coming down the stem to the first hallway's T, the new node's openings (the hallway on both sides)
// are the old node's edges, not its openings. The loop check starts at the T and closes there:
// before, it closed only at the next door (the T zipped into the old one then), and in large_floor
// the door just past the T was entered as a new room while the map was still a new stretch.
TEST(MapBuilder, ComingDownAStemToAKnownHallwayClosesTheLoopAtItsJunction) {
  SyntheticFloor floor;
  floor.doors.push_back({{8.0, 2.1}, 0.5 * kPi, 2.0, 0});  // the stem's mouth, seen from the south hallway
  floor.doors.push_back({{6.9, 1.0}, kPi, 2.0, 1});         // the south hallway, seen from the stem
  floor.doors.push_back({{9.1, 1.0}, 0.0, 2.0, 1});
  floor.doors.push_back({{12.0, 2.1}, 0.5 * kPi, 0.9, 0});  // a door between the T and the corner
  Drive drive;
  drive.run(&floor, {{2, 1}, {15, 1}, {15, 11}, {8, 11}, {8, 1}, {15, 1}, {15, 6}}, 0.0);
  EXPECT_EQ(drive.builder.loopsClosed().size(), 1u);
  TopoEvent closed;
  for (const TopoEvent& e : drive.builder.takeEvents()) {
    if (e.kind == TopoEvent::Kind::LoopClosed) closed = e;
  }
  ASSERT_EQ(closed.kind, TopoEvent::Kind::LoopClosed);
  EXPECT_EQ(closed.other_node, 1) << closed.text;  // the T, the first node after the start
  EXPECT_EQ(drive.count(NodeType::Junction), 4u);  // two T's, two corners
  EXPECT_EQ(drive.count(NodeType::Door), 1u);
  EXPECT_EQ(drive.map.nodeCount(), 6u);  // and the start
  EXPECT_GE(double(drive.right) / std::max<size_t>(1, drive.localized), 0.9) << drive.right << " of " << drive.localized;
}

// The ladder again, with the stem going on south through the first hallway's crossing into an
// unexplored stem: no loop check can start at the crossing (the old node knows nothing south to
// verify against), so it is recorded twice. Back from the south stem, turning east at the copy,
// the robot would leave the known graph there and map the hallway again (large_floor: six rooms of
// hall_1); the copy is merged into the known crossing, which has the way east.
TEST(MapBuilder, ACrossingRecordedTwiceIsMergedWhereTheCopyHasNoWayOn) {
  SyntheticFloor floor;
  floor.doors.push_back({{8.0, 2.1}, 0.5 * kPi, 2.0, 0});   // the crossing's stems, seen from the hallway
  floor.doors.push_back({{8.0, -0.1}, -0.5 * kPi, 2.0, 0});
  floor.doors.push_back({{6.9, 1.0}, kPi, 2.0, 1});          // the hallway, seen from the stems
  floor.doors.push_back({{9.1, 1.0}, 0.0, 2.0, 1});
  Drive drive;
  drive.run(&floor, {{2, 1}, {15, 1}, {15, 11}, {8, 11}, {8, -5}, {8, 1}, {13, 1}}, 0.0);
  bool merged = false, left = false;
  for (const TopoEvent& e : drive.builder.takeEvents()) {
    merged = merged || (e.kind == TopoEvent::Kind::NodesMerged && e.text.find("by the dead reckoning") != std::string::npos);
    left = left || e.kind == TopoEvent::Kind::NewStretch;
  }
  EXPECT_TRUE(merged);
  EXPECT_FALSE(left);
  EXPECT_EQ(drive.count(NodeType::Junction), 4u);  // the crossing, two corners, the north T
  EXPECT_EQ(drive.count(NodeType::HallwayEnd), 1u);
  EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
  EXPECT_GE(double(drive.right) / std::max<size_t>(1, drive.localized), 0.9) << drive.right << " of " << drive.localized;
}

// A door 0.9 m before a hallway's end: the U-turn there makes no node of its own (the door's
// node is within node_radius), so the door's node has no way on. Coming back to the end is no new
// stretch (institute's hall_north: a second node beside the door, and a hallway that never ended).
TEST(MapBuilder, AHallwayEndJustPastADoorIsNoNewStretchWhenComeBackTo) {
  SyntheticFloor floor;
  floor.doors.push_back({{6.0, 1.1}, 0.5 * kPi, 0.9});
  floor.doors.push_back({{19.1, 1.1}, 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {8.0, 0}, {20.0, 0}, {8.0, 0}, {20.0, 0}, {8.0, 0}}, 0.0);
  EXPECT_EQ(drive.count(NodeType::Door), 2u);
  EXPECT_EQ(drive.map.nodeCount(), 3u);  // the start and the two doors
  EXPECT_GE(double(drive.right) / std::max<size_t>(1, drive.localized), 0.9) << drive.right << " of " << drive.localized;
}

// A belief that puts the robot at a hallway's end, heading on, while it is really mid-hallway: the
// map cannot be extended through a wall, so the belief is reset, and no stretch is added.
TEST(MapBuilder, ABeliefPastAHallwayEndIsResetNotANewStretch) {
  SyntheticFloor floor;
  floor.doors.push_back({{6.0, 1.1}, 0.5 * kPi, 0.9});
  floor.doors.push_back({{12.0, -1.1}, -0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {3.0, 0}, {4.0, 0}}, 0.0);  // ends heading east
  ASSERT_EQ(drive.count(NodeType::HallwayEnd), 1u);
  const size_t nodes = drive.map.nodeCount();
  uint32_t end = 0;
  for (const auto& kv : drive.map.nodes()) {
    if (kv.second.type == NodeType::HallwayEnd) end = kv.first;
  }
  ASSERT_TRUE(drive.localizer.resetToNode(end, 0.0));  // at the east end heading east: wrong
  drive.run(&floor, {{4.0, 0}, {9.0, 0}}, 0.0);
  EXPECT_EQ(drive.map.nodeCount(), nodes);
  EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
}

// The start node with start_node_closed (explore.launch: the coordinator records the way behind the
// robot when there is one): a belief that leaves it backwards while the robot is elsewhere is reset,
// like one past a hallway end (institute: after the U-turn at hall_south's east end the belief
// settled on the start, 25 m away, and a copy of the hallway grew from it). Without the parameter
// (replay: nobody knows what is behind the start) that is a new stretch. The position gate and the
// dead-reckoning checks are off here (position_gate 0): they would refuse that belief too, the
// robot being nowhere near the start (ABeliefBeyondTheMapIsOnlyWhereTheRobotIsOnTheWayOutOfItsNode).
TEST(MapBuilder, AClosedStartNodeIsNotLeftWhereItHasNoWay) {
  for (const bool closed : {true, false}) {
    SyntheticFloor floor;
    floor.doors.push_back({{6.0, 1.1}, 0.5 * kPi, 0.9});
    floor.doors.push_back({{12.0, -1.1}, -0.5 * kPi, 0.9});
    MapBuilderParams params;
    params.start_node_closed = closed;
    params.position_gate = 0.0;
    Drive drive(params);
    drive.run(&floor, {{1.5, 0}, {20.0, 0}, {8.0, 0}}, 0.0);  // ends heading west, mid-hallway
    const size_t nodes = drive.map.nodeCount();
    ASSERT_TRUE(drive.localizer.resetToNode(0, kPi));  // at the start heading west: wrong
    drive.run(&floor, {{8.0, 0}, {4.0, 0}}, kPi);
    if (closed) {
      EXPECT_EQ(drive.map.nodeCount(), nodes);
      EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
    } else {
      EXPECT_GT(drive.map.nodeCount() + (drive.builder.mode() == MapBuilder::Mode::Frontier ? 1 : 0), nodes);
    }
  }
}

// Localization only: nothing is ever added to an empty map, and nothing crashes.
TEST(MapBuilder, LocalizationOnlyNeverChangesTheMap) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9});
  Drive drive;
  MapBuilderParams params;
  params.mapping = false;
  MapBuilder builder(&drive.map, &drive.localizer, params);
  std::swap(drive.builder, builder);
  drive.run(&floor, {{1.5, 0}, {10.0, 0}}, 0.0);
  EXPECT_EQ(drive.map.nodeCount(), 0u);
  EXPECT_EQ(drive.localizer.mostLikely(), -1);
}

// Missions freeze the map (pomdp_topo's set_mapping): mapping turned off while a stretch is being
// mapped adds nothing more, doors passed after it included; the robot relocalizes on the map instead.
TEST(MapBuilder, MappingTurnedOffWhileRunningChangesTheMapNoMore) {
  SyntheticFloor floor;
  for (const double x : {4.0, 9.0, 13.0}) floor.doors.push_back({{x, 1.1}, 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {6.0, 0}}, 0.0);
  ASSERT_EQ(drive.count(NodeType::Door), 1u) << "the first door is mapped while mapping is on";
  const size_t nodes = drive.map.nodeCount(), edges = drive.map.edgeCount();
  drive.builder.setMapping(false);
  drive.run(&floor, {{6.0, 0}, {16.0, 0}}, 0.0);
  EXPECT_EQ(drive.map.nodeCount(), nodes);
  EXPECT_EQ(drive.map.edgeCount(), edges);
  EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
  EXPECT_FALSE(drive.builder.params().mapping);
}

// The map frame is the odometry frame at the first scan, whenever that scan comes: a robot that
// drove off before pomdp_topo started (a node slow to start under load) must not shift the map by
// the distance it drove (CI: small_loop's map 0.8 m off the world, the belief "wrong" by as much).
TEST(FrontEnd, TheFirstScanLateInTheRunStartsAtTheOdometryPose) {
  for (bool explicit_reset : {false, true}) {
    FrontEnd fe;
    std::vector<Action> actions;
    std::vector<laser_features::LineSegment> lines;
    std::vector<laser_features::Corner> corners;
    std::vector<laser_features::Opening> openings;
    Pose2D pose{3.0, -2.0, 0.5 * kPi};
    if (explicit_reset) fe.reset(pose, pose.theta, 1e-4);  // as pomdp_topo_node does
    ASSERT_TRUE(fe.process(pose, lines, corners, openings, &actions));
    EXPECT_NEAR(fe.pose().x, 3.0, 1e-9);
    EXPECT_NEAR(fe.pose().y, -2.0, 1e-9);
    EXPECT_NEAR(fe.pose().theta, 0.5 * kPi, 1e-3);
    pose.y += 1.0;  // 1 m north
    ASSERT_TRUE(fe.process(pose, lines, corners, openings, &actions));
    EXPECT_NEAR(fe.pose().x, 3.0, 1e-3);
    EXPECT_NEAR(fe.pose().y, -1.0, 1e-3);
  }
}

TEST(FrontEnd, OneTurnActionPerUTurnAndTravelInResolutionSteps) {
  FrontEnd fe;
  std::vector<Action> actions;
  std::vector<laser_features::LineSegment> lines;
  std::vector<laser_features::Corner> corners;
  std::vector<laser_features::Opening> openings;
  Pose2D pose{0, 0, 0};
  for (int i = 0; i <= 100; ++i) {  // 5 m east
    pose.x = 0.05 * i;
    ASSERT_TRUE(fe.process(pose, lines, corners, openings, &actions));
  }
  double travel = 0.0;
  for (const Action& a : actions) {
    ASSERT_EQ(a.kind, Action::Travel);
    travel += a.distance;
  }
  EXPECT_NEAR(travel, 5.0, 1e-9);
  actions.clear();
  for (int i = 1; i <= 30; ++i) {  // turn on the spot by pi, then stand still
    pose.theta = normalizeAngle(std::min(kPi, 0.12 * i));
    ASSERT_TRUE(fe.process(pose, lines, corners, openings, &actions));
  }
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].kind, Action::Turn);
  EXPECT_EQ(std::abs(actions[0].turn_bins), 2);
  // An odometry jump is refused with a reason.
  std::string error;
  pose.x += 5.0;
  EXPECT_FALSE(fe.process(pose, lines, corners, openings, &actions, &error));
  EXPECT_NE(error.find("jump"), std::string::npos);
  pose.x = std::nan("");
  EXPECT_FALSE(fe.process(pose, lines, corners, openings, &actions, &error));
}


// A wing's walls run 30-60 deg off the building's axes: once the robot follows them, travel is
// measured along them (not their projection on a bin) and the travel frame turns with them; a wing
// past half a bin off the robot's bin is a turn into the nearer bin. Along the axes nothing changes.
TEST(FrontEnd, TravelAndTurnsFollowAWingsWalls) {
  for (const double wing : {0.0, 0.6, 0.98, -0.98}) {
    FrontEnd fe;
    std::vector<Action> actions;
    std::vector<laser_features::Corner> corners;
    std::vector<laser_features::Opening> openings;
    // The robot stands in the wing, facing along it: its walls 1 m to either side (robot frame).
    std::vector<laser_features::LineSegment> lines(2);
    lines[0].start = {-2.0, 1.0};
    lines[0].end = {6.0, 1.0};
    lines[1].start = {-2.0, -1.0};
    lines[1].end = {6.0, -1.0};
    Pose2D pose{0.0, 0.0, 0.0};
    fe.reset(pose, 0.0, 1e-6);
    // Turn on the spot to the wing's heading, slowly, with no walls in view.
    for (int i = 1; i <= 20; ++i) {
      pose.theta = wing * i / 20.0;
      ASSERT_TRUE(fe.process(pose, {}, corners, openings, &actions));
    }
    // Then drive 4 m along the wing, its walls in view.
    for (int i = 1; i <= 80; ++i) {
      pose.x += 0.05 * std::cos(wing);
      pose.y += 0.05 * std::sin(wing);
      ASSERT_TRUE(fe.process(pose, lines, corners, openings, &actions));
    }
    double travel = 0.0;
    int turns = 0;
    for (const Action& a : actions) {
      if (a.kind == Action::Travel) travel += a.distance;
      if (a.kind == Action::Turn) turns += a.turn_bins;
    }
    const int expected_turn = int(std::lround(wing / (0.5 * kPi)));
    EXPECT_EQ(turns, expected_turn) << wing;
    EXPECT_EQ(fe.headingBin(), (expected_turn + 4) % 4) << wing;
    EXPECT_NEAR(fe.travelHeading(), wing, 0.02) << wing;
    EXPECT_NEAR(travel, 4.0, 0.5 + 1e-9) << wing;  // within a cell: sub-cell travel is dropped at a turn
  }
}

// A wing's door faces across the wing: its opening is stored across the bin the wing's hallway is
// followed in (the graph matches openings and turns by bins) with the wing's skew, so its direction
// is the door's own, whatever the wing's angle to the building's axes (30-60 deg).
TEST(MapBuilder, AWingsDoorFacesAcrossTheWingNotAcrossItsBin) {
  for (const double wing : {0.0, 0.6, -0.9}) {
    SyntheticFloor floor;
    floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9});
    floor.doors.push_back({{9.0, -1.1}, -0.5 * kPi, 0.9});
    Drive drive;
    drive.yaw = wing;  // the hallway runs `wing` off the building's axis, which stays at 0
    drive.run(&floor, {{1.5, 0}, {14.0, 0}}, 0.0);
    size_t doors = 0;
    for (const auto& [id, node] : drive.map.nodes()) {
      if (node.type != NodeType::Door) continue;
      for (const NodeOpening& o : node.openings) {
        ++doors;
        const double across = o.direction() - wing;  // in the wing's frame: +-90 deg
        EXPECT_NEAR(std::abs(normalizeAngle(across)), 0.5 * kPi, 0.1) << "wing " << wing << ", node " << id;
        EXPECT_NEAR(std::abs(normalizeAngle(4.0 * o.bearing)), 0.0, 1e-6) << "wing " << wing << ": not on a bin";
      }
    }
    EXPECT_EQ(doors, 2u) << "wing " << wing;
  }
}

// A side opening is the hallway's own (passed, so recorded at a node) within half the widest
// hallway of the travel line (BuildingRules::hallwayReach), whatever the widest hallway is: the
// same reach the coordinator tracks doors and hallway walls within.
TEST(FrontEnd, ASideOpeningIsPassedWithinHalfTheWidestHallway) {
  for (const double hallway_max_width : {4.0, 6.0}) {
    for (const double aside : {1.5, 2.6}) {
      FrontEndParams params;
      params.rules.hallway_max_width = hallway_max_width;
      FrontEnd fe(params);
      std::vector<Action> actions;
      std::vector<laser_features::Corner> corners;
      std::vector<laser_features::LineSegment> lines;
      Pose2D pose{0.0, 0.0, 0.0};
      fe.reset(pose, 0.0, 1e-6);
      size_t passed = 0;
      for (int i = 1; i <= 140; ++i) {  // 7 m east past a door 4 m ahead, `aside` m to the left
        pose.x = 0.05 * i;
        laser_features::Opening o;
        o.center = {4.0 - pose.x, aside};
        o.theta = 0.5 * kPi;
        o.width = 1.0;
        o.confidence = 0.8;
        ASSERT_TRUE(fe.process(pose, lines, corners, {o}, &actions));
        for (const PassedLandmark& p : fe.takePassed()) passed += p.landmark.type == LandmarkType::Opening;
      }
      const bool within = aside <= 0.5 * hallway_max_width;
      EXPECT_EQ(passed, within ? 1u : 0u) << "widest hallway " << hallway_max_width << " m, door " << aside << " m aside";
    }
  }
}

// An odometry jump (kidnapping) while a frontier is mapped: the frontier's way is left as an
// unexplored opening of the node it started from, and the belief is uniform (unconfident, so the
// map does not change until the robot is localized again); on the known graph, just the belief.
TEST(MapBuilder, OdometryJumpLeavesTheFrontierUnexploredAndTheBeliefUniform) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {9.0, 0}}, 0.0);
  ASSERT_EQ(drive.builder.mode(), MapBuilder::Mode::Frontier);
  const uint32_t from = uint32_t(drive.builder.currentNode());
  const size_t nodes = drive.map.nodeCount();
  drive.front_end.clearTracks();  // in the node's order
  drive.builder.odometryJump(drive.front_end);
  EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Localized);
  EXPECT_FALSE(drive.builder.confident());
  EXPECT_EQ(drive.map.nodeCount(), nodes);
  const TopoNode* n = drive.map.node(from);
  ASSERT_NE(n, nullptr);
  bool east_unexplored = false;
  for (const NodeOpening& o : n->openings) east_unexplored |= std::abs(normalizeAngle(o.bearing)) < 0.1 && !o.explored;
  EXPECT_TRUE(east_unexplored) << "the frontier's way (east) is not an unexplored opening of node " << from;
  EXPECT_FALSE(n->explored);
  // Every state equally likely.
  const auto& belief = drive.localizer.belief();
  ASSERT_FALSE(belief.empty());
  for (double p : belief) EXPECT_NEAR(p, 1.0 / double(belief.size()), 1e-9);
}

// A kidnapping on the frontier, back onto the mapped stretch: after relocalizing at the doors the
// robot leaves the known graph where the frontier was left, at the last door, not elsewhere.
TEST(MapBuilder, KidnappedOnTheFrontierRelocalizesAndResumesTheFrontierAtItsNode) {
  SyntheticFloor floor;
  floor.doors.push_back({{4.0, 1.1}, 0.5 * kPi, 0.9});
  floor.doors.push_back({{6.0, -1.1}, -0.5 * kPi, 0.9});
  floor.doors.push_back({{8.0, 1.1}, 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {11.0, 0}}, 0.0);
  ASSERT_EQ(drive.builder.mode(), MapBuilder::Mode::Frontier);
  ASSERT_EQ(drive.count(NodeType::Door), 3u);
  // Moved 8 m back west; odometry goes on from where it was.
  drive.shift = Eigen::Vector2d(3.0 - 11.0, 0.0);
  drive.builder.odometryJump(drive.front_end);
  drive.front_end.clearTracks();
  drive.run(&floor, {{3.0, 0}, {14.0, 0}}, 0.0);
  ASSERT_EQ(drive.relocations.size(), 1u);
  EXPECT_LT((drive.relocations[0].first - drive.relocations[0].second).norm(), 1.0)
      << drive.relocations[0].first.transpose() << " vs " << drive.relocations[0].second.transpose();
  EXPECT_EQ(drive.count(NodeType::Door), 3u);
  EXPECT_EQ(drive.builder.mode(), MapBuilder::Mode::Frontier);
  const TopoNode* last = drive.map.node(uint32_t(drive.builder.currentNode()));
  ASSERT_NE(last, nullptr);
  EXPECT_NEAR(last->pose.x, 8.0, 0.5) << "the frontier resumed from another node";
  EXPECT_NEAR(drive.builder.frontierDistance(), 6.0, 1.0);
  EXPECT_NEAR(drive.front_end.pose().x, 14.0, 1.0) << "the front end's position was not moved to the map's";
}

// An odometry jump on the known graph (the hallway of five doors, mapped and localized): the belief
// becomes uniform, is confident again after some doors, and the position handed to the front end
// once is where the robot truly is.
TEST(MapBuilder, OdometryJumpOnTheKnownGraphRelocalizesWhereTheRobotIs) {
  SyntheticFloor floor;
  const double xs[] = {4.0, 7.5, 9.0, 14.0, 17.0};
  for (int i = 0; i < 5; ++i) floor.doors.push_back({{xs[i], i % 2 ? -1.1 : 1.1}, i % 2 ? -0.5 * kPi : 0.5 * kPi, 0.9});
  Drive drive;
  drive.run(&floor, {{1.5, 0}, {20.0, 0}, {-1.5, 0}, {2.0, 0}}, 0.0);
  ASSERT_TRUE(drive.builder.confident());
  const size_t nodes = drive.map.nodeCount();
  drive.builder.odometryJump(drive.front_end);
  EXPECT_FALSE(drive.builder.confident());
  drive.run(&floor, {{2.0, 0}, {19.0, 0}}, 0.0);
  ASSERT_EQ(drive.relocations.size(), 1u);
  EXPECT_LT((drive.relocations[0].first - drive.relocations[0].second).norm(), 1.0)
      << drive.relocations[0].first.transpose() << " vs " << drive.relocations[0].second.transpose();
  EXPECT_TRUE(drive.builder.confident());
  EXPECT_EQ(drive.map.nodeCount(), nodes) << "the map changed while relocalizing";
}

}  // namespace
}  // namespace pomdp_topo
