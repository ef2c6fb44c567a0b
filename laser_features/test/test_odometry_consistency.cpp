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
  // Scans taken at the true sensor poses `truth` (world) while odometry reports `odometry`; returns
  // what update() returned for each scan.
  std::vector<double> drive(const std::vector<Pose2D>& truth, const std::vector<Pose2D>& odometry,
                            OdometryConsistency* consistency = nullptr) {
    OdometryConsistency own;
    if (consistency == nullptr) consistency = &own;
    std::vector<double> out;
    for (size_t k = 0; k < truth.size(); ++k) {
      std::vector<float> r = synthetic::simulateScan(world_, truth[k], spec_, 0.01, &rng_);
      points_.assign(synthetic::makeView(spec_, r));
      out.push_back(consistency->update(points_, odometry[k]));
    }
    return out;
  }

  synthetic::World world_ = hallway();
  synthetic::ScanSpec spec_;  // 720 beams, 360 degrees
  ScanPoints points_;
  std::mt19937 rng_{3};
};

TEST_F(OdometryConsistencyTest, MotionTheOdometryExplainsAgrees) {
  // 6 cm forward (0.6 m/s at 10 Hz), past the door.
  auto c = drive({{11.0, 1.0, 0.0}, {11.06, 1.0, 0.0}}, {{0, 0, 0}, {0.06, 0, 0}});
  EXPECT_EQ(c[0], -1.0);  // nothing to compare with yet
  EXPECT_GT(c[1], 0.97);
  // A turn on the spot of 0.15 rad (1.5 rad/s).
  EXPECT_GT(drive({{5.0, 1.0, 0.0}, {5.0, 1.0, 0.15}}, {{0, 0, 0}, {0, 0, 0.15}})[1], 0.97);
  // Odometry off by 2 cm and 1 degree: agrees at once.
  EXPECT_GT(drive({{5.0, 1.0, 0.0}, {5.06, 1.0, 0.0}}, {{0, 0, 0}, {0.04, 0, 0.017}})[1], 0.9);
  // Off by 15 cm and 4 degrees (a long step of a logged robot): the correction search finds it.
  EXPECT_GT(drive({{5.0, 1.0, 0.0}, {6.0, 1.0, 0.0}}, {{0, 0, 0}, {0.85, 0, 0.07}})[1], 0.9);
}

TEST_F(OdometryConsistencyTest, TeleportAlongTheHallwayIsReportedOneScanLater) {
  // From x = 13.5 back to x = 5 with the same heading, while odometry says 6 cm forward: only the
  // hallway's ends and the door tell, but they tell clearly. The doubtful pair is confirmed with
  // the next scan against the scan from before the jump.
  auto c = drive({{13.44, 1.0, 0.0}, {13.5, 1.0, 0.0}, {5.0, 1.0, 0.0}, {5.06, 1.0, 0.0}, {5.12, 1.0, 0.0}},
                 {{13.44, 1.0, 0.0}, {13.5, 1.0, 0.0}, {13.56, 1.0, 0.0}, {13.62, 1.0, 0.0}, {13.68, 1.0, 0.0}});
  EXPECT_GT(c[1], 0.97);
  EXPECT_EQ(c[2], -1.0);  // doubtful: deferred
  EXPECT_GE(c[3], 0.0);
  EXPECT_LT(c[3], 0.75);  // confirmed against the scan before the jump
  EXPECT_GT(c[4], 0.97);  // and the robot goes on from its new place
  // Turned round by the teleport, on the spot.
  auto u = drive({{5.0, 1.0, 0.0}, {5.0, 1.0, kPi}, {5.0, 1.0, kPi}}, {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}});
  EXPECT_EQ(u[1], -1.0);
  EXPECT_LT(u[2], 0.75);
}

TEST_F(OdometryConsistencyTest, OneOddScanIsNoJump) {
  // The middle scan is taken elsewhere (a glitch); the next one agrees with the one before it.
  auto c = drive({{9.0, 1.0, 0.0}, {3.0, 1.0, 0.0}, {9.12, 1.0, 0.0}}, {{9.0, 1.0, 0.0}, {9.06, 1.0, 0.0}, {9.12, 1.0, 0.0}});
  EXPECT_EQ(c[1], -1.0);
  EXPECT_GT(c[2], 0.97);
}

TEST_F(OdometryConsistencyTest, TooFewPointsGiveNoVerdict) {
  OdometryConsistencyParams params;
  params.max_range = 0.05;  // nothing is close enough to compare
  OdometryConsistency consistency(params);
  auto c = drive({{5.0, 1.0, 0.0}, {5.0, 1.0, 0.0}}, {{0, 0, 0}, {0, 0, 0}}, &consistency);
  EXPECT_EQ(c[1], -1.0);
  // After reset() the next scan has nothing to compare with.
  OdometryConsistency fresh;
  drive({{5.0, 1.0, 0.0}}, {{0, 0, 0}}, &fresh);
  fresh.reset();
  EXPECT_EQ(drive({{5.0, 1.0, 0.0}}, {{0, 0, 0}}, &fresh)[0], -1.0);
}

}  // namespace
}  // namespace laser_features
