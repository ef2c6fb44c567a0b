// The map checked against the dead reckoning only while it shares the map's frame, and where a
// passed landmark lies by it.
#include <gtest/gtest.h>

#include "pomdp_topo/dead_reckoning_gate.h"

using laser_features::HeadingBins;
using laser_features::Pose2D;
using pomdp_topo::DeadReckoningGate;
using pomdp_topo::MapBuilderParams;
using pomdp_topo::PassedLandmark;
using pomdp_topo::TopoNode;

namespace {
// A door passed on the left 1.2 m back along bin 0 (east), the robot at (10, 2) 30 m into the run.
PassedLandmark doorPassed() {
  PassedLandmark p;
  p.travel = 29.0;
  p.landmark.along = -0.2;
  p.heading_bin = 0;
  return p;
}
}  // namespace

TEST(DeadReckoningGate, ChecksNothingUntilTheDeadReckoningIsTheMapsAndAgainAfterARelocation) {
  const MapBuilderParams params;
  const HeadingBins bins{0.0, 4};
  const Pose2D robot{10.0, 2.0, 0.0};
  DeadReckoningGate gate;
  Eigen::Vector2d at;
  EXPECT_FALSE(gate.deadReckonedPosition(params, bins, doorPassed(), robot, 30.0, &at)) << "not trusted yet";
  gate.setTrusted(true, true, 0.0);
  ASSERT_TRUE(gate.deadReckonedPosition(params, bins, doorPassed(), robot, 30.0, &at));
  EXPECT_NEAR(at.x(), 10.0 - 1.2, 1e-12);
  EXPECT_NEAR(at.y(), 2.0, 1e-12);
  TopoNode far;
  far.pose = Pose2D{8.8 + params.min_node_separation + params.match_distance + 0.1, 2.0, 0.0};
  EXPECT_TRUE(gate.farFromNode(params, bins, far, doorPassed(), robot, 30.0));
  gate.lose();
  EXPECT_FALSE(gate.checks(params));
  EXPECT_FALSE(gate.farFromNode(params, bins, far, doorPassed(), robot, 30.0)) << "lost: no check";
  EXPECT_EQ(gate.departure(params, far, 0.0, robot, &at.x()), DeadReckoningGate::Departure::Here);
  gate.relocated(40.0);
  EXPECT_TRUE(gate.checks(params));
}

// A new stretch out of a node starts where the robot is on the node's way out: the belief late by
// more than the tolerance starts it as far along as the robot; ahead of the robot, it waits; off
// the way (farther aside than update_position_tolerance) it is wrong.
TEST(DeadReckoningGate, AStretchLeavesANodeWhereTheRobotIsOnItsWayOut) {
  const MapBuilderParams params;
  DeadReckoningGate gate;
  gate.setTrusted(true, true, 0.0);
  TopoNode n;
  n.pose = Pose2D{0.0, 0.0, 0.0};
  double s = 1.0;
  EXPECT_EQ(gate.departure(params, n, 0.0, Pose2D{6.0, 0.3, 0.0}, &s), DeadReckoningGate::Departure::Here);
  EXPECT_DOUBLE_EQ(s, 6.0);
  s = 6.0;
  EXPECT_EQ(gate.departure(params, n, 0.0, Pose2D{1.0, 0.0, 0.0}, &s), DeadReckoningGate::Departure::NotYet);
  EXPECT_DOUBLE_EQ(s, 1.0);
  s = 1.0;
  EXPECT_EQ(gate.departure(params, n, 0.0, Pose2D{1.0, params.update_position_tolerance + 0.5, 0.0}, &s),
            DeadReckoningGate::Departure::Elsewhere);
}
