// Geometry: angle wrapping, pose compounding, line transforms and their Jacobians checked against
// central finite differences, transform round trips, the r-sign flip, Mahalanobis wrap-around.
#include "laser_features/testing/numeric_jacobian.h"
#include "laser_features/geometry.h"
#include "laser_features/planar_covariance.h"

#include <gtest/gtest.h>

#include <array>
#include <random>

namespace laser_features {
namespace {

constexpr double kJacobianTol = 1e-6;
using laser_features::testing::lineParamDifference;
using laser_features::testing::numericJacobian;
using laser_features::testing::poseDifference;
using laser_features::testing::toPose;
using laser_features::testing::toVector;

class RandomGeometry : public ::testing::Test {
 protected:
  std::mt19937 rng{42};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  Pose2D randomPose() { return {uniform(-5, 5), uniform(-5, 5), uniform(-kPi, kPi)}; }
  Line randomLine() {
    Line line;
    line.alpha = uniform(-kPi, kPi);
    line.r = uniform(0.2, 8.0);
    Eigen::Matrix2d A;
    A << uniform(-0.1, 0.1), uniform(-0.1, 0.1), uniform(-0.1, 0.1), uniform(-0.1, 0.1);
    line.cov = A * A.transpose() + 1e-4 * Eigen::Matrix2d::Identity();
    return line;
  }
};

TEST(NormalizeAngle, WrapsToHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(normalizeAngle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(normalizeAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(normalizeAngle(-kPi), kPi);  // -pi is excluded
  EXPECT_NEAR(normalizeAngle(3.0 * kPi), kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-3.0 * kPi), kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(kTwoPi), 0.0, 1e-12);
  EXPECT_NEAR(normalizeAngle(-1.5 * kPi), 0.5 * kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(2.5 * kPi), 0.5 * kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-kPi - 1e-9), kPi - 1e-9, 1e-12);
  const double big = normalizeAngle(1e6);
  EXPECT_GT(big, -kPi);
  EXPECT_LE(big, kPi);
  EXPECT_NEAR(std::sin(big), std::sin(1e6), 1e-9);
  EXPECT_TRUE(std::isnan(normalizeAngle(std::numeric_limits<double>::quiet_NaN())));
}

TEST_F(RandomGeometry, ComposeAndInverseRoundTrip) {
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2D a = randomPose(), b = randomPose();
    const Pose2D identity = compose(a, inverse(a));
    EXPECT_NEAR(identity.x, 0.0, 1e-12);
    EXPECT_NEAR(identity.y, 0.0, 1e-12);
    EXPECT_NEAR(identity.theta, 0.0, 1e-12);
    const Pose2D back = compose(inverse(a), compose(a, b));
    EXPECT_LT(poseDifference(back, b).norm(), 1e-12);
    EXPECT_LT(poseDifference(inverse(inverse(a)), a).norm(), 1e-12);
    // transformPoint agrees with compose on the translation.
    const Eigen::Vector2d p = transformPoint(a, b.translation());
    EXPECT_LT((p - compose(a, b).translation()).norm(), 1e-12);
  }
}

TEST_F(RandomGeometry, ComposeJacobiansMatchNumeric) {
  for (int trial = 0; trial < 50; ++trial) {
    const Pose2D a = randomPose(), b = randomPose();
    Eigen::Matrix3d J_a, J_b;
    compose(a, b, &J_a, &J_b);
    const auto diff = [](const Pose2D& p, const Pose2D& q) { return poseDifference(p, q); };
    const auto numeric_a = numericJacobian<3, 3>([&](const Eigen::Vector3d& v) { return compose(toPose(v), b); },
                                                 diff, toVector(a));
    const auto numeric_b = numericJacobian<3, 3>([&](const Eigen::Vector3d& v) { return compose(a, toPose(v)); },
                                                 diff, toVector(b));
    EXPECT_LT((J_a - numeric_a).norm(), kJacobianTol) << J_a << "\n" << numeric_a;
    EXPECT_LT((J_b - numeric_b).norm(), kJacobianTol);
  }
}

TEST_F(RandomGeometry, InverseJacobianMatchesNumeric) {
  for (int trial = 0; trial < 50; ++trial) {
    const Pose2D a = randomPose();
    Eigen::Matrix3d J;
    inverse(a, &J);
    const auto numeric = numericJacobian<3, 3>(
        [&](const Eigen::Vector3d& v) { return inverse(toPose(v)); },
        [](const Pose2D& p, const Pose2D& q) { return poseDifference(p, q); }, toVector(a));
    EXPECT_LT((J - numeric).norm(), kJacobianTol);
  }
}

TEST_F(RandomGeometry, TransformPointJacobianMatchesNumeric) {
  for (int trial = 0; trial < 50; ++trial) {
    const Pose2D frame = randomPose();
    const Eigen::Vector2d p(uniform(-5, 5), uniform(-5, 5));
    Matrix23d J;
    transformPoint(frame, p, &J);
    const auto numeric = numericJacobian<2, 3>(
        [&](const Eigen::Vector3d& v) { return transformPoint(toPose(v), p); },
        [](const Eigen::Vector2d& u, const Eigen::Vector2d& w) { return Eigen::Vector2d(u - w); },
        toVector(frame));
    EXPECT_LT((J - numeric).norm(), kJacobianTol);
  }
}

TEST(Canonicalize, FlipsNegativeRAndCovariance) {
  Line line;
  line.alpha = 0.3;
  line.r = -2.0;
  line.cov << 0.01, 0.002, 0.002, 0.04;
  Eigen::Matrix2d J;
  EXPECT_TRUE(canonicalize(&line, &J));
  EXPECT_NEAR(line.alpha, 0.3 - kPi, 1e-12);  // 0.3 + pi wrapped
  EXPECT_DOUBLE_EQ(line.r, 2.0);
  EXPECT_DOUBLE_EQ(line.cov(0, 1), -0.002);
  EXPECT_DOUBLE_EQ(line.cov(1, 0), -0.002);
  EXPECT_DOUBLE_EQ(line.cov(0, 0), 0.01);
  EXPECT_DOUBLE_EQ(line.cov(1, 1), 0.04);
  EXPECT_EQ(J, (Eigen::Matrix2d() << 1, 0, 0, -1).finished());

  Line positive;
  positive.alpha = 4.0;  // only wrapped
  positive.r = 1.0;
  EXPECT_FALSE(canonicalize(&positive, &J));
  EXPECT_NEAR(positive.alpha, 4.0 - kTwoPi, 1e-12);
  EXPECT_EQ(J, Eigen::Matrix2d::Identity());
}

TEST_F(RandomGeometry, LineThroughPointsContainsBoth) {
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector2d p(uniform(-5, 5), uniform(-5, 5)), q(uniform(-5, 5), uniform(-5, 5));
    const Line line = lineThroughPoints(p, q);
    EXPECT_GE(line.r, 0.0);
    EXPECT_GT(line.alpha, -kPi);
    EXPECT_LE(line.alpha, kPi);
    EXPECT_NEAR(signedDistanceToLine(line, p), 0.0, 1e-12);
    EXPECT_NEAR(signedDistanceToLine(line, q), 0.0, 1e-12);
  }
}

TEST_F(RandomGeometry, TransformLineMovesItsPoints) {
  // Points of the world line, expressed in the frame, lie on the transformed line.
  for (int trial = 0; trial < 100; ++trial) {
    const Line world = randomLine();
    const Pose2D frame = randomPose();
    const Line local = transformLineToFrame(world, frame);
    EXPECT_GE(local.r, 0.0);
    for (double s : {-3.0, 0.0, 2.5}) {
      const Eigen::Vector2d p_world = world.r * world.normal() + s * world.direction();
      const Eigen::Vector2d p_local = transformPoint(inverse(frame), p_world);
      EXPECT_NEAR(signedDistanceToLine(local, p_local), 0.0, 1e-9);
    }
  }
}

TEST_F(RandomGeometry, TransformLineRoundTrip) {
  for (int trial = 0; trial < 100; ++trial) {
    const Line world = randomLine();
    const Pose2D frame = randomPose();
    const Line back = transformLineFromFrame(transformLineToFrame(world, frame), frame);
    EXPECT_LT(lineParamDifference(back, world).norm(), 1e-12);
    EXPECT_LT((back.cov - world.cov).norm(), 1e-12);
  }
}

TEST(TransformLine, SignFlipWhenFrameCrossesTheLine) {
  // The wall x = 2 (alpha = 0, r = 2) seen from (3, 0), beyond it, heading 0: the wall is behind,
  // at distance 1: alpha' = pi, r' = 1.
  Line wall;
  wall.alpha = 0.0;
  wall.r = 2.0;
  Eigen::Matrix2d J_line;
  Matrix23d J_pose;
  const Line seen = transformLineToFrame(wall, {3.0, 0.0, 0.0}, &J_line, &J_pose);
  EXPECT_NEAR(seen.alpha, kPi, 1e-12);
  EXPECT_NEAR(seen.r, 1.0, 1e-12);
  // r' = -(r - x cos a - y sin a): dr'/dx = +cos a = 1 after the flip.
  EXPECT_NEAR(J_pose(1, 0), 1.0, 1e-12);
  EXPECT_NEAR(J_line(1, 1), -1.0, 1e-12);
  // Without the flip (frame at (1, 0)): r' = 1, dr'/dx = -1.
  const Line near = transformLineToFrame(wall, {1.0, 0.0, 0.0}, &J_line, &J_pose);
  EXPECT_NEAR(near.alpha, 0.0, 1e-12);
  EXPECT_NEAR(near.r, 1.0, 1e-12);
  EXPECT_NEAR(J_pose(1, 0), -1.0, 1e-12);
}

TEST_F(RandomGeometry, TransformLineJacobiansMatchNumeric) {
  int flipped = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Line world = randomLine();
    const Pose2D frame = randomPose();
    Eigen::Matrix2d J_line;
    Matrix23d J_pose;
    const Line local = transformLineToFrame(world, frame, &J_line, &J_pose);
    if (local.r < 1e-3) continue;  // the derivative is not defined at the flip itself
    flipped += (world.r - frame.x * std::cos(world.alpha) - frame.y * std::sin(world.alpha)) < 0.0;
    const auto diff = [](const Line& a, const Line& b) { return lineParamDifference(a, b); };
    const auto numeric_line = numericJacobian<2, 2>(
        [&](const Eigen::Vector2d& v) {
          Line l = world;
          l.alpha = v.x();
          l.r = v.y();
          return transformLineToFrame(l, frame);
        },
        diff, world.params());
    const auto numeric_pose = numericJacobian<2, 3>(
        [&](const Eigen::Vector3d& v) { return transformLineToFrame(world, toPose(v)); }, diff, toVector(frame));
    EXPECT_LT((J_line - numeric_line).norm(), kJacobianTol);
    EXPECT_LT((J_pose - numeric_pose).norm(), kJacobianTol);
    // The covariance follows J_line.
    EXPECT_LT((local.cov - J_line * world.cov * J_line.transpose()).norm(), 1e-12);
  }
  EXPECT_GT(flipped, 20);  // the flip branch was exercised
}

TEST_F(RandomGeometry, TransformLineFromFrameJacobiansMatchNumeric) {
  int flipped = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Line local = randomLine();
    const Pose2D frame = randomPose();
    Eigen::Matrix2d J_line;
    Matrix23d J_pose;
    const Line world = transformLineFromFrame(local, frame, &J_line, &J_pose);
    if (world.r < 1e-3) continue;
    const double alpha_w = local.alpha + frame.theta;
    flipped += (local.r + frame.x * std::cos(alpha_w) + frame.y * std::sin(alpha_w)) < 0.0;
    const auto diff = [](const Line& a, const Line& b) { return lineParamDifference(a, b); };
    const auto numeric_line = numericJacobian<2, 2>(
        [&](const Eigen::Vector2d& v) {
          Line l = local;
          l.alpha = v.x();
          l.r = v.y();
          return transformLineFromFrame(l, frame);
        },
        diff, local.params());
    const auto numeric_pose = numericJacobian<2, 3>(
        [&](const Eigen::Vector3d& v) { return transformLineFromFrame(local, toPose(v)); }, diff,
        toVector(frame));
    EXPECT_LT((J_line - numeric_line).norm(), kJacobianTol);
    EXPECT_LT((J_pose - numeric_pose).norm(), kJacobianTol);
  }
  EXPECT_GT(flipped, 20);
}

TEST(LineMahalanobis, HandlesAngleWrapAround) {
  Line a, b;
  a.alpha = kPi - 0.01;
  b.alpha = -kPi + 0.01;  // 0.02 rad away through +-pi
  a.r = b.r = 3.0;
  a.cov = b.cov = Eigen::Matrix2d::Identity() * 1e-4;
  EXPECT_NEAR(lineDifference(a, b).x(), -0.02, 1e-12);
  EXPECT_NEAR(lineMahalanobisSq(a, b), 0.02 * 0.02 / 2e-4, 1e-9);
}

TEST(LineMahalanobis, HandlesSignAmbiguityNearOrigin) {
  // A line passing 1 cm from the origin, estimated once on each side of it.
  Line a, b;
  a.alpha = 0.5;
  a.r = 0.01;
  b.alpha = normalizeAngle(0.5 + kPi + 0.001);
  b.r = 0.005;
  a.cov = b.cov = Eigen::Matrix2d::Identity() * 1e-4;
  const Eigen::Vector2d d = lineDifference(a, b);
  EXPECT_NEAR(d.x(), -0.001, 1e-12);
  EXPECT_NEAR(d.y(), 0.015, 1e-12);
  EXPECT_LT(lineMahalanobisSq(a, b), 2.0);
}

TEST(LineMahalanobis, SingularCovarianceIsInfinite) {
  Line a, b;
  a.alpha = b.alpha = 0.1;
  a.r = b.r = 1.0;
  EXPECT_TRUE(std::isinf(lineMahalanobisSq(a, b)));
}

TEST_F(RandomGeometry, IntersectionLiesOnBothLinesAndJacobianMatches) {
  for (int trial = 0; trial < 100; ++trial) {
    const Line a = randomLine(), b = randomLine();
    if (angleBetweenLines(a, b) < 0.2) continue;
    Eigen::Vector2d p;
    Matrix24d J;
    ASSERT_TRUE(intersectLines(a, b, &p, &J));
    EXPECT_NEAR(signedDistanceToLine(a, p), 0.0, 1e-9);
    EXPECT_NEAR(signedDistanceToLine(b, p), 0.0, 1e-9);
    const auto numeric = numericJacobian<2, 4>(
        [&](const Eigen::Vector4d& v) {
          Line la = a, lb = b;
          la.alpha = v(0), la.r = v(1), lb.alpha = v(2), lb.r = v(3);
          Eigen::Vector2d q;
          intersectLines(la, lb, &q);
          return q;
        },
        [](const Eigen::Vector2d& u, const Eigen::Vector2d& w) { return Eigen::Vector2d(u - w); },
        Eigen::Vector4d(a.alpha, a.r, b.alpha, b.r));
    EXPECT_LT((J - numeric).norm(), 1e-5 * (1.0 + J.norm()));
  }
}

TEST(Intersection, ParallelLinesDoNotIntersect) {
  Line a, b;
  a.alpha = 0.2;
  a.r = 1.0;
  b.alpha = 0.2 + kPi;
  b.r = 2.0;
  Eigen::Vector2d p(7, 7);
  EXPECT_FALSE(intersectLines(a, b, &p));
  EXPECT_EQ(p, Eigen::Vector2d(7, 7));
}

TEST(LineHelpers, DistancesAnglesAndRanges) {
  Line wall;  // y = 2
  wall.alpha = 0.5 * kPi;
  wall.r = 2.0;
  EXPECT_NEAR(signedDistanceToLine(wall, {5.0, 3.0}), 1.0, 1e-12);
  EXPECT_NEAR(signedDistanceToLine(wall, {5.0, 0.0}), -2.0, 1e-12);
  EXPECT_LT((projectOntoLine(wall, {5.0, 3.0}) - Eigen::Vector2d(5.0, 2.0)).norm(), 1e-12);
  EXPECT_NEAR(rangeToLine(wall, 0.5 * kPi), 2.0, 1e-12);
  EXPECT_NEAR(rangeToLine(wall, 0.25 * kPi), 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(std::isinf(rangeToLine(wall, -0.5 * kPi)));
  Line other;
  other.alpha = -kPi + 0.1;
  EXPECT_NEAR(angleBetweenLines(wall, other), 0.5 * kPi - 0.1, 1e-12);
  other.alpha = 0.5 * kPi + kPi - 0.05;  // nearly antiparallel normal: the lines are nearly parallel
  EXPECT_NEAR(angleBetweenLines(wall, other), 0.05, 1e-12);
}

}  // namespace
}  // namespace laser_features

// A planar covariance goes into a ROS 6 x 6 pose covariance at x, y and yaw (0, 1, 5), zero
// elsewhere, and comes back out the same.
TEST(PlanarCovariance, XYAndYawOfTheRosSixBySixAndBack) {
  Eigen::Matrix3d m;
  m << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.0025;
  std::array<double, 36> ros{};
  ros.fill(7.0);
  laser_features::setPlanarCovariance(m, &ros);
  EXPECT_DOUBLE_EQ(ros[0], 0.04);
  EXPECT_DOUBLE_EQ(ros[1 * 6 + 5], -0.003);
  EXPECT_DOUBLE_EQ(ros[5 * 6 + 5], 0.0025);
  EXPECT_DOUBLE_EQ(ros[2 * 6 + 2], 0.0) << "z, roll and pitch are zero";
  EXPECT_TRUE(laser_features::planarCovariance(ros).isApprox(m));
}
