#include "exploration/motion_controller.h"

#include "core_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace exploration {

using laser_features::kPi;
using laser_features::kTwoPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;

namespace {

using core::fail;
using core::finite;

/// `want`, or as close to it as `max_step` away from `last` allows.
double stepTowards(double last, double want, double max_step) {
  const double d = want - last;
  if (d > max_step) return last + max_step;
  if (d < -max_step) return last - max_step;
  return want;  // exactly: a ramp ends on zero, not on a rounding residue
}

constexpr double kTieCost = 0.25;  // weight of the turn from the previous choice, breaks side ties
constexpr double kKeepFree = 0.05;  // m, the previous choice stays free this much below `required`
                                    // (scan noise would flip it at the threshold)

}  // namespace

const char* toString(MotionStatus status) {
  switch (status) {
    case MotionStatus::Idle: return "Idle";
    case MotionStatus::Moving: return "Moving";
    case MotionStatus::Reached: return "Reached";
    case MotionStatus::Blocked: return "Blocked";
    case MotionStatus::Bumped: return "Bumped";
    case MotionStatus::NoScan: return "NoScan";
    case MotionStatus::Invalid: return "Invalid";
  }
  return "?";
}

MotionController::MotionController(const MotionParams& params) : params_(params) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("MotionController: " + why);
  clearance_ = params_.robot_radius + params_.safety_margin;
  range_cap_ = std::max(params_.lookahead, params_.slow_down_distance);
  candidate_free_.assign(static_cast<std::size_t>(params_.candidate_headings), 0.0);
  scan_robot_.reserve(1024);
  scan_world_.reserve(1024);
  nearby_.reserve(1024);
  finish(MotionStatus::Idle, "idle: no goal");
}

double passageSteering(double width, double robot_radius) { return 0.5 * (0.5 * width - robot_radius); }

void MotionController::setPassageWidth(std::optional<double> width) {
  double margin = params_.safety_margin;
  if (width && std::isfinite(*width)) margin = std::clamp(passageSteering(*width, params_.robot_radius), 0.0, margin);
  clearance_ = params_.robot_radius + margin;
}

bool MotionController::validate(const MotionParams& p, std::string* error) {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!positive(p.max_linear)) return fail(error, "max_linear must be > 0");
  if (!positive(p.max_angular)) return fail(error, "max_angular must be > 0");
  if (!positive(p.max_linear_accel)) return fail(error, "max_linear_accel must be > 0");
  if (!positive(p.max_angular_accel)) return fail(error, "max_angular_accel must be > 0");
  if (!positive(p.robot_radius)) return fail(error, "robot_radius must be > 0");
  if (!nonneg(p.safety_margin)) return fail(error, "safety_margin must be >= 0");
  if (!positive(p.goal_tolerance)) return fail(error, "goal_tolerance must be > 0");
  if (!positive(p.heading_tolerance)) return fail(error, "heading_tolerance must be > 0");
  if (!positive(p.lookahead)) return fail(error, "lookahead must be > 0");
  if (!positive(p.slow_down_distance)) return fail(error, "slow_down_distance must be > 0");
  if (!nonneg(p.min_linear) || p.min_linear > p.max_linear)
    return fail(error, "min_linear must be in [0, max_linear]");
  if (!positive(p.heading_gain)) return fail(error, "heading_gain must be > 0");
  if (!nonneg(p.reverse_distance) || p.reverse_distance > p.safety_margin)
    return fail(error, "reverse_distance must be in [0, safety_margin]");
  if (!positive(p.turn_in_place_angle) || p.turn_in_place_angle > kPi)
    return fail(error, "turn_in_place_angle must be in (0, pi]");
  if (p.candidate_headings < 3 || p.candidate_headings > 3600)
    return fail(error, "candidate_headings must be in [3, 3600]");
  if (!positive(p.scan_timeout)) return fail(error, "scan_timeout must be > 0");
  if (!positive(p.stuck_time)) return fail(error, "stuck_time must be > 0");
  if (!positive(p.progress_distance)) return fail(error, "progress_distance must be > 0");
  if (!positive(p.progress_angle)) return fail(error, "progress_angle must be > 0");
  return true;
}

void MotionController::setText(const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::vsnprintf(text_.data(), text_.size(), format, args);
  va_end(args);
}

void MotionController::finish(MotionStatus status, const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::vsnprintf(text_.data(), text_.size(), format, args);
  va_end(args);
  status_ = final_status_ = status;
  final_text_ = text_;
}

bool MotionController::setGoal(double x, double y, std::optional<double> theta,
                               std::optional<std::pair<double, double>> tolerance) {
  has_goal_ = false;
  if (!std::isfinite(x) || !std::isfinite(y) || (theta && !std::isfinite(*theta))) {
    finish(MotionStatus::Invalid, "goal refused: non-finite coordinates; stopping");
    return false;
  }
  has_goal_ = true;
  goal_tolerance_ = tolerance && tolerance->first > 0.0 ? tolerance->first : params_.goal_tolerance;
  heading_tolerance_ = tolerance && tolerance->second > 0.0 ? tolerance->second : params_.heading_tolerance;
  goal_x_ = x;
  goal_y_ = y;
  goal_theta_ = theta;
  if (goal_theta_) goal_theta_ = normalizeAngle(*goal_theta_);
  phase_ = Phase::Position;
  turning_in_place_ = false;
  have_previous_choice_ = false;
  best_ = std::numeric_limits<double>::infinity();
  stuck_elapsed_ = 0.0;
  status_ = MotionStatus::Moving;
  setText("moving: new goal (%.2f, %.2f)", x, y);
  return true;
}

void MotionController::cancel() {
  has_goal_ = false;
  finish(MotionStatus::Idle, "idle: cancelled");
}

bool MotionController::setScan(const std::vector<Eigen::Vector2d>& points_in_robot, double stamp) {
  if (!std::isfinite(stamp)) return false;
  scan_robot_.clear();  // keeps the capacity
  for (const Eigen::Vector2d& p : points_in_robot)
    if (std::isfinite(p.x()) && std::isfinite(p.y())) scan_robot_.push_back(p);
  scan_stamp_ = stamp;
  have_scan_ = true;
  scan_pending_ = true;
  return true;
}

void MotionController::recordPose(double now, const Pose2D& pose) {
  if (history_size_ > 0) {
    const StampedPose& newest = history_[(history_head_ + kHistory - 1) % kHistory];
    if (now < newest.t) history_size_ = 0;  // the clock went back (a restart): older poses mean nothing
  }
  history_[history_head_] = {now, pose};
  history_head_ = (history_head_ + 1) % kHistory;
  history_size_ = std::min(history_size_ + 1, kHistory);
}

Pose2D MotionController::poseAt(double t) const {
  auto at = [this](std::size_t i) -> const StampedPose& {  // i-th newest
    return history_[(history_head_ + 2 * kHistory - 1 - i) % kHistory];
  };
  if (t >= at(0).t) return at(0).pose;
  for (std::size_t i = 1; i < history_size_; ++i) {
    const StampedPose& older = at(i);
    if (t < older.t) continue;
    const StampedPose& newer = at(i - 1);
    const double span = newer.t - older.t;
    const double a = span > 0.0 ? (t - older.t) / span : 1.0;
    Pose2D p;
    p.x = older.pose.x + a * (newer.pose.x - older.pose.x);
    p.y = older.pose.y + a * (newer.pose.y - older.pose.y);
    p.theta = normalizeAngle(older.pose.theta + a * normalizeAngle(newer.pose.theta - older.pose.theta));
    return p;
  }
  return at(history_size_ - 1).pose;  // older than the history: the oldest pose is the best guess
}

void MotionController::placeScan() {
  const Pose2D at_scan = poseAt(scan_stamp_);
  scan_world_.clear();
  for (const Eigen::Vector2d& p : scan_robot_) scan_world_.push_back(laser_features::transformPoint(at_scan, p));
  if (nearby_.capacity() < scan_world_.size()) nearby_.reserve(scan_world_.size());
  scan_pending_ = false;
}

double MotionController::freeDistance(double heading) const {
  const Eigen::Vector2d u = laser_features::unitVector(heading);
  const double r2 = clearance_ * clearance_;
  double free = range_cap_;
  for (const Eigen::Vector2d& r : nearby_) {
    const double t = u.dot(r);
    if (t <= 0.0) continue;  // behind: moving along u only gets farther from it
    const double lateral = laser_features::cross2(u, r);
    const double l2 = lateral * lateral;
    if (l2 >= r2) continue;
    const double s = t - std::sqrt(r2 - l2);  // travel until the swept circle touches the point
    if (s < free) free = s;
  }
  return std::max(0.0, free);
}

Command MotionController::limit(const Command& desired, double dt) {
  double v = std::isfinite(desired.v) ? std::clamp(desired.v, -params_.max_linear, params_.max_linear) : 0.0;
  double w = std::isfinite(desired.w) ? std::clamp(desired.w, -params_.max_angular, params_.max_angular) : 0.0;
  v = stepTowards(last_.v, v, params_.max_linear_accel * dt);
  w = stepTowards(last_.w, w, params_.max_angular_accel * dt);
  last_ = {v, w};
  return last_;
}

double MotionController::turnRate(double error) const {
  // Proportional, but never faster than what the angular acceleration can brake before the target.
  const double e = std::abs(error);
  const double rate = std::min({params_.max_angular, params_.heading_gain * e,
                                std::sqrt(2.0 * params_.max_angular_accel * e)});
  return std::copysign(rate, error);
}

bool MotionController::notStuck(double value, double step, double dt) {
  if (value <= best_ - step) {
    best_ = value;
    stuck_elapsed_ = 0.0;
    return true;
  }
  stuck_elapsed_ += dt;
  return stuck_elapsed_ < params_.stuck_time;
}

Command MotionController::update(const Pose2D& pose, double now, double dt, bool bumper) {
  if (!(std::isfinite(dt) && dt >= 0.0)) dt = 0.0;
  if (bumper) {  // Bumped is then a final status: it stays until setGoal() or cancel()
    has_goal_ = false;
    finish(MotionStatus::Bumped, "bumped: stopped until a new goal or cancel");
    last_ = Command{};  // the one place the deceleration limit does not hold
    return last_;
  }
  if (!finite(pose) || !std::isfinite(now)) {
    status_ = MotionStatus::Invalid;
    setText(finite(pose) ? "time refused: non-finite; stopping" : "pose refused: non-finite; stopping");
    return stop(dt);
  }
  recordPose(now, pose);
  if (scan_pending_) placeScan();
  if (!has_goal_) {
    status_ = final_status_;
    text_ = final_text_;
    return stop(dt);
  }
  const double age = now - scan_stamp_;
  if (!have_scan_ || std::abs(age) > params_.scan_timeout) {
    status_ = MotionStatus::NoScan;
    if (have_scan_)
      setText("no scan: the last one is %.2f s old; stopping", age);
    else
      setText("no scan yet; stopping");
    return stop(dt);
  }
  return drive(pose, dt);
}

Command MotionController::drive(const Pose2D& pose, double dt) {
  const double dx = goal_x_ - pose.x, dy = goal_y_ - pose.y;
  const double distance = std::hypot(dx, dy);
  if (phase_ == Phase::Position && distance <= goal_tolerance_) {
    if (!goal_theta_) {
      has_goal_ = false;
      finish(MotionStatus::Reached, "reached: %.3f m from the goal", distance);
      return stop(dt);
    }
    phase_ = Phase::Heading;
    best_ = std::numeric_limits<double>::infinity();
    stuck_elapsed_ = 0.0;
  }

  if (phase_ == Phase::Heading) return driveHeading(pose, dt);

  if (!notStuck(distance, params_.progress_distance, dt)) {
    has_goal_ = false;
    finish(MotionStatus::Blocked, "blocked: no progress towards the goal (%.2f m away) for %.1f s", distance,
           params_.stuck_time);
    return stop(dt);
  }

  // The points that can matter this cycle, relative to the robot (pose-frame axes).
  const Eigen::Vector2d position(pose.x, pose.y);
  const double reach2 = (range_cap_ + clearance_) * (range_cap_ + clearance_);
  nearby_.clear();
  for (const Eigen::Vector2d& q : scan_world_) {
    const Eigen::Vector2d r = q - position;
    if (r.squaredNorm() < reach2) nearby_.push_back(r);
  }
  free_ahead_ = freeDistance(pose.theta);

  const double goal_direction = std::atan2(dy, dx);
  if (const std::optional<Command> back = reverseApproach(pose, goal_direction, distance, dt)) return *back;

  bool none_free = false;
  const int chosen = chooseHeading(goal_direction, distance, &none_free);
  const double spacing = kTwoPi / params_.candidate_headings;
  const int k = (chosen % 2 == 1) ? (chosen + 1) / 2 : -(chosen / 2);
  target_heading_ = normalizeAngle(goal_direction + k * spacing);
  previous_choice_ = target_heading_;
  have_previous_choice_ = true;

  const double error = normalizeAngle(target_heading_ - pose.theta);
  if (std::abs(error) > params_.turn_in_place_angle) {
    turning_in_place_ = true;
  } else if (std::abs(error) < 0.5 * params_.turn_in_place_angle) {
    turning_in_place_ = false;
  }
  double v = 0.0;
  if (!turning_in_place_) {
    // Towards the goal: constant deceleration (sqrt). Towards an obstacle: linear, so the robot
    // only creeps up to the margin, never through it.
    const double near_goal =
        std::max(params_.min_linear, params_.max_linear * std::sqrt(distance / params_.slow_down_distance));
    const double near_obstacle = params_.max_linear * free_ahead_ / params_.slow_down_distance;
    v = std::min({params_.max_linear, near_goal, near_obstacle}) * std::max(0.0, std::cos(error));
  }

  status_ = MotionStatus::Moving;
  if (none_free)
    setText("moving: no free direction, turning to the freest (%.2f m free)", candidate_free_[chosen]);
  else if (chosen != 0)
    setText("moving: avoiding, %.2f rad off the goal direction", normalizeAngle(target_heading_ - goal_direction));
  else
    setText("moving: %.2f m to the goal", distance);
  return limit(Command{v, turnRate(error)}, dt);
}

Command MotionController::driveHeading(const Pose2D& pose, double dt) {
  // In place: a circular robot cannot hit anything turning.
  const double error = normalizeAngle(*goal_theta_ - pose.theta);
  if (std::abs(error) <= heading_tolerance_) {
    has_goal_ = false;
    finish(MotionStatus::Reached, "reached: heading %.3f rad off", error);
    return stop(dt);
  }
  if (!notStuck(std::abs(error), params_.progress_angle, dt)) {
    has_goal_ = false;
    finish(MotionStatus::Blocked, "blocked: the final heading, %.2f rad off, made no progress for %.1f s", error,
           params_.stuck_time);
    return stop(dt);
  }
  target_heading_ = *goal_theta_;
  status_ = MotionStatus::Moving;
  setText("moving: turning to the goal heading, %.2f rad left", error);
  return limit(Command{0.0, turnRate(error)}, dt);
}

std::optional<Command> MotionController::reverseApproach(const Pose2D& pose, double goal_direction, double distance,
                                                         double dt) {
  // The fine approach: a goal a few centimetres behind (an EKF correction after the final turn)
  // is reached backwards. Turning round to it would turn half a circle there and half back, and
  // each turn's odometry error moves the goal again.
  if (!(goal_theta_ && distance <= params_.reverse_distance &&
        std::abs(normalizeAngle(goal_direction - pose.theta)) > 0.5 * kPi &&
        freeDistance(pose.theta + kPi) >= distance))
    return std::nullopt;
  target_heading_ = normalizeAngle(goal_direction + kPi);  // the rear towards the goal
  const double error = normalizeAngle(target_heading_ - pose.theta);
  double v = 0.0;
  if (std::abs(error) <= params_.turn_in_place_angle)
    v = -std::max(params_.min_linear, params_.max_linear * std::sqrt(distance / params_.slow_down_distance)) *
        std::cos(error);
  have_previous_choice_ = false;
  status_ = MotionStatus::Moving;
  setText("moving: backwards, %.3f m to the goal", distance);
  return limit(Command{v, turnRate(error)}, dt);
}

int MotionController::chooseHeading(double goal_direction, double distance, bool* none_free) {
  // Candidates k * spacing from the goal direction, k = 0 first: the goal direction is one of them.
  const int n = params_.candidate_headings;
  const double spacing = kTwoPi / n;
  const double required = std::min(params_.lookahead, distance);
  int chosen = -1, freest = -1;
  double chosen_cost = 0.0, freest_cost = 0.0;
  for (int i = 0; i < n; ++i) {
    const int k = (i % 2 == 1) ? (i + 1) / 2 : -(i / 2);  // 0, 1, -1, 2, -2, ...
    const double heading = goal_direction + k * spacing;
    const double free = freeDistance(heading);
    candidate_free_[i] = free;
    double cost = std::abs(k) * spacing;
    double needed = required;
    if (have_previous_choice_) {
      const double turn = std::abs(normalizeAngle(heading - previous_choice_));
      cost += kTieCost * turn;
      if (turn <= 0.5 * spacing) needed = std::max(0.0, required - kKeepFree);
    }
    if (free >= needed && (chosen < 0 || cost < chosen_cost)) {
      chosen = i;
      chosen_cost = cost;
    }
    constexpr double kSameFree = 0.01;  // m
    if (freest < 0 || free > candidate_free_[freest] + kSameFree ||
        (free > candidate_free_[freest] - kSameFree && cost < freest_cost)) {
      freest = i;
      freest_cost = cost;
    }
  }
  *none_free = chosen < 0;
  return *none_free ? freest : chosen;
}

}  // namespace exploration
