// The exploration ends when it makes no progress: hallway travel of (max_route_attempts + 1) times
// the graph's edge length with no new ground, node or place and no opening explored or given up.
#include <gtest/gtest.h>

#include "exploration/progress_watch.h"
#include "exploration/topo_route.h"

using exploration::GraphEdge;
using exploration::GraphNode;
using exploration::GraphOpening;
using exploration::ProgressWatch;
using exploration::TopoGraph;

namespace {

// A corridor of `nodes` nodes, `edge_length` m of edges in all; `places` openings linked to a place
// and `explored` more openings explored (none linked).
TopoGraph corridor(uint32_t nodes, double edge_length, int places = 0, int explored = 0) {
  TopoGraph g;
  for (uint32_t id = 0; id < nodes; ++id) {
    GraphNode n;
    n.id = id;
    g.addNode(n);
  }
  for (uint32_t id = 1; id < nodes; ++id) g.addEdge(GraphEdge{id, id - 1, id, 0.0, edge_length / (nodes - 1)});
  GraphNode n;
  n.id = nodes;  // the openings on a node of their own, off the edges' headings
  for (int k = 0; k < places; ++k) {
    GraphOpening o;
    o.bearing = 1.5;
    o.explored = true;
    o.place_id = k;
    n.openings.push_back(o);
  }
  for (int k = 0; k < explored; ++k) {
    GraphOpening o;
    o.bearing = -1.5;
    o.explored = true;
    n.openings.push_back(o);
  }
  g.addNode(n);
  return g;
}

}  // namespace

// A belief lost for good on a map of 30 m of hallways: with three route attempts, 120 m of
// hallway travel without progress end it, not 119 m.
TEST(ProgressWatch, ALostBeliefEndsTheExplorationAfterAsManyWalksOverTheMapAsTheRouteWould) {
  ProgressWatch watch(3);
  watch.mapChanged(corridor(4, 30.0, 2, 1));
  EXPECT_FALSE(watch.stalled(200.0, false, 0));  // progress last seen at 200 m
  EXPECT_FALSE(watch.stalled(319.0, false, 0));
  EXPECT_DOUBLE_EQ(watch.window(), 120.0);
  watch.mapChanged(corridor(4, 30.0, 2, 1));  // the same map published again is no progress
  EXPECT_TRUE(watch.stalled(321.0, false, 0));
  EXPECT_NEAR(watch.sinceProgress(), 121.0, 1e-9);
  EXPECT_NE(watch.why().find("121 m"), std::string::npos) << watch.why();
}

// Each kind of progress starts the window again: a node, a place, an opening explored, an opening
// given up (the route moves on to another), and travel on a new stretch (new ground).
TEST(ProgressWatch, AnyProgressStartsTheWindowAgain) {
  const TopoGraph base = corridor(3, 10.0, 1, 1);
  const TopoGraph changed[] = {corridor(4, 10.0, 1, 1), corridor(3, 10.0, 2, 1), corridor(3, 10.0, 1, 2)};
  for (const TopoGraph& g : changed) {
    ProgressWatch watch(3);
    watch.mapChanged(base);
    watch.stalled(0.0, false, 0);
    EXPECT_FALSE(watch.stalled(39.0, false, 0));
    watch.mapChanged(g);
    EXPECT_FALSE(watch.stalled(39.5, false, 0));
    EXPECT_FALSE(watch.stalled(79.0, false, 0));
    EXPECT_TRUE(watch.stalled(80.0, false, 0));
  }
  ProgressWatch watch(3);
  watch.mapChanged(base);
  watch.stalled(0.0, false, 0);
  EXPECT_FALSE(watch.stalled(39.5, false, 1)) << "an opening given up";
  EXPECT_FALSE(watch.stalled(79.0, false, 1));
  EXPECT_TRUE(watch.stalled(80.0, false, 1));
  EXPECT_FALSE(watch.stalled(119.0, true, 1)) << "a new stretch is new ground";
  EXPECT_FALSE(watch.stalled(158.0, false, 1));
  EXPECT_TRUE(watch.stalled(160.0, false, 1));
}

// Before the graph has an edge the robot is on its first stretch: nothing to measure against.
TEST(ProgressWatch, NeverWhileTheGraphHasNoEdge) {
  ProgressWatch watch(3);
  watch.stalled(0.0, false, 0);
  EXPECT_FALSE(watch.stalled(500.0, false, 0));
  watch.mapChanged(corridor(1, 0.0));
  EXPECT_FALSE(watch.stalled(1000.0, false, 0));
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
