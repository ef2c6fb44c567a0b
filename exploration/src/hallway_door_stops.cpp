#include "exploration/hallway_door_stops.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace exploration {

using laser_features::inverse;
using laser_features::transformPoint;

HallwayDoorStops::HallwayDoorStops(const HallwayDoorParams& params, const laser_features::BuildingRules& rules,
                                   const HallwayFollower& follower, const RoutePolicy& route)
    : follower_(follower), route_(route), doors_(params, rules), entry_(params, rules) {}

void HallwayDoorStops::forgetEndPassed(double travel) {
  if (travel - end_travel_ > 2.0 * HallwayDoors::kSameDoorSpan) left_at_end_.clear();
}

bool HallwayDoorStops::enterPassed(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v,
                                   const HallwayContext& at, HallwayStep* step, Decision* d) {
  // Doors: entered once passed, if new (frontier) or known and unexplored, and the belief is sure.
  walls_ = doors_.track(p.odom, p.openings, dir_robot, v, at.travel);
  DoorTrack door;
  return doors_.passed(p.odom, dir_robot, walls_, &door) &&
         stopAt(door, "stopping at a door to enter the room", p, topo, at, step, d);
}

bool HallwayDoorStops::enterAfterTurn(const Perception& p, const TopoView& topo, const HallwayContext& at,
                                      HallwayStep* step, Decision* d) {
  if (!after_turn_) return false;  // most ticks: no copy of the belief's view
  // A door beside the end of a new stretch is new, as a door passed on it would be: the turn there
  // puts the robot on the stretch just made (the belief localized on its end node), where no
  // opening of the node has the door yet.
  TopoView at_end = topo;
  at_end.mode = after_turn_mode_;
  while (after_turn_) {
    const DoorTrack door = *after_turn_;
    after_turn_.reset();
    if (stopAt(door, "stopping at a door beside the hallway's end turned at, to enter the room", p, at_end, at, step,
               d)) {
      entering_.beside_end = entering_.node < 0;
      return true;
    }
    // The next door there (one refused is the room just left, or one entered on the way back).
    nextAtEnd();
  }
  return false;
}

bool HallwayDoorStops::stopAt(const DoorTrack& door, const char* what, const Perception& p, const TopoView& topo,
                              const HallwayContext& at, HallwayStep* step, Decision* d) {
  const bool just_left = entry_.justLeft(door, at.travel);
  const std::optional<EntryOpening> entry = just_left ? std::nullopt : mayEnter(topo, at, door);
  if (!entry) {
    if (just_left) step->text = "door passed: the one just left";
    ++doors_passed_;
    return false;
  }
  if (!at.mission_door) {
    // A door that would be entered but is a door of a room mapped already (the room just left, or
    // any other) is an explored way into that room: recorded so at the opening it would have been
    // entered as, linked to the room's place and stored in it (a room with two doors is one place,
    // reachable by either), not entered as a new room.
    const std::optional<MappedRoomDoor> mapped = entry_.mappedRoomOf(door, topo.map_from_odom);
    if (mapped || entry_.otherDoorOfRoomLeft(door, at.travel)) {
      Request rec;
      rec.kind = Request::RecordOpening;
      rec.node = entry->node;
      rec.bearing = entry->bearing;
      rec.width = door.width;
      rec.explored = true;
      rec.beside_robot = entry->node < 0;
      if (mapped) {
        rec.place_id = mapped->place_id;
        rec.pose = mapped->door_in_place;
        rec.store_in_place = true;
        ++mapped_room_doors_;
      }
      d->requests.push_back(rec);
      step->text = mapped ? "door passed: a door of the room of place " + std::to_string(mapped->place_id) +
                                ", mapped already"
                          : "door passed: another door of the room just left";
      ++doors_passed_;
      return false;
    }
  }
  entering_ = *entry;
  door_ = door;
  // Where the door was taken to be (the log tells a door tracked wrongly from a real one).
  const Eigen::Vector2d rel = transformPoint(inverse(p.odom), door.centre_odom);  // robot frame
  char where[128];
  char wall[40] = "no wall known";
  if (door.wall_lateral >= 0.0) std::snprintf(wall, sizeof(wall), "its wall %.2f m aside", door.wall_lateral);
  std::snprintf(where, sizeof(where), " (%.2f m wide, %d sightings, at %.2f m ahead, %.2f m left, %s)", door.width,
                door.sightings, rel.x(), rel.y(), wall);
  step->kind = HallwayStep::StopForDoor;
  step->text = what + std::string(where);
  d->stop = true;
  return true;
}

bool HallwayDoorStops::enterInEndWall(const Perception& p, const TopoView& topo, double dir_robot,
                                      const HallwayView& v, const HallwayContext& at, HallwayStep* step, Decision* d) {
  // A room at a hallway's end has its door in the end wall: no door passes beside the robot there.
  // At a dead end (a side open is a way on, and a door in the far wall of a crossing is passed on
  // it) the door ahead is entered as a door passed would be, unless the robot came out of it. A
  // mission's door may be that door (mayEnter takes its own only); the rooms mapped are what a
  // mission goes to.
  if (v.end_open_left || v.end_open_right) return false;
  const std::optional<DoorTrack> door = doors_.inEndWall(p.odom, p.openings, dir_robot, v);
  if (!door || entry_.justLeft(*door, at.travel)) return false;
  if (!at.mission_door &&
      (entry_.otherDoorOfRoomLeft(*door, at.travel) || entry_.mappedRoomOf(*door, topo.map_from_odom)))
    return false;
  const std::optional<EntryOpening> entry = mayEnter(topo, at, *door);
  if (!entry) return false;
  entering_ = *entry;
  door_ = *door;
  const Eigen::Vector2d rel = transformPoint(inverse(p.odom), door->centre_odom);
  char text[160];
  std::snprintf(text, sizeof(text), "stopping at a door in the hallway's end wall to enter the room (%.2f m wide, %.2f m ahead, %.2f m left)",
                door->width, rel.x(), rel.y());
  step->kind = HallwayStep::StopForDoor;
  step->text = text;
  d->stop = true;
  return true;
}

void HallwayDoorStops::rememberAtEnd(HallwayDoors at_end, const Perception& p, double dir_robot,
                                     const HallwayView& v, bool turned_back, const std::vector<WayLine>& at_angle,
                                     TopoMode mode, double travel) {
  // A door in a side wall between the robot and the end wall is never passed: the robot turns
  // there (the outer wall of an L corner, a dead end's side walls next to its end). It is entered
  // once turned, when the map builder has the turn's node to record it at, as a door passed
  // would be.
  const std::array<bool, 2> closed{{!v.end_open_left, !v.end_open_right}};
  DoorTrack beside;
  if (at_end.besideEnd(p.odom, dir_robot, walls_, v.free_ahead, closed, turned_back, &beside) &&
      !inMouthOfWay(beside, at_angle))
    after_turn_ = beside;
  while (at_end.besideEnd(p.odom, dir_robot, walls_, v.free_ahead, closed, false, &beside)) {
    if (!inMouthOfWay(beside, at_angle)) left_at_end_.push_back(beside);
  }
  after_turn_mode_ = mode;
  end_travel_ = travel;
}

bool HallwayDoorStops::inMouthOfWay(const DoorTrack& door, const std::vector<WayLine>& at_angle) const {
  return std::any_of(at_angle.begin(), at_angle.end(), [&](const WayLine& way) {
    const Eigen::Vector2d u(std::cos(way.heading), std::sin(way.heading)), n(-u.y(), u.x());
    const Eigen::Vector2d c = door.centre_odom - way.origin;
    return c.dot(u) >= 0.0 && std::abs(c.dot(n)) <= 0.5 * door.width + follower_.rules().width_tolerance;
  });
}

void HallwayDoorStops::turned() {
  after_turn_.reset();
  left_at_end_.clear();
  doors_.clear();
}

std::optional<EntryOpening> HallwayDoorStops::enterAfterStop(const TopoView& topo, const HallwayContext& at,
                                                             std::string* why_passed) {
  if (entering_.node < 0 && !entering_.beside_end && topo.mode != TopoMode::Frontier) {
    // Stopped for a door on a new stretch, and pomdp_topo has since made its node and taken it
    // for a known one: a loop hypothesis (the check merges the node, the door explored, or
    // rejects it, its opening unexplored and come back to), or a loop closed in the same scan
    // (explore_restart: room_east mapped twice). Entered only as a known unexplored door
    // (mayEnter); else on along the hallway. Not a door beside the end of a new stretch: the turn
    // there localizes the belief on the end's node, whose door it is (enterAfterTurn).
    const std::optional<EntryOpening> known = mayEnter(topo, at, door_);
    if (!known) {
      ++doors_passed_;
      *why_passed = topo.mode == TopoMode::LoopCheck ? "door passed: pomdp_topo checks whether it is a known one"
                                                     : "door passed: it is a known one (pomdp_topo closed a loop at it)";
      return std::nullopt;
    }
    entering_ = *known;
  }
  if (entering_.node < 0 &&
      entry_.exploredAtFrontierNode(topo, at.graph, door_, follower_.topoBearing(door_.into_odom, topo), at.travel)) {
    // On a new stretch pomdp_topo took the door for one its current node has, explored: a door
    // recorded at a junction a metre off its centre, seen again from it (large_floor: room_7_14,
    // entered from the junction at a T, entered again from a stretch leaving it 5,600 s later).
    ++doors_passed_;
    *why_passed = "door passed: the node's explored one";
    return std::nullopt;
  }
  return entering_;
}

void HallwayDoorStops::nextAtEnd() {
  if (left_at_end_.empty()) return;
  after_turn_ = left_at_end_.front();
  left_at_end_.erase(left_at_end_.begin());
}

void HallwayDoorStops::backFromRoom(const DoorTrack& door_left, const std::vector<DoorTrack>& other_doors,
                                    double travel, const std::optional<laser_features::Pose2D>& drift) {
  after_turn_.reset();
  end_travel_ = travel;
  nextAtEnd();
  entry_.leftBy(door_left, other_doors, travel);
  doors_.roomVisited(drift);
}

std::optional<EntryOpening> HallwayDoorStops::mayEnter(const TopoView& topo, const HallwayContext& at,
                                                       const DoorTrack& door) const {
  return entry_.mayEnter(topo, at.graph, door, follower_.topoBearing(door.into_odom, topo),
                         route_.beliefTrusted(topo, at.travel), at.mission_door);
}

}  // namespace exploration
