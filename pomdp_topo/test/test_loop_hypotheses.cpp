// Loop hypotheses (Tapus & Siegwart's two belief peaks) on a hand-made graph: which old nodes a new
// node may be, and how the landmarks passed from it on decide between the old place and a new one.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pomdp_topo/loop_hypotheses.h"

using laser_features::HeadingBins;
using pomdp_topo::EdgeLandmark;
using pomdp_topo::Fingerprint;
using pomdp_topo::FingerprintEntry;
using pomdp_topo::LandmarkType;
using pomdp_topo::LoopHypotheses;
using pomdp_topo::MapBuilderParams;
using pomdp_topo::NodeOpening;
using pomdp_topo::NodeType;
using pomdp_topo::PassedLandmark;
using pomdp_topo::TopologicalMap;
using pomdp_topo::TopoNode;

namespace {

constexpr double kPi = 3.14159265358979323846;

uint32_t doorNode(TopologicalMap* map, double x, double y) {
  TopoNode n;
  n.type = NodeType::Door;
  n.pose = laser_features::Pose2D{x, y, 0.0};
  NodeOpening north;
  north.bearing = 0.5 * kPi;
  north.width = 0.9;
  n.openings.push_back(north);
  return map->addNode(n);
}

// An old hallway along +x: a door at x = 0 and another 5 m on (both on the left, north), and a new
// door node just made 0.3 m from the first one, at the end of a stretch come from the west.
struct Ring {
  TopologicalMap map;
  uint32_t old_door = 0, next_door = 0, west = 0, fresh = 0;
  Ring() {
    map.setHeadingBins(HeadingBins{0.0, 4});
    old_door = doorNode(&map, 0.0, 0.0);
    next_door = doorNode(&map, 5.0, 0.0);
    map.addEdge(old_door, next_door, 0.0, 5.0);
    TopoNode w;
    w.type = NodeType::Junction;
    w.pose = laser_features::Pose2D{-6.0, 0.3, 0.0};
    west = map.addNode(w);
    fresh = doorNode(&map, 0.3, 0.1);
    map.addEdge(west, fresh, 0.0, 6.3);
  }
  bool begin(LoopHypotheses* h) const {
    return h->begin(map, MapBuilderParams(), HeadingBins{0.0, 4}, fresh, west, 0.0, 0, 2.0, 10.0);
  }
};

PassedLandmark doorOnTheLeft(double travel) {
  PassedLandmark p;
  p.landmark.type = LandmarkType::Opening;
  p.landmark.lateral = 1.0;
  p.landmark.door = true;
  p.landmark.width = 0.9;
  p.travel = travel;
  p.heading_bin = 0;
  return p;
}

}  // namespace

TEST(FingerprintSimilarity, CountsEachEntryOnceOfItsKindWithinTheTolerance) {
  Fingerprint a, b;
  a.entries = {{FingerprintEntry::Corner, 0.0}, {FingerprintEntry::Corner, 0.05}, {FingerprintEntry::Opening, 1.0}};
  b.entries = {{FingerprintEntry::Corner, 0.1}, {FingerprintEntry::Corner, 2.0}, {FingerprintEntry::Corner, 1.0}};
  EXPECT_DOUBLE_EQ(pomdp_topo::fingerprintSimilarity(a, b, 0.3), 2.0 * 1 / 6);
  EXPECT_DOUBLE_EQ(pomdp_topo::fingerprintSimilarity(a, a, 0.3), 1.0);
  EXPECT_DOUBLE_EQ(pomdp_topo::fingerprintSimilarity(Fingerprint(), b, 0.3), 0.0);
}

// The old door 0.3 m away with the same opening and a way on is the candidate; the junction the
// stretch came from is not (another type, and on the stretch just built).
TEST(LoopHypotheses, AnOldNodeOfTheTypeNearbyWithTheWayOnIsTheCandidate) {
  Ring ring;
  LoopHypotheses h;
  ASSERT_TRUE(ring.begin(&h));
  EXPECT_EQ(h.candidates(), std::vector<uint32_t>{ring.old_door});
  EXPECT_EQ(h.newNode(), ring.fresh);
  EXPECT_DOUBLE_EQ(h.travel0(), 10.0);
  // Going on the other way (west, bin 2) there is nothing beyond the old door to verify against.
  LoopHypotheses west;
  EXPECT_FALSE(west.begin(ring.map, MapBuilderParams(), HeadingBins{0.0, 4}, ring.fresh, ring.west, 0.0, 2, 2.0, 10.0));
}

// The door expected 5 m on is passed there: the old place wins outright; passed at 2.5 m instead,
// where the old place has none, it speaks for a new one.
TEST(LoopHypotheses, TheLandmarksPassedDecideBetweenTheOldPlaceAndANewOne) {
  const Ring ring;
  const MapBuilderParams params;
  LoopHypotheses old_place, new_place;
  ASSERT_TRUE(ring.begin(&old_place));
  ASSERT_TRUE(ring.begin(&new_place));
  const double before = old_place.logOdds();
  old_place.observe(ring.map, params, HeadingBins{0.0, 4}, 0.3, {doorOnTheLeft(15.0)}, {}, 15.3);
  new_place.observe(ring.map, params, HeadingBins{0.0, 4}, 0.3, {doorOnTheLeft(12.5)}, {}, 12.8);
  EXPECT_GT(old_place.logOdds(), before);
  EXPECT_LT(new_place.logOdds(), before);
  EXPECT_GE(old_place.logOdds(), params.loop_decision_log_odds) << "one door where it is expected decides";
  EXPECT_EQ(old_place.bestNode(), ring.old_door);
}
