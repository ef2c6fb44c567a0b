// Messages <-> the exploration core's types: the one place where ROS types meet the core.
#pragma once

#include <hybrid_slam_msgs/AddDoor.h>
#include <hybrid_slam_msgs/RelocateAtDoor.h>
#include <hybrid_slam_msgs/ExplorationStatus.h>
#include <hybrid_slam_msgs/LaserFeatures.h>
#include <hybrid_slam_msgs/TopologicalBelief.h>
#include <hybrid_slam_msgs/TopologicalMap.h>
#include <hybrid_slam_msgs/TopologicalState.h>
#include <sensor_msgs/LaserScan.h>
#include <ros/node_handle.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "exploration/coordinator.h"

namespace exploration {

/// Scan points (finite returns) in the robot frame, given the laser's pose in it.
void scanPoints(const sensor_msgs::LaserScan& scan, const laser_features::Pose2D& sensor_in_robot,
                std::vector<Eigen::Vector2d>* points);

/// Lines and openings of a features message (sensor frame) in the robot frame. Entries with
/// non-finite numbers are dropped (counted in `dropped`).
void featuresInRobot(const hybrid_slam_msgs::LaserFeatures& msg, const laser_features::Pose2D& sensor_in_robot,
                     std::vector<laser_features::LineSegment>* lines, std::vector<laser_features::Opening>* openings,
                     size_t* dropped);

void fromMsg(const hybrid_slam_msgs::TopologicalMap& msg, TopoGraph* graph);
/// pomdp_topo's map builder mode; Unknown for a value this version does not know.
TopoMode modeFromMsg(const hybrid_slam_msgs::TopologicalState& msg);

/// ekf_local_map's add_door request: door `door_id` (a node id) at its pose in the robot's frame.
hybrid_slam_msgs::AddDoor::Request addDoorRequest(int door_id, const laser_features::Pose2D& door_in_robot);
/// A door of place `place_id` (closed or not) at its pose in the place.
hybrid_slam_msgs::AddDoor::Request addDoorInPlaceRequest(int place_id, int door_id, const laser_features::Pose2D& door_in_place);
/// ekf_local_map's relocate_at_door request: the robot's pose in the door's frame, with independent
/// standard deviations of its position (m) and heading (rad).
hybrid_slam_msgs::RelocateAtDoor::Request relocateRequest(int place_id, int door_id, const laser_features::Pose2D& robot_from_door,
                                                          double sigma_xy, double sigma_theta);
/// The same with the pose's covariance over (x, y, theta).
hybrid_slam_msgs::RelocateAtDoor::Request relocateRequest(int place_id, int door_id, const laser_features::Pose2D& robot_from_door,
                                                          const Eigen::Matrix3d& covariance);
/// The belief's most likely state (invalid when lost or empty).
GraphPosition fromMsg(const hybrid_slam_msgs::TopologicalBelief& msg);

/// The room being explored (its grid's free and occupied cells, the goal) in the place frame.
void roomMarkers(const RoomExplorer& room, const std::string& frame, const ros::Time& stamp,
                 visualization_msgs::MarkerArray* markers);

/// The coordinator's mode and state as a text above the robot.
visualization_msgs::Marker modeMarker(CoordinatorMode mode, const std::string& state, const std::string& robot_frame,
                                      const ros::Time& stamp);

}  // namespace exploration
