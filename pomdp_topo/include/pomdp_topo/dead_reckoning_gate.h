// The belief and the map checked against the dead reckoning (the front end's heading-corrected
// position and heading), while it shares the map's frame: a map built in this run, no odometry jump
// since, or a relocation after one. Heading-corrected dead reckoning drifts little in a
// rectilinear building, and the map's node positions come from the same dead reckoning, so a belief
// far from it is a look-alike elsewhere:
//  - the position and heading gates (gate()): the belief restricted to the states near the
//    dead-reckoned position (position_gate plus position_gate_per_m of travel since the two last
//    agreed) and with its heading bin; a state beyond the known map (at a node, heading where no
//    edge leads) only on that node's way out (alongWayOut);
//  - where a passed landmark lies by the dead reckoning (deadReckonedPosition), against where the
//    belief puts it (farFromDeadReckoning, farFromNode);
//  - where a new stretch leaves a node (departure), and a node recorded twice (twinWithWay).
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "laser_features/building_axes.h"
#include "laser_features/geometry.h"
#include "pomdp_topo/front_end.h"
#include "pomdp_topo/map_builder_params.h"
#include "pomdp_topo/pomdp_localizer.h"
#include "pomdp_topo/topological_map.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace pomdp_topo {

/// The map position of a belief state (a node, or along an edge between its nodes' poses).
bool statePosition(const TopologicalMap& map, const PomdpLocalizer::State& st, Eigen::Vector2d* p);

class DeadReckoningGate {
 public:
  using Pose2D = laser_features::Pose2D;

  /// Whether the dead reckoning's position and heading are the map's; `travel` (FrontEnd::travel())
  /// is where they last agreed.
  void setTrusted(bool position, bool heading, double travel) {
    position_trusted_ = position;
    heading_trusted_ = heading;
    trusted_travel_ = travel;
  }
  void setHeadingTrusted(bool trusted) { heading_trusted_ = trusted; }
  /// The robot was moved, or its odometry refused: neither is the map's from now on.
  void lose() {
    position_trusted_ = false;
    heading_trusted_ = false;
  }
  /// Relocalized after an odometry jump, `travel` into the run: the position is the map's again.
  void relocated(double travel) {
    position_trusted_ = true;
    trusted_travel_ = travel;
  }
  /// The heading bins changed (the building's axis): the per-state positions and bins are computed again.
  void invalidate() {
    state_bins_.clear();
    state_positions_.clear();
    state_beyond_map_.clear();
  }
  /// The map is checked against the dead reckoning (update_position_tolerance): the position gate
  /// is on, the tolerance set and the position trusted.
  bool checks(const MapBuilderParams& params) const {
    return position_trusted_ && params.position_gate > 0.0 && params.update_position_tolerance > 0.0;
  }

  /// The position and heading gates (position_gate, heading_gate) for one scan, the robot at
  /// `robot` (map frame) `travel` into the run, heading in `heading_bin`: the belief restricted to
  /// the states allowed. Returns what happened for the map builder's log, or "" when nothing to say.
  std::string gate(const TopologicalMap& map, PomdpLocalizer* localizer, const MapBuilderParams& params,
                   const laser_features::HeadingBins& bins, const Pose2D& robot, double travel, int heading_bin);

  /// Where the dead reckoning puts a passed landmark (map frame), the robot at `robot` `travel` into
  /// the run; false while the map is not checked against it (checks()).
  bool deadReckonedPosition(const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                            const PassedLandmark& p, const Pose2D& robot, double travel, Eigen::Vector2d* at) const;
  /// update_position_tolerance: the dead-reckoned position of a passed landmark is farther than the
  /// tolerance from `believed` (where the belief puts it, map frame), while checks() holds.
  bool farFromDeadReckoning(const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                            const Eigen::Vector2d& believed, const PassedLandmark& p, const Pose2D& robot,
                            double travel) const;
  /// The dead reckoning puts the passed opening `p` farther than min_node_separation +
  /// match_distance from node `n`: it is not an opening `n` lacks. False without dead reckoning.
  bool farFromNode(const MapBuilderParams& params, const laser_features::HeadingBins& bins, const TopoNode& n,
                   const PassedLandmark& p, const Pose2D& robot, double travel) const;

  /// Whether `robot` lies on the way out of a node at `node` along `heading`: within
  /// update_position_tolerance of that ray, not farther behind the node; `*along` is its distance
  /// along the way.
  static bool alongWayOut(const MapBuilderParams& params, const Eigen::Vector2d& node, double heading,
                          const Eigen::Vector2d& robot, double* along);
  /// Where the dead-reckoned position `robot` lies against a new stretch `*s` m out of node `n`
  /// along `heading`, within update_position_tolerance: there (Here; `*s` becomes the dead
  /// reckoning's distance along the way where that is farther by more than the tolerance: the
  /// belief reached the node late), on the way out but short of that (NotYet; `*s` becomes its
  /// distance past the node, at least 0: the belief leads the robot out), or off the way out
  /// (Elsewhere: the belief is wrong). Here when the map is not checked against the dead reckoning.
  enum class Departure { Here, NotYet, Elsewhere };
  Departure departure(const MapBuilderParams& params, const TopoNode& n, double heading, const Pose2D& robot,
                      double* s) const;
  /// A node of the same type as `id` within update_position_tolerance of it (checks() on) with an
  /// edge along `heading`, which `id` lacks: one place recorded twice. -1 if none.
  int twinWithWay(const TopologicalMap& map, const MapBuilderParams& params, uint32_t id, double heading) const;

 private:
  bool position_trusted_ = false;   // the front end's position is in the map's frame (see position_gate)
  bool heading_trusted_ = false;    // the front end's heading is in the map's frame (see heading_gate)
  double trusted_travel_ = 0.0;     // FrontEnd::travel() when it last became so
  // The gates' per-state positions (NaN: none) and heading bins, kept until the map or the localizer's
  // states change, and its mask: nothing allocated or looked up per scan.
  std::vector<Eigen::Vector2d> state_positions_;
  std::vector<int> state_bins_;  // the heading gate's per-state heading bins, kept with the positions
  std::vector<bool> state_beyond_map_;  // per state: at a node, heading where no edge leads (wayOn)
  uint64_t state_positions_revision_ = ~0ull, state_positions_states_revision_ = ~0ull;
  std::vector<bool> gate_allowed_;
};

}  // namespace pomdp_topo
