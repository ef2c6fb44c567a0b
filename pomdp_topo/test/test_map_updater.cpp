// The known map updated while the belief is confident on it: a landmark passed where it is expected
// raises its p_lmap (eq. 4, a running average of the confidences it was seen with); one passed
// without being seen lowers it (eq. 5) and is deleted below p_lmap_min once observed often enough.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pomdp_topo/map_updater.h"

using laser_features::HeadingBins;
using laser_features::Pose2D;
using pomdp_topo::DeadReckoningGate;
using pomdp_topo::EdgeLandmark;
using pomdp_topo::LandmarkType;
using pomdp_topo::MapBuilderParams;
using pomdp_topo::MapUpdater;
using pomdp_topo::NodeType;
using pomdp_topo::PassedLandmark;
using pomdp_topo::PomdpLocalizer;
using pomdp_topo::ScanRecord;
using pomdp_topo::TopologicalMap;
using pomdp_topo::TopoNode;

namespace {
EdgeLandmark corner(double distance, double p_lmap, uint32_t observations) {
  EdgeLandmark l;
  l.type = LandmarkType::Corner;
  l.distance = distance;
  l.lateral = 1.0;
  l.p_lmap = p_lmap;
  l.observations = observations;
  return l;
}
}  // namespace

TEST(MapUpdater, ALandmarkSeenWhereExpectedGainsAndOneMissedLosesUntilDeleted) {
  TopologicalMap map;
  map.setHeadingBins(HeadingBins{0.0, 4});
  TopoNode a, b;
  a.type = b.type = NodeType::Junction;
  b.pose = Pose2D{10.0, 0.0, 0.0};
  const uint32_t ia = map.addNode(a), ib = map.addNode(b);
  const uint32_t edge = map.addEdge(ia, ib, 0.0, 10.0, {corner(5.0, 0.5, 2), corner(6.5, 0.22, 4)});
  PomdpLocalizer localizer;
  localizer.setMap(map);
  const MapBuilderParams params;
  MapUpdater updater(&map, &localizer);
  DeadReckoningGate gate;  // not trusted: no dead-reckoning checks
  std::vector<pomdp_topo::TopoEvent> events;

  // The robot in the cell at 6 m; the corner at 5 m passed (1.25 m behind the cell's centre).
  ASSERT_TRUE(localizer.resetToEdge(edge, 6.0, true));
  ScanRecord scan;
  scan.travel = 20.0;
  PassedLandmark seen;
  seen.landmark.type = LandmarkType::Corner;
  seen.landmark.along = 5.0 - localizer.state(size_t(localizer.mostLikely())).offset;
  seen.landmark.lateral = 1.0;
  seen.landmark.confidence = 1.0;
  seen.travel = 20.0;
  scan.passed = {seen};
  updater.update(scan, params, gate, HeadingBins{0.0, 4}, 0.3, &events);
  const auto& landmarks = [&]() -> const std::vector<EdgeLandmark>& { return map.edge(edge)->landmarks; };
  ASSERT_EQ(landmarks().size(), 2u);
  EXPECT_NEAR(landmarks()[0].p_lmap, (0.5 * 2 + 1.0) / 3, 1e-12);
  EXPECT_EQ(landmarks()[0].observations, 3u);

  // On to 8 m: the corner at 6.5 m is passed unseen (0.22 x 4 / 5 < p_lmap_min 0.2, five
  // observations): deleted; the one at 5 m was passed before and keeps its count.
  ASSERT_TRUE(localizer.resetToEdge(edge, 8.0, true));
  scan.passed.clear();
  scan.travel = 22.0;
  updater.update(scan, params, gate, HeadingBins{0.0, 4}, 0.3, &events);
  ASSERT_EQ(landmarks().size(), 1u);
  EXPECT_DOUBLE_EQ(landmarks()[0].distance, 5.0);
  EXPECT_EQ(landmarks()[0].observations, 3u);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, pomdp_topo::TopoEvent::Kind::LandmarkDeleted) << events.back().text;
  EXPECT_GE(events.back().edge, 0);
}
