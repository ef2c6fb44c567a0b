#include "pomdp_topo/graph_states.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {

constexpr double kEps = 1e-9;                // m: ties at cell boundaries go forward
constexpr double kStraight = kPi / 4 + 1e-6;  // rad: "within 45 deg" of exitWithHeading

bool finite(double v) { return std::isfinite(v); }

}  // namespace

GraphStates::GraphStates(const PomdpParams& params)
    : resolution_(params.resolution),
      node_radius_(params.node_radius),
      axis_angle_(params.axis_angle),
      bins_(params.heading_bins),
      max_cells_per_edge_(params.max_cells_per_edge) {}

void GraphStates::build(const TopologicalMap& map) {
  indexNodes(map);
  std::vector<std::vector<int32_t>> exits;
  const std::vector<uint32_t> edge_ids = buildDirectedEdges(map, &exits);
  linkWays(map, exits);
  buildStates(edge_ids);
}

int GraphStates::headingBin(double heading) const {
  return laser_features::HeadingBins{axis_angle_, bins_}.bin(heading);
}

double GraphStates::binHeading(int bin) const {
  return laser_features::HeadingBins{axis_angle_, bins_}.heading(bin);
}

int32_t GraphStates::nodeIndex(uint32_t node_id) const {
  const auto it = node_index_.find(node_id);
  return it == node_index_.end() ? -1 : it->second;
}

// The map's nodes, indexed in id order, with their openings; everything built from the last map
// cleared.
void GraphStates::indexNodes(const TopologicalMap& map) {
  dir_edges_.clear();
  node_ids_.clear();
  node_index_.clear();
  edge_index_.clear();
  node_exit_.clear();
  node_exit_back_.clear();
  node_openings_.clear();
  node_closed_.clear();
  node_open_way_.clear();
  edge_landmarks_.clear();
  near_node_.clear();
  state_dir_edge_.clear();

  for (const auto& entry : map.nodes()) {
    node_index_[entry.first] = int32_t(node_ids_.size());
    node_ids_.push_back(entry.first);
    node_openings_.push_back(entry.second.openings);
    node_closed_.push_back(entry.second.type == NodeType::HallwayEnd);
  }
}

// Both travel directions of every edge, their cells' state indices (per edge its forward cells
// then its backward cells); `exits`: per node the directed edges leaving it. Returns the edge ids
// by index.
std::vector<uint32_t> GraphStates::buildDirectedEdges(const TopologicalMap& map,
                                                        std::vector<std::vector<int32_t>>* exits) {
  // Exits per node in the order of TopologicalMap::exits (edge id order, source side first).
  exits->assign(node_ids_.size(), {});
  int32_t base = 0;
  std::vector<uint32_t> edge_ids;
  for (const auto& entry : map.edges()) {
    const TopoEdge& e = entry.second;
    // A map assembled by TopologicalMap::assign is not checked: skip dangling edges, sanitize numbers.
    if (!node_index_.count(e.source) || !node_index_.count(e.target)) continue;
    const int32_t index = int32_t(edge_ids.size());
    edge_index_[entry.first] = index;
    edge_ids.push_back(entry.first);
    const double length = finite(e.length) && e.length > 0.0 ? e.length : 0.0;
    const double heading = finite(e.heading) ? e.heading : 0.0;
    const long rounded = std::lround(std::min(length / resolution_, double(max_cells_per_edge_)));
    const int32_t n = int32_t(std::max(1L, std::min(rounded, long(max_cells_per_edge_))));
    for (int dir = 0; dir < 2; ++dir) {
      DirEdge d;
      d.length = length;
      d.cell = length / n;
      d.inv_cell = length > 0.0 ? n / length : 0.0;
      d.heading = dir == 0 ? normalizeAngle(heading) : normalizeAngle(heading + kPi);
      d.cells = n;
      d.base = base + dir * n;
      d.start = node_index_.at(dir == 0 ? e.source : e.target);
      d.end = node_index_.at(dir == 0 ? e.target : e.source);
      d.bin = headingBin(d.heading);
      d.bin_reversed = headingBin(d.heading + kPi);
      dir_edges_.push_back(d);
    }
    (*exits)[node_index_.at(e.source)].push_back(2 * index);
    (*exits)[node_index_.at(e.target)].push_back(2 * index + 1);
    edge_landmarks_.push_back(e.landmarks);
    base += 2 * n;
  }
  node_base_ = base;
  return edge_ids;
}

// Where travel goes on at each node: straight on from every directed edge, and from a node state
// with each heading bin ahead and behind.
void GraphStates::linkWays(const TopologicalMap& map, const std::vector<std::vector<int32_t>>& exits) {
  // The rule of TopologicalMap::exitWithHeading on the local adjacency (closest within tolerance,
  // later ones win ties).
  auto exitWithHeading = [&](int32_t node, double heading) {
    double best = kStraight;
    int32_t found = -1;
    for (int32_t de : exits[node]) {
      const double d = std::abs(normalizeAngle(dir_edges_[de].heading - heading));
      if (d <= best) {
        best = d;
        found = de;
      }
    }
    return found;
  };
  // The rule of TopologicalMap::wayOn: where a node has no exit, a neighbour's across a staggered
  // crossing's link.
  const laser_features::BuildingRules& rules = map.buildingRules();
  auto wayOn = [&](int32_t node, double heading) {
    const int32_t own = exitWithHeading(node, heading);
    if (own >= 0 || map.hasOpeningToward(node_ids_[node], heading)) return own;
    for (int32_t link : exits[node]) {
      const DirEdge& l = dir_edges_[link];
      if (!TopologicalMap::staggeredLink(l.length, l.heading, heading, rules)) continue;
      const int32_t on = exitWithHeading(l.end, heading);
      if (on >= 0 && dir_edges_[on].end != node) return on;
    }
    return int32_t(-1);
  };
  for (DirEdge& d : dir_edges_) d.next = wayOn(d.end, d.heading);
  const int32_t num_nodes = int32_t(node_ids_.size());
  node_exit_.resize(size_t(num_nodes) * bins_);
  node_exit_back_.resize(size_t(num_nodes) * bins_);
  for (int32_t n = 0; n < num_nodes; ++n) {
    for (int b = 0; b < bins_; ++b) {
      node_exit_[n * bins_ + b] = wayOn(n, binHeading(b));
      node_exit_back_[n * bins_ + b] = wayOn(n, binHeading(b) + kPi);
    }
  }
  markOpenWays(map);
}

// Where the known map ends at a node (mapEndsBeyond): an opening's way, the way straight on from an
// edge that arrives there, or any way at a node without edges; never at a hallway end.
void GraphStates::markOpenWays(const TopologicalMap& map) {
  const int32_t num_nodes = int32_t(node_ids_.size());
  node_open_way_.assign(size_t(num_nodes) * bins_, 0);
  std::vector<char> has_edge(size_t(num_nodes), 0);
  for (const DirEdge& d : dir_edges_) {
    has_edge[size_t(d.end)] = 1;
    if (!node_closed_[size_t(d.end)]) node_open_way_[size_t(d.end) * bins_ + d.bin] = 1;
  }
  for (int32_t n = 0; n < num_nodes; ++n) {
    if (node_closed_[size_t(n)]) continue;
    for (int b = 0; b < bins_; ++b) {
      char& open = node_open_way_[size_t(n) * bins_ + b];
      if (!has_edge[size_t(n)] || map.hasOpeningToward(node_ids_[size_t(n)], binHeading(b))) open = 1;
    }
  }
}

void GraphStates::buildStates(const std::vector<uint32_t>& edge_ids) {
  // States: per edge its forward cells then its backward cells, then the nodes' bins.
  const int32_t num_nodes = int32_t(node_ids_.size());
  states_.resize(size_t(node_base_) + size_t(num_nodes) * bins_);
  near_node_.assign(size_t(node_base_), -1);
  state_dir_edge_.assign(size_t(node_base_), -1);
  for (int32_t index = 0; index < int32_t(edge_ids.size()); ++index) {
    for (int dir = 0; dir < 2; ++dir) {
      const DirEdge& d = dir_edges_[2 * index + dir];
      for (int32_t i = 0; i < d.cells; ++i) {
        State& s = states_[d.base + i];
        s.kind = State::Edge;
        s.id = edge_ids[index];
        s.forward = dir == 0;
        s.offset = (i + 0.5) * d.cell;
        s.heading = d.heading;
        s.cell = uint32_t(i);
        state_dir_edge_[d.base + i] = 2 * index + dir;
        const double to_source = s.offset, to_target = d.length - s.offset;
        const int32_t source = dir == 0 ? d.start : d.end, target = dir == 0 ? d.end : d.start;
        if (std::min(to_source, to_target) <= node_radius_) {
          near_node_[d.base + i] = to_target < to_source ? target : source;
        }
      }
    }
  }
  for (int32_t n = 0; n < num_nodes; ++n) {
    for (int b = 0; b < bins_; ++b) {
      State& s = states_[nodeState(n, b)];
      s.kind = State::Node;
      s.id = node_ids_[n];
      s.forward = true;
      s.offset = 0.0;
      s.heading = binHeading(b);
      s.cell = uint32_t(b);
    }
  }
}

int GraphStates::edgeStateIndex(uint32_t edge, double offset, bool forward) const {
  auto it = edge_index_.find(edge);
  if (it == edge_index_.end() || !finite(offset)) return -1;
  const DirEdge& d = dir_edges_[2 * it->second + (forward ? 0 : 1)];
  int32_t k = d.cell > 0.0 ? int32_t(std::floor(std::clamp(offset, 0.0, d.length) / d.cell + kEps)) : 0;
  k = std::clamp(k, 0, d.cells - 1);
  return d.base + k;
}

int GraphStates::nodeStateIndex(uint32_t node, double heading) const {
  auto it = node_index_.find(node);
  if (it == node_index_.end() || !finite(heading)) return -1;
  return nodeState(it->second, headingBin(heading));
}

// The state at `s` (m from the start of travel along `de`); `reversed`: the robot faces against `de`.
int32_t GraphStates::cellState(int32_t de, double s, bool reversed) const {
  const DirEdge& d = dir_edges_[de];
  // s >= 0 and s <= length here: truncation is floor, the index at most `cells` (clamped).
  const int32_t k = d.cell > 0.0 ? std::min(int32_t(s * d.inv_cell + kEps), d.cells - 1) : 0;
  const int32_t source_cell = (de & 1) == 0 ? k : d.cells - 1 - k;
  return dir_edges_[reversed ? de ^ 1 : de].base + source_cell;
}

// Moves `distance` >= 0 along `de` from `s`, through nodes by the straight continuation; stops at a
// node when the overshoot is below resolution / 2 or there is no way on (hallway end). A successor
// at least one cell past a node without a way on (into a wall) is returned as ~index ("blocked").
int32_t GraphStates::walk(int32_t de, double s, double distance, bool reversed) const {
  for (int hop = 0;; ++hop) {
    const DirEdge& d = dir_edges_[de];
    const double s2 = s + distance;
    if (s2 <= d.length) return cellState(de, s2, reversed);
    const double over = s2 - d.length;
    const int32_t at_node = nodeState(d.end, reversed ? d.bin_reversed : d.bin);
    if (over < 0.5 * resolution_ - kEps || hop >= kMaxWalkHops) return at_node;
    if (d.next < 0) return over < resolution_ - kEps ? at_node : ~at_node;
    de = d.next;
    s = 0.0;
    distance = over;
  }
}

int32_t GraphStates::travelFrom(size_t state, double distance) const {
  if (distance == 0.0) return int32_t(state);
  if (int32_t(state) < node_base_) {
    const State& st = states_[state];
    const int32_t de = state_dir_edge_[state];
    const DirEdge& d = dir_edges_[de];
    const int32_t k = (de & 1) == 0 ? int32_t(st.cell) : d.cells - 1 - int32_t(st.cell);
    const double pos = (k + 0.5) * d.cell;  // along the travel heading
    return distance > 0.0 ? walk(de, pos, distance, false) : walk(de ^ 1, d.length - pos, -distance, true);
  }
  const int32_t n = (int32_t(state) - node_base_) / bins_;
  const int b = (int32_t(state) - node_base_) % bins_;
  const double a = std::abs(distance);
  if (a < 0.5 * resolution_ - kEps) return int32_t(state);
  const int32_t exit = distance > 0.0 ? node_exit_[n * bins_ + b] : node_exit_back_[n * bins_ + b];
  if (exit < 0) return a < resolution_ - kEps ? int32_t(state) : ~int32_t(state);  // blocked
  return walk(exit, 0.0, a, distance < 0.0);
}

int32_t GraphStates::turnFrom(size_t state, int k, bool* mid_edge) const {
  *mid_edge = false;
  if (int32_t(state) >= node_base_) {
    const int32_t n = (int32_t(state) - node_base_) / bins_;
    const int b = (int32_t(state) - node_base_) % bins_;
    return nodeState(n, (b + k) % bins_);
  }
  const State& st = states_[state];
  const int32_t de = state_dir_edge_[state];
  if (near_node_[state] >= 0) return nodeState(near_node_[state], (dir_edges_[de].bin + k) % bins_);
  if (2 * k == bins_) return dir_edges_[de ^ 1].base + int32_t(st.cell);  // 180 deg: same cell, reversed
  *mid_edge = true;
  return int32_t(state);
}

}  // namespace pomdp_topo
