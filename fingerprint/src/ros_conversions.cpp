#include "ros_conversions.h"

#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>

namespace fingerprint {

PanoramaModel toModel(const sensor_msgs::CameraInfo& info) {
  PanoramaModel m;
  m.width = int(info.width);
  m.height = int(info.height);
  m.fx = info.K[0];
  m.fy = info.K[4];
  m.cx = info.K[2];
  m.cy = info.K[5];
  return m;
}

bool toRgb(const sensor_msgs::Image& msg, cv::Mat* rgb, std::string* why) {
  const bool is_rgb = msg.encoding == sensor_msgs::image_encodings::RGB8;
  if (!is_rgb && msg.encoding != sensor_msgs::image_encodings::BGR8) {
    *why = "encoding '" + msg.encoding + "' (rgb8 or bgr8 expected)";
    return false;
  }
  if (msg.step < msg.width * 3 || msg.data.size() < size_t(msg.step) * msg.height || msg.width == 0 || msg.height == 0) {
    *why = "a " + std::to_string(msg.width) + " x " + std::to_string(msg.height) + " image with step " +
           std::to_string(msg.step) + " and " + std::to_string(msg.data.size()) + " bytes";
    return false;
  }
  const cv::Mat view(int(msg.height), int(msg.width), CV_8UC3, const_cast<uint8_t*>(msg.data.data()), msg.step);
  if (is_rgb) *rgb = view;
  else cv::cvtColor(view, *rgb, cv::COLOR_BGR2RGB);
  return true;
}

void appendLaserFeatures(const hybrid_slam_msgs::LaserFeatures& msg, const Pose2& laser_in_camera,
                         std::vector<Feature>* out) {
  for (const auto& c : msg.corners) {
    Eigen::Matrix2d cov;
    cov << c.covariance[0], c.covariance[1], c.covariance[3], c.covariance[4];
    out->push_back(laserCorner(laser_in_camera, Eigen::Vector2d(c.x, c.y), cov, c.confidence));
  }
  for (const auto& o : msg.openings) {
    if (o.kind == hybrid_slam_msgs::OpeningFeature::UNKNOWN) continue;
    out->push_back(laserOpening(laser_in_camera, Eigen::Vector2d(o.x, o.y), o.width,
                                o.kind == hybrid_slam_msgs::OpeningFeature::DOOR, o.confidence));
  }
}

hybrid_slam_msgs::Fingerprint toMessage(const std::vector<Feature>& features, const std_msgs::Header& header,
                                        bool has_image) {
  hybrid_slam_msgs::Fingerprint m;
  m.header = header;
  m.has_image = has_image;
  m.features.reserve(features.size());
  for (const Feature& f : features) {
    hybrid_slam_msgs::FingerprintFeature x;
    x.type = uint8_t(f.type);
    x.bearing = f.bearing;
    x.bearing_sigma = f.sigma;
    x.angular_width = f.width;
    x.hue_bin = f.hue_bin >= 0 ? uint8_t(f.hue_bin) : 255;
    x.color = {f.color[0], f.color[1], f.color[2]};
    x.strength = f.strength;
    m.features.push_back(x);
  }
  return m;
}

}  // namespace fingerprint
