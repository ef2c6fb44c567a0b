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
// ROS-free: the standard library and the exploration core only.
#pragma once

#include <cstddef>
#include <string>

#include "exploration/topo_route.h"

namespace exploration {

class ProgressWatch {
 public:
  explicit ProgressWatch(int max_route_attempts) : walks_(max_route_attempts + 1) {}

  /// The topological map changed: its counts (nodes, places, openings explored) and edge length,
  /// taken here once rather than at every tick.
  void mapChanged(const TopoGraph& graph);
  /// Each tick in a hallway: `hallway_travel` (m, odometric, only ever growing), whether the robot is
  /// on a new stretch, and the openings the route gave up so far. True once no progress was made
  /// over window() of hallway travel (never while the graph has no edge).
  bool stalled(double hallway_travel, bool on_frontier, int openings_given_up);
  /// m, the hallway travel without progress that ends the exploration (at the last call).
  double window() const { return walks_ * edge_length_; }
  /// m, the hallway travel since the last progress (at the last call).
  double sinceProgress() const { return since_; }
  /// Why the exploration ends, for its summary.
  std::string why() const;

 private:
  struct Counts {  // a change of any is progress
    size_t nodes = 0, places = 0, openings_explored = 0;
    int openings_given_up = 0;
    bool operator==(const Counts& o) const {
      return nodes == o.nodes && places == o.places && openings_explored == o.openings_explored &&
             openings_given_up == o.openings_given_up;
    }
  };
  int walks_;
  Counts now_, last_;
  double edge_length_ = 0.0;      // m, the map's at its last change
  bool started_ = false;
  double progress_travel_ = 0.0;  // hallway travel at the last progress
  double since_ = 0.0;
};

}  // namespace exploration
