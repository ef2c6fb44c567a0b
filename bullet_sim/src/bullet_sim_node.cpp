// bullet_sim_node: runs the simulator in sim time and talks ROS. All the simulation is in the core
// library; this node reads parameters, converts messages and paces the loop.
#include <geometry_msgs/Twist.h>
#include <hybrid_slam_msgs/Teleport.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cmath>
#include <thread>

#include "bullet_sim/simulator.h"
#include "lockstep_driver.h"
#include "ros_conversions.h"

namespace bullet_sim {
namespace {

template <typename T>
T param(const ros::NodeHandle& nh, const std::string& name, const T& fallback) {
  T v;
  nh.param(name, v, fallback);
  return v;
}

SimParams readSimParams(const ros::NodeHandle& pnh) {
  SimParams d;  // defaults of config/bullet_sim.yaml
  SimParams p;
  p.physics_rate = param(pnh, "physics_rate", d.physics_rate);
  p.max_linear_velocity = param(pnh, "max_linear_velocity", d.max_linear_velocity);
  p.max_angular_velocity = param(pnh, "max_angular_velocity", d.max_angular_velocity);
  p.max_linear_accel = param(pnh, "max_linear_accel", d.max_linear_accel);
  p.max_angular_accel = param(pnh, "max_angular_accel", d.max_angular_accel);
  p.wheel_base = param(pnh, "wheel_base", d.wheel_base);
  p.laser_beams = param(pnh, "laser_beams", d.laser_beams);
  p.laser_fov = param(pnh, "laser_fov", d.laser_fov);
  p.laser_range_min = param(pnh, "laser_range_min", d.laser_range_min);
  p.laser_range_max = param(pnh, "laser_range_max", d.laser_range_max);
  p.laser_noise_stddev = param(pnh, "laser_noise_stddev", d.laser_noise_stddev);
  p.odom_left_radius_error = param(pnh, "odom_left_radius_error", d.odom_left_radius_error);
  p.odom_right_radius_error = param(pnh, "odom_right_radius_error", d.odom_right_radius_error);
  p.odom_wheelbase_error = param(pnh, "odom_wheelbase_error", d.odom_wheelbase_error);
  p.odom_wheel_noise = param(pnh, "odom_wheel_noise", d.odom_wheel_noise);
  p.seed = static_cast<uint64_t>(param(pnh, "seed", static_cast<int>(d.seed)));
  return p;
}

CameraParams readCameraParams(const ros::NodeHandle& pnh) {
  CameraParams d;  // defaults of config/bullet_sim.yaml
  CameraParams p;
  p.width = param(pnh, "camera_width", d.width);
  p.height = param(pnh, "camera_height", d.height);
  p.vertical_fov = param(pnh, "camera_vertical_fov", d.vertical_fov);
  p.max_range = param(pnh, "camera_max_range", d.max_range);
  // The camera's noise is shared with the nodes that read its images (config/camera.yaml, namespace camera).
  p.noise_stddev = param(ros::NodeHandle(), "camera/noise_stddev", d.noise_stddev);
  p.ambient = param(pnh, "camera_ambient", d.ambient);
  return p;
}

// Fires every `period` of sim time, on the step at or after each multiple of it.
class Every {
 public:
  explicit Every(double rate_hz) : period_(rate_hz > 0 ? 1.0 / rate_hz : 0.0) {}
  bool due(double t) {
    if (period_ <= 0.0 || t + 1e-9 < next_) return false;
    next_ += period_ * std::max(1.0, std::floor((t + 1e-9 - next_) / period_) + 1.0);
    return true;
  }

 private:
  double period_;
  double next_ = 0.0;
};

// "a/b, room_c" -> {"a/b", "room_c"}: the ~closed_doors and ~lockstep_participants parameters.
std::vector<std::string> commaList(const std::string& list) {
  std::vector<std::string> out;
  std::string item;
  for (const char c : list + ",") {
    if (c == ',') {
      if (!item.empty()) out.push_back(item);
      item.clear();
    } else if (c != ' ') {
      item += c;
    }
  }
  return out;
}

class SimNode {
 public:
  SimNode(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

  bool init() {
    std::string world_file;
    if (!pnh_.getParam("world_file", world_file)) {
      ROS_FATAL("bullet_sim: parameter ~world_file is not set (path of a worlds/*.yaml file)");
      return false;
    }
    std::string urdf;
    const std::string description_param = param<std::string>(pnh_, "robot_description_param", "robot_description");
    if (!nh_.getParam(description_param, urdf)) {
      ROS_FATAL("bullet_sim: parameter '%s' (the robot's URDF) is not set", description_param.c_str());
      return false;
    }
    base_frame_ = param<std::string>(pnh_, "base_frame", "base_link");
    laser_frame_ = param<std::string>(pnh_, "laser_frame", "laser");
    const bool camera = param(pnh_, "camera", false);
    camera_frame_ = param<std::string>(pnh_, "camera_frame", "camera");
    camera_rate_ = param(pnh_, "camera_rate", 5.0);
    odom_frame_ = param<std::string>(pnh_, "odom_frame", "odom");
    map_frame_ = param<std::string>(pnh_, "map_frame", "map");
    world_frame_ = param<std::string>(pnh_, "world_frame", "world");
    rate_ = param(pnh_, "rate", 1.0);
    scan_rate_ = param(pnh_, "scan_rate", 10.0);
    odom_rate_ = param(pnh_, "odom_rate", 50.0);
    clock_rate_ = param(pnh_, "clock_rate", 100.0);
    cmd_timeout_ = param(pnh_, "cmd_timeout", 0.5);
    publish_world_to_map_ = param(pnh_, "publish_world_to_map", true);
    fake_localization_ = param(pnh_, "fake_localization", false);
    max_sim_time_ = param(pnh_, "max_sim_time", 0.0);
    if (!(scan_rate_ > 0) || !(odom_rate_ > 0) || !(clock_rate_ > 0) || !(camera_rate_ > 0)) {
      ROS_FATAL("bullet_sim: scan_rate, odom_rate, clock_rate and camera_rate must be positive");
      return false;
    }
    try {
      World world = loadWorldFile(world_file);
      world.closeDoors(commaList(param<std::string>(pnh_, "closed_doors", "")));
      robot_ = robotModelFromUrdf(urdf, base_frame_, laser_frame_, camera ? camera_frame_ : "");
      const SimParams sim_params = readSimParams(pnh_);
      sim_ = std::make_unique<Simulator>(world, robot_, sim_params);
      if (camera) {
        // Its own noise generator: turning the camera on changes no scan or odometry message.
        camera_ = std::make_unique<PanoramicCamera>(sim_->world(), sim_->rayCaster(), readCameraParams(pnh_),
                                                    sim_params.seed ^ 0x63616d657261ull);
        if (!(robot_.camera_z > 0.0 && robot_.camera_z < sim_->world().wall_height))
          throw std::invalid_argument("the camera link '" + camera_frame_ + "' is " + std::to_string(robot_.camera_z) +
                                      " m high: it must be above the floor and below the walls' top (" +
                                      std::to_string(sim_->world().wall_height) + " m)");
      }
    } catch (const std::exception& e) {
      ROS_FATAL("bullet_sim: %s", e.what());
      return false;
    }
    ROS_INFO("bullet_sim: world '%s' (%zu obstacle primitives) from %s; %d beams at %.1f Hz, rate %.1fx",
             sim_->world().name.c_str(), sim_->rayCaster().primitiveCount(), world_file.c_str(), sim_->laser().beams,
             scan_rate_, rate_);

    // config/lockstep.yaml, loaded once into lockstep/ for the simulator and every participant.
    if (param(nh_, "lockstep/enabled", false)) {
      LockstepDriver::Options o;
      o.participants = commaList(param<std::string>(nh_, "lockstep/participants", ""));
      o.observers = commaList(param<std::string>(nh_, "lockstep/observers", ""));
      o.timeout = param(nh_, "lockstep/timeout", o.timeout);
      o.stop_on_timeout = param(nh_, "lockstep/stop_on_timeout", o.stop_on_timeout);
      if (o.participants.empty()) {
        ROS_FATAL("bullet_sim: lockstep/enabled is set but lockstep/participants names no node");
        return false;
      }
      lockstep_ = std::make_unique<LockstepDriver>(nh_, o);
    }
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    scan_pub_ = advertise<sensor_msgs::LaserScan>("scan", 10);
    odom_pub_ = advertise<nav_msgs::Odometry>("odom", 50);
    truth_pub_ = advertise<nav_msgs::Odometry>("ground_truth", 50);
    bumper_pub_ = advertise<std_msgs::Bool>("bumper", 10, true);
    if (camera_) {
      image_pub_ = advertise<sensor_msgs::Image>("camera/image_raw", 2);
      info_pub_ = advertise<sensor_msgs::CameraInfo>("camera/camera_info", 2);
      ROS_INFO("bullet_sim: panoramic camera %d x %d at %.1f Hz (frame '%s', %.2f m high)", camera_->params().width,
               camera_->params().height, camera_rate_, camera_frame_.c_str(), robot_.camera_z);
    }
    markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("world_markers", 1, true);
    // In lockstep a dropped cmd_vel would stall the step that counts it (lockstep::kUnboundedQueue).
    cmd_sub_ = nh_.subscribe("cmd_vel", lockstep_ ? lockstep::kUnboundedQueue : 10, &SimNode::onCmdVel, this,
                             ros::TransportHints().tcpNoDelay());
    if (lockstep_) lockstep_->watch(cmd_sub_);
    reset_srv_ = pnh_.advertiseService("reset", &SimNode::onReset, this);
    teleport_srv_ = pnh_.advertiseService("teleport", &SimNode::onTeleport, this);

    markers_pub_.publish(worldMarkers(sim_->world(), world_frame_));
    std_msgs::Bool b;
    b.data = false;
    bumper_pub_.publish(b);
    if (publish_world_to_map_) {
      // Display only: the map frame starts where the robot starts, so maps overlay the world in rviz.
      static_tf_.sendTransform(toTransform(toTf(sim_->world().start), ros::Time(0), world_frame_, map_frame_));
    }
    return true;
  }

  void run() {
    if (lockstep_ && !lockstep_->start([this](const ros::Time& t) { publishClock(t); })) return;
    const ros::WallTime wall_start = ros::WallTime::now();
    ros::WallTime last_report = wall_start;
    Every clock_due(clock_rate_), odom_due(odom_rate_), scan_due(scan_rate_), camera_due(camera_ ? camera_rate_ : 0.0);
    while (ros::ok()) {
      ros::spinOnce();
      const double t = sim_->time();
      if (t - last_cmd_time_ > cmd_timeout_) sim_->setCommand(0.0, 0.0);
      sim_->step();
      const double now = sim_->time();
      const ros::Time stamp(now);
      const bool scan_now = scan_due.due(now);
      const bool camera_now = camera_due.due(now);
      // A lockstep step: a scan or an image, or a participant's own wake-up (its control period), due
      // within half a physics step; the step's odometry and tf go out with it, so it can look them
      // up at exactly the step's stamp.
      const bool lockstep_step = lockstep_ && (scan_now || camera_now ||
                                               lockstep_->wakeDue(stamp, 0.5 / sim_->params().physics_rate));
      // In lockstep, time and odometry matter to the nodes only at the steps: publishing them in
      // between would only wake every node more often.
      const bool clock_now = clock_due.due(now), odom_now = odom_due.due(now);
      if (lockstep_ ? lockstep_step : clock_now) publishClock(stamp);
      if (sim_->bumper() != last_bumper_) {
        last_bumper_ = sim_->bumper();
        std_msgs::Bool b;
        b.data = last_bumper_;
        bumper_pub_.publish(b);
        if (last_bumper_) ROS_WARN_THROTTLE(5.0, "bullet_sim: bumper contact at t = %.2f s", now);
      }
      if (lockstep_ ? lockstep_step : odom_now) publishOdometry(stamp);
      if (scan_now) {
        sim_->scan(&ranges_);
        toLaserScan(*sim_, ranges_, stamp, 1.0 / scan_rate_, laser_frame_, &scan_msg_);
        scan_pub_.publish(scan_msg_);
      }
      if (camera_now) publishImage(stamp);
      if (lockstep_step && !lockstep_->step(stamp)) break;
      const ros::WallTime wall_now = ros::WallTime::now();
      if ((wall_now - last_report).toSec() > 10.0) {
        const double wall = (wall_now - wall_start).toSec();
        if (lockstep_)
          ROS_INFO("bullet_sim: sim time %.1f s, real-time factor %.1f; lockstep: %lu steps, %.0f %% of the wall time "
                   "waiting for the nodes (%.2f ms a step)", now, now / wall, (unsigned long)lockstep_->steps(),
                   100.0 * lockstep_->waited() / wall, 1e3 * lockstep_->waited() / std::max<double>(1, lockstep_->steps()));
        else
          ROS_INFO("bullet_sim: sim time %.1f s, real-time factor %.1f", now, now / wall);
        last_report = wall_now;
      }
      if (max_sim_time_ > 0.0 && now >= max_sim_time_) {
        ROS_INFO("bullet_sim: reached max_sim_time %.1f s", max_sim_time_);
        break;
      }
      if (rate_ > 0.0 && !lockstep_) {
        const ros::WallTime target = wall_start + ros::WallDuration(now / rate_);
        const ros::WallDuration wait = target - ros::WallTime::now();
        if (wait.toSec() > 0) wait.sleep();
      }
    }
  }

 private:
  template <class M>
  lockstep::Publisher advertise(const std::string& topic, uint32_t queue, bool latch = false) {
    if (lockstep_) return lockstep_->advertise<M>(nh_, topic, latch);
    return lockstep::Publisher(nh_.advertise<M>(topic, queue, latch), nullptr);
  }

  void publishClock(const ros::Time& stamp) {
    rosgraph_msgs::Clock c;
    c.clock = stamp;
    clock_pub_.publish(c);
  }

  void publishOdometry(const ros::Time& stamp) {
    odom_pub_.publish(toOdometry(*sim_, stamp, odom_frame_, base_frame_));
    truth_pub_.publish(toGroundTruth(*sim_, stamp, world_frame_, base_frame_));
    const tf2::Transform odom_base = toTf(sim_->odomPose());
    std::vector<geometry_msgs::TransformStamped> tfs{toTransform(odom_base, stamp, odom_frame_, base_frame_)};
    if (fake_localization_) {
      // map -> odom such that base_link sits at its true pose (no localizer running).
      const tf2::Transform map_base = toTf(sim_->world().start).inverse() * toTf(sim_->truePose());
      tfs.push_back(toTransform(map_base * odom_base.inverse(), stamp, map_frame_, odom_frame_));
    }
    tf_.sendTransform(tfs);
  }

  void publishImage(const ros::Time& stamp) {
    const Pose2& base = sim_->truePose();
    const double c = std::cos(base.yaw), s = std::sin(base.yaw);
    const Pose2 camera{base.x + c * robot_.camera_x - s * robot_.camera_y, base.y + s * robot_.camera_x + c * robot_.camera_y,
                       base.yaw + robot_.camera_yaw};
    camera_->render(camera, robot_.camera_z, &rgb_);
    toImage(rgb_, camera_->params(), stamp, camera_frame_, &image_msg_);
    image_pub_.publish(image_msg_);
    info_pub_.publish(toCameraInfo(camera_->params(), stamp, camera_frame_));
  }

  void onCmdVel(const geometry_msgs::Twist& msg) {
    if (lockstep_) lockstep_->received(cmd_sub_.getTopic());
    if (!std::isfinite(msg.linear.x) || !std::isfinite(msg.angular.z)) {
      ROS_WARN_THROTTLE(5.0, "bullet_sim: ignoring a cmd_vel with non-finite values");
      return;
    }
    sim_->setCommand(msg.linear.x, msg.angular.z);
    last_cmd_time_ = sim_->time();
  }

  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    sim_->reset();
    res.success = true;
    res.message = "robot back at the start pose, odometry restarted";
    return true;
  }

  bool onTeleport(hybrid_slam_msgs::Teleport::Request& req, hybrid_slam_msgs::Teleport::Response& res) {
    res.success = sim_->teleport({req.pose.x, req.pose.y, req.pose.theta});
    res.message = res.success ? "teleported" : "pose refused: not finite or the footprint overlaps an obstacle";
    if (!res.success) ROS_WARN("bullet_sim: teleport to (%.2f, %.2f) refused", req.pose.x, req.pose.y);
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  std::unique_ptr<Simulator> sim_;
  std::string base_frame_, laser_frame_, camera_frame_, odom_frame_, map_frame_, world_frame_;
  RobotModel robot_;
  std::unique_ptr<PanoramicCamera> camera_;  // ~camera: true
  double camera_rate_ = 5.0;
  std::vector<uint8_t> rgb_;
  sensor_msgs::Image image_msg_;
  double rate_ = 1.0, scan_rate_ = 10.0, odom_rate_ = 50.0, clock_rate_ = 100.0, cmd_timeout_ = 0.5;
  double max_sim_time_ = 0.0;
  bool publish_world_to_map_ = true, fake_localization_ = false;
  double last_cmd_time_ = -1e9;
  bool last_bumper_ = false;
  std::vector<float> ranges_;
  sensor_msgs::LaserScan scan_msg_;
  std::unique_ptr<LockstepDriver> lockstep_;  // rate 0: deterministic lockstep with the nodes
  ros::Publisher clock_pub_, markers_pub_;
  lockstep::Publisher scan_pub_, odom_pub_, truth_pub_, bumper_pub_, image_pub_, info_pub_;
  ros::Subscriber cmd_sub_;
  ros::ServiceServer reset_srv_, teleport_srv_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
};

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  ros::init(argc, argv, "bullet_sim");
  bullet_sim::SimNode node{ros::NodeHandle(), ros::NodeHandle("~")};
  if (!node.init()) return 1;
  node.run();
  return 0;
}
