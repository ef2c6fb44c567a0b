// The exploration ends when it makes no progress: hallway travel of (max_route_attempts + 1) times
// the graph's edge length with no new ground, node or place and no opening explored or given up.
#include <gtest/gtest.h>

#include "exploration/progress_watch.h"
#include "exploration/topo_route.h"

using exploration::GraphEdge;
using exploration::GraphNode;
using exploration::ProgressCounts;
using exploration::ProgressWatch;
using exploration::TopoGraph;

// A belief lost for good on a map of 30 m of hallways: with three route attempts, 120 m of
// hallway travel without progress end it, not 119 m.
TEST(ProgressWatch, ALostBeliefEndsTheExplorationAfterAsManyWalksOverTheMapAsTheRouteWouldTry) {
  ProgressWatch watch(3);
  const ProgressCounts counts{5, 3, 6, 0};
  EXPECT_FALSE(watch.stalled(200.0, false, counts, 30.0));  // progress last seen at 200 m
  EXPECT_FALSE(watch.stalled(319.0, false, counts, 30.0));
  EXPECT_DOUBLE_EQ(watch.window(), 120.0);
  EXPECT_TRUE(watch.stalled(321.0, false, counts, 30.0));
  EXPECT_NEAR(watch.sinceProgress(), 121.0, 1e-9);
  EXPECT_NE(watch.why().find("121 m"), std::string::npos) << watch.why();
}

// Each kind of progress starts the window again: a node, a place, an opening explored, an opening
// given up (the route moves on to another), and travel on a new stretch (new ground).
TEST(ProgressWatch, AnyProgressStartsTheWindowAgain) {
  const ProgressCounts base{5, 3, 6, 0};
  const ProgressCounts changed[] = {{6, 3, 6, 0}, {5, 4, 6, 0}, {5, 3, 7, 0}, {5, 3, 6, 1}};
  for (const ProgressCounts& c : changed) {
    ProgressWatch watch(3);
    watch.stalled(0.0, false, base, 10.0);
    EXPECT_FALSE(watch.stalled(39.0, false, base, 10.0));
    EXPECT_FALSE(watch.stalled(39.5, false, c, 10.0));
    EXPECT_FALSE(watch.stalled(79.0, false, c, 10.0));
    EXPECT_TRUE(watch.stalled(80.0, false, c, 10.0));
  }
  ProgressWatch watch(3);
  watch.stalled(0.0, false, base, 10.0);
  EXPECT_FALSE(watch.stalled(39.0, true, base, 10.0)) << "a new stretch is new ground";
  EXPECT_FALSE(watch.stalled(78.0, false, base, 10.0));
  EXPECT_TRUE(watch.stalled(80.0, false, base, 10.0));
}

// Before the graph has an edge the robot is on its first stretch: nothing to measure against.
TEST(ProgressWatch, NeverWhileTheGraphHasNoEdge) {
  ProgressWatch watch(3);
  const ProgressCounts counts{1, 0, 0, 0};
  EXPECT_FALSE(watch.stalled(0.0, false, counts, 0.0));
  EXPECT_FALSE(watch.stalled(500.0, false, counts, 0.0));
}

TEST(TopoGraph, EdgeLengthIsAllEdgesTogether) {
  TopoGraph g;
  for (uint32_t id = 0; id < 3; ++id) {
    GraphNode n;
    n.id = id;
    g.addNode(n);
  }
  EXPECT_EQ(g.edgeLength(), 0.0);
  g.addEdge(GraphEdge{0, 0, 1, 0.0, 4.5});
  g.addEdge(GraphEdge{1, 1, 2, 1.57, 7.25});
  EXPECT_DOUBLE_EQ(g.edgeLength(), 11.75);
}
