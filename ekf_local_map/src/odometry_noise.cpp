#include "ekf_local_map/odometry_noise.h"

#include <cmath>

namespace ekf_local_map {

OdometryNoise OdometryNoise::fromWheelModel(double wheel_noise, double wheel_base, double inflation) {
  const double k2 = wheel_noise * wheel_noise;
  const double b = wheel_base;
  OdometryNoise noise;
  noise.translation_var_per_meter = k2 / 2.0;
  noise.translation_var_per_radian = k2 * b / 4.0;
  noise.rotation_var_per_meter = 2.0 * k2 / (b * b);
  noise.rotation_var_per_radian = k2 / b;
  noise.inflation = inflation;
  return noise;
}

Eigen::Matrix3d OdometryNoise::covariance(const laser_features::Pose2D& increment) const {
  const double distance = std::hypot(increment.x, increment.y);
  const double ds = increment.x < 0.0 ? -distance : distance;
  const double dtheta = increment.theta;
  const double turned = std::abs(dtheta);

  const double var_ds = translation_var_per_meter * distance + translation_var_per_radian * turned;
  const double var_dtheta = rotation_var_per_meter * distance + rotation_var_per_radian * turned;

  // d(x, y, theta)/d(ds, dtheta) of the mid-point arc.
  const double c = std::cos(0.5 * dtheta);
  const double s = std::sin(0.5 * dtheta);
  Eigen::Matrix<double, 3, 2> J;
  J << c, -0.5 * ds * s,  //
      s, 0.5 * ds * c,    //
      0.0, 1.0;
  Eigen::Matrix3d Q = J * Eigen::Vector2d(var_ds, var_dtheta).asDiagonal() * J.transpose();
  Q.diagonal() += Eigen::Vector3d(translation_var_floor, translation_var_floor, rotation_var_floor);
  return inflation * Q;
}

}  // namespace ekf_local_map
