// TopologicalMap's bookkeeping: openings recorded by the exploration, and node merging (loop
// closing) with stretches that turn out to be one hallway.
#include <gtest/gtest.h>

#include <cmath>

#include "pomdp_topo/topological_map.h"

using namespace pomdp_topo;

namespace {
constexpr double kPi = 3.14159265358979323846;

TopoNode nodeAt(NodeType type, double x, double y) {
  TopoNode n;
  n.type = type;
  n.pose = Pose2D{x, y, 0.0};
  return n;
}
}  // namespace

TEST(TopologicalMap, RecordOpeningAddsOrUpdatesAndKeepsExplored) {
  TopologicalMap map;
  const uint32_t a = map.addNode(nodeAt(NodeType::Door, 0, 0));
  const uint64_t rev = map.revision();
  NodeOpening o;
  o.bearing = 0.5 * kPi;
  o.width = 0.9;
  ASSERT_TRUE(map.recordOpening(a, o));
  ASSERT_EQ(map.node(a)->openings.size(), 1u);
  EXPECT_FALSE(map.node(a)->explored);
  o.bearing = 0.5 * kPi + 0.2;  // the same opening, seen a little differently
  o.explored = true;
  ASSERT_TRUE(map.recordOpening(a, o));
  ASSERT_EQ(map.node(a)->openings.size(), 1u);
  EXPECT_TRUE(map.node(a)->openings[0].explored);
  EXPECT_TRUE(map.node(a)->explored);
  o.explored = false;  // an explored opening stays explored
  ASSERT_TRUE(map.recordOpening(a, o));
  EXPECT_TRUE(map.node(a)->openings[0].explored);
  o.bearing = -0.5 * kPi;  // another one
  ASSERT_TRUE(map.recordOpening(a, o));
  EXPECT_EQ(map.node(a)->openings.size(), 2u);
  EXPECT_FALSE(map.node(a)->explored);
  EXPECT_EQ(map.revision(), rev);  // bookkeeping, no structural change
  EXPECT_FALSE(map.recordOpening(99, o));
  o.bearing = std::nan("");
  EXPECT_FALSE(map.recordOpening(a, o));
}

TEST(TopologicalMap, ADoorBesideAJunctionsBranchIsAnotherOpening) {
  // Institute: the coordinator entered a door 3 m past hall_link's junction, which pomdp_topo had
  // not made a node of; recorded at the junction (the robot's node), it marked the branch on the
  // same side explored and the north half of the building was never visited.
  TopologicalMap map;
  const uint32_t j = map.addNode(nodeAt(NodeType::Junction, 0, 0));
  NodeOpening branch;
  branch.bearing = 0.5 * kPi;
  branch.width = 2.18;
  ASSERT_TRUE(map.recordOpening(j, branch));
  NodeOpening door;
  door.bearing = 0.5 * kPi + 0.05;
  door.width = 0.9;
  door.explored = true;
  ASSERT_TRUE(map.recordOpening(j, door));
  ASSERT_EQ(map.node(j)->openings.size(), 2u);
  EXPECT_FALSE(map.node(j)->openings[0].explored) << "the branch was marked explored by the door";
  EXPECT_TRUE(map.node(j)->openings[1].explored);
  EXPECT_FALSE(map.node(j)->explored);
  NodeOpening unmeasured;  // no width: the same opening as before
  unmeasured.bearing = 0.5 * kPi;
  ASSERT_TRUE(map.recordOpening(j, unmeasured));
  EXPECT_EQ(map.node(j)->openings.size(), 2u);
}

TEST(TopologicalMap, ADoorMeasuredAnotherWidthIsTheSameDoor) {
  // large_floor: a door measured 0.66 m wide on the first pass and 1.28 m after a U-turn was taken
  // for a second opening of its own node, and the known room behind it was entered as a new one.
  TopologicalMap map;  // the default building rules: doors up to 1.3 m
  const uint32_t d = map.addNode(nodeAt(NodeType::Door, 0, 0));
  NodeOpening first;
  first.bearing = 0.5 * kPi;
  first.width = 0.66;
  first.explored = true;
  ASSERT_TRUE(map.recordOpening(d, first));
  NodeOpening again = first;
  again.width = 1.28;
  again.explored = false;
  ASSERT_TRUE(map.recordOpening(d, again));
  ASSERT_EQ(map.node(d)->openings.size(), 1u) << "one door, measured twice, became two openings";
  EXPECT_TRUE(map.node(d)->explored);
  // Door against branch still tells apart; within BuildingRules::kWidthSpread nothing does; nor does no width.
  EXPECT_TRUE(map.differentOpenings(0.9, 2.18));
  EXPECT_FALSE(map.differentOpenings(0.66, 1.28));
  EXPECT_FALSE(map.differentOpenings(1.2, 1.5));
  EXPECT_FALSE(map.differentOpenings(0.0, 2.18));
  // The limit is the map's: with hallways from 1.1 m, 0.66 and 1.28 are a door and a branch.
  laser_features::BuildingRules narrow;
  narrow.hallway_min_width = 1.1;
  map.setBuildingRules(narrow);
  EXPECT_TRUE(map.differentOpenings(0.66, 1.28));
}

TEST(TopologicalMap, MergingKeepsAnOpeningExploredFromEitherCopy) {
  TopologicalMap map;
  const uint32_t a = map.addNode(nodeAt(NodeType::Door, 0, 0));
  const uint32_t b = map.addNode(nodeAt(NodeType::Door, 0.2, 0));
  NodeOpening o;
  o.bearing = 0.5 * kPi;
  map.recordOpening(a, o);
  o.explored = true;
  map.recordOpening(b, o);
  ASSERT_TRUE(map.mergeNodes(a, b));
  ASSERT_EQ(map.node(a)->openings.size(), 1u);
  EXPECT_TRUE(map.node(a)->openings[0].explored);
}

// small_loop under load: the returning stretch 6 -> 7 (door) -> 8 (junction) had its loop
// hypothesis "7 is 1" rejected, then closed at 8 = 2. 7 and 1 are then both 2.7-3 m behind 2 the
// same way: one door recorded twice. `second_y`: where the dead reckoning put 6 and 7.
struct ClosedLoopScene {
  TopologicalMap map;
  uint32_t s, d, j, j6, d7, j8;
  explicit ClosedLoopScene(double second_y) {
    NodeOpening left;
    left.bearing = 0.5 * kPi;
    s = map.addNode(nodeAt(NodeType::Start, 2, 0));
    d = map.addNode(nodeAt(NodeType::Door, 12, 0));
    j = map.addNode(nodeAt(NodeType::Junction, 14.74, 0));
    j6 = map.addNode(nodeAt(NodeType::Junction, 1, second_y));
    d7 = map.addNode(nodeAt(NodeType::Door, 11.98, second_y));
    j8 = map.addNode(nodeAt(NodeType::Junction, 14.94, 0));
    for (uint32_t n : {d, j, j6, d7, j8}) map.recordOpening(n, left);
    map.addEdge(s, d, 0.0, 10.0);
    map.addEdge(d, j, 0.0, 2.74);
    map.addEdge(j6, d7, 0.0, 10.98);
    map.addEdge(d7, j8, 0.0, 2.96);
  }
};

TEST(TopologicalMap, ANodeRecordedTwiceBehindAClosedLoopIsZipped) {
  // The door recorded twice is merged too; 6 -> 1 then runs through the start 0.
  ClosedLoopScene scene(0.0);
  TopologicalMap& map = scene.map;
  const uint32_t s = scene.s, d = scene.d, j = scene.j, j6 = scene.j6, d7 = scene.d7, j8 = scene.j8;
  std::vector<std::pair<uint32_t, uint32_t>> zipped;
  ASSERT_TRUE(map.mergeNodes(j, j8, &zipped));
  ASSERT_EQ(zipped.size(), 1u);
  EXPECT_EQ(zipped[0], std::make_pair(d, d7));
  EXPECT_EQ(map.node(d7), nullptr);
  ASSERT_EQ(map.nodeCount(), 4u);
  ASSERT_EQ(map.edgeCount(), 3u);
  for (const auto& [id, e] : map.edges()) {
    if (e.source == j6) {
      EXPECT_EQ(e.target, s);
      EXPECT_NEAR(e.length, 0.98, 1e-9);
    } else if (e.source == d) {
      EXPECT_EQ(e.target, j);
      EXPECT_NEAR(e.length, 0.5 * (2.74 + 2.96), 1e-9);
    } else {
      EXPECT_EQ(e.source, s);
      EXPECT_EQ(e.target, d);
    }
  }
  // The same with the second door recorded 30 m away (the dead reckoning disagrees): not zipped
  // when zips are limited to 15 m.
  {
    ClosedLoopScene far(30.0);
    std::vector<std::pair<uint32_t, uint32_t>> kept_apart;
    ASSERT_TRUE(far.map.mergeNodes(far.j, far.j8, &kept_apart, 15.0));
    EXPECT_TRUE(kept_apart.empty());
    EXPECT_NE(far.map.node(far.d7), nullptr);
  }
  // A junction and a door the same distance behind are two places: left alone.
  TopologicalMap other;
  const uint32_t a = other.addNode(nodeAt(NodeType::Junction, 0, 0));
  const uint32_t b = other.addNode(nodeAt(NodeType::Junction, 3, 0));
  const uint32_t c = other.addNode(nodeAt(NodeType::Door, 0.2, 0));
  const uint32_t b2 = other.addNode(nodeAt(NodeType::Junction, 3.1, 0));
  other.addEdge(a, b, 0.0, 3.0);
  other.addEdge(c, b2, 0.0, 2.9);
  std::vector<std::pair<uint32_t, uint32_t>> none;
  ASSERT_TRUE(other.mergeNodes(b, b2, &none));
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(other.nodeCount(), 3u);
}

TEST(TopologicalMap, EachDoorOfANodeLinksItsOwnPlaceAndKeepsItsFirst) {
  // institute's library and office_11, and large_floor's rows of rooms: two doors facing each other
  // across the hallway are one node. Each door links the room behind it (with one place per node,
  // the second room was mapped but missions could not name it: 27 of 158 on large_floor).
  TopologicalMap map;
  const uint32_t n = map.addNode(nodeAt(NodeType::Door, 0, 0));
  NodeOpening north, south;
  north.bearing = 0.5 * kPi;
  north.width = 1.2;
  south.bearing = -0.5 * kPi;
  south.width = 0.9;
  map.recordOpening(n, north);
  map.recordOpening(n, south);
  ASSERT_TRUE(map.linkPlace(n, south, 18, Pose2D{0.1, 0.2, 0.3}));
  ASSERT_TRUE(map.linkPlace(n, north, 19, Pose2D{-0.4, 0.5, 0.6}));
  const NodeOpening* s18 = TopologicalMap::placeDoor(*map.node(n), 18);
  const NodeOpening* n19 = TopologicalMap::placeDoor(*map.node(n), 19);
  ASSERT_NE(s18, nullptr);
  ASSERT_NE(n19, nullptr);
  EXPECT_NEAR(s18->bearing, -0.5 * kPi, 1e-9);
  EXPECT_NEAR(s18->door_in_place.y, 0.2, 1e-9);
  EXPECT_NEAR(n19->bearing, 0.5 * kPi, 1e-9);
  EXPECT_NEAR(n19->door_in_place.x, -0.4, 1e-9);
  EXPECT_EQ(TopologicalMap::placeDoor(*map.node(n), 20), nullptr);
  // A door keeps its first place: the room entered again through it is not linked a second time.
  int32_t linked = -1;
  EXPECT_FALSE(map.linkPlace(n, south, 21, Pose2D{}, &linked));
  EXPECT_EQ(linked, 18);
  EXPECT_NEAR(TopologicalMap::placeDoor(*map.node(n), 18)->door_in_place.y, 0.2, 1e-9);
  EXPECT_TRUE(map.linkPlace(n, south, 18, Pose2D{0.1, 0.2, 0.3}));  // the same place again
  // A door that is not recorded links nothing.
  NodeOpening east;
  east.bearing = 0.0;
  EXPECT_FALSE(map.linkPlace(n, east, 22, Pose2D{}));
  // A merge keeps both rooms on the kept node, at their doors.
  const uint32_t k = map.addNode(nodeAt(NodeType::Door, 0.1, 0));
  map.recordOpening(k, north);
  ASSERT_TRUE(map.mergeNodes(k, n));
  ASSERT_EQ(map.node(k)->openings.size(), 2u);
  ASSERT_NE(TopologicalMap::placeDoor(*map.node(k), 18), nullptr);
  ASSERT_NE(TopologicalMap::placeDoor(*map.node(k), 19), nullptr);
  EXPECT_NEAR(TopologicalMap::placeDoor(*map.node(k), 18)->bearing, -0.5 * kPi, 1e-9);
  EXPECT_NEAR(TopologicalMap::placeDoor(*map.node(k), 19)->bearing, 0.5 * kPi, 1e-9);
  EXPECT_FALSE(map.linkPlace(99, south, 1, Pose2D{}));
}

TEST(TopologicalMap, AStretchPastAnUnrecognizedNodeIsCutThere) {
  // A hallway along +x: start S at x 2, door D at x 12 (edge S -> D, 10 m). The loop comes back
  // from a corner C at x 1 heading east and closes at a new door D' (11 m from C), merged into D:
  // C -> D (11 m) and S -> D (10 m) leave D the same way, so S lies on C -> D: C -> S, 1 m.
  TopologicalMap map;
  const uint32_t s = map.addNode(nodeAt(NodeType::Start, 2, 0));
  const uint32_t d = map.addNode(nodeAt(NodeType::Door, 12, 0));
  const uint32_t c = map.addNode(nodeAt(NodeType::Junction, 1, 0));
  const uint32_t d2 = map.addNode(nodeAt(NodeType::Door, 12.1, 0));
  map.addEdge(s, d, 0.0, 10.0);
  EdgeLandmark near_c, near_d;
  near_c.distance = 0.5;   // on the part C..S: dropped (S's side has its own)
  near_d.distance = 6.0;   // 5 m past S
  map.addEdge(c, d2, 0.0, 11.0, {near_c, near_d});
  ASSERT_TRUE(map.mergeNodes(d, d2));
  ASSERT_EQ(map.edgeCount(), 2u);
  bool found = false;
  for (const auto& [id, e] : map.edges()) {
    if (e.source == c) {
      found = true;
      EXPECT_EQ(e.target, s);
      EXPECT_NEAR(e.length, 1.0, 1e-9);
      EXPECT_TRUE(e.landmarks.empty() || e.landmarks[0].distance <= 1.0);
    } else {
      EXPECT_EQ(e.source, s);
      EXPECT_EQ(e.target, d);
    }
  }
  EXPECT_TRUE(found);
  // Stretches leaving a node different ways are left alone.
  TopologicalMap other;
  const uint32_t x = other.addNode(nodeAt(NodeType::Junction, 0, 0));
  const uint32_t y = other.addNode(nodeAt(NodeType::Door, 5, 0));
  const uint32_t z = other.addNode(nodeAt(NodeType::Door, 0, 5));
  const uint32_t z2 = other.addNode(nodeAt(NodeType::Door, 0.1, 0));
  other.addEdge(x, y, 0.0, 5.0);
  other.addEdge(z, z2, -0.5 * kPi, 5.0);
  ASSERT_TRUE(other.mergeNodes(x, z2));
  for (const auto& [id, e] : other.edges()) EXPECT_NEAR(e.length, 5.0, 1e-9);
}

// A staggered crossing: the hallway's west part leaves node `north`, its east part node `south`
// 1.2 m away across the stem (shorter than the narrowest hallway, 1.5 m). Driving on east from
// `north`, or west from `south`, goes on along the other node's edge; a link as long as a hallway
// is wide, or one along the way (behind the node), carries nothing on.
TEST(TopologicalMap, AStaggeredCrossingCarriesTheWayOnAcrossItsShortLink) {
  for (const double link : {1.2, 1.6}) {
    TopologicalMap map;
    const uint32_t south = map.addNode(nodeAt(NodeType::Junction, 0, 0));
    const uint32_t north = map.addNode(nodeAt(NodeType::Junction, 0, link));
    const uint32_t east = map.addNode(nodeAt(NodeType::Door, 6, 0));
    const uint32_t west = map.addNode(nodeAt(NodeType::Door, -6, link));
    map.addEdge(south, north, 0.5 * kPi, link);
    const uint32_t to_east = map.addEdge(south, east, 0.0, 6.0);
    const uint32_t to_west = map.addEdge(north, west, kPi, 6.0);
    EdgeExit x;
    EXPECT_FALSE(map.exitWithHeading(north, 0.0, 0.25 * kPi, &x));
    const bool staggered = link < map.buildingRules().hallway_min_width;
    ASSERT_EQ(map.wayOn(north, 0.0, 0.25 * kPi, &x), staggered) << "link " << link;
    if (staggered) {
      EXPECT_EQ(x.edge, to_east);
      EXPECT_EQ(x.other, east);
    }
    ASSERT_EQ(map.wayOn(south, kPi, 0.25 * kPi, &x), staggered);
    if (staggered) EXPECT_EQ(x.edge, to_west);
    // Its own exit first.
    ASSERT_TRUE(map.wayOn(south, 0.0, 0.25 * kPi, &x));
    EXPECT_EQ(x.edge, to_east);
    // Not across the link's own direction: north of `north` there is no way.
    EXPECT_FALSE(map.wayOn(north, 0.5 * kPi, 0.25 * kPi, &x));
    EXPECT_FALSE(map.wayOn(east, 0.5 * kPi, 0.25 * kPi, &x));
  }
}

// A node with an opening of its own the way on has a branch of its own there (to be mapped), not
// its neighbour's: at the end of a wide hallway a robot that turns twice within 1.4 m is on the
// hallway's other side, and the opening it recorded is explored as such.
TEST(TopologicalMap, ANodesOwnOpeningIsNotCarriedOnToItsNeighbour) {
  TopologicalMap map;
  const uint32_t south = map.addNode(nodeAt(NodeType::Junction, 0, 0));
  const uint32_t north = map.addNode(nodeAt(NodeType::Junction, 0, 1.2));
  const uint32_t east = map.addNode(nodeAt(NodeType::Door, 6, 0));
  map.addEdge(south, north, 0.5 * kPi, 1.2);
  map.addEdge(south, east, 0.0, 6.0);
  EdgeExit x;
  ASSERT_TRUE(map.wayOn(north, 0.0, 0.25 * kPi, &x));
  NodeOpening own;
  own.bearing = 0.0;
  own.width = 1.7;
  ASSERT_TRUE(map.recordOpening(north, own));
  EXPECT_TRUE(map.hasOpeningToward(north, 0.1));
  EXPECT_FALSE(map.wayOn(north, 0.0, 0.25 * kPi, &x));
}
