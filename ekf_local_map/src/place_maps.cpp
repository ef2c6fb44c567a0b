#include "ekf_local_map/place_maps.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ekf_local_map {

namespace {
bool finitePose(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}
}  // namespace

PlaceMaps::PlaceMaps(const StochasticMapParams& params) : params_(params) {}

uint32_t PlaceMaps::createPlace(const Pose2D& display_pose_in_map) {
  const uint32_t id = next_id_++;
  places_.emplace(id, Place{id, display_pose_in_map, StochasticMap(params_), {}});
  active_ = id;
  return id;
}

bool PlaceMaps::activate(uint32_t id) {
  if (places_.count(id) == 0) return false;
  active_ = id;
  return true;
}

void PlaceMaps::close() { active_.reset(); }

StochasticMap* PlaceMaps::active() {
  Place* p = active_ ? place(*active_) : nullptr;
  return p ? &p->map : nullptr;
}

const StochasticMap* PlaceMaps::active() const {
  const Place* p = active_ ? place(*active_) : nullptr;
  return p ? &p->map : nullptr;
}

Place* PlaceMaps::place(uint32_t id) {
  const auto it = places_.find(id);
  return it == places_.end() ? nullptr : &it->second;
}

const Place* PlaceMaps::place(uint32_t id) const {
  const auto it = places_.find(id);
  return it == places_.end() ? nullptr : &it->second;
}

std::vector<uint32_t> PlaceMaps::placeIds() const {
  std::vector<uint32_t> ids;
  ids.reserve(places_.size());
  for (const auto& entry : places_) ids.push_back(entry.first);
  return ids;
}

bool PlaceMaps::addDoor(uint32_t place_id, uint32_t door_id, const Pose2D& door_in_place,
                        const Eigen::Matrix3d& cov) {
  Place* p = place(place_id);
  if (!p || !finitePose(door_in_place) || !cov.allFinite()) return false;
  p->doors[door_id] = Door{door_id, door_in_place, 0.5 * (cov + cov.transpose())};
  return true;
}

bool PlaceMaps::addDoorAtRobot(uint32_t door_id, const Pose2D& door_in_robot) {
  StochasticMap* map = active();
  if (!map) return false;
  Eigen::Matrix3d J_robot;
  const Pose2D door = laser_features::compose(map->robotPose(), door_in_robot, &J_robot);
  return addDoor(*active_, door_id, door, J_robot * map->robotCovariance() * J_robot.transpose());
}

bool PlaceMaps::addDoorInPlace(uint32_t place_id, uint32_t door_id, const Pose2D& door_in_place) {
  const Place* p = place(place_id);
  return p != nullptr && addDoor(place_id, door_id, door_in_place, p->map.robotCovariance());
}

bool PlaceMaps::relocateAtDoor(uint32_t place_id, uint32_t door_id, const Pose2D& robot_offset_from_door,
                               const Eigen::Matrix3d& offset_cov) {
  Place* p = place(place_id);
  if (!p || !finitePose(robot_offset_from_door) || !offset_cov.allFinite()) return false;
  const auto door = p->doors.find(door_id);
  if (door == p->doors.end()) return false;
  Eigen::Matrix3d J_door, J_offset;
  const Pose2D pose = laser_features::compose(door->second.pose, robot_offset_from_door, &J_door, &J_offset);
  const Eigen::Matrix3d cov = J_door * door->second.cov * J_door.transpose() +
                              J_offset * offset_cov * J_offset.transpose();
  if (!p->map.relocate(pose, cov)) return false;
  active_ = place_id;
  return true;
}

void PlaceMaps::assign(std::map<uint32_t, Place> places, uint32_t next_id) {
  places_ = std::move(places);
  uint32_t after_last = 0;
  for (const auto& entry : places_) after_last = std::max(after_last, entry.first + 1);
  next_id_ = std::max(next_id, after_last);
  active_.reset();
}

void PlaceMaps::swap(PlaceMaps& other) {
  std::swap(params_, other.params_);
  places_.swap(other.places_);
  std::swap(active_, other.active_);
  std::swap(next_id_, other.next_id_);
}

}  // namespace ekf_local_map
