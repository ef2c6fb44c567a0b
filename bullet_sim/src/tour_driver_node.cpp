// tour_driver_node: a scripted teleoperator for demos and tests. It drives the simulated robot
// through a list of waypoints (config/tours/*.yaml) by reading the simulator's ground truth, as a
// person with a joystick would by looking at the robot. Never used by mapping or localization.
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <yaml-cpp/yaml.h>

#include "lockstep/participant.h"


#include <cmath>
#include <functional>
#include <vector>

namespace {

struct Waypoint {
  double x, y;
};

class TourDriver {
 public:
  TourDriver(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), lockstep_(nh) {
    pnh.param("linear_speed", linear_speed_, 0.5);
    pnh.param("angular_speed", angular_speed_, 1.2);
    pnh.param("goal_tolerance", goal_tolerance_, 0.15);
    pnh.param("turn_in_place_angle", turn_in_place_angle_, 0.35);
    pnh.param("loops", loops_, 1);
    pnh.param("shutdown_when_done", shutdown_when_done_, true);
    std::string file;
    if (!pnh.getParam("tour_file", file)) throw std::runtime_error("parameter ~tour_file is not set");
    YAML::Node root;
    try {
      root = YAML::LoadFile(file);
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(file + ": " + e.what());
    }
    if (!root["waypoints"] || !root["waypoints"].IsSequence())
      throw std::runtime_error(file + ": needs a list 'waypoints' of [x, y] points");
    for (const auto& p : root["waypoints"]) {
      if (!p.IsSequence() || p.size() != 2) throw std::runtime_error(file + ": a waypoint must be [x, y]");
      waypoints_.push_back({p[0].as<double>(), p[1].as<double>()});
    }
    if (waypoints_.empty()) throw std::runtime_error(file + ": no waypoints");
    pnh.param("control_rate", control_rate_, 50.0);
    cmd_pub_ = lockstep_.advertise<geometry_msgs::Twist>(nh_, "cmd_vel", 10);
    done_pub_ = lockstep_.advertise<std_msgs::Bool>(nh_, "tour_done", 1, true);
    // In lockstep, each ground truth is acted on at the simulator's step of its stamp, and a step is
    // asked for every control period (that of the ground truth by default).
    truth_sub_ = lockstep_.subscribe<nav_msgs::Odometry>(
        nh_, "ground_truth", 10, [this](const nav_msgs::Odometry::ConstPtr& m) { onTruth(*m); }, lockstep::Delivery::Gated);
    lockstep_.onStep([this](const ros::Time& t) { return lockstep::nextMultiple(t, 1.0 / control_rate_); });
    std_msgs::Bool done;
    done.data = false;
    done_pub_.publish(done);
    ROS_INFO("tour_driver: %zu waypoints from %s", waypoints_.size(), file.c_str());
  }

 private:
  void onTruth(const nav_msgs::Odometry& msg) {
    if (finished_) return;
    const double x = msg.pose.pose.position.x, y = msg.pose.pose.position.y;
    const auto& q = msg.pose.pose.orientation;
    const double yaw = std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
    const Waypoint& goal = waypoints_[next_];
    const double dx = goal.x - x, dy = goal.y - y;
    const double dist = std::hypot(dx, dy);
    geometry_msgs::Twist cmd;
    if (dist < goal_tolerance_) {
      if (++next_ == waypoints_.size()) {
        next_ = 0;
        if (++loop_ >= loops_) {
          finish();
          return;
        }
      }
      cmd_pub_.publish(cmd);
      return;
    }
    const double err = std::remainder(std::atan2(dy, dx) - yaw, 2.0 * M_PI);
    cmd.angular.z = std::max(-angular_speed_, std::min(angular_speed_, 2.0 * err));
    if (std::abs(err) < turn_in_place_angle_) cmd.linear.x = std::min(linear_speed_, 0.8 * dist + 0.05);
    cmd_pub_.publish(cmd);
  }

  void finish() {
    finished_ = true;
    cmd_pub_.publish(geometry_msgs::Twist());
    std_msgs::Bool done;
    done.data = true;
    done_pub_.publish(done);
    ROS_INFO("tour_driver: tour finished");
    if (shutdown_when_done_) ros::shutdown();
  }

  ros::NodeHandle nh_;
  std::vector<Waypoint> waypoints_;
  size_t next_ = 0;
  int loop_ = 0, loops_ = 1;
  bool finished_ = false, shutdown_when_done_ = true;
  double linear_speed_, angular_speed_, goal_tolerance_, turn_in_place_angle_, control_rate_ = 50.0;
  lockstep::Participant lockstep_;
  lockstep::Publisher cmd_pub_, done_pub_;
  ros::Subscriber truth_sub_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "tour_driver");
  try {
    TourDriver driver{ros::NodeHandle(), ros::NodeHandle("~")};
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("tour_driver: %s", e.what());
    return 1;
  }
  return 0;
}
