// The ROS-free part of the rviz plugins: the panel's lines of text from the exploration's status
// and the belief, and the GoToPlace tool's choice of place and goal in the place's frame.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "laser_features/geometry.h"

namespace hybrid_slam_rviz {

using laser_features::Pose2D;

/// What the panel shows of an ExplorationStatus (filled from the message by the panel).
struct StatusFields {
  std::string mode;  // TOPOLOGICAL, METRIC, SWITCHING or DONE
  std::string state;
  int place = -1, node = -1;
  unsigned places = 0, nodes = 0, explored = 0, unexplored = 0;
  double travel_m = 0.0, real_time_factor = 0.0;
};

struct StatusText {
  std::string mode, where, map, travel;
};

StatusText describe(const StatusFields& s);

/// "U 0.41 of U_max 2.00: confident" (nats, eq. 3 of the POMDP).
std::string beliefText(double entropy, double entropy_max, bool confident);

/// The place id of a frame named <prefix><id> (ekf_local_map's place frames), if it is one.
std::optional<int> placeOfFrame(const std::string& frame, const std::string& prefix);

struct PlaceFrame {
  int id = -1;
  Pose2D pose;  // the place frame's pose in the frame the click is in
};

/// The place whose frame origin is nearest (x, y); -1 when there is none.
int nearestPlace(const std::vector<PlaceFrame>& places, double x, double y);

/// A pose given in the click's frame, in the place's own frame (what GoToPlace takes).
Pose2D goalInPlace(const Pose2D& place_pose, const Pose2D& goal);

}  // namespace hybrid_slam_rviz
