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
  if (!(p.reentry_distance >= 0.0) || !(p.reentry_per_m >= 0.0))
    return fail("reentry_distance and reentry_per_m must be >= 0");
  if (p.path_door_id_base < 0) return fail("path_door_id_base must be >= 0");
  if (!(p.max_place_extent > 0.0)) return fail("max_place_extent must be > 0");
  if (!(p.relocation_distance >= 0.0)) return fail("relocation_distance must be >= 0");
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
  const PlaceAction a = decide(o);
  if (a.kind == PlaceAction::Enter) {
    last_reentry_.reset();
    if (a.known_place >= 0) last_reentry_ = a;
  }
  return a;
}

PlaceAction PassivePlaces::decide(const PlaceObservation& o) {
  const bool finite = std::isfinite(o.odom.x) && std::isfinite(o.odom.y) && std::isfinite(o.odom.theta);
  if (!finite) return {};  // a bad pose neither moves the robot nor counts
  if (have_odom_) {
    const double step = std::hypot(o.odom.x - last_odom_.x, o.odom.y - last_odom_.y);
    travel_ += step;
    if (!inPlace()) outside_travel_ += step;
  }
  last_odom_ = o.odom;
  have_odom_ = true;
  if (o.door_node != ignored_door_) ignored_door_ = -1;
  if (o.door_node >= 0 && o.door_node != ignored_door_) {
    last_door_ = o.door_node;
    last_door_travel_ = travel_;
  }

  if (o.crossing) {
    const PlaceAction a = crossingAction(o);
    if (a.kind != PlaceAction::None) return a;
  }
  if (inPlace() && std::hypot(o.odom.x - place_entry_odom_.x, o.odom.y - place_entry_odom_.y) > params_.max_place_extent) {
    PlaceAction a;
    a.kind = PlaceAction::Leave;
    return a;
  }

  // Hysteresis: an unsure scan keeps both streaks as they are; a confident one breaks the other.
  if (o.type == ScanPlace::Room && o.confidence >= params_.room_confidence) {
    count(&room_, o);
    hallway_ = Streak{};
  } else if (o.type == ScanPlace::Hallway && o.confidence >= params_.hallway_confidence) {
    count(&hallway_, o);
    room_ = Streak{};
  }

  if (!inPlace() && params_.enter_by_type && complete(room_, params_.enter_scans, params_.enter_distance))
    return enterAction(o);
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
  a.door_id = a.door_node;
  a.known_place = door_recent ? placeOfDoor(last_door_) : -1;
  // The doorway: where the room streak began, heading into the room.
  const Pose2D door_odom = room_.start_odom;
  a.door_odom = door_odom;
  a.door_in_robot = compose(inverse(o.odom), door_odom);
  a.door_in_robot.theta = normalizeAngle(a.door_in_robot.theta);
  a.robot_from_door = compose(inverse(door_odom), o.odom);
  a.robot_from_door.theta = normalizeAngle(a.robot_from_door.theta);
  a.door_bearing_map = normalizeAngle(room_.start_heading_map);
  return a;
}

void PassivePlaces::entered(int place_id, int door_id) {
  room_ = Streak{};
  hallway_ = Streak{};
  std::optional<PathDoor> path_door;
  path_door.swap(pending_path_door_);
  if (last_reentry_ && last_reentry_->known_place != place_id) last_reentry_.reset();
  if (place_id < 0) return;
  place_ = place_id;
  place_entry_odom_ = last_odom_;
  place_door_ = door_id;
  ++entries_;
  if (path_door && door_id == path_door->id) {
    // A crossed door without a node: remembered where it was crossed now, for the next re-entry.
    path_door->place = place_id;
    path_door->outside_travel = outside_travel_;
    bool known = false;
    for (PathDoor& d : path_doors_) {
      if (d.id == path_door->id) d = *path_door, known = true;
    }
    if (!known) path_doors_.push_back(*path_door);
  } else if (door_id >= 0) {
    door_places_[door_id] = place_id;
  }
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

const PassivePlaces::PathDoor* PassivePlaces::knownPathDoor(const Pose2D& door_map) const {
  const PathDoor* best = nullptr;
  double best_d = 0.0;
  for (const PathDoor& d : path_doors_) {
    const double gate = params_.reentry_distance + params_.reentry_per_m * (outside_travel_ - d.outside_travel);
    const double dist = std::hypot(d.door_map.x - door_map.x, d.door_map.y - door_map.y);
    if (dist > gate || std::abs(normalizeAngle(d.door_map.theta - door_map.theta)) > 0.25 * M_PI) continue;
    if (best == nullptr || dist < best_d) best = &d, best_d = dist;
  }
  return best;
}

PlaceAction PassivePlaces::crossingAction(const PlaceObservation& o) {
  const bool hallway_now = o.type == ScanPlace::Hallway && o.confidence >= params_.hallway_confidence;
  PlaceAction a;
  if (hallway_now) {
    // Through a door into a hallway: out of the place, if in one.
    if (inPlace()) a.kind = PlaceAction::Leave;
    return a;
  }
  a.kind = PlaceAction::Enter;
  a.leave_first = inPlace();
  const Pose2D& door = o.crossing->door_odom;
  Pose2D door_map = compose(o.map_odom, door);
  door_map.theta = normalizeAngle(door_map.theta);
  // The door node the belief passed just now names the door when there is one.
  const bool node_recent = !inPlace() && last_door_ >= 0 && travel_ - last_door_travel_ <= params_.door_memory;
  if (node_recent) {
    a.door_node = last_door_;
    a.door_id = last_door_;
    a.known_place = placeOfDoor(last_door_);
  } else if (const PathDoor* known = knownPathDoor(door_map)) {
    a.door_id = known->id;
    a.known_place = known->place;
    pending_path_door_ = *known;
    pending_path_door_->door_map = door_map;
    reentry_door_map_ = door_map;
  } else {
    PathDoor d;
    d.id = params_.path_door_id_base + int(path_doors_.size());
    d.door_map = door_map;
    a.door_id = d.id;
    pending_path_door_ = d;
  }
  a.door_odom = door;
  a.door_in_robot = compose(inverse(o.odom), door);
  a.door_in_robot.theta = normalizeAngle(a.door_in_robot.theta);
  a.robot_from_door = compose(inverse(door), o.odom);
  a.robot_from_door.theta = normalizeAngle(a.robot_from_door.theta);
  a.door_bearing_map = normalizeAngle(o.heading_map + normalizeAngle(door.theta - o.odom.theta));
  return a;
}

PlaceAction PassivePlaces::reentryRefused(const Pose2D& odom) {
  if (!inPlace() || !last_reentry_ || last_reentry_->known_place != place_) return {};
  PlaceAction a = *last_reentry_;
  last_reentry_.reset();
  a.leave_first = true;
  a.known_place = -1;
  if (a.door_id >= params_.path_door_id_base) {
    // A crossed door: the known place keeps its door; the new place gets a door of its own.
    PathDoor d;
    d.id = params_.path_door_id_base + int(path_doors_.size());
    d.door_map = reentry_door_map_;
    a.door_id = d.id;
    pending_path_door_ = d;
  }
  a.door_in_robot = compose(inverse(odom), a.door_odom);
  a.door_in_robot.theta = normalizeAngle(a.door_in_robot.theta);
  a.robot_from_door = compose(inverse(a.door_odom), odom);
  a.robot_from_door.theta = normalizeAngle(a.robot_from_door.theta);
  return a;
}

}  // namespace exploration
