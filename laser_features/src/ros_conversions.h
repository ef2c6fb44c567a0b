// The one place where laser_features' core types meet ROS messages.
#pragma once

#include <hybrid_slam_msgs/LaserFeatures.h>
#include <sensor_msgs/LaserScan.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "laser_features/feature_extractor.h"

namespace laser_features {

// A view of the message's ranges (no copy), or an error string if the header fields are
// inconsistent (see validateScanHeader).
std::string toScanView(const sensor_msgs::LaserScan& scan, ScanView* view);

// Fills `msg` with the features, in the scan's frame and stamp.
void toMsg(const Features& features, const std_msgs::Header& header, hybrid_slam_msgs::LaserFeatures* msg);

// Lines as segments, corners as arrows along their orientation (green concave, red convex),
// openings as orange bars with an arrow through them, the place type as text above the sensor.
void toMarkers(const Features& features, const std_msgs::Header& header, visualization_msgs::MarkerArray* markers);

}  // namespace laser_features
