// Corners: position, free-space orientation, convexity, covariance (against numeric propagation and
// by NEES over noisy trials) and the rejection of shallow or open angles.
#include "laser_features/corner_extractor.h"
#include "laser_features/feature_extractor.h"

#include "synthetic_scan.h"
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <random>

namespace laser_features {
namespace {

using namespace synthetic;

constexpr double kSigma = 0.01;

Features extractFeatures(const World& world, const Pose2D& sensor, const ScanSpec& spec, std::mt19937* rng) {
  const std::vector<float> ranges = simulateScan(world, sensor, spec, kSigma, rng);
  FeatureExtractor extractor;
  Features features;
  std::string error;
  EXPECT_TRUE(extractor.extract(makeView(spec, ranges), &features, &error)) << error;
  return features;
}

/// The corner nearest to `p` (sensor frame), or nullptr when none is within 0.2 m.
const Corner* cornerNear(const Features& features, const Eigen::Vector2d& p) {
  const Corner* best = nullptr;
  double best_distance = 0.2;
  for (const Corner& corner : features.corners) {
    const double distance = (corner.position - p).norm();
    if (distance < best_distance) best_distance = distance, best = &corner;
  }
  return best;
}

TEST(CornerExtractor, FindsTheFourConcaveCornersOfARoom) {
  const World room = rectangularRoom(6.0, 4.0);
  const Pose2D sensor{2.2, 1.7, 0.3};
  std::mt19937 rng(1);
  const Features features = extractFeatures(room, sensor, ScanSpec::full(720), &rng);
  EXPECT_EQ(features.corners.size(), 4u);
  // World corners and the direction into the room from each.
  const std::vector<std::pair<Eigen::Vector2d, double>> truth = {
      {{0, 0}, kPi / 4}, {{6, 0}, 3 * kPi / 4}, {{6, 4}, -3 * kPi / 4}, {{0, 4}, -kPi / 4}};
  for (const auto& [world_corner, world_direction] : truth) {
    const Eigen::Vector2d p = pointInSensorFrame(world_corner, sensor);
    const Corner* corner = cornerNear(features, p);
    ASSERT_NE(corner, nullptr) << world_corner.transpose();
    EXPECT_LT((corner->position - p).norm(), 0.02);
    EXPECT_FALSE(corner->convex);
    EXPECT_NEAR(normalizeAngle(corner->theta - (world_direction - sensor.theta)), 0.0, 0.02);
    EXPECT_GT(corner->confidence, 0.5);
    EXPECT_LE(corner->confidence, 1.0);
  }
}

TEST(CornerExtractor, FindsConvexCornerOfABox) {
  World world = rectangularRoom(8.0, 6.0);
  world.addBox(4.0, 3.3, 1.0, 1.0);  // corner (3.5, 2.8) juts towards the sensor
  const Pose2D sensor{1.5, 1.2, 0.0};
  std::mt19937 rng(2);
  const Features features = extractFeatures(world, sensor, ScanSpec::full(1440), &rng);
  const Eigen::Vector2d p = pointInSensorFrame({3.5, 2.8}, sensor);
  const Corner* corner = cornerNear(features, p);
  ASSERT_NE(corner, nullptr);
  EXPECT_TRUE(corner->convex);
  EXPECT_LT((corner->position - p).norm(), 0.03);
  EXPECT_NEAR(normalizeAngle(corner->theta - (-3 * kPi / 4)), 0.0, 0.03);  // away from the box
  // The room's corners stay concave.
  for (const Eigen::Vector2d& room_corner : {Eigen::Vector2d(0, 0), Eigen::Vector2d(8, 0)}) {
    const Corner* inner = cornerNear(features, pointInSensorFrame(room_corner, sensor));
    ASSERT_NE(inner, nullptr);
    EXPECT_FALSE(inner->convex);
  }
}

LineSegment segmentFromPoints(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double sigma_alpha, double sigma_r) {
  LineSegment segment;
  segment.line = lineThroughPoints(a, b);
  segment.line.cov << sigma_alpha * sigma_alpha, 0.3 * sigma_alpha * sigma_r, 0.3 * sigma_alpha * sigma_r,
      sigma_r * sigma_r;
  segment.start = projectOntoLine(segment.line, a);
  segment.end = projectOntoLine(segment.line, b);
  segment.num_points = 50;
  return segment;
}

TEST(CornerExtractor, CovarianceMatchesNumericPropagation) {
  // An inner corner at (3, 2) of the walls x = 3 and y = 2, at 80 degrees to each other.
  const LineSegment a = segmentFromPoints({3.0, -1.0}, {3.0, 2.0}, 0.002, 0.003);
  const LineSegment b = segmentFromPoints({3.0 + 2.0 * std::cos(0.17), 2.0 - 2.0 * std::sin(0.17) + 0.0}, {3.0, 2.0}, 0.004, 0.002);
  CornerExtractor extractor;
  Corner corner;
  ASSERT_TRUE(extractor.makeCorner(a, b, &corner));
  // Numeric Jacobian of (x, y, theta) with respect to (alpha_a, r_a, alpha_b, r_b).
  Eigen::Matrix<double, 3, 4> J;
  const Eigen::Vector4d x0(a.line.alpha, a.line.r, b.line.alpha, b.line.r);
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector3d values[2];
    for (int side = 0; side < 2; ++side) {
      Eigen::Vector4d x = x0;
      x(k) += side == 0 ? 1e-6 : -1e-6;
      LineSegment pa = a, pb = b;
      pa.line.alpha = x(0), pa.line.r = x(1), pb.line.alpha = x(2), pb.line.r = x(3);
      Corner perturbed;
      ASSERT_TRUE(extractor.makeCorner(pa, pb, &perturbed));
      values[side] = Eigen::Vector3d(perturbed.position.x(), perturbed.position.y(), perturbed.theta);
    }
    J.col(k) = (values[0] - values[1]) / 2e-6;
    J(2, k) = normalizeAngle(values[0].z() - values[1].z()) / 2e-6;
  }
  Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
  C.topLeftCorner<2, 2>() = a.line.cov;
  C.bottomRightCorner<2, 2>() = b.line.cov;
  const Eigen::Matrix3d expected = J * C * J.transpose();
  EXPECT_LT((corner.cov - expected).norm(), 1e-6 * expected.norm()) << corner.cov << "\n\n" << expected;
}

TEST(CornerExtractor, CovarianceIsConsistentNees) {
  const World room = rectangularRoom(6.0, 4.0);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> x(1.2, 4.8), y(1.2, 2.8), heading(-kPi, kPi);
  double nees_sum = 0.0;
  int count = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2D sensor{x(rng), y(rng), heading(rng)};
    const Features features = extractFeatures(room, sensor, ScanSpec::full(720), &rng);
    const Eigen::Vector2d world_corner(6.0, 4.0);
    const Corner* corner = cornerNear(features, pointInSensorFrame(world_corner, sensor));
    ASSERT_NE(corner, nullptr);
    const Eigen::Vector2d p = pointInSensorFrame(world_corner, sensor);
    const Eigen::Vector3d error(corner->position.x() - p.x(), corner->position.y() - p.y(),
                                normalizeAngle(corner->theta - (-3 * kPi / 4 - sensor.theta)));
    nees_sum += error.dot(corner->cov.inverse() * error);
    ++count;
  }
  const double mean = nees_sum / count;
  std::printf("corner mean NEES (3 dof): %.3f\n", mean);
  EXPECT_GE(mean, 2.2);
  EXPECT_LE(mean, 3.9);
}

TEST(CornerExtractor, RejectsShallowAnglesAndDistantEnds) {
  CornerExtractor extractor;
  Corner corner;
  // A 160-degree bend: the lines meet at 20 degrees, below the 30-degree threshold.
  const LineSegment a = segmentFromPoints({3.0, -2.0}, {3.0, 1.0}, 0.001, 0.001);
  const LineSegment shallow =
      segmentFromPoints({3.0, 1.0}, {3.0 - 2.0 * std::sin(0.35), 1.0 + 2.0 * std::cos(0.35)}, 0.001, 0.001);
  EXPECT_FALSE(extractor.makeCorner(a, shallow, &corner));
  // Perpendicular, but the second segment starts 0.5 m from the intersection.
  const LineSegment far = segmentFromPoints({2.5, 1.0}, {0.5, 1.0}, 0.001, 0.001);
  EXPECT_FALSE(extractor.makeCorner(a, far, &corner));
  const LineSegment near = segmentFromPoints({2.9, 1.0}, {0.5, 1.0}, 0.001, 0.001);
  EXPECT_TRUE(extractor.makeCorner(a, near, &corner));
  EXPECT_FALSE(corner.convex);
}

}  // namespace
}  // namespace laser_features
