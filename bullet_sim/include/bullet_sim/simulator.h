// The simulated robot: a differential-drive base swept against the world, a 360° (or any FOV) laser,
// and odometry with random and systematic error. Deterministic for a given seed and command sequence.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "bullet_sim/collision_world.h"
#include "bullet_sim/ray_caster.h"
#include "bullet_sim/robot_model.h"
#include "bullet_sim/world.h"

namespace bullet_sim {

// Defaults here are the defaults of config/bullet_sim.yaml.
struct SimParams {
  double physics_rate = 100.0;        // Hz, integration steps per simulated second
  double max_linear_velocity = 0.6;   // m/s
  double max_angular_velocity = 1.5;  // rad/s
  double max_linear_accel = 1.0;      // m/s^2
  double max_angular_accel = 3.0;     // rad/s^2
  double wheel_base = 0.40;           // m, true distance between the wheels

  // Laser (angles in the laser frame)
  int laser_beams = 720;              // beams per scan
  double laser_fov = 2.0 * M_PI;      // rad; 2*pi: 360° scan with no repeated beam
  double laser_range_min = 0.10;      // m; closer returns are -inf (REP 117)
  double laser_range_max = 15.0;      // m; no return is +inf (REP 117)
  double laser_noise_stddev = 0.01;   // m, Gaussian range noise

  // Odometry error model (per wheel): measured = true * (1 + radius_error) + N(0, k^2 |true|)
  double odom_left_radius_error = 0.001;   // relative, systematic
  double odom_right_radius_error = -0.001; // relative, systematic
  double odom_wheelbase_error = 0.003;     // relative error of the wheelbase the odometry assumes
  double odom_wheel_noise = 0.005;         // k, m^(1/2): variance k^2 |distance| per wheel

  uint64_t seed = 1;
};

struct LaserGeometry {
  double angle_min = 0.0;  // rad, in the laser frame
  double angle_increment = 0.0;
  int beams = 0;
  double angle_max() const { return angle_min + angle_increment * (beams - 1); }
};

class Simulator {
 public:
  Simulator(const World& world, const RobotModel& robot, const SimParams& params);

  // Velocity command (m/s, rad/s); clipped to the limits, reached within the acceleration limits.
  void setCommand(double v, double w);
  // Advances by one physics step (1 / physics_rate s).
  void step();

  // A scan at the current true pose: ranges in laser order, with noise, -inf below range_min and
  // +inf for no return. Resizes `ranges` on first use only.
  void scan(std::vector<float>* ranges);
  // The same without noise and clamping (for tests: the exact distances).
  void exactScan(std::vector<float>* ranges) const;
  const LaserGeometry& laser() const { return laser_; }

  double time() const { return static_cast<double>(steps_) / params_.physics_rate; }
  uint64_t steps() const { return steps_; }
  double dt() const { return 1.0 / params_.physics_rate; }
  const Pose2& truePose() const { return true_pose_; }
  double trueLinearVelocity() const { return v_; }
  double trueAngularVelocity() const { return w_; }
  const Pose2& odomPose() const { return odom_pose_; }
  const Eigen::Matrix3d& odomCovariance() const { return odom_cov_; }
  double odomLinearVelocity() const { return odom_v_; }
  double odomAngularVelocity() const { return odom_w_; }
  bool bumper() const { return bumper_; }
  double travelled() const { return travelled_; }  // m, true path length

  // Puts the robot at `pose` (world frame) without telling odometry (kidnapping). False if the
  // footprint would overlap an obstacle.
  bool teleport(const Pose2& pose);
  // Back to the start pose, at rest, with odometry restarted at zero.
  void reset();

  const World& world() const { return world_; }
  const RobotModel& robot() const { return robot_; }
  const SimParams& params() const { return params_; }
  const RayCaster2D& rayCaster() const { return ray_caster_; }
  const CollisionWorld& collisionWorld() const { return collision_; }

 private:
  void integrateOdometry(double true_ds, double true_dtheta);

  World world_;
  RobotModel robot_;
  SimParams params_;
  CollisionWorld collision_;
  RayCaster2D ray_caster_;
  LaserGeometry laser_;

  std::mt19937_64 motion_rng_;
  std::mt19937_64 laser_rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};

  uint64_t steps_ = 0;
  double cmd_v_ = 0.0, cmd_w_ = 0.0;
  double v_ = 0.0, w_ = 0.0;
  Pose2 true_pose_;
  Pose2 odom_pose_;
  Eigen::Matrix3d odom_cov_ = Eigen::Matrix3d::Zero();
  double odom_v_ = 0.0, odom_w_ = 0.0;
  bool bumper_ = false;
  double travelled_ = 0.0;
};

// Throws std::invalid_argument naming the parameter if a value is out of range.
void validate(const SimParams& params);

}  // namespace bullet_sim
