// Whether a door the robot has passed on the hallway is entered (Tomatis, Nourbakhsh & Siegwart
// 2001, section 3.2: a door passed that is new, or known but not explored, while the belief is
// confident), and as which opening of the topological map:
//  - never a door the robot came out of a moment ago, nor another door of that room (seen from
//    inside it): the room is one place, explored already;
//  - never a door of a room mapped earlier, however long ago: each room's doors (the one entered by
//    and those seen from inside) are kept in the map frame of pomdp_topo's corrected dead reckoning
//    (TopoView::map_from_odom), whose heading the building's walls hold, so that a corner room's
//    second door, reached from another hallway long after, is that room's (a room with two doors
//    is one place);
//  - on a new stretch (pomdp_topo's frontier) a door is new, unless the node pomdp_topo stands at
//    has it already, explored;
//  - on the known map, an unexplored opening of the node a trusted belief puts the robot at;
//  - on a mission, only the mission's door.
// HallwayNavigator tracks the doors (HallwayDoors) and stops for the one entered.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/topo_route.h"
#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"

#include <optional>
#include <utility>
#include <vector>

namespace exploration {

/// A door of a room mapped earlier: its place and its pose there (centre, direction into the room).
struct MappedRoomDoor {
  int place_id = -1;
  laser_features::Pose2D door_in_place;
};

/// The opening of the topological map a door is entered as.
struct EntryOpening {
  int node = -1;         // -1: a new door, at pomdp_topo's current node
  double bearing = 0.0;  // rad, map frame, into the room
  bool beside_end = false;  // new, beside the end of a new stretch turned at: the belief is localized
                            // on the end's node by then, and the door is that node's
};

class DoorEntry {
 public:
  /// `doors.same_distance` and `rules` (BuildingRules::differentOpenings) tell one door from another.
  DoorEntry(const HallwayDoorParams& doors, const laser_features::BuildingRules& rules)
      : doors_(doors), rules_(rules) {}
  /// The heading bins of the topological map's bearings (the building's axes): a door is a graph
  /// opening the same way (HeadingBins::sameWay), as pomdp_topo matches openings.
  void setHeadingBins(const laser_features::HeadingBins& bins) { bins_ = bins; }

  /// Each tick: the node pomdp_topo's frontier stands at, and the travel (m) since when.
  void observe(const TopoView& topo, double travel);
  /// The robot came out of a room through `door` at `travel` (m); `others`: the room's other doors
  /// as seen from inside it (RoomVisit::otherDoorsOdom).
  void leftBy(const DoorTrack& door, const std::vector<DoorTrack>& others, double travel);
  /// `door` is one the robot came out of within the last kLeftDoorsTravel (10 m) of travel: their
  /// spans overlap and they face the same way.
  bool justLeft(const DoorTrack& door, double travel) const;
  /// `door` is another door of a room the robot came out of within the last kLeftDoorsTravel of
  /// travel: within half HallwayDoors::kSameDoorSpan of one seen from inside, facing the same way.
  bool otherDoorOfRoomLeft(const DoorTrack& door, double travel) const;

  /// The room of place `place_id` is mapped: its doors in the place (centre and direction into the
  /// room: the one entered by and those seen from inside) and the place's origin in the map frame.
  void roomMapped(int place_id, const laser_features::Pose2D& origin_map,
                  const std::vector<laser_features::Pose2D>& doors_in_place);
  /// The mapped room's door that `door` (odometry frame; `map_from_odom` takes it into the map frame)
  /// is: within half HallwayDoors::kSameDoorSpan of it, facing the same way (the nearest such).
  /// None if no mapped room has it.
  std::optional<MappedRoomDoor> mappedRoomOf(const DoorTrack& door, const laser_features::Pose2D& map_from_odom) const;

  /// The opening `door` is entered as, if it is entered. `bearing`: the door's bearing into the room
  /// as the topological map has it (map frame); `belief_trusted`: the belief is localized and
  /// confident and not on hold after a jump; `mission_door`: the running mission's door, if any.
  std::optional<EntryOpening> mayEnter(const TopoView& topo, const TopoGraph& graph, const DoorTrack& door,
                                       double bearing, bool belief_trusted, const PlaceDoor* mission_door) const;
  /// On the frontier, the node pomdp_topo is at has `door` (at `bearing`) already, explored
  /// (pomdp_topo joined the door to that node rather than making a new one).
  bool exploredAtFrontierNode(const TopoView& topo, const TopoGraph& graph, const DoorTrack& door, double bearing,
                              double travel) const;

 private:
  /// Opening `o` is the opening at `bearing` (map frame, rad) measured `width` (m) wide.
  bool sameOpening(const GraphOpening& o, double bearing, double width) const;

  HallwayDoorParams doors_;
  laser_features::BuildingRules rules_;
  laser_features::HeadingBins bins_;  // see setHeadingBins
  // The doors the robot came out of within the last kLeftDoorsTravel of travel, and the travel then:
  // none is entered again from just outside it (two doors facing the robot in turn at a hallway's
  // end would otherwise be entered again and again).
  std::vector<std::pair<DoorTrack, double>> left_doors_;
  std::vector<std::pair<DoorTrack, double>> other_doors_;  // the other doors of the rooms left, and the travel then
  static constexpr double kLeftDoorsTravel = 10.0;  // m
  struct MappedDoor {
    MappedRoomDoor door;
    Eigen::Vector2d centre_map = Eigen::Vector2d::Zero();
    double into_map = 0.0;  // rad
  };
  std::vector<MappedDoor> mapped_doors_;  // the doors of every room mapped (roomMapped)
  // The node pomdp_topo's frontier was last at, and the travel when it became so.
  int frontier_node_ = -1;
  double frontier_node_travel_ = 0.0;
};

}  // namespace exploration
