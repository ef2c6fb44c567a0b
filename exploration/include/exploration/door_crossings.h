// DoorCrossings: the doors a recorded path went through, for a replayed bag.
//
// Nobody steers the robot of a recording, so no coordinator says "the robot enters this door". The
// path says it: laser_features reports doors (openings of door width, BuildingRules::isDoor) in
// each scan; their edges are kept in the odometry frame for the last `memory` metres of travel, and
// when the straight step between two scan poses crosses the line between a door's edges (within
// `edge_margin` of them), the robot went through that door. Odometry is good over a few metres, so
// a door seen from up to `memory` before it is crossed stays where it was seen; a log with a scan
// per metre (CARMEN) sees a door in one to four scans before it goes through it, too few for a
// track, never abeam (it turns into it), but always crosses its line.
// ROS-free: the node gives it each scan's odometry pose and door openings (robot frame).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "laser_features/geometry.h"

namespace exploration {

using laser_features::Pose2D;

struct DoorCrossingsParams {
  double memory = 5.0;       // m, travel for which a door sighting is kept (a door seen this far ahead is
                             // crossed within it; wheel odometry's error over it, 1-3 %, stays below edge_margin)
  double edge_margin = 0.2;  // m, the step may cross the door's line this far outside its edges (edges are
                             // the last beams on the jambs, width_tolerance short, plus odometry's error)
};

template <typename Visitor>
void visitDoorCrossingsParams(DoorCrossingsParams* p, Visitor&& visit) {
  visit("crossing_memory", &p->memory);
  visit("crossing_edge_margin", &p->edge_margin);
}

/// A door opening as laser_features reports it, in the robot frame.
struct DoorSighting {
  double left_x = 0.0, left_y = 0.0;    // m, one edge
  double right_x = 0.0, right_y = 0.0;  // m, the other
};

/// A sighting in the sensor's frame carried into the robot's (`sensor`: the sensor's pose on the robot).
DoorSighting inRobotFrame(const Pose2D& sensor, const DoorSighting& d);

/// A door the path went through: its centre in the odometry frame, theta the direction the robot
/// crossed it in (into the side it went to), and its width (mean of the sightings crossed).
struct DoorCrossing {
  Pose2D door_odom;
  double width = 0.0;
  int sightings = 0;
};

class DoorCrossings {
 public:
  using Params = DoorCrossingsParams;
  explicit DoorCrossings(const Params& params = Params()) : params_(params) {}
  static bool validate(const Params& p, std::string* why);

  /// One scan: the robot's odometry pose and the doors it sees (robot frame). Returns the door the
  /// step from the previous scan's pose went through, if any (the sightings of it are then dropped:
  /// crossing back needs the door seen again, from the other side).
  std::optional<DoorCrossing> update(const Pose2D& odom, const std::vector<DoorSighting>& doors);
  double travel() const { return travel_; }
  size_t remembered() const { return seen_.size(); }

 private:
  struct Seen {
    Eigen::Vector2d left, right;  // m, edges in the odometry frame
    double travel;                // m, travel when seen
  };
  Params params_;
  bool have_pose_ = false;
  Pose2D last_;
  double travel_ = 0.0;
  std::vector<Seen> seen_;
};

}  // namespace exploration
