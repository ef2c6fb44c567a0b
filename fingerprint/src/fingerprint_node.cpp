// fingerprint_node: a fingerprint of place from each panoramic image and the laser's features of the
// same moment (hybrid_slam_msgs/Fingerprint on `fingerprint`). All the work is in the core library;
// this node pairs the messages, converts them and reports bad input.
//
// Pairing: an image waits for the laser features of its stamp (or a later scan), so that which
// scan it is paired with does not depend on which message arrives first; it is built with the
// latest features at or before its stamp, within max_stamp_gap. Without images for image_timeout,
// each scan's features make a laser-only fingerprint (has_image false), as does an image that
// cannot be used (wrong encoding or size, no camera_info, no panorama), with a throttled error.
#include <hybrid_slam_msgs/Fingerprint.h>
#include <hybrid_slam_msgs/LaserFeatures.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2/utils.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <deque>
#include <map>
#include <optional>

#include "fingerprint/params_visit.h"
#include "lockstep/participant.h"
#include "ros_conversions.h"

namespace fingerprint {
namespace {

VisualFeatureParams readParams(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  VisualFeatureParams p;
  visitParams(&p, [&](const char* name, auto* value) { pnh.param(name, *value, *value); });
  // The camera's noise is the camera's, shared (config/camera.yaml in namespace camera).
  nh.param("camera/noise_stddev", p.image_noise_stddev, p.image_noise_stddev);
  return p;
}

class FingerprintNode {
 public:
  FingerprintNode(ros::NodeHandle nh, ros::NodeHandle pnh)
      : extractor_(readParams(nh, pnh)), tf_listener_(tf_buffer_, true, lockstep::kTransportHints), lockstep_(nh) {
    pnh.param("image_timeout", image_timeout_, 1.0);
    pnh.param("max_stamp_gap", max_stamp_gap_, 0.1);
    fingerprint_pub_ = lockstep_.advertise<hybrid_slam_msgs::Fingerprint>(nh, "fingerprint", 10);
    // Counted (in lockstep a step waits for its camera_info), taken on arrival: the step's image,
    // delivered once the step's inputs are in, finds it.
    info_sub_ = lockstep_.subscribe(nh, "camera/camera_info", 2, &FingerprintNode::onInfo, this);
    image_sub_ = lockstep_.subscribe(nh, "camera/image_raw", 2, &FingerprintNode::onImage, this, lockstep::Delivery::Gated);
    features_sub_ = lockstep_.subscribe(nh, "features", 10, &FingerprintNode::onFeatures, this, lockstep::Delivery::Gated);
    ROS_INFO("fingerprint: images from '%s' with the laser's '%s' into '%s' (edges over %.0f levels)",
             image_sub_.getTopic().c_str(), features_sub_.getTopic().c_str(), fingerprint_pub_.getTopic().c_str(),
             extractor_.params().edge_step_sigmas * std::sqrt(2.0) * extractor_.params().image_noise_stddev);
  }

 private:
  void reportOnce(const std::string& cause, const std::string& detail) {
    const ros::WallTime now = ros::WallTime::now();
    auto it = last_report_.find(cause);
    if (it != last_report_.end() && (now - it->second).toSec() < 10.0) return;
    last_report_[cause] = now;
    ROS_ERROR("fingerprint: %s", detail.c_str());
  }

  void onInfo(const sensor_msgs::CameraInfo::ConstPtr& msg) { info_ = *msg; }

  void onImage(const sensor_msgs::Image::ConstPtr& msg) {
    if (pending_) build(pending_);  // its scan never came: the image goes with the laser's latest
    pending_ = msg;
    last_image_ = msg->header.stamp;
    if (!features_.empty() && features_.back()->header.stamp >= msg->header.stamp) flushPending();
  }

  void onFeatures(const hybrid_slam_msgs::LaserFeatures::ConstPtr& msg) {
    features_.push_back(msg);
    while (features_.size() > 20) features_.pop_front();
    if (pending_ && msg->header.stamp >= pending_->header.stamp) flushPending();
    if (!pending_ && (last_image_.isZero() || (msg->header.stamp - last_image_).toSec() > image_timeout_)) {
      std::vector<Feature> features;
      std::string frame = msg->header.frame_id;
      const std::optional<Pose2> laser = laserInCamera(msg->header.frame_id, camera_frame_);
      if (laser) frame = camera_frame_;
      appendLaserFeatures(*msg, laser ? *laser : Pose2(), &features);
      publish(features, msg->header.stamp, frame, false);
    }
  }

  void flushPending() {
    build(pending_);
    pending_.reset();
  }

  void build(const sensor_msgs::Image::ConstPtr& image) {
    camera_frame_ = image->header.frame_id;
    std::vector<Feature> features;
    bool has_image = false;
    std::string why;
    cv::Mat rgb;
    if (!info_) {
      reportOnce("info", "no camera_info on '" + info_sub_.getTopic() + "' yet: laser features only");
    } else if (!toRgb(*image, &rgb, &why)) {
      reportOnce("image", image_sub_.getTopic() + ": " + why + ": laser features only");
    } else if (!extractor_.extract(rgb, toModel(*info_), &features, &why)) {
      reportOnce("model", image_sub_.getTopic() + ": " + why + ": laser features only");
    } else {
      has_image = true;
    }
    // The scan of the image's moment: the latest at or before it, within max_stamp_gap.
    const hybrid_slam_msgs::LaserFeatures::ConstPtr* scan = nullptr;
    for (const auto& f : features_)
      if (f->header.stamp <= image->header.stamp && (image->header.stamp - f->header.stamp).toSec() <= max_stamp_gap_)
        scan = &f;
    std::string frame = image->header.frame_id;
    if (scan) {
      const std::optional<Pose2> laser = laserInCamera((*scan)->header.frame_id, camera_frame_);
      if (laser) {
        appendLaserFeatures(**scan, *laser, &features);
      } else if (!has_image) {
        frame = (*scan)->header.frame_id;  // laser features only, in the laser's frame
        appendLaserFeatures(**scan, Pose2(), &features);
      }
    }
    publish(features, image->header.stamp, frame, has_image);
  }

  std::optional<Pose2> laserInCamera(const std::string& laser_frame, const std::string& camera_frame) {
    if (camera_frame.empty()) return std::nullopt;
    if (laser_in_camera_ && laser_frame == cached_laser_ && camera_frame == cached_camera_) return laser_in_camera_;
    try {
      const auto t = tf_buffer_.lookupTransform(camera_frame, laser_frame, ros::Time(0));
      laser_in_camera_ = Pose2{t.transform.translation.x, t.transform.translation.y, tf2::getYaw(t.transform.rotation)};
      cached_laser_ = laser_frame;
      cached_camera_ = camera_frame;
      return laser_in_camera_;
    } catch (const tf2::TransformException& e) {
      reportOnce("tf", "no transform from the laser's '" + laser_frame + "' to the camera's '" + camera_frame +
                           "' (" + e.what() + "): the laser's features are left out of the images' fingerprints");
      return std::nullopt;
    }
  }

  void publish(std::vector<Feature>& features, const ros::Time& stamp, const std::string& frame, bool has_image) {
    sortByBearing(&features);
    std_msgs::Header header;
    header.stamp = stamp;
    header.frame_id = frame;
    fingerprint_pub_.publish(toMessage(features, header, has_image));
  }

  VisualFeatureExtractor extractor_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  lockstep::Participant lockstep_;
  lockstep::Publisher fingerprint_pub_;
  ros::Subscriber info_sub_, image_sub_, features_sub_;
  double image_timeout_ = 1.0, max_stamp_gap_ = 0.1;
  std::optional<sensor_msgs::CameraInfo> info_;
  sensor_msgs::Image::ConstPtr pending_;
  std::deque<hybrid_slam_msgs::LaserFeatures::ConstPtr> features_;
  ros::Time last_image_;
  std::string camera_frame_, cached_laser_, cached_camera_;
  std::optional<Pose2> laser_in_camera_;
  std::map<std::string, ros::WallTime> last_report_;
};

}  // namespace
}  // namespace fingerprint

int main(int argc, char** argv) {
  ros::init(argc, argv, "fingerprint");
  try {
    fingerprint::FingerprintNode node{ros::NodeHandle(), ros::NodeHandle("~")};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("fingerprint: %s", e.what());
    return 1;
  }
  return 0;
}
