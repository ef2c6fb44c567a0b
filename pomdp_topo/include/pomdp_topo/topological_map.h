// The global topological map (Tomatis et al. 2001, section 3.3; Tapus & Siegwart for fingerprints).
//
// Nodes are openings (doors into rooms, hallway junctions and turns), hallway ends and the robot's
// start; a door node links to a place (a local metric map of ekf_local_map) by its id and the
// door's pose in the place frame. Edges are hallway stretches between two nodes, stored once with
// the direction of travel from source to target (the reverse travel has heading + pi), an estimated
// length, and the ordered landmarks (corners) between the two nodes.
//
// Headings are general angles in the map frame; the building's axes (rectilinear buildings: N, E,
// S, W) only enter through TopoParams::heading_bins of the localizer, not here.
#pragma once

#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pomdp_topo {

using laser_features::Pose2D;

enum class NodeType : uint8_t { Door = 0, Junction = 1, HallwayEnd = 2, Place = 3, Start = 4 };
enum class LandmarkType : uint8_t { Corner = 0, Opening = 1 };

const char* toString(NodeType type);
const char* toString(LandmarkType type);

/// A landmark along an edge, in the edge's frame: travel from source to target along +x, left +y.
struct EdgeLandmark {
  LandmarkType type = LandmarkType::Corner;
  double distance = 0.0;     // m, along the edge from its source node
  double lateral = 0.0;      // m, signed offset from the edge's mid-line, + on the left of travel
  double orientation = 0.0;  // rad, relative to the direction of travel source -> target, (-pi, pi]
  double p_lmap = 0.5;       // probability of seeing the landmark when passing it (eqs. 4-5)
  uint32_t observations = 0; // how many passes contributed to p_lmap (running average, eq. 4)
};

/// The side of a landmark or opening from its lateral offset (m, left positive): +1 left, -1 right.
inline double sideOf(double lateral) { return lateral >= 0.0 ? 1.0 : -1.0; }

/// An opening at a node: a door into a room, or a hallway branch at a junction.
struct NodeOpening {
  double bearing = 0.0;  // rad, map frame: the direction from the node's centre through the opening,
                         // turned onto the heading bins (a side door: perpendicular to the bin of the
                         // hallway it was seen from). The graph matches openings and turns by it.
  double offset = 0.0;   // m, from the node's centre to the opening's centre along direction()
  double width = 0.0;    // m
  bool explored = false; // the robot went through it (a room mapped or a hallway stretch followed)
  int32_t place_id = -1; // the place (local metric map) behind this door, -1 if none: each door of a
                         // node links its own (doors facing each other across a hallway are one node)
  Pose2D door_in_place;  // with place_id >= 0: the door's pose in the frame place_<place_id>
  double skew = 0.0;     // rad: the hallway's angle to that bin where a side door was seen (a wing's,
                         // 30-60 deg off the building's axes; 0 along them). See direction().

  /// The direction from the node's centre through the opening as it is (rad, map frame): a wing's
  /// door faces across the wing, not across the bin its hallway was followed in.
  double direction() const { return laser_features::normalizeAngle(bearing + skew); }
};

/// One entry of a fingerprint: a feature seen around the robot at the node.
struct FingerprintEntry {
  enum Kind : uint8_t { Corner = 0, Opening = 1, LineDirection = 2 };
  Kind kind = Corner;
  double bearing = 0.0;  // rad, map frame, direction from the node's centre to the feature
};

/// The circular sequence of features around a node (Tapus & Siegwart), ordered by bearing.
struct Fingerprint {
  std::vector<FingerprintEntry> entries;
  /// Sorts entries by bearing in (-pi, pi].
  void normalize();
};

struct TopoNode {
  uint32_t id = 0;
  NodeType type = NodeType::Junction;
  Pose2D pose;                 // display pose in the map frame (dead reckoning; not metric truth)
  std::vector<NodeOpening> openings;  // each door with the place behind it, if mapped
  Fingerprint fingerprint;
  bool explored = false;       // every opening has been visited
};

struct TopoEdge {
  uint32_t id = 0;
  uint32_t source = 0;
  uint32_t target = 0;
  double heading = 0.0;  // rad, map frame, direction of travel source -> target
  double length = 0.0;   // m
  std::vector<EdgeLandmark> landmarks;  // ordered by distance
  /// Sorts landmarks by distance.
  void sortLandmarks();
};

/// One way of leaving a node along an edge.
struct EdgeExit {
  uint32_t edge = 0;
  bool forward = true;   // true: the node is the edge's source and the travel goes source -> target
  double heading = 0.0;  // rad, heading of that travel
  uint32_t other = 0;    // the node at the far end
};

class TopologicalMap {
 public:
  /// Adds a node; its id is assigned (the `id` of `node` is ignored) and returned.
  uint32_t addNode(TopoNode node);
  /// Adds an edge between two existing nodes; returns its id, or throws std::invalid_argument
  /// for an unknown node, a self-loop, or a non-finite or negative length.
  uint32_t addEdge(uint32_t source, uint32_t target, double heading, double length,
                   std::vector<EdgeLandmark> landmarks = {});
  /// Removes a node and every edge touching it. Returns false if there is no such node.
  bool removeNode(uint32_t id);
  bool removeEdge(uint32_t id);
  /// Merges node `drop` into node `keep` (loop closing): edges of `drop` are re-attached to `keep`,
  /// openings not already present at `keep` (same bearing within 0.35 rad) are added, `drop` is
  /// removed. Edges that would become duplicates (same two nodes, same heading within 0.35 rad) are
  /// merged: the longer-observed one is kept and the lengths averaged. Two stretches leaving `keep`
  /// the same way to different nodes are one hallway: the longer is cut at the shorter one's far
  /// node (a loop closed past a node the returning stretch did not recognize, such as the start).
  /// Two such stretches of about the same length (within 0.5 m) to nodes of the same type with an
  /// opening on the same side end at one place recorded twice: those nodes are merged in turn (the
  /// older id kept), and so on along the stretch, unless their display poses lie more than
  /// `max_zip_distance` (m) apart; each such pair (keep, drop) is appended to `also_merged`.
  /// Returns false for unknown ids.
  bool mergeNodes(uint32_t keep, uint32_t drop, std::vector<std::pair<uint32_t, uint32_t>>* also_merged = nullptr,
                  double max_zip_distance = std::numeric_limits<double>::infinity());

  /// Two measured widths name two openings at one bearing only where one is a door and the other
  /// a branch (a door beside a junction's branch): BuildingRules::differentOpenings with this map's
  /// rules.
  bool differentOpenings(double width_a, double width_b) const { return rules_.differentOpenings(width_a, width_b); }
  /// The building rules that tell a door's width from a junction's (MapBuilder sets its own).
  void setBuildingRules(const laser_features::BuildingRules& rules) { rules_ = rules; }
  const laser_features::BuildingRules& buildingRules() const { return rules_; }
  /// The heading bins the map's bearings and headings lie on (MapBuilder sets its own): two of
  /// them are one way within HeadingBins::sameWayTolerance.
  void setHeadingBins(const laser_features::HeadingBins& bins) { bins_ = bins; }
  const laser_features::HeadingBins& headingBins() const { return bins_; }
  /// Records an opening of node `id` (the exploration's bookkeeping): the opening the same way
  /// (HeadingBins::sameWay) as `opening.bearing` is updated (explored stays once set; offset and
  /// width are taken when it had no width), else `opening` is added; two widths that
  /// differentOpenings tells apart are two openings (a door beside a junction's branch on the same
  /// side must not mark the branch explored); the node's `explored` flag
  /// becomes "every opening explored". No structural change: the revision is not bumped (the
  /// localizer's states stay). False for an unknown node or a non-finite bearing.
  bool recordOpening(uint32_t id, const NodeOpening& opening);
  /// Links place `place_id` (its door at `door_in_place` in the place's frame) to the opening of
  /// node `id` that matches `door` (as recordOpening matches; record it first). A door links one
  /// place, the first: false (no change) when it links another already, for an unknown node, no
  /// such opening or a negative id. Doors facing each other across a hallway are one node with two
  /// openings, each linking its own room. `linked` (if given) gets the place the door links after the call.
  bool linkPlace(uint32_t id, const NodeOpening& door, int32_t place_id, const Pose2D& door_in_place,
                 int32_t* linked = nullptr);
  /// The node's opening that links place `place_id`, nullptr if none.
  static const NodeOpening* placeDoor(const TopoNode& node, int32_t place_id);

  const TopoNode* node(uint32_t id) const;
  TopoNode* node(uint32_t id);
  const TopoEdge* edge(uint32_t id) const;
  TopoEdge* edge(uint32_t id);
  const std::map<uint32_t, TopoNode>& nodes() const { return nodes_; }
  const std::map<uint32_t, TopoEdge>& edges() const { return edges_; }
  size_t nodeCount() const { return nodes_.size(); }
  size_t edgeCount() const { return edges_.size(); }
  bool empty() const { return nodes_.empty(); }

  /// Every way to leave `node` along an edge (both directions of the edges touching it).
  std::vector<EdgeExit> exits(uint32_t node) const;
  /// The exit of `node` whose heading is within `tolerance` (rad) of `heading`; false if none.
  bool exitWithHeading(uint32_t node, double heading, double tolerance, EdgeExit* exit) const;
  /// A staggered crossing: two branches that leave one hallway on opposite sides, or a hallway
  /// that goes on offset to one side, are recorded at two nodes joined by a short link across the
  /// way. A robot drives on across the offset without turning: shorter than the narrowest hallway
  /// (BuildingRules::hallway_min_width), it bends the path by less than 45 deg across a hallway at
  /// least that wide, which no heading bin registers as a turn. True for a link (length, heading)
  /// that carries the way `heading` on so: that short, and within 45 deg of a right angle to it.
  static bool staggeredLink(double link_length, double link_heading, double heading,
                            const laser_features::BuildingRules& rules);
  /// The way on from `node` along `heading` (within `tolerance`, rad): its own exit that way, or
  /// where it has neither an exit nor an opening that way (an opening is a branch of its own, to be
  /// mapped), the exit that way of a neighbour across a staggeredLink (never one back to `node`).
  /// False if none.
  bool wayOn(uint32_t node, double heading, double tolerance, EdgeExit* exit) const;
  /// Whether `node` has a recorded opening the way of `heading` (HeadingBins::sameWay).
  bool hasOpeningToward(uint32_t node, double heading) const;
  /// The point `d` metres along edge `e` from its source (clamped to the edge), between its nodes'
  /// display poses (map frame); false for an edge whose nodes are unknown.
  bool pointOnEdge(const TopoEdge& e, double d, Eigen::Vector2d* p) const;

  /// Ids the next addNode / addEdge will assign.
  uint32_t nextNodeId() const { return next_node_id_; }
  uint32_t nextEdgeId() const { return next_edge_id_; }

  /// Replaces everything (used by loading); ids must be consistent (checked by the caller).
  void assign(std::map<uint32_t, TopoNode> nodes, std::map<uint32_t, TopoEdge> edges,
              uint32_t next_node_id, uint32_t next_edge_id);
  void clear();
  /// Monotonic counter bumped by every structural change (node or edge added, removed, merged,
  /// an edge's length changed through setEdgeLength): the localizer rebuilds its states when it moves.
  uint64_t revision() const { return revision_; }
  void setEdgeLength(uint32_t edge, double length);
  void touch() { ++revision_; }

 private:
  void splitCollinearEdges(uint32_t node, std::vector<std::pair<uint32_t, uint32_t>>* also_merged,
                           double max_zip_distance);
  std::vector<NodeOpening>::iterator findOpening(TopoNode* n, const NodeOpening& opening);
  /// Same node type, and an opening on the same side (or neither has one).
  bool sameKind(uint32_t a, uint32_t b) const;

  std::map<uint32_t, TopoNode> nodes_;
  std::map<uint32_t, TopoEdge> edges_;
  uint32_t next_node_id_ = 0;
  uint32_t next_edge_id_ = 0;
  uint64_t revision_ = 0;
  laser_features::BuildingRules rules_;  // see setBuildingRules
  laser_features::HeadingBins bins_;     // see setHeadingBins
};

}  // namespace pomdp_topo
