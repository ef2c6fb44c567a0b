// laser_features_node: scan in, features out. All extraction is in the core library; this node
// reads parameters, converts messages and reports bad input (throttled, once per cause).
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>

#include <cmath>
#include <map>

#include "laser_features/feature_extractor.h"
#include "laser_features/building_rules_ros.h"
#include "laser_features/params_visit.h"
#include "laser_features/param_reader_ros.h"
#include "laser_features/tf_lookup.h"
#include "laser_features/node_main_ros.h"
#include "lockstep/participant.h"
#include "ros_conversions.h"

namespace laser_features {
namespace {

FeatureExtractor::Params readParams(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  FeatureExtractor::Params p;
  visitParams(&p, RosParamReader{pnh});
  p.openings.rules = readBuildingRules(nh);
  p.openings.robot_radius = readRobotFootprint(nh).radius;
  // The hallway score's width term falls to 0 at the widest hallway (config/building.yaml).
  p.place.hallway_max_width = p.openings.rules.hallway_max_width - p.place.width_softness;
  return p;
}

class FeaturesNode {
 public:
  FeaturesNode(ros::NodeHandle nh, ros::NodeHandle pnh)
      : extractor_(readParams(nh, pnh)),
        consistency_(extractor_.params().odometry_consistency),
        tf_listener_(tf_buffer_, true, lockstep::kTransportHints),
        lockstep_(nh) {
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh.param("require_transform", require_transform_, true);
    pnh.param("transform_timeout", transform_timeout_, 0.1);
    transform_timeout_ = lockstep_.transformTimeout(transform_timeout_);
    features_pub_ = lockstep_.advertise<hybrid_slam_msgs::LaserFeatures>(nh, "features", 10);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("features_markers", 2);
    scan_sub_ = lockstep_.subscribe(nh, "scan", 10, &FeaturesNode::onScan, this, lockstep::Delivery::Gated);
    ROS_INFO("laser_features: extracting from '%s' into '%s'", scan_sub_.getTopic().c_str(),
             features_pub_.getTopic().c_str());
  }

 private:
  // One throttled error per cause (the cause's text is the key).
  void reportOnce(const std::string& cause, const std::string& detail) {
    const ros::WallTime now = ros::WallTime::now();
    auto it = last_report_.find(cause);
    if (it != last_report_.end() && (now - it->second).toSec() < 10.0) return;
    if (last_report_.size() > 100) last_report_.clear();  // causes with varying text stay bounded
    last_report_[cause] = now;
    ROS_ERROR("laser_features: %s: %s", scan_sub_.getTopic().c_str(), detail.c_str());
  }

  void onScan(const sensor_msgs::LaserScanConstPtr& scan) {
    if (require_transform_ && scan->header.frame_id != base_frame_) {
      std::string why;
      geometry_msgs::TransformStamped unused;
      if (!lookupTransform(tf_buffer_, base_frame_, scan->header.frame_id, scan->header.stamp, transform_timeout_,
                           &unused, &why)) {
        reportOnce("no transform " + scan->header.frame_id,
                   "no transform from the scan's frame '" + scan->header.frame_id + "' to '" + base_frame_ +
                       "'; scan skipped (" + why + ")");
        return;
      }
    }
    ScanView view;
    std::string error = toScanView(*scan, &view);
    if (error.empty()) extractor_.extract(view, &features_, &error);
    if (!error.empty()) {
      reportOnce(error, "bad scan, publishing no features: " + error);
      features_.clear();
    }
    toMsg(features_, scan->header, &msg_);
    msg_.odometry_consistency = error.empty() ? odometryConsistency(*scan) : -1.0;
    features_pub_.publish(msg_);
    if (markers_pub_.getNumSubscribers() > 0) {
      toMarkers(features_, scan->header, &markers_);
      markers_pub_.publish(markers_);
    }
  }

  // How well odometry (tf odom_frame -> scan frame at the scan's stamp) explains the change from
  // the previous scans; -1 without odometry.
  double odometryConsistency(const sensor_msgs::LaserScan& scan) {
    Pose2D pose;
    // A bag without odometry: no waiting per scan for a frame that never comes.
    if ((!lockstep_.enabled() && !tf_buffer_._frameExists(odom_frame_)) ||
        !lookupPose2D(tf_buffer_, odom_frame_, scan.header.frame_id, scan.header.stamp, transform_timeout_, &pose)) {
      consistency_.reset();
      return -1.0;
    }
    return consistency_.update(extractor_.points(), pose);
  }

  FeatureExtractor extractor_;
  OdometryConsistency consistency_;
  std::string odom_frame_;
  Features features_;
  hybrid_slam_msgs::LaserFeatures msg_;
  visualization_msgs::MarkerArray markers_;
  std::string base_frame_;
  bool require_transform_ = true;
  double transform_timeout_ = 0.1;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::map<std::string, ros::WallTime> last_report_;
  lockstep::Participant lockstep_;
  lockstep::Publisher features_pub_;
  ros::Publisher markers_pub_;
  ros::Subscriber scan_sub_;
};

}  // namespace
}  // namespace laser_features

int main(int argc, char** argv) { return laser_features::runNode<laser_features::FeaturesNode>(argc, argv, "laser_features"); }
