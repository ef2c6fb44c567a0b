// The hallway's navigation on its own, on a straight hallway of wall segments: setting off along it,
// following its mid-line, a U-turn at its dead end, the stop at a door passed on a new stretch and
// the opening it is entered as (or passed, when pomdp_topo checks a loop), the doors beside a
// hallway's end, the ways not taken at a turn, and what the known map says: no unexplored opening
// left, a mission's door with no route.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "exploration/coordinator_params.h"
#include "exploration/hallway_navigator.h"
#include "segment_world.h"

using exploration::Decision;
using exploration::EntryOpening;
using exploration::GraphEdge;
using exploration::GraphNode;
using exploration::GraphOpening;
using exploration::HallwayContext;
using exploration::HallwayNavigator;
using exploration::HallwayStep;
using exploration::Perception;
using exploration::PlaceDoor;
using exploration::TopoGraph;
using exploration::TopoMode;
using exploration::TopoView;
using laser_features::kPi;
using laser_features::Pose2D;

namespace {

// The scan's points (360 beams, 1 deg apart, to 15 m) and the walls' lines (all of them) of `w` in
// the frame of a robot at `robot`.
Perception scanOf(const exploration::test::SegmentWorld& w, const Pose2D& robot, double stamp) {
  Perception p;
  p.stamp = stamp;
  p.odom = robot;
  const Pose2D to_robot = laser_features::inverse(robot);
  const Eigen::Vector2d at(robot.x, robot.y);
  for (int k = 0; k < 360; ++k) {
    const Eigen::Vector2d u = laser_features::unitVector(robot.theta + k * kPi / 180.0);
    const double r = w.raycast(at, u);
    if (r < 15.0) p.points.push_back(laser_features::transformPoint(to_robot, at + r * u));
  }
  for (const exploration::test::Segment& s : w.walls) {
    laser_features::LineSegment l;
    l.start = laser_features::transformPoint(to_robot, s.a);
    l.end = laser_features::transformPoint(to_robot, s.b);
    p.lines.push_back(l);
  }
  return p;
}

// A 0.9 m door centred at x = `x` in the wall y = `side` (+1: the left wall of a hallway along +x, -1:
// the right one), as laser_features reports it to a robot at `robot`.
laser_features::Opening sideDoor(const Pose2D& robot, double x, double side) {
  const Pose2D to_robot = laser_features::inverse(robot);
  laser_features::Opening o;
  o.left = laser_features::transformPoint(to_robot, Eigen::Vector2d(x - side * 0.45, side));
  o.right = laser_features::transformPoint(to_robot, Eigen::Vector2d(x + side * 0.45, side));
  o.center = 0.5 * (o.left + o.right);
  o.theta = laser_features::normalizeAngle(side * 0.5 * kPi - robot.theta);
  o.width = 0.9;
  o.kind = laser_features::OpeningKind::kDoor;
  o.confidence = 0.9;
  return o;
}

// A hallway along +x, 2 m wide (y in [-1, 1]), from x = -10 to its dead end at x = 20; with
// `door`, a 0.9 m door in its left wall at x = `door_x` (5 m) to a room 4 m deep.
struct Hallway : exploration::test::SegmentWorld {
  bool door = false;
  double door_x = 5.0;

  explicit Hallway(bool with_door, double at_x = 5.0) : door(with_door), door_x(at_x) {
    wall(-10.0, -1.0, 20.0, -1.0);
    wall(-10.0, -1.0, -10.0, 1.0);
    wall(20.0, -1.0, 20.0, 1.0);
    if (!door) {
      wall(-10.0, 1.0, 20.0, 1.0);
      return;
    }
    wall(-10.0, 1.0, door_x - 0.45, 1.0);
    wall(door_x + 0.45, 1.0, 20.0, 1.0);
    wall(door_x - 2.0, 1.0, door_x - 2.0, 5.0);
    wall(door_x - 2.0, 5.0, std::min(20.0, door_x + 2.0), 5.0);
    wall(std::min(20.0, door_x + 2.0), 5.0, std::min(20.0, door_x + 2.0), 1.0);
  }

  // The scan's points and the walls' lines (all of them) in the robot frame; the door as
  // laser_features reports it, from within 6 m.
  Perception perceive(const Pose2D& robot, double stamp) const {
    Perception p = scanOf(*this, robot, stamp);
    if (door && std::abs(robot.x - door_x) < 6.0) p.openings.push_back(sideDoor(robot, door_x, 1.0));
    return p;
  }
};

TopoView belief(TopoMode mode) {
  TopoView v;
  v.valid = true;
  v.mode = mode;
  v.confident = true;
  v.heading_valid = true;
  return v;
}

// The navigator is not copyable (its door stops read its follower and route): held by pointer.
std::unique_ptr<HallwayNavigator> navigator() {
  const exploration::CoordinatorParams p;
  auto nav = std::make_unique<HallwayNavigator>(p.follow, p.hallway, p.rules, p.room.planner, p.doors, p.route,
                                                p.branch_record_distance);
  nav->setHeadingBins({0.0, 4});
  return nav;
}

// An ideal robot, one 0.1 s tick: 0.05 m towards the goal, or at it 0.1 rad towards its heading.
void step(const Decision& d, Pose2D* robot) {
  if (d.stop || !d.has_goal) return;
  const Eigen::Vector2d to(d.x - robot->x, d.y - robot->y);
  if (to.norm() > 0.01) {
    const Eigen::Vector2d s = to.norm() > 0.05 ? Eigen::Vector2d(0.05 * to.normalized()) : to;
    robot->x += s.x();
    robot->y += s.y();
  } else if (d.theta) {
    robot->theta += std::max(-0.1, std::min(0.1, laser_features::normalizeAngle(*d.theta - robot->theta)));
  }
}

struct Followed {
  HallwayStep step;
  Decision last;  // the decision of the last tick
  double travel = 0.0;  // m
  int ticks = 0;
};

// Follows the hallway of `h` (a new stretch, no map yet) from `robot` until the tick that is not on
// along the hallway, or for `max_ticks`; `mode`: pomdp_topo's.
template <typename World>
Followed followUntilChange(HallwayNavigator* nav, const World& h, Pose2D* robot, int max_ticks,
                           TopoMode mode = TopoMode::Frontier) {
  const TopoGraph none;
  Followed run;
  for (; run.ticks < max_ticks; ++run.ticks) {
    Decision d;
    const Pose2D before = *robot;
    const HallwayContext at{none, run.travel, nullptr};
    run.step = nav->follow(h.perceive(*robot, 0.1 * run.ticks), belief(mode), false, at, &d);
    run.last = d;
    if (run.step.kind != HallwayStep::Following) break;
    step(d, robot);
    run.travel += std::hypot(robot->x - before.x, robot->y - before.y);
  }
  return run;
}

// Turns on the spot (HallwayNavigator::turn) for at most 100 ticks; true once turned.
template <typename World>
bool turnOnTheSpot(HallwayNavigator* nav, const World& h, Pose2D* robot, double travel) {
  for (int i = 0; i < 100; ++i) {
    Decision d;
    const bool turned = nav->turn(h.perceive(*robot, 0.1 * i), false, false, travel, &d);
    step(d, robot);
    if (turned) return true;
  }
  return false;
}

// From x = 12 m along the hallway of `w` to its dead end at x = 20, and round on the spot there: the
// travel (m), or -1 if the robot did not turn round at the end (the failure reported).
template <typename World>
double turnRoundAtTheEnd(HallwayNavigator* nav, const World& w, Pose2D* robot) {
  *robot = Pose2D{12.0, 0.0, 0.0};
  const Followed run = followUntilChange(nav, w, robot, 400);
  EXPECT_EQ(run.step.kind, HallwayStep::Turning) << run.step.text;
  EXPECT_EQ(run.step.text.rfind("hallway end: turning round", 0), 0u) << run.step.text;
  if (run.step.kind != HallwayStep::Turning || !turnOnTheSpot(nav, w, robot, run.travel)) return -1.0;
  return run.travel;
}

}  // namespace

// Mid-hallway on a new stretch the robot sets off the way it faces and the way behind it is an
// unexplored opening; it keeps to the hallway's mid-line; across the hallway it turns first.
TEST(HallwayNavigator, SetsOffAlongTheHallwayAndFollowsItsMidLine) {
  const Hallway h(false);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{0.0, 0.3, 0.1};
  nav.faceRobotsBin(h.perceive(robot, 0.0), belief(TopoMode::Frontier));
  Decision start;
  EXPECT_FALSE(nav.setOff(h.perceive(robot, 0.0), belief(TopoMode::Frontier), &start));
  ASSERT_EQ(start.requests.size(), 1u);
  EXPECT_EQ(start.requests[0].kind, exploration::Request::RecordOpening);
  EXPECT_NEAR(std::abs(start.requests[0].bearing), kPi, 1e-9);

  const Followed run = followUntilChange(&nav, h, &robot, 100);
  EXPECT_EQ(run.step.kind, HallwayStep::Following);
  EXPECT_EQ(run.step.text, "following a new hallway");
  EXPECT_TRUE(run.last.has_goal);
  EXPECT_GT(run.last.x, robot.x + 1.0);
  EXPECT_NEAR(run.last.y, 0.0, 0.05);
  EXPECT_NEAR(robot.y, 0.0, 0.1);
  EXPECT_EQ(followUntilChange(&nav, h, &robot, 1, TopoMode::LoopCheck).step.text,
            "following the hallway until the belief is confident");

  const auto across_owner = navigator();
  HallwayNavigator& across = *across_owner;
  Pose2D facing_wall{0.0, 0.0, 0.5 * kPi};
  across.faceRobotsBin(h.perceive(facing_wall, 0.0), belief(TopoMode::Frontier));
  Decision turn;
  EXPECT_TRUE(across.setOff(h.perceive(facing_wall, 0.0), belief(TopoMode::Frontier), &turn));
}

// Starting at a crossing, the ways to both sides are unexplored openings of the start node as well as
// the way behind; starting beside a door, the door is none (a door never opens a side).
TEST(HallwayNavigator, TheWaysAtTheStartAreTheOpeningsOfTheStartNode) {
  Hallway crossing(false);
  crossing.walls.clear();
  crossing.wall(-10.0, 1.0, -1.0, 1.0);
  crossing.wall(-1.0, 1.0, -1.0, 10.0);
  crossing.wall(1.0, 1.0, 20.0, 1.0);
  crossing.wall(1.0, 1.0, 1.0, 10.0);
  crossing.wall(-10.0, -1.0, -1.0, -1.0);
  crossing.wall(-1.0, -1.0, -1.0, -10.0);
  crossing.wall(1.0, -1.0, 20.0, -1.0);
  crossing.wall(1.0, -1.0, 1.0, -10.0);
  crossing.wall(-10.0, -1.0, -10.0, 1.0);
  crossing.wall(20.0, -1.0, 20.0, 1.0);
  crossing.wall(-1.0, 10.0, 1.0, 10.0);
  crossing.wall(-1.0, -10.0, 1.0, -10.0);
  // The bearings of the openings recorded, sorted (pi for -pi).
  const auto recorded = [](const Hallway& h, const Pose2D& robot, bool* turns) {
    const auto nav_owner = navigator();
    HallwayNavigator& nav = *nav_owner;
    nav.faceRobotsBin(h.perceive(robot, 0.0), belief(TopoMode::Frontier));
    Decision d;
    *turns = nav.setOff(h.perceive(robot, 0.0), belief(TopoMode::Frontier), &d);
    std::vector<double> b;
    for (const exploration::Request& r : d.requests) {
      EXPECT_EQ(r.kind, exploration::Request::RecordOpening);
      b.push_back(std::abs(r.bearing) > kPi - 1e-6 ? kPi : r.bearing);
    }
    std::sort(b.begin(), b.end());
    return b;
  };
  // In the crossing: three of the four ways (the fourth is set off along), none twice.
  bool turns = false;
  const std::vector<double> at_crossing = recorded(crossing, Pose2D{0.0, 0.0, 0.0}, &turns);
  ASSERT_EQ(at_crossing.size(), 3u);
  for (size_t k = 0; k < at_crossing.size(); ++k) {
    const double quarter = at_crossing[k] / (0.5 * kPi);
    EXPECT_NEAR(quarter, std::round(quarter), 1e-6);
    if (k > 0) EXPECT_GT(at_crossing[k] - at_crossing[k - 1], 1.0);
  }
  // Beside a door, mid-hallway: along the hallway the robot faces; the way behind only.
  const std::vector<double> at_door = recorded(Hallway(true), Pose2D{5.0, 0.0, 0.0}, &turns);
  EXPECT_FALSE(turns);
  ASSERT_EQ(at_door.size(), 1u);
  EXPECT_NEAR(at_door[0], kPi, 1e-6);
}

// At the dead end the robot turns round on the spot, and then follows the hallway back.
TEST(HallwayNavigator, TurnsRoundAtADeadEndAndFollowsTheHallwayBack) {
  const Hallway h(false);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{14.0, 0.0, 0.0};
  const Followed run = followUntilChange(&nav, h, &robot, 400);
  ASSERT_EQ(run.step.kind, HallwayStep::Turning) << run.step.text;
  EXPECT_EQ(run.step.text.rfind("hallway end: turning round", 0), 0u) << run.step.text;
  EXPECT_EQ(nav.stats().u_turns, 1);
  EXPECT_GT(robot.x, 17.0);
  ASSERT_TRUE(run.last.theta);
  EXPECT_NEAR(std::abs(*run.last.theta), kPi, 1e-6);

  bool turned = false;
  for (int i = 0; i < 100 && !turned; ++i) {
    Decision d;
    turned = nav.turn(h.perceive(robot, 0.1 * i), false, false, run.travel, &d);
    EXPECT_NEAR(d.x, robot.x, 1e-12);  // on the spot
    step(d, &robot);
  }
  ASSERT_TRUE(turned);
  EXPECT_EQ(nav.direction().bin, 2);
  const TopoGraph none;
  Decision back;
  nav.follow(h.perceive(robot, 20.0), belief(TopoMode::Frontier), false, HallwayContext{none, run.travel, nullptr}, &back);
  ASSERT_TRUE(back.has_goal);
  EXPECT_LT(back.x, robot.x - 1.0);
}

// Where the robot turned round and finds the way back closed too (a pocket both ways: a stub the
// route turned it into, a lane blocked both ways), it turns to the freer side instead of round again:
// U-turns on the spot would go on for ever.
TEST(HallwayNavigator, TurnedRoundIntoAClosedWayItTurnsToTheFreerSide) {
  Hallway pocket(false);
  pocket.walls.clear();  // 2.6 m by 1.6 m, closed: the robot 0.8 m from its west wall, 1.8 m from its east one
  pocket.wall(0.0, -0.8, 2.6, -0.8);
  pocket.wall(2.6, -0.8, 2.6, 0.8);
  pocket.wall(2.6, 0.8, 0.0, 0.8);
  pocket.wall(0.0, 0.8, 0.0, -0.8);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{0.8, 0.0, 0.5 * kPi};
  nav.faceRobotsBin(pocket.perceive(robot, 0.0), belief(TopoMode::Frontier));
  const Followed first = followUntilChange(&nav, pocket, &robot, 5);
  ASSERT_EQ(first.step.kind, HallwayStep::Turning) << first.step.text;
  EXPECT_EQ(first.step.text.rfind("hallway end: turning round", 0), 0u) << first.step.text;
  ASSERT_TRUE(turnOnTheSpot(&nav, pocket, &robot, 0.0));
  const Followed again = followUntilChange(&nav, pocket, &robot, 5);
  ASSERT_EQ(again.step.kind, HallwayStep::Turning) << again.step.text;
  EXPECT_EQ(again.step.text.rfind("hallway end where the robot turned round: turning to the freer side, left", 0), 0u)
      << again.step.text;
  ASSERT_TRUE(again.last.theta);
  EXPECT_NEAR(*again.last.theta, 0.0, 1e-6);  // east: the freer side
  EXPECT_EQ(nav.stats().u_turns, 1);
}

// A door passed on a new stretch is stopped for and entered as a new opening; while pomdp_topo
// checks whether the door's node is a known one, it is passed.
TEST(HallwayNavigator, StopsForADoorPassedOnANewStretch) {
  const Hallway h(true);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{0.0, 0.0, 0.0};
  const Followed run = followUntilChange(&nav, h, &robot, 400);
  ASSERT_EQ(run.step.kind, HallwayStep::StopForDoor) << run.step.text;
  EXPECT_TRUE(run.last.stop);
  EXPECT_EQ(run.step.text.rfind("stopping at a door to enter the room (0.90 m wide", 0), 0u) << run.step.text;
  EXPECT_NEAR(nav.door().centre_odom.x(), 5.0, 0.1);
  EXPECT_NEAR(nav.door().centre_odom.y(), 1.0, 0.1);
  EXPECT_NEAR(nav.door().into_odom, 0.5 * kPi, 0.05);
  EXPECT_GT(robot.x, 5.0);  // passed

  const TopoGraph none;
  const HallwayContext at{none, run.travel, nullptr};
  std::string why;
  EXPECT_FALSE(nav.enterAfterStop(belief(TopoMode::LoopCheck), at, &why));
  EXPECT_EQ(why, "door passed: pomdp_topo checks whether it is a known one");
  EXPECT_EQ(nav.stats().doors_passed, 1);
  const std::optional<EntryOpening> entry = nav.enterAfterStop(belief(TopoMode::Frontier), at, &why);
  ASSERT_TRUE(entry);
  EXPECT_EQ(entry->node, -1);  // a new door, at pomdp_topo's current node
  EXPECT_NEAR(entry->bearing, 0.5 * kPi, 0.05);
}

// A door in a side wall between the robot and the hallway's end wall is never passed: the robot turns
// there. It is entered once the robot has turned (the map builder has the turn's node then), not
// forgotten with the hallway left.
TEST(HallwayNavigator, ADoorBesideTheHallwaysEndIsEnteredOnceTurned) {
  const Hallway h(true, 19.2);  // the door's centre 0.8 m from the end wall: ahead where the robot turns
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot;
  const double travel = turnRoundAtTheEnd(&nav, h, &robot);
  ASSERT_GE(travel, 0.0);
  EXPECT_LT(robot.x, 19.2 - 0.3);  // the door not passed
  const Followed after = followUntilChange(&nav, h, &robot, 5);
  ASSERT_EQ(after.step.kind, HallwayStep::StopForDoor) << after.step.text;
  EXPECT_EQ(after.step.text.rfind("stopping at a door beside the hallway's end turned at", 0), 0u) << after.step.text;
  EXPECT_NEAR(nav.door().centre_odom.x(), 19.2, 0.1);
  EXPECT_NEAR(nav.door().into_odom, 0.5 * kPi, 0.05);
  const TopoGraph none;
  std::string why;
  const std::optional<EntryOpening> entry =
      nav.enterAfterStop(belief(TopoMode::Frontier), HallwayContext{none, after.travel + travel, nullptr}, &why);
  ASSERT_TRUE(entry) << why;
  EXPECT_NEAR(entry->bearing, 0.5 * kPi, 0.05);
}

// Turning round, a door within tracks.enter_lag of abeam lies on the robot's way back: it is passed and
// entered there as any door, not taken at the end (which would change nothing but the moment).
TEST(HallwayNavigator, TurningRoundADoorAbeamIsPassedOnTheWayBack) {
  const Hallway h(true, 18.85);  // the robot turns round at x = 18.7: the door 0.15 m ahead
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot;
  ASSERT_GE(turnRoundAtTheEnd(&nav, h, &robot), 0.0);
  const double x_turned = robot.x;
  const Followed after = followUntilChange(&nav, h, &robot, 100);
  ASSERT_EQ(after.step.kind, HallwayStep::StopForDoor) << after.step.text;
  EXPECT_EQ(after.step.text.rfind("stopping at a door to enter the room", 0), 0u) << after.step.text;
  EXPECT_LT(robot.x, x_turned - 0.1);  // driven on to pass it
  EXPECT_NEAR(nav.door().centre_odom.x(), 18.85, 0.1);
}

// At an L corner the door in the outer wall (beside the robot where it turns, on the side that stays
// closed) ends up behind the robot once it has turned: it is entered then, not forgotten.
TEST(HallwayNavigator, ADoorInACornersOuterWallIsEnteredOnceTurned) {
  Hallway corner(true, 9.0);  // the door (x in [8.55, 9.45]) in the left wall of the corner's square
  corner.walls.clear();       // a 2 m hallway along +x turning right at x = 10 into one along -y (x in [8, 10])
  corner.wall(-10.0, -1.0, -10.0, 1.0);
  corner.wall(-10.0, 1.0, 8.55, 1.0);
  corner.wall(9.45, 1.0, 10.0, 1.0);
  corner.wall(6.0, 1.0, 6.0, 5.0);  // the room behind the door
  corner.wall(6.0, 5.0, 10.0, 5.0);
  corner.wall(10.0, 5.0, 10.0, -12.0);
  corner.wall(-10.0, -1.0, 8.0, -1.0);
  corner.wall(8.0, -1.0, 8.0, -12.0);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{2.0, 0.0, 0.0};
  const Followed run = followUntilChange(&nav, corner, &robot, 400);
  ASSERT_EQ(run.step.kind, HallwayStep::Turning) << run.step.text;
  EXPECT_EQ(run.step.text.rfind("hallway end: turning right", 0), 0u) << run.step.text;
  EXPECT_NE(run.step.text.find("left closed, right open"), std::string::npos) << run.step.text;
  ASSERT_TRUE(turnOnTheSpot(&nav, corner, &robot, run.travel));
  const Followed after = followUntilChange(&nav, corner, &robot, 5);
  ASSERT_EQ(after.step.kind, HallwayStep::StopForDoor) << after.step.text;
  EXPECT_NEAR(nav.door().centre_odom.x(), 9.0, 0.1);
  EXPECT_NEAR(nav.door().centre_odom.y(), 1.0, 0.1);
  EXPECT_NEAR(nav.door().into_odom, 0.5 * kPi, 0.05);
}

namespace {

// The dead end of `Hallway` (x = 20) with a 0.9 m door in each side wall near it: the left one's
// centre at x = `left_x`, the right one's at `right_x`, each to a room 4 m deep; laser_features
// reports each from within 6 m.
struct DeadEndWithTwoDoors : exploration::test::SegmentWorld {
  double left_x, right_x;

  DeadEndWithTwoDoors(double left, double right) : left_x(left), right_x(right) {
    wall(-10.0, -1.0, -10.0, 1.0);
    wall(20.0, -5.0, 20.0, 5.0);
    wall(-10.0, 1.0, left_x - 0.45, 1.0);
    wall(left_x + 0.45, 1.0, 20.0, 1.0);
    wall(left_x - 2.0, 1.0, left_x - 2.0, 5.0);
    wall(left_x - 2.0, 5.0, 20.0, 5.0);
    wall(-10.0, -1.0, right_x - 0.45, -1.0);
    wall(right_x + 0.45, -1.0, 20.0, -1.0);
    wall(right_x - 2.0, -1.0, right_x - 2.0, -5.0);
    wall(right_x - 2.0, -5.0, 20.0, -5.0);
  }

  Perception perceive(const Pose2D& robot, double stamp) const {
    Perception p = scanOf(*this, robot, stamp);
    for (const double side : {1.0, -1.0}) {
      const double x = side > 0.0 ? left_x : right_x;
      if (std::abs(robot.x - x) < 6.0) p.openings.push_back(sideDoor(robot, x, side));
    }
    return p;
  }
};

}  // namespace

// The robot leaves a dead end the way it came and passes none of the doors beside it on the way: each
// is entered from the end. The first after the U-turn; it is new, as a door passed on the new stretch
// would be, though by then the belief is localized on the end's node (the stretch is known once the
// robot turns back along it) and no opening of that node has the door. Back from that room, the door
// on the other side (abeam where the robot turned, so not taken at the turn) is offered next; the
// door just left is not offered again.
TEST(HallwayNavigator, EveryDoorBesideADeadEndIsEnteredFromItAsANewDoor) {
  const DeadEndWithTwoDoors end(19.2, 18.85);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot;
  const double travel = turnRoundAtTheEnd(&nav, end, &robot);
  ASSERT_GE(travel, 0.0);
  const Followed after = followUntilChange(&nav, end, &robot, 5);
  ASSERT_EQ(after.step.kind, HallwayStep::StopForDoor) << after.step.text;
  EXPECT_NEAR(nav.door().centre_odom.x(), 19.2, 0.1);
  EXPECT_NEAR(nav.door().centre_odom.y(), 1.0, 0.1);
  const TopoGraph none;
  std::string why;
  const std::optional<EntryOpening> entry =
      nav.enterAfterStop(belief(TopoMode::Localized), HallwayContext{none, travel + after.travel, nullptr}, &why);
  ASSERT_TRUE(entry) << why;
  EXPECT_EQ(entry->node, -1);
  EXPECT_NEAR(entry->bearing, 0.5 * kPi, 0.05);

  const exploration::DoorTrack left_by = nav.door();
  nav.backFromRoom(nav.direction(), left_by, {}, travel + after.travel + 12.0, Pose2D{});  // no drift in the room
  const Followed back = followUntilChange(&nav, end, &robot, 5);
  ASSERT_EQ(back.step.kind, HallwayStep::StopForDoor) << back.step.text;
  EXPECT_EQ(back.step.text.rfind("stopping at a door beside the hallway's end turned at", 0), 0u) << back.step.text;
  EXPECT_NEAR(nav.door().centre_odom.x(), 18.85, 0.1);
  EXPECT_NEAR(nav.door().centre_odom.y(), -1.0, 0.1);
}

// On the known map: with no unexplored opening left the exploration is complete; a mission's door
// the graph does not reach has no route.
TEST(HallwayNavigator, SaysWhenNoOpeningIsLeftAndWhenAMissionsDoorHasNoRoute) {
  const Hallway h(false);
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  g.addNode(GraphNode{1, 2, 10.0, 0.0, {}});
  g.addNode(GraphNode{7, 0, 30.0, 0.0, {GraphOpening{0.5 * kPi, 0.9, true, 3, {0.0, 0.0, 0.0}}}});
  g.addEdge(GraphEdge{0, 0, 1, 0.0, 10.0});
  TopoView on_edge = belief(TopoMode::Localized);
  on_edge.position.valid = true;
  on_edge.position.id = 0;
  on_edge.position.offset = 2.0;
  const Pose2D robot{2.0, 0.0, 0.0};

  const auto exploring_owner = navigator();
  HallwayNavigator& exploring = *exploring_owner;
  Decision d;
  EXPECT_EQ(exploring.follow(h.perceive(robot, 0.0), on_edge, false, HallwayContext{g, 0.0, nullptr}, &d).kind,
            HallwayStep::Complete);

  const auto mission_owner = navigator();
  HallwayNavigator& mission = *mission_owner;
  const PlaceDoor door = *g.placeDoor(3);
  const HallwayStep step = mission.follow(h.perceive(robot, 0.0), on_edge, false, HallwayContext{g, 0.0, &door}, &d);
  EXPECT_EQ(step.kind, HallwayStep::NoRoute);
  EXPECT_FALSE(step.route.found);
}

// A mission's door beside a dead end is entered from the end, as exploration's is: the robot goes
// no farther than the end and passes no door beside it on its way back. On the known map (a
// localized belief on the hallway's edge, the door at its end node), the robot drives to the end,
// turns round there and stops for the mission's door at once.
TEST(HallwayNavigator, AMissionsDoorBesideADeadEndIsEnteredFromTheEnd) {
  const Hallway h(true, 19.2);
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  g.addNode(GraphNode{1, 0, 18.7, 0.0, {GraphOpening{0.5 * kPi, 0.9, true, 3, {0.0, 0.0, 0.0}}}});
  g.addEdge(GraphEdge{0, 0, 1, 0.0, 18.7});
  const PlaceDoor door = *g.placeDoor(3);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{12.0, 0.0, 0.0};
  double travel = 0.0;
  bool turned_round = false;
  HallwayStep last;
  for (int tick = 0; tick < 800; ++tick) {
    TopoView on_edge = belief(TopoMode::Localized);
    on_edge.position.valid = true;
    on_edge.position.id = 0;
    on_edge.position.offset = std::min(robot.x, 18.7);
    on_edge.position.heading = robot.theta;
    Decision d;
    const Pose2D before = robot;
    last = nav.follow(h.perceive(robot, 0.1 * tick), on_edge, false, HallwayContext{g, travel, &door}, &d);
    if (last.kind == HallwayStep::Turning) {
      turned_round = turned_round || last.text.rfind("hallway end: turning round", 0) == 0;
      ASSERT_TRUE(turnOnTheSpot(&nav, h, &robot, travel)) << last.text;
      continue;
    }
    if (last.kind != HallwayStep::Following) break;
    step(d, &robot);
    travel += std::hypot(robot.x - before.x, robot.y - before.y);
  }
  EXPECT_TRUE(turned_round);
  ASSERT_EQ(last.kind, HallwayStep::StopForDoor) << last.text;
  EXPECT_EQ(last.text.rfind("stopping at a door beside the hallway's end turned at", 0), 0u) << last.text;
  EXPECT_NEAR(nav.door().centre_odom.x(), 19.2, 0.1);
}

namespace {

// A 2 m hallway along +x (y in [-1, 1]) whose end at x = 10 turns right into a hallway along -y
// (x in [8, 10]), with a wing leaving at `angle` (rad) from the corner: its right wall starts at
// (10, 1), where the end wall meets the left wall.
Hallway cornerWithWing(double angle) {
  Hallway h(false);
  h.walls.clear();
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle)), n(-d.y(), d.x());
  const Eigen::Vector2d right0(10.0, 1.0), left0 = right0 + 2.0 * n;  // the wing's walls' first points
  h.wall(-10.0, -1.0, -10.0, 1.0);
  h.wall(-10.0, 1.0, left0.x(), 1.0);
  h.wall(left0.x(), 1.0, left0.x(), left0.y());
  h.wall(left0.x(), left0.y(), left0.x() + 9.0 * d.x(), left0.y() + 9.0 * d.y());
  h.wall(right0.x(), right0.y(), right0.x() + 9.0 * d.x(), right0.y() + 9.0 * d.y());
  h.wall(10.0, 1.0, 10.0, -12.0);
  h.wall(-10.0, -1.0, 8.0, -1.0);
  h.wall(8.0, -1.0, 8.0, -12.0);
  return h;
}

}  // namespace

namespace {

// cornerWithWing(angle) whose wing's mouth (the gap in the left wall, x in [left0.x, 10]) laser_features
// reports as a door: as wide as one, free space behind it as behind a room's door.
struct WingMouthSeen {
  Hallway h;
  double angle;

  Perception perceive(const Pose2D& robot, double stamp) const {
    Perception p = h.perceive(robot, stamp);
    const double from = 10.0 - 2.0 * std::sin(angle);  // left0.x
    const Pose2D to_robot = laser_features::inverse(robot);
    laser_features::Opening o;
    o.left = laser_features::transformPoint(to_robot, Eigen::Vector2d(from, 1.0));
    o.right = laser_features::transformPoint(to_robot, Eigen::Vector2d(10.0, 1.0));
    o.center = 0.5 * (o.left + o.right);
    o.theta = laser_features::normalizeAngle(0.5 * kPi - robot.theta);
    o.width = 10.0 - from;
    o.kind = laser_features::OpeningKind::kDoor;
    o.confidence = 0.9;
    o.room_behind = true;
    if (std::abs(robot.x - 10.0) < 6.0) p.openings.push_back(o);
    return p;
  }
};

}  // namespace

// A wing's mouth beside a hallway's end is as wide as a double door, with free space behind it as a
// room's door has: where a hallway at an angle leaves the end through it, it is that hallway's mouth
// (recorded as a way not taken), not a door to enter once turned.
TEST(HallwayNavigator, AWingsMouthBesideTheEndIsNoDoorToEnter) {
  for (const double angle : {0.6, 0.7, 0.8}) {
    const WingMouthSeen w{cornerWithWing(angle), angle};
    const auto nav_owner = navigator();
    HallwayNavigator& nav = *nav_owner;
    Pose2D robot{0.0, 0.0, 0.0};
    const Followed run = followUntilChange(&nav, w, &robot, 400);
    ASSERT_EQ(run.step.kind, HallwayStep::Turning) << run.step.text;
    EXPECT_EQ(run.step.text.rfind("hallway end: turning right (free ahead", 0), 0u) << run.step.text;
    ASSERT_TRUE(turnOnTheSpot(&nav, w, &robot, run.travel));
    const Followed after = followUntilChange(&nav, w, &robot, 20);
    EXPECT_NE(after.step.kind, HallwayStep::StopForDoor) << angle << ": " << after.step.text;
  }
}

// At a hallway's end the wings leaving it at an angle are ways out as the sides open along the axes
// are: on a new stretch those not taken are recorded as the turn's node's unexplored openings, in
// the bin pomdp_topo gives the branch once the robot turns into it.
TEST(HallwayNavigator, AWingNotTakenAtAHallwaysEndIsAnUnexploredOpening) {
  for (const double angle : {0.6, 0.7, 0.8}) {  // 34-46 deg: the left side stays closed
    const Hallway h = cornerWithWing(angle);
    const auto nav_owner = navigator();
    HallwayNavigator& nav = *nav_owner;
    Pose2D robot{0.0, 0.0, 0.0};
    Followed run = followUntilChange(&nav, h, &robot, 400);
    ASSERT_EQ(run.step.kind, HallwayStep::Turning) << run.step.text;
    EXPECT_EQ(run.step.text.rfind("hallway end: turning right (free ahead", 0), 0u) << run.step.text;
    EXPECT_NE(run.step.text.find("left closed, right open"), std::string::npos) << run.step.text;
    ASSERT_TRUE(turnOnTheSpot(&nav, h, &robot, run.travel));
    // Along the new stretch until the ways not taken are recorded.
    std::vector<double> recorded;
    const TopoGraph none;
    double travel = run.travel;
    for (int i = 0; i < 200 && recorded.empty(); ++i) {
      Decision d;
      const Pose2D before = robot;
      nav.follow(h.perceive(robot, 10.0 + 0.1 * i), belief(TopoMode::Frontier), false, HallwayContext{none, travel, nullptr}, &d);
      for (const exploration::Request& r : d.requests) {
        if (r.kind == exploration::Request::RecordOpening) recorded.push_back(r.bearing);
      }
      step(d, &robot);
      travel += std::hypot(robot.x - before.x, robot.y - before.y);
    }
    ASSERT_EQ(recorded.size(), 1u) << angle;
    EXPECT_NEAR(recorded[0], 0.5 * kPi * std::round(angle / (0.5 * kPi)), 1e-6) << angle;  // the wing's bin
  }
}

// A T whose way taken ends at once (its arm shorter than the robot's end distance plus the distance
// driven before the ways not taken are recorded): the robot turns again, here back into the hallway
// it came by, and the way not taken at the T is still recorded, not dropped with the first turn.
// Dropped, the exploration would end "complete" with the T's other arm never seen.
TEST(HallwayNavigator, AWayNotTakenIsRecordedThoughTheRobotTurnsAgainAtOnce) {
  Hallway t(false);
  t.walls.clear();  // 3.6 m wide along +x (y in [-1.8, 1.8]) to a T at x in [20, 22]: north 0.4 m deep, south 10.2 m
  t.wall(-10.0, -1.8, -10.0, 1.8);
  t.wall(-10.0, 1.8, 20.0, 1.8);
  t.wall(20.0, 1.8, 20.0, 2.2);
  t.wall(20.0, 2.2, 22.0, 2.2);
  t.wall(22.0, 2.2, 22.0, -12.0);
  t.wall(-10.0, -1.8, 20.0, -1.8);
  t.wall(20.0, -1.8, 20.0, -12.0);
  t.wall(20.0, -12.0, 22.0, -12.0);
  const auto nav_owner = navigator();
  HallwayNavigator& nav = *nav_owner;
  Pose2D robot{14.0, 0.0, 0.0};
  const TopoGraph none;
  double travel = 0.0;
  std::vector<std::string> turns;
  std::vector<double> recorded;
  double recorded_travel = 0.0;
  for (int i = 0; i < 1500 && recorded.empty(); ++i) {
    Decision d;
    const Pose2D before = robot;
    const HallwayStep s = nav.follow(t.perceive(robot, 0.1 * i), belief(TopoMode::Frontier), false,
                                     HallwayContext{none, travel, nullptr}, &d);
    for (const exploration::Request& r : d.requests) {
      if (r.kind == exploration::Request::RecordOpening) recorded.push_back(r.bearing);
    }
    if (!recorded.empty()) recorded_travel = travel;
    if (s.kind == HallwayStep::Turning) {
      turns.push_back(s.text);
      ASSERT_TRUE(turnOnTheSpot(&nav, t, &robot, travel));
      continue;
    }
    step(d, &robot);
    travel += std::hypot(robot.x - before.x, robot.y - before.y);
  }
  ASSERT_GE(turns.size(), 2u);
  EXPECT_EQ(turns[0].rfind("hallway end: turning left", 0), 0u) << turns[0];
  EXPECT_NE(turns[0].find("left open, right open"), std::string::npos) << turns[0];
  EXPECT_EQ(turns[1].rfind("hallway end: turning left", 0), 0u) << turns[1];
  ASSERT_EQ(recorded.size(), 1u);
  EXPECT_NEAR(recorded[0], -0.5 * kPi, 1e-6);  // the T's south arm
  // Once the robot has driven branch_record_distance from the T (6.7 m from the start), not when it
  // comes back to the T from the hallway's far end.
  EXPECT_LT(recorded_travel, 10.0);
}
