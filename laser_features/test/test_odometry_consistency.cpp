// OdometryConsistency: a scan pair the odometry explains agrees; a teleport along a hallway does not.
#include <gtest/gtest.h>

#include <random>

#include "laser_features/odometry_consistency.h"
#include "synthetic_scan.h"

namespace laser_features {
namespace {

// A hallway 2 m wide from x = 0 to x = 16 with a 1 m door gap in its north wall at x = 12.
synthetic::World hallway() {
  synthetic::World w;
  w.addWall(0, 0, 16, 0);
  w.addWall(0, 2, 11.5, 2);
  w.addWall(12.5, 2, 16, 2);
  w.addWall(0, 0, 0, 2);
  w.addWall(16, 0, 16, 2);
  w.addPolygon({{11.5, 2}, {11.5, 6}, {12.5, 6}, {12.5, 2}});  // the door's recess
  return w;
}

class OdometryConsistencyTest : public ::testing::Test {
 protected:
  // Scans at `first` then at `second` (world poses); odometry says the sensor moved by `odometry`.
  double pair(const Pose2D& first, const Pose2D& second, const Pose2D& odometry) {
    OdometryConsistency consistency;
    ScanPoints points;
    std::vector<float> r1 = synthetic::simulateScan(world_, first, spec_, 0.01, &rng_);
    points.assign(synthetic::makeView(spec_, r1));
    EXPECT_EQ(consistency.update(points, Pose2D()), -1.0);  // nothing to compare with yet
    std::vector<float> r2 = synthetic::simulateScan(world_, second, spec_, 0.01, &rng_);
    points.assign(synthetic::makeView(spec_, r2));
    return consistency.update(points, inverse(odometry));  // the previous frame in the current one
  }

  synthetic::World world_ = hallway();
  synthetic::ScanSpec spec_;  // 720 beams, 360 degrees
  std::mt19937 rng_{3};
};

TEST_F(OdometryConsistencyTest, MotionTheOdometryExplainsAgrees) {
  // 6 cm forward (0.6 m/s at 10 Hz), past the door.
  EXPECT_GT(pair({11.0, 1.0, 0.0}, {11.06, 1.0, 0.0}, {0.06, 0.0, 0.0}), 0.97);
  // A turn on the spot of 0.15 rad (1.5 rad/s).
  EXPECT_GT(pair({5.0, 1.0, 0.0}, {5.0, 1.0, 0.15}, {0.0, 0.0, 0.15}), 0.97);
  // Odometry slightly off (2 cm, 1 degree) still agrees.
  EXPECT_GT(pair({5.0, 1.0, 0.0}, {5.06, 1.0, 0.0}, {0.04, 0.0, 0.017}), 0.9);
}

TEST_F(OdometryConsistencyTest, TeleportAlongTheHallwayDisagrees) {
  // From x = 13.5 back to x = 5 with the same heading, while odometry says 6 cm forward: only the
  // hallway's ends and the door tell, but they tell clearly.
  const double c = pair({13.5, 1.0, 0.0}, {5.0, 1.0, 0.0}, {0.06, 0.0, 0.0});
  EXPECT_GE(c, 0.0);
  EXPECT_LT(c, 0.75);
  // Turned round by the teleport.
  EXPECT_LT(pair({5.0, 1.0, 0.0}, {5.0, 1.0, kPi}, {0.0, 0.0, 0.0}), 0.75);
}

TEST_F(OdometryConsistencyTest, TooFewPointsGiveNoVerdict) {
  OdometryConsistencyParams params;
  params.max_range = 0.05;  // nothing is close enough to compare
  OdometryConsistency consistency(params);
  ScanPoints points;
  std::vector<float> r = synthetic::simulateScan(world_, {5.0, 1.0, 0.0}, spec_, 0.01, &rng_);
  points.assign(synthetic::makeView(spec_, r));
  consistency.update(points, Pose2D());
  EXPECT_EQ(consistency.update(points, Pose2D()), -1.0);
  // After reset() the next scan has nothing to compare with.
  OdometryConsistency fresh;
  fresh.update(points, Pose2D());
  fresh.reset();
  EXPECT_EQ(fresh.update(points, Pose2D()), -1.0);
}

}  // namespace
}  // namespace laser_features
