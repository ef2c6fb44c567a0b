// The one place where fingerprint's core types and ROS messages meet.
#pragma once

#include <hybrid_slam_msgs/Fingerprint.h>
#include <hybrid_slam_msgs/LaserFeatures.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "fingerprint/fingerprint.h"

namespace fingerprint {

/// The panorama camera_info describes (its size and K).
PanoramaModel toModel(const sensor_msgs::CameraInfo& info);
/// `msg` as an rgb CV_8UC3 image (rgb8 shared without a copy, bgr8 converted); false with `why` for
/// any other encoding or a buffer of the wrong size.
bool toRgb(const sensor_msgs::Image& msg, cv::Mat* rgb, std::string* why);
/// The laser's corners and openings (doors, junctions) as features around the camera.
void appendLaserFeatures(const hybrid_slam_msgs::LaserFeatures& msg, const Pose2& laser_in_camera,
                         std::vector<Feature>* out);
hybrid_slam_msgs::Fingerprint toMessage(const std::vector<Feature>& features, const std_msgs::Header& header,
                                        bool has_image);

}  // namespace fingerprint
