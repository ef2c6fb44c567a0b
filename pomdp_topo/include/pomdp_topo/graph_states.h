// The state space of the topological POMDP (Tomatis, Nourbakhsh & Siegwart, IROS 2001, section
// 3.3) over a topological map, and the walks on it that the transition T(s, a, s') of eq. 2 is made
// of. Every edge of length L is cut into n = max(1, round(L / resolution)) cells, each in both travel
// directions; every node has one state per heading bin. Travel goes along edges and straight on
// through nodes (the exit within 45 degrees of the heading); a turn at a node changes the bin.
//
// ROS-free; the queries do not allocate.
#pragma once

#include "laser_features/building_axes.h"
#include "pomdp_topo/pomdp_params.h"
#include "pomdp_topo/topological_map.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace pomdp_topo {

class GraphStates {
 public:
  struct State {
    enum Kind : uint8_t { Edge = 0, Node = 1 };
    Kind kind = Edge;
    uint32_t id = 0;       // edge id (Edge) or node id (Node)
    bool forward = true;   // Edge: travel source -> target; Node: true
    double offset = 0.0;   // m, cell centre from the edge's source; 0 for nodes
    double heading = 0.0;  // rad, map frame, direction of travel
    uint32_t cell = 0;     // Edge: cell index counted from the source; Node: heading bin
  };
  // A travel direction of an edge: 2 * edge index + (0 forward, 1 backward).
  struct DirEdge {
    double length = 0.0;
    double cell = 0.0;      // m, cell length L / n
    double inv_cell = 0.0;  // 1/m, n / L (0 for a zero length)
    double heading = 0.0;   // rad, travel heading
    int32_t cells = 1;
    int32_t base = 0;       // state index of cell 0 (counted from the edge's source)
    int32_t start = 0;      // node index where the travel starts
    int32_t end = 0;        // node index where it ends
    int32_t next = -1;      // straight continuation at `end` (directed edge, heading within 45 deg), -1 if none
    int32_t bin = 0;        // heading bin of `heading`
    int32_t bin_reversed = 0;  // heading bin of heading + pi
  };

  /// Edges one walk may pass (travel, a landmark window): a bound for loops of zero-length edges.
  static constexpr int kMaxWalkHops = 1000;

  /// Uses resolution, heading_bins, axis_angle, node_radius and max_cells_per_edge (checked by
  /// PomdpLocalizer::validate).
  explicit GraphStates(const PomdpParams& params);
  /// The building's axis (rad, map frame): bin k has heading axis + k 2 pi / heading_bins.
  void setAxis(double axis_angle) { axis_angle_ = axis_angle; }
  /// Rebuilds the states from `map`: per edge its forward cells then its backward cells, then the
  /// nodes' bins. Dangling edges are skipped, non-finite lengths and headings taken as 0.
  void build(const TopologicalMap& map);

  size_t size() const { return states_.size(); }
  const State& state(size_t index) const { return states_[index]; }
  const std::vector<State>& states() const { return states_; }
  const std::vector<DirEdge>& dirEdges() const { return dir_edges_; }
  int bins() const { return bins_; }
  /// The first node state: edge states are [0, nodeBase()).
  int32_t nodeBase() const { return node_base_; }
  size_t nodeCount() const { return node_ids_.size(); }
  int32_t nodeState(int32_t node_index, int bin) const { return node_base_ + node_index * bins_ + bin; }
  /// The node's index (states, dirEdges' start and end), -1 if unknown.
  int32_t nodeIndex(uint32_t node_id) const;
  /// The directed edge leaving node `node_index` with heading ~ bin `bin` (+ pi when `back`), -1 if none.
  int32_t nodeExit(int32_t node_index, int bin, bool back) const {
    return (back ? node_exit_back_ : node_exit_)[size_t(node_index) * bins_ + bin];
  }
  const std::vector<NodeOpening>& nodeOpenings(int32_t node_index) const { return node_openings_[node_index]; }
  /// A hallway end: nothing lies beyond it.
  bool nodeClosed(int32_t node_index) const { return node_closed_[node_index] != 0; }
  /// Whether the known map ends at node `node_index` in heading bin `bin` where no edge leaves that
  /// way: beyond an opening of the node (its room or an unexplored branch), or straight on past the
  /// last node of a stretch (the hallway goes on, unmapped). Not at a hallway end, and not on a
  /// side of the node that is neither an edge nor an opening nor an edge's continuation: that side
  /// is the hallway's wall (a door node's side across from its door), and what is seen there the
  /// map explains or not, as anywhere along the hallway.
  bool mapEndsBeyond(int32_t node_index, int bin) const { return node_open_way_[size_t(node_index) * bins_ + bin] != 0; }
  /// The landmarks of the edge of directed edge `dir_edge` (in its source -> target frame).
  const std::vector<EdgeLandmark>& edgeLandmarks(int32_t dir_edge) const { return edge_landmarks_[dir_edge >> 1]; }
  /// An edge state's directed edge.
  int32_t stateDirEdge(size_t state) const { return state_dir_edge_[state]; }

  int headingBin(double heading) const;
  double binHeading(int bin) const;
  int edgeStateIndex(uint32_t edge, double offset, bool forward) const;  // -1 if unknown
  int nodeStateIndex(uint32_t node, double heading) const;               // -1 if unknown

  /// The state reached from `state` by travelling `distance` (m, < 0 backwards): along the edge,
  /// through nodes by the straight continuation; it stops at a node when the overshoot is below
  /// resolution / 2 or there is no way on (hallway end). A successor at least one cell past a node
  /// without a way on (into a wall) is returned as ~index ("blocked").
  int32_t travelFrom(size_t state, double distance) const;
  /// The state reached from `state` by turning `k` heading bins (0 < k < bins): at a node (or an
  /// edge state within node_radius of one) the node's bin; 180 degrees mid-edge the same cell
  /// reversed; any other turn mid-edge stays (`mid_edge` set).
  int32_t turnFrom(size_t state, int k, bool* mid_edge) const;

 private:
  int32_t cellState(int32_t dir_edge, double s, bool reversed) const;
  int32_t walk(int32_t dir_edge, double s, double distance, bool reversed) const;
  void indexNodes(const TopologicalMap& map);
  std::vector<uint32_t> buildDirectedEdges(const TopologicalMap& map, std::vector<std::vector<int32_t>>* exits);
  void linkWays(const TopologicalMap& map, const std::vector<std::vector<int32_t>>& exits);
  void markOpenWays(const TopologicalMap& map);
  void buildStates(const std::vector<uint32_t>& edge_ids);

  double resolution_, node_radius_, axis_angle_;
  int bins_;
  int max_cells_per_edge_;

  std::vector<State> states_;
  std::vector<DirEdge> dir_edges_;
  int32_t node_base_ = 0;
  std::vector<uint32_t> node_ids_;
  std::unordered_map<uint32_t, int32_t> node_index_;
  std::unordered_map<uint32_t, int32_t> edge_index_;
  std::vector<int32_t> node_exit_;       // [node * bins + b]: directed edge leaving with heading ~ bin b
  std::vector<int32_t> node_exit_back_;  // [node * bins + b]: leaving with heading ~ bin b + pi
  std::vector<std::vector<NodeOpening>> node_openings_;
  std::vector<char> node_closed_;        // per node: a hallway end (nothing beyond it)
  std::vector<char> node_open_way_;      // [node * bins + b]: mapEndsBeyond(node, b)
  std::vector<std::vector<EdgeLandmark>> edge_landmarks_;
  std::vector<int32_t> near_node_;       // per edge state: node index within node_radius, -1 if none
  std::vector<int32_t> state_dir_edge_;  // per edge state: its directed edge
};

}  // namespace pomdp_topo
