// frontier_baseline_node: the baseline the topological-metric exploration is compared against
// (issue 6): greedy frontier exploration on one occupancy grid of the whole building, in the spirit
// of explore_lite (Hörner 2016) on top of a grid map. Thin: the ROS-free core does the work
// (exploration/occupancy_grid.h, frontier_explorer.h, frontier_goal.h, path_driver.h); this
// node converts messages and drives the goal's path.
//
// Localization: the robot's pose is tf map -> base_link. The simulator runs with
// fake_localization, so map -> odom is the ground truth: the baseline maps with perfect poses. That
// is an upper bound on what explore_lite gets from gmapping (no drift, no loop-closure jumps, no
// smeared walls); its grid and travel are the best case for a metric-grid explorer.
//
// Per scan (main thread): the scan goes into the growing grid (OccupancyGrid::insertScan, the pose
// at the scan's stamp). Every replan_period (sim time), or at once when the robot reached its goal
// or the motion controller gave up (Blocked, Bumped):
//  - the held goal ends when reached (within goal_reach_tolerance), when the motion controller is
//    Blocked or Bumped (blacklisted, blacklist_radius), or when the robot made no progress towards
//    it for goal_timeout (blacklisted: explore_lite's progress_timeout; progress is a new shortest
//    planned path to the goal, and a goal that moved with its frontier restarts the count);
//  - FrontierExplorer::nextGoal costs every frontier (explore_lite's cost). The held goal follows
//    its frontier (the usable frontier whose goal or centroid lies within
//    max(goal_search_radius, goal_reach_tolerance) of it); its frontier gone (seen on the way) frees
//    the robot for the cheapest one. A frontier whose goal is where the robot already stands is
//    unobservable from there (beyond range, glass): blacklisted, else it is "reached" forever;
//  - no usable frontier left: exploration is complete.
// The goal is driven to along the planner's path (move_base's global plan, in explore_lite) by
// PathDriver (exploration/path_driver.h): the motion controller gets the path's waypoints one at a
// time; its scan-based avoidance handles what the grid does not show.
//
// Control (its own callback queue and thread, as exploration_node: planning on a large grid must
// never starve the watchdog or the velocity commands): scans for the avoidance, the bumper, and a
// control_rate timer running MotionController::update with the map pose and publishing cmd_vel.
//
// Output: nav_msgs/OccupancyGrid baseline_map (every map_publish_period, latched) and
// nav_msgs/Path baseline_path (the path to the goal, at each plan) for rviz; a progress line every
// progress_period; at the end (complete, or max_time of sim time) a JSON summary_file, then the node
// shuts down (with required="true" the launch ends).
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Bool.h>
#include <tf2/utils.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "exploration/baseline_params.h"
#include "exploration/frontier_goal.h"
#include "laser_features/building_rules_ros.h"
#include "laser_features/param_reader_ros.h"
#include "laser_features/tf_lookup.h"
#include "lockstep/participant.h"
#include "exploration/motion_controller.h"
#include "exploration/path_driver.h"
#include "ros_conversions.h"

namespace exploration {

using laser_features::Pose2D;


namespace {

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool nonNegative(double v) { return std::isfinite(v) && v >= 0.0; }


}  // namespace

class FrontierBaselineNode {
 public:
  FrontierBaselineNode()
      : nh_(), pnh_("~"), tf_listener_(tf_buffer_, true, lockstep::kTransportHints), control_spinner_(1, &control_queue_), lockstep_(nh_) {
    visitBaselineParams(&p_, laser_features::RosParamReader{pnh_});
    applyFootprint(laser_features::readRobotFootprint(nh_), &p_);
    std::string why;
    if (!OccupancyGrid::validate(p_.grid, &why)) why = "grid: " + why;
    else if (!FrontierExplorer::validate(p_.frontier, &why)) why = "frontier: " + why;
    else if (!GridPlanner::validate(p_.planner, &why)) why = "planner: " + why;
    else if (!MotionController::validate(p_.motion, &why)) why = "motion: " + why;
    else if (!positive(p_.control_rate) || !positive(p_.replan_period) || !positive(p_.goal_timeout) ||
             !nonNegative(p_.goal_reach_tolerance) || !nonNegative(p_.blacklist_radius) ||
             !nonNegative(p_.waypoint_tolerance) || !nonNegative(p_.goal_refresh_distance) ||
             !positive(p_.map_publish_period) || !positive(p_.progress_period) || !nonNegative(p_.max_time))
      why = "control_rate, replan_period, goal_timeout, map_publish_period and progress_period must be > 0, "
            "the tolerances, distances and max_time >= 0";
    else why.clear();
    if (!why.empty()) {
      ROS_FATAL("frontier_baseline: bad parameter: %s", why.c_str());
      throw std::invalid_argument(why);
    }
    explorer_ = std::make_unique<FrontierExplorer>(p_.frontier, p_.planner);
    FrontierGoalParams goal;
    goal.reach_tolerance = p_.goal_reach_tolerance;
    goal.timeout = p_.goal_timeout;
    goal.blacklist_radius = p_.blacklist_radius;
    goal.track_radius = std::max(p_.frontier.goal_search_radius, p_.goal_reach_tolerance);
    goal_ = FrontierGoal(goal);
    PathDriverParams drive;
    drive.waypoint_tolerance = p_.waypoint_tolerance;
    drive.goal_reach_tolerance = p_.goal_reach_tolerance;
    drive.goal_refresh_distance = p_.goal_refresh_distance;
    driver_ = std::make_unique<PathDriver>(p_.motion, drive);

    cmd_pub_ = lockstep_.advertise<geometry_msgs::Twist>(nh_, "cmd_vel", 10);
    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("baseline_map", 1, true);
    path_pub_ = nh_.advertise<nav_msgs::Path>("baseline_path", 2, true);
    // The grid and the planning: the global queue (ros::spin in main). A small queue: when planning
    // falls behind, old scans are dropped rather than mapped late.
    // Both scan subscriptions share one connection: both ask for TCP_NODELAY (no batching of scans,
    // the watchdog's scan_timeout is 0.5 s of sim time, 50 ms of wall time at rate 10).
    // In lockstep every scan is mapped at its step, and the control runs at the simulator's steps
    // of its period, on the one thread.
    using lockstep::Delivery;
    const auto nodelay = ros::TransportHints().tcpNoDelay();
    map_scan_sub_ = lockstep_.subscribe(nh_, "scan", 2, &FrontierBaselineNode::onMapScan, this, Delivery::Gated, nodelay);
    // Motion control: its own queue and thread.
    control_nh_.setCallbackQueue(&control_queue_);
    control_scan_sub_ =
        lockstep_.subscribe(control_nh_, "scan", 10, &FrontierBaselineNode::onControlScan, this, Delivery::Immediate, nodelay);
    bumper_sub_ = lockstep_.subscribe(control_nh_, "bumper", 10, &FrontierBaselineNode::onBumper, this);
    if (lockstep_.enabled()) {
      lockstep_.onStep([this](const ros::Time& t) {
        if (t >= next_control_) {
          control(t, t.toSec());
          next_control_ = lockstep::nextMultiple(t, 1.0 / p_.control_rate);
        }
        return next_control_;
      });
    } else {
      timer_ = control_nh_.createTimer(ros::Duration(1.0 / p_.control_rate), &FrontierBaselineNode::onTimer, this);
    }
    wall_start_ = std::chrono::steady_clock::now();
    sim_start_ = ros::Time::now();
    last_progress_ = last_map_publish_ = sim_start_;
    if (!lockstep_.enabled()) control_spinner_.start();
    ROS_INFO("frontier_baseline: exploring (grid %.3f m, replan every %.1f s, goal timeout %.0f s%s)",
             p_.grid.resolution, p_.replan_period, p_.goal_timeout,
             p_.max_time > 0.0 ? (", max " + std::to_string(int(p_.max_time)) + " s").c_str() : "");
  }

  ~FrontierBaselineNode() {
    control_spinner_.stop();
    timer_.stop();
  }

  int exitCode() const { return exit_code_; }

 private:
  bool lookup(const std::string& target, const std::string& source, const ros::Time& stamp, Pose2D* out,
              double timeout = 0.1) {
    std::string why;
    if (laser_features::lookupPose2D(tf_buffer_, target, source, stamp, lockstep_.transformTimeout(timeout), out, &why))
      return true;
    ROS_WARN_THROTTLE(5.0, "frontier_baseline: no transform %s <- %s: %s", target.c_str(), source.c_str(), why.c_str());
    return false;
  }

  static bool wellFormed(const sensor_msgs::LaserScan& msg) {
    return !msg.ranges.empty() && std::isfinite(msg.angle_min) && std::isfinite(msg.angle_increment);
  }

  // ---------------------------------------------------------------------------------------------
  // Main thread: the grid, the frontiers, the goal

  void onMapScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    if (done_) return;
    if (!wellFormed(*msg)) {
      ROS_WARN_THROTTLE(5.0, "frontier_baseline: an empty or malformed scan on %s is skipped", map_scan_sub_.getTopic().c_str());
      return;
    }
    if (!have_sensor_map_ && !lookup(p_.base_frame, msg->header.frame_id, ros::Time(0), &sensor_in_robot_map_)) return;
    have_sensor_map_ = true;
    if (!grid_) {
      // The sensor's minimum range: nearer readings say nothing about the cells they cross.
      OccupancyGridParams g = p_.grid;
      if (std::isfinite(msg->range_min)) g.min_range = std::max(g.min_range, double(msg->range_min));
      grid_ = std::make_unique<OccupancyGrid>(g);
    }
    // The pose at the scan's stamp (the tf may come a little after the scan: waits up to 0.3 s).
    Pose2D robot;
    if (!lookup(p_.map_frame, p_.base_frame, msg->header.stamp, &robot, 0.3)) return;
    std::string why;
    if (!grid_->insertScan(laser_features::compose(robot, sensor_in_robot_map_), msg->ranges, msg->angle_min,
                           msg->angle_increment, &why)) {
      ++scans_refused_;
      ROS_WARN_THROTTLE(5.0, "frontier_baseline: scan not mapped: %s", why.c_str());
      return;
    }
    const ros::Time now = msg->header.stamp;
    if (p_.max_time > 0.0 && (now - sim_start_).toSec() >= p_.max_time) {
      finish(false, "max_time reached (" + std::to_string(int(p_.max_time)) + " s of sim time)");
      return;
    }
    if (replan_requested_.exchange(false) || last_plan_.isZero() || (now - last_plan_).toSec() >= p_.replan_period) {
      last_plan_ = now;
      plan(robot.translation(), now);
      if (done_) return;
    }
    if ((now - last_map_publish_).toSec() >= p_.map_publish_period) {
      last_map_publish_ = now;
      publishMap(now);
    }
    if ((now - last_progress_).toSec() >= p_.progress_period) {
      last_progress_ = now;
      printProgress(now);
    }
  }

  /// The controller's goal and the path's waypoints go with the goal.
  void stopDriving() {
    std::lock_guard<std::mutex> lock(mutex_);
    driver_->stop();
  }

  /// The held goal reached or given up (FrontierGoal::review).
  void reviewGoal(const Eigen::Vector2d& robot, bool reached, bool stopped, const ros::Time& now) {
    const std::optional<Eigen::Vector2d> held = goal_.goal();
    const FrontierGoal::End end = goal_.review(robot, reached, stopped, now.toNSec(), explorer_.get());
    if (end == FrontierGoal::End::Held) return;
    if (end == FrontierGoal::End::Reached) {
      ++goals_reached_;
    } else {
      ++goals_given_up_;
      ROS_WARN("frontier_baseline: goal (%.2f, %.2f) given up (%s): blacklisted", held->x(), held->y(),
               end == FrontierGoal::End::Stopped ? "the motion controller stopped: blocked or bumped"
                                                 : "no progress within goal_timeout");
    }
    stopDriving();
  }

  void plan(const Eigen::Vector2d& robot, const ros::Time& now) {
    bool reached_flag = false, stopped_flag = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      driver_->takeEnds(&reached_flag, &stopped_flag);
    }
    reviewGoal(robot, reached_flag, stopped_flag, now);

    const auto t0 = std::chrono::steady_clock::now();
    explorer_->nextGoal(*grid_, robot);  // all frontiers costed; the choice of goal is below
    plan_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++plans_;
    if (explorer_->status() == ExplorerStatus::Invalid) {
      ROS_WARN_THROTTLE(5.0, "frontier_baseline: the robot (%.2f, %.2f) is off the grid: no plan", robot.x(), robot.y());
      return;
    }
    usable_frontiers_ = 0;
    for (const Frontier& f : explorer_->frontiers()) usable_frontiers_ += f.reachable && !f.blacklisted;
    total_frontiers_ = explorer_->frontiers().size();

    // The held goal follows its frontier; a frontier gone frees the robot for the cheapest one.
    const bool held = goal_.goal().has_value();
    bool is_new = false;
    std::vector<Eigen::Vector2d> unobservable;
    const bool have = goal_.choose(robot, now.toNSec(), explorer_.get(), &is_new, &unobservable);
    for (const Eigen::Vector2d& c : unobservable) {
      ++goals_given_up_;
      ROS_WARN("frontier_baseline: the frontier at (%.2f, %.2f) stays unseen from its goal: blacklisted", c.x(), c.y());
    }
    if (held && (is_new || !have)) {
      ROS_DEBUG("frontier_baseline: the goal's frontier vanished");
      stopDriving();
    }
    if (!have) {
      finish(true, "exploration complete: no reachable frontier left");
      return;
    }
    const Eigen::Vector2d goal = *goal_.goal();
    if (is_new) {
      ++goals_;
      ROS_DEBUG("frontier_baseline: goal %d at (%.2f, %.2f), %zu usable frontiers", goals_, goal.x(), goal.y(),
                usable_frontiers_);
    }
    std::optional<Path> path = explorer_->planner().pathTo(goal);
    if (!path) {  // not expected for a reachable frontier's goal: drive straight
      path = Path();
      path->waypoints = {robot, goal};
      path->length = (goal - robot).norm();
    }
    goal_.progress(path->length, grid_->resolution(), now.toNSec());
    publishPath(*path, now);
    std::lock_guard<std::mutex> lock(mutex_);
    driver_->follow(path->waypoints, robot);
  }

  void publishMap(const ros::Time& stamp) {
    nav_msgs::OccupancyGrid m;
    m.header.stamp = stamp;
    m.header.frame_id = p_.map_frame;
    m.info.map_load_time = stamp;
    m.info.resolution = float(grid_->resolution());
    m.info.width = uint32_t(grid_->width());
    m.info.height = uint32_t(grid_->height());
    m.info.origin.position.x = grid_->origin().x();
    m.info.origin.position.y = grid_->origin().y();
    m.info.origin.orientation.w = 1.0;
    grid_->toOccupancyData(&m.data);
    map_pub_.publish(m);
  }

  void publishPath(const Path& path, const ros::Time& stamp) {
    if (path_pub_.getNumSubscribers() == 0) return;
    nav_msgs::Path m;
    m.header.stamp = stamp;
    m.header.frame_id = p_.map_frame;
    for (const Eigen::Vector2d& w : path.waypoints) {
      geometry_msgs::PoseStamped ps;
      ps.header = m.header;
      ps.pose.position.x = w.x();
      ps.pose.position.y = w.y();
      ps.pose.orientation.w = 1.0;
      m.poses.push_back(ps);
    }
    path_pub_.publish(m);
  }

  double freeArea() const {
    return grid_ ? double(grid_->count(CellState::Free)) * grid_->resolution() * grid_->resolution() : 0.0;
  }

  double travel() {
    std::lock_guard<std::mutex> lock(mutex_);
    return travel_;
  }

  void printProgress(const ros::Time& stamp) {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    const double sim = (stamp - sim_start_).toSec();
    char goal[64] = "none";
    if (goal_.goal()) std::snprintf(goal, sizeof(goal), "(%.1f, %.1f)", goal_.goal()->x(), goal_.goal()->y());
    ROS_INFO("frontier_baseline: %.1f m2 free | %zu frontiers (%zu usable) | %d goals (%d reached, %d given up), "
             "goal %s | %.0f m | sim %.0f s, real-time factor %.1f | grid %d x %d, plan %.0f ms",
             freeArea(), total_frontiers_, usable_frontiers_, goals_, goals_reached_, goals_given_up_, goal, travel(),
             sim, sim / std::max(wall, 1e-3), grid_->width(), grid_->height(), 1e3 * plan_seconds_ / std::max(plans_, 1));
  }

  void finish(bool complete, const std::string& text) {
    done_ = true;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      driver_->stop();
    }
    cmd_pub_.publish(geometry_msgs::Twist());
    const ros::Time stamp = ros::Time::now();
    if (grid_) publishMap(stamp);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    const double sim = (stamp - sim_start_).toSec();
    const double rtf = sim / std::max(wall, 1e-3);
    const double free_area = freeArea();
    const double travelled = travel();
    if (complete)
      ROS_INFO("frontier_baseline: %s; %d goals, %.1f m, %.1f m2 free; %.0f s sim, %.0f s wall (real-time factor %.1f)",
               text.c_str(), goals_, travelled, free_area, sim, wall, rtf);
    else
      ROS_ERROR("frontier_baseline: %s; %d goals, %.1f m, %.1f m2 free; %.0f s sim, %.0f s wall", text.c_str(), goals_,
                travelled, free_area, sim, wall);
    if (!p_.summary_file.empty()) {
      std::ofstream f(p_.summary_file);
      f << "{\"complete\": " << (complete ? "true" : "false") << ", \"goals\": " << goals_
        << ", \"goals_reached\": " << goals_reached_ << ", \"travel_m\": " << travelled << ", \"sim_time_s\": " << sim
        << ", \"wall_time_s\": " << wall << ", \"real_time_factor\": " << rtf
        << ", \"grid_bytes\": " << (grid_ ? grid_->bytes() : 0) << ", \"grid_cells\": " << (grid_ ? grid_->cellCount() : 0)
        << ", \"free_area_m2\": " << free_area << ", \"blacklisted\": " << explorer_->blacklistSize()
        << ", \"text\": \"" << text << "\"}\n";
      if (!f) ROS_ERROR("frontier_baseline: could not write %s", p_.summary_file.c_str());
    }
    exit_code_ = complete ? 0 : 1;
    if (p_.shutdown_when_done) ros::requestShutdown();
  }

  // ---------------------------------------------------------------------------------------------
  // Control thread

  void onControlScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    if (!wellFormed(*msg)) return;  // the main thread warns
    if (!have_sensor_control_ && !lookup(p_.base_frame, msg->header.frame_id, ros::Time(0), &sensor_in_robot_control_)) return;
    have_sensor_control_ = true;
    scanPoints(*msg, sensor_in_robot_control_, &points_);
    std::lock_guard<std::mutex> lock(mutex_);
    driver_->setScan(points_, msg->header.stamp.toSec());
  }

  void onBumper(const std_msgs::Bool::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    bumper_ = msg->data;
  }

  void onTimer(const ros::TimerEvent&) { control(ros::Time(0), ros::Time::now().toSec()); }

  /// One control step: the poses at `stamp` (zero: the latest), at sim time `now`.
  void control(const ros::Time& stamp, double now) {
    if (done_) {
      cmd_pub_.publish(geometry_msgs::Twist());
      return;
    }
    Pose2D pose, odom;
    if (!lookup(p_.map_frame, p_.base_frame, stamp, &pose)) return;
    const bool have_odom = lookup(p_.odom_frame, p_.base_frame, stamp, &odom);
    const double dt = last_control_ > 0.0 ? now - last_control_ : 0.0;
    last_control_ = now;
    std::lock_guard<std::mutex> lock(mutex_);
    if (have_odom) {
      if (have_last_odom_) travel_ += (odom.translation() - last_odom_.translation()).norm();
      last_odom_ = odom;
      have_last_odom_ = true;
    }
    const PathDriver::Step step = driver_->update(pose, now, dt, bumper_);
    if (step.replan) replan_requested_ = true;
    if (step.warn)
      ROS_WARN("frontier_baseline: motion %s: %s", toString(step.status), driver_->statusText().c_str());
    const Command& c = step.command;
    geometry_msgs::Twist t;
    t.linear.x = c.v;
    t.angular.z = c.w;
    cmd_pub_.publish(t);
  }

  ros::NodeHandle nh_, pnh_, control_nh_;
  ros::CallbackQueue control_queue_;
  BaselineParams p_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  ros::AsyncSpinner control_spinner_;
  lockstep::Participant lockstep_;
  ros::Time next_control_;  // lockstep: the sim time of the next control step
  lockstep::Publisher cmd_pub_;
  ros::Publisher map_pub_, path_pub_;
  ros::Subscriber map_scan_sub_, control_scan_sub_, bumper_sub_;
  ros::Timer timer_;

  // Main thread only.
  std::unique_ptr<OccupancyGrid> grid_;
  std::unique_ptr<FrontierExplorer> explorer_;
  Pose2D sensor_in_robot_map_;
  bool have_sensor_map_ = false;
  FrontierGoal goal_;  // the held frontier goal, map frame
  ros::Time last_plan_, last_map_publish_, last_progress_, sim_start_;
  int goals_ = 0, goals_reached_ = 0, goals_given_up_ = 0, plans_ = 0;
  size_t usable_frontiers_ = 0, total_frontiers_ = 0, scans_refused_ = 0;
  double plan_seconds_ = 0.0;
  std::chrono::steady_clock::time_point wall_start_;
  int exit_code_ = 0;

  // Shared with the control thread: under mutex_.
  std::mutex mutex_;
  std::unique_ptr<PathDriver> driver_;  // the controller and the goal's path
  bool bumper_ = false;
  double travel_ = 0.0;  // m, odometric
  Pose2D last_odom_;
  bool have_last_odom_ = false;
  std::atomic<bool> replan_requested_{false}, done_{false};

  // Control thread only.
  Pose2D sensor_in_robot_control_;
  bool have_sensor_control_ = false;
  std::vector<Eigen::Vector2d> points_;
  double last_control_ = -1.0;
};

}  // namespace exploration

int main(int argc, char** argv) {
  ros::init(argc, argv, "frontier_baseline");
  ros::NodeHandle nh;         // starts the node (and its /clock subscription) ...
  ros::Time::waitForValid();  // ... so that sim time can become valid
  try {
    exploration::FrontierBaselineNode node;
    ros::spin();
    return node.exitCode();
  } catch (const std::exception& e) {
    ROS_FATAL("frontier_baseline: %s", e.what());
    return 1;
  }
}
