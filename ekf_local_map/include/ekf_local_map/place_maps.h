// Many places, each an independent stochastic map in its own frame place_<id> (Tomatis et al.
// 2001: a local metric map per room, the rooms joined by the topological map). Only the active
// place is updated; a place stores its doors, so that the robot entering it again through a door
// can be relocated (the paper's switch from topological to metric mode).
#pragma once

#include "ekf_local_map/stochastic_map.h"

#include <laser_features/geometry.h>

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

namespace ekf_local_map {

/// A door (opening) of a place: its pose in the place frame (x along the passage, into the place,
/// by the caller's convention) with a covariance. Doors are not part of the filter state.
struct Door {
  uint32_t id = 0;
  Pose2D pose;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
};

struct Place {
  uint32_t id = 0;
  Pose2D display_pose;  // pose of the place frame in `map`, for display only
  StochasticMap map;
  std::map<uint32_t, Door> doors;
};

class PlaceMaps {
 public:
  explicit PlaceMaps(const StochasticMapParams& params = StochasticMapParams());

  const StochasticMapParams& params() const { return params_; }

  /// A new place whose origin is the robot's pose on entry (robot at (0, 0, 0), zero covariance);
  /// it becomes the active place. Returns its id.
  uint32_t createPlace(const Pose2D& display_pose_in_map);
  /// Makes a stored place the active one (the robot state in it is whatever it was; use
  /// relocateAtDoor when entering). False for an unknown id.
  bool activate(uint32_t id);
  /// No place is active (the robot is in topological mode).
  void close();

  /// The active place's map, or null.
  StochasticMap* active();
  const StochasticMap* active() const;
  std::optional<uint32_t> activeId() const { return active_; }

  Place* place(uint32_t id);
  const Place* place(uint32_t id) const;
  std::vector<uint32_t> placeIds() const;
  size_t size() const { return places_.size(); }
  const std::map<uint32_t, Place>& places() const { return places_; }

  /// Stores (or replaces) a door of a place. False for an unknown place or a non-finite pose/cov.
  bool addDoor(uint32_t place, uint32_t door_id, const Pose2D& door_in_place, const Eigen::Matrix3d& cov);
  /// Stores a door of the ACTIVE place at `door_in_robot` from the current robot estimate; the
  /// door's covariance is the robot's propagated through the compounding. False without an active place.
  bool addDoorAtRobot(uint32_t door_id, const Pose2D& door_in_robot);
  /// Stores a door of `place` at `door_in_place`, seen by the EKF from inside it: its covariance is
  /// the place's last robot pose's. False for an unknown place or a non-finite pose.
  bool addDoorInPlace(uint32_t place, uint32_t door_id, const Pose2D& door_in_place);

  /// Entering `place` through `door_id`: activates the place and relocates its robot at
  /// door (+) robot_offset_from_door, with the door's and the offset's covariances compounded
  /// (the door–map correlation is not kept). The next update of the active map refines the pose by
  /// line matching and reports success or failure (UpdateReport::relocation). False, changing
  /// nothing, for an unknown place or door.
  bool relocateAtDoor(uint32_t place, uint32_t door_id, const Pose2D& robot_offset_from_door,
                      const Eigen::Matrix3d& offset_cov);

  /// Replaces the contents (used by load: a place id, maps, doors; `next_id` the next id to give).
  void assign(std::map<uint32_t, Place> places, uint32_t next_id);
  uint32_t nextId() const { return next_id_; }
  void swap(PlaceMaps& other);

 private:
  StochasticMapParams params_;
  std::map<uint32_t, Place> places_;
  std::optional<uint32_t> active_;
  uint32_t next_id_ = 0;
};

}  // namespace ekf_local_map
