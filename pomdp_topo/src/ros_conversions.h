// Conversions between ROS messages and pomdp_topo's core types (the only file of the package
// that knows both).
#pragma once

#include <hybrid_slam_msgs/LaserFeatures.h>
#include <hybrid_slam_msgs/TopologicalBelief.h>
#include <hybrid_slam_msgs/TopologicalMap.h>
#include <hybrid_slam_msgs/TopologicalState.h>
#include <hybrid_slam_msgs/TopoEvent.h>
#include <visualization_msgs/MarkerArray.h>

#include "laser_features/corner_extractor.h"
#include "laser_features/line_extractor.h"
#include "laser_features/opening_extractor.h"
#include "pomdp_topo/map_builder.h"
#include "pomdp_topo/pomdp_localizer.h"
#include "pomdp_topo/topo_event.h"
#include "pomdp_topo/topological_map.h"

namespace pomdp_topo {

/// Features of a scan, moved into the robot frame by `sensor_in_robot`. Entries with non-finite
/// numbers are dropped and counted in `*dropped`.
void fromMsg(const hybrid_slam_msgs::LaserFeatures& msg, const Pose2D& sensor_in_robot,
             std::vector<laser_features::LineSegment>* lines, std::vector<laser_features::Corner>* corners,
             std::vector<laser_features::Opening>* openings, size_t* dropped);

void toMsg(const TopologicalMap& map, const std_msgs::Header& header, hybrid_slam_msgs::TopologicalMap* msg);
void toMsg(const PomdpLocalizer& localizer, const std_msgs::Header& header, hybrid_slam_msgs::TopologicalBelief* msg);
/// The map builder's mode, whether the robot's place is known (MapBuilder::confident) and the
/// robot's pose in the map frame (FrontEnd::pose: the filtered heading, corrected dead reckoning) of one step.
void toMsg(MapBuilder::Mode mode, bool confident, const Pose2D& pose, const std_msgs::Header& header,
           hybrid_slam_msgs::TopologicalState* msg);
/// An event of the map builder, stamped with the step it happened at.
void toMsg(const TopoEvent& event, const std_msgs::Header& header, hybrid_slam_msgs::TopoEvent* msg);

/// The graph (nodes by type, edges, corner landmarks coloured by orientation, openings) and the
/// belief (spheres scaled by probability, at the states' display positions).
void toMarkers(const TopologicalMap& map, const PomdpLocalizer& localizer, const std_msgs::Header& header,
               visualization_msgs::MarkerArray* out);

/// Display position of a state in the map frame (interpolated between its edge's nodes).
Eigen::Vector2d displayPosition(const TopologicalMap& map, const PomdpLocalizer::State& state);

}  // namespace pomdp_topo
