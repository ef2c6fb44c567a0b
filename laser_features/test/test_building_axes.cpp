// The building's axis from wall lines (BuildingAxisEstimator) and the one heading-bin conversion
// (HeadingBins): on the real extractor's lines of simulated scans, at any building yaw and start.
#include "laser_features/building_axes.h"

#include "laser_features/feature_extractor.h"
#include "synthetic_scan.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

namespace laser_features {
namespace {

using namespace synthetic;

/// Turns a world by `yaw` about the origin.
World turned(const World& w, double yaw) {
  World out;
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (const Wall& wall : w.walls) {
    out.walls.push_back({{c * wall.a.x() - s * wall.a.y(), s * wall.a.x() + c * wall.a.y()},
                         {c * wall.b.x() - s * wall.b.y(), s * wall.b.x() + c * wall.b.y()}});
  }
  return out;
}

/// The axis the estimator finds from one scan of `world` taken at `sensor` (world frame); the lines'
/// normals are given in the world frame (sensor heading + alpha).
BuildingAxisEstimator scanOnce(const World& world, const Pose2D& sensor, uint32_t seed) {
  std::mt19937 rng(seed);
  const ScanSpec spec = ScanSpec::full(720);
  const std::vector<float> ranges = simulateScan(world, sensor, spec, 0.01, &rng);
  FeatureExtractor extractor;
  Features f;
  EXPECT_TRUE(extractor.extract(makeView(spec, ranges), &f));
  BuildingAxisEstimator est;
  for (const LineSegment& l : f.lines) est.add(sensor.theta + l.line.alpha, l.line.cov(0, 0), l.length());
  return est;
}

double axisError(double estimated, double truth) {
  return std::abs(normalizeAngle(4.0 * (estimated - truth))) / 4.0;  // modulo pi/2
}

TEST(BuildingAxes, AStartAt34DegreesToTheHallwayFindsTheWallsAxis) {
  // A 3.2 m hallway with a side door; the robot faces 34 deg off its walls.
  const World hall = hallwayWithSideDoor(12.0, 0.9);
  const BuildingAxisEstimator est = scanOnce(hall, {8.0, 1.6, 0.5934}, 1);
  ASSERT_TRUE(est.ready()) << est.totalLength() << " m, agreement " << est.agreement();
  EXPECT_LT(axisError(est.axis(), 0.0), 0.01);
}

TEST(BuildingAxes, ABuildingAtAnyYawNeedsNoParameter) {
  for (const double yaw : {0.0, 0.3, 0.7853, 0.8, -1.2, 2.9}) {
    const World office = turned(officeScene(), yaw);
    const Eigen::Vector2d p = Eigen::Rotation2Dd(yaw) * Eigen::Vector2d(3.5, 2.5);
    const BuildingAxisEstimator est = scanOnce(office, {p.x(), p.y(), 0.2}, 2);
    ASSERT_TRUE(est.ready()) << yaw;
    EXPECT_LT(axisError(est.axis(), yaw), 0.01) << yaw;
    EXPECT_GT(est.axis(), -kPi / 4 - 1e-9);
    EXPECT_LE(est.axis(), kPi / 4 + 1e-9);
  }
}

TEST(BuildingAxes, FurnitureAtOtherAnglesLowersTheAgreementNotTheAxis) {
  World room = rectangularRoom(8.0, 6.0);
  // two tables turned by 20 and 55 deg
  for (const auto& t : {std::make_tuple(2.5, 2.0, 0.35), std::make_tuple(5.5, 4.0, 0.96)}) {
    const double c = std::cos(std::get<2>(t)), s = std::sin(std::get<2>(t));
    std::vector<Eigen::Vector2d> corners;
    for (const auto& q : {Eigen::Vector2d(-0.8, -0.4), Eigen::Vector2d(0.8, -0.4), Eigen::Vector2d(0.8, 0.4),
                          Eigen::Vector2d(-0.8, 0.4)})
      corners.push_back({std::get<0>(t) + c * q.x() - s * q.y(), std::get<1>(t) + s * q.x() + c * q.y()});
    room.addPolygon(corners);
  }
  const BuildingAxisEstimator est = scanOnce(room, {4.0, 3.0, 1.0}, 3);
  ASSERT_TRUE(est.ready());
  EXPECT_LT(est.agreement(), 0.999);
  EXPECT_LT(axisError(est.axis(), 0.0), 0.02);
}

// A wing at 45 deg to the rest in view (12 m of its walls against 20 m of the main hallway's): a
// plain mean of 4 beta would cancel the two families; the axis is the majority's.
TEST(BuildingAxes, AWingAt45DegreesInViewIsTheMinority) {
  BuildingAxisEstimator est;
  for (int k = 0; k < 10; ++k) est.add(0.2 + (k % 2) * 0.5 * kPi + 0.002 * k, 1e-4, 2.0);          // 20 m
  for (int k = 0; k < 6; ++k) est.add(0.2 + 0.25 * kPi + (k % 2) * 0.5 * kPi, 1e-4, 2.0);           // 12 m
  ASSERT_TRUE(est.ready()) << est.agreement();
  EXPECT_NEAR(est.axis(), 0.209, 0.01);
  EXPECT_NEAR(est.agreement(), 20.0 / 32.0, 1e-9);
}

TEST(BuildingAxes, ShortOrUncertainLinesAndTooLittleWallAreNotEnough) {
  BuildingAxisEstimator est;
  EXPECT_FALSE(est.add(0.1, 1e-4, 0.5));   // too short
  EXPECT_FALSE(est.add(0.1, 0.04, 3.0));   // sigma 0.2 rad
  EXPECT_TRUE(est.add(0.1, 1e-4, 3.0));
  EXPECT_FALSE(est.ready());               // 3 m of the 4 m needed
  EXPECT_TRUE(est.add(0.1 + kPi / 2, 1e-4, 1.5));
  EXPECT_TRUE(est.ready());
  EXPECT_NEAR(est.axis(), 0.1, 1e-9);
  est.clear();
  EXPECT_FALSE(est.ready());
}

TEST(BuildingAxes, LinesThatDisagreeAreNoAxis) {
  // Walls of a round hall: normals spread over every direction (each 4 beta held by four lines).
  BuildingAxisEstimator est;
  for (int k = 0; k < 36; ++k) est.add(k * kPi / 18.0 + 0.01, 1e-4, 1.2);
  EXPECT_GT(est.totalLength(), est.params().min_wall_length);
  EXPECT_FALSE(est.ready());
}

TEST(BuildingAxes, TheAxisOfAMapsEdgesIsTheirCommonDirectionModuloAQuarterTurn) {
  EXPECT_NEAR(dominantAxis({0.6, 0.6 + kPi / 2, 0.6 - kPi, 0.61}, {1, 1, 1, 1}), 0.6025, 1e-3);
  EXPECT_EQ(dominantAxis({}, {}), 0.0);
}

// The walls of the hallway the robot stands in, on the real extractor's lines: a wing at 30-60 deg
// to the building's axes (its rooms' walls square to it), seen from a robot that heads along the
// building's axis; the robot's own narrow hallway, not the wider one seen past its end.
TEST(HallwayWalls, AWingsWallsAtAnAngleAreTheHallwayAroundTheRobot) {
  for (const double wing : {0.52, 0.61, 0.79, 1.04}) {
    World straight;
    straight.addWall(-8, 1.1, 8, 1.1);   // a 2 m hallway along x, the robot 0.1 m right of its middle
    straight.addWall(-8, -0.9, 8, -0.9);
    straight.addWall(-8, 6.0, 8, 6.0);   // a wider space's wall beyond the left wall's end: not this hallway
    const World w = turned(straight, wing);
    std::mt19937 rng(3);
    const ScanSpec spec = ScanSpec::full(720);
    const std::vector<float> ranges = simulateScan(w, Pose2D{0.0, 0.0, 0.0}, spec, 0.01, &rng);
    FeatureExtractor extractor;
    Features f;
    ASSERT_TRUE(extractor.extract(makeView(spec, ranges), &f));
    HallwayWallsParams params;
    const double max_turn = 0.25 * kPi + params.parallel_tolerance;  // half a quarter-turn bin and the tolerance: 60 deg
    const std::optional<double> found = hallwayWallsDirection(f.lines, 0.0, max_turn, params);
    ASSERT_TRUE(found.has_value()) << wing;
    EXPECT_NEAR(*found, wing, 0.02) << wing;
    // Heading the other way, the same walls give the opposite sense.
    const std::optional<double> back = hallwayWallsDirection(f.lines, kPi, max_turn, params);
    ASSERT_TRUE(back.has_value()) << wing;
    EXPECT_NEAR(std::abs(normalizeAngle(*back - wing)), kPi, 0.02) << wing;
    // Beyond the turn searched, nothing.
    EXPECT_FALSE(hallwayWallsDirection(f.lines, wing + 0.5 * kPi, 0.25 * kPi, params).has_value()) << wing;
  }
}

TEST(HallwayWalls, OneWallOrAWiderSpaceIsNoHallway) {
  std::vector<LineSegment> lines(1);
  lines[0].start = {-3.0, 1.0};
  lines[0].end = {3.0, 1.0};
  HallwayWallsParams params;
  EXPECT_FALSE(hallwayWallsDirection(lines, 0.0, 0.25 * kPi, params).has_value());
  lines.push_back(lines[0]);
  lines[1].start = {-3.0, -3.5};
  lines[1].end = {3.0, -3.5};  // 4.5 m apart: wider than any hallway
  EXPECT_FALSE(hallwayWallsDirection(lines, 0.0, 0.25 * kPi, params).has_value());
  lines[1].start.y() = lines[1].end.y() = -1.0;
  const std::optional<double> found = hallwayWallsDirection(lines, 0.1, 0.25 * kPi, params);
  ASSERT_TRUE(found.has_value());
  EXPECT_NEAR(*found, 0.0, 1e-9);
}

TEST(HeadingBins, BinsRunAlongTheAxisAndRoundTrip) {
  const HeadingBins bins{0.6, 4};
  EXPECT_EQ(bins.bin(0.6), 0);
  EXPECT_EQ(bins.bin(0.6 + kPi / 2 + 0.3), 1);
  EXPECT_EQ(bins.bin(0.6 - kPi / 2), 3);
  EXPECT_EQ(bins.bin(0.6 + kPi / 4 + 0.01), 1);
  for (int b = -5; b < 9; ++b) EXPECT_EQ(bins.bin(bins.heading(b)), bins.wrap(b)) << b;
  EXPECT_NEAR(bins.heading(2), normalizeAngle(0.6 + kPi), 1e-12);
  const HeadingBins eight{0.0, 8};
  EXPECT_EQ(eight.bin(kPi / 4), 1);
  EXPECT_EQ(eight.bin(-kPi / 4), 7);
}

// Two directions on the bins are one way out of a node within a quarter of a bin, on either side
// of the wrap at pi; half a bin apart is never one way, whatever the number of bins.
TEST(HeadingBins, TwoDirectionsAreOneWayWithinAQuarterOfABin) {
  for (const int n : {4, 8}) {
    const HeadingBins bins{0.6, n};
    const double quarter = 0.25 * bins.width();
    EXPECT_DOUBLE_EQ(bins.sameWayTolerance(), quarter);
    for (int b = 0; b < n; ++b) {
      const double h = bins.heading(b);
      EXPECT_TRUE(bins.sameWay(h, h + 0.9 * quarter)) << n << " bins, bin " << b;
      EXPECT_TRUE(bins.sameWay(h - 0.9 * quarter, h + 2.0 * kPi)) << n << " bins, bin " << b;
      EXPECT_FALSE(bins.sameWay(h, h + 1.1 * quarter)) << n << " bins, bin " << b;
      EXPECT_FALSE(bins.sameWay(h, bins.heading(b + 1) - 0.5 * bins.width())) << n << " bins, bin " << b;
    }
  }
}

}  // namespace
}  // namespace laser_features
