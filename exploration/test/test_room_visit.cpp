// RoomVisit's way out of a room through its door: where each step's goal lies and when the robot
// goes on to the next one.
#include <gtest/gtest.h>

#include <cmath>

#include "exploration/motion_controller.h"
#include "exploration/room_visit.h"

using exploration::Decision;
using exploration::DoorTrack;
using exploration::HallwayDoorParams;
using exploration::MotionFeedback;
using exploration::Perception;
using exploration::RoomVisit;
using laser_features::BuildingRules;
using laser_features::Pose2D;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The room lies above the hallway (+y); its door, 0.70 m wide (the narrowest, config/building.yaml),
// is centred at (0, 1) in the place, whose origin is where the robot left the hallway.
const Eigen::Vector2d kDoor(0.0, 1.0);
constexpr double kDoorWidth = 0.70;

// The robot inside at `robot` (place frame = odometry frame), seeing the door from inside: its
// opening's normal points away from the robot, out of the room.
Perception inside(const Pose2D& robot) {
  Perception q;
  q.odom = robot;
  q.room_pose = robot;
  q.room_pose_valid = true;
  laser_features::Opening o;
  o.center = laser_features::transformPoint(laser_features::inverse(robot), kDoor);
  o.theta = laser_features::normalizeAngle(-0.5 * kPi - robot.theta);
  const Eigen::Vector2d along = laser_features::unitVector(o.theta + 0.5 * kPi);
  o.left = o.center + 0.5 * kDoorWidth * along;
  o.right = o.center - 0.5 * kDoorWidth * along;
  o.width = kDoorWidth;
  o.confidence = 1.0;
  o.room_behind = true;
  q.openings.push_back(o);
  return q;
}

}  // namespace

// A narrow door leaves the controller a few centimetres a side (passageSteering: 5 cm in a 0.7 m
// door), less than the door as placed in the place may be off by (here 4.5 cm along its wall, as
// tracked from the hallway). The way out goes by the door as seen from inside: first to its axis,
// exit_depth inside, facing out (from aside of it, or on it facing elsewhere), and only from there
// straight through, with the clearance of the door as seen. Generated building 21 (seed 21): three
// ways out of a 0.70 m door placed 4.5 cm off all failed and the run ended.
TEST(RoomVisit, ANarrowDoorIsLeftFromItsAxisFacingOutAsSeenFromInside) {
  RoomVisit visit{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                  HallwayDoorParams()};
  DoorTrack placed;
  placed.centre_odom = kDoor + Eigen::Vector2d(0.045, 0.0);
  placed.into_odom = 0.5 * kPi;
  placed.width = 0.72;
  placed.sightings = 10;
  visit.beginNewRoom(Pose2D{0.0, 0.0, 0.0}, placed, 0.0);
  visit.beginExit();
  visit.beginDoorExit(0.0);
  const double depth = visit.explorer().params().exit_depth;
  const MotionFeedback moving;
  auto step = [&](const Pose2D& robot, double t) {
    Decision d;
    EXPECT_EQ(visit.exitThroughDoor(inside(robot), t, t, moving, &d), RoomVisit::Exit::Passing);
    return d;
  };

  const Decision aside = step(Pose2D{0.3, 1.0 + depth + 0.2, 0.5 * kPi}, 0.1);
  ASSERT_TRUE(aside.has_goal);
  EXPECT_NEAR(aside.x, 0.0, 1e-6) << "the goal is on the door as seen, not as placed";
  EXPECT_NEAR(aside.y, 1.0 + depth, 1e-6);
  ASSERT_TRUE(aside.theta.has_value());
  EXPECT_NEAR(*aside.theta, -0.5 * kPi, 1e-6) << "facing out";

  const Decision facing_aside = step(Pose2D{0.0, 1.0 + depth, 0.0}, 0.2);
  ASSERT_TRUE(facing_aside.has_goal);
  EXPECT_NEAR(facing_aside.y, 1.0 + depth, 1e-6) << "on the axis but not facing out: not yet through";
  ASSERT_TRUE(facing_aside.theta.has_value());

  const Decision through = step(Pose2D{0.02, 1.0 + depth, -0.5 * kPi + 0.03}, 0.3);
  ASSERT_TRUE(through.has_goal);
  EXPECT_NEAR(through.x, 0.0, 1e-6);
  EXPECT_LT(through.y, 1.0) << "on the axis facing out: through the door";
  EXPECT_FALSE(through.theta.has_value());
  ASSERT_TRUE(through.passage_width.has_value());
  EXPECT_NEAR(*through.passage_width, kDoorWidth, 1e-6) << "the clearance of the door as seen";
}

// The place stands still in the building, so its origin moves in the odometry frame by the
// odometry's drift alone: the drift over a visit is the origin as the EKF last placed it against
// where the visit's first EKF pose placed it (HallwayDoors moves the doors tracked before by it).
TEST(RoomVisit, TheOdometrysDriftOverAVisitIsWhereTheEKFMovedThePlacesOrigin) {
  RoomVisit visit{exploration::RoomVisitParams(), exploration::RoomExplorerParams(), BuildingRules(),
                  HallwayDoorParams()};
  DoorTrack door;
  door.centre_odom = Eigen::Vector2d(3.0, 3.0);
  door.into_odom = 0.5 * kPi;
  door.width = 0.9;
  door.sightings = 10;
  const Pose2D origin{3.0, 2.0, 0.3};
  visit.beginNewRoom(origin, door, 0.0);
  EXPECT_FALSE(visit.odometryDrift().has_value()) << "no EKF pose yet: unmeasured";
  Perception q;
  q.room_pose_valid = false;
  q.odom = laser_features::compose(origin, Pose2D{0.5, 0.0, 0.0});
  visit.inPlace(q);
  EXPECT_FALSE(visit.odometryDrift().has_value()) << "the odometry stood in: still unmeasured";
  q.room_pose_valid = true;
  q.room_pose = Pose2D{1.0, 0.2, 0.1};
  q.odom = laser_features::compose(origin, q.room_pose);  // no drift yet
  visit.inPlace(q);
  ASSERT_TRUE(visit.odometryDrift().has_value());
  EXPECT_NEAR(visit.odometryDrift()->translation().norm(), 0.0, 1e-9);
  // 20 m later the odometry has drifted by `drift` (in the odometry frame); the EKF's pose has not.
  const Pose2D drift{0.25, -0.1, 0.04};
  q.room_pose = Pose2D{2.0, 3.0, -1.2};
  q.odom = laser_features::compose(drift, laser_features::compose(origin, q.room_pose));
  visit.inPlace(q);
  ASSERT_TRUE(visit.odometryDrift().has_value());
  EXPECT_NEAR(visit.odometryDrift()->x, drift.x, 1e-9);
  EXPECT_NEAR(visit.odometryDrift()->y, drift.y, 1e-9);
  EXPECT_NEAR(visit.odometryDrift()->theta, drift.theta, 1e-9);
  // A new visit starts unmeasured again.
  visit.beginNewRoom(origin, door, 0.0);
  EXPECT_FALSE(visit.odometryDrift().has_value());
}
