// What the exploration coordinator takes in each tick (Perception, TopoView, MotionFeedback) and gives
// out (Decision with its Requests): shared by the Coordinator and the classes it delegates to
// (HallwayNavigator, RoomVisit, MissionRunner).
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/topo_route.h"
#include "laser_features/geometry.h"
#include "laser_features/line_extractor.h"
#include "laser_features/opening_extractor.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace exploration {

enum class CoordinatorMode : uint8_t { Topological = 0, Metric = 1, Switching = 2, Done = 3 };
const char* toString(CoordinatorMode mode);

/// One tick's perception: the scan and its features, at one stamp.
struct Perception {
  double stamp = 0.0;                      // s
  laser_features::Pose2D odom;             // robot in the odometry frame at the stamp
  laser_features::Pose2D sensor_in_robot;  // the laser in the robot frame
  std::vector<float> ranges;               // the raw scan (REP 117), for the room grid
  double angle_min = 0.0, angle_increment = 0.0;
  std::vector<Eigen::Vector2d> points;     // scan points, robot frame
  std::vector<laser_features::LineSegment> lines;  // robot frame
  std::vector<laser_features::Opening> openings;   // robot frame
  bool room_pose_valid = false;            // the EKF's robot pose in the active place at the stamp
  laser_features::Pose2D room_pose;
  Eigen::Matrix3d room_pose_cov = Eigen::Matrix3d::Zero();  // its covariance over (x, y, theta) as the EKF
                                                            // gave it; zero where it did not (odometry since)
};

/// pomdp_topo's map builder mode (TopologicalState): Unknown until the first state arrives.
enum class TopoMode : uint8_t { Unknown, Frontier, Localized, LoopCheck };

/// What pomdp_topo says (its latest messages).
struct TopoView {
  bool valid = false;         // something was received
  TopoMode mode = TopoMode::Unknown;
  bool confident = false;
  bool heading_valid = false;
  // map <- odom as pomdp_topo's corrected dead reckoning has it (theta: map heading - odometry
  // heading, the heading estimator's correction; valid with heading_valid): a pose in
  // the odometry frame composed with it is in the frame of the graph's display poses. Its drift is
  // the residual of the filtered heading and the wheels' along-track noise, not the odometry's
  // heading random walk; held while the robot is in a room (pomdp_topo publishes no state there).
  laser_features::Pose2D map_from_odom;
  GraphPosition position;       // the belief's most likely state
};

/// The motion controller's status for the last goal sent.
struct MotionFeedback {
  bool reached = false;
  bool blocked = false;
};

/// Door ids from here up name doors that no door node names (above any node id, so no mission routes
/// to them): a replay's crossed doors (PassivePlaces) and, in a host room's place, the origin of each
/// room behind it (Coordinator: the host is relocated there when the robot comes back).
constexpr int kNodelessDoorIdBase = 1000000;

/// A request to another node.
struct Request {
  enum Kind { CreatePlace, AddDoor, RecordOpening, ClosePlace, SaveMaps, Finish, Relocate, ResetBelief };
  Kind kind = SaveMaps;
  int node = -1;             // RecordOpening: -1 = pomdp_topo's current node
  double bearing = 0.0;      // RecordOpening: rad, map frame
  double width = 0.0;        // RecordOpening: m
  double offset = 0.0;       // RecordOpening: m
  bool explored = false;     // RecordOpening
  bool beside_robot = false; // RecordOpening with node -1: a door beside the robot where it stopped
                             // (on a new stretch pomdp_topo makes its node there)
  bool store_in_place = false;  // RecordOpening with place_id: the door is stored in that place too
                                // (ekf_local_map, under its node's id), a way to relocate there
  int place_id = -1;         // RecordOpening (link), AddDoor, Relocate
  int door_id = -1;          // AddDoor, Relocate
  laser_features::Pose2D pose;  // AddDoor: door in the robot frame; RecordOpening: door in the place;
                                // Relocate: the robot in the door's frame
  std::optional<Eigen::Matrix3d> pose_cov;  // Relocate: pose's covariance, where known (else the door's
                                            // sigmas, relocation_sigma_xy and _theta)
  bool success = true;       // Finish: complete exploration
  std::string text;          // Finish: summary
};

struct Decision {
  bool has_goal = false;     // drive to (x, y[, theta]) in the odometry frame
  double x = 0.0, y = 0.0;
  std::optional<double> theta;
  std::optional<std::pair<double, double>> tolerance;  // m, rad: the goal's, if not the controller's own
  std::optional<double> passage_width;  // m, the robot is passing a door this wide (MotionController::setPassageWidth)
  bool stop = false;         // stand still (no goal)
  CoordinatorMode mode = CoordinatorMode::Topological;
  std::vector<Request> requests;
};

/// x, y and theta are all finite.
inline bool finitePose(const laser_features::Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

}  // namespace exploration
