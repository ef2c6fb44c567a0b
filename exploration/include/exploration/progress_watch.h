// ProgressWatch: the exploration ends when it no longer makes progress.
//
// Progress is new ground (travel on a new stretch, pomdp_topo's frontier), a new node or place, or an
// opening explored or given up. On the known map the route policy gives an opening up after
// max_route_attempts misses, each miss at most one walk over the map's hallways (a shortest route
// is no longer than all the graph's edges together). A belief lost for good counts no misses: the
// robot would drive the hallways until the time limit (buildings whose map no longer explains
// what is seen drove 1.2 km for rooms all mapped in the first 200 m). So hallway travel of
// (max_route_attempts + 1) times the graph's edge length with no progress ends the exploration,
// incomplete. Travel in rooms does not count (a room's coverage is the place's progress).
//
// ROS-free: the standard library only.
#pragma once

#include <cstddef>
#include <string>

namespace exploration {

/// What the map and the route count at a tick; a change of any is progress.
struct ProgressCounts {
  size_t nodes = 0;
  size_t places = 0;
  size_t openings_explored = 0;
  int openings_given_up = 0;
  bool operator==(const ProgressCounts& o) const {
    return nodes == o.nodes && places == o.places && openings_explored == o.openings_explored &&
           openings_given_up == o.openings_given_up;
  }
};

class ProgressWatch {
 public:
  explicit ProgressWatch(int max_route_attempts) : walks_(max_route_attempts + 1) {}

  /// Each tick in a hallway: `hallway_travel` (m, odometric, only ever growing), whether the robot is
  /// on a new stretch, the counts, and the graph's edge length (m). True once no progress was made
  /// over window() of hallway travel (never while the graph has no edge).
  bool stalled(double hallway_travel, bool on_frontier, const ProgressCounts& counts, double edge_length);
  /// m, the hallway travel without progress that ends the exploration (at the last call).
  double window() const { return window_; }
  /// m, the hallway travel since the last progress (at the last call).
  double sinceProgress() const { return since_; }
  /// Why the exploration ends, for its summary.
  std::string why() const;

 private:
  int walks_;
  bool started_ = false;
  ProgressCounts last_;
  double progress_travel_ = 0.0;  // hallway travel at the last progress
  double window_ = 0.0, since_ = 0.0, edge_length_ = 0.0;
};

}  // namespace exploration
