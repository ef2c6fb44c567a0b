#include "ekf_local_map/measurement_model.h"

#include <cmath>
#include <limits>

namespace ekf_local_map {

using laser_features::compose;
using laser_features::normalizeAngle;

Pose2D predictRobotPose(const Pose2D& robot, const Pose2D& increment, Eigen::Matrix3d* F,
                        Eigen::Matrix3d* G) {
  return compose(robot, increment, F, G);
}

SensorPose sensorPose(const Pose2D& robot, const Pose2D& sensor_in_robot) {
  SensorPose sensor;
  sensor.pose = compose(robot, sensor_in_robot, &sensor.J_robot);
  return sensor;
}

Line predictLineInSensor(const Line& map_line, const SensorPose& sensor, Eigen::Matrix2d* J_line,
                         Matrix23d* J_robot) {
  // laser_features::transformLineToFrame written out for this hot path (once per map line and
  // scan), with the chain rule through robot (+) sensor applied to the sparse d(h)/d(sensor) = diag(1, sign) [0 0 -1; -cos(alpha) -sin(alpha) 0]. Same values
  // (the dropped terms are exact zeros).
  const double c = std::cos(map_line.alpha);
  const double s = std::sin(map_line.alpha);
  const Pose2D& frame = sensor.pose;
  Line predicted;
  predicted.alpha = map_line.alpha - frame.theta;
  predicted.r = map_line.r - frame.x * c - frame.y * s;
  const bool flip = predicted.r < 0.0;  // canonical form r >= 0: (alpha + pi, -r)
  if (flip) {
    predicted.alpha += laser_features::kPi;
    predicted.r = -predicted.r;
  }
  predicted.alpha = normalizeAngle(predicted.alpha);
  const double sign = flip ? -1.0 : 1.0;
  Eigen::Matrix2d Jl;
  Jl << 1.0, 0.0, sign * (frame.x * s - frame.y * c), sign;
  predicted.cov = Jl * map_line.cov * Jl.transpose();  // as transformLineToFrame (zero in the filter)
  if (J_line) *J_line = Jl;
  if (J_robot) {
    const Eigen::Matrix3d& J = sensor.J_robot;
    J_robot->row(0) = -J.row(2);
    J_robot->row(1) = (sign * -c) * J.row(0) + (sign * -s) * J.row(1);
  }
  return predicted;
}

Line predictLineInSensor(const Line& map_line, const Pose2D& robot, const Pose2D& sensor_in_robot,
                         Eigen::Matrix2d* J_line, Matrix23d* J_robot) {
  return predictLineInSensor(map_line, sensorPose(robot, sensor_in_robot), J_line, J_robot);
}

Line lineFromSensorToPlace(const Line& observed, const Pose2D& robot, const Pose2D& sensor_in_robot,
                           Eigen::Matrix2d* J_observation, Matrix23d* J_robot) {
  Eigen::Matrix3d J_sensor_robot;
  const Pose2D sensor = compose(robot, sensor_in_robot, &J_sensor_robot);
  Matrix23d J_sensor;
  const Line in_place = laser_features::transformLineFromFrame(observed, sensor, J_observation, &J_sensor);
  if (J_robot) *J_robot = J_sensor * J_sensor_robot;
  return in_place;
}

LineInnovation lineInnovation(const Line& observed, const Line& predicted) {
  LineInnovation innovation;
  innovation.nu = laser_features::lineDifference(observed, predicted);
  // lineDifference either subtracted (alpha, r) or (alpha + pi, -r): the angle parts differ by pi.
  const double plain_angle = normalizeAngle(observed.alpha - predicted.alpha);
  innovation.flipped = std::abs(normalizeAngle(innovation.nu.x() - plain_angle)) > 0.5 * laser_features::kPi;
  return innovation;
}

ObservationDefect checkObservation(const LineSegment& observation) {
  const Line& line = observation.line;
  if (!std::isfinite(line.alpha) || !std::isfinite(line.r) || !line.cov.allFinite() ||
      !observation.start.allFinite() || !observation.end.allFinite()) {
    return ObservationDefect::kNotFinite;
  }
  const Eigen::Matrix2d& C = line.cov;
  const double asymmetry = std::abs(C(0, 1) - C(1, 0));
  const double scale = std::abs(C(0, 0)) + std::abs(C(1, 1));
  const double det = C(0, 0) * C(1, 1) - C(0, 1) * C(1, 0);
  // Positive definite: positive diagonal and determinant (relative to the scale, so that a
  // numerically singular matrix is not accepted either).
  if (!(C(0, 0) > 0.0) || !(C(1, 1) > 0.0) || !(det > 1e-12 * scale * scale) ||
      asymmetry > 1e-9 * scale) {
    return ObservationDefect::kCovarianceNotPositiveDefinite;
  }
  return ObservationDefect::kNone;
}

double mahalanobisSq(const Eigen::Vector2d& nu, const Eigen::Matrix2d& S) {
  const double s01 = 0.5 * (S(0, 1) + S(1, 0));
  const double det = S(0, 0) * S(1, 1) - s01 * s01;
  if (!(det > 0.0) || !(S(0, 0) > 0.0)) return std::numeric_limits<double>::infinity();
  return (nu.x() * nu.x() * S(1, 1) - 2.0 * nu.x() * nu.y() * s01 + nu.y() * nu.y() * S(0, 0)) / det;
}

}  // namespace ekf_local_map
