// The exploration's view of the topological map (pomdp_topo's graph, as published) and the route
// to the nearest unexplored opening: Dijkstra over the edges (as H-SLAM's "nearest node with
// unexplored edges", Lisien et al.), from the robot's most likely state.
//
// An opening counts as unexplored when it is not marked explored and no edge leaves its node in its
// bearing (a branch reached the other way round, e.g. after a loop closure, is explored).
//
// ROS-free: the standard library only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace exploration {

struct GraphOpening {
  double bearing = 0.0;  // rad, map frame, from the node through the opening
  double width = 0.0;    // m, 0 if not measured
  bool explored = false;
  int place_id = -1;     // the place behind this door, -1 if none
  double door_in_place[3] = {0.0, 0.0, 0.0};  // m, m, rad: with place_id >= 0, the door in place_<place_id>
};

struct GraphNode {
  uint32_t id = 0;
  uint8_t type = 0;  // pomdp_topo's TopoNode type: 0 door, 1 junction, 2 hallway end, 3 place, 4 start
  double x = 0.0, y = 0.0;  // m, display pose (for messages only)
  std::vector<GraphOpening> openings;  // each door with the place behind it, if mapped
};

struct GraphEdge {
  uint32_t id = 0;
  uint32_t source = 0;
  uint32_t target = 0;
  double heading = 0.0;  // rad, map frame, travel source -> target
  double length = 0.0;   // m
};

/// The door of a place, as the graph links it: the door node and its opening (which holds the
/// door's pose in the place).
struct PlaceDoor {
  uint32_t node = 0;
  GraphOpening opening;
};

/// Where the belief puts the robot: at a node, or on an edge at an offset from its source.
struct GraphPosition {
  bool valid = false;
  bool at_node = false;
  uint32_t id = 0;       // node id (at_node) or edge id
  double offset = 0.0;   // m, from the edge's source
  double heading = 0.0;  // rad, map frame, the robot's travel heading
};

/// The first step of a route: leave along `heading` (map frame, rad). At the goal node itself the
/// step is the unexplored opening's bearing.
struct RouteStep {
  bool found = false;
  uint32_t goal_node = 0;       // the node with the unexplored opening
  double goal_bearing = 0.0;    // rad, the opening's bearing there
  double goal_width = 0.0;      // m, the opening's width (0 if not measured)
  double distance = 0.0;        // m, along the edges to the goal node
  uint32_t next_node = 0;       // the node the step leads to (the goal node when at it)
  double heading = 0.0;         // rad, map frame, the heading to travel now
  double next_heading = 0.0;    // rad, map frame, the heading to leave next_node by (the goal's
                                // opening when next_node is the goal; see door_behind)
  double arrival_heading = 0.0;  // rad, map frame, the heading the route reaches the goal node with
                                 // (standing at it: the robot's)
  bool door_behind = false;     // the goal is a door the route reaches heading away from it:
                                // next_heading is along its wall (RoutePolicy::plan)
};

class TopoGraph {
 public:
  void clear();
  void addNode(const GraphNode& node);
  void addEdge(const GraphEdge& edge);
  const std::map<uint32_t, GraphNode>& nodes() const { return nodes_; }
  const std::map<uint32_t, GraphEdge>& edges() const { return edges_; }
  const GraphNode* node(uint32_t id) const;
  const GraphEdge* edge(uint32_t id) const;

  /// Whether an edge leaves `node` with a travel heading within `tolerance` (rad) of `heading`.
  bool hasExit(uint32_t node, double heading, double tolerance = 0.5) const;
  /// The heading of the oldest edge leaving `node` along the wall of its opening at `bearing`
  /// (within 45 deg of a right angle to it): the hallway a door there was passed on, since
  /// pomdp_topo makes a door's node at the end of the stretch the robot passed it on. None if no
  /// edge runs so.
  std::optional<double> headingAlongOpening(uint32_t node, double bearing) const;
  /// The unexplored openings of a node (see the file comment).
  std::vector<GraphOpening> unexplored(uint32_t node) const;
  /// Unexplored openings over the whole graph (but those `skip` names).
  size_t unexploredCount() const;
  size_t unexploredCount(const std::function<bool(uint32_t, const GraphOpening&)>& skip) const;
  size_t exploredCount() const;
  /// m, the length of all edges together (no shortest route is longer).
  double edgeLength() const;
  /// Places linked to the graph's nodes (distinct place ids).
  size_t placeCount() const { return placeIds().size(); }
  std::set<int> placeIds() const;

  /// Whether an edge joins the two nodes.
  bool adjacent(uint32_t a, uint32_t b) const;
  /// Shortest distance along the edges between two nodes, m (infinity if unconnected or unknown).
  double distance(uint32_t a, uint32_t b) const;

  /// The node the robot is at, or the edge's end it is nearer (ahead of it when half-way); -1 if
  /// `pos` is not valid or names nothing in the graph.
  int nearestNode(const GraphPosition& pos) const;
  /// The distance along the edge from `pos` to nearestNode(pos) (0 at a node; infinity if none).
  double nearestNodeDistance(const GraphPosition& pos) const;

  /// The route from `pos` to the nearest unexplored opening (distance along the edges; a U-turn on
  /// an edge costs `u_turn_cost` m), but those `skip` names.
  RouteStep route(const GraphPosition& pos, double u_turn_cost = 2.0,
                  const std::function<bool(uint32_t, const GraphOpening&)>& skip = {}) const;
  /// The route from `pos` to one opening of one node (a mission's door).
  RouteStep routeTo(const GraphPosition& pos, uint32_t goal_node, const GraphOpening& opening,
                    double u_turn_cost = 2.0) const;
  /// The door node and opening that link a place; nothing if no door links it.
  std::optional<PlaceDoor> placeDoor(int place_id) const;

 private:
  /// Dijkstra from `pos` to the nearest node where `goal_at` names an opening.
  RouteStep search(const GraphPosition& pos, double u_turn_cost,
                   const std::function<std::optional<GraphOpening>(uint32_t)>& goal_at) const;

  std::map<uint32_t, GraphNode> nodes_;
  std::map<uint32_t, GraphEdge> edges_;
};

}  // namespace exploration
