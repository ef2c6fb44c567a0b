// The motion and measurement models of the stochastic map (Tomatis et al. 2001, sec. 3.4, after
// Smith, Self & Cheeseman), written once on top of the shared planar geometry of laser_features:
// the robot moves by compounding odometry increments (eqs. 7–8), a map line is predicted in the
// sensor frame (eq. 12) and an observed line is brought into the place frame (eqs. 9–11).
//
// The laser may be mounted off the robot's base: its pose on the robot, `sensor_in_robot`, is
// compounded with the robot pose, and every Jacobian here is with respect to the ROBOT pose (the
// chain rule through robot (+) sensor is applied inside).
#pragma once

#include <laser_features/geometry.h>
#include <laser_features/line_extractor.h>

#include <Eigen/Core>

namespace ekf_local_map {

using laser_features::Line;
using laser_features::LineSegment;
using laser_features::Matrix23d;
using laser_features::Pose2D;

/// Eq. 7: the robot pose after an odometry increment, robot (+) increment. F = d/d(robot),
/// G = d/d(increment) (eq. 8 uses them to propagate the covariance).
Pose2D predictRobotPose(const Pose2D& robot, const Pose2D& increment, Eigen::Matrix3d* F = nullptr,
                        Eigen::Matrix3d* G = nullptr);

/// The sensor's pose in the place frame, robot (+) sensor_in_robot, with its Jacobian w.r.t. the
/// robot pose (computed once per scan, shared by all line predictions).
struct SensorPose {
  Pose2D pose;
  Eigen::Matrix3d J_robot = Eigen::Matrix3d::Identity();  // d(robot (+) sensor)/d(robot)
};
SensorPose sensorPose(const Pose2D& robot, const Pose2D& sensor_in_robot);

/// Eq. 12 for a precomputed sensor pose (see below).
Line predictLineInSensor(const Line& map_line, const SensorPose& sensor, Eigen::Matrix2d* J_line,
                         Matrix23d* J_robot);

/// Eq. 12: a map line (place frame) as the sensor would measure it, canonical (r >= 0).
/// J_line = dh/d(alpha, r) of the map line, J_robot = dh/d(x, y, theta) of the robot pose.
/// The returned covariance is not meaningful (the filter assembles H P H^T itself).
Line predictLineInSensor(const Line& map_line, const Pose2D& robot, const Pose2D& sensor_in_robot,
                         Eigen::Matrix2d* J_line = nullptr, Matrix23d* J_robot = nullptr);

/// Eqs. 9–11: a line observed in the sensor frame, expressed in the place frame, canonical.
/// J_observation = d/d(alpha, r) of the observation, J_robot = d/d(x, y, theta) of the robot pose.
Line lineFromSensorToPlace(const Line& observed, const Pose2D& robot, const Pose2D& sensor_in_robot,
                           Eigen::Matrix2d* J_observation = nullptr, Matrix23d* J_robot = nullptr);

/// Eq. 13: the innovation nu = z - h of an observed line against a predicted one, taken by
/// laser_features::lineDifference (angle wrapped, and against (alpha + pi, -r) when that
/// representation of the prediction is closer, which happens for lines passing near the sensor).
/// In that case nu depends on h through -diag(1, -1), so the filter's H must be premultiplied by
/// `jacobian_sign` = diag(1, -1); otherwise it is the identity.
struct LineInnovation {
  Eigen::Vector2d nu = Eigen::Vector2d::Zero();
  bool flipped = false;  // compared with the prediction's other representation
  Eigen::Matrix2d jacobianSign() const {
    return Eigen::Vector2d(1.0, flipped ? -1.0 : 1.0).asDiagonal();
  }
};
LineInnovation lineInnovation(const Line& observed, const Line& predicted);

/// Why an observation cannot be fused at all.
enum class ObservationDefect {
  kNone,
  kNotFinite,                       // NaN or infinity in alpha, r, the covariance or the end points
  kCovarianceNotPositiveDefinite,   // the 2x2 covariance is not symmetric positive definite
};
ObservationDefect checkObservation(const LineSegment& observation);

/// Squared Mahalanobis distance nu^T S^-1 nu for a 2x2 S; +infinity when S is not positive definite.
double mahalanobisSq(const Eigen::Vector2d& nu, const Eigen::Matrix2d& S);

}  // namespace ekf_local_map
