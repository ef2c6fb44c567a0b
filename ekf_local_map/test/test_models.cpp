// The motion and measurement models: Jacobians of the prediction (eqs. 7–8), of the measurement
// prediction (eq. 12) and of a new line (eqs. 9–11) against central finite differences, with a
// sensor mounted off the robot's base; the innovation's sign for the flipped representation; the
// observation checks; the odometry noise model against Monte Carlo samples of the wheel model;
// the chi-square quantiles against tables.
#include "laser_features/testing/numeric_jacobian.h"
#include "laser_features/chi_square.h"
#include "ekf_local_map/measurement_model.h"
#include "ekf_local_map/odometry_noise.h"

#include "simulated_room.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace ekf_local_map {
namespace {

using laser_features::normalizeAngle;
using namespace testing_support;

constexpr double kJacobianTol = 1e-6;
using laser_features::testing::lineParamDifference;
using laser_features::testing::numericJacobian;
using laser_features::testing::poseDifference;
using laser_features::testing::toPose;
using laser_features::testing::toVector;

class RandomModels : public ::testing::Test {
 protected:
  std::mt19937 rng{7};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  Pose2D randomPose(double extent = 5.0) {
    return {uniform(-extent, extent), uniform(-extent, extent), uniform(-kPi, kPi)};
  }
  Pose2D randomSensorMount() { return {uniform(-0.3, 0.3), uniform(-0.2, 0.2), uniform(-kPi, kPi)}; }
  Line randomLine() { return {uniform(-kPi, kPi), uniform(0.5, 8.0), Eigen::Matrix2d::Identity() * 1e-4}; }
};

TEST_F(RandomModels, PredictionJacobiansMatchFiniteDifferences) {  // eqs. 7–8
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2D robot = randomPose();
    const Pose2D increment{uniform(-0.3, 0.3), uniform(-0.1, 0.1), uniform(-0.5, 0.5)};
    Eigen::Matrix3d F, G;
    predictRobotPose(robot, increment, &F, &G);
    const auto diff = [](const Pose2D& a, const Pose2D& b) { return poseDifference(a, b); };
    const Eigen::Matrix3d F_num = numericJacobian<3, 3>(
        [&](const Eigen::Vector3d& v) { return predictRobotPose(toPose(v), increment); }, diff, toVector(robot));
    const Eigen::Matrix3d G_num = numericJacobian<3, 3>(
        [&](const Eigen::Vector3d& v) { return predictRobotPose(robot, toPose(v)); }, diff, toVector(increment));
    EXPECT_LT((F - F_num).cwiseAbs().maxCoeff(), kJacobianTol) << "trial " << trial;
    EXPECT_LT((G - G_num).cwiseAbs().maxCoeff(), kJacobianTol) << "trial " << trial;
  }
}

TEST_F(RandomModels, MeasurementPredictionJacobiansMatchFiniteDifferences) {  // eq. 12
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Pose2D robot = randomPose();
    const Pose2D mount = randomSensorMount();
    const Line map_line = randomLine();
    Eigen::Matrix2d J_line;
    Matrix23d J_robot;
    const Line h = predictLineInSensor(map_line, robot, mount, &J_line, &J_robot);
    if (h.r < 0.05) continue;  // the r-sign flip is not differentiable at r = 0
    const Eigen::Matrix<double, 2, 3> J_robot_num = numericJacobian<2, 3>(
        [&](const Eigen::Vector3d& v) { return predictLineInSensor(map_line, toPose(v), mount); },
        lineParamDifference, toVector(robot));
    const Eigen::Matrix2d J_line_num = numericJacobian<2, 2>(
        [&](const Eigen::Vector2d& v) { return predictLineInSensor({v.x(), v.y(), {}}, robot, mount); },
        lineParamDifference, Eigen::Vector2d(map_line.alpha, map_line.r));
    EXPECT_LT((J_robot - J_robot_num).cwiseAbs().maxCoeff(), kJacobianTol) << "trial " << trial;
    EXPECT_LT((J_line - J_line_num).cwiseAbs().maxCoeff(), kJacobianTol) << "trial " << trial;
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

TEST_F(RandomModels, NewLineJacobiansMatchFiniteDifferences) {  // eqs. 9–11
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Pose2D robot = randomPose();
    const Pose2D mount = randomSensorMount();
    const Line observed = randomLine();
    Eigen::Matrix2d J_obs;
    Matrix23d J_robot;
    const Line in_place = lineFromSensorToPlace(observed, robot, mount, &J_obs, &J_robot);
    if (in_place.r < 0.05) continue;
    const Eigen::Matrix<double, 2, 3> J_robot_num = numericJacobian<2, 3>(
        [&](const Eigen::Vector3d& v) { return lineFromSensorToPlace(observed, toPose(v), mount); },
        lineParamDifference, toVector(robot));
    const Eigen::Matrix2d J_obs_num = numericJacobian<2, 2>(
        [&](const Eigen::Vector2d& v) { return lineFromSensorToPlace({v.x(), v.y(), {}}, robot, mount); },
        lineParamDifference, Eigen::Vector2d(observed.alpha, observed.r));
    EXPECT_LT((J_robot - J_robot_num).cwiseAbs().maxCoeff(), kJacobianTol) << "trial " << trial;
    EXPECT_LT((J_obs - J_obs_num).cwiseAbs().maxCoeff(), kJacobianTol) << "trial " << trial;
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

TEST_F(RandomModels, NewLineInvertsPrediction) {
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2D robot = randomPose();
    const Pose2D mount = randomSensorMount();
    const Line map_line = randomLine();
    const Line back = lineFromSensorToPlace(predictLineInSensor(map_line, robot, mount), robot, mount);
    EXPECT_LT(lineParamDifference(back, map_line).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(LineInnovation, SignOfTheFlippedRepresentation) {
  // Predicted line just beside the sensor; the observation lands on the other side (r changes
  // sign, alpha jumps by pi). The innovation is small and its Jacobian w.r.t. h is -diag(1, -1).
  const Line predicted{0.5 * kPi, 0.004, {}};
  const Line observed{-0.5 * kPi + 0.002, 0.003, {}};
  const LineInnovation innovation = lineInnovation(observed, predicted);
  EXPECT_TRUE(innovation.flipped);
  EXPECT_NEAR(innovation.nu.x(), 0.002, 1e-12);
  EXPECT_NEAR(innovation.nu.y(), 0.007, 1e-12);
  EXPECT_DOUBLE_EQ(innovation.jacobianSign()(1, 1), -1.0);
  // d nu / d h numerically, on the flipped branch.
  const double eps = 1e-7;
  const Line h_plus{predicted.alpha, predicted.r + eps, {}};
  const double dnu_r_dr = (lineInnovation(observed, h_plus).nu.y() - innovation.nu.y()) / eps;
  EXPECT_NEAR(dnu_r_dr, -innovation.jacobianSign()(1, 1), 1e-6);

  const LineInnovation plain = lineInnovation(Line{0.5 * kPi + 0.001, 1.01, {}}, Line{0.5 * kPi, 1.0, {}});
  EXPECT_FALSE(plain.flipped);
  EXPECT_NEAR(plain.nu.y(), 0.01, 1e-12);
}

TEST(CheckObservation, RejectsNonFiniteAndNonPositiveDefinite) {
  LineSegment good;
  good.line = {0.3, 2.0, Eigen::Vector2d(1e-5, 1e-5).asDiagonal()};
  good.start = {2.0, -1.0};
  good.end = {2.0, 1.0};
  EXPECT_EQ(checkObservation(good), ObservationDefect::kNone);

  LineSegment nan = good;
  nan.line.r = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(checkObservation(nan), ObservationDefect::kNotFinite);
  LineSegment nan_cov = good;
  nan_cov.line.cov(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(checkObservation(nan_cov), ObservationDefect::kNotFinite);
  LineSegment inf_end = good;
  inf_end.end.x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(checkObservation(inf_end), ObservationDefect::kNotFinite);

  LineSegment indefinite = good;
  indefinite.line.cov << 1e-5, 2e-5, 2e-5, 1e-5;  // determinant < 0
  EXPECT_EQ(checkObservation(indefinite), ObservationDefect::kCovarianceNotPositiveDefinite);
  LineSegment negative = good;
  negative.line.cov(0, 0) = -1e-5;
  EXPECT_EQ(checkObservation(negative), ObservationDefect::kCovarianceNotPositiveDefinite);
  LineSegment singular = good;
  singular.line.cov << 1e-5, 1e-5, 1e-5, 1e-5;
  EXPECT_EQ(checkObservation(singular), ObservationDefect::kCovarianceNotPositiveDefinite);
  LineSegment zero = good;
  zero.line.cov.setZero();
  EXPECT_EQ(checkObservation(zero), ObservationDefect::kCovarianceNotPositiveDefinite);
  LineSegment asymmetric = good;
  asymmetric.line.cov(0, 1) = 5e-6;
  EXPECT_EQ(checkObservation(asymmetric), ObservationDefect::kCovarianceNotPositiveDefinite);
}

// ---- odometry noise ---------------------------------------------------------------------------

/// Monte Carlo covariance of the (x, y, theta) increment of the simulator's wheel model (random
/// part only): each wheel's travel with variance k^2 |travel|, mid-point integration.
Eigen::Matrix3d wheelModelCovariance(double ds, double dtheta, double k, double b, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  const double left = ds - 0.5 * b * dtheta, right = ds + 0.5 * b * dtheta;
  const int samples = 200000;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (int i = 0; i < samples; ++i) {
    const double l = left + k * std::sqrt(std::abs(left)) * normal(*rng);
    const double r = right + k * std::sqrt(std::abs(right)) * normal(*rng);
    const double s = 0.5 * (l + r), th = (r - l) / b;
    const Eigen::Vector3d v(s * std::cos(0.5 * th), s * std::sin(0.5 * th), th);
    mean += v;
    second += v * v.transpose();
  }
  mean /= samples;
  return second / samples - mean * mean.transpose();
}

TEST(OdometryNoise, BoundsTheWheelModelAndMatchesItForStraightDrivesAndTurns) {
  std::mt19937 rng(3);
  OdometryNoise model = OdometryNoise::fromWheelModel(0.005, 0.40, 1.0);
  model.translation_var_floor = model.rotation_var_floor = 0.0;
  struct Motion { double ds, dtheta; const char* name; };
  for (const Motion& m : {Motion{0.06, 0.0, "straight"}, Motion{0.0, 0.15, "turn on the spot"},
                          Motion{0.06, 0.1, "arc"}, Motion{-0.05, -0.05, "backwards arc"},
                          Motion{0.01, 0.2, "tight turn"}}) {
    const Eigen::Matrix3d empirical = wheelModelCovariance(m.ds, m.dtheta, 0.005, 0.40, &rng);
    const Eigen::Matrix3d Q = model.covariance(arcIncrement(m.ds, m.dtheta));
    // Q >= empirical along every direction the wheel noise excites (within Monte Carlo error).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(empirical);
    for (int i = 0; i < 3; ++i) {
      if (eigen.eigenvalues()(i) < 1e-3 * eigen.eigenvalues().maxCoeff()) continue;
      const Eigen::Vector3d v = eigen.eigenvectors().col(i);
      EXPECT_GE(v.dot(Q * v), 0.97 * v.dot(empirical * v)) << m.name << ", direction " << v.transpose();
    }
    // Never grossly pessimistic: at most twice the variance (sum instead of max).
    EXPECT_LE(Q(2, 2), 2.05 * empirical(2, 2)) << m.name;
  }
  // Exact for a straight drive (x and theta variances) and for a turn on the spot.
  const Eigen::Matrix3d straight = wheelModelCovariance(0.1, 0.0, 0.005, 0.40, &rng);
  const Eigen::Matrix3d Q_straight = model.covariance({0.1, 0.0, 0.0});
  EXPECT_NEAR(Q_straight(0, 0) / straight(0, 0), 1.0, 0.03);
  EXPECT_NEAR(Q_straight(2, 2) / straight(2, 2), 1.0, 0.03);
  const Eigen::Matrix3d spin = wheelModelCovariance(0.0, 0.3, 0.005, 0.40, &rng);
  EXPECT_NEAR(model.covariance({0.0, 0.0, 0.3})(2, 2) / spin(2, 2), 1.0, 0.03);
}

TEST(OdometryNoise, DefaultsAreTheSimulatorsWheelModelWithFloorsAndInflation) {
  const OdometryNoise defaults;
  const OdometryNoise wheel = OdometryNoise::fromWheelModel(0.005, 0.40);
  EXPECT_DOUBLE_EQ(defaults.translation_var_per_meter, wheel.translation_var_per_meter);
  EXPECT_DOUBLE_EQ(defaults.translation_var_per_radian, wheel.translation_var_per_radian);
  EXPECT_DOUBLE_EQ(defaults.rotation_var_per_meter, wheel.rotation_var_per_meter);
  EXPECT_DOUBLE_EQ(defaults.rotation_var_per_radian, wheel.rotation_var_per_radian);
  // Standing still: the floors only, scaled by the inflation, positive definite.
  const Eigen::Matrix3d still = defaults.covariance({0, 0, 0});
  EXPECT_NEAR(still(0, 0), defaults.inflation * defaults.translation_var_floor, 1e-20);
  EXPECT_NEAR(still(2, 2), defaults.inflation * defaults.rotation_var_floor, 1e-20);
  EXPECT_GT(still.determinant(), 0.0);
  // Proportional to the inflation.
  OdometryNoise doubled = defaults;
  doubled.inflation = 2.0 * defaults.inflation;
  const Pose2D step{0.06, 0.001, 0.05};
  EXPECT_LT((doubled.covariance(step) - 2.0 * defaults.covariance(step)).norm(), 1e-18);
}

// ---- chi-square ----------------------------------------------------------------------------

TEST(ChiSquare, QuantilesMatchTables) {
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.95, 2), 5.991, 1e-3);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.9999, 2), 18.421, 1e-3);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.95, 3), 7.815, 0.01 * 7.815);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.99, 6), 16.812, 0.01 * 16.812);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.99, 20), 37.566, 0.01 * 37.566);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.025, 150), 117.98, 0.005 * 117.98);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.975, 150), 185.80, 0.005 * 185.80);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.025, 100), 74.22, 0.005 * 74.22);
  EXPECT_NEAR(laser_features::chiSquareQuantile(0.975, 100), 129.56, 0.005 * 129.56);
  EXPECT_NEAR(laser_features::normalQuantile(0.975), 1.959964, 1e-6);
  EXPECT_NEAR(laser_features::normalQuantile(0.001), -3.090232, 1e-6);
}

}  // namespace
}  // namespace ekf_local_map
