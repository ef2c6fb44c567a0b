#include "pomdp_topo/pomdp_localizer.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::kTwoPi;
using laser_features::normalizeAngle;

namespace {

constexpr double kEps = 1e-9;               // m: ties at cell boundaries go forward
constexpr double kStraight = kPi / 4 + 1e-6; // rad: "within 45 deg" of exitWithHeading
constexpr int kMaxHops = 1000;              // edges one travel may pass (zero-length loops)
constexpr double kPlmapMin = 0.01, kPlmapMax = 0.99;

bool fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

PomdpLocalizer::PomdpLocalizer(const PomdpParams& params) : params_(params) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("PomdpLocalizer: " + why);
  bins_ = params.heading_bins;
  bin_width_ = kTwoPi / bins_;
}

bool PomdpLocalizer::validate(const PomdpParams& p, std::string* error) {
  auto positive = [](double v) { return finite(v) && v > 0.0; };
  auto nonneg = [](double v) { return finite(v) && v >= 0.0; };
  auto unit = [](double v) { return finite(v) && v >= 0.0 && v <= 1.0; };
  if (!positive(p.resolution)) return fail(error, "resolution must be > 0");
  if (p.heading_bins < 1 || p.heading_bins > 3600) return fail(error, "heading_bins must be in [1, 3600]");
  if (!finite(p.axis_angle)) return fail(error, "axis_angle must be finite");
  if (!nonneg(p.travel_spread)) return fail(error, "travel_spread must be >= 0");
  if (!nonneg(p.node_radius)) return fail(error, "node_radius must be >= 0");
  if (!unit(p.turn_mid_edge_probability)) return fail(error, "turn_mid_edge_probability must be in [0, 1]");
  if (!unit(p.turn_lost_mass)) return fail(error, "turn_lost_mass must be in [0, 1]");
  if (!unit(p.blocked_travel_probability)) return fail(error, "blocked_travel_probability must be in [0, 1]");
  if (!nonneg(p.window_ahead) || !nonneg(p.window_behind) || !nonneg(p.window_lateral))
    return fail(error, "windows must be >= 0");
  if (!positive(p.match_sigma_along) || !positive(p.match_sigma_lateral))
    return fail(error, "match sigmas must be > 0");
  if (!nonneg(p.match_orientation_tolerance)) return fail(error, "match_orientation_tolerance must be >= 0");
  if (!(unit(p.false_landmark_probability) && p.false_landmark_probability > 0.0))
    return fail(error, "false_landmark_probability must be in (0, 1]");
  if (!(unit(p.unexplored_landmark_probability) && p.unexplored_landmark_probability > 0.0))
    return fail(error, "unexplored_landmark_probability must be in (0, 1]");
  if (!(finite(p.opening_p_lmap) && p.opening_p_lmap > 0.0 && p.opening_p_lmap < 1.0))
    return fail(error, "opening_p_lmap must be in (0, 1)");
  if (!nonneg(p.observation_weight)) return fail(error, "observation_weight must be >= 0");
  if (!positive(p.heading_sigma)) return fail(error, "heading_sigma must be > 0");
  if (!(unit(p.heading_floor) && p.heading_floor > 0.0)) return fail(error, "heading_floor must be in (0, 1]");
  if (!unit(p.uniform_mixing)) return fail(error, "uniform_mixing must be in [0, 1]");
  if (!nonneg(p.entropy_max)) return fail(error, "entropy_max must be >= 0");
  if (!unit(p.lost_likelihood)) return fail(error, "lost_likelihood must be in [0, 1]");
  if (p.lost_steps < 1) return fail(error, "lost_steps must be >= 1");
  if (p.max_cells_per_edge < 1) return fail(error, "max_cells_per_edge must be >= 1");
  return true;
}

int PomdpLocalizer::headingBin(double heading) const {
  return laser_features::HeadingBins{params_.axis_angle, bins_}.bin(heading);
}

double PomdpLocalizer::binHeading(int bin) const {
  return laser_features::HeadingBins{params_.axis_angle, bins_}.heading(bin);
}

// ---------------------------------------------------------------------------------------------
// Map -> states

void PomdpLocalizer::setMap(const TopologicalMap& map) {
  // Old belief, carried over by key below.
  std::vector<State> old_states;
  std::vector<double> old_belief;
  old_states.swap(states_);
  old_belief.swap(belief_);

  map_revision_ = map.revision();
  indexNodes(map);
  std::vector<std::vector<int32_t>> exits;
  const std::vector<uint32_t> edge_ids = buildDirectedEdges(map, &exits);
  linkWays(map, exits);
  buildStates(edge_ids);
  applyOpenWays();
  buildExpected();

  // Buffers of the steps.
  belief_.assign(states_.size(), 0.0);
  scratch_.assign(states_.size(), 0.0);
  log_likelihood_.assign(states_.size(), 0.0);
  for (auto& t : travel_cache_) t.next.assign(3 * states_.size(), 0);  // predict() never allocates

  carryBelief(old_states, old_belief);
  lost_ = false;
  low_likelihood_steps_ = 0;
}

// The map's nodes, indexed in id order, with their openings; everything built from the last map
// cleared.
void PomdpLocalizer::indexNodes(const TopologicalMap& map) {
  dir_edges_.clear();
  node_ids_.clear();
  node_index_.clear();
  edge_index_.clear();
  node_exit_.clear();
  node_exit_back_.clear();
  node_openings_.clear();
  node_closed_.clear();
  edge_landmarks_.clear();
  near_node_.clear();
  state_dir_edge_.clear();
  for (auto& t : travel_cache_) t.valid = false;

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
std::vector<uint32_t> PomdpLocalizer::buildDirectedEdges(const TopologicalMap& map,
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
    const long rounded = std::lround(std::min(length / params_.resolution, double(params_.max_cells_per_edge)));
    const int32_t n = int32_t(std::max(1L, std::min(rounded, long(params_.max_cells_per_edge))));
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
void PomdpLocalizer::linkWays(const TopologicalMap& map, const std::vector<std::vector<int32_t>>& exits) {
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
}

void PomdpLocalizer::buildStates(const std::vector<uint32_t>& edge_ids) {
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
        if (std::min(to_source, to_target) <= params_.node_radius) {
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

// The old belief re-projected onto the new states by key (edge, offset, direction / node,
// heading); uniform when none of it lands.
void PomdpLocalizer::carryBelief(const std::vector<State>& old_states, const std::vector<double>& old_belief) {
  double carried = 0.0;
  for (size_t i = 0; i < old_states.size(); ++i) {
    const double p = old_belief[i];
    if (!(p > 0.0)) continue;
    const State& s = old_states[i];
    const int index = s.kind == State::Edge ? edgeStateIndex(s.id, s.offset, s.forward)
                                            : nodeStateIndex(s.id, binHeading(int(s.cell)));
    if (index < 0) continue;
    belief_[index] += p;
    carried += p;
  }
  if (carried > 0.0) {
    for (double& b : belief_) b /= carried;
  } else {
    setUniform();
  }
}

int PomdpLocalizer::edgeStateIndex(uint32_t edge, double offset, bool forward) const {
  auto it = edge_index_.find(edge);
  if (it == edge_index_.end() || !finite(offset)) return -1;
  const DirEdge& d = dir_edges_[2 * it->second + (forward ? 0 : 1)];
  int32_t k = d.cell > 0.0 ? int32_t(std::floor(std::clamp(offset, 0.0, d.length) / d.cell + kEps)) : 0;
  k = std::clamp(k, 0, d.cells - 1);
  return d.base + k;
}

int PomdpLocalizer::nodeStateIndex(uint32_t node, double heading) const {
  auto it = node_index_.find(node);
  if (it == node_index_.end() || !finite(heading)) return -1;
  return nodeState(it->second, headingBin(heading));
}

// ---------------------------------------------------------------------------------------------
// Expected landmarks (the window of OS(o, s))

void PomdpLocalizer::addEdgeLandmarks(int32_t de, double a0) {
  const bool fwd = (de & 1) == 0;
  const double length = dir_edges_[de].length;
  const std::vector<EdgeLandmark>& landmarks = edge_landmarks_[de >> 1];
  for (size_t index = 0; index < landmarks.size(); ++index) {
    const EdgeLandmark& lm = landmarks[index];
    const double along = a0 + (fwd ? lm.distance : length - lm.distance);
    const double lateral = fwd ? lm.lateral : -lm.lateral;
    if (along < -params_.window_behind || along > params_.window_ahead) continue;
    if (std::abs(lateral) > params_.window_lateral || !finite(along) || !finite(lateral) || !finite(lm.orientation))
      continue;
    if (lm.type != LandmarkType::Corner && lm.type != LandmarkType::Opening) continue;
    const double p = std::clamp(finite(lm.p_lmap) ? lm.p_lmap : 0.5, kPlmapMin, kPlmapMax);
    const double orientation = fwd ? normalizeAngle(lm.orientation) : normalizeAngle(lm.orientation + kPi);
    expected_.push_back({float(along), float(lateral), float(orientation), float(std::log(p) - std::log1p(-p)),
                         float(p), lm.type, (1ull << 62) | (uint64_t(de >> 1) << 24) | uint64_t(index)});
  }
}

void PomdpLocalizer::addNodeOpenings(int32_t node, double along, double heading) {
  if (std::find(visited_nodes_.begin(), visited_nodes_.end(), node) != visited_nodes_.end()) return;
  visited_nodes_.push_back(node);
  const double p = std::clamp(params_.opening_p_lmap, kPlmapMin, kPlmapMax);
  for (size_t index = 0; index < node_openings_[node].size(); ++index) {
    const NodeOpening& o = node_openings_[node][index];
    const double rel = normalizeAngle(o.bearing - heading);
    const double a = along + o.offset * std::cos(rel);
    const double l = o.offset * std::sin(rel);
    if (std::abs(l) > params_.window_lateral || !finite(a) || !finite(l)) continue;
    expected_.push_back({float(a), float(l), float(rel), float(std::log(p) - std::log1p(-p)), float(p),
                         LandmarkType::Opening, (2ull << 62) | (uint64_t(node) << 24) | uint64_t(index)});
  }
}

// Along the travel heading from the start of `de` (at along a0), straight through nodes.
void PomdpLocalizer::walkForward(int32_t de, double a0, double heading) {
  for (int hop = 0; de >= 0 && hop < kMaxHops; ++hop) {
    const uint32_t edge = uint32_t(de >> 1);
    if (std::find(visited_edges_.begin(), visited_edges_.end(), edge) != visited_edges_.end()) return;
    visited_edges_.push_back(edge);
    addEdgeLandmarks(de, a0);
    const double a_end = a0 + dir_edges_[de].length;
    if (a_end > params_.window_ahead) return;
    addNodeOpenings(dir_edges_[de].end, a_end, heading);
    a0 = a_end;
    if (dir_edges_[de].next < 0 && !node_closed_[dir_edges_[de].end]) cur_unknown_ahead_ = float(a_end);
    de = dir_edges_[de].next;
  }
}

// Against the travel heading: `motion` leaves the node at along a_end backwards; the robot's
// direction on that edge is motion ^ 1.
void PomdpLocalizer::walkBackward(int32_t motion, double a_end, double heading) {
  for (int hop = 0; motion >= 0 && hop < kMaxHops; ++hop) {
    const uint32_t edge = uint32_t(motion >> 1);
    if (std::find(visited_edges_.begin(), visited_edges_.end(), edge) != visited_edges_.end()) return;
    visited_edges_.push_back(edge);
    const double a0 = a_end - dir_edges_[motion].length;
    addEdgeLandmarks(motion ^ 1, a0);
    if (a0 < -params_.window_behind) return;
    addNodeOpenings(dir_edges_[motion].end, a0, heading);
    a_end = a0;
    if (dir_edges_[motion].next < 0 && !node_closed_[dir_edges_[motion].end]) cur_unknown_behind_ = float(a0);
    motion = dir_edges_[motion].next;
  }
}

void PomdpLocalizer::buildExpected() {
  expectStateLandmarks();
  expectEdgeLandmarks();
  // Structure of arrays of the per-state lists (node states, irregular edges, expectedLandmarks()).
  const size_t n = expected_.size();
  ex_along_.assign(n, 0.0f);
  ex_lateral_.assign(n, 0.0f);
  ex_cos_.assign(n, 0.0f);
  ex_sin_.assign(n, 0.0f);
  ex_gain_.assign(n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    ex_along_[i] = expected_[i].along;
    ex_lateral_[i] = expected_[i].lateral;
    ex_cos_[i] = float(std::cos(double(expected_[i].orientation)));
    ex_sin_[i] = float(std::sin(double(expected_[i].orientation)));
    ex_gain_[i] = expected_[i].gain;
  }
  expected_.clear();
  expected_.shrink_to_fit();
}

// Per state: the landmarks in its window (CSR in expected_), corners then openings, each by along;
// their sum of log(1 - p_lmap), and where the known map ends ahead and behind.
void PomdpLocalizer::expectStateLandmarks() {
  expected_.clear();
  expected_begin_.assign(states_.size() + 1, 0);
  expected_base_.assign(states_.size(), 0.0f);
  expected_split_.assign(states_.size(), 0);
  unknown_ahead_.assign(states_.size(), std::numeric_limits<float>::infinity());
  unknown_behind_.assign(states_.size(), -std::numeric_limits<float>::infinity());
  max_expected_ = 0;
  for (size_t s = 0; s < states_.size(); ++s) {
    expected_begin_[s] = uint32_t(expected_.size());
    visited_edges_.clear();
    visited_nodes_.clear();
    cur_unknown_ahead_ = std::numeric_limits<float>::infinity();
    cur_unknown_behind_ = -std::numeric_limits<float>::infinity();
    const double h = states_[s].heading;
    if (states_[s].kind == State::Edge) {
      const int32_t de = state_dir_edge_[s];
      const DirEdge& d = dir_edges_[de];
      const int32_t k = d.cells - 1 - int32_t(states_[s].cell);
      const double pos = (de & 1) == 0 ? states_[s].offset : (k + 0.5) * d.cell;  // along the travel
      visited_edges_.push_back(uint32_t(de >> 1));
      addEdgeLandmarks(de, -pos);
      if (d.length - pos <= params_.window_ahead) {
        addNodeOpenings(d.end, d.length - pos, h);
        if (d.next < 0 && !node_closed_[d.end]) cur_unknown_ahead_ = float(d.length - pos);
        walkForward(d.next, d.length - pos, h);
      }
      if (pos <= params_.window_behind) {
        addNodeOpenings(d.start, -pos, h);
        if (dir_edges_[de ^ 1].next < 0 && !node_closed_[d.start]) cur_unknown_behind_ = float(-pos);
        walkBackward(dir_edges_[de ^ 1].next, -pos, h);
      }
    } else {
      const int32_t n = node_index_.at(states_[s].id);
      const int b = int(states_[s].cell);
      addNodeOpenings(n, 0.0, h);
      if (node_exit_[n * bins_ + b] < 0 && !node_closed_[n]) cur_unknown_ahead_ = 0.0f;
      if (node_exit_back_[n * bins_ + b] < 0 && !node_closed_[n]) cur_unknown_behind_ = 0.0f;
      walkForward(node_exit_[n * bins_ + b], 0.0, h);
      walkBackward(node_exit_back_[n * bins_ + b], 0.0, h);
    }
    unknown_ahead_[s] = cur_unknown_ahead_;
    unknown_behind_[s] = cur_unknown_behind_;
    // Corners then openings, each by along: update() pairs only landmarks of the same type.
    std::sort(expected_.begin() + expected_begin_[s], expected_.end(), [](const Expected& a, const Expected& b) {
      return a.type != b.type ? a.type < b.type : a.along < b.along;
    });
    expected_split_[s] = uint32_t(std::partition_point(expected_.begin() + expected_begin_[s], expected_.end(),
                                                       [](const Expected& e) { return e.type == LandmarkType::Corner; }) -
                                  expected_.begin());
    double base = 0.0;
    for (size_t i = expected_begin_[s]; i < expected_.size(); ++i) base += std::log1p(-double(expected_[i].p_lmap));
    expected_base_[s] = float(base);
    max_expected_ = std::max(max_expected_, expected_.size() - expected_begin_[s]);
  }
  expected_begin_[states_.size()] = uint32_t(expected_.size());
}

void PomdpLocalizer::expectEdgeLandmarks() {
  // Per directed edge: the union of its cells' expected landmarks in travel coordinates t (along =
  // t - cell position), each with the range of cells [kmin, kmax] (travel order) that expect it. A
  // landmark expected by non-consecutive cells (tiny loops) makes the edge "irregular": its cells
  // are then evaluated one by one.
  de_expected_begin_.assign(dir_edges_.size() + 1, 0);
  de_regular_.assign(dir_edges_.size(), 1);
  edge_expected_.clear();
  size_t max_members = 0, max_union = 0, max_cells = 0;
  for (size_t de = 0; de < dir_edges_.size(); ++de) {
    const DirEdge& d = dir_edges_[de];
    const uint32_t first = uint32_t(edge_expected_.size());
    de_expected_begin_[de] = first;
    size_t members = 0;
    for (int32_t k = 0; k < d.cells; ++k) {
      const size_t s = size_t(d.base + ((de & 1) == 0 ? k : d.cells - 1 - k));
      const double pos = (k + 0.5) * d.cell;
      for (size_t i = expected_begin_[s]; i < expected_begin_[s + 1]; ++i) {
        const Expected& e = expected_[i];
        const double t = double(e.along) + pos;
        ++members;
        bool found = false;
        for (size_t x = first; x < edge_expected_.size(); ++x) {
          EdgeExpected& u = edge_expected_[x];
          if (u.key != e.key || std::abs(u.t - t) > 1e-3) continue;
          if (u.kmax != k - 1) de_regular_[de] = 0;
          u.kmax = k;
          found = true;
          break;
        }
        if (!found) {
          edge_expected_.push_back({t, e.lateral, float(std::cos(double(e.orientation))),
                                    float(std::sin(double(e.orientation))), e.gain, e.type, k, k, e.key});
        }
      }
    }
    max_members = std::max(max_members, members);
    max_union = std::max(max_union, edge_expected_.size() - first);
    max_cells = std::max(max_cells, size_t(d.cells));
  }
  de_expected_begin_[dir_edges_.size()] = uint32_t(edge_expected_.size());
  x_gain_.resize(edge_expected_.size());
  for (size_t x = 0; x < edge_expected_.size(); ++x) x_gain_[x] = edge_expected_[x].gain;
  max_edge_members_ = max_members;
  cell_head_.assign(max_cells, -1);
  used_expected_.assign(std::max(max_expected_, max_union), 0);
}

std::vector<ExpectedLandmark> PomdpLocalizer::expectedLandmarks(size_t index) const {
  std::vector<ExpectedLandmark> out;
  if (index >= states_.size()) return out;
  for (size_t i = expected_begin_[index]; i < expected_begin_[index + 1]; ++i) {
    const LandmarkType type = i < expected_split_[index] ? LandmarkType::Corner : LandmarkType::Opening;
    const double p = 1.0 / (1.0 + std::exp(-double(ex_gain_[i])));
    out.push_back({type, ex_along_[i], ex_lateral_[i], std::atan2(double(ex_sin_[i]), double(ex_cos_[i])), p});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Transition T(s, a, s') (eq. 2)

// The state at `s` (m from the start of travel along `de`); `reversed`: the robot faces against `de`.
int32_t PomdpLocalizer::cellState(int32_t de, double s, bool reversed) const {
  const DirEdge& d = dir_edges_[de];
  // s >= 0 and s <= length here: truncation is floor, the index at most `cells` (clamped).
  const int32_t k = d.cell > 0.0 ? std::min(int32_t(s * d.inv_cell + kEps), d.cells - 1) : 0;
  const int32_t source_cell = (de & 1) == 0 ? k : d.cells - 1 - k;
  return dir_edges_[reversed ? de ^ 1 : de].base + source_cell;
}

// Moves `distance` >= 0 along `de` from `s`, through nodes by the straight continuation; stops at a
// node when the overshoot is below resolution / 2 or there is no way on (hallway end). A successor
// at least one cell past a node without a way on (into a wall) is returned as ~index ("blocked").
int32_t PomdpLocalizer::walk(int32_t de, double s, double distance, bool reversed) const {
  for (int hop = 0;; ++hop) {
    const DirEdge& d = dir_edges_[de];
    const double s2 = s + distance;
    if (s2 <= d.length) return cellState(de, s2, reversed);
    const double over = s2 - d.length;
    const int32_t at_node = nodeState(d.end, reversed ? d.bin_reversed : d.bin);
    if (over < 0.5 * params_.resolution - kEps || hop >= kMaxHops) return at_node;
    if (d.next < 0) return over < params_.resolution - kEps ? at_node : ~at_node;
    de = d.next;
    s = 0.0;
    distance = over;
  }
}

int32_t PomdpLocalizer::travelFrom(size_t state, double distance) const {
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
  if (a < 0.5 * params_.resolution - kEps) return int32_t(state);
  const int32_t exit = distance > 0.0 ? node_exit_[n * bins_ + b] : node_exit_back_[n * bins_ + b];
  if (exit < 0) return a < params_.resolution - kEps ? int32_t(state) : ~int32_t(state);  // blocked
  return walk(exit, 0.0, a, distance < 0.0);
}

const PomdpLocalizer::TravelTable& PomdpLocalizer::travelTable(double distance) {
  ++travel_uses_;
  TravelTable* slot = &travel_cache_[0];
  for (TravelTable& t : travel_cache_) {
    if (t.valid && t.distance == distance) {
      t.last_use = travel_uses_;
      return t;
    }
    if (!t.valid || t.last_use < slot->last_use) slot = &t;
  }
  // Successors for distance - cell, distance, distance + cell (cell of the state's edge, resolution
  // at nodes).
  slot->next.resize(3 * states_.size());
  for (size_t s = 0; s < states_.size(); ++s) {
    double cell = params_.resolution;
    if (int32_t(s) < node_base_) {
      const double c = dir_edges_[state_dir_edge_[s]].cell;
      if (c > 0.0) cell = c;
    }
    slot->next[3 * s + 0] = travelFrom(s, distance - cell);
    slot->next[3 * s + 1] = travelFrom(s, distance);
    slot->next[3 * s + 2] = travelFrom(s, distance + cell);
  }
  slot->distance = distance;
  slot->valid = true;
  slot->last_use = travel_uses_;
  return *slot;
}

int32_t PomdpLocalizer::turnFrom(size_t state, int k, bool* mid_edge) const {
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

void PomdpLocalizer::finishPrediction() {
  double total = 0.0;
  for (double p : scratch_) total += p;
  if (!(total > 0.0) || !finite(total)) {
    setUniform();
    return;
  }
  const double u = params_.uniform_mixing;
  const double keep = (1.0 - u) / total, add = u / double(scratch_.size());
  for (size_t s = 0; s < scratch_.size(); ++s) belief_[s] = scratch_[s] * keep + add;
}

void PomdpLocalizer::addOpenWay(uint32_t node, double heading) {
  open_ways_.emplace_back(node, headingBin(heading));
  applyOpenWays();
}

void PomdpLocalizer::clearOpenWays() {
  open_ways_.clear();
  applyOpenWays();
}

void PomdpLocalizer::applyOpenWays() {
  if (blocked_factor_.size() != states_.size()) blocked_factor_.assign(states_.size(), 0.0);
  std::fill(blocked_factor_.begin(), blocked_factor_.end(), params_.blocked_travel_probability);
  for (const auto& way : open_ways_) {
    const auto it = node_index_.find(way.first);
    if (it != node_index_.end()) blocked_factor_[nodeState(it->second, way.second)] = 1.0;
  }
}

bool PomdpLocalizer::predict(const Action& action, std::string* error) {
  if (action.kind == Action::Travel) {
    if (!finite(action.distance)) return fail(error, "travel distance is not finite");
    if (states_.empty() || action.distance == 0.0) return true;
    const TravelTable& table = travelTable(action.distance);
    const double p = std::min(0.45, params_.travel_spread * std::abs(action.distance));
    const double p_under = p, p_over = p, p_mid = 1.0 - 2.0 * p;
    std::fill(scratch_.begin(), scratch_.end(), 0.0);
    const int32_t* next = table.next.data();
    auto add = [&](int32_t t, double mass) {
      if (t >= 0) {
        scratch_[t] += mass;
      } else {
        scratch_[~t] += blocked_factor_[size_t(~t)] * mass;
      }
    };
    for (size_t s = 0; s < belief_.size(); ++s) {  // sum_s T(s, a, s') b(s)
      const double b = belief_[s];
      add(next[3 * s + 0], p_under * b);
      add(next[3 * s + 1], p_mid * b);
      add(next[3 * s + 2], p_over * b);
    }
    finishPrediction();
    return true;
  }
  if (action.kind == Action::Turn) {
    if (states_.empty()) return true;
    const int k = ((action.turn_bins % bins_) + bins_) % bins_;
    if (k == 0) return true;
    std::fill(scratch_.begin(), scratch_.end(), 0.0);
    double at_nodes = 0.0;
    for (size_t s = 0; s < belief_.size(); ++s) {
      bool mid_edge = false;
      const int32_t t = turnFrom(s, k, &mid_edge);
      scratch_[t] += mid_edge ? params_.turn_mid_edge_probability * belief_[s] : belief_[s];
      if (!mid_edge || 2 * k == bins_) at_nodes += belief_[s];
    }
    finishPrediction();
    // Hallways are left only at nodes: a turn the belief cannot place at one means the robot is not
    // where the belief says (kidnapped, or a missed node).
    if (at_nodes < params_.turn_lost_mass) {
      setUniform();
      lost_ = true;
      ++lost_resets_;
    }
    return true;
  }
  return fail(error, "unknown action kind");
}

// ---------------------------------------------------------------------------------------------
// Observation OS(o, s) (eq. 2)

// The greedy one-to-one association of OS(o, s): candidates by increasing d^2, each expected and
// each observed landmark used once. A match replaces log(1 - p_lmap) + log(false) by
// log(p_lmap * confidence) - d^2 / 2. `gains` (log p_lmap - log(1 - p_lmap)) is indexed by Candidate::e.
double PomdpLocalizer::greedyMatch(uint32_t count, const float* gains) {
  Candidate* cand = candidates_.data();
  auto gain = [&](const Candidate& c) { return double(gains[c.e]) + obs_[c.o].match_bonus - 0.5 * double(c.d2); };
  auto before = [](const Candidate& a, const Candidate& b) {
    return a.d2 < b.d2 || (a.d2 == b.d2 && (a.e < b.e || (a.e == b.e && a.o < b.o)));
  };
  if (count == 0) return 0.0;
  if (count == 1) return gain(cand[0]);
  if (count == 2) {
    if (cand[0].e != cand[1].e && cand[0].o != cand[1].o) return gain(cand[0]) + gain(cand[1]);
    return gain(before(cand[0], cand[1]) ? cand[0] : cand[1]);
  }
  std::sort(cand, cand + count, before);
  double sum = 0.0;
  for (uint32_t c = 0; c < count; ++c) {
    if (used_expected_[cand[c].e] || used_observed_[cand[c].o]) continue;
    used_expected_[cand[c].e] = used_observed_[cand[c].o] = 1;
    sum += gain(cand[c]);
  }
  for (uint32_t c = 0; c < count; ++c) used_expected_[cand[c].e] = used_observed_[cand[c].o] = 0;
  return sum;
}

// log OS(o, s) of one state without the heading term, from its own list of expected landmarks.
// Observed landmarks beyond where the known map ends (at a node with no way on that is no hallway
// end) are unexplored: their factor is unexplored_landmark_probability instead of the false one.
double PomdpLocalizer::unknownCorrection(size_t state) const {
  if (obs_along_sorted_.empty()) return 0.0;
  const float margin = float(params_.match_sigma_along);
  const auto first = obs_along_sorted_.begin(), last = obs_along_sorted_.end();
  const size_t ahead = size_t(last - std::upper_bound(first, last, unknown_ahead_[state] + margin));
  const size_t behind = size_t(std::lower_bound(first, last, unknown_behind_[state] - margin) - first);
  return double(ahead + behind) * unknown_gain_;
}

double PomdpLocalizer::observationLogLikelihood(size_t state) {
  const double ll = double(expected_base_[state]) + obs_log_false_ + unknownCorrection(state);
  const uint32_t begin = expected_begin_[state], split = expected_split_[state], end = expected_begin_[state + 1];
  if (begin == end) return ll;
  // Every (expected, observed) pair of the same type, without branches: a candidate is written always
  // and kept when d^2 <= 9 and the orientations agree (cos of the difference >= cos tol).
  Candidate* cand = candidates_.data();
  uint32_t count = 0;
  const float* along = ex_along_.data();
  const float* lateral = ex_lateral_.data();
  const float* cs = ex_cos_.data();
  const float* sn = ex_sin_.data();
  const float inv_a = inv_sigma_along_, inv_l = inv_sigma_lateral_, cos_tol = cos_tolerance_;
  for (uint32_t j = 0; j < uint32_t(obs_.size()); ++j) {
    const float oa = obs_[j].along, ol = obs_[j].lateral, oc = obs_[j].cos, os = obs_[j].sin;
    const bool corner = obs_[j].type == LandmarkType::Corner;
    const uint32_t from = corner ? begin : split, to = corner ? split : end;
    for (uint32_t i = from; i < to; ++i) {
      const float da = (oa - along[i]) * inv_a;
      const float dl = (ol - lateral[i]) * inv_l;
      const float d2 = da * da + dl * dl;
      const float dot = oc * cs[i] + os * sn[i];
      cand[count] = {d2, i - begin, j};
      count += uint32_t((d2 <= 9.0f) & (dot >= cos_tol));
    }
  }
  return ll + greedyMatch(count, ex_gain_.data() + begin);
}

// log OS(o, s) + heading term for every cell of a regular directed edge: each (landmark, observed)
// pair is checked once for lateral and orientation, then only the cells whose along offset fits get
// a candidate.
void PomdpLocalizer::edgeLogLikelihoods(int32_t de, double heading_term) {
  const DirEdge& d = dir_edges_[de];
  const uint32_t xb = de_expected_begin_[de], xe = de_expected_begin_[de + 1];
  const double sa = params_.match_sigma_along;
  const double inv_a = double(inv_sigma_along_), inv_l = double(inv_sigma_lateral_);
  std::fill(cell_head_.begin(), cell_head_.begin() + d.cells, -1);
  PoolCandidate* pool = pool_.data();  // sized for every (expected, observed) pair of the edge's cells
  const int32_t capacity = int32_t(std::min(pool_.size(), size_t(INT32_MAX)));
  int32_t pooled = 0;
  bool overflow = false;  // cannot happen (see the sizing in prepareObservation); defensive
  for (uint32_t x = xb; x < xe; ++x) {
    const EdgeExpected& u = edge_expected_[x];
    for (uint32_t j = 0; j < uint32_t(obs_.size()); ++j) {
      const Obs& o = obs_[j];
      if (o.type != u.type || !(o.cos * u.cos + o.sin * u.sin >= cos_tolerance_)) continue;
      const double dl = (double(o.lateral) - double(u.lateral)) * inv_l;
      const double dl2 = dl * dl;
      if (dl2 > 9.0) continue;
      int32_t k_lo = u.kmin, k_hi = u.kmax;
      if (d.cell > 0.0) {  // cells with |o.along - (t - pos)| <= sa sqrt(9 - dl^2), one cell of margin
        const double center = u.t - double(o.along), r = sa * std::sqrt(9.0 - dl2);
        const double lo = (center - r) / d.cell - 0.5, hi = (center + r) / d.cell + 0.5;  // truncated below
        if (lo > double(u.kmin)) k_lo = lo < double(u.kmax) ? int32_t(lo) : u.kmax;
        if (hi < double(u.kmax)) k_hi = hi > double(u.kmin) ? int32_t(hi) : u.kmin;
      }
      for (int32_t k = k_lo; k <= k_hi; ++k) {
        const double da = (double(o.along) - u.t + (k + 0.5) * d.cell) * inv_a;
        const double d2 = da * da + dl2;
        if (!(d2 <= 9.0)) continue;
        if (pooled == capacity) {
          overflow = true;
          break;
        }
        pool[pooled] = {float(d2), x - xb, j, cell_head_[k]};
        cell_head_[k] = pooled++;
      }
    }
  }
  if (overflow) {
    for (int32_t i = 0; i < d.cells; ++i) log_likelihood_[d.base + i] = observationLogLikelihood(d.base + i) + heading_term;
    return;
  }
  const float* gains = x_gain_.data() + xb;
  const uint32_t max_count = uint32_t(candidates_.size());
  for (int32_t k = 0; k < d.cells; ++k) {
    const size_t s = size_t(d.base + ((de & 1) == 0 ? k : d.cells - 1 - k));
    uint32_t count = 0;
    for (int32_t p = cell_head_[k]; p >= 0 && count < max_count; p = pool[p].next) {
      candidates_[count++] = {pool[p].d2, pool[p].e, pool[p].o};
    }
    log_likelihood_[s] = double(expected_base_[s]) + obs_log_false_ + greedyMatch(count, gains) + heading_term +
                         unknownCorrection(s);
  }
}

bool PomdpLocalizer::checkObservation(const Observation& o, std::string* error) {
  for (const ObservedLandmark& l : o.landmarks) {
    if (l.type != LandmarkType::Corner && l.type != LandmarkType::Opening) {
      return fail(error, "observation holds a landmark of unknown type");
    }
    if (!finite(l.along) || !finite(l.lateral) || !finite(l.orientation) || !finite(l.width) ||
        !finite(l.confidence)) {
      return fail(error, "observation holds a non-finite landmark value");
    }
  }
  if (o.heading_valid && (!finite(o.heading) || !finite(o.heading_variance) || o.heading_variance < 0.0)) {
    return fail(error, "observation heading or heading variance is not finite or negative");
  }
  return true;
}

void PomdpLocalizer::prepareObservation(const Observation& o) {
  const double log_false = std::log(params_.false_landmark_probability);
  inv_sigma_along_ = float(1.0 / params_.match_sigma_along);
  inv_sigma_lateral_ = float(1.0 / params_.match_sigma_lateral);
  cos_tolerance_ = params_.match_orientation_tolerance >= kPi ? -2.0f : float(std::cos(params_.match_orientation_tolerance));
  obs_log_false_ = double(o.landmarks.size()) * log_false;
  unknown_gain_ = std::log(params_.unexplored_landmark_probability) - log_false;
  obs_along_sorted_.clear();
  for (const ObservedLandmark& l : o.landmarks) obs_along_sorted_.push_back(float(std::clamp(l.along, -1e6, 1e6)));
  std::sort(obs_along_sorted_.begin(), obs_along_sorted_.end());
  obs_.clear();
  for (const ObservedLandmark& l : o.landmarks) {
    // Far-off values (beyond float range) can match nothing: clamp them so that float stays finite.
    obs_.push_back({l.type, float(std::clamp(l.along, -1e6, 1e6)), float(std::clamp(l.lateral, -1e6, 1e6)),
                    float(std::cos(l.orientation)), float(std::sin(l.orientation)),
                    std::log(std::clamp(l.confidence, 1e-6, 1.0)) - log_false});
  }
  if (used_observed_.size() < obs_.size()) used_observed_.resize(obs_.size(), 0);
  if (candidates_.size() < max_expected_ * obs_.size()) candidates_.resize(max_expected_ * obs_.size());
  if (pool_.size() < max_edge_members_ * obs_.size()) pool_.resize(max_edge_members_ * obs_.size());
  heading_valid_ = o.heading_valid;
  heading_ = o.heading;
  heading_variance_ = params_.heading_sigma * params_.heading_sigma + o.heading_variance;
}

double PomdpLocalizer::headingTerm(double h) const {
  if (!heading_valid_) return 0.0;
  const double d = normalizeAngle(heading_ - h);
  return std::log(params_.heading_floor + (1.0 - params_.heading_floor) * std::exp(-d * d / (2.0 * heading_variance_)));
}

double PomdpLocalizer::stateLogLikelihood(size_t index, const Observation& o) {
  if (index >= states_.size() || !checkObservation(o, nullptr)) return std::nan("");
  prepareObservation(o);
  return observationLogLikelihood(index) + headingTerm(states_[index].heading);
}

bool PomdpLocalizer::update(const Observation& o, std::string* error) {
  if (!checkObservation(o, error)) return false;
  if (states_.empty()) return true;
  lost_ = false;
  prepareObservation(o);

  // log OS(o, s), with the heading term per directed edge / node state.
  for (size_t de = 0; de < dir_edges_.size(); ++de) {
    const DirEdge& d = dir_edges_[de];
    const double ht = headingTerm(d.heading);
    if (de_regular_[de]) {
      edgeLogLikelihoods(int32_t(de), ht);
    } else {
      for (int32_t i = 0; i < d.cells; ++i) log_likelihood_[d.base + i] = observationLogLikelihood(d.base + i) + ht;
    }
  }
  for (size_t s = size_t(node_base_); s < states_.size(); ++s) {
    log_likelihood_[s] = observationLogLikelihood(s) + headingTerm(states_[s].heading);
  }
  double max_ll = -std::numeric_limits<double>::infinity();
  for (double ll : log_likelihood_) max_ll = std::max(max_ll, ll);
  if (!finite(max_ll)) {
    setUniform();
    lost_ = true;
    ++lost_resets_;
    return true;
  }

  // b'(s) = eta * OS(o, s)^w * b(s)   (eq. 2, tempered by w = observation_weight)
  const double w = params_.observation_weight;
  double total = 0.0;
  for (size_t s = 0; s < belief_.size(); ++s) {
    scratch_[s] = belief_[s] * std::exp(w * (log_likelihood_[s] - max_ll));
    total += scratch_[s];
  }

  // Lost detection on the normalizer 1/eta = sum_s b(s) OS(o, s)^w, brought back to the scale of one
  // likelihood: log L = log(1/eta) / w (w = 0: the untempered sum_s b(s) OS(o, s)).
  if (w > 0.0) {
    last_log_likelihood_ = max_ll + std::log(total) / w;
  } else {
    double z = 0.0;
    for (size_t s = 0; s < belief_.size(); ++s) z += belief_[s] * std::exp(log_likelihood_[s] - max_ll);
    last_log_likelihood_ = max_ll + std::log(z);
  }
  const double log_lost = params_.lost_likelihood > 0.0 ? std::log(params_.lost_likelihood)
                                                        : -std::numeric_limits<double>::infinity();
  if (!(last_log_likelihood_ - obs_log_false_ >= log_lost)) {
    if (++low_likelihood_steps_ >= params_.lost_steps) {
      // Reset to uniform; this observation is then applied to the uniform prior.
      lost_ = true;
      ++lost_resets_;
      low_likelihood_steps_ = 0;
      total = 0.0;
      for (size_t s = 0; s < belief_.size(); ++s) {
        scratch_[s] = std::exp(w * (log_likelihood_[s] - max_ll));
        total += scratch_[s];
      }
    }
  } else {
    low_likelihood_steps_ = 0;
  }
  if (!(total > 0.0) || !finite(total)) {
    setUniform();
    lost_ = true;
    return true;
  }
  const double eta = 1.0 / total;
  for (size_t s = 0; s < belief_.size(); ++s) belief_[s] = scratch_[s] * eta;
  return true;
}

bool PomdpLocalizer::step(const Action& action, const Observation& observation, std::string* error) {
  if (!checkObservation(observation, error)) return false;  // a refused step changes nothing
  if (!predict(action, error)) return false;
  return update(observation, error);
}

// ---------------------------------------------------------------------------------------------
// Belief

void PomdpLocalizer::setUniform() {
  if (states_.empty()) return;
  std::fill(belief_.begin(), belief_.end(), 1.0 / double(states_.size()));
  low_likelihood_steps_ = 0;
}

bool PomdpLocalizer::setState(size_t index) {
  if (index >= states_.size()) return false;
  std::fill(belief_.begin(), belief_.end(), 0.0);
  belief_[index] = 1.0;
  lost_ = false;
  low_likelihood_steps_ = 0;
  return true;
}

bool PomdpLocalizer::setBelief(const std::vector<double>& belief) {
  if (belief.size() != belief_.size() || belief.empty()) return false;
  double total = 0.0;
  for (double p : belief) {
    if (!finite(p) || p < 0.0) return false;
    total += p;
  }
  if (!(total > 0.0) || !finite(total)) return false;
  for (size_t s = 0; s < belief.size(); ++s) belief_[s] = belief[s] / total;
  lost_ = false;
  low_likelihood_steps_ = 0;
  return true;
}

bool PomdpLocalizer::restrictTo(const std::vector<bool>& allowed) {
  if (allowed.size() != belief_.size()) return true;
  double inside = 0.0;
  size_t count = 0;
  for (size_t s = 0; s < belief_.size(); ++s) {
    if (!allowed[s]) continue;
    inside += belief_[s];
    ++count;
  }
  if (count == 0) return true;
  const bool kept = inside > 1e-12;
  for (size_t s = 0; s < belief_.size(); ++s) {
    belief_[s] = !allowed[s] ? 0.0 : kept ? belief_[s] / inside : 1.0 / double(count);
  }
  return kept;
}

bool PomdpLocalizer::resetToNode(uint32_t node, double heading) {
  const int index = nodeStateIndex(node, heading);
  return index >= 0 && setState(size_t(index));
}

bool PomdpLocalizer::resetToEdge(uint32_t edge, double offset, bool forward) {
  const int index = edgeStateIndex(edge, offset, forward);
  return index >= 0 && setState(size_t(index));
}

double PomdpLocalizer::entropy() const {  // eq. 3
  double u = 0.0;
  for (double p : belief_) {
    if (p > 0.0) u -= p * std::log(p);
  }
  return u;
}

bool PomdpLocalizer::confident() const {
  return !states_.empty() && !lost_ && entropy() < params_.entropy_max;
}

int PomdpLocalizer::mostLikely() const {
  if (belief_.empty()) return -1;
  return int(std::max_element(belief_.begin(), belief_.end()) - belief_.begin());
}

double PomdpLocalizer::probabilityNearNode(uint32_t node, double radius) const {
  auto it = node_index_.find(node);
  if (it == node_index_.end()) return 0.0;
  double p = 0.0;
  for (int b = 0; b < bins_; ++b) p += belief_[nodeState(it->second, b)];
  for (size_t de = 0; de < dir_edges_.size(); de += 2) {
    const DirEdge& d = dir_edges_[de];  // forward: start = source
    if (d.start != it->second && d.end != it->second) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const DirEdge& dd = dir_edges_[de + dir];
      for (int32_t i = 0; i < dd.cells; ++i) {
        const double x = (i + 0.5) * dd.cell;  // from the source
        if ((d.start == it->second && x <= radius) || (d.end == it->second && d.length - x <= radius)) {
          p += belief_[dd.base + i];
        }
      }
    }
  }
  return p;
}

double PomdpLocalizer::probabilityWhere(const std::function<bool(const State&)>& predicate) const {
  double p = 0.0;
  for (size_t s = 0; s < states_.size(); ++s) {
    if (predicate(states_[s])) p += belief_[s];
  }
  return p;
}

}  // namespace pomdp_topo
