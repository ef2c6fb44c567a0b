// Rooms behind a room's inner doors (suites): which doors of a covered room lead into another room
// (RoomVisit::innerDoors) and when the space behind such a door is a hallway, not a room
// (hallwayBehindDoor). The scans are ray cast in worlds of wall segments and go through
// laser_features' extractors, as the node's do.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "exploration/grid_planner.h"
#include "exploration/room_visit.h"
#include "exploration/suite_visit.h"
#include "laser_features/feature_extractor.h"
#include "segment_world.h"

using exploration::Decision;
using exploration::DoorTrack;
using exploration::HallwayDoorParams;
using exploration::Perception;
using exploration::RoomVisit;
using laser_features::BuildingRules;
using laser_features::Pose2D;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A wall along x at height y from x0 to x1 with door gaps [a, b] in it.
void wallWithGaps(exploration::test::SegmentWorld* w, double y, double x0, double x1,
                  const std::vector<std::pair<double, double>>& gaps, bool vertical = false) {
  double from = x0;
  auto add = [&](double a, double b) {
    if (b - a < 1e-9) return;
    if (vertical) w->wall(y, a, y, b);
    else w->wall(a, y, b, y);
  };
  for (const auto& g : gaps) {
    add(from, g.first);
    from = g.second;
  }
  add(from, x1);
}

// The world's scan from `robot` (place frame = world frame), 0.5 deg beams to 15 m, through the
// feature extractor: points, lines and openings in the robot frame, the pose as the EKF's.
Perception perceive(const exploration::test::SegmentWorld& world, const Pose2D& robot, double stamp) {
  constexpr int kBeams = 720;
  std::vector<float> ranges(kBeams);
  const Eigen::Vector2d at(robot.x, robot.y);
  for (int k = 0; k < kBeams; ++k) {
    const double r = world.raycast(at, laser_features::unitVector(robot.theta - kPi + k * 2.0 * kPi / kBeams));
    ranges[k] = r < 15.0 ? float(r) : std::numeric_limits<float>::infinity();
  }
  laser_features::ScanView view;
  view.angle_min = -kPi;
  view.angle_increment = 2.0 * kPi / kBeams;
  view.range_min = 0.05;
  view.range_max = 15.0;
  view.ranges = ranges.data();
  view.size = ranges.size();
  laser_features::FeatureExtractor extractor;
  laser_features::Features f;
  EXPECT_TRUE(extractor.extract(view, &f));
  Perception q;
  q.stamp = stamp;
  q.odom = robot;
  q.room_pose = robot;
  q.room_pose_valid = true;
  q.ranges = ranges;
  q.angle_min = view.angle_min;
  q.angle_increment = view.angle_increment;
  for (size_t i = 0; i < extractor.points().size(); ++i)
    if (extractor.points()[i].status == laser_features::BeamStatus::kValid) q.points.push_back(extractor.points()[i].p);
  q.lines = f.lines;
  q.openings = f.openings;
  return q;
}

// The host room: x in [-2.5, 2.5], y in [0, 5], above a 2 m hallway along x. Its entry door is
// 0.9 m wide at x = 0 in the hallway wall, a second hallway door 1.65 m beside it in the same wall,
// a 0.9 m door at y = 2.45 in its right wall into a room only reachable through it (x in
// [2.5, 6.5]), a shelf 0.9 m off its left wall (the gap behind it is the room's own) and a table
// whose legs stand 0.7 m apart (the narrowest door's width).
// With `connecting`, the room behind has a hallway door of its own at x = 4.5.
// The 2 m hallway below the host, from x = -8 to 12: its upper wall has the host's entry door at x = 0,
// its second hallway door 1.65 m beside it and `more` doors.
void hallwayBelowHost(exploration::test::SegmentWorld* w, const std::vector<std::pair<double, double>>& more = {}) {
  std::vector<std::pair<double, double>> gaps{{-0.45, 0.45}, {1.2, 2.1}};
  gaps.insert(gaps.end(), more.begin(), more.end());
  wallWithGaps(w, 0.0, -8.0, 12.0, gaps);  // the hallway's upper wall
  w->wall(-8.0, -2.0, 12.0, -2.0);
  w->wall(-8.0, -2.0, -8.0, 0.0);
  w->wall(12.0, -2.0, 12.0, 0.0);
}

exploration::test::SegmentWorld suite(bool connecting = false, bool table = true) {
  exploration::test::SegmentWorld w;
  hallwayBelowHost(&w, connecting ? std::vector<std::pair<double, double>>{{4.05, 4.95}}
                                  : std::vector<std::pair<double, double>>{});
  w.wall(-2.5, 0.0, -2.5, 5.0);
  w.wall(-2.5, 5.0, 6.5, 5.0);
  wallWithGaps(&w, 2.5, 0.0, 5.0, {{2.0, 2.9}}, true);  // the door into the room behind
  w.wall(6.5, 0.0, 6.5, 5.0);
  w.box(-1.6, 2.5, -1.2, 4.2);  // the shelf
  if (!table) return w;
  for (double x : {0.9, 1.6})  // a table's legs, 0.7 m apart
    for (double y : {3.6, 4.3}) w.box(x - 0.025, y - 0.025, x + 0.025, y + 0.025);
  return w;
}

// A room entered by a 0.9 m door at `door_at` facing +y (the place frame is the world's), covered
// from a walk through it: each pose's scan observed and the coverage stepped.
RoomVisit coveredRoom(const exploration::test::SegmentWorld& world, const std::vector<Pose2D>& walk,
                      const Eigen::Vector2d& door_at = Eigen::Vector2d::Zero()) {
  RoomVisit visit{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                  HallwayDoorParams()};
  DoorTrack door;
  door.centre_odom = door_at;
  door.into_odom = 0.5 * kPi;
  door.width = 0.9;
  visit.beginNewRoom(Pose2D{0.0, 0.0, 0.0}, door, 0.0);
  double t = 0.0;
  for (const Pose2D& robot : walk) {
    const Perception q = perceive(world, robot, t);
    Decision d;
    visit.observe(q, false, &d);
    visit.coverRoom(q, t, t, &d);
    t += 1.0;
  }
  return visit;
}

// The host room of suite(), covered.
RoomVisit coveredHost(const exploration::test::SegmentWorld& world) {
  return coveredRoom(world, {{0.0, 1.0, 0.5 * kPi}, {0.0, 2.0, 0.5 * kPi}, {0.5, 3.0, 0.0}, {1.5, 2.5, 0.0},
                             {1.5, 4.0, 0.5 * kPi}, {-0.5, 4.2, kPi}, {-0.8, 1.5, -0.5 * kPi}, {1.0, 1.2, 0.0}});
}

}  // namespace

// A room's doors not in its entry's wall lead to other rooms: the door in its side wall into a room
// reachable only through it is one; a second hallway door in the entry's wall, 1.65 m beside the
// entry, is not; nor is the gap between a shelf and the wall (the space behind it is the room's), nor
// a gap between a table's legs. Generated building 4 (seed 4): the rooms behind five such doors were
// never mapped.
// Generated building 4 (seed 4): the rooms behind five such doors were never mapped.
TEST(SuiteVisit, OnlyADoorInAnotherWallIntoSpaceOutsideTheRoomIsAnInnerDoor) {
  const exploration::test::SegmentWorld world = suite();
  const RoomVisit host = coveredHost(world);
  const std::vector<RoomVisit::DoorInPlace> inner = host.innerDoors();
  ASSERT_EQ(inner.size(), 1u);
  EXPECT_NEAR(inner[0].centre.x(), 2.5, 0.1);
  EXPECT_NEAR(inner[0].centre.y(), 2.45, 0.1);
  EXPECT_NEAR(inner[0].width, 0.9, 0.1);
  EXPECT_NEAR(std::abs(laser_features::normalizeAngle(inner[0].into - kPi)), 0.0, 0.1);  // into the host
}

// The host of suite() with its door into the room behind in its back wall instead, next to the
// corner: its jamb there (0.3 m) is shorter than a line, so it is never seen between two pieces of
// one wall; the back wall on its other side sets it in the wall.
TEST(SuiteVisit, ADoorNextToTheBackWallsCornerIsAnInnerDoor) {
  exploration::test::SegmentWorld w;
  hallwayBelowHost(&w);
  w.wall(-2.5, 0.0, -2.5, 9.0);
  w.wall(2.5, 0.0, 2.5, 9.0);
  wallWithGaps(&w, 5.0, -2.5, 2.5, {{1.3, 2.2}});  // the back wall, its door 0.3 m from the corner
  w.wall(-2.5, 9.0, 2.5, 9.0);                     // the room behind: y in [5, 9]
  const RoomVisit host = coveredHost(w);
  const std::vector<RoomVisit::DoorInPlace> inner = host.innerDoors();
  ASSERT_EQ(inner.size(), 1u);
  EXPECT_NEAR(inner[0].centre.x(), 1.75, 0.1);
  EXPECT_NEAR(inner[0].centre.y(), 5.0, 0.1);
  EXPECT_NEAR(laser_features::normalizeAngle(inner[0].into + 0.5 * kPi), 0.0, 0.1);  // into the host
}

// The same room with its side door leading into another hallway (a corner room): the space behind
// it, seen from just inside, is 2 m deep and open far both ways along the door's wall; a room behind
// the door is deeper than the widest hallway or closed within it along the wall.
TEST(SuiteVisit, TheSpaceBehindADoorIsAHallwayOnlyWhenShallowAndLongBothWays) {
  const Pose2D door{2.5, 2.45, 0.0};                   // into the space behind, +x
  const Pose2D just_inside{3.2, 2.45, 0.0};            // 0.7 m past the door (RoomExplorer's entry_depth)
  const BuildingRules rules;
  std::string why;

  exploration::test::SegmentWorld room = suite();      // a 4 m by 5 m room behind
  EXPECT_FALSE(exploration::hallwayBehindDoor(perceive(room, just_inside, 0.0), door, rules, &why)) << why;

  exploration::test::SegmentWorld hallway;             // a 2 m hallway along y behind
  wallWithGaps(&hallway, 2.5, -10.0, 15.0, {{2.0, 2.9}}, true);
  hallway.wall(4.5, -10.0, 4.5, 15.0);
  hallway.wall(-2.5, 0.0, -2.5, 5.0);
  hallway.wall(-2.5, 0.0, 2.5, 0.0);
  hallway.wall(-2.5, 5.0, 2.5, 5.0);
  EXPECT_TRUE(exploration::hallwayBehindDoor(perceive(hallway, just_inside, 0.0), door, rules, &why)) << why;
  // From where SuiteVisit::peek looks, a robot radius past the door: the same verdicts.
  const Pose2D peek_at{2.75, 2.45, 0.0};
  EXPECT_TRUE(exploration::hallwayBehindDoor(perceive(hallway, peek_at, 0.0), door, rules, &why)) << why;
  EXPECT_FALSE(exploration::hallwayBehindDoor(perceive(room, peek_at, 0.0), door, rules, &why)) << why;

  // A room as shallow as a hallway, closed 1.5 m from the door on one side: a room.
  exploration::test::SegmentWorld shallow;
  wallWithGaps(&shallow, 2.5, -10.0, 15.0, {{2.0, 2.9}}, true);
  shallow.wall(4.5, 1.0, 4.5, 12.0);
  shallow.wall(2.5, 1.0, 4.5, 1.0);
  shallow.wall(2.5, 12.0, 4.5, 12.0);
  EXPECT_FALSE(exploration::hallwayBehindDoor(perceive(shallow, just_inside, 0.0), door, rules, &why)) << why;
}

// A room 3.4 m wide and 9 m deep entered from a hallway at its short end, with legs standing in a
// row across it at y = 4.5, 0.85 m apart and from its walls: every gap door-wide.
exploration::test::SegmentWorld legsAcrossALongRoom() {
  exploration::test::SegmentWorld w;
  wallWithGaps(&w, 0.0, -8.0, 8.0, {{-0.45, 0.45}});
  w.wall(-8.0, -2.0, 8.0, -2.0);
  w.wall(-8.0, -2.0, -8.0, 0.0);
  w.wall(8.0, -2.0, 8.0, 0.0);
  w.box(-1.7, 0.0, 1.7, 9.0);
  for (double x : {-0.85, 0.0, 0.85}) w.box(x - 0.025, 4.475, x + 0.025, 4.525);
  return w;
}

const std::vector<Pose2D> kLegsWalk{{0.0, 1.0, 0.5 * kPi}, {0.0, 2.5, 0.5 * kPi}, {1.0, 3.5, 0.5 * kPi},
                                    {-1.0, 3.5, 0.5 * kPi}, {0.4, 3.8, 0.5 * kPi}};

// Legs standing in a row across a long room, 0.85 m apart and from its walls: every gap is door-wide and
// each is closed by a virtual wall, so the room's far end is cut off from its free area; still no
// gap is a door into another room: a door is a gap in a wall (a wall piece runs on from an edge),
// seen so twice.
// Generated building 2 (seed 2): a table's and chairs' legs across a 9 m room were taken for doors,
// the room's far end for a room behind them, and the robot was stuck among the legs.
TEST(SuiteVisit, GapsBetweenLegsAcrossALongRoomAreNoInnerDoors) {
  const exploration::test::SegmentWorld w = legsAcrossALongRoom();
  const RoomVisit visit = coveredRoom(w, kLegsWalk);
  EXPECT_TRUE(visit.innerDoors().empty());
  EXPECT_FALSE(visit.otherDoorsOdom().empty());  // the gaps were seen as door-wide openings
}

// Connecting rooms: the room behind the side door has a hallway door of its own and was covered
// from the hallway a moment ago. Its door seen from the neighbour leads into a room mapped already:
// not visited again. Covered longer ago than kRecentTravel (the odometry no longer places it
// reliably), it is visited. Institute (the shipped world): office_2's door into meeting_1, mapped
// from the hallway 20 m before, made meeting_1 a second place.
TEST(SuiteVisit, ADoorIntoARoomCoveredAMomentAgoIsNotVisitedAgain) {
  const exploration::test::SegmentWorld world = suite(true);
  const RoomVisit neighbour = coveredRoom(
      world, {{4.5, 1.0, 0.5 * kPi}, {4.5, 2.5, 0.5 * kPi}, {3.5, 3.5, kPi}, {5.5, 3.5, 0.0}}, {4.5, 0.0});
  RoomVisit host = coveredHost(world);
  ASSERT_EQ(host.innerDoors().size(), 1u);
  exploration::SuiteVisit suite{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                                HallwayDoorParams()};
  suite.roomCovered(neighbour, 10.0);
  suite.begin(host, 30.0);
  EXPECT_FALSE(suite.nextDoor(host, Eigen::Vector2d(1.0, 1.2)));
  suite.begin(host, 10.0 + exploration::SuiteVisit::kRecentTravel + 1.0);
  EXPECT_TRUE(suite.nextDoor(host, Eigen::Vector2d(1.0, 1.2)));
}

// The virtual walls across the gaps between legs cut the room in two: its far half is no part of
// its free area and no path reaches it. Opened once the coverage is over (they are no doors: never
// a gap in a wall), the room is whole again, a path crosses the legs' row; closed again for the way
// out. Generated building 7 (seed 7): room_4 and room_5 behind room_2 and room_3, their doors
// beyond a table, were never entered.
TEST(SuiteVisit, FurnitureGapsOpenedMakeTheRoomWholeAndClosedCutItAgain) {
  RoomVisit visit = coveredRoom(legsAcrossALongRoom(), kLegsWalk);
  const Eigen::Vector2d robot(0.4, 3.8), far_end(0.0, 7.5);
  ASSERT_TRUE(visit.extentOdom());
  EXPECT_LT(visit.extentOdom()->depth_max, 4.6);
  EXPECT_FALSE(visit.pathTo(robot, far_end));
  visit.openFurnitureGaps();
  EXPECT_GT(visit.extentOdom()->depth_max, 4.6);
  EXPECT_TRUE(visit.pathTo(robot, far_end));
  visit.closeFurnitureGaps();
  EXPECT_LT(visit.extentOdom()->depth_max, 4.6);
  EXPECT_FALSE(visit.pathTo(robot, far_end));
}

// The way out keeps the walls across furniture gaps while they leave the robot a way to its door.
// Beyond the legs' row (it crossed the row before the gaps were seen) they cut it off from the door
// it came in by, which is no wall of the room's: the first attempt goes without a path (the steps
// through the door from where the robot is), and once it has failed the next one plans with the
// gaps' walls taken away. Before the row they stay. Generated building 21 (seed 21): back from a
// room behind room_18, no attempt found a path out through the gaps' walls, the robot turned on
// the spot for 240 s and the exploration stopped.
TEST(SuiteVisit, FurnitureGapWallsThatCutTheRobotOffItsDoorAreTakenAwayAfterAFailedWayOut) {
  const exploration::test::SegmentWorld world = legsAcrossALongRoom();
  const Eigen::Vector2d before_row(0.4, 3.8), beyond_row(0.0, 6.0);
  for (const Eigen::Vector2d& robot : {before_row, beyond_row}) {
    std::vector<Pose2D> walk = kLegsWalk;
    walk.push_back(Pose2D{robot.x(), robot.y(), -0.5 * kPi});
    RoomVisit visit = coveredRoom(world, walk);
    const Perception q = perceive(world, walk.back(), 10.0);
    ASSERT_FALSE(visit.pathTo(before_row, beyond_row));  // the gaps are walls
    visit.beginExit();
    Decision d;
    const bool cut_off = robot == beyond_row;
    EXPECT_EQ(visit.followExitPath(q, 0.0, &d), cut_off) << robot.transpose();  // no path: the door steps
    if (!cut_off) {
      EXPECT_FALSE(visit.pathTo(before_row, beyond_row));  // the gaps' walls stay
      continue;
    }
    // The steps through the door (each ends at its time limit) did not get it out: still inside,
    // the next attempt.
    visit.beginDoorExit(10.0);
    RoomVisit::Exit exit = RoomVisit::Exit::Passing;
    for (int step = 1; step <= 3 && exit == RoomVisit::Exit::Passing; ++step) {
      const double now = 10.0 + step * visit.params().exit_time_limit;
      exit = visit.exitThroughDoor(q, now, now - 10.0, exploration::MotionFeedback{}, &d);
    }
    ASSERT_EQ(exit, RoomVisit::Exit::TryAgain);
    d = Decision{};
    EXPECT_FALSE(visit.followExitPath(q, 0.0, &d));
    EXPECT_TRUE(d.has_goal);
    EXPECT_TRUE(visit.pathTo(before_row, beyond_row));  // taken away
  }
}

// The look through an inner door (SuiteVisit::peek) from just past it: a room behind with a hallway
// door of its own in the host's hallway wall (a connecting room) is left to the hallway; a room
// with no such door (a suite) is visited. The host's own second hallway door, in the same wall on
// the host's side, is no door of the room behind. large_floor (the shipped world): with rooms
// behind rooms visited, connecting rooms entered both from their neighbour and from the hallway, more
// than 30 m of travel apart, were 26 rooms mapped twice.
TEST(SuiteVisit, ARoomWithADoorOntoTheHostsHallwayIsLeftToTheHallway) {
  for (const bool connecting : {false, true}) {
    const exploration::test::SegmentWorld world = suite(connecting);
    const RoomVisit host = coveredHost(world);
    exploration::SuiteVisit suite{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                                  HallwayDoorParams()};
    RoomVisit for_paths = host;
    suite.begin(host, 0.0);
    ASSERT_TRUE(suite.nextDoor(for_paths, Eigen::Vector2d(1.0, 1.2)));
    const Pose2D past{2.5 + suite.peekDepth(), 2.45, 0.0};
    const Pose2D front{2.5 - exploration::SuiteVisit::kFront, 2.45, 0.0};
    auto peekFrom = [&](const Pose2D& robot) {
      Decision d;
      const auto drive = suite.peek(host, perceive(world, robot, 0.0), 0.0, &d);
      EXPECT_TRUE(d.passage_width && std::abs(*d.passage_width - 0.9) < 0.1);
      return drive;
    };
    EXPECT_EQ(peekFrom(front), exploration::SuiteVisit::Drive::Driving);  // in through the door
    for (int k = 0; k <= exploration::SuiteVisit::kLookScans; ++k)
      EXPECT_EQ(peekFrom(past), exploration::SuiteVisit::Drive::Driving);  // there, looking
    EXPECT_EQ(peekFrom(front), exploration::SuiteVisit::Drive::There) << "back at the front facing the door";
    EXPECT_EQ(suite.behind(), connecting ? exploration::SuiteVisit::Behind::ConnectingRoom
                                         : exploration::SuiteVisit::Behind::Room)
        << (connecting ? "connecting room" : "suite") << ": " << suite.space();
  }
}

// The rule is for doors in the host's side walls: the room behind a door in its back wall lies away
// from the hallway, and a door seen on the hallway's wall line is none of its own.
TEST(SuiteVisit, ADoorInTheHostsBackWallLeadsAwayFromItsHallway) {
  const exploration::test::SegmentWorld world = suite(true);
  const Perception q = perceive(world, Pose2D{3.5, 2.45, 0.0}, 0.0);
  RoomVisit::DoorInPlace side{Eigen::Vector2d(2.5, 2.45), kPi, 0.9, 2};
  RoomVisit::DoorInPlace back{Eigen::Vector2d(2.5, 2.45), -0.5 * kPi, 0.9, 2};
  const Pose2D host_door{0.0, 0.0, 0.5 * kPi};
  std::string why;
  EXPECT_TRUE(exploration::doorOntoHostHallway(q, host_door, side, BuildingRules(), &why));
  EXPECT_FALSE(exploration::doorOntoHostHallway(q, host_door, back, BuildingRules()));
  // Seen from the host side of the side wall, the host's own hallway doors are none of the room behind.
  EXPECT_FALSE(exploration::doorOntoHostHallway(perceive(world, Pose2D{1.0, 2.45, 0.0}, 0.0), host_door,
                                                RoomVisit::DoorInPlace{Eigen::Vector2d(5.5, 2.45), kPi, 0.9, 2},
                                                BuildingRules()));
}

// Back from a room behind, the host's place is relocated where the robot stands, not dead reckoned
// from the host's last EKF pose: the host keeps the room behind's origin (the robot's pose when its
// place was created) as a door no node names, and the robot's pose in the room behind is its pose
// from that door. Each room behind has a door of its own; the relocation names the last one.
// Generated building 15 (seed 15): dead reckoned over a room behind and the 8.5 m back through the
// host, the robot met the wall 0.9 m beside the host's 0.7 m door, three times.
TEST(SuiteVisit, BackFromARoomBehindTheHostIsRelocatedAtThatRoomsOrigin) {
  exploration::SuiteVisit suite{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                                HallwayDoorParams()};
  const Pose2D origin_in_host{-0.85, -8.46, -1.60};  // where the robot stands, facing the inner door
  const exploration::Request keep = suite.keepOrigin(2);
  EXPECT_EQ(keep.kind, exploration::Request::AddDoor);
  EXPECT_EQ(keep.place_id, 2);
  EXPECT_GE(keep.door_id, exploration::kNodelessDoorIdBase);
  const Pose2D door_in_host = laser_features::compose(origin_in_host, keep.pose);  // as ekf_local_map stores it

  Perception q;  // back through the inner door, 1.2 m from its origin, turned round
  q.room_pose = Pose2D{-1.2, 0.1, 3.1};
  const exploration::Request back = suite.relocateHost(2, q);
  EXPECT_EQ(back.kind, exploration::Request::Relocate);
  EXPECT_EQ(back.place_id, 2);
  EXPECT_EQ(back.door_id, keep.door_id);
  const Pose2D relocated = laser_features::compose(door_in_host, back.pose);  // as ekf_local_map relocates
  const Pose2D truth = laser_features::compose(origin_in_host, q.room_pose);
  EXPECT_NEAR(relocated.x, truth.x, 1e-9);
  EXPECT_NEAR(relocated.y, truth.y, 1e-9);
  EXPECT_NEAR(laser_features::normalizeAngle(relocated.theta - truth.theta), 0.0, 1e-9);

  EXPECT_FALSE(back.pose_cov) << "no EKF covariance with the pose: the door's sigmas";
  q.room_pose_cov = Eigen::Vector3d(0.04, 0.01, 0.002).asDiagonal();
  const exploration::Request with_cov = suite.relocateHost(2, q);
  ASSERT_TRUE(with_cov.pose_cov);
  EXPECT_TRUE(with_cov.pose_cov->isApprox(q.room_pose_cov)) << "the EKF's own uncertainty of the pose";

  const exploration::Request second = suite.keepOrigin(2);
  EXPECT_NE(second.door_id, keep.door_id) << "each room behind keeps its own origin";
  EXPECT_EQ(suite.relocateHost(2, q).door_id, second.door_id);
}

// The path to an inner door is planned on the host's grid, which loses thin table and chair legs
// (beams passing beside a leg mark its cell free). It is planned again every replan_period from
// where the robot is, clear of the latest scan's returns, as a mission's path in a room is: the
// robot reaches the door's front round the table, not between its legs. Generated buildings 10, 12,
// 21 and 29 (seeds 1-40 at 34920f8): the robot turned to and fro between a table's legs for the
// whole exit_time_limit, the room behind was given up and the run ended incomplete.
TEST(SuiteVisit, AWayToAnInnerDoorIsPlannedAgainClearOfLegsTheGridLost) {
  RoomVisit host = coveredHost(suite(false, false));  // the grid has no legs
  ASSERT_EQ(host.innerDoors().size(), 1u);
  // A table whose legs stand 0.7 m apart (the narrowest door's width), 1.1 m below the back wall.
  const std::vector<Eigen::Vector2d> legs = {{0.9, 3.2}, {0.9, 3.9}, {1.6, 3.2}, {1.6, 3.9}};
  exploration::test::SegmentWorld with_table = suite(false, false);
  for (const Eigen::Vector2d& l : legs) with_table.box(l.x() - 0.025, l.y() - 0.025, l.x() + 0.025, l.y() + 0.025);
  const double clear = exploration::GridPlanner(exploration::RoomExplorerParams().planner).clearance();
  const auto nearest_leg = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    double m = std::numeric_limits<double>::infinity();
    for (double t = 0.0; t <= 1.0; t += 0.01)
      for (const Eigen::Vector2d& l : legs) m = std::min(m, (a + t * (b - a) - l).norm());
    return m;
  };
  const double period = exploration::RoomVisitParams().replan_period;
  exploration::SuiteVisit suite{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                                HallwayDoorParams()};
  suite.begin(host, 0.0);
  Pose2D robot{1.25, 4.5, -0.5 * kPi};  // above the table: the straight way to the door's front runs between its legs
  ASSERT_TRUE(suite.nextDoor(host, robot.translation()));
  Perception q = perceive(with_table, robot, 20.0);
  q.ranges.clear();  // the scan's returns for the way, not into the grid (which keeps the legs lost)
  Decision d;
  host.observe(q, false, &d);
  d = Decision{};
  ASSERT_EQ(suite.driveToDoor(host, q, 0.0, &d), exploration::SuiteVisit::Drive::Driving);
  ASSERT_TRUE(d.has_goal);
  EXPECT_LT(nearest_leg(robot.translation(), Eigen::Vector2d(d.x, d.y)), clear) << "the grid's way runs between the legs";
  // Along the path planned again, waypoint by waypoint, to the door's front: never within the legs' clearance.
  bool there = false;
  for (int step = 1; step < 40 && !there; ++step) {
    d = Decision{};
    there = suite.driveToDoor(host, q, step * period, &d) == exploration::SuiteVisit::Drive::There;
    if (there) break;
    ASSERT_TRUE(d.has_goal);
    const Eigen::Vector2d goal(d.x, d.y);
    EXPECT_GE(nearest_leg(robot.translation(), goal), clear) << robot.translation().transpose() << " -> " << goal.transpose();
    robot = Pose2D{goal.x(), goal.y(), d.theta.value_or(robot.theta)};
    q.room_pose = q.odom = robot;
  }
  EXPECT_TRUE(there) << "the door's front reached round the table";
}

// A door of a room lies in the room's walls. The host's second hallway door, in its left wall, opens
// onto a side hallway; across it a door into another room is seen through that door, twice, a wall
// running on from both its edges. It lies 2 m beyond the host's wall, and no path from the host
// reaches its front: no door of the host's. Generated building 25 (seed 25 at 1f137d4): such a
// 1.62 m gap, 7.6 m from the entry door, was given up as the host's inner door "for want of a
// path", and the run ended incomplete with every room mapped.
TEST(SuiteVisit, ADoorSeenThroughAnotherDoorIsNoDoorOfTheRoom) {
  exploration::test::SegmentWorld w;
  wallWithGaps(&w, 0.0, -8.5, 6.0, {{-0.45, 0.45}});  // the hallway below the host, the entry door at x = 0
  w.wall(-8.5, -2.0, 6.0, -2.0);
  w.wall(6.0, -2.0, 6.0, 0.0);
  w.wall(2.5, 0.0, 2.5, 5.0);                                   // the host's right wall
  w.wall(-2.5, 5.0, 2.5, 5.0);                                  // its back wall
  wallWithGaps(&w, -2.5, 0.0, 5.0, {{2.0, 2.9}}, true);        // its left wall: a door onto the side hallway
  wallWithGaps(&w, -4.5, 0.0, 8.0, {{2.0, 2.9}}, true);        // across the side hallway: another room's door
  w.wall(-2.5, 5.0, -2.5, 8.0);
  w.wall(-4.5, 8.0, -2.5, 8.0);
  w.wall(-8.5, 0.0, -8.5, 5.0);                                 // the room beyond
  w.wall(-8.5, 5.0, -4.5, 5.0);
  w.wall(-8.5, -2.0, -8.5, 0.0);
  const RoomVisit host = coveredRoom(w, {{0.0, 1.0, 0.5 * kPi}, {0.0, 2.0, 0.5 * kPi}, {-1.0, 2.45, kPi},
                                         {-1.2, 2.45, kPi}, {1.5, 2.5, 0.0}, {0.0, 4.0, 0.5 * kPi},
                                         {-1.5, 4.2, kPi}, {1.0, 1.2, 0.0}});
  bool side_door = false;
  for (const RoomVisit::DoorInPlace& d : host.innerDoors()) {
    EXPECT_GT(d.centre.x(), -3.0) << "a door across the side hallway at " << d.centre.transpose();
    if (std::abs(d.centre.x() + 2.5) < 0.2) side_door = true;
  }
  EXPECT_TRUE(side_door) << "the host's own door onto the side hallway";
}
