#include "bullet_sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace bullet_sim {
namespace {

// Angle to [-pi, pi] in double precision (btNormalizeAngle works in float).
double wrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

double clamp(double v, double limit) { return std::max(-limit, std::min(limit, v)); }

double approach(double current, double target, double max_change) {
  return current + clamp(target - current, max_change);
}

void require(bool ok, const std::string& name, const std::string& what) {
  if (!ok) throw std::invalid_argument("bullet_sim parameter '" + name + "' " + what);
}

}  // namespace

void validate(const SimParams& p) {
  require(p.physics_rate > 0 && std::isfinite(p.physics_rate), "physics_rate", "must be positive");
  require(p.max_linear_velocity > 0, "max_linear_velocity", "must be positive");
  require(p.max_angular_velocity > 0, "max_angular_velocity", "must be positive");
  require(p.max_linear_accel > 0, "max_linear_accel", "must be positive");
  require(p.max_angular_accel > 0, "max_angular_accel", "must be positive");
  require(p.wheel_base > 0, "wheel_base", "must be positive");
  require(p.laser_beams >= 1 && p.laser_beams <= 100000, "laser_beams", "must be in [1, 100000]");
  require(p.laser_fov > 0 && p.laser_fov <= 2 * M_PI + 1e-9, "laser_fov", "must be in (0, 2*pi]");
  require(p.laser_range_min >= 0 && p.laser_range_max > p.laser_range_min, "laser_range_max",
          "must be larger than laser_range_min >= 0");
  require(p.laser_noise_stddev >= 0, "laser_noise_stddev", "must not be negative");
  require(p.odom_wheel_noise >= 0, "odom_wheel_noise", "must not be negative");
  require(p.odom_wheelbase_error > -0.5 && p.odom_wheelbase_error < 0.5, "odom_wheelbase_error", "must be in (-0.5, 0.5)");
}

Simulator::Simulator(const World& world, const RobotModel& robot, const SimParams& params)
    : world_(world),
      robot_(robot),
      params_(params),
      collision_(world, robot.radius),
      ray_caster_(world),
      motion_rng_(params.seed),
      laser_rng_(params.seed ^ 0x9E3779B97F4A7C15ull) {
  validate(params_);
  const bool full_circle = params_.laser_fov >= 2 * M_PI - 1e-9;
  laser_.beams = params_.laser_beams;
  // A full circle has no repeated beam at +pi; a partial FOV spans [-fov/2, +fov/2] inclusive.
  laser_.angle_increment = full_circle ? 2 * M_PI / laser_.beams
                                       : (laser_.beams > 1 ? params_.laser_fov / (laser_.beams - 1) : 0.0);
  laser_.angle_min = full_circle ? -M_PI : -params_.laser_fov / 2;
  if (laser_.beams == 1) laser_.angle_min = 0.0;
  reset();
  if (collision_.overlaps({true_pose_.x, true_pose_.y}))
    throw WorldError(world_.source + ": robot.start: the robot's footprint (radius " + std::to_string(robot_.radius) +
                     " m) overlaps an obstacle at the start pose");
}

void Simulator::reset() {
  true_pose_ = world_.start;
  odom_pose_ = Pose2{};
  odom_cov_.setZero();
  v_ = w_ = cmd_v_ = cmd_w_ = odom_v_ = odom_w_ = 0.0;
  bumper_ = false;
}

bool Simulator::teleport(const Pose2& pose) {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw)) return false;
  if (collision_.overlaps({pose.x, pose.y})) return false;
  true_pose_ = {pose.x, pose.y, wrapAngle(pose.yaw)};
  v_ = w_ = 0.0;
  bumper_ = false;
  return true;
}

void Simulator::setCommand(double v, double w) {
  cmd_v_ = std::isfinite(v) ? clamp(v, params_.max_linear_velocity) : 0.0;
  cmd_w_ = std::isfinite(w) ? clamp(w, params_.max_angular_velocity) : 0.0;
}

void Simulator::step() {
  const double dt = this->dt();
  v_ = approach(v_, cmd_v_, params_.max_linear_accel * dt);
  w_ = approach(w_, cmd_w_, params_.max_angular_accel * dt);

  // Exact arc of a constant (v, w) over dt.
  double ds = v_ * dt;
  const double dth = w_ * dt;
  const double mid = true_pose_.yaw + dth / 2;
  const double chord = std::abs(dth) > 1e-9 ? ds * std::sin(dth / 2) / (dth / 2) : ds;
  Vec2 from{true_pose_.x, true_pose_.y};
  Vec2 to{from.x + chord * std::cos(mid), from.y + chord * std::sin(mid)};

  bumper_ = false;
  const SweepResult sweep = collision_.sweep(from, to);
  if (sweep.contact) {
    // Stop just short of the contact (1 mm), like a bumper that halts the base.
    const double length = std::hypot(to.x - from.x, to.y - from.y);
    const double free = std::max(0.0, sweep.fraction * length - 1e-3);
    const double f = length > 0 ? free / length : 0.0;
    to = {from.x + f * (to.x - from.x), from.y + f * (to.y - from.y)};
    ds *= f;
    v_ = 0.0;
    bumper_ = true;
  }
  true_pose_ = {to.x, to.y, wrapAngle(true_pose_.yaw + dth)};
  travelled_ += std::abs(ds);
  integrateOdometry(ds, dth);
  ++steps_;
}

void Simulator::integrateOdometry(double true_ds, double true_dtheta) {
  // Wheel travel of the executed motion, then what the encoders report.
  const double b = params_.wheel_base;
  const double left = true_ds - b * true_dtheta / 2;
  const double right = true_ds + b * true_dtheta / 2;
  const double k2 = params_.odom_wheel_noise * params_.odom_wheel_noise;
  const double var_l = k2 * std::abs(left), var_r = k2 * std::abs(right);
  const double ml = left * (1 + params_.odom_left_radius_error) + std::sqrt(var_l) * normal_(motion_rng_);
  const double mr = right * (1 + params_.odom_right_radius_error) + std::sqrt(var_r) * normal_(motion_rng_);

  // Dead reckoning with the wheelbase the odometry believes in.
  const double b_odom = b * (1 + params_.odom_wheelbase_error);
  const double ds = (ml + mr) / 2;
  const double dth = (mr - ml) / b_odom;
  const double mid = odom_pose_.yaw + dth / 2;
  const double c = std::cos(mid), s = std::sin(mid);
  odom_pose_.x += ds * c;
  odom_pose_.y += ds * s;
  odom_pose_.yaw = wrapAngle(odom_pose_.yaw + dth);
  odom_v_ = ds / dt();
  odom_w_ = dth / dt();

  // Covariance of the odometry pose: Σ' = F Σ Fᵀ + G diag(var_l, var_r) Gᵀ.
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 2) = -ds * s;
  F(1, 2) = ds * c;
  Eigen::Matrix<double, 3, 2> G;  // columns: d/d(left wheel), d/d(right wheel)
  G << c / 2 + ds * s / (2 * b_odom), c / 2 - ds * s / (2 * b_odom),
       s / 2 - ds * c / (2 * b_odom), s / 2 + ds * c / (2 * b_odom),
       -1 / b_odom, 1 / b_odom;
  const Eigen::Vector2d q(var_l, var_r);
  odom_cov_ = F * odom_cov_ * F.transpose() + G * q.asDiagonal() * G.transpose();
}

void Simulator::exactScan(std::vector<float>* ranges) const {
  ranges->resize(static_cast<size_t>(laser_.beams));
  const double c = std::cos(true_pose_.yaw), s = std::sin(true_pose_.yaw);
  const double ox = true_pose_.x + c * robot_.laser_x - s * robot_.laser_y;
  const double oy = true_pose_.y + s * robot_.laser_x + c * robot_.laser_y;
  const double start = true_pose_.yaw + robot_.laser_yaw + laser_.angle_min;
  ray_caster_.castFan(ox, oy, start, laser_.angle_increment, ranges->size(), params_.laser_range_max + 0.5,
                      ranges->data());
}

void Simulator::scan(std::vector<float>* ranges) {
  exactScan(ranges);
  const double inf = std::numeric_limits<double>::infinity();
  for (float& r : *ranges) {
    // One noise draw per beam whatever the outcome, so the stream does not depend on the geometry.
    const double noisy = r + params_.laser_noise_stddev * normal_(laser_rng_);
    if (!std::isfinite(r) || r > params_.laser_range_max) {
      r = static_cast<float>(inf);
    } else if (noisy < params_.laser_range_min) {
      r = static_cast<float>(-inf);
    } else {
      r = static_cast<float>(std::min(noisy, params_.laser_range_max));
    }
  }
}

}  // namespace bullet_sim
