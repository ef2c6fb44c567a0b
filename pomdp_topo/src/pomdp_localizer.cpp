#include "pomdp_topo/pomdp_localizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pomdp_topo {

namespace {

bool fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

PomdpLocalizer::PomdpLocalizer(const PomdpParams& params) : params_(params), graph_(params), model_(params) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("PomdpLocalizer: " + why);
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

// ---------------------------------------------------------------------------------------------
// Map -> states

void PomdpLocalizer::setMap(const TopologicalMap& map) {
  // Old belief, carried over by key below.
  const std::vector<State> old_states = graph_.states();
  std::vector<double> old_belief;
  old_belief.swap(belief_);

  map_revision_ = map.revision();
  for (auto& t : travel_cache_) t.valid = false;
  graph_.build(map);
  applyOpenWays();
  model_.build(graph_);

  // Buffers of the steps.
  const size_t n = graph_.size();
  belief_.assign(n, 0.0);
  scratch_.assign(n, 0.0);
  log_likelihood_.assign(n, 0.0);
  for (auto& t : travel_cache_) t.next.assign(3 * n, 0);  // predict() never allocates

  carryBelief(old_states, old_belief);
  lost_ = false;
  low_likelihood_steps_ = 0;
}

// The old belief re-projected onto the new states by key (edge, offset, direction / node,
// heading); uniform when none of it lands.
void PomdpLocalizer::carryBelief(const std::vector<State>& old_states, const std::vector<double>& old_belief) {
  double carried = 0.0;
  for (size_t i = 0; i < old_states.size(); ++i) {
    const double p = old_belief[i];
    if (!(p > 0.0)) continue;
    const State& s = old_states[i];
    const int index = s.kind == State::Edge ? graph_.edgeStateIndex(s.id, s.offset, s.forward)
                                            : graph_.nodeStateIndex(s.id, graph_.binHeading(int(s.cell)));
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

// ---------------------------------------------------------------------------------------------
// Transition T(s, a, s') (eq. 2)

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
  slot->next.resize(3 * graph_.size());
  for (size_t s = 0; s < graph_.size(); ++s) {
    double cell = params_.resolution;
    if (int32_t(s) < graph_.nodeBase()) {
      const double c = graph_.dirEdges()[graph_.stateDirEdge(s)].cell;
      if (c > 0.0) cell = c;
    }
    slot->next[3 * s + 0] = graph_.travelFrom(s, distance - cell);
    slot->next[3 * s + 1] = graph_.travelFrom(s, distance);
    slot->next[3 * s + 2] = graph_.travelFrom(s, distance + cell);
  }
  slot->distance = distance;
  slot->valid = true;
  slot->last_use = travel_uses_;
  return *slot;
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
  if (blocked_factor_.size() != graph_.size()) blocked_factor_.assign(graph_.size(), 0.0);
  std::fill(blocked_factor_.begin(), blocked_factor_.end(), params_.blocked_travel_probability);
  for (const auto& way : open_ways_) {
    const int32_t node = graph_.nodeIndex(way.first);
    if (node >= 0) blocked_factor_[graph_.nodeState(node, way.second)] = 1.0;
  }
}

bool PomdpLocalizer::predict(const Action& action, std::string* error) {
  if (action.kind == Action::Travel) {
    if (!finite(action.distance)) return fail(error, "travel distance is not finite");
    if (graph_.states().empty() || action.distance == 0.0) return true;
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
    if (graph_.states().empty()) return true;
    const int k = ((action.turn_bins % graph_.bins()) + graph_.bins()) % graph_.bins();
    if (k == 0) return true;
    std::fill(scratch_.begin(), scratch_.end(), 0.0);
    double at_nodes = 0.0;
    for (size_t s = 0; s < belief_.size(); ++s) {
      bool mid_edge = false;
      const int32_t t = graph_.turnFrom(s, k, &mid_edge);
      scratch_[t] += mid_edge ? params_.turn_mid_edge_probability * belief_[s] : belief_[s];
      if (!mid_edge || 2 * k == graph_.bins()) at_nodes += belief_[s];
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
// Observation (eq. 2)

bool PomdpLocalizer::update(const Observation& o, std::string* error) {
  if (!ObservationModel::check(o, error)) return false;
  if (graph_.states().empty()) return true;
  lost_ = false;
  model_.logLikelihoods(graph_, o, &log_likelihood_);  // log OS(o, s)
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
  if (!(last_log_likelihood_ - model_.logAllFalse() >= log_lost)) {
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
  if (!ObservationModel::check(observation, error)) return false;  // a refused step changes nothing
  if (!predict(action, error)) return false;
  return update(observation, error);
}

// ---------------------------------------------------------------------------------------------
// Belief

void PomdpLocalizer::setUniform() {
  if (graph_.states().empty()) return;
  std::fill(belief_.begin(), belief_.end(), 1.0 / double(graph_.size()));
  low_likelihood_steps_ = 0;
}

bool PomdpLocalizer::setState(size_t index) {
  if (index >= graph_.size()) return false;
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
  return !graph_.states().empty() && !lost_ && entropy() < params_.entropy_max;
}

int PomdpLocalizer::mostLikely() const {
  if (belief_.empty()) return -1;
  return int(std::max_element(belief_.begin(), belief_.end()) - belief_.begin());
}

double PomdpLocalizer::probabilityNearNode(uint32_t node, double radius) const {
  const int32_t n = graph_.nodeIndex(node);
  if (n < 0) return 0.0;
  double p = 0.0;
  for (int b = 0; b < graph_.bins(); ++b) p += belief_[graph_.nodeState(n, b)];
  const std::vector<GraphStates::DirEdge>& dir_edges = graph_.dirEdges();
  for (size_t de = 0; de < dir_edges.size(); de += 2) {
    const GraphStates::DirEdge& d = dir_edges[de];  // forward: start = source
    if (d.start != n && d.end != n) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const GraphStates::DirEdge& dd = dir_edges[de + dir];
      for (int32_t i = 0; i < dd.cells; ++i) {
        const double x = (i + 0.5) * dd.cell;  // from the source
        if ((d.start == n && x <= radius) || (d.end == n && d.length - x <= radius)) p += belief_[dd.base + i];
      }
    }
  }
  return p;
}

double PomdpLocalizer::probabilityWhere(const std::function<bool(const State&)>& predicate) const {
  double p = 0.0;
  for (size_t s = 0; s < graph_.size(); ++s) {
    if (predicate(graph_.state(s))) p += belief_[s];
  }
  return p;
}

}  // namespace pomdp_topo
