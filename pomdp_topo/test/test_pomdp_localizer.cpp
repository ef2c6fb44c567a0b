// PomdpLocalizer: the transition model on hand-built graphs (hallway, T junction, L turn, ring),
// the observation model's expected landmarks, global localization, look-alike places, kidnapping,
// lost detection, bad input, re-projection on map changes and the steady-state allocation count.
#include "pomdp_topo/pomdp_localizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

// The program-wide counting operator new of this binary (include in exactly one file).
#include "laser_features/testing/counting_allocator.h"

namespace pomdp_topo {
namespace {

using laser_features::kPi;
using laser_features::normalizeAngle;
using State = PomdpLocalizer::State;

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

::testing::AssertionResult isDistribution(const PomdpLocalizer& loc) {
  for (double p : loc.belief())
    if (!std::isfinite(p) || p < 0.0) return ::testing::AssertionFailure() << "bad entry " << p;
  if (loc.size() > 0 && std::abs(sum(loc.belief()) - 1.0) > 1e-9)
    return ::testing::AssertionFailure() << "sum " << sum(loc.belief());
  return ::testing::AssertionSuccess();
}

// ---------------------------------------------------------------------------------------------
// A world of straight sides (a hallway, or a ring of sides joined by 90-degree corners) with
// features at known distances along the sides, and the topological map built from it.

struct Feature {
  double dist;         // m along the side
  double lateral;      // m, + left of the side's direction
  double orientation;  // rad, relative to the side's direction
  LandmarkType type;
  bool door;           // a door node (opening at a node) instead of an edge landmark
};

Feature door(double dist, bool left) { return {dist, left ? 1.0 : -1.0, left ? kPi / 2 : -kPi / 2, LandmarkType::Opening, true}; }
Feature corner(double dist, double lateral, double orientation) {
  return {dist, lateral, orientation, LandmarkType::Corner, false};
}

struct Side {
  double heading;
  double length;
  std::vector<Feature> features;  // sorted by dist, doors strictly inside the side
};

struct World {
  std::vector<Side> sides;
  bool ring = false;
  TopologicalMap map;
  std::vector<Eigen::Vector2d> start;  // start point of each side
  std::vector<uint32_t> corners;       // corner node at the start of each side (+ the end of a hallway)
  std::vector<uint32_t> doors;         // door nodes in order of creation
};

World buildWorld(std::vector<Side> sides, bool ring) {
  World w;
  w.sides = std::move(sides);
  w.ring = ring;
  Eigen::Vector2d p(0.0, 0.0);
  const size_t n = w.sides.size();
  for (size_t k = 0; k <= n; ++k) {
    if (k < n) w.start.push_back(p);
    if (k == n && ring) break;
    TopoNode node;
    node.type = ring ? NodeType::Junction : NodeType::HallwayEnd;
    node.pose = {p.x(), p.y(), 0.0};
    w.corners.push_back(w.map.addNode(node));
    if (k < n) p += w.sides[k].length * laser_features::unitVector(w.sides[k].heading);
  }
  for (size_t k = 0; k < n; ++k) {
    const Side& side = w.sides[k];
    const Eigen::Vector2d dir = laser_features::unitVector(side.heading);
    uint32_t from = w.corners[k];
    double from_dist = 0.0;
    std::vector<EdgeLandmark> pending;
    auto close = [&](uint32_t to, double to_dist) {
      w.map.addEdge(from, to, side.heading, to_dist - from_dist, pending);
      pending.clear();
      from = to;
      from_dist = to_dist;
    };
    for (const Feature& f : side.features) {
      if (f.door) {
        TopoNode node;
        node.type = NodeType::Door;
        const Eigen::Vector2d q = w.start[k] + f.dist * dir;
        node.pose = {q.x(), q.y(), 0.0};
        node.openings.push_back({normalizeAngle(side.heading + f.orientation), std::abs(f.lateral), 0.9, false});
        const uint32_t id = w.map.addNode(node);
        w.doors.push_back(id);
        close(id, f.dist);
      } else {
        EdgeLandmark lm;
        lm.type = f.type;
        lm.distance = f.dist - from_dist;
        lm.lateral = f.lateral;
        lm.orientation = f.orientation;
        lm.p_lmap = 0.8;
        pending.push_back(lm);
      }
    }
    close(ring ? w.corners[(k + 1) % n] : w.corners[k + 1], side.length);
  }
  return w;
}

/// A straight 20 m hallway heading east: door nodes at 5 m (left) and 12 m (right), a corner
/// landmark at 7.5 m; edges A->D1 (5 m), D1->D2 (7 m), D2->B (8 m).
World hallway() {
  return buildWorld({{0.0, 20.0, {door(5.0, true), corner(7.5, -1.2, -2.3), door(12.0, false)}}}, false);
}

/// A 16 x 10 m rectangle driven counter-clockwise with a distinct pattern of doors and corners.
World ring() {
  return buildWorld({{0.0, 16.0, {door(4.0, true), corner(7.0, 1.2, 2.0), door(11.0, false)}},
                     {kPi / 2, 10.0, {door(5.0, true)}},
                     {kPi, 16.0, {door(3.0, false), door(6.0, false), door(12.0, true)}},
                     {-kPi / 2, 10.0, {corner(4.0, -1.2, -2.0), door(7.0, true)}}},
                    true);
}

uint32_t edgeBetween(const TopologicalMap& map, uint32_t a, uint32_t b) {
  for (const auto& e : map.edges())
    if (e.second.source == a && e.second.target == b) return e.first;
  ADD_FAILURE() << "no edge " << a << " -> " << b;
  return 0;
}

// Where a state is in the world (from the nodes' poses) and its heading.
Eigen::Vector2d statePosition(const TopologicalMap& map, const State& s) {
  if (s.kind == State::Node) return map.node(s.id)->pose.translation();
  const TopoEdge* e = map.edge(s.id);
  return map.node(e->source)->pose.translation() + s.offset * laser_features::unitVector(e->heading);
}

// The true robot: on side `side` at `x` m from its start, facing along it (forward) or against it.
struct Truth {
  int side = 0;
  double x = 0.0;
  bool forward = true;
};

Eigen::Vector2d truthPosition(const World& w, const Truth& t) {
  return w.start[t.side] + t.x * laser_features::unitVector(w.sides[t.side].heading);
}
double truthHeading(const World& w, const Truth& t) {
  return normalizeAngle(w.sides[t.side].heading + (t.forward ? 0.0 : kPi));
}

double massNearTruth(const PomdpLocalizer& loc, const World& w, const Truth& t, double radius) {
  const Eigen::Vector2d p = truthPosition(w, t);
  const double h = truthHeading(w, t);
  return loc.probabilityWhere([&](const State& s) {
    return (statePosition(w.map, s) - p).norm() <= radius && std::abs(normalizeAngle(s.heading - h)) < 0.5;
  });
}

bool mostLikelyNearTruth(const PomdpLocalizer& loc, const World& w, const Truth& t, double radius) {
  const int i = loc.mostLikely();
  if (i < 0) return false;
  const State& s = loc.state(size_t(i));
  return (statePosition(w.map, s) - truthPosition(w, t)).norm() <= radius &&
         std::abs(normalizeAngle(s.heading - truthHeading(w, t))) < 0.5;
}

// The observation at the truth, computed from the world (not from the localizer): the features of
// the current side within the window, with noise, misses and the odd spurious landmark.
struct Sensor {
  std::mt19937 rng{7};
  double sigma = 0.1;          // m
  double sigma_angle = 0.05;   // rad
  double miss = 0.2;           // probability of missing a landmark
  double spurious = 0.05;      // probability of a spurious landmark per observation
  bool heading_valid = false;

  Observation observe(const World& w, const Truth& t) {
    std::normal_distribution<double> noise(0.0, sigma), angle_noise(0.0, sigma_angle);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Observation o;
    for (const Feature& f : w.sides[t.side].features) {
      const double along = t.forward ? f.dist - t.x : t.x - f.dist;
      const double lateral = t.forward ? f.lateral : -f.lateral;
      if (along < -3.0 || along > 3.0 || std::abs(lateral) > 3.0) continue;
      if (u(rng) < miss) continue;
      ObservedLandmark l;
      l.type = f.type;
      l.along = along + noise(rng);
      l.lateral = lateral + noise(rng);
      l.orientation = normalizeAngle((t.forward ? f.orientation : f.orientation + kPi) + angle_noise(rng));
      l.width = f.type == LandmarkType::Opening ? 0.9 : 0.0;
      l.confidence = 0.8;
      o.landmarks.push_back(l);
    }
    if (u(rng) < spurious) {
      ObservedLandmark l;
      l.type = LandmarkType::Corner;
      l.along = 4.0 * u(rng) - 2.0;
      l.lateral = u(rng) < 0.5 ? 1.2 : -1.2;
      l.orientation = 2.0 * kPi * u(rng) - kPi;
      l.confidence = 0.5;
      o.landmarks.push_back(l);
    }
    o.heading_valid = heading_valid;
    o.heading = normalizeAngle(truthHeading(w, t) + angle_noise(rng));
    o.heading_variance = sigma_angle * sigma_angle;
    return o;
  }
};

// Drives the truth 0.5 m forward (turning left at the corners of a ring) and runs the filter step.
void driveStep(const World& w, Truth* t, PomdpLocalizer* loc, Sensor* sensor) {
  Action a;
  const double length = w.sides[t->side].length;
  if (t->x >= length - 1e-9 && w.ring) {
    a.kind = Action::Turn;
    a.turn_bins = 1;  // counter-clockwise ring: left turns
    t->side = (t->side + 1) % int(w.sides.size());
    t->x = 0.0;
  } else {
    a.kind = Action::Travel;
    a.distance = std::min(0.5, length - t->x);
    t->x += a.distance;
  }
  std::string error;
  ASSERT_TRUE(loc->step(a, sensor->observe(w, *t), &error)) << error;
}

PomdpParams exactParams() {  // no spreading, no mixing: transitions are deterministic
  PomdpParams p;
  p.travel_spread = 0.0;
  p.uniform_mixing = 0.0;
  return p;
}

Action travel(double d) {
  Action a;
  a.kind = Action::Travel;
  a.distance = d;
  return a;
}
Action turn(int bins) {
  Action a;
  a.kind = Action::Turn;
  a.turn_bins = bins;
  return a;
}

const State& best(const PomdpLocalizer& loc) { return loc.state(size_t(loc.mostLikely())); }

// ---------------------------------------------------------------------------------------------
// States, uniform belief, entropy

TEST(PomdpLocalizer, StatesOfTheHallway) {
  World w = hallway();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  // 5 + 7 + 8 m at 0.5 m: 40 cells, both directions, plus 4 nodes x 4 bins.
  EXPECT_EQ(loc.size(), 2u * 40u + 16u);
  size_t nodes = 0;
  for (size_t i = 0; i < loc.size(); ++i) {
    const State& s = loc.state(i);
    if (s.kind == State::Node) {
      ++nodes;
      EXPECT_NEAR(normalizeAngle(s.heading - loc.binHeading(int(s.cell))), 0.0, 1e-12);
      continue;
    }
    const TopoEdge* e = w.map.edge(s.id);
    ASSERT_NE(e, nullptr);
    const int n = int(std::lround(e->length / 0.5));
    EXPECT_NEAR(s.offset, (s.cell + 0.5) * e->length / n, 1e-12);
    EXPECT_NEAR(normalizeAngle(s.heading - e->heading - (s.forward ? 0.0 : kPi)), 0.0, 1e-12);
  }
  EXPECT_EQ(nodes, 16u);
}

TEST(PomdpLocalizer, UniformEntropyIsLogN) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  ASSERT_GT(loc.size(), 100u);
  EXPECT_TRUE(isDistribution(loc));
  EXPECT_NEAR(loc.entropy(), std::log(double(loc.size())), 1e-9);
  EXPECT_FALSE(loc.confident());
  ASSERT_TRUE(loc.setState(3));
  EXPECT_NEAR(loc.entropy(), 0.0, 1e-12);
  EXPECT_TRUE(loc.confident());
  EXPECT_EQ(loc.mostLikely(), 3);
}

// The position gate's restriction: the mass outside is dropped and the rest renormalized; with
// nothing inside, uniform over the allowed states (false); a wrong size or nothing allowed: no change.
TEST(PomdpLocalizer, RestrictToKeepsTheAllowedStatesOnly) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  const size_t n = loc.size();
  std::vector<bool> allowed(n, false);
  allowed[1] = allowed[2] = allowed[5] = true;
  std::vector<double> b(n, 0.0);
  b[1] = 0.2;
  b[2] = 0.2;
  b[7] = 0.6;
  ASSERT_TRUE(loc.setBelief(b));
  EXPECT_TRUE(loc.restrictTo(allowed));
  EXPECT_NEAR(loc.belief()[1], 0.5, 1e-12);
  EXPECT_NEAR(loc.belief()[2], 0.5, 1e-12);
  EXPECT_EQ(loc.belief()[7], 0.0);
  EXPECT_TRUE(isDistribution(loc));
  ASSERT_TRUE(loc.setState(7));  // all outside
  EXPECT_FALSE(loc.restrictTo(allowed));
  for (size_t s : {1u, 2u, 5u}) EXPECT_NEAR(loc.belief()[s], 1.0 / 3.0, 1e-12);
  EXPECT_TRUE(isDistribution(loc));
  const std::vector<double> before = loc.belief();
  EXPECT_TRUE(loc.restrictTo(std::vector<bool>(n, false)));
  EXPECT_TRUE(loc.restrictTo(std::vector<bool>(n + 1, true)));
  EXPECT_EQ(loc.belief(), before);
}

TEST(PomdpLocalizer, HeadingBins) {
  PomdpParams p;
  p.axis_angle = 0.1;
  PomdpLocalizer loc(p);
  EXPECT_EQ(loc.headingBin(0.1), 0);
  EXPECT_EQ(loc.headingBin(0.1 + kPi / 2 + 0.3), 1);
  EXPECT_EQ(loc.headingBin(0.1 - kPi / 2), 3);
  EXPECT_EQ(loc.headingBin(0.1 + kPi), 2);
  EXPECT_EQ(loc.headingBin(0.1 - kPi + 1e-9), 2);
  EXPECT_NEAR(loc.binHeading(1), 0.1 + kPi / 2, 1e-12);
  PomdpParams bad;
  bad.resolution = 0.0;
  EXPECT_THROW(PomdpLocalizer{bad}, std::invalid_argument);
  bad = PomdpParams();
  bad.heading_floor = std::nan("");
  EXPECT_FALSE(PomdpLocalizer::validate(bad));
}

// ---------------------------------------------------------------------------------------------
// Transitions

TEST(PomdpTransition, TravelMovesByTheRightNumberOfCells) {
  World w = hallway();
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);  // D1 -> D2, 7 m, 14 cells
  PomdpLocalizer loc(exactParams());
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(e1, 1.3, true));
  EXPECT_EQ(best(loc).cell, 2u);
  ASSERT_TRUE(loc.predict(travel(1.5)));
  EXPECT_NEAR(loc.belief()[loc.mostLikely()], 1.0, 1e-12);
  EXPECT_EQ(best(loc).id, e1);
  EXPECT_EQ(best(loc).cell, 5u);
  EXPECT_TRUE(best(loc).forward);
  // Backing up keeps the heading.
  ASSERT_TRUE(loc.predict(travel(-1.0)));
  EXPECT_EQ(best(loc).cell, 3u);
  EXPECT_TRUE(best(loc).forward);
  // Travelling west on the same edge: the cell index (from the source) decreases.
  ASSERT_TRUE(loc.resetToEdge(e1, 5.25, false));
  ASSERT_TRUE(loc.predict(travel(2.0)));
  EXPECT_EQ(best(loc).cell, 6u);
  EXPECT_FALSE(best(loc).forward);
  // Travel(0) is the identity.
  const std::vector<double> before = loc.belief();
  ASSERT_TRUE(loc.predict(travel(0.0)));
  EXPECT_EQ(loc.belief(), before);
}

TEST(PomdpTransition, SpreadUnderAndOvershootConservesProbability) {
  World w = hallway();
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  PomdpParams p;
  p.uniform_mixing = 0.0;
  PomdpLocalizer loc(p);
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(e1, 1.25, true));  // cell 2
  ASSERT_TRUE(loc.predict(travel(1.0)));         // to cell 4, p = 0.15 each side
  EXPECT_TRUE(isDistribution(loc));
  const double spread = std::min(0.45, p.travel_spread * 1.0);
  EXPECT_NEAR(loc.belief()[loc.edgeStateIndex(e1, 1.75, true)], spread, 1e-12);
  EXPECT_NEAR(loc.belief()[loc.edgeStateIndex(e1, 2.25, true)], 1.0 - 2.0 * spread, 1e-12);
  EXPECT_NEAR(loc.belief()[loc.edgeStateIndex(e1, 2.75, true)], spread, 1e-12);
  // Long travel: the spread is capped, still three cells.
  ASSERT_TRUE(loc.resetToEdge(e1, 0.25, true));
  ASSERT_TRUE(loc.predict(travel(4.0)));
  EXPECT_NEAR(loc.belief()[loc.edgeStateIndex(e1, 4.25, true)], 1.0 - 2.0 * 0.45, 1e-12);
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpTransition, RandomActionsKeepADistribution) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> b(loc.size());
  for (int i = 0; i < 40; ++i) {
    Action a = u(rng) < 0.7 ? travel(4.0 * u(rng) - 1.0) : turn(int(7.0 * u(rng)) - 3);
    ASSERT_TRUE(loc.predict(a));
    ASSERT_TRUE(isDistribution(loc)) << "action " << i;
  }
}

TEST(PomdpTransition, PassesThroughANodeIntoTheContinuingEdge) {
  World w = hallway();
  const uint32_t e0 = edgeBetween(w.map, w.corners[0], w.doors[0]);  // A -> D1, 5 m
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  PomdpLocalizer loc(exactParams());
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(e0, 4.75, true));
  ASSERT_TRUE(loc.predict(travel(1.0)));  // 0.75 m past D1
  EXPECT_EQ(best(loc).id, e1);
  EXPECT_EQ(best(loc).cell, 1u);
  // Less than half a cell past the node: at the node, facing east.
  ASSERT_TRUE(loc.resetToEdge(e0, 4.75, true));
  ASSERT_TRUE(loc.predict(travel(0.3)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(w.doors[0], 0.0));
  // From the node into the exit along its heading bin.
  ASSERT_TRUE(loc.predict(travel(1.1)));
  EXPECT_EQ(best(loc).id, e1);
  EXPECT_EQ(best(loc).cell, 2u);
  // Westwards through D1: from 0.25 m on D1->D2 to 4.25 m on A->D1.
  ASSERT_TRUE(loc.resetToEdge(e1, 0.25, false));
  ASSERT_TRUE(loc.predict(travel(1.0)));
  EXPECT_EQ(best(loc).id, e0);
  EXPECT_FALSE(best(loc).forward);
  EXPECT_NEAR(best(loc).offset, 4.25, 1e-9);
  // Backing up through D1 (facing east, moving west).
  ASSERT_TRUE(loc.resetToEdge(e1, 0.25, true));
  ASSERT_TRUE(loc.predict(travel(-1.0)));
  EXPECT_EQ(best(loc).id, e0);
  EXPECT_TRUE(best(loc).forward);
  EXPECT_NEAR(best(loc).offset, 4.25, 1e-9);
}

TEST(PomdpTransition, PassesSeveralShortEdges) {
  // Five 0.5 m edges then a 5 m edge, all eastwards.
  TopologicalMap map;
  std::vector<uint32_t> n;
  for (int i = 0; i < 7; ++i) n.push_back(map.addNode(TopoNode()));
  std::vector<uint32_t> e;
  for (int i = 0; i < 5; ++i) e.push_back(map.addEdge(n[i], n[i + 1], 0.0, 0.5));
  const uint32_t last = map.addEdge(n[5], n[6], 0.0, 5.0);
  PomdpLocalizer loc(exactParams());
  loc.setMap(map);
  ASSERT_TRUE(loc.resetToEdge(e[0], 0.25, true));
  ASSERT_TRUE(loc.predict(travel(4.1)));  // 0.25 + 4.1 - 5 x 0.5 = 1.85 m past n[5]
  EXPECT_EQ(best(loc).id, last);
  EXPECT_EQ(best(loc).cell, 3u);  // [1.5, 2.0)
  // And back: 4.1 m westwards from 1.75 m on the last edge ends on the first short edge.
  ASSERT_TRUE(loc.predict(turn(2)));
  ASSERT_TRUE(loc.predict(travel(4.1)));
  EXPECT_EQ(best(loc).id, e[0]);
  EXPECT_FALSE(best(loc).forward);
}

TEST(PomdpTransition, BlockedAtTheHallwayEnd) {
  World w = hallway();
  const uint32_t e0 = edgeBetween(w.map, w.corners[0], w.doors[0]);
  const uint32_t e2 = edgeBetween(w.map, w.doors[1], w.corners[1]);  // D2 -> B, 8 m
  PomdpLocalizer loc(exactParams());
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(e2, 7.25, true));
  ASSERT_TRUE(loc.predict(travel(3.0)));
  const int at_end = loc.nodeStateIndex(w.corners[1], 0.0);
  EXPECT_EQ(loc.mostLikely(), at_end);
  ASSERT_TRUE(loc.predict(travel(1.0)));  // no exit eastwards: stays
  EXPECT_EQ(loc.mostLikely(), at_end);
  EXPECT_NEAR(loc.belief()[at_end], 1.0, 1e-12);
  // Backing up into the west end while facing east.
  ASSERT_TRUE(loc.resetToEdge(e0, 0.75, true));
  ASSERT_TRUE(loc.predict(travel(-2.0)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(w.corners[0], 0.0));
  // Turned around at the end, facing west: forward travel is blocked, backing up leaves the end.
  ASSERT_TRUE(loc.predict(turn(2)));
  ASSERT_TRUE(loc.predict(travel(1.0)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(w.corners[0], kPi));
  ASSERT_TRUE(loc.predict(travel(-1.0)));
  EXPECT_EQ(best(loc).id, e0);
  EXPECT_FALSE(best(loc).forward);
  ASSERT_TRUE(loc.resetToNode(w.corners[0], 0.0));
  ASSERT_TRUE(loc.predict(travel(1.0)));
  EXPECT_EQ(best(loc).id, e0);
  EXPECT_TRUE(best(loc).forward);
}

TEST(PomdpTransition, TravelIntoAWallIsUnlikely) {
  World w = hallway();
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  const uint32_t e2 = edgeBetween(w.map, w.doors[1], w.corners[1]);
  const PomdpParams p = exactParams();
  PomdpLocalizer loc(p);
  loc.setMap(w.map);
  const int at_end = loc.nodeStateIndex(w.corners[1], 0.0);
  const int mid = loc.edgeStateIndex(e1, 3.25, true);
  // Reaching the end is fine (0.25 m past it: within half a cell) ...
  std::vector<double> b(loc.size(), 0.0);
  b[size_t(loc.edgeStateIndex(e2, 7.75, true))] = 0.5;
  b[size_t(mid)] = 0.5;
  ASSERT_TRUE(loc.setBelief(b));
  ASSERT_TRUE(loc.predict(travel(0.5)));
  EXPECT_NEAR(loc.belief()[at_end], 0.5, 1e-12);
  // ... driving on into the wall costs blocked_travel_probability.
  ASSERT_TRUE(loc.predict(travel(1.0)));
  const double moved = loc.belief()[loc.edgeStateIndex(e1, 4.75, true)];
  EXPECT_NEAR(loc.belief()[at_end] / moved, p.blocked_travel_probability, 1e-12);
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpTransition, TurnsAtAJunctionSelectTheBranch) {
  // T junction: W -> J -> E eastwards, J -> S southwards.
  TopologicalMap map;
  const uint32_t W = map.addNode(TopoNode()), J = map.addNode(TopoNode()), E = map.addNode(TopoNode()),
                 S = map.addNode(TopoNode());
  const uint32_t wj = map.addEdge(W, J, 0.0, 10.0);
  map.addEdge(J, E, 0.0, 10.0);
  const uint32_t js = map.addEdge(J, S, -kPi / 2, 10.0);
  PomdpParams p = exactParams();
  PomdpLocalizer loc(p);
  loc.setMap(map);

  // Near J: a right turn puts the robot at J facing south, then travel enters J -> S.
  ASSERT_TRUE(loc.resetToEdge(wj, 9.25, true));
  ASSERT_TRUE(loc.predict(turn(-1)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(J, -kPi / 2));
  ASSERT_TRUE(loc.predict(travel(1.6)));
  EXPECT_EQ(best(loc).id, js);
  EXPECT_TRUE(best(loc).forward);
  EXPECT_NEAR(best(loc).offset, 1.75, 1e-9);

  // A left turn at J faces a wall: travel stays at J.
  ASSERT_TRUE(loc.resetToEdge(wj, 9.75, true));
  ASSERT_TRUE(loc.predict(turn(1)));
  ASSERT_TRUE(loc.predict(travel(1.0)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(J, kPi / 2));

  // Half the mass near J, half mid-edge: the mid-edge half stays, times turn_mid_edge_probability,
  // the other half goes to J facing south, then into the branch.
  const int mid = loc.edgeStateIndex(wj, 5.25, true);
  const int near = loc.edgeStateIndex(wj, 9.75, true);
  std::vector<double> b(loc.size(), 0.0);
  b[size_t(mid)] = 0.5;
  b[size_t(near)] = 0.5;
  ASSERT_TRUE(loc.setBelief(b));
  ASSERT_TRUE(loc.predict(turn(-1)));
  const double q = p.turn_mid_edge_probability;
  EXPECT_NEAR(loc.belief()[mid], q / (1.0 + q), 1e-12);
  EXPECT_NEAR(loc.belief()[loc.nodeStateIndex(J, -kPi / 2)], 1.0 / (1.0 + q), 1e-12);
  ASSERT_TRUE(loc.predict(travel(1.0)));
  const double on_branch = loc.probabilityWhere([&](const State& s) { return s.kind == State::Edge && s.id == js; });
  EXPECT_NEAR(on_branch, 1.0 / (1.0 + q), 1e-12);
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpTransition, TurnAtAnLCorner) {
  TopologicalMap map;
  const uint32_t A = map.addNode(TopoNode()), C = map.addNode(TopoNode()), B = map.addNode(TopoNode());
  const uint32_t ac = map.addEdge(A, C, 0.0, 10.0);
  const uint32_t cb = map.addEdge(C, B, kPi / 2, 10.0);
  PomdpLocalizer loc(exactParams());
  loc.setMap(map);
  // East into the corner: blocked at C facing east; a left turn and travel go north.
  ASSERT_TRUE(loc.resetToEdge(ac, 8.25, true));
  ASSERT_TRUE(loc.predict(travel(3.0)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(C, 0.0));
  ASSERT_TRUE(loc.predict(turn(1)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(C, kPi / 2));
  ASSERT_TRUE(loc.predict(travel(2.0)));
  EXPECT_EQ(best(loc).id, cb);
  EXPECT_TRUE(best(loc).forward);
  // South back into the corner, right turn, west.
  ASSERT_TRUE(loc.resetToEdge(cb, 0.75, false));
  ASSERT_TRUE(loc.predict(turn(-1)));  // within node_radius of C: at C, facing west
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(C, kPi));
  ASSERT_TRUE(loc.predict(travel(1.0)));
  EXPECT_EQ(best(loc).id, ac);
  EXPECT_FALSE(best(loc).forward);
  EXPECT_NEAR(best(loc).offset, 8.75, 1e-9);
}

TEST(PomdpTransition, UTurnMidEdge) {
  World w = hallway();
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  PomdpLocalizer loc(exactParams());
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(e1, 3.25, true));
  const uint32_t cell = best(loc).cell;
  ASSERT_TRUE(loc.predict(turn(2)));
  EXPECT_EQ(best(loc).id, e1);
  EXPECT_FALSE(best(loc).forward);
  EXPECT_EQ(best(loc).cell, cell);
  ASSERT_TRUE(loc.predict(turn(-2)));
  EXPECT_TRUE(best(loc).forward);
  EXPECT_EQ(best(loc).cell, cell);
  ASSERT_TRUE(loc.predict(turn(4)));  // a full turn: nothing
  EXPECT_EQ(best(loc).cell, cell);
  // Near a node the U-turn happens at the node.
  ASSERT_TRUE(loc.resetToEdge(e1, 6.75, true));
  ASSERT_TRUE(loc.predict(turn(2)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(w.doors[1], kPi));
}

// ---------------------------------------------------------------------------------------------
// Observation model

bool hasExpected(const std::vector<ExpectedLandmark>& v, LandmarkType type, double along, double lateral,
                 double orientation) {
  for (const ExpectedLandmark& e : v) {
    if (e.type == type && std::abs(e.along - along) < 1e-5 && std::abs(e.lateral - lateral) < 1e-5 &&
        std::abs(normalizeAngle(e.orientation - orientation)) < 1e-5)
      return true;
  }
  return false;
}

TEST(PomdpObservation, ExpectedLandmarksInTheTravelFrame) {
  World w = hallway();
  const uint32_t e0 = edgeBetween(w.map, w.corners[0], w.doors[0]);
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  PomdpParams params;
  params.window_ahead = 3.0;  // the figures below assume 3 m windows both ways
  PomdpLocalizer loc(params);
  loc.setMap(w.map);
  // East at 3.25 m: door D1 (5 m, left) 1.75 m ahead; the corner (7.5 m) is out of the window.
  auto v = loc.expectedLandmarks(size_t(loc.edgeStateIndex(e0, 3.25, true)));
  EXPECT_EQ(v.size(), 1u);
  EXPECT_TRUE(hasExpected(v, LandmarkType::Opening, 1.75, 1.0, kPi / 2));
  EXPECT_NEAR(v.at(0).p_lmap, 0.9, 1e-6);
  // East at 6.25 m: D1 1.25 m behind, the corner 1.25 m ahead on the right.
  v = loc.expectedLandmarks(size_t(loc.edgeStateIndex(e1, 1.25, true)));
  EXPECT_EQ(v.size(), 2u);
  EXPECT_TRUE(hasExpected(v, LandmarkType::Opening, -1.25, 1.0, kPi / 2));
  EXPECT_TRUE(hasExpected(v, LandmarkType::Corner, 1.25, -1.2, -2.3));
  // West at 9.25 m: the corner 1.75 m ahead on the left, orientation turned by pi; D2 (12 m,
  // right of east = left of west) 2.75 m behind.
  v = loc.expectedLandmarks(size_t(loc.edgeStateIndex(e1, 4.25, false)));
  EXPECT_EQ(v.size(), 2u);
  EXPECT_TRUE(hasExpected(v, LandmarkType::Corner, 1.75, 1.2, normalizeAngle(-2.3 + kPi)));
  EXPECT_TRUE(hasExpected(v, LandmarkType::Opening, -2.75, 1.0, kPi / 2));
  // At D1 facing east: its own door beside, the corner 2.5 m ahead; facing north: the door ahead.
  v = loc.expectedLandmarks(size_t(loc.nodeStateIndex(w.doors[0], 0.0)));
  EXPECT_EQ(v.size(), 2u);
  EXPECT_TRUE(hasExpected(v, LandmarkType::Opening, 0.0, 1.0, kPi / 2));
  EXPECT_TRUE(hasExpected(v, LandmarkType::Corner, 2.5, -1.2, -2.3));
  v = loc.expectedLandmarks(size_t(loc.nodeStateIndex(w.doors[0], kPi / 2)));
  EXPECT_TRUE(hasExpected(v, LandmarkType::Opening, 1.0, 0.0, 0.0));
  EXPECT_TRUE(loc.expectedLandmarks(loc.size()).empty());
}

TEST(PomdpObservation, LikelihoodRatiosFollowTheModel) {
  World w = hallway();
  const uint32_t e0 = edgeBetween(w.map, w.corners[0], w.doors[0]);
  const PomdpParams p;
  PomdpLocalizer loc(p);
  loc.setMap(w.map);
  Observation o;
  ObservedLandmark l;
  l.type = LandmarkType::Opening;
  l.along = 1.75;
  l.lateral = 1.0;
  l.orientation = kPi / 2;
  l.confidence = 0.7;
  o.landmarks.push_back(l);
  ASSERT_TRUE(loc.update(o));
  ASSERT_TRUE(isDistribution(loc));
  const double at = loc.belief()[loc.edgeStateIndex(e0, 3.25, true)];       // matches D1 exactly
  const double behind = loc.belief()[loc.edgeStateIndex(e0, 3.25, false)];  // expects D1 behind, right
  const double nothing = loc.belief()[loc.edgeStateIndex(e0, 0.75, true)];  // expects nothing
  // (Expected landmarks are stored in single precision: ratios to 1e-5.)
  const double q = p.opening_p_lmap, f = p.false_landmark_probability, wgt = p.observation_weight;
  // L(at) = q c, L(nothing) = f (a false landmark), L(behind) = (1 - q) f; tempered by the weight.
  EXPECT_NEAR(at / nothing, std::pow(q * 0.7 / f, wgt), 1e-5);
  EXPECT_NEAR(at / behind, std::pow(q * 0.7 / ((1.0 - q) * f), wgt), 1e-5);
  EXPECT_GT(at, 1.0 / double(loc.size()));
  // 0.4 m off along: the Gaussian factor exp(-d^2 / 2).
  const double off = loc.belief()[loc.edgeStateIndex(e0, 3.75, true)];  // expects D1 at 1.25
  const double d = 0.5 / p.match_sigma_along;
  EXPECT_NEAR(off / at, std::exp(-wgt * d * d / 2.0), 1e-5);
  // The same door on the wrong side matches nowhere near 3.25 m east.
  PomdpLocalizer loc2(p);
  loc2.setMap(w.map);
  o.landmarks[0].lateral = -1.0;
  o.landmarks[0].orientation = -kPi / 2;
  ASSERT_TRUE(loc2.update(o));
  EXPECT_NEAR(loc2.belief()[loc2.edgeStateIndex(e0, 3.25, true)] / loc2.belief()[loc2.edgeStateIndex(e0, 0.75, true)],
              std::pow(1.0 - q, wgt), 1e-5);
  // Untempered (weight 1), an unexplained observation costs the full factor.
  PomdpParams p1 = p;
  p1.observation_weight = 1.0;
  PomdpLocalizer loc3(p1);
  loc3.setMap(w.map);
  o.landmarks[0] = l;
  ASSERT_TRUE(loc3.update(o));
  EXPECT_NEAR(loc3.belief()[loc3.edgeStateIndex(e0, 3.25, true)] / loc3.belief()[loc3.edgeStateIndex(e0, 0.75, true)],
              q * 0.7 / f, 1e-5);
}

/// An octagonal ring of 0.75 m edges (45-degree bends: straight continuations), doors at two nodes:
/// windows wrap around it.
TopologicalMap octagon() {
  TopologicalMap map;
  std::vector<uint32_t> n;
  for (int i = 0; i < 8; ++i) {
    TopoNode node;
    if (i % 3 == 0) node.openings.push_back({normalizeAngle(i * kPi / 4 + kPi / 2), 1.0, 0.9, false});
    n.push_back(map.addNode(node));
  }
  for (int i = 0; i < 8; ++i) {
    EdgeLandmark lm;
    lm.distance = 0.3;
    lm.lateral = i % 2 ? 1.0 : -1.0;
    lm.orientation = 0.4 * i - 1.5;
    map.addEdge(n[i], n[(i + 1) % 8], normalizeAngle(i * kPi / 4), 0.75, {lm});
  }
  return map;
}

TEST(PomdpObservation, UpdateMatchesThePerStateLikelihood) {
  World h = hallway(), r = ring();
  const TopologicalMap maps[] = {h.map, r.map, octagon()};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.4);
  for (const TopologicalMap& map : maps) {
    PomdpLocalizer loc;
    loc.setMap(map);
    for (int trial = 0; trial < 30; ++trial) {
      // Landmarks near those expected at a random state, plus a random one.
      const size_t at = size_t(u(rng) * double(loc.size())) % loc.size();
      Observation o;
      for (const ExpectedLandmark& e : loc.expectedLandmarks(at)) {
        if (u(rng) < 0.2) continue;
        ObservedLandmark l;
        l.type = e.type;
        l.along = e.along + noise(rng);
        l.lateral = e.lateral + noise(rng);
        l.orientation = normalizeAngle(e.orientation + noise(rng));
        l.confidence = 0.5 + 0.5 * u(rng);
        o.landmarks.push_back(l);
      }
      ObservedLandmark extra;
      extra.type = u(rng) < 0.5 ? LandmarkType::Corner : LandmarkType::Opening;
      extra.along = 6.0 * u(rng) - 3.0;
      extra.lateral = 2.0 * u(rng) - 1.0;
      extra.orientation = 2.0 * kPi * u(rng) - kPi;
      o.landmarks.push_back(extra);
      o.heading_valid = trial % 2 == 0;
      o.heading = 2.0 * kPi * u(rng) - kPi;
      o.heading_variance = 0.05;
      ASSERT_TRUE(loc.update(o));
      ASSERT_TRUE(isDistribution(loc));
      for (size_t s = 0; s < loc.size(); ++s) {
        ASSERT_NEAR(loc.stateLogLikelihoods()[s], loc.stateLogLikelihood(s, o), 1e-4) << "state " << s;
      }
    }
  }
}

TEST(PomdpObservation, HeadingEstimateFavoursTheRightDirection) {
  World w = hallway();
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  PomdpLocalizer loc;
  loc.setMap(w.map);
  Observation o;
  o.heading_valid = true;
  o.heading = 0.05;
  o.heading_variance = 0.01;
  ASSERT_TRUE(loc.update(o));
  const double east = loc.probabilityWhere([](const State& s) { return std::abs(s.heading) < 0.5; });
  EXPECT_GT(east, 0.5);
  // 8.25 m east or west: the same landmarks (the corner at 0.75 m), the heading term differs. The
  // floor keeps the wrong direction alive (a wrong heading estimate can be recovered from).
  const PomdpParams p;
  auto term = [&](double d) {
    return p.heading_floor + (1.0 - p.heading_floor) * std::exp(-d * d / (2.0 * (p.heading_sigma * p.heading_sigma + 0.01)));
  };
  const double west = loc.belief()[loc.edgeStateIndex(e1, 3.25, false)];
  const double east_cell = loc.belief()[loc.edgeStateIndex(e1, 3.25, true)];
  EXPECT_NEAR(west / east_cell, std::pow(term(kPi - 0.05) / term(0.05), p.observation_weight), 1e-5);
  EXPECT_GT(west / east_cell, std::pow(p.heading_floor, p.observation_weight));
}

// An observed landmark where the known map ends (beyond an opening, straight on past the last node
// of a stretch) is unexplored; on a node's side that is neither an edge, an opening nor an edge's
// continuation it is not: that side is the hallway's wall (across from a door node's door), and a
// landmark seen there is a false one. (A door's state facing its door once explained everything
// seen along the hallway, both ways, as unexplored, and took the belief from a robot driving on.)
TEST(PomdpObservation, ADoorNodesSideAcrossFromItsDoorIsTheHallwaysWallNotUnexplored) {
  // A stretch being mapped: the start, then a door node 4 m east with its door on the left (north).
  TopologicalMap map;
  TopoNode start;
  start.type = NodeType::Start;
  const uint32_t a = map.addNode(start);
  TopoNode door_node;
  door_node.type = NodeType::Door;
  door_node.pose = {4.0, 0.0, 0.0};
  door_node.openings.push_back({kPi / 2, 1.0, 0.9, false});
  const uint32_t b = map.addNode(door_node);
  map.addEdge(a, b, 0.0, 4.0, {});
  const PomdpParams p;
  PomdpLocalizer loc(p);
  loc.setMap(map);
  auto corner_at = [](double along) {
    Observation o;
    ObservedLandmark l;
    l.type = LandmarkType::Corner;
    l.along = along;
    l.lateral = 0.3;
    l.orientation = 0.5;
    l.confidence = 1.0;
    o.landmarks.push_back(l);
    return o;
  };
  const double unexplored = std::log(p.unexplored_landmark_probability), false_one = std::log(p.false_landmark_probability);
  // At the door facing it (north): beyond the door the map ends; behind the robot is the wall.
  const size_t north = size_t(loc.nodeStateIndex(b, kPi / 2));
  const double ahead = loc.stateLogLikelihood(north, corner_at(2.0));
  const double behind = loc.stateLogLikelihood(north, corner_at(-2.0));
  EXPECT_NEAR(ahead - behind, unexplored - false_one, 1e-5);
  // Facing east, straight on past the stretch's last node: the hallway goes on unmapped.
  const size_t east = size_t(loc.nodeStateIndex(b, 0.0));
  const double beyond_end = loc.stateLogLikelihood(east, corner_at(2.0));
  EXPECT_NEAR(beyond_end - ahead, 0.0, 1e-5);
  // Facing south (the wall), and the wall's side seen from the edge's continuation: false.
  const size_t south = size_t(loc.nodeStateIndex(b, -kPi / 2));
  EXPECT_NEAR(loc.stateLogLikelihood(south, corner_at(2.0)) - ahead, false_one - unexplored, 1e-5);
  EXPECT_NEAR(loc.stateLogLikelihood(south, corner_at(-2.0)) - ahead, 0.0, 1e-5);  // the door's way behind
  // At a hallway's end nothing lies beyond, whatever the side.
  TopologicalMap closed = map;
  closed.node(b)->type = NodeType::HallwayEnd;
  PomdpLocalizer at_end(p);
  at_end.setMap(closed);
  EXPECT_NEAR(at_end.stateLogLikelihood(size_t(at_end.nodeStateIndex(b, 0.0)), corner_at(2.0)) - ahead,
              false_one - unexplored, 1e-5);
}

// ---------------------------------------------------------------------------------------------
// Localization

TEST(PomdpLocalization, GlobalLocalizationOnARing) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  Sensor sensor;  // no heading estimate: only the landmarks
  Truth t{0, 1.0, true};
  const double start_entropy = loc.entropy();
  int first_confident = -1;
  for (int i = 0; i < 90; ++i) {  // 43 m: most of the ring
    driveStep(w, &t, &loc, &sensor);
    ASSERT_TRUE(isDistribution(loc));
    if (first_confident < 0 && loc.confident() && mostLikelyNearTruth(loc, w, t, 1.0)) first_confident = i;
  }
  EXPECT_GE(first_confident, 0);
  EXPECT_LE(first_confident, 40);  // within 20 m: past two or three doors and a corner landmark
  EXPECT_LT(loc.entropy(), start_entropy - 2.0);
  EXPECT_TRUE(mostLikelyNearTruth(loc, w, t, 1.0));
  EXPECT_GT(massNearTruth(loc, w, t, 1.0), 0.7);
  // And it keeps tracking.
  for (int i = 0; i < 40; ++i) {
    driveStep(w, &t, &loc, &sensor);
    EXPECT_GT(massNearTruth(loc, w, t, 1.5), 0.5) << "step " << i;
  }
}

TEST(PomdpLocalization, LookAlikeDoorsAreDisambiguatedByTheSequence) {
  // Two identical doors on the left at 6 and 13 m, a third at 25 m; the hallway is 32 m.
  World w = buildWorld({{0.0, 32.0, {door(6.0, true), door(13.0, true), door(25.0, true)}}}, false);
  PomdpLocalizer loc;
  loc.setMap(w.map);
  Sensor sensor;
  sensor.miss = 0.0;
  sensor.spurious = 0.0;
  sensor.heading_valid = true;  // the direction is known: only the place is ambiguous
  // From 2.5 m: the twin 7 m further on has seen the same (nothing, then a door on the left).
  Truth t{0, 2.5, true};
  while (t.x < 9.5 - 1e-9) driveStep(w, &t, &loc, &sensor);
  // Passed one door: here, or 7 m further on (past the second door), look the same.
  Truth twin = t;
  twin.x += 7.0;
  const double here = massNearTruth(loc, w, t, 1.5), there = massNearTruth(loc, w, twin, 1.5);
  EXPECT_GT(here, 0.2);
  EXPECT_GT(there, 0.2);
  EXPECT_FALSE(loc.confident());
  // The second door 7 m after the first only fits the true place.
  while (t.x < 17.0 - 1e-9) driveStep(w, &t, &loc, &sensor);
  twin = t;
  twin.x += 7.0;
  EXPECT_GT(massNearTruth(loc, w, t, 1.5), 0.8);
  EXPECT_LT(massNearTruth(loc, w, twin, 1.5), 0.05);
  EXPECT_TRUE(mostLikelyNearTruth(loc, w, t, 1.0));
}

// Kidnapped after localizing: (a) to the far side, facing the other way (the heading estimate
// helps), (b) 10 m back on the same side, same heading (only the landmarks tell).
void kidnapping(const Truth& start, int steps_before, const Truth& jump, int max_steps, bool heading) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  Sensor sensor;
  sensor.heading_valid = heading;
  Truth t = start;
  for (int i = 0; i < steps_before; ++i) driveStep(w, &t, &loc, &sensor);
  ASSERT_TRUE(loc.confident());
  ASSERT_TRUE(mostLikelyNearTruth(loc, w, t, 1.0));
  t = jump;
  int recovered = -1;
  for (int i = 0; i < max_steps && recovered < 0; ++i) {
    driveStep(w, &t, &loc, &sensor);
    ASSERT_TRUE(isDistribution(loc));
    if (massNearTruth(loc, w, t, 1.5) > 0.5 && mostLikelyNearTruth(loc, w, t, 1.0)) recovered = i;
  }
  EXPECT_GE(recovered, 0) << "not recovered within " << max_steps << " steps";
  for (int i = 0; i < 10; ++i) driveStep(w, &t, &loc, &sensor);
  EXPECT_GT(massNearTruth(loc, w, t, 1.5), 0.5);
  EXPECT_TRUE(mostLikelyNearTruth(loc, w, t, 1.0));
}

TEST(PomdpLocalization, RecoversFromKidnappingToTheFarSide) {
  kidnapping(Truth{0, 1.0, true}, 40, Truth{2, 1.0, true}, 24, true);  // 12 m: past 2 doors
}

TEST(PomdpLocalization, RecoversFromKidnappingAlongTheSameHallway) {
  kidnapping(Truth{0, 1.0, true}, 20, Truth{0, 1.0, true}, 24, false);  // 12 m: past a door and a corner
}

TEST(PomdpLocalization, LostAfterConsecutiveUnexplainedObservations) {
  World w = hallway();
  PomdpParams params;
  params.lost_likelihood = 0.05;  // this small hallway has at most two landmarks in a window
  PomdpLocalizer loc(params);
  loc.setMap(w.map);
  // The state whose window expects the most landmarks; the robot sees none of them (and nothing
  // else): relative to "nothing expected", the likelihood is the product of (1 - p_lmap).
  size_t best = 0;
  for (size_t i = 0; i < loc.size(); ++i) {
    if (loc.expectedLandmarks(i).size() > loc.expectedLandmarks(best).size()) best = i;
  }
  double log_missed = 0.0;
  for (const auto& e : loc.expectedLandmarks(best)) log_missed += std::log1p(-e.p_lmap);
  ASSERT_LT(log_missed, std::log(loc.params().lost_likelihood)) << "the test needs a state expecting enough landmarks";
  ASSERT_TRUE(loc.setState(best));
  Observation o;
  for (int i = 1; i <= 3; ++i) {
    ASSERT_TRUE(loc.update(o));
    EXPECT_EQ(loc.lost(), i == 3) << "update " << i;
    EXPECT_TRUE(isDistribution(loc));
  }
  EXPECT_FALSE(loc.confident());
  EXPECT_GT(loc.entropy(), 1.0);
  // Landmarks the map does not explain are no reason to be lost (furniture, people): eight extra
  // corners with the belief on a state that expects nothing.
  size_t quiet = 0;
  while (quiet < loc.size() && !loc.expectedLandmarks(quiet).empty()) ++quiet;
  ASSERT_LT(quiet, loc.size());
  ASSERT_TRUE(loc.setState(quiet));
  for (int i = 0; i < 8; ++i) {
    ObservedLandmark l;
    l.along = -1.4 + 0.4 * i;
    l.lateral = i % 2 ? 0.5 : -0.5;
    l.orientation = 0.1;
    o.landmarks.push_back(l);
  }
  for (int i = 1; i <= 4; ++i) {
    ASSERT_TRUE(loc.update(o));
    EXPECT_FALSE(loc.lost()) << "update " << i;
  }
}

// ---------------------------------------------------------------------------------------------
// Bad input, empty map, map changes

TEST(PomdpRobustness, BadInputIsRefusedAndChangesNothing) {
  World w = hallway();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  ASSERT_TRUE(loc.predict(travel(2.0)));
  Observation good;
  good.landmarks.push_back(ObservedLandmark());
  ASSERT_TRUE(loc.update(good));
  const std::vector<double> before = loc.belief();

  std::string error;
  Observation bad = good;
  bad.landmarks[0].along = std::nan("");
  EXPECT_FALSE(loc.update(bad, &error));
  EXPECT_FALSE(error.empty());
  bad = good;
  bad.landmarks[0].confidence = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(loc.update(bad));
  bad = good;
  bad.heading_valid = true;
  bad.heading = std::nan("");
  EXPECT_FALSE(loc.update(bad));
  bad.heading = 0.0;
  bad.heading_variance = -1.0;
  EXPECT_FALSE(loc.update(bad));
  error.clear();
  EXPECT_FALSE(loc.predict(travel(std::nan("")), &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(loc.predict(travel(-std::numeric_limits<double>::infinity())));
  bad = good;
  bad.landmarks[0].type = static_cast<LandmarkType>(7);
  EXPECT_FALSE(loc.update(bad));
  EXPECT_FALSE(loc.step(travel(1.0), bad));  // refused as a whole: the travel is not applied
  EXPECT_FALSE(loc.step(travel(std::nan("")), good));
  EXPECT_FALSE(loc.resetToNode(999, 0.0));
  EXPECT_FALSE(loc.resetToNode(w.doors[0], std::nan("")));
  EXPECT_FALSE(loc.resetToEdge(999, 1.0, true));
  EXPECT_FALSE(loc.resetToEdge(0, std::nan(""), true));
  EXPECT_FALSE(loc.setState(loc.size()));
  EXPECT_EQ(loc.belief(), before);
  EXPECT_TRUE(isDistribution(loc));
  // Heading values are ignored when not valid.
  bad = good;
  bad.heading = std::nan("");
  EXPECT_TRUE(loc.update(bad));
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpRobustness, ExtremeButFiniteInputsStayADistribution) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  ASSERT_TRUE(loc.predict(travel(1e9)));
  EXPECT_TRUE(isDistribution(loc));
  ASSERT_TRUE(loc.predict(turn(-1000001)));
  EXPECT_TRUE(isDistribution(loc));
  Observation o;
  for (int i = 0; i < 200; ++i) {
    ObservedLandmark l;
    l.type = i % 2 ? LandmarkType::Opening : LandmarkType::Corner;
    l.along = 1e12 * (i % 3 - 1);
    l.lateral = 1e-300;
    l.orientation = 1e6;
    l.confidence = i % 4 ? 0.0 : 7.0;
    o.landmarks.push_back(l);
  }
  o.heading_valid = true;
  o.heading = 1e8;
  o.heading_variance = 1e300;
  ASSERT_TRUE(loc.update(o));
  EXPECT_TRUE(isDistribution(loc));
  // A delta belief that the observation rules out completely: degenerate -> uniform, lost.
  PomdpParams p;
  p.uniform_mixing = 0.0;
  p.observation_weight = 1000.0;
  PomdpLocalizer sharp(p);
  sharp.setMap(w.map);
  ASSERT_TRUE(sharp.resetToEdge(w.map.edges().begin()->first, 0.25, false));
  Observation doors;
  for (int i = 0; i < 3; ++i) {
    ObservedLandmark l;
    l.type = LandmarkType::Opening;
    l.along = i - 1.0;
    l.lateral = 1.0;
    l.orientation = kPi / 2;
    doors.landmarks.push_back(l);
  }
  ASSERT_TRUE(sharp.update(doors));
  EXPECT_TRUE(isDistribution(sharp));
  EXPECT_TRUE(sharp.lost());
}

TEST(PomdpRobustness, EmptyMap) {
  TopologicalMap map;
  PomdpLocalizer loc;
  EXPECT_EQ(loc.mostLikely(), -1);
  loc.setMap(map);
  EXPECT_EQ(loc.size(), 0u);
  EXPECT_TRUE(loc.predict(travel(1.0)));
  EXPECT_TRUE(loc.predict(turn(1)));
  Observation o;
  o.landmarks.push_back(ObservedLandmark());
  EXPECT_TRUE(loc.update(o));
  EXPECT_TRUE(loc.step(travel(1.0), o));
  EXPECT_EQ(loc.mostLikely(), -1);
  EXPECT_FALSE(loc.confident());
  EXPECT_EQ(loc.entropy(), 0.0);
  loc.setUniform();
  EXPECT_FALSE(loc.setState(0));
  EXPECT_FALSE(loc.resetToNode(0, 0.0));
  EXPECT_EQ(loc.probabilityNearNode(0, 1.0), 0.0);
  // A single node without edges: only node states, travel is blocked.
  map.addNode(TopoNode());
  loc.setMap(map);
  EXPECT_EQ(loc.size(), 4u);
  EXPECT_TRUE(loc.predict(travel(1.0)));
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpRobustness, ZeroLengthEdgesDoNotHang) {
  TopologicalMap map;
  const uint32_t a = map.addNode(TopoNode()), b = map.addNode(TopoNode());
  map.addEdge(a, b, 0.0, 0.0);
  map.addEdge(b, a, 0.0, 0.0);  // a loop of zero length eastwards
  PomdpLocalizer loc;
  loc.setMap(map);
  EXPECT_TRUE(loc.predict(travel(5.0)));
  EXPECT_TRUE(isDistribution(loc));
  EXPECT_TRUE(loc.update(Observation()));
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpRobustness, UncheckedMapContents) {
  // TopologicalMap::assign does not check: a dangling edge, non-finite numbers.
  std::map<uint32_t, TopoNode> nodes;
  std::map<uint32_t, TopoEdge> edges;
  nodes[0].id = 0;
  nodes[1].id = 1;
  nodes[1].openings.push_back({std::nan(""), 1.0, 0.9, false});
  TopoEdge good;
  good.id = 0;
  good.source = 0;
  good.target = 1;
  good.length = 3.0;
  good.landmarks.resize(1);
  good.landmarks[0].distance = std::nan("");
  TopoEdge dangling = good;
  dangling.id = 1;
  dangling.target = 7;
  TopoEdge weird = good;
  weird.id = 2;
  weird.length = std::numeric_limits<double>::infinity();
  weird.heading = std::nan("");
  edges[0] = good;
  edges[1] = dangling;
  edges[2] = weird;
  TopologicalMap map;
  map.assign(nodes, edges, 2, 3);
  PomdpLocalizer loc;
  loc.setMap(map);
  EXPECT_EQ(loc.size(), 2u * 6u + 2u + 8u);  // edge 0: 6 cells; edge 2: length 0, one cell
  EXPECT_EQ(loc.edgeStateIndex(1, 0.0, true), -1);
  ASSERT_TRUE(loc.step(travel(0.5), Observation()));
  EXPECT_TRUE(isDistribution(loc));
}

TEST(PomdpMapChange, ReprojectionKeepsTheBeliefOnALongerEdge) {
  World w = hallway();
  const uint32_t e1 = edgeBetween(w.map, w.doors[0], w.doors[1]);
  PomdpLocalizer loc;
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(e1, 3.25, false));
  const uint64_t revision = w.map.revision();
  w.map.setEdgeLength(e1, 9.0);
  ASSERT_NE(w.map.revision(), revision);
  loc.setMap(w.map);
  EXPECT_EQ(loc.mapRevision(), w.map.revision());
  EXPECT_EQ(loc.size(), 2u * 44u + 16u);
  ASSERT_TRUE(isDistribution(loc));
  EXPECT_EQ(best(loc).id, e1);
  EXPECT_FALSE(best(loc).forward);
  EXPECT_NEAR(best(loc).offset, 3.25, 1e-9);
  EXPECT_NEAR(loc.belief()[loc.mostLikely()], 1.0, 1e-12);
  // Node states carry over too, split beliefs keep their ratio.
  ASSERT_TRUE(loc.resetToNode(w.doors[1], kPi / 2));
  ASSERT_TRUE(loc.predict(turn(0)));
  TopoNode extra;
  const uint32_t x = w.map.addNode(extra);
  w.map.addEdge(w.corners[1], x, kPi / 2, 4.0);
  loc.setMap(w.map);
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(w.doors[1], kPi / 2));
  EXPECT_NEAR(loc.belief()[loc.mostLikely()], 1.0, 1e-12);
  // Nothing carried (the node is removed): uniform.
  ASSERT_TRUE(w.map.removeNode(w.doors[1]));
  loc.setMap(w.map);
  EXPECT_NEAR(loc.entropy(), std::log(double(loc.size())), 1e-9);
}

TEST(PomdpMapChange, ProbabilityNearNode) {
  World w = hallway();
  PomdpLocalizer loc(exactParams());
  loc.setMap(w.map);
  ASSERT_TRUE(loc.resetToEdge(edgeBetween(w.map, w.doors[0], w.doors[1]), 0.75, false));
  EXPECT_NEAR(loc.probabilityNearNode(w.doors[0], 1.0), 1.0, 1e-12);
  EXPECT_NEAR(loc.probabilityNearNode(w.doors[0], 0.5), 0.0, 1e-12);
  EXPECT_NEAR(loc.probabilityNearNode(w.doors[1], 1.0), 0.0, 1e-12);
  loc.setUniform();
  // 4 node states + 2 directions x 2 cells on each of the two edges at D1.
  EXPECT_NEAR(loc.probabilityNearNode(w.doors[0], 1.0), 12.0 / double(loc.size()), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Allocation

TEST(PomdpAllocation, SteadyStateStepsDoNotAllocate) {
  World w = ring();
  PomdpLocalizer loc;
  loc.setMap(w.map);
  Sensor sensor;
  sensor.heading_valid = true;
  Truth t{0, 1.0, true};
  std::vector<Observation> observations;
  std::vector<Action> actions;
  for (int i = 0; i < 60; ++i) {  // inputs generated before counting
    const double length = w.sides[t.side].length;
    Action a = travel(0.5);
    if (t.x >= length - 1e-9) {
      a = turn(1);
      t.side = (t.side + 1) % 4;
      t.x = 0.0;
    } else {
      t.x += 0.5;
    }
    actions.push_back(a);
    observations.push_back(sensor.observe(w, t));
  }
  ObservedLandmark many;
  Observation big;
  big.landmarks.assign(12, many);
  // Warm up: the largest observation.
  for (size_t i = 0; i < actions.size(); ++i) loc.step(actions[i], observations[i]);
  loc.update(big);
  const long before = laser_features::testing::allocationCount();
  for (int repeat = 0; repeat < 3; ++repeat) {
    for (size_t i = 0; i < actions.size(); ++i) ASSERT_TRUE(loc.step(actions[i], observations[i]));
  }
  // New distances: the successors are recomputed into the cache slots allocated by setMap.
  for (double d : {0.37, 0.41, -0.3, 0.45, 0.55, 2.0}) ASSERT_TRUE(loc.predict(travel(d)));
  ASSERT_TRUE(loc.predict(turn(1)));
  EXPECT_GT(loc.size(), 0u);
  EXPECT_EQ(laser_features::testing::allocationCount() - before, 0);
}

}  // namespace
// The localizer's travel follows TopologicalMap::wayOn: at a staggered crossing (the hallway's
// east part leaves a node 1.2 m across the stem from the one its west part leaves) the belief
// drives on across the offset, with no turn, onto the other node's edge; through the node from
// the west edge too.
TEST(PomdpTransition, DrivesOnAcrossAStaggeredCrossing) {
  TopologicalMap map;
  auto node = [&](double x, double y) {
    TopoNode n;
    n.type = NodeType::Junction;
    n.pose = Pose2D{x, y, 0.0};
    return map.addNode(n);
  };
  const uint32_t south = node(0, 0), north = node(0, 1.2), east = node(6, 0), west = node(-6, 1.2);
  map.addEdge(south, north, 0.5 * kPi, 1.2);
  const uint32_t to_east = map.addEdge(south, east, 0.0, 6.0);
  const uint32_t to_west = map.addEdge(north, west, kPi, 6.0);
  PomdpLocalizer loc(exactParams());
  loc.setMap(map);
  ASSERT_TRUE(loc.resetToNode(north, 0.0));  // at the west part's node, facing east
  ASSERT_TRUE(loc.predict(travel(2.0)));
  EXPECT_EQ(best(loc).kind, State::Edge);
  EXPECT_EQ(best(loc).id, to_east);
  EXPECT_TRUE(best(loc).forward);
  EXPECT_NEAR(best(loc).offset, 2.25, 1e-9);  // the cell of 2 m on: the offset across is not travel along
  // From the cell 1.0-1.5 m along the west edge, heading east, through `north` and on east.
  ASSERT_TRUE(loc.resetToEdge(to_west, 1.0, false));
  ASSERT_TRUE(loc.predict(travel(3.0)));
  EXPECT_EQ(best(loc).kind, State::Edge);
  EXPECT_EQ(best(loc).id, to_east);
  EXPECT_NEAR(best(loc).offset, 1.75, 1e-9);  // from the cell centre 1.25 m before `north`
  // A longer link (1.6 m, a hallway's width): the node has no way on, the travel is blocked.
  TopologicalMap wide = map;
  wide.removeEdge(to_west);
  const uint32_t far_north = wide.addNode(TopoNode());
  wide.node(far_north)->pose = Pose2D{0, 1.6, 0};
  wide.addEdge(south, far_north, 0.5 * kPi, 1.6);
  wide.addEdge(far_north, west, kPi, 6.0);
  loc.setMap(wide);
  ASSERT_TRUE(loc.resetToNode(far_north, 0.0));
  ASSERT_TRUE(loc.predict(travel(2.0)));
  EXPECT_EQ(loc.mostLikely(), loc.nodeStateIndex(far_north, 0.0));
}

}  // namespace pomdp_topo
