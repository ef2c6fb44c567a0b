#include "pomdp_topo/loop_hypotheses.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

double fingerprintSimilarity(const Fingerprint& a, const Fingerprint& b, double tolerance) {
  if (a.entries.empty() && b.entries.empty()) return 1.0;
  if (a.entries.empty() || b.entries.empty()) return 0.0;
  std::vector<bool> used(b.entries.size(), false);
  size_t matched = 0;
  for (const auto& ea : a.entries) {
    for (size_t j = 0; j < b.entries.size(); ++j) {
      if (used[j] || b.entries[j].kind != ea.kind) continue;
      if (std::abs(normalizeAngle(b.entries[j].bearing - ea.bearing)) <= tolerance) {
        used[j] = true;
        ++matched;
        break;
      }
    }
  }
  return 2.0 * double(matched) / double(a.entries.size() + b.entries.size());
}

bool LoopHypotheses::begin(const TopologicalMap& map, const MapBuilderParams& params,
                           const laser_features::HeadingBins& bins, uint32_t new_node, uint32_t previous_node,
                           double arrival_heading, int go_bin, double gate, double travel0) {
  const TopoNode* fresh = map.node(new_node);
  const double h = arrival_heading;
  // The way it goes on: straight past a door; the branch it turned to at a junction. The old node
  // must have that way too, and the path beyond it is what the hypotheses are verified against
  // (a corner has no way straight on: verifying along the arrival heading never saw a ring close
  // at a corner, only at a door, with a duplicate of every corner in between).
  const double go = bins.heading(go_bin);
  const double sigma = 0.5 * gate;
  candidates_.clear();
  // The nodes of the straight stretch just built are never candidates: coming back to a place
  // takes a turn.
  std::vector<uint32_t> stretch = {previous_node};
  for (uint32_t at = previous_node; stretch.size() < 256;) {
    EdgeExit back;
    if (!map.exitWithHeading(at, normalizeAngle(h + kPi), 0.25 * kPi, &back)) break;
    at = back.other;
    if (std::find(stretch.begin(), stretch.end(), at) != stretch.end()) break;
    stretch.push_back(at);
  }
  for (const auto& entry : map.nodes()) {
    const TopoNode& m = entry.second;
    if (m.id == new_node || m.type != fresh->type) continue;
    if (std::find(stretch.begin(), stretch.end(), m.id) != stretch.end()) continue;
    const double d = std::hypot(m.pose.x - fresh->pose.x, m.pose.y - fresh->pose.y);
    if (d > gate) continue;
    // Every opening of the new node must exist at the old one: as an opening, or as an edge. A stem
    // coming to a known hallway's T sees the hallway both ways as openings, which the T, made along
    // the hallway, has as its edges (large_floor: no check started there, and the door just past
    // the T was entered as a new room before the loop closed at the next one).
    bool openings_match = true, seen_from_another_way = false;
    for (const NodeOpening& o : fresh->openings) {
      const bool opening = map.hasOpeningToward(m.id, o.bearing);
      EdgeExit way;
      const bool edge = !opening && map.exitWithHeading(m.id, o.bearing, bins.sameWayTolerance(), &way);
      openings_match = openings_match && (opening || edge);
      seen_from_another_way = seen_from_another_way || edge;
    }
    if (!openings_match) continue;
    // The fingerprint is the view on arrival: from the stem a T shows other openings than from its
    // hallway, so it is compared only for a node come to the way the old one was.
    if (!seen_from_another_way && !fresh->fingerprint.entries.empty() && !m.fingerprint.entries.empty() &&
        fingerprintSimilarity(fresh->fingerprint, m.fingerprint, params.fingerprint_tolerance) <
            params.loop_fingerprint_min) {
      continue;
    }
    EdgeExit exit;
    if (!map.wayOn(m.id, go, 0.25 * kPi, &exit)) continue;  // nothing to verify against
    candidates_.push_back(
        candidate(map, params, m.id, go, std::log(1.0 - params.loop_new_place_prior) - d * d / (2.0 * sigma * sigma)));
  }
  if (candidates_.empty()) return false;
  new_node_ = new_node;
  bin_ = go_bin;
  new_score_ = std::log(params.loop_new_place_prior);
  travel0_ = travel0;
  return true;
}

LoopHypotheses::Candidate LoopHypotheses::candidate(const TopologicalMap& map, const MapBuilderParams& params,
                                                    uint32_t m, double go, double prior) const {
  Candidate c;
  c.node = m;
  c.prior = prior;
  c.score = c.prior;
  // The side openings of a node `base` metres along the path, as landmarks the robot will pass.
  auto expectOpenings = [&](uint32_t id, double base) {
    for (const NodeOpening& o : map.node(id)->openings) {
      const double s = std::sin(normalizeAngle(o.bearing - go));
      if (std::abs(s) < 0.7) continue;  // along the hallway: not a side opening
      EdgeLandmark r;
      r.type = LandmarkType::Opening;
      r.distance = base;
      r.lateral = s > 0 ? 1.0 : -1.0;
      r.p_lmap = 0.9;
      c.expected.push_back(r);
    }
  };
  // The old node's own openings first: the new node's door is passed (pass_lag behind the robot)
  // after the node was made, during the check; unexpected, it counted against every door loop
  // (small_loop's closed at log odds 0.99, by a hair at the next corner's turn).
  expectOpenings(m, 0.0);
  // The known path beyond the old node, straight on.
  double base = 0.0;
  uint32_t at = m;
  for (int hops = 0; hops < 64 && base < params.loop_verify_distance + 2.0; ++hops) {
    EdgeExit x;
    if (!map.wayOn(at, go, 0.25 * kPi, &x)) break;
    const TopoEdge* e = map.edge(x.edge);
    for (const EdgeLandmark& l : e->landmarks) {
      EdgeLandmark r = l;
      r.distance = base + (x.forward ? l.distance : e->length - l.distance);
      if (!x.forward) {
        r.lateral = -l.lateral;
        r.orientation = normalizeAngle(l.orientation + kPi);
      }
      c.expected.push_back(r);
    }
    base += e->length;
    at = x.other;
    expectOpenings(at, base);
  }
  c.path_end = base;
  c.used.assign(c.expected.size(), false);
  return c;
}

bool LoopHypotheses::observe(const TopologicalMap& map, const MapBuilderParams& params,
                             const laser_features::HeadingBins& bins, double pass_lag,
                             const std::vector<PassedLandmark>& passed, const std::vector<Action>& actions,
                             double travel) {
  const double u = travel - travel0_;
  scorePassed(params, passed);
  const bool turned = scoreTurns(map, params, bins, actions, u);
  scoreMissed(params, pass_lag, u);
  return turned;
}

void LoopHypotheses::scorePassed(const MapBuilderParams& params, const std::vector<PassedLandmark>& passed) {
  const double p_new = params.loop_new_landmark_probability;
  const double p_false = params.loop_false_landmark_probability;
  for (const PassedLandmark& p : passed) {
    if (p.heading_bin != bin_) continue;
    if (p.landmark.type == LandmarkType::Corner && p.landmark.confidence < params.corner_min_confidence) continue;
    const double pos = (p.travel - travel0_) + p.landmark.along;
    new_score_ += std::log(p_new);
    for (auto& c : candidates_) {
      bool matched = false;
      for (size_t i = 0; i < c.expected.size(); ++i) {
        const EdgeLandmark& l = c.expected[i];
        if (c.used[i] || l.type != p.landmark.type || sideOf(l.lateral) != sideOf(p.landmark.lateral)) continue;
        if (std::abs(l.distance - pos) > params.match_distance) continue;
        // The new node's own door (distance 0) is no evidence either way: both hypotheses have it
        // (the candidate was chosen for its openings). Scored like the new place's, it only keeps
        // it from counting against the old one.
        c.score += l.distance <= 0.0 ? std::log(p_new) : std::log(std::max(1e-3, l.p_lmap));
        c.used[i] = true;
        matched = true;
        ++c.matched;
        break;
      }
      if (!matched && p.landmark.type == LandmarkType::Opening) ++c.unexpected;
      // An unexpected opening speaks against the old place; an unexpected corner does not (corners
      // seen at low confidence on the first pass were never added to the map).
      if (!matched) c.score += std::log(p.landmark.type == LandmarkType::Opening ? p_false : p_new);
    }
  }
}

bool LoopHypotheses::scoreTurns(const TopologicalMap& map, const MapBuilderParams& params,
                                const laser_features::HeadingBins& bins, const std::vector<Action>& actions,
                                double u) {
  bool turned = false;
  for (const Action& a : actions) {
    if (a.kind != Action::Turn) continue;
    turned = true;
    new_score_ += std::log(0.5);
    const double new_heading = bins.heading(bins.wrap(bin_ + a.turn_bins));
    for (auto& c : candidates_) {
      // A turn is expected only at a node of the old path with an edge (or opening) that way.
      bool possible = 2 * std::abs(a.turn_bins) == bins.bins;  // U-turns happen anywhere
      double base = 0.0;
      uint32_t at = c.node;
      for (int hops = 0; hops < 64 && !possible; ++hops) {
        if (std::abs(u - base) <= params.node_radius) {
          EdgeExit x;
          possible = map.wayOn(at, new_heading, 0.25 * kPi, &x) || map.hasOpeningToward(at, new_heading);
        }
        EdgeExit x;
        if (!map.wayOn(at, bins.heading(bin_), 0.25 * kPi, &x)) break;
        base += map.edge(x.edge)->length;
        at = x.other;
        if (base > u + params.node_radius) break;
      }
      c.score += std::log(possible ? 0.9 : 0.02);
      ++(possible ? c.turns_possible : c.turns_impossible);
    }
  }
  return turned;
}

void LoopHypotheses::scoreMissed(const MapBuilderParams& params, double pass_lag, double u) {
  // Expected landmarks left behind unseen (eq. 5's 1 - p_lmap), and travel past the known path.
  for (auto& c : candidates_) {
    for (size_t i = 0; i < c.expected.size(); ++i) {
      if (c.used[i] || c.expected[i].distance > u - params.match_distance - pass_lag) continue;
      // The old node's own openings (distance 0) may have been passed before the check began.
      if (c.expected[i].distance <= 0.0) continue;
      c.score += std::log(std::max(1e-3, 1.0 - c.expected[i].p_lmap));
      c.used[i] = true;
      ++c.missed;
    }
    if (u > c.path_end + params.node_radius) c.score = -std::numeric_limits<double>::infinity();
  }
}

double LoopHypotheses::logOdds() const {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& c : candidates_) best = std::max(best, c.score);
  return best - new_score_;
}

std::vector<uint32_t> LoopHypotheses::candidates() const {
  std::vector<uint32_t> nodes;
  for (const auto& c : candidates_) nodes.push_back(c.node);
  return nodes;
}

uint32_t LoopHypotheses::bestNode() const {
  const Candidate* best = &candidates_.front();
  for (const auto& c : candidates_) {
    if (c.score > best->score) best = &c;
  }
  return best->node;
}

std::string LoopHypotheses::evidence() const {
  const Candidate* best = nullptr;
  for (const auto& c : candidates_) {
    if (best == nullptr || c.score > best->score) best = &c;
  }
  if (best == nullptr) return "no candidate";
  char text[200];
  std::snprintf(text, sizeof(text),
                "best node %u: position prior %.2f, %d landmarks matched, %d unexpected openings, %d expected "
                "missed, turns %d possible / %d not; new place %.2f",
                best->node, best->prior, best->matched, best->unexpected, best->missed, best->turns_possible,
                best->turns_impossible, new_score_);
  return text;
}

}  // namespace pomdp_topo
