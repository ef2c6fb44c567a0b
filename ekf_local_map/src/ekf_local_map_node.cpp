// ekf_local_map_node: one stochastic map per place (Tomatis et al. 2001, section 3.4). The filter is
// the core library; this node feeds it odometry increments (tf odom -> base_link) and the lines of
// `features`, answers the coordinator's place services and publishes the pose, the map and, while
// a place is active (metric mode), map -> odom.
#include <hybrid_slam_msgs/ActivatePlace.h>
#include <hybrid_slam_msgs/AddDoor.h>
#include <hybrid_slam_msgs/CreatePlace.h>
#include <hybrid_slam_msgs/LoadMap.h>
#include <hybrid_slam_msgs/RelocateAtDoor.h>
#include <hybrid_slam_msgs/RelocationResult.h>
#include <hybrid_slam_msgs/SaveMap.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <optional>

#include "laser_features/param_reader_ros.h"
#include "laser_features/tf_lookup.h"
#include "laser_features/node_main_ros.h"
#include "lockstep/participant.h"
#include "ekf_local_map/odometry_noise.h"
#include "ekf_local_map/params_visit.h"
#include "ekf_local_map/persistence.h"
#include "ekf_local_map/place_maps.h"
#include "ros_conversions.h"

namespace ekf_local_map {
namespace {

using laser_features::Pose2D;

StochasticMapParams readMapParams(const ros::NodeHandle& pnh) {
  StochasticMapParams p;
  visitParams(&p, laser_features::RosParamReader{pnh});
  return p;
}

class LocalMapNode {
 public:
  LocalMapNode(ros::NodeHandle nh, ros::NodeHandle pnh)
      : nh_(nh), maps_(readMapParams(pnh)), tf_listener_(tf_buffer_, true, lockstep::kTransportHints) {
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param<std::string>("place_frame_prefix", place_prefix_, "place_");
    pnh.param("publish_tf", publish_tf_, true);
    pnh.param("transform_tolerance", transform_tolerance_, 0.1);
    pnh.param("transform_timeout", transform_timeout_, 0.1);
    pnh.param<std::string>("map_file", map_file_, "");
    // Closed places are saved compact (marginals, float32) unless this asks for the joint covariance.
    pnh.param("store_joint_covariance", save_options_.store_joint_covariance, save_options_.store_joint_covariance);
    double wheel_noise, wheel_base, inflation;
    pnh.param("odom_wheel_noise", wheel_noise, 0.005);
    pnh.param("odom_wheel_base", wheel_base, 0.40);
    pnh.param("odom_inflation", inflation, 1.2);
    noise_ = OdometryNoise::fromWheelModel(wheel_noise, wheel_base, inflation);

    transform_timeout_ = lockstep_.transformTimeout(transform_timeout_);
    pose_pub_ = lockstep_.advertise<geometry_msgs::PoseWithCovarianceStamped>(nh_, "local_pose", 10);
    map_pub_ = lockstep_.advertise<hybrid_slam_msgs::LocalMap>(nh_, "local_map", 2, true);
    markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("local_map_markers", 2);
    // The same estimate as map -> odom, as a topic: for nodes that cannot take it from tf (a replay,
    // where publish_tf is off because a recorded bag may hold a map -> odom of its own).
    map_odom_pub_ = nh_.advertise<geometry_msgs::TransformStamped>("map_odom", 10);
    places_markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("places_markers", 1, true);
    relocation_pub_ = lockstep_.advertise<hybrid_slam_msgs::RelocationResult>(nh_, "relocation", 10);
    // In lockstep, the features of a step wait for laser_features' acknowledgement of it.
    features_sub_ = lockstep_.subscribe(nh_, "features", 10, &LocalMapNode::onFeatures, this, lockstep::Delivery::Gated);
    services_ = {
        pnh.advertiseService("create_place", &LocalMapNode::onCreate, this),
        pnh.advertiseService("activate_place", &LocalMapNode::onActivate, this),
        pnh.advertiseService("close_place", &LocalMapNode::onClose, this),
        pnh.advertiseService("add_door", &LocalMapNode::onAddDoor, this),
        pnh.advertiseService("relocate_at_door", &LocalMapNode::onRelocate, this),
        pnh.advertiseService("save_map", &LocalMapNode::onSave, this),
        pnh.advertiseService("load_map", &LocalMapNode::onLoad, this),
    };
    bool load_on_start = false;
    pnh.param("load_on_start", load_on_start, false);
    if (load_on_start && !map_file_.empty()) {
      std::string message;
      load(map_file_, &message);
      ROS_INFO("ekf_local_map: %s", message.c_str());
    }
  }

 private:
  void reportOnce(const std::string& what) { ROS_ERROR_THROTTLE(10.0, "ekf_local_map: %s", what.c_str()); }

  bool lookup(const std::string& target, const std::string& source, const ros::Time& stamp, Pose2D* out,
              std::string* why) {
    return laser_features::lookupPose2D(tf_buffer_, target, source, stamp, transform_timeout_, out, why);
  }

  void onFeatures(const hybrid_slam_msgs::LaserFeaturesConstPtr& msg) {
    std::string why;
    Pose2D sensor_in_robot;
    if (!lookup(base_frame_, msg->header.frame_id, msg->header.stamp, &sensor_in_robot, &why)) {
      reportOnce("features in frame '" + msg->header.frame_id + "' refused: no transform to '" + base_frame_ +
                 "' (" + why + ")");
      return;
    }
    Pose2D odom;
    if (!lookup(odom_frame_, base_frame_, msg->header.stamp, &odom, &why)) {
      reportOnce("no odometry (" + odom_frame_ + " -> " + base_frame_ + ") at the features' time: " + why);
      return;
    }
    if (origin_stamp_ && msg->header.stamp < *origin_stamp_) {
      // Taken before the new place's origin (the odometry's latest pose when it was created): the
      // scan was still on its way. Not the place's; no error.
      ROS_DEBUG("ekf_local_map: features from before the place's origin skipped");
      return;
    }
    if (last_stamp_ && msg->header.stamp < *last_stamp_) {
      reportOnce("features out of time order on '" + features_sub_.getTopic() + "': skipped");
      return;
    }
    StochasticMap* map = maps_.active();
    if (map && last_odom_) {
      const Pose2D increment = laser_features::compose(laser_features::inverse(*last_odom_), odom);
      map->predict(increment, noise_.covariance(increment));  // eqs. 7-8
    }
    last_odom_ = odom;
    last_stamp_ = msg->header.stamp;
    if (!map) {
      sendMapToOdom(msg->header.stamp);  // between places: the last place's correction, held
      return;
    }

    toObservations(*msg, &observations_);
    map->update(observations_, sensor_in_robot, &report_);  // eqs. 13-17, new lines eqs. 9-11
    if (report_.rejected_not_finite + report_.rejected_not_positive_definite > 0)
      ROS_WARN_THROTTLE(10.0, "ekf_local_map: %u line(s) with NaN or a non-positive-definite covariance rejected",
                        report_.rejected_not_finite + report_.rejected_not_positive_definite);
    if (report_.gating_failure)
      ROS_WARN_THROTTLE(5.0, "ekf_local_map: place %u: %u lines expected, none matched (odometry jump, wrong place?); "
                        "the state was not updated", *maps_.activeId(), report_.expected_lines);
    if (report_.relocation_attempted) publishRelocation(msg->header.stamp);
    publish(msg->header.stamp, odom);
  }

  void publishRelocation(const ros::Time& stamp) {
    hybrid_slam_msgs::RelocationResult r;
    r.header.stamp = stamp;
    r.place_id = static_cast<int>(*maps_.activeId());
    r.success = report_.relocation.success();
    r.verdict = toString(report_.relocation.verdict);
    r.matched = report_.relocation.matched;
    r.joint_nis = report_.relocation.joint_nis;
    r.joint_nis_bound = report_.relocation.joint_nis_bound;
    relocation_pub_.publish(r);
    // A pending relocation is tried on every scan until it succeeds: each verdict is published, the
    // log says when it changes and how many scans it took (not one line per scan).
    if (r.success) {
      ROS_INFO("ekf_local_map: relocated in place %d (%u lines matched%s)", r.place_id, r.matched,
               relocation_failures_ > 0 ? (", after " + std::to_string(relocation_failures_) + " scans refused").c_str() : "");
      relocation_failures_ = 0;
      last_refusal_.clear();
      return;
    }
    ++relocation_failures_;
    if (r.verdict != last_refusal_) ROS_WARN("ekf_local_map: relocation in place %d refused: %s; tried again on the next scans",
                                             r.place_id, r.verdict.c_str());
    last_refusal_ = r.verdict;
  }

  std::string placeFrame(uint32_t id) const { return place_prefix_ + std::to_string(id); }

  void publish(const ros::Time& stamp, const Pose2D& odom) {
    const uint32_t id = *maps_.activeId();
    const StochasticMap& map = *maps_.active();
    std_msgs::Header header;
    header.stamp = stamp;
    header.frame_id = placeFrame(id);
    geometry_msgs::PoseWithCovarianceStamped pose;
    pose.header = header;
    toPoseWithCovariance(map, &pose.pose);
    pose_pub_.publish(pose);
    toLocalMap(map, static_cast<int>(id), header, &local_map_);
    map_pub_.publish(local_map_);
    if (markers_pub_.getNumSubscribers() > 0) {
      toMarkers(map, header, &markers_);
      markers_pub_.publish(markers_);
    }
    // map -> odom = (map -> place) (+) (place -> robot) (+) (odom -> robot)^-1: the EKF's estimate.
    const Pose2D map_robot = laser_features::compose(maps_.place(id)->display_pose, map.robotPose());
    map_odom_ = laser_features::compose(map_robot, laser_features::inverse(odom));
    sendMapToOdom(stamp);
  }

  /// The stack's own map -> odom (with publish_tf), post-dated (REP 105): in a place, from the
  /// place's display pose and the EKF's robot pose; between places the last place's correction is
  /// held, so the robot's pose in `map` is dead reckoning since it left the place. Before the first
  /// place, map is the odometry frame at the start.
  void sendMapToOdom(const ros::Time& stamp) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = map_frame_;
    t.child_frame_id = odom_frame_;
    t.transform = toTransform(map_odom_);
    map_odom_pub_.publish(t);
    if (!publish_tf_) return;
    t.header.stamp = stamp + ros::Duration(transform_tolerance_);
    tf_.sendTransform(t);
  }

  /// Every place's lines in its own frame (latched): the hybrid map's metric part, e.g. for a saved
  /// map shown without a robot (view_map.launch). Sent when a place is closed and after a load.
  void publishAllPlaces() {
    visualization_msgs::MarkerArray all, one;
    visualization_msgs::Marker clear;
    clear.header.frame_id = map_frame_;
    clear.header.stamp = ros::Time::now();
    clear.action = visualization_msgs::Marker::DELETEALL;
    all.markers.push_back(clear);
    for (const auto& [id, place] : maps_.places()) {
      std_msgs::Header header;
      header.stamp = clear.header.stamp;
      header.frame_id = placeFrame(id);
      toMarkers(place.map, header, &one);
      for (auto& m : one.markers) {
        if (m.ns != "lines") continue;  // not the DELETEALL nor the robot of each place
        m.ns = "place_" + std::to_string(id);
        all.markers.push_back(m);
      }
    }
    places_markers_pub_.publish(all);
  }

  void publishPlaceFrames() {
    std::vector<geometry_msgs::TransformStamped> frames;
    for (const auto& [id, place] : maps_.places()) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = ros::Time::now();
      t.header.frame_id = map_frame_;
      t.child_frame_id = placeFrame(id);
      t.transform = toTransform(place.display_pose);
      frames.push_back(t);
    }
    if (!frames.empty()) static_tf_.sendTransform(frames);
  }

  bool onCreate(hybrid_slam_msgs::CreatePlace::Request& req, hybrid_slam_msgs::CreatePlace::Response& res) {
    Pose2D display = toPose(req.display_pose);
    if (!req.use_display_pose) {
      // The robot's pose in `map`: this node's own estimate when it publishes map -> odom, else
      // whatever localizer does (a replayed bag's), else this node's estimate all the same (a bag
      // with no map frame), else nothing.
      std::string why;
      Pose2D odom;
      const bool have_odom = lookup(odom_frame_, base_frame_, ros::Time(0), &odom, &why);
      if (publish_tf_ && have_odom)
        display = laser_features::compose(map_odom_, odom);
      else if (!lookup(map_frame_, base_frame_, ros::Time(0), &display, &why))
        display = have_odom ? laser_features::compose(map_odom_, odom) : Pose2D{};
    }
    res.place_id = static_cast<int>(maps_.createPlace(display));
    // The origin is the robot's pose at its latest odometry: predictions continue from there.
    try {
      const auto t = tf_buffer_.lookupTransform(odom_frame_, base_frame_, ros::Time(0));
      last_odom_ = toPose(t.transform);
      last_stamp_ = t.header.stamp;
      origin_stamp_ = t.header.stamp;
      res.origin_stamp = t.header.stamp;
    } catch (const tf2::TransformException&) {
      last_odom_.reset();  // the first features after this set it
    }
    res.success = true;
    res.message = "place " + std::to_string(res.place_id) + " created and active";
    ROS_INFO("ekf_local_map: %s", res.message.c_str());
    publishPlaceFrames();
    return true;
  }

  bool onActivate(hybrid_slam_msgs::ActivatePlace::Request& req, hybrid_slam_msgs::ActivatePlace::Response& res) {
    res.success = req.place_id >= 0 && maps_.activate(static_cast<uint32_t>(req.place_id));
    res.message = res.success ? "place " + std::to_string(req.place_id) + " active"
                              : "no place " + std::to_string(req.place_id);
    return true;
  }

  bool onClose(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    maps_.close();
    publishAllPlaces();
    res.success = true;
    res.message = "no place active (topological mode)";
    if (!map_file_.empty()) {
      // Nothing lost on a crash: every closed place is on disk.
      const IoResult saved = savePlaces(maps_, map_file_, save_options_);
      if (!saved) res.message += "; autosave failed: " + saved.error;
    }
    return true;
  }

  bool onAddDoor(hybrid_slam_msgs::AddDoor::Request& req, hybrid_slam_msgs::AddDoor::Response& res) {
    if (req.place_id >= 0) {
      res.success = req.door_id >= 0 && maps_.addDoorInPlace(static_cast<uint32_t>(req.place_id),
                                                             static_cast<uint32_t>(req.door_id), toPose(req.door_in_place));
      res.message = res.success ? "door stored in place " + std::to_string(req.place_id)
                                : "unknown place " + std::to_string(req.place_id) + ", or a bad door id or pose";
      return true;
    }
    res.success = req.door_id >= 0 && maps_.addDoorAtRobot(static_cast<uint32_t>(req.door_id), toPose(req.door_in_robot));
    res.message = res.success ? "door stored" : "no active place, or a bad door id or pose";
    return true;
  }

  bool onRelocate(hybrid_slam_msgs::RelocateAtDoor::Request& req, hybrid_slam_msgs::RelocateAtDoor::Response& res) {
    Eigen::Matrix3d cov;
    for (int k = 0; k < 9; ++k) cov(k / 3, k % 3) = req.covariance[k];
    res.success = req.place_id >= 0 && req.door_id >= 0 &&
                  maps_.relocateAtDoor(static_cast<uint32_t>(req.place_id), static_cast<uint32_t>(req.door_id),
                                       toPose(req.robot_from_door), cov);
    res.message = res.success ? "relocating; the verdict follows on 'relocation'" : "unknown place or door";
    if (res.success) {
      relocation_failures_ = 0;
      last_refusal_.clear();
    }
    // The pose holds at req.stamp: predictions go on from the odometry then (a replay's scans run ahead
    // of its service calls; a robot turning into a door turns on meanwhile).
    Pose2D odom;
    std::string why;
    if (res.success && !req.stamp.isZero() && lookup(odom_frame_, base_frame_, req.stamp, &odom, &why)) {
      last_odom_ = odom;
      last_stamp_ = req.stamp;
    }
    return true;
  }

  bool load(const std::string& path, std::string* message) {
    PlaceMaps loaded(maps_.params());
    const IoResult r = loadPlaces(path, &loaded);
    if (!r) {
      *message = "kept the maps in memory: " + r.error;
      return false;
    }
    maps_.swap(loaded);
    last_odom_.reset();
    publishPlaceFrames();
    publishAllPlaces();
    *message = "loaded " + std::to_string(maps_.size()) + " places from " + path;
    return true;
  }

  bool onSave(hybrid_slam_msgs::SaveMap::Request& req, hybrid_slam_msgs::SaveMap::Response& res) {
    const std::string path = req.path.empty() ? map_file_ : req.path;
    if (path.empty()) {
      res.success = false;
      res.message = "no path given and no ~map_file parameter";
      return true;
    }
    const IoResult r = savePlaces(maps_, path, save_options_);
    res.success = static_cast<bool>(r);
    res.message = r ? "saved " + std::to_string(maps_.size()) + " places to " + path : r.error;
    return true;
  }

  bool onLoad(hybrid_slam_msgs::LoadMap::Request& req, hybrid_slam_msgs::LoadMap::Response& res) {
    const std::string path = req.path.empty() ? map_file_ : req.path;
    res.success = load(path, &res.message);
    if (!res.success) ROS_ERROR("ekf_local_map: %s", res.message.c_str());
    return true;
  }

  ros::NodeHandle nh_;
  PlaceMaps maps_;
  OdometryNoise noise_;
  std::string map_frame_, odom_frame_, base_frame_, place_prefix_, map_file_;
  PlacesSaveOptions save_options_;
  bool publish_tf_ = true;
  int relocation_failures_ = 0;  // scans the pending relocation was refused on
  std::string last_refusal_;     // the verdict of the last refusal (logged when it changes)
  double transform_tolerance_ = 0.1, transform_timeout_ = 0.1;
  Pose2D map_odom_{};  // the stack's map -> odom (see sendMapToOdom)
  std::optional<Pose2D> last_odom_;
  std::optional<ros::Time> last_stamp_;
  std::optional<ros::Time> origin_stamp_;  // the latest place's origin: features before it are skipped quietly
  std::vector<LineSegment> observations_;
  UpdateReport report_;
  hybrid_slam_msgs::LocalMap local_map_;
  visualization_msgs::MarkerArray markers_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  lockstep::Participant lockstep_{nh_, {"laser_features"}};
  lockstep::Publisher pose_pub_, map_pub_, relocation_pub_;
  ros::Publisher map_odom_pub_, markers_pub_, places_markers_pub_;
  ros::Subscriber features_sub_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace
}  // namespace ekf_local_map

int main(int argc, char** argv) { return laser_features::runNode<ekf_local_map::LocalMapNode>(argc, argv, "ekf_local_map"); }
