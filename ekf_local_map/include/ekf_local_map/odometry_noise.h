// The covariance of an odometry increment (the U of eq. 8) for a differential-drive robot.
//
// Derivation from a per-wheel model (the simulator's: each wheel's measured travel has variance
// k^2 |travel|). For an increment of travel ds and rotation dtheta on wheel base b the wheels roll
//     l = ds - b dtheta / 2,   r = ds + b dtheta / 2,
// and ds = (l + r) / 2, dtheta = (r - l) / b give
//     var(ds)     = k^2 (|l| + |r|) / 4,
//     var(dtheta) = k^2 (|l| + |r|) / b^2,
//     cov(ds, dtheta) = k^2 (|r| - |l|) / (2 b),
// with |l| + |r| = max(2 |ds|, b |dtheta|). This model uses the sum instead of the max and drops
// the correlation:
//     var(ds)     = k^2 / 2 |ds|   + k^2 b / 4 |dtheta|
//     var(dtheta) = 2 k^2 / b^2 |ds| + k^2 / b |dtheta|
// which is never smaller (in the positive semi-definite sense: the difference has determinant
// zero and a non-negative trace) than the exact covariance, and equal to it for straight drives and
// turns on the spot. The (ds, dtheta) covariance is mapped to (x, y, theta) through the mid-point
// arc x = ds cos(dtheta / 2), y = ds sin(dtheta / 2), theta = dtheta; small floors keep it
// positive definite (and cover lateral slip), and `inflation` scales it for the systematic error
// the random model leaves out (wheel radius and wheel base errors, see below).
#pragma once

#include <laser_features/geometry.h>

#include <Eigen/Core>

namespace ekf_local_map {

struct OdometryNoise {
  // Defaults: k = 0.005 m^(1/2), b = 0.40 m (the simulator's config/bullet_sim.yaml).
  double translation_var_per_meter = 1.25e-5;   // m^2 per m travelled:   k^2 / 2
  double translation_var_per_radian = 2.5e-6;   // m^2 per rad turned:    k^2 b / 4
  double rotation_var_per_meter = 3.125e-4;     // rad^2 per m travelled: 2 k^2 / b^2
  double rotation_var_per_radian = 6.25e-5;     // rad^2 per rad turned:  k^2 / b
  double translation_var_floor = 1e-8;          // m^2 per increment, (0.1 mm)^2, on x and y
  double rotation_var_floor = 1e-8;             // rad^2 per increment, (0.1 mrad)^2
  // Variance multiplier for unmodelled systematic error. The simulator's defaults (wheel radii
  // +-0.1 %, wheel base 0.3 %) bias a 6 cm / 0.15 rad scan-to-scan increment by 3e-4 rad, against a
  // random standard deviation of 4e-3 rad: well below 10 % of the variance, but the bias adds up
  // coherently over unobserved travel (about 8 % of the variance after 1 m). 1.2 covers that; a
  // real robot with uncalibrated odometry needs 2–4.
  double inflation = 1.2;

  /// Parameters from the per-wheel model: wheel noise k (m^(1/2)), wheel base b (m).
  static OdometryNoise fromWheelModel(double wheel_noise, double wheel_base, double inflation = 1.2);

  /// Covariance of the increment (x, y, theta) in the frame of the pose it starts from.
  /// ds = +-|(x, y)| (negative when driving backwards), dtheta = theta.
  Eigen::Matrix3d covariance(const laser_features::Pose2D& increment) const;
};

}  // namespace ekf_local_map
