// Local motion for the differential-drive robot: drives to a goal (x, y) or (x, y, theta) given in
// the frame of the robot's pose (odometry-like, continuous), avoiding the obstacles of the latest
// laser scan, within velocity and acceleration limits, with a scan watchdog and a bumper stop.
//
// Avoidance: candidate headings evenly around the full circle, one of them on the goal direction;
// a candidate is free when the circle of robot_radius + safety_margin swept along it stays clear of
// the scan points for min(lookahead, distance to goal). The robot follows the free candidate
// closest to the goal direction (ties and near-threshold cases: the side chosen before), turning in
// place when the heading error exceeds turn_in_place_angle; with no free candidate it turns to the
// freest one (and creeps along it as far as its free distance allows). The linear
// speed also scales with the free distance along the current heading, so an arc towards a free
// candidate never runs into what lies straight ahead.
//
// ROS-free: Eigen, laser_features' geometry and the standard library only. No allocation per cycle
// in steady state (scans no larger than the largest seen so far).
#pragma once

#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace exploration {

struct MotionParams {
  double max_linear = 0.5;            // m/s, |v| bound (the base allows 0.6)
  double max_angular = 1.2;           // rad/s, |w| bound (the base allows 1.5)
  double max_linear_accel = 1.0;      // m/s^2, |v - v_last| <= this * dt (only a bump stops harder)
  double max_angular_accel = 3.0;     // rad/s^2, |w - w_last| <= this * dt
  double robot_radius = 0.25;         // m, the robot is a circle
  double safety_margin = 0.10;        // m, clearance kept to obstacles on top of robot_radius
  double goal_tolerance = 0.05;       // m, the position is reached within this distance
  double heading_tolerance = 0.05;    // rad, the final heading (when given) is reached within this
  double lookahead = 0.6;             // m, a candidate heading must be free this far (or to the goal)
  double slow_down_distance = 0.8;    // m, v scales down within this of the goal (as the square root
                                      // of the distance: constant deceleration) and of the first
                                      // obstacle along the current heading (linearly)
  double min_linear = 0.05;           // m/s, floor of the slow-down near the goal (not of the one
                                      // near obstacles)
  double heading_gain = 2.0;          // 1/s, w = heading_gain * heading error, before the limits
  double turn_in_place_angle = 0.6;   // rad, v = 0 above this heading error (until back below half)
  double reverse_distance = 0.10;     // m, a goal with a final heading this close behind the robot is
                                      // reached backwards, straight, instead of turning round to it and
                                      // back (the last centimetres of a mission's goal); 0: never. At most
                                      // safety_margin: the rear is checked only against the current scan
  int candidate_headings = 31;        // -, directions sampled around the full circle for avoidance,
                                      // one on the goal direction
  double scan_timeout = 0.5;          // s, no scan younger than this: stop (the watchdog)
  double stuck_time = 5.0;            // s, no progress this long while driving: Blocked
  double progress_distance = 0.10;    // m, a new best distance to the goal by this much is progress
  double progress_angle = 0.10;       // rad, same for the final heading error
};

/// A velocity command: forward speed and turn rate.
struct Command {
  double v = 0.0;  // m/s
  double w = 0.0;  // rad/s, counter-clockwise
};

enum class MotionStatus {
  Idle,     // no goal (or cancelled)
  Moving,   // driving to the goal (or turning to its final heading)
  Reached,  // the goal is reached; zero command until the next goal
  Blocked,  // no progress for stuck_time; the goal is dropped
  Bumped,   // the bumper was pressed; stopped until setGoal() or cancel()
  NoScan,   // the watchdog: no recent scan; stopping, resumes when scans return
  Invalid,  // an input was refused (non-finite): see statusText()
};

const char* toString(MotionStatus status);

/// m, half of a door's slack a side (width / 2 - robot_radius): in a door `width` wide, the
/// clearance the controller keeps on top of the robot's radius (at most safety_margin), and how far
/// off the door's axis a robot may start straight through it (MotionController::setPassageWidth).
double passageSteering(double width, double robot_radius);

class MotionController {
 public:
  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit MotionController(const MotionParams& params = MotionParams());
  static bool validate(const MotionParams& params, std::string* error = nullptr);
  const MotionParams& params() const { return params_; }

  /// A new goal in the frame of the poses given to update(); cancels the previous goal. A
  /// non-finite goal is refused (false, status Invalid, no goal).
  /// `tolerance` (m, rad): this goal's position and heading tolerances instead of the parameters'
  /// (a mission's goal is approached closer than a room's frontier).
  bool setGoal(double x, double y, std::optional<double> theta = std::nullopt,
               std::optional<std::pair<double, double>> tolerance = std::nullopt);
  /// Drops the goal (status Idle); the command ramps down to zero.
  void cancel();
  /// The robot is passing a door `width` wide (nullopt: it is not): the clearance kept to obstacles
  /// is then the robot's radius plus half of the door's slack on each side (width / 2 - radius), at
  /// most safety_margin; the other half is left for steering (passageSteering()). A 0.7 m door (the narrowest) leaves a
  /// 0.25 m robot 0.1 m a side, all of which a 0.1 m margin would take. Non-finite: ignored.
  void setPassageWidth(std::optional<double> width);

  /// The obstacles: scan points in the robot frame (x forward, y left) measured at `stamp` (s, the
  /// clock of update()'s `now`). Non-finite points are skipped; a non-finite stamp refuses the scan
  /// (false). The points are placed in the pose frame with the pose at `stamp`, interpolated from
  /// the poses of the recent update() calls, at the next update().
  bool setScan(const std::vector<Eigen::Vector2d>& points_in_robot, double stamp);

  /// One control cycle at time `now` (s) with the robot pose (same frame as the goal), the time
  /// `dt` (s) since the previous cycle and the bumper. Returns the velocity command, within the
  /// speed limits and within accel * dt of the previous command (except on a bump: zero at once).
  /// A non-finite pose or time is refused (status Invalid for the cycle, the goal is kept, the
  /// command ramps down); a non-finite or negative dt counts as 0 (the command is held). A scan
  /// stamped more than scan_timeout after `now` (a clock jump) counts as missing.
  Command update(const laser_features::Pose2D& pose, double now, double dt, bool bumper);

  MotionStatus status() const { return status_; }
  std::string statusText() const { return text_.data(); }

  bool hasGoal() const { return has_goal_; }
  /// The previous command returned by update().
  Command lastCommand() const { return last_; }
  /// Heading (pose frame) the controller steers to in the last cycle, for display.
  double targetHeading() const { return target_heading_; }
  /// Free travel along the current heading in the last cycle (m, capped at
  /// max(lookahead, slow_down_distance)).
  double freeDistanceAhead() const { return free_ahead_; }
  /// Valid points of the last accepted scan.
  std::size_t scanSize() const { return scan_robot_.size(); }

 private:
  struct StampedPose {
    double t = 0.0;
    laser_features::Pose2D pose;
  };
  enum class Phase { Position, Heading };

  Command limit(const Command& desired, double dt);
  Command stop(double dt) { return limit(Command{}, dt); }
  void setText(const char* format, ...);
  void finish(MotionStatus status, const char* format, ...);  // a final status: kept while no goal
  void recordPose(double now, const laser_features::Pose2D& pose);
  laser_features::Pose2D poseAt(double t) const;
  void placeScan();
  double freeDistance(double heading) const;
  Command drive(const laser_features::Pose2D& pose, double dt);
  Command driveHeading(const laser_features::Pose2D& pose, double dt);  // the final heading, in place
  /// A goal a few centimetres behind, approached backwards; none where that does not apply.
  std::optional<Command> reverseApproach(const laser_features::Pose2D& pose, double goal_direction, double distance,
                                         double dt);
  /// The candidate heading to drive along (index: k = 0, 1, -1, 2, ... spacings off the goal's
  /// direction): the cheapest free one, else the freest (`none_free`).
  int chooseHeading(double goal_direction, double distance, bool* none_free);
  double turnRate(double heading_error) const;
  bool notStuck(double value, double step, double dt);

  MotionParams params_;
  double clearance_;  // robot_radius + safety_margin, or less in a door (setPassageWidth)
  double range_cap_;  // max(lookahead, slow_down_distance)

  bool has_goal_ = false;
  double goal_x_ = 0.0, goal_y_ = 0.0;
  double goal_tolerance_ = 0.05, heading_tolerance_ = 0.05;  // m, rad: this goal's
  std::optional<double> goal_theta_;
  Phase phase_ = Phase::Position;
  bool turning_in_place_ = false;
  bool have_previous_choice_ = false;
  double previous_choice_ = 0.0;  // rad, pose frame
  double best_ = 0.0;             // best distance (Position) or heading error (Heading) so far
  double stuck_elapsed_ = 0.0;    // s of driving since the last progress

  MotionStatus status_ = MotionStatus::Idle;
  std::array<char, 160> text_{};
  MotionStatus final_status_ = MotionStatus::Idle;
  std::array<char, 160> final_text_{};
  Command last_;
  double target_heading_ = 0.0;
  double free_ahead_ = 0.0;

  // Scans: the raw points until the next update() places them in the pose frame.
  std::vector<Eigen::Vector2d> scan_robot_;
  double scan_stamp_ = 0.0;
  bool have_scan_ = false;
  bool scan_pending_ = false;
  std::vector<Eigen::Vector2d> scan_world_;
  std::vector<Eigen::Vector2d> nearby_;  // per cycle: world points near the robot, relative to it
  std::vector<double> candidate_free_;   // per cycle: free distance of each candidate

  static constexpr std::size_t kHistory = 64;  // 3.2 s of poses at 20 Hz
  std::array<StampedPose, kHistory> history_{};
  std::size_t history_size_ = 0, history_head_ = 0;  // head: the next slot to write
};

}  // namespace exploration
