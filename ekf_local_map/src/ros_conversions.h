// The one place where ekf_local_map's core types meet ROS messages.
#pragma once

#include <geometry_msgs/Pose2D.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <hybrid_slam_msgs/LaserFeatures.h>
#include <hybrid_slam_msgs/LocalMap.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "ekf_local_map/place_maps.h"

namespace ekf_local_map {

// The lines of a feature message as observations (sensor frame). Lines with a non-finite value
// are kept: the filter rejects and counts them.
void toObservations(const hybrid_slam_msgs::LaserFeatures& msg, std::vector<LineSegment>* out);

laser_features::Pose2D toPose(const geometry_msgs::Pose2D& p);
laser_features::Pose2D toPose(const geometry_msgs::Transform& t);
geometry_msgs::Transform toTransform(const laser_features::Pose2D& p);

// Robot pose with its 3x3 covariance placed in the 6x6 (x, y, z, roll, pitch, yaw) of ROS.
void toPoseWithCovariance(const StochasticMap& map, geometry_msgs::PoseWithCovariance* out);

// The place's lines (extent as start/end, marginal covariance) and the full joint covariance.
void toLocalMap(const StochasticMap& map, int place_id, const std_msgs::Header& header,
                hybrid_slam_msgs::LocalMap* out);

// Lines as segments (width grows with the r uncertainty), the robot's 2-sigma covariance ellipse.
void toMarkers(const StochasticMap& map, const std_msgs::Header& header, visualization_msgs::MarkerArray* out);

}  // namespace ekf_local_map
