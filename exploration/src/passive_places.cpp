#include "exploration/passive_places.h"

#include <cmath>

namespace exploration {

using laser_features::compose;
using laser_features::inverse;
using laser_features::normalizeAngle;

bool PassivePlaces::validate(const Params& p, std::string* why) {
  auto fail = [&](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  if (!(p.room_confidence >= 0.0 && p.room_confidence <= 1.0)) return fail("room_confidence must be in [0, 1]");
  if (!(p.hallway_confidence >= 0.0 && p.hallway_confidence <= 1.0)) return fail("hallway_confidence must be in [0, 1]");
  if (p.enter_scans < 1 || p.leave_scans < 1) return fail("enter_scans and leave_scans must be at least 1");
  if (!(p.enter_distance >= 0.0) || !(p.leave_distance >= 0.0) || !(p.door_memory >= 0.0))
    return fail("enter_distance, leave_distance and door_memory must be >= 0");
  if (!(p.relocation_sigma_xy > 0.0) || !(p.relocation_sigma_theta > 0.0))
    return fail("relocation_sigma_xy and relocation_sigma_theta must be > 0");
  return true;
}

int PassivePlaces::placeOfDoor(int door_node) const {
  const auto it = door_places_.find(door_node);
  return it == door_places_.end() ? -1 : it->second;
}

void PassivePlaces::count(Streak* s, const PlaceObservation& o) {
  if (s->scans == 0) {
    s->start_travel = travel_;
    s->start_odom = o.odom;
    s->start_heading_map = o.heading_map;
  }
  ++s->scans;
}

PlaceAction PassivePlaces::update(const PlaceObservation& o) {
  const bool finite = std::isfinite(o.odom.x) && std::isfinite(o.odom.y) && std::isfinite(o.odom.theta);
  if (!finite) return {};  // a bad pose neither moves the robot nor counts
  if (have_odom_) travel_ += std::hypot(o.odom.x - last_odom_.x, o.odom.y - last_odom_.y);
  last_odom_ = o.odom;
  have_odom_ = true;
  if (o.door_node != ignored_door_) ignored_door_ = -1;
  if (o.door_node >= 0 && o.door_node != ignored_door_) {
    last_door_ = o.door_node;
    last_door_travel_ = travel_;
  }

  // Hysteresis: an unsure scan keeps both streaks as they are; a confident one breaks the other.
  if (o.type == ScanPlace::Room && o.confidence >= params_.room_confidence) {
    count(&room_, o);
    hallway_ = Streak{};
  } else if (o.type == ScanPlace::Hallway && o.confidence >= params_.hallway_confidence) {
    count(&hallway_, o);
    room_ = Streak{};
  }

  if (!inPlace() && complete(room_, params_.enter_scans, params_.enter_distance)) return enterAction(o);
  if (inPlace() && complete(hallway_, params_.leave_scans, params_.leave_distance)) {
    PlaceAction a;
    a.kind = PlaceAction::Leave;
    return a;
  }
  return {};
}

PlaceAction PassivePlaces::enterAction(const PlaceObservation& o) const {
  PlaceAction a;
  a.kind = PlaceAction::Enter;
  const bool door_recent = last_door_ >= 0 && room_.start_travel - last_door_travel_ <= params_.door_memory;
  a.door_node = door_recent ? last_door_ : -1;
  a.known_place = door_recent ? placeOfDoor(last_door_) : -1;
  // The doorway: where the room streak began, heading into the room.
  const Pose2D door_odom = room_.start_odom;
  a.door_in_robot = compose(inverse(o.odom), door_odom);
  a.door_in_robot.theta = normalizeAngle(a.door_in_robot.theta);
  a.robot_from_door = compose(inverse(door_odom), o.odom);
  a.robot_from_door.theta = normalizeAngle(a.robot_from_door.theta);
  a.door_bearing_map = normalizeAngle(room_.start_heading_map);
  return a;
}

void PassivePlaces::entered(int place_id, int door_node) {
  room_ = Streak{};
  hallway_ = Streak{};
  if (place_id < 0) return;
  place_ = place_id;
  place_door_ = door_node;
  ++entries_;
  if (door_node >= 0) door_places_[door_node] = place_id;
  last_door_ = -1;  // the door is used; leaving starts afresh
}

void PassivePlaces::left() {
  // Back in the hallway the belief resumes at the door just used: that is not the way into the next room.
  ignored_door_ = place_door_;
  place_door_ = -1;
  place_ = -1;
  room_ = Streak{};
  hallway_ = Streak{};
  last_door_ = -1;
}

}  // namespace exploration
