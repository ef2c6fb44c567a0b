#include "pomdp_topo/observation_model.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {

constexpr double kPlmapMin = 0.01, kPlmapMax = 0.99;

bool fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

void ObservationModel::addEdgeLandmarks(const GraphStates& graph, int32_t de, double a0) {
  const bool fwd = (de & 1) == 0;
  const double length = graph.dirEdges()[de].length;
  const std::vector<EdgeLandmark>& landmarks = graph.edgeLandmarks(de);
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

void ObservationModel::addNodeOpenings(const GraphStates& graph, int32_t node, double along, double heading) {
  if (std::find(visited_nodes_.begin(), visited_nodes_.end(), node) != visited_nodes_.end()) return;
  visited_nodes_.push_back(node);
  const double p = std::clamp(params_.opening_p_lmap, kPlmapMin, kPlmapMax);
  for (size_t index = 0; index < graph.nodeOpenings(node).size(); ++index) {
    const NodeOpening& o = graph.nodeOpenings(node)[index];
    const double rel = normalizeAngle(o.bearing - heading);
    const double a = along + o.offset * std::cos(rel);
    const double l = o.offset * std::sin(rel);
    if (std::abs(l) > params_.window_lateral || !finite(a) || !finite(l)) continue;
    expected_.push_back({float(a), float(l), float(rel), float(std::log(p) - std::log1p(-p)), float(p),
                         LandmarkType::Opening, (2ull << 62) | (uint64_t(node) << 24) | uint64_t(index)});
  }
}

// Along the travel heading from the start of `de` (at along a0), straight through nodes.
void ObservationModel::walkForward(const GraphStates& graph, int32_t de, double a0, double heading) {
  for (int hop = 0; de >= 0 && hop < GraphStates::kMaxWalkHops; ++hop) {
    const uint32_t edge = uint32_t(de >> 1);
    if (std::find(visited_edges_.begin(), visited_edges_.end(), edge) != visited_edges_.end()) return;
    visited_edges_.push_back(edge);
    addEdgeLandmarks(graph, de, a0);
    const double a_end = a0 + graph.dirEdges()[de].length;
    if (a_end > params_.window_ahead) return;
    addNodeOpenings(graph, graph.dirEdges()[de].end, a_end, heading);
    a0 = a_end;
    if (graph.dirEdges()[de].next < 0 && !graph.nodeClosed(graph.dirEdges()[de].end)) cur_unknown_ahead_ = float(a_end);
    de = graph.dirEdges()[de].next;
  }
}

// Against the travel heading: `motion` leaves the node at along a_end backwards; the robot's
// direction on that edge is motion ^ 1.
void ObservationModel::walkBackward(const GraphStates& graph, int32_t motion, double a_end, double heading) {
  for (int hop = 0; motion >= 0 && hop < GraphStates::kMaxWalkHops; ++hop) {
    const uint32_t edge = uint32_t(motion >> 1);
    if (std::find(visited_edges_.begin(), visited_edges_.end(), edge) != visited_edges_.end()) return;
    visited_edges_.push_back(edge);
    const double a0 = a_end - graph.dirEdges()[motion].length;
    addEdgeLandmarks(graph, motion ^ 1, a0);
    if (a0 < -params_.window_behind) return;
    addNodeOpenings(graph, graph.dirEdges()[motion].end, a0, heading);
    a_end = a0;
    if (graph.dirEdges()[motion].next < 0 && !graph.nodeClosed(graph.dirEdges()[motion].end)) cur_unknown_behind_ = float(a0);
    motion = graph.dirEdges()[motion].next;
  }
}

void ObservationModel::build(const GraphStates& graph) {
  expectStateLandmarks(graph);
  expectEdgeLandmarks(graph);
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
void ObservationModel::expectStateLandmarks(const GraphStates& graph) {
  const std::vector<GraphStates::State>& states = graph.states();
  expected_.clear();
  expected_begin_.assign(states.size() + 1, 0);
  expected_base_.assign(states.size(), 0.0f);
  expected_split_.assign(states.size(), 0);
  unknown_ahead_.assign(states.size(), std::numeric_limits<float>::infinity());
  unknown_behind_.assign(states.size(), -std::numeric_limits<float>::infinity());
  max_expected_ = 0;
  for (size_t s = 0; s < states.size(); ++s) {
    expected_begin_[s] = uint32_t(expected_.size());
    visited_edges_.clear();
    visited_nodes_.clear();
    cur_unknown_ahead_ = std::numeric_limits<float>::infinity();
    cur_unknown_behind_ = -std::numeric_limits<float>::infinity();
    const double h = states[s].heading;
    if (states[s].kind == GraphStates::State::Edge) {
      const int32_t de = graph.stateDirEdge(s);
      const GraphStates::DirEdge& d = graph.dirEdges()[de];
      const int32_t k = d.cells - 1 - int32_t(states[s].cell);
      const double pos = (de & 1) == 0 ? states[s].offset : (k + 0.5) * d.cell;  // along the travel
      visited_edges_.push_back(uint32_t(de >> 1));
      addEdgeLandmarks(graph, de, -pos);
      if (d.length - pos <= params_.window_ahead) {
        addNodeOpenings(graph, d.end, d.length - pos, h);
        if (d.next < 0 && !graph.nodeClosed(d.end)) cur_unknown_ahead_ = float(d.length - pos);
        walkForward(graph, d.next, d.length - pos, h);
      }
      if (pos <= params_.window_behind) {
        addNodeOpenings(graph, d.start, -pos, h);
        if (graph.dirEdges()[de ^ 1].next < 0 && !graph.nodeClosed(d.start)) cur_unknown_behind_ = float(-pos);
        walkBackward(graph, graph.dirEdges()[de ^ 1].next, -pos, h);
      }
    } else {
      const int32_t n = graph.nodeIndex(states[s].id);
      const int b = int(states[s].cell);
      addNodeOpenings(graph, n, 0.0, h);
      if (graph.nodeExit(n, b, false) < 0 && graph.mapEndsBeyond(n, b)) cur_unknown_ahead_ = 0.0f;
      if (graph.nodeExit(n, b, true) < 0 && graph.mapEndsBeyond(n, (b + graph.bins() / 2) % graph.bins()))
        cur_unknown_behind_ = 0.0f;
      walkForward(graph, graph.nodeExit(n, b, false), 0.0, h);
      walkBackward(graph, graph.nodeExit(n, b, true), 0.0, h);
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
  expected_begin_[states.size()] = uint32_t(expected_.size());
}

void ObservationModel::expectEdgeLandmarks(const GraphStates& graph) {
  // Per directed edge: the union of its cells' expected landmarks in travel coordinates t (along =
  // t - cell position), each with the range of cells [kmin, kmax] (travel order) that expect it. A
  // landmark expected by non-consecutive cells (tiny loops) makes the edge "irregular": its cells
  // are then evaluated one by one.
  de_expected_begin_.assign(graph.dirEdges().size() + 1, 0);
  de_regular_.assign(graph.dirEdges().size(), 1);
  edge_expected_.clear();
  size_t max_members = 0, max_union = 0, max_cells = 0;
  for (size_t de = 0; de < graph.dirEdges().size(); ++de) {
    const GraphStates::DirEdge& d = graph.dirEdges()[de];
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
  de_expected_begin_[graph.dirEdges().size()] = uint32_t(edge_expected_.size());
  x_gain_.resize(edge_expected_.size());
  for (size_t x = 0; x < edge_expected_.size(); ++x) x_gain_[x] = edge_expected_[x].gain;
  max_edge_members_ = max_members;
  cell_head_.assign(max_cells, -1);
  used_expected_.assign(std::max(max_expected_, max_union), 0);
}

std::vector<ExpectedLandmark> ObservationModel::expectedLandmarks(size_t index) const {
  std::vector<ExpectedLandmark> out;
  if (index + 1 >= expected_begin_.size()) return out;
  for (size_t i = expected_begin_[index]; i < expected_begin_[index + 1]; ++i) {
    const LandmarkType type = i < expected_split_[index] ? LandmarkType::Corner : LandmarkType::Opening;
    const double p = 1.0 / (1.0 + std::exp(-double(ex_gain_[i])));
    out.push_back({type, ex_along_[i], ex_lateral_[i], std::atan2(double(ex_sin_[i]), double(ex_cos_[i])), p});
  }
  return out;
}

// The greedy one-to-one association of OS(o, s): candidates by increasing d^2, each expected and
// each observed landmark used once. A match replaces log(1 - p_lmap) + log(false) by
// log(p_lmap * confidence) - d^2 / 2. `gains` (log p_lmap - log(1 - p_lmap)) is indexed by Candidate::e.
double ObservationModel::greedyMatch(uint32_t count, const float* gains) {
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
double ObservationModel::unknownCorrection(size_t state) const {
  if (obs_along_sorted_.empty()) return 0.0;
  const float margin = float(params_.match_sigma_along);
  const auto first = obs_along_sorted_.begin(), last = obs_along_sorted_.end();
  const size_t ahead = size_t(last - std::upper_bound(first, last, unknown_ahead_[state] + margin));
  const size_t behind = size_t(std::lower_bound(first, last, unknown_behind_[state] - margin) - first);
  return double(ahead + behind) * unknown_gain_;
}

double ObservationModel::observationLogLikelihood(size_t state) {
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
void ObservationModel::edgeLogLikelihoods(const GraphStates& graph, int32_t de, double heading_term, double* out) {
  const GraphStates::DirEdge& d = graph.dirEdges()[de];
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
    for (int32_t i = 0; i < d.cells; ++i) out[d.base + i] = observationLogLikelihood(d.base + i) + heading_term;
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
    out[s] = double(expected_base_[s]) + obs_log_false_ + greedyMatch(count, gains) + heading_term +
                         unknownCorrection(s);
  }
}

bool ObservationModel::check(const Observation& o, std::string* error) {
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

void ObservationModel::prepareObservation(const Observation& o) {
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

double ObservationModel::headingTerm(double h) const {
  if (!heading_valid_) return 0.0;
  const double d = normalizeAngle(heading_ - h);
  return std::log(params_.heading_floor + (1.0 - params_.heading_floor) * std::exp(-d * d / (2.0 * heading_variance_)));
}

double ObservationModel::stateLogLikelihood(const GraphStates& graph, size_t index, const Observation& o) {
  if (index >= graph.size() || index + 1 >= expected_begin_.size() || !check(o, nullptr)) return std::nan("");
  prepareObservation(o);
  return observationLogLikelihood(index) + headingTerm(graph.state(index).heading);
}

void ObservationModel::logLikelihoods(const GraphStates& graph, const Observation& o, std::vector<double>* out) {
  prepareObservation(o);
  // With the heading term per directed edge / node state.
  const std::vector<GraphStates::DirEdge>& dir_edges = graph.dirEdges();
  double* ll = out->data();
  for (size_t de = 0; de < dir_edges.size(); ++de) {
    const GraphStates::DirEdge& d = dir_edges[de];
    const double ht = headingTerm(d.heading);
    if (de_regular_[de]) {
      edgeLogLikelihoods(graph, int32_t(de), ht, ll);
    } else {
      for (int32_t i = 0; i < d.cells; ++i) ll[d.base + i] = observationLogLikelihood(d.base + i) + ht;
    }
  }
  for (size_t s = size_t(graph.nodeBase()); s < graph.size(); ++s) {
    ll[s] = observationLogLikelihood(s) + headingTerm(graph.state(s).heading);
  }
}

}  // namespace pomdp_topo
