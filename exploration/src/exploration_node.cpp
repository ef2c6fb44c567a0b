// exploration_node: the coordinator that explores a building by itself (see coordinator.h), with
// the local motion controller driving cmd_vel. Thin: it converts messages, calls the core, and
// carries out the core's requests as service calls to pomdp_topo and ekf_local_map. Missions
// (GoToPlace) are an actionlib server on `go_to_place` once the exploration is done (or with
// explore false, on a loaded map).
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/Twist.h>
#include <hybrid_slam_msgs/BuildingAxes.h>
#include <hybrid_slam_msgs/ExplorationStatus.h>
#include <hybrid_slam_msgs/RelocationResult.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_srvs/SetBool.h>
#include <tf2_ros/transform_listener.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <fstream>
#include <atomic>
#include <mutex>

#include "exploration/coordinator.h"
#include "exploration/params_visit.h"
#include "exploration/run_summary.h"
#include "laser_features/building_rules_ros.h"
#include "laser_features/param_reader_ros.h"
#include "laser_features/tf_lookup.h"
#include "lockstep/participant.h"
#include "local_poses.h"
#include "mission_service.h"
#include "ros_conversions.h"
#include "service_requests.h"

namespace exploration {

using laser_features::Pose2D;


class ExplorationNode {
 public:
  ExplorationNode()
      : nh_(),
        pnh_("~"),
        tf_listener_(tf_buffer_, true, lockstep::kTransportHints),
        control_spinner_(1, &control_queue_),
        lockstep_(nh_, lockstepUpstream(pnh_)) {
    visitParams(&params_, laser_features::RosParamReader{pnh_});
    params_.coordinator.rules = laser_features::readBuildingRules(nh_);
    params_.coordinator.doors.tracks = laser_features::readOpeningTracks(nh_);
    applyFootprint(laser_features::readRobotFootprint(nh_), &params_);
    std::string why;
    if (!params_.coordinator.valid(&why) || !MotionController::validate(params_.motion, &why)) {
      ROS_FATAL("exploration: bad parameter: %s", why.c_str());
      throw std::invalid_argument(why);
    }
    coordinator_ = std::make_unique<Coordinator>(params_.coordinator);
    motion_ = std::make_unique<MotionController>(params_.motion);
    pnh_.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh_.param<std::string>("base_frame", base_frame_, "base_link");
    std::string topo_node, local_map_node;
    pnh_.param<std::string>("topo_node", topo_node, "pomdp_topo");
    pnh_.param<std::string>("local_map_node", local_map_node, "ekf_local_map");
    pnh_.param("control_rate", control_rate_, 20.0);
    pnh_.param("progress_period", progress_period_, 30.0);
    pnh_.param("shutdown_when_done", shutdown_when_done_, true);
    pnh_.param("serve_missions", serve_missions_, false);
    pnh_.param("freeze_map_for_missions", freeze_map_for_missions_, true);
    double relocation_sigma_xy = 0.05, relocation_sigma_theta = 0.05;
    pnh_.param("relocation_sigma_xy", relocation_sigma_xy, relocation_sigma_xy);
    pnh_.param("relocation_sigma_theta", relocation_sigma_theta, relocation_sigma_theta);
    requests_ = std::make_unique<ServiceRequests>(nh_, topo_node, local_map_node, relocation_sigma_xy, relocation_sigma_theta);
    if (!params_.coordinator.explore) serve_missions_ = true;
    pnh_.param<std::string>("summary_file", summary_file_, "");

    cmd_pub_ = lockstep_.advertise<geometry_msgs::Twist>(nh_, "cmd_vel", 10);
    status_pub_ = lockstep_.advertise<hybrid_slam_msgs::ExplorationStatus>(nh_, "exploration_status", 10, true);
    markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("exploration_markers", 2);
    // Motion control (scans, bumper, the control timer) has its own thread: the coordinator's
    // planning in rooms must never starve the watchdog or the velocity commands. In lockstep sim
    // time waits for the coordinator, and the control runs at the simulator's steps, on one thread.
    control_nh_.setCallbackQueue(&control_queue_);
    using lockstep::Delivery;
    scan_sub_ = lockstep_.subscribe(control_nh_, "scan", 10, &ExplorationNode::onScan, this);
    // In lockstep the features of a step wait for laser_features', pomdp_topo's and
    // ekf_local_map's output of that step.
    features_sub_ = lockstep_.subscribe(nh_, "features", 10, &ExplorationNode::onFeatures, this, Delivery::Gated);
    map_sub_ = lockstep_.subscribe(nh_, "topological_map", 2, &ExplorationNode::onMap, this);
    belief_sub_ = lockstep_.subscribe(nh_, "topological_belief", 10, &ExplorationNode::onBelief, this);
    state_sub_ = lockstep_.subscribe(nh_, "topological_state", 10, &ExplorationNode::onTopoState, this);
    axes_sub_ = lockstep_.subscribe(nh_, "building_axes", 1, &ExplorationNode::onAxes, this);
    pose_sub_ = lockstep_.subscribe(nh_, "local_pose", 10, &ExplorationNode::onLocalPose, this);
    bumper_sub_ = lockstep_.subscribe(control_nh_, "bumper", 10, &ExplorationNode::onBumper, this);
    relocation_sub_ = lockstep_.subscribe(nh_, "relocation", 10, &ExplorationNode::onRelocation, this);
    pause_srv_ = pnh_.advertiseService("pause", &ExplorationNode::onPause, this);
    if (serve_missions_) {
      MissionService::Hooks hooks;
      hooks.stop_motion = [this] {
        std::lock_guard<std::mutex> lock(mutex_);
        motion_->cancel();
        has_goal_ = false;
      };
      hooks.freeze_map = [this](std::string* message) { return requests_->setMapping(false, message); };
      hooks.final_pose = [this](hybrid_slam_msgs::GoToPlaceResult* r) {
        if (coordinator_->currentPlace() >= 0 && local_poses_.lastPlace() == coordinator_->currentPlace())
          r->final_pose = local_poses_.lastMessage().pose;
      };
      missions_ = std::make_unique<MissionService>(nh_, coordinator_.get(), &lockstep_, !mission_client_.empty(),
                                                   freeze_map_for_missions_, std::move(hooks));
    }
    if (lockstep_.enabled()) {
      lockstep_.onStep([this](const ros::Time& t) { return onStep(t); });
    } else {
      timer_ = control_nh_.createTimer(ros::Duration(1.0 / control_rate_), &ExplorationNode::onTimer, this);
      control_spinner_.start();
    }
    wall_start_ = std::chrono::steady_clock::now();
    publishStatus(ros::Time::now());
  }

 private:
  /// The participants whose output of a step the coordinator uses within that step: the perception
  /// and, when one is named (~mission_client, e.g. run_missions), the node sending GoToPlace goals,
  /// so that a goal sent at a step is taken at that step whatever the machine's load.
  std::vector<std::string> lockstepUpstream(const ros::NodeHandle& pnh) {
    pnh.param<std::string>("mission_client", mission_client_, "");
    std::vector<std::string> upstream{"laser_features", "pomdp_topo", "ekf_local_map"};
    if (!mission_client_.empty()) upstream.push_back(mission_client_);
    return upstream;
  }

  bool lookup(const std::string& target, const std::string& source, const ros::Time& stamp, Pose2D* out) {
    std::string why;
    if (laser_features::lookupPose2D(tf_buffer_, target, source, stamp, lockstep_.transformTimeout(0.1), out, &why)) return true;
    ROS_WARN_THROTTLE(5.0, "exploration: no transform %s <- %s: %s", target.c_str(), source.c_str(), why.c_str());
    return false;
  }

  void onScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    if (msg->ranges.empty() || !std::isfinite(msg->angle_min) || !std::isfinite(msg->angle_increment)) {
      ROS_WARN_THROTTLE(5.0, "exploration: an empty or malformed scan on %s is skipped", scan_sub_.getTopic().c_str());
      return;
    }
    if (!have_sensor_ && !lookup(base_frame_, msg->header.frame_id, ros::Time(0), &sensor_in_robot_)) return;
    have_sensor_ = true;
    scanPoints(*msg, sensor_in_robot_, &points_);
    std::lock_guard<std::mutex> lock(mutex_);
    motion_->setScan(points_, msg->header.stamp.toSec());
    scans_.push_back(msg);  // under the lock
    while (scans_.size() > 20) scans_.pop_front();
  }

  void onFeatures(const hybrid_slam_msgs::LaserFeatures::ConstPtr& msg) {
    sensor_msgs::LaserScan::ConstPtr scan;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& s : scans_) {
        if (s->header.stamp == msg->header.stamp) scan = s;
      }
    }
    if (!scan || !have_sensor_) return;
    if (!axes_known_) {
      // The hallways' headings are the building's axes, which pomdp_topo finds from the first scans.
      ROS_INFO_THROTTLE(5.0, "exploration: waiting for the building's axes on %s (pomdp_topo)", axes_sub_.getTopic().c_str());
      return;
    }
    Perception p;
    if (!perceive(*msg, *scan, &p)) return;
    std::unique_lock<std::mutex> lock(mutex_);
    if (paused_) {
      lock.unlock();
      if ((msg->header.stamp - last_status_).toSec() > 1.0) publishStatus(msg->header.stamp);
      return;
    }
    const bool reached = motion_->status() == MotionStatus::Reached;
    const bool blocked = motion_->status() == MotionStatus::Blocked;
    lock.unlock();
    const Decision d = coordinator_->update(p, topo_, reached, blocked);
    for (const Request& r : d.requests) execute(r);
    if (missions_) missions_->afterStep(topo_.confident ? coordinator_->graph().nearestNode(topo_.position) : -1, entropy_);
    applyGoal(d);
    report(msg->header.stamp);
  }

  /// The perception of one features message and its scan: odometry at their stamp, the scan and
  /// the features in the robot frame, and the EKF's pose in the current place. False without odometry.
  bool perceive(const hybrid_slam_msgs::LaserFeatures& msg, const sensor_msgs::LaserScan& scan, Perception* p) {
    p->stamp = msg.header.stamp.toSec();
    if (!lookup(odom_frame_, base_frame_, msg.header.stamp, &p->odom)) return false;
    p->sensor_in_robot = sensor_in_robot_;
    p->ranges = scan.ranges;
    p->angle_min = scan.angle_min;
    p->angle_increment = scan.angle_increment;
    scanPoints(scan, sensor_in_robot_, &p->points);
    size_t dropped = 0;
    featuresInRobot(msg, sensor_in_robot_, &p->lines, &p->openings, &dropped);
    if (dropped > 0) ROS_WARN_THROTTLE(10.0, "exploration: %zu non-finite features dropped", dropped);
    odom_at_features_ = p->odom;
    // In lockstep pomdp_topo's heading of these very features has arrived (the step waited for it):
    // pair it with their odometry.
    if (lockstep_.enabled() && topo_.heading_valid) pairWithOdometry(p->odom);
    const auto odom_at = [&](const ros::Time& t, Pose2D* out) { return lookup(odom_frame_, base_frame_, t, out); };
    p->room_pose_valid =
        local_poses_.at(coordinator_->currentPlace(), msg.header.stamp, p->odom, odom_at, &p->room_pose, &p->room_pose_cov);
    return true;
  }

  /// The coordinator's goal to the motion controller: a new goal only when it changed.
  void applyGoal(const Decision& d) {
    std::lock_guard<std::mutex> lock(mutex_);
    motion_->setPassageWidth(d.passage_width);
    if (d.has_goal) {
      const bool same = has_goal_ && std::abs(d.x - goal_x_) < 1e-6 && std::abs(d.y - goal_y_) < 1e-6 &&
                        d.theta.has_value() == goal_theta_.has_value() &&
                        (!d.theta || std::abs(*d.theta - *goal_theta_) < 1e-6);
      if (!same) {
        motion_->setGoal(d.x, d.y, d.theta, d.tolerance);
        goal_x_ = d.x;
        goal_y_ = d.y;
        goal_theta_ = d.theta;
        has_goal_ = true;
      }
    } else if (has_goal_) {
      motion_->cancel();
      has_goal_ = false;
    }
  }

  /// The log line on a change of mode or state, the status each second, the progress line and the markers.
  void report(const ros::Time& stamp) {
    if (coordinator_->mode() != last_mode_ || coordinator_->state() != last_state_) {
      ROS_INFO("exploration: %s - %s", toString(coordinator_->mode()), coordinator_->state().c_str());
      last_mode_ = coordinator_->mode();
      last_state_ = coordinator_->state();
      publishStatus(stamp);
    }
    if ((stamp - last_status_).toSec() > 1.0) publishStatus(stamp);
    if ((stamp - last_progress_).toSec() > progress_period_) {
      last_progress_ = stamp;
      printProgress(stamp);
    }
    if (markers_pub_.getNumSubscribers() > 0 && (stamp - last_markers_).toSec() > 1.0) {
      last_markers_ = stamp;
      visualization_msgs::MarkerArray m;
      if (coordinator_->mode() == CoordinatorMode::Metric && coordinator_->currentPlace() >= 0)
        roomMarkers(coordinator_->room(), "place_" + std::to_string(coordinator_->currentPlace()), stamp, &m);
      m.markers.push_back(modeMarker(coordinator_->mode(), coordinator_->state(), base_frame_, stamp));
      markers_pub_.publish(m);
    }
  }

  void onRelocation(const hybrid_slam_msgs::RelocationResult::ConstPtr& msg) {
    coordinator_->relocationResult(msg->place_id, msg->success, msg->verdict);
  }

  void execute(const Request& r) {
    if (r.kind == Request::Finish) finish(r);
    else requests_->execute(r, coordinator_.get());
  }

  void finish(const Request& r) {
    cmd_pub_.publish(geometry_msgs::Twist());
    publishStatus(ros::Time::now());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    const double sim = (ros::Time::now() - sim_start_).toSec();
    if (r.success) ROS_INFO("exploration: %s; %.0f s sim, %.0f s wall (real-time factor %.1f)", r.text.c_str(), sim, wall, sim / std::max(wall, 1e-3));
    else ROS_ERROR("exploration: %s; %.0f s sim, %.0f s wall", r.text.c_str(), sim, wall);
    if (!summary_file_.empty()) {
      std::ofstream f(summary_file_);
      f << runSummaryJson(*coordinator_, r.success, r.text, sim, wall);
    }
    exit_code_ = r.success ? 0 : 1;
    if (serve_missions_) {
      ROS_INFO("exploration: serving missions on %s", missions_ ? "go_to_place" : "?");
      return;  // the robot stays under control for missions
    }
    done_ = true;
    if (shutdown_when_done_) {
      ros::WallDuration(1.0).sleep();  // the final status reaches its subscribers (the evaluator) first
      ros::requestShutdown();
    }
  }

  void onTimer(const ros::TimerEvent&) { control(ros::Time(0), ros::Time::now().toSec()); }

  /// Lockstep: the control at the simulator's steps of its period (the odometry of exactly the
  /// step), and the next sim time it needs a step at.
  ros::Time onStep(const ros::Time& t) {
    if (t >= next_control_) {
      control(t, t.toSec());
      next_control_ = lockstep::nextMultiple(t, 1.0 / control_rate_);
    }
    return next_control_;
  }

  /// One control step: the odometry at `odom_stamp` (zero: the latest), at sim time `now`.
  void control(const ros::Time& odom_stamp, double now) {
    if (done_) {
      cmd_pub_.publish(geometry_msgs::Twist());
      return;
    }
    Pose2D pose;
    if (!lookup(odom_frame_, base_frame_, odom_stamp, &pose)) return;
    const double dt = last_control_ > 0.0 ? now - last_control_ : 0.0;
    last_control_ = now;
    std::lock_guard<std::mutex> lock(mutex_);
    if (paused_) {
      cmd_pub_.publish(geometry_msgs::Twist());
      return;
    }
    const Command c = motion_->update(pose, now, dt, bumper_);
    geometry_msgs::Twist t;
    t.linear.x = c.v;
    t.angular.z = c.w;
    cmd_pub_.publish(t);
    if (motion_->status() != last_motion_) {
      last_motion_ = motion_->status();
      if (last_motion_ == MotionStatus::NoScan || last_motion_ == MotionStatus::Blocked || last_motion_ == MotionStatus::Bumped)
        ROS_WARN("exploration: motion %s: %s", toString(last_motion_), motion_->statusText().c_str());
    }
  }

  void onMap(const hybrid_slam_msgs::TopologicalMap::ConstPtr& msg) {
    TopoGraph g;
    fromMsg(*msg, &g);
    coordinator_->setGraph(g);
  }
  void onBelief(const hybrid_slam_msgs::TopologicalBelief::ConstPtr& msg) {
    entropy_ = msg->entropy;
    topo_.position = fromMsg(*msg);
    topo_.valid = true;
  }
  void onAxes(const hybrid_slam_msgs::BuildingAxes::ConstPtr& msg) {
    if (!std::isfinite(msg->axis_angle) || msg->heading_bins < 4 || msg->heading_bins % 4 != 0) {
      ROS_ERROR_THROTTLE(5.0, "exploration: building axes on %s refused: axis %f, %u heading bins (a multiple of 4 wanted)",
                         axes_sub_.getTopic().c_str(), msg->axis_angle, msg->heading_bins);
      return;
    }
    coordinator_->setHeadingBins({msg->axis_angle, int(msg->heading_bins)});
    axes_known_ = true;
  }

  void onTopoState(const hybrid_slam_msgs::TopologicalState::ConstPtr& msg) {
    topo_.mode = modeFromMsg(*msg);
    topo_.confident = msg->confident;
    topo_.valid = true;
    if (!std::isfinite(msg->heading)) return;
    // pomdp_topo publishes its state right after the features it came from: pair the heading
    // with the odometry of the latest features seen here.
    topo_pose_ = Pose2D{std::isfinite(msg->x) ? msg->x : topo_pose_.x, std::isfinite(msg->y) ? msg->y : topo_pose_.y,
                        msg->heading};
    pairWithOdometry(odom_at_features_);
    topo_.heading_valid = true;
  }
  /// pomdp_topo's pose of a step paired with the odometry of the same features: map <- odom.
  void pairWithOdometry(const Pose2D& odom) {
    topo_.map_from_odom = laser_features::compose(topo_pose_, laser_features::inverse(odom));
    topo_.map_from_odom.theta = laser_features::normalizeAngle(topo_.map_from_odom.theta);
  }
  void onLocalPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) { local_poses_.add(*msg); }
  /// ~pause (SetBool): true stops the robot and the coordinator's decisions where they are (the
  /// maps keep their state); false goes on. Paused sim time counts towards the time limits.
  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    res.success = paused_ != req.data;
    res.message = req.data ? (res.success ? "exploration paused" : "already paused")
                           : (res.success ? "exploration resumed" : "not paused");
    paused_ = req.data;
    ROS_INFO("exploration: %s", res.message.c_str());
    return true;
  }

  void onBumper(const std_msgs::Bool::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    bumper_ = msg->data;
  }

  void publishStatus(const ros::Time& stamp) {
    last_status_ = stamp;
    hybrid_slam_msgs::ExplorationStatus s;
    s.header.stamp = stamp;
    s.mode = static_cast<uint8_t>(coordinator_->mode());
    s.current_place = coordinator_->mode() == CoordinatorMode::Metric ? coordinator_->placeOfRobot() : -1;
    s.current_node = topo_.confident ? coordinator_->graph().nearestNode(topo_.position) : -1;
    s.places = uint32_t(coordinator_->graph().placeCount());  // survives a restart of this node
    s.nodes = uint32_t(coordinator_->graph().nodes().size());
    s.openings_explored = uint32_t(coordinator_->graph().exploredCount());
    s.openings_unexplored = uint32_t(coordinator_->graph().unexploredCount());
    s.travel_distance = coordinator_->stats().travel;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    s.real_time_factor = (stamp - sim_start_).toSec() / std::max(wall, 1e-3);
    s.state = paused_ ? "paused: " + coordinator_->state() : coordinator_->state();
    status_pub_.publish(s);
  }

  void printProgress(const ros::Time& stamp) {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    const double sim = (stamp - sim_start_).toSec();
    ROS_INFO("exploration: %s | %zu places, %zu nodes, %zu openings explored, %zu unexplored | %.0f m | sim %.0f s, "
             "real-time factor %.1f | %s",
             toString(coordinator_->mode()), coordinator_->graph().placeCount(), coordinator_->graph().nodes().size(),
             coordinator_->graph().exploredCount(), coordinator_->graph().unexploredCount(), coordinator_->stats().travel,
             sim, sim / std::max(wall, 1e-3), coordinator_->state().c_str());
  }

 public:
  int exitCode() const { return exit_code_; }
  void setSimStart(const ros::Time& t) { sim_start_ = t; last_progress_ = t; }

 private:
  ros::NodeHandle nh_, pnh_, control_nh_;
  ros::CallbackQueue control_queue_;
  std::mutex mutex_;  // motion_, scans_, bumper_: shared by the control thread and the coordinator's
  ExplorationParams params_;
  std::unique_ptr<Coordinator> coordinator_;
  std::unique_ptr<MotionController> motion_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  ros::AsyncSpinner control_spinner_;
  std::unique_ptr<ServiceRequests> requests_;
  std::string odom_frame_, base_frame_, summary_file_;
  std::string mission_client_;  // ~mission_client: lockstep upstream sending goals ("": none)
  double control_rate_ = 20.0, progress_period_ = 30.0;
  bool shutdown_when_done_ = true;
  bool serve_missions_ = false;
  std::atomic<bool> paused_{false};  // ~pause: no decisions, no motion
  ros::ServiceServer pause_srv_;
  bool freeze_map_for_missions_ = true;  // pomdp_topo's mapping off from the first mission on
  ros::Subscriber relocation_sub_;
  double entropy_ = 0.0;
  lockstep::Participant lockstep_;
  std::unique_ptr<MissionService> missions_;  // after lockstep_: its goal count is a lockstep subscription
  ros::Time next_control_;  // lockstep: the sim time of the next control step
  lockstep::Publisher cmd_pub_, status_pub_;
  ros::Publisher markers_pub_;
  bool axes_known_ = false;  // the building's axes from pomdp_topo, before the coordinator runs
  ros::Subscriber axes_sub_;
  ros::Subscriber scan_sub_, features_sub_, map_sub_, belief_sub_, state_sub_, pose_sub_,
      bumper_sub_;
  ros::Timer timer_;
  TopoView topo_;
  std::deque<sensor_msgs::LaserScan::ConstPtr> scans_;
  std::vector<Eigen::Vector2d> points_;
  Pose2D sensor_in_robot_;
  bool have_sensor_ = false;
  Pose2D odom_at_features_;  // the odometry of the latest features seen here
  Pose2D topo_pose_;  // pomdp_topo's latest pose of the robot (map frame)
  LocalPoses local_poses_;
  bool bumper_ = false;
  bool has_goal_ = false;
  double goal_x_ = 0.0, goal_y_ = 0.0;
  std::optional<double> goal_theta_;
  double last_control_ = -1.0;
  MotionStatus last_motion_ = MotionStatus::Idle;
  CoordinatorMode last_mode_ = CoordinatorMode::Topological;
  std::string last_state_;
  ros::Time last_status_, last_progress_, last_markers_, sim_start_;
  std::chrono::steady_clock::time_point wall_start_;
  std::atomic<bool> done_{false};
  int exit_code_ = 0;
};

}  // namespace exploration

int main(int argc, char** argv) {
  ros::init(argc, argv, "exploration");
  ros::NodeHandle nh;        // starts the node (and its /clock subscription) ...
  ros::Time::waitForValid();  // ... so that sim time can become valid
  try {
    exploration::ExplorationNode node;
    node.setSimStart(ros::Time::now());
    ros::spin();
    return node.exitCode();
  } catch (const std::exception& e) {
    ROS_FATAL("exploration: %s", e.what());
    return 1;
  }
}
