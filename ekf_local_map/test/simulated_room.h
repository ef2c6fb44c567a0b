// Test fixtures: rooms made of wall and furniture segments, given directly in the place frame, and
// line observations of them drawn analytically (no ray casting): the true line is transformed into
// the sensor frame, noise drawn from the observation's own covariance is added, and the segment's
// end points are projected onto the noisy line, as laser_features' extractor reports them.
#pragma once

#include "ekf_local_map/odometry_noise.h"
#include "ekf_local_map/stochastic_map.h"

#include <laser_features/geometry.h>
#include <laser_features/line_extractor.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <random>
#include <vector>

namespace ekf_local_map {
namespace testing_support {

using laser_features::kPi;
using laser_features::Line;
using laser_features::LineSegment;
using laser_features::Pose2D;

/// A true wall or furniture edge, place frame.
struct TrueSegment {
  Eigen::Vector2d a, b;
  Line line() const { return laser_features::lineThroughPoints(a, b); }
};

/// A 6 m x 4.5 m room, x in [-2.5, 3.5], y in [-1.5, 3]: 4 walls and 3 furniture edges (a table,
/// a shelf, a cupboard at an angle). The robot starts at the place origin.
inline std::vector<TrueSegment> officeRoom() {
  return {
      {{-2.5, -1.5}, {3.5, -1.5}},  // walls
      {{3.5, -1.5}, {3.5, 3.0}},
      {{3.5, 3.0}, {-2.5, 3.0}},
      {{-2.5, 3.0}, {-2.5, -1.5}},
      {{-2.0, 2.3}, {-0.6, 2.3}},  // table edge
      {{2.8, 0.2}, {2.8, 1.8}},    // shelf
      {{-2.2, 0.4}, {-1.4, -0.6}},  // cupboard, at an angle
  };
}

/// A different room with the same kind of layout but other dimensions (for wrong-room relocation).
inline std::vector<TrueSegment> otherRoom() {
  return {
      {{-2.0, -1.2}, {3.0, -1.2}},
      {{3.0, -1.2}, {3.0, 2.4}},
      {{3.0, 2.4}, {-2.0, 2.4}},
      {{-2.0, 2.4}, {-2.0, -1.2}},
      {{1.0, 1.8}, {2.2, 1.8}},
  };
}

/// Standard deviations of the simulated line observations; they differ per line index so that
/// the filter sees a mix of covariances, with a correlation between alpha and r.
inline Eigen::Matrix2d observationCovariance(size_t index, double scale = 1.0) {
  const double sigma_alpha = scale * (0.002 + 0.001 * double(index % 3));  // rad
  const double sigma_r = scale * (0.003 + 0.001 * double(index % 2));      // m
  const double rho = (index % 2 == 0) ? 0.3 : -0.3;
  Eigen::Matrix2d R;
  R << sigma_alpha * sigma_alpha, rho * sigma_alpha * sigma_r,  //
      rho * sigma_alpha * sigma_r, sigma_r * sigma_r;
  return R;
}

/// A sample of N(0, C).
template <int N>
Eigen::Matrix<double, N, 1> gaussian(const Eigen::Matrix<double, N, N>& C, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, N, 1> z;
  for (int i = 0; i < N; ++i) z(i) = normal(*rng);
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(C);
  return llt.matrixL() * z;
}

/// The observation of one true segment from a sensor at `sensor_pose` (place frame); noise-free
/// when rng is null.
inline LineSegment observeSegment(const TrueSegment& segment, size_t index, const Pose2D& sensor_pose,
                                  std::mt19937* rng, double noise_scale = 1.0) {
  const Pose2D to_sensor = laser_features::inverse(sensor_pose);
  const Eigen::Vector2d a = laser_features::transformPoint(to_sensor, segment.a);
  const Eigen::Vector2d b = laser_features::transformPoint(to_sensor, segment.b);
  LineSegment observation;
  Line line = laser_features::lineThroughPoints(a, b);
  line.cov = observationCovariance(index, noise_scale);
  if (rng) {
    const Eigen::Vector2d noise = gaussian<2>(line.cov, rng);
    line.alpha += noise.x();
    line.r += noise.y();
    laser_features::canonicalize(&line);  // flips the covariance too when r < 0
  }
  observation.line = line;
  observation.start = laser_features::projectOntoLine(line, a);
  observation.end = laser_features::projectOntoLine(line, b);
  observation.num_points = 60;
  return observation;
}

/// Observations of all segments (no occlusion), in the order of `segments`.
inline std::vector<LineSegment> observeAll(const std::vector<TrueSegment>& segments, const Pose2D& robot,
                                           const Pose2D& sensor_in_robot, std::mt19937* rng,
                                           double noise_scale = 1.0) {
  const Pose2D sensor_pose = laser_features::compose(robot, sensor_in_robot);
  std::vector<LineSegment> observations;
  for (size_t i = 0; i < segments.size(); ++i) {
    observations.push_back(observeSegment(segments[i], i, sensor_pose, rng, noise_scale));
  }
  return observations;
}

/// The chord of an arc of length ds turning by dtheta (the true odometry increment).
inline Pose2D arcIncrement(double ds, double dtheta) {
  return {ds * std::cos(0.5 * dtheta), ds * std::sin(0.5 * dtheta), dtheta};
}

/// The increment the odometry reports: the true one plus noise drawn from the noise model.
inline Pose2D noisyIncrement(const Pose2D& truth, const OdometryNoise& noise, std::mt19937* rng) {
  const Eigen::Vector3d e = gaussian<3>(noise.covariance(truth), rng);
  return {truth.x + e.x(), truth.y + e.y(), truth.theta + e.z()};
}

inline double minEigenvalue(const Eigen::MatrixXd& P) {
  const Eigen::MatrixXd S = 0.5 * (P + P.transpose());
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
}

/// Positive semi-definite within rounding relative to the largest diagonal entry.
inline bool positiveSemiDefinite(const Eigen::MatrixXd& P) {
  return P.allFinite() && minEigenvalue(P) >= -1e-12 * std::max(1.0, P.diagonal().maxCoeff());
}

inline double positionError(const Pose2D& a, const Pose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }

/// The noise model the tests draw odometry from (the filter is given the same: no inflation).
inline OdometryNoise testOdometryNoise() {
  OdometryNoise noise;
  noise.inflation = 1.0;
  return noise;
}

/// Filter parameters matching the simulated observations (no extra floor on their covariance).
inline StochasticMapParams testParams() {
  StochasticMapParams params;
  params.observation_alpha_sigma_floor = 0.0;
  params.observation_r_sigma_floor = 0.0;
  return params;
}

}  // namespace testing_support
}  // namespace ekf_local_map
