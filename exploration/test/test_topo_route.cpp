// The route to the nearest unexplored opening on the topological graph.
#include <gtest/gtest.h>

#include <cmath>

#include "exploration/route_policy.h"
#include "exploration/topo_route.h"

using exploration::GraphEdge;
using exploration::GraphNode;
using exploration::GraphOpening;
using exploration::GraphPosition;
using exploration::TopoGraph;
using exploration::TopoMode;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A hallway along +x: 0 (start) -- 4 m -- 1 (door, north) -- 6 m -- 2 (junction, branch north)
// -- 3 m -- 3 (hallway end).
TopoGraph hallway(bool door_explored, bool branch_explored) {
  TopoGraph g;
  GraphNode n0{0, 4, 0.0, 0.0, {}};
  GraphNode n1{1, 0, 4.0, 0.0, {GraphOpening{0.5 * kPi, 0.9, door_explored}}};
  GraphNode n2{2, 1, 10.0, 0.0, {GraphOpening{0.5 * kPi, 2.0, branch_explored}}};
  GraphNode n3{3, 2, 13.0, 0.0, {}};
  g.addNode(n0);
  g.addNode(n1);
  g.addNode(n2);
  g.addNode(n3);
  g.addEdge(GraphEdge{0, 0, 1, 0.0, 4.0});
  g.addEdge(GraphEdge{1, 1, 2, 0.0, 6.0});
  g.addEdge(GraphEdge{2, 2, 3, 0.0, 3.0});
  return g;
}

// A confident belief at `pos`.
exploration::TopoView localizedAt(const GraphPosition& pos) {
  exploration::TopoView topo;
  topo.valid = true;
  topo.mode = TopoMode::Localized;
  topo.confident = true;
  topo.position = pos;
  return topo;
}

GraphPosition onEdge(uint32_t edge, double offset, double heading) {
  GraphPosition p;
  p.valid = true;
  p.at_node = false;
  p.id = edge;
  p.offset = offset;
  p.heading = heading;
  return p;
}

}  // namespace

TEST(TopoRoute, CountsUnexploredOpenings) {
  EXPECT_EQ(hallway(false, false).unexploredCount(), 2u);
  EXPECT_EQ(hallway(true, false).unexploredCount(), 1u);
  EXPECT_EQ(hallway(true, true).unexploredCount(), 0u);
  EXPECT_EQ(hallway(true, true).exploredCount(), 2u);
}

TEST(TopoRoute, ABranchWithAnEdgeInItsBearingIsExplored) {
  TopoGraph g = hallway(true, false);
  g.addNode(GraphNode{4, 2, 10.0, 5.0, {}});
  g.addEdge(GraphEdge{3, 4, 2, -0.5 * kPi, 5.0});  // reached from the north (a loop): arrives heading south
  EXPECT_EQ(g.unexploredCount(), 0u);
}

TEST(TopoRoute, GoesToTheNearestUnexploredOpeningAheadOrBehind) {
  const TopoGraph g = hallway(false, false);
  // At 1 m past the door heading east: the door (1 m back) is nearer than the junction (5 m on),
  // even with the U-turn's cost.
  auto r = g.route(onEdge(1, 1.0, 0.0), 2.0);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.goal_node, 1u);
  EXPECT_NEAR(std::abs(r.heading), kPi, 1e-9);  // turn round
  EXPECT_NEAR(r.distance, 3.0, 1e-9);
  // At 4 m past the door: the junction, ahead.
  r = g.route(onEdge(1, 4.0, 0.0), 2.0);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.goal_node, 2u);
  EXPECT_NEAR(r.heading, 0.0, 1e-9);
  EXPECT_NEAR(r.distance, 2.0, 1e-9);
}

TEST(TopoRoute, AtTheGoalNodeTheStepIsTheOpening) {
  const TopoGraph g = hallway(true, false);
  GraphPosition at;
  at.valid = true;
  at.at_node = true;
  at.id = 2;
  at.heading = 0.0;
  const auto r = g.route(at);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.goal_node, 2u);
  EXPECT_NEAR(r.heading, 0.5 * kPi, 1e-9);
  // From the hallway end, heading back west along the edges.
  at.id = 3;
  at.heading = kPi;
  const auto back = g.route(at);
  ASSERT_TRUE(back.found);
  EXPECT_EQ(back.goal_node, 2u);
  EXPECT_EQ(back.next_node, 3u);  // at a node, the step starts there
  EXPECT_NEAR(std::abs(back.heading), kPi, 1e-9);
  EXPECT_NEAR(std::abs(back.next_heading), kPi, 1e-9);
}

TEST(TopoRoute, TheHeadingToLeaveTheNextNodeTurnsIntoTheBranch) {
  // From the door (node 1) heading east, the route to a door up the branch of junction 2: at
  // node 2 the robot must turn north.
  TopoGraph g = hallway(true, true);
  g.addNode(GraphNode{4, 0, 10.0, 6.0, {GraphOpening{kPi, 0.9, false}}});
  g.addEdge(GraphEdge{3, 2, 4, 0.5 * kPi, 6.0});
  const auto r = g.route(onEdge(1, 2.0, 0.0));
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.goal_node, 4u);
  EXPECT_EQ(r.next_node, 2u);
  EXPECT_NEAR(r.heading, 0.0, 1e-9);
  EXPECT_NEAR(r.next_heading, 0.5 * kPi, 1e-9);
  EXPECT_NEAR(r.distance, 10.0, 1e-9);
  // Once at node 2, the step itself turns north; the goal's opening comes after.
  GraphPosition at;
  at.valid = true;
  at.at_node = true;
  at.id = 2;
  at.heading = 0.0;
  const auto s = g.route(at);
  EXPECT_EQ(s.next_node, 2u);
  EXPECT_NEAR(s.heading, 0.5 * kPi, 1e-9);
}

TEST(TopoRoute, NothingLeftOrNoPosition) {
  EXPECT_FALSE(hallway(true, true).route(onEdge(1, 1.0, 0.0)).found);
  GraphPosition lost;
  EXPECT_FALSE(hallway(false, false).route(lost).found);
  EXPECT_FALSE(hallway(false, false).route(onEdge(99, 1.0, 0.0)).found);
  EXPECT_EQ(hallway(false, false).nearestNode(lost), -1);
}

TEST(TopoRoute, DistanceAlongTheEdges) {
  const TopoGraph g = hallway(false, false);
  EXPECT_NEAR(g.distance(0, 3), 13.0, 1e-9);
  EXPECT_NEAR(g.distance(3, 1), 9.0, 1e-9);
  EXPECT_NEAR(g.distance(2, 2), 0.0, 1e-9);
  TopoGraph split = g;
  split.addNode(GraphNode{9, 2, 50.0, 0.0, {}});  // not connected
  EXPECT_TRUE(std::isinf(split.distance(0, 9)));
  EXPECT_TRUE(std::isinf(g.distance(0, 42)));
}

TEST(TopoRoute, NearestNodeOfAnEdgePosition) {
  const TopoGraph g = hallway(false, false);
  EXPECT_EQ(g.nearestNode(onEdge(1, 1.0, 0.0)), 1);
  EXPECT_EQ(g.nearestNode(onEdge(1, 5.0, 0.0)), 2);
  EXPECT_EQ(g.nearestNode(onEdge(1, 3.0, 0.0)), 2);   // half-way: the one ahead
  EXPECT_EQ(g.nearestNode(onEdge(1, 3.0, kPi)), 1);
}

TEST(TopoRoute, DistanceToTheNearestNode) {
  const TopoGraph g = hallway(false, false);
  EXPECT_NEAR(g.nearestNodeDistance(onEdge(1, 1.0, 0.0)), 1.0, 1e-9);  // to node 1
  EXPECT_NEAR(g.nearestNodeDistance(onEdge(1, 5.5, 0.0)), 0.5, 1e-9);  // to node 2
  EXPECT_NEAR(g.nearestNodeDistance(onEdge(1, 3.0, kPi)), 3.0, 1e-9);
  GraphPosition at;
  at.valid = at.at_node = true;
  at.id = 2;
  EXPECT_EQ(g.nearestNodeDistance(at), 0.0);
  EXPECT_TRUE(std::isinf(g.nearestNodeDistance(GraphPosition())));
}

TEST(TopoRoute, RouteToAMissionsDoorGoesPastNearerUnexploredOpenings) {
  TopoGraph g = hallway(false, false);
  // Doors facing each other across the hallway: one node, each door linking its own room.
  GraphNode door{4, 0, 12.0, 0.0, {GraphOpening{-0.5 * kPi, 0.8, true, 9, {1.0, 2.0, 0.3}},
                                   GraphOpening{0.5 * kPi, 0.9, true, 11, {0.5, -1.0, -2.0}}}};
  // Node 4 sits on the edge 2 -- 3 in this test's eyes; only its links matter here.
  g.addNode(door);
  g.addEdge(GraphEdge{3, 3, 4, 0.0, 2.0});
  const auto pd = g.placeDoor(9);
  ASSERT_TRUE(pd.has_value());
  EXPECT_EQ(pd->node, 4u);
  EXPECT_NEAR(pd->opening.bearing, -0.5 * kPi, 1e-12) << "place 9's door, not the one across";
  EXPECT_NEAR(pd->opening.door_in_place[0], 1.0, 1e-12);
  EXPECT_NEAR(pd->opening.door_in_place[2], 0.3, 1e-12);
  const auto across = g.placeDoor(11);
  ASSERT_TRUE(across.has_value());
  EXPECT_EQ(across->node, 4u);
  EXPECT_NEAR(across->opening.bearing, 0.5 * kPi, 1e-12);
  EXPECT_NEAR(across->opening.door_in_place[1], -1.0, 1e-12);
  EXPECT_EQ(g.placeIds(), (std::set<int>{9, 11}));
  EXPECT_FALSE(g.placeDoor(8).has_value());
  EXPECT_FALSE(g.placeDoor(-1).has_value());

  // From the start going east: the unexplored door of node 1 is nearer, the mission's is node 4's.
  const auto r = g.routeTo(onEdge(0, 1.0, 0.0), 4, pd->opening);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.goal_node, 4u);
  EXPECT_NEAR(r.distance, 3.0 + 6.0 + 3.0 + 2.0, 1e-9);
  EXPECT_NEAR(r.goal_bearing, -0.5 * kPi, 1e-12);
  EXPECT_EQ(g.route(onEdge(0, 1.0, 0.0)).goal_node, 1u);
  // Facing west: turning round costs the U-turn.
  EXPECT_NEAR(g.routeTo(onEdge(0, 1.0, kPi), 4, pd->opening, 2.0).distance, 14.0 + 2.0, 1e-9);
  // An unknown goal node: no route.
  EXPECT_FALSE(g.routeTo(onEdge(0, 1.0, 0.0), 77, pd->opening).found);
}

// An opening the route keeps missing is set aside the first time (the route goes to the others
// first: a wrong belief is the likeliest reason for a miss), tried once more when every other
// opening is explored, and only then given up (marked explored, and never routed to again
// whether or not the map builder took the record).
TEST(RoutePolicy, AnOpeningMissedIsSetAsideTriedOnceMoreThenGivenUp) {
  using exploration::RouteAction;
  exploration::RoutePolicyParams params;
  exploration::RoutePolicy policy(params, laser_features::BuildingRules());
  // Both the door at node 1 and the branch at node 2 unexplored; the robot on edge 1 heading west
  // (back towards node 1) with the route pointing east would turn round: here it heads east past
  // node 2 on edge 2, and the route to the branch points back west.
  const TopoGraph g = hallway(false, false);
  const exploration::TopoView topo = localizedAt(onEdge(2, 2.0, 0.0));  // 2 m past node 2, towards the end 3
  double travel = 100.0;
  // Misses until the route's goal is set aside: turn round max_route_attempts times, then the miss.
  RouteAction last;  // the last action missUntil() returned the kind of
  auto missUntil = [&](RouteAction::Kind kind) {
    for (int i = 0; i < 200; ++i) {
      travel += 1.0;  // each tick far from the last turn
      const exploration::RouteStep r = policy.plan(g, topo.position, nullptr);
      if (!r.found) return RouteAction::None;
      const exploration::RouteContext at{g, topo, travel, false};
      const RouteAction a = policy.alongRoute(at, r, 0.0);
      if (a.kind == RouteAction::TurnRound) policy.turned(travel - 10.0);  // the turn is long ago
      if (a.kind == kind || a.kind == RouteAction::GiveUp || a.kind == RouteAction::SetAside) {
        last = a;
        return a.kind;
      }
    }
    return RouteAction::None;
  };
  const size_t both = policy.openingsLeft(g);
  EXPECT_EQ(both, 2u);
  // The nearest opening (the branch at node 2, 2 m back) is missed: set aside, not given up.
  EXPECT_EQ(missUntil(RouteAction::SetAside), RouteAction::SetAside);
  EXPECT_EQ(policy.openingsLeft(g), 1u);
  EXPECT_EQ(policy.plan(g, topo.position, nullptr).goal_node, 1u);  // the door at node 1 next
  // The door is missed too: set aside; nothing is left to plan for but the two set aside.
  EXPECT_EQ(missUntil(RouteAction::SetAside), RouteAction::SetAside);
  EXPECT_EQ(policy.openingsLeft(g), 0u);
  EXPECT_EQ(policy.stats().openings_given_up, 0);
  // Tried once more: both planned for again; a second miss gives the opening up for good.
  EXPECT_EQ(policy.retrySetAside(), 2u);
  EXPECT_EQ(policy.openingsLeft(g), 2u);
  EXPECT_EQ(missUntil(RouteAction::GiveUp), RouteAction::GiveUp);
  EXPECT_EQ(policy.stats().openings_given_up, 1);
  EXPECT_EQ(policy.stats().openings_set_aside, 2);
  // The record marks that opening explored: its node, bearing and width (the width tells it from a
  // door on the same side of the node).
  EXPECT_EQ(last.record.kind, exploration::Request::RecordOpening);
  EXPECT_TRUE(last.record.explored);
  EXPECT_EQ(last.record.node, 2);
  EXPECT_NEAR(last.record.width, 2.0, 1e-9);
  // Given up is never routed to again, even while the map (here never updated: the map builder
  // refused the record) still shows it unexplored: one opening is left, not two.
  EXPECT_EQ(policy.openingsLeft(g), 1u);
  EXPECT_EQ(missUntil(RouteAction::GiveUp), RouteAction::GiveUp);
  EXPECT_EQ(policy.openingsLeft(g), 0u);
  EXPECT_FALSE(policy.plan(g, topo.position, nullptr).found);
  EXPECT_EQ(policy.stats().openings_given_up, 2);
}

// A mission's route that turns into the same branch towards its door again and again (the belief
// moves back to the junction as the robot turns, or flips between two look-alike junctions) goes
// round in circles: a mission once turned into two branches in turn for 390 m until its client gave
// up. After max_route_attempts such turns the door counts as missed (the coordinator resets the
// belief, and ends the mission after mission/max_relocation_failures misses), as after as many
// turns round; the turns count afresh when the belief is reset.
TEST(RoutePolicy, AMissionThatKeepsTurningIntoTheSameBranchMissesItsDoor) {
  using exploration::RouteAction;
  exploration::RoutePolicyParams params;
  exploration::RoutePolicy policy(params, laser_features::BuildingRules());
  // The hallway above, explored, and a branch north at node 2 to a door node 4 with place 7's door.
  TopoGraph g = hallway(true, true);
  g.addNode(GraphNode{4, 0, 10.0, 5.0, {GraphOpening{0.0, 0.9, true, 7, {0.0, 0.0, 0.0}}}});
  g.addEdge(GraphEdge{3, 2, 4, 0.5 * kPi, 5.0});
  const std::optional<exploration::PlaceDoor> door = g.placeDoor(7);
  ASSERT_TRUE(door.has_value());
  GraphPosition junction;  // at the junction, heading east, again and again
  junction.valid = true;
  junction.at_node = true;
  junction.id = 2;
  junction.heading = 0.0;
  const exploration::TopoView topo = localizedAt(junction);
  double travel = 100.0;
  const auto turnAtTheJunction = [&]() {
    travel += 10.0;
    const exploration::RouteStep r = policy.plan(g, topo.position, &*door);
    EXPECT_TRUE(r.found);
    EXPECT_EQ(r.next_node, 2u);
    const exploration::RouteContext at{g, topo, travel, true};
    return policy.atBranch(at, r, true, std::nullopt).kind;
  };
  for (int i = 0; i < params.max_route_attempts; ++i) EXPECT_EQ(turnAtTheJunction(), RouteAction::TurnIntoBranch);
  EXPECT_EQ(turnAtTheJunction(), RouteAction::MissedDoor);
  policy.clearAttempts();  // the belief reset
  EXPECT_EQ(turnAtTheJunction(), RouteAction::TurnIntoBranch);
}

// A door is entered once passed beside the robot. A route that reaches the door's node heading away
// from it (along a branch that leaves beside the door, both at one node) turns at the node into the
// hallway the door was passed on; from that hallway it drives on past the door.
TEST(RoutePolicy, ADoorReachedHeadingAwayFromItIsPassedAlongItsWall) {
  using exploration::RouteAction;
  exploration::RoutePolicyParams params;
  exploration::RoutePolicy policy(params, laser_features::BuildingRules());
  // A hallway north: 0 (start) -- 4.4 m -- 1 (door east, place 3's) -- 1.2 m -- 2 (junction); a
  // branch east from node 1, beside the door, to node 9.
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  g.addNode(GraphNode{1, 0, 0.0, 4.4, {GraphOpening{0.0, 0.85, true, 3, {0.0, 0.0, 0.0}}}});
  g.addNode(GraphNode{2, 1, 0.0, 5.6, {}});
  g.addNode(GraphNode{9, 0, 4.5, 4.4, {}});
  g.addEdge(GraphEdge{0, 0, 1, 0.5 * kPi, 4.4});
  g.addEdge(GraphEdge{1, 1, 2, 0.5 * kPi, 1.2});
  g.addEdge(GraphEdge{8, 1, 9, 0.0, 4.5});
  ASSERT_TRUE(g.headingAlongOpening(1, 0.0).has_value());
  EXPECT_NEAR(*g.headingAlongOpening(1, 0.0), -0.5 * kPi, 1e-12) << "the oldest edge across the door: south";
  EXPECT_FALSE(g.headingAlongOpening(9, 0.0).has_value()) << "node 9's only edge runs straight at a door east";
  const std::optional<exploration::PlaceDoor> door = g.placeDoor(3);
  ASSERT_TRUE(door.has_value());

  // From the branch, heading west to node 1: the door is behind; the last leg runs south.
  const exploration::RouteStep from_branch = policy.plan(g, onEdge(8, 2.0, kPi), &*door);
  ASSERT_TRUE(from_branch.found);
  EXPECT_EQ(from_branch.next_node, 1u);
  EXPECT_NEAR(from_branch.arrival_heading, kPi, 1e-12);
  EXPECT_TRUE(from_branch.door_behind);
  EXPECT_NEAR(from_branch.next_heading, -0.5 * kPi, 1e-12);
  GraphPosition at_node;
  at_node.valid = true;
  at_node.at_node = true;
  at_node.id = 1;
  at_node.heading = kPi;
  const exploration::RouteStep at_door = policy.plan(g, at_node, &*door);
  EXPECT_TRUE(at_door.door_behind);
  const exploration::RouteContext at{g, localizedAt(at_node), 50.0, true};
  const RouteAction turn = policy.atBranch(at, at_door, true, std::nullopt);
  EXPECT_EQ(turn.kind, RouteAction::TurnIntoBranch);

  // Turned south at node 1, or coming from the start heading north: the door is beside the way on,
  // passed and entered, never turned into.
  at_node.heading = -0.5 * kPi;
  const exploration::RouteStep turned = policy.plan(g, at_node, &*door);
  EXPECT_FALSE(turned.door_behind);
  EXPECT_EQ(policy.atBranch(exploration::RouteContext{g, localizedAt(at_node), 60.0, true}, turned, true,
                            std::nullopt).kind,
            RouteAction::None);
  const exploration::RouteStep from_start = policy.plan(g, onEdge(0, 1.0, 0.5 * kPi), &*door);
  EXPECT_FALSE(from_start.door_behind);
  EXPECT_NEAR(from_start.next_heading, 0.0, 1e-12) << "the door's own bearing";
}
