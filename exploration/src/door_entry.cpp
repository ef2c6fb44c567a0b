#include "exploration/door_entry.h"

#include <algorithm>
#include <cmath>

namespace exploration {

using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::transformPoint;

void DoorEntry::observe(const TopoView& topo, double travel) {
  if (topo.mode != TopoMode::Frontier || !topo.position.valid || !topo.position.at_node) {
    frontier_node_ = -1;  // a new stretch from the same node later starts counting again
  } else if (int(topo.position.id) != frontier_node_) {
    frontier_node_ = int(topo.position.id);
    frontier_node_travel_ = travel;
  }
}

void DoorEntry::leftBy(const DoorTrack& door, const std::vector<DoorTrack>& others, double travel) {
  const auto old = [&](const std::pair<DoorTrack, double>& left) { return travel - left.second > kLeftDoorsTravel; };
  left_doors_.erase(std::remove_if(left_doors_.begin(), left_doors_.end(), old), left_doors_.end());
  other_doors_.erase(std::remove_if(other_doors_.begin(), other_doors_.end(), old), other_doors_.end());
  left_doors_.emplace_back(door, travel);
  for (const DoorTrack& o : others) other_doors_.emplace_back(o, travel);
}

namespace {
// A door's direction into the room, seen from the hallway and from inside, or passed twice, agrees
// within this (rad): a door facing the other way at the same place is the room's across the hallway.
constexpr double kSameDirection = 0.5;

// `door` is one of `doors` recorded within `window` (m) of travel: centres within `distance(seen)`,
// directions into the room within kSameDirection.
template <typename Distance>
bool seenWithin(const std::vector<std::pair<DoorTrack, double>>& doors, const DoorTrack& door, double travel,
                double window, Distance distance) {
  return std::any_of(doors.begin(), doors.end(), [&](const std::pair<DoorTrack, double>& seen) {
    return travel - seen.second <= window &&
           (door.centre_odom - seen.first.centre_odom).norm() < distance(seen.first) &&
           std::abs(normalizeAngle(door.into_odom - seen.first.into_odom)) < kSameDirection;
  });
}
}  // namespace

bool DoorEntry::justLeft(const DoorTrack& door, double travel) const {
  // Two doors in one wall cannot overlap: the door passed is the one left only where their spans
  // do, centres closer than half the sum of their widths. A door beside it (door centres 1.2 m
  // apart and more) is another room's. Within kLeftDoorsTravel of travel the odometry has not
  // drifted by that much.
  return seenWithin(left_doors_, door, travel, kLeftDoorsTravel,
                    [&](const DoorTrack& left) { return 0.5 * (door.width + left.width); });
}

bool DoorEntry::otherDoorOfRoomLeft(const DoorTrack& door, double travel) const {
  // Seen from inside the room (the EKF's place) and tracked from the hallway, one door lies well
  // within half the span that tells two doors apart; within kLeftDoorsTravel the odometry has not
  // drifted by it. Its direction into the room is the same seen from either side.
  return seenWithin(other_doors_, door, travel, kLeftDoorsTravel,
                    [](const DoorTrack&) { return 0.5 * HallwayDoors::kSameDoorSpan; });
}

void DoorEntry::roomMapped(int place_id, const Pose2D& origin_map, const std::vector<Pose2D>& doors_in_place) {
  for (const Pose2D& d : doors_in_place) {
    const Pose2D m = laser_features::compose(origin_map, d);
    mapped_doors_.push_back(MappedDoor{MappedRoomDoor{place_id, d}, Eigen::Vector2d(m.x, m.y), normalizeAngle(m.theta)});
  }
}

std::optional<MappedRoomDoor> DoorEntry::mappedRoomOf(const DoorTrack& door, const Pose2D& map_from_odom) const {
  // The map frame's drift between two passes is its heading filter's residual and the wheels'
  // along-track noise: a few decimetres over a floor, well within half the span that tells two
  // doors apart (doors 1.2 m apart on one wall, where two share a divider, stay two).
  const Eigen::Vector2d centre = transformPoint(map_from_odom, door.centre_odom);
  const double into = normalizeAngle(door.into_odom + map_from_odom.theta);
  const MappedDoor* best = nullptr;
  double best_distance = 0.5 * HallwayDoors::kSameDoorSpan;
  for (const MappedDoor& m : mapped_doors_) {
    const double distance = (m.centre_map - centre).norm();
    if (distance >= best_distance || std::abs(normalizeAngle(into - m.into_map)) >= kSameDirection) continue;
    best = &m;
    best_distance = distance;
  }
  if (best == nullptr) return std::nullopt;
  return best->door;
}

std::optional<EntryOpening> DoorEntry::mayEnter(const TopoView& topo, const TopoGraph& graph, const DoorTrack& door,
                                                double bearing, bool belief_trusted,
                                                const PlaceDoor* mission_door) const {
  if (mission_door) {
    // Only the mission's door, at its node as a trusted belief says, on its side, and as wide as
    // the map has it: a door of another width is another room's, however alike the rooms are
    // (widthsApart: the spread of one door's widths measured from different places).
    if (!belief_trusted) return std::nullopt;
    const int n = graph.nearestNode(topo.position);
    if (n < 0 || uint32_t(n) != mission_door->node) return std::nullopt;
    if (!bins_.sameWay(mission_door->opening.bearing, bearing)) return std::nullopt;
    if (rules_.widthsApart(mission_door->opening.width, door.width)) return std::nullopt;
    return EntryOpening{n, mission_door->opening.bearing};
  }
  if (topo.mode == TopoMode::Frontier) return EntryOpening{-1, bearing};  // a door on a new stretch is new: its node is pomdp_topo's current one
  if (!belief_trusted) return std::nullopt;
  const int n = graph.nearestNode(topo.position);
  if (n < 0) return std::nullopt;
  for (const GraphOpening& o : graph.unexplored(uint32_t(n))) {
    // A known door not explored yet: the records go to that node and that opening.
    if (sameOpening(o, bearing, door.width)) return EntryOpening{n, o.bearing};
  }
  return std::nullopt;
}

bool DoorEntry::sameOpening(const GraphOpening& o, double bearing, double width) const {
  // A door beside a junction's branch on the same side is not that branch; a door measured
  // another width is that door (as pomdp_topo's TopologicalMap::differentOpenings).
  if (rules_.differentOpenings(o.width, width)) return false;
  return bins_.sameWay(o.bearing, bearing);
}

bool DoorEntry::exploredAtFrontierNode(const TopoView& topo, const TopoGraph& graph, const DoorTrack& door,
                                       double bearing, double travel) const {
  if (topo.mode != TopoMode::Frontier || !topo.position.valid || !topo.position.at_node) return false;
  // Only near the node (a door joined to it lies within a door's spacing): a new door on the same
  // side farther on, whose node pomdp_topo has not made yet, is not this one.
  if (int(topo.position.id) != frontier_node_ || travel - frontier_node_travel_ > 2.0 * doors_.same_distance)
    return false;
  const GraphNode* n = graph.node(topo.position.id);
  if (n == nullptr) return false;  // a node made for this door, not in the graph received yet
  return std::any_of(n->openings.begin(), n->openings.end(),
                     [&](const GraphOpening& o) { return o.explored && sameOpening(o, bearing, door.width); });
}

}  // namespace exploration
