#include "pomdp_topo/topological_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pomdp_topo {

using laser_features::normalizeAngle;

namespace {
constexpr double kMinSplit = 0.5;  // m, a stretch this much longer than another one from a node the same way contains it
}

const char* toString(NodeType type) {
  switch (type) {
    case NodeType::Door: return "door";
    case NodeType::Junction: return "junction";
    case NodeType::HallwayEnd: return "hallway_end";
    case NodeType::Place: return "place";
    case NodeType::Start: return "start";
  }
  return "unknown";
}

const char* toString(LandmarkType type) { return type == LandmarkType::Corner ? "corner" : "opening"; }

void Fingerprint::normalize() {
  for (auto& e : entries) e.bearing = normalizeAngle(e.bearing);
  std::sort(entries.begin(), entries.end(),
            [](const FingerprintEntry& a, const FingerprintEntry& b) { return a.bearing < b.bearing; });
}

void TopoEdge::sortLandmarks() {
  std::stable_sort(landmarks.begin(), landmarks.end(),
                   [](const EdgeLandmark& a, const EdgeLandmark& b) { return a.distance < b.distance; });
}

uint32_t TopologicalMap::addNode(TopoNode node) {
  node.id = next_node_id_++;
  const uint32_t id = node.id;
  nodes_.emplace(id, std::move(node));
  ++revision_;
  return id;
}

uint32_t TopologicalMap::addEdge(uint32_t source, uint32_t target, double heading, double length,
                                 std::vector<EdgeLandmark> landmarks) {
  if (!nodes_.count(source) || !nodes_.count(target)) {
    throw std::invalid_argument("addEdge: unknown node " + std::to_string(nodes_.count(source) ? target : source));
  }
  if (source == target) throw std::invalid_argument("addEdge: an edge from node " + std::to_string(source) + " to itself");
  if (!std::isfinite(length) || length < 0.0 || !std::isfinite(heading)) {
    throw std::invalid_argument("addEdge: non-finite or negative length or heading");
  }
  TopoEdge edge;
  edge.id = next_edge_id_++;
  edge.source = source;
  edge.target = target;
  edge.heading = normalizeAngle(heading);
  edge.length = length;
  edge.landmarks = std::move(landmarks);
  edge.sortLandmarks();
  const uint32_t id = edge.id;
  edges_.emplace(id, std::move(edge));
  ++revision_;
  return id;
}

bool TopologicalMap::removeEdge(uint32_t id) {
  if (!edges_.erase(id)) return false;
  ++revision_;
  return true;
}

bool TopologicalMap::removeNode(uint32_t id) {
  if (!nodes_.erase(id)) return false;
  for (auto it = edges_.begin(); it != edges_.end();) {
    if (it->second.source == id || it->second.target == id) {
      it = edges_.erase(it);
    } else {
      ++it;
    }
  }
  ++revision_;
  return true;
}

std::vector<NodeOpening>::iterator TopologicalMap::findOpening(TopoNode* n, const NodeOpening& opening) {
  return std::find_if(n->openings.begin(), n->openings.end(), [&](const NodeOpening& k) {
    return bins_.sameWay(k.bearing, opening.bearing) && !differentOpenings(k.width, opening.width);
  });
}

bool TopologicalMap::linkPlace(uint32_t id, const NodeOpening& door, int32_t place_id, const Pose2D& door_in_place,
                               int32_t* linked) {
  TopoNode* n = node(id);
  if (linked) *linked = -1;
  if (n == nullptr || place_id < 0) return false;
  auto it = findOpening(n, door);
  if (it == n->openings.end()) return false;
  if (linked) *linked = it->place_id >= 0 ? it->place_id : place_id;
  if (it->place_id >= 0 && it->place_id != place_id) return false;  // one place per door: the first stays
  it->place_id = place_id;
  it->door_in_place = Pose2D{door_in_place.x, door_in_place.y, normalizeAngle(door_in_place.theta)};
  return true;
}

const NodeOpening* TopologicalMap::placeDoor(const TopoNode& node, int32_t place_id) {
  if (place_id < 0) return nullptr;
  for (const NodeOpening& o : node.openings) {
    if (o.place_id == place_id) return &o;
  }
  return nullptr;
}

bool TopologicalMap::recordOpening(uint32_t id, const NodeOpening& opening) {
  TopoNode* n = node(id);
  if (n == nullptr || !std::isfinite(opening.bearing)) return false;
  auto it = findOpening(n, opening);
  if (it == n->openings.end()) {
    NodeOpening o = opening;
    o.bearing = normalizeAngle(o.bearing);
    n->openings.push_back(o);
  } else {
    it->explored = it->explored || opening.explored;
    if (it->width <= 0.0 && opening.width > 0.0) {
      it->width = opening.width;
      it->offset = opening.offset;
    }
    if (it->place_id < 0 && opening.place_id >= 0) {  // a merged copy's room
      it->place_id = opening.place_id;
      it->door_in_place = opening.door_in_place;
    }
  }
  n->explored = std::all_of(n->openings.begin(), n->openings.end(), [](const NodeOpening& k) { return k.explored; });
  return true;
}

bool TopologicalMap::mergeNodes(uint32_t keep, uint32_t drop, std::vector<std::pair<uint32_t, uint32_t>>* also_merged,
                                double max_zip_distance) {
  if (keep == drop || !nodes_.count(keep) || !nodes_.count(drop)) return false;
  const TopoNode& dropped = nodes_.at(drop);
  for (const NodeOpening& o : dropped.openings) {
    // An opening explored from either copy stays explored; a room linked at either stays linked.
    recordOpening(keep, o);
  }
  for (auto& entry : edges_) {
    TopoEdge& e = entry.second;
    if (e.source == drop) e.source = keep;
    if (e.target == drop) e.target = keep;
  }
  nodes_.erase(drop);
  // Self-loops left by the merge (an edge between the two merged nodes) carry no information.
  for (auto it = edges_.begin(); it != edges_.end();) {
    if (it->second.source == it->second.target) {
      it = edges_.erase(it);
    } else {
      ++it;
    }
  }
  // Duplicate stretches: the same two nodes joined with the same heading (either direction).
  for (auto a = edges_.begin(); a != edges_.end(); ++a) {
    for (auto b = std::next(a); b != edges_.end();) {
      const TopoEdge& ea = a->second;
      const TopoEdge& eb = b->second;
      const bool same = ea.source == eb.source && ea.target == eb.target && bins_.sameWay(ea.heading, eb.heading);
      const bool reversed = ea.source == eb.target && ea.target == eb.source &&
                            bins_.sameWay(ea.heading, eb.heading + laser_features::kPi);
      if (same || reversed) {
        a->second.length = 0.5 * (ea.length + eb.length);
        b = edges_.erase(b);
      } else {
        ++b;
      }
    }
  }
  ++revision_;
  splitCollinearEdges(keep, also_merged, max_zip_distance);
  return true;
}

void TopologicalMap::splitCollinearEdges(uint32_t n, std::vector<std::pair<uint32_t, uint32_t>>* also_merged,
                                         double max_zip_distance) {
  auto near = [&](uint32_t a, uint32_t b) {
    const TopoNode* na = node(a);
    const TopoNode* nb = node(b);
    return na != nullptr && nb != nullptr &&
           std::hypot(na->pose.x - nb->pose.x, na->pose.y - nb->pose.y) <= max_zip_distance;
  };
  // Direction of an edge leaving n, and its far node.
  auto away = [&](const TopoEdge& e) { return e.source == n ? e.heading : normalizeAngle(e.heading + laser_features::kPi); };
  auto far = [&](const TopoEdge& e) { return e.source == n ? e.target : e.source; };
  for (bool changed = true; changed;) {
    changed = false;
    std::pair<uint32_t, uint32_t> zip{0, 0};
    bool zip_found = false;
    for (auto& ea : edges_) {
      TopoEdge& a = ea.second;  // the longer one
      if (a.source != n && a.target != n) continue;
      for (const auto& eb : edges_) {
        const TopoEdge& b = eb.second;
        if (eb.first == ea.first || (b.source != n && b.target != n)) continue;
        if (far(a) == far(b) || !bins_.sameWay(away(a), away(b))) continue;
        if (std::abs(a.length - b.length) <= kMinSplit) {
          // Both stretches end at the same place: one node recorded twice (a loop hypothesis
          // rejected one node before the loop closed at the next). Zip them, the older one kept,
          // unless the dead reckoning put them far apart (large_floor: zips of nodes 25 m apart
          // joined hallways across the building).
          if (sameKind(far(a), far(b)) && near(far(a), far(b))) {
            zip = {std::min(far(a), far(b)), std::max(far(a), far(b))};
            zip_found = true;
            break;
          }
          continue;
        }
        if (!(b.length < a.length - kMinSplit)) continue;
        // b's far node lies on a, b.length from n: a now runs from there.
        const uint32_t mid = far(b);
        const double cut = b.length;
        std::vector<EdgeLandmark> kept;
        if (a.source == n) {
          a.source = mid;
          for (EdgeLandmark l : a.landmarks) {
            l.distance -= cut;
            if (l.distance >= 0.0) kept.push_back(l);
          }
        } else {
          a.target = mid;
          for (const EdgeLandmark& l : a.landmarks) {
            if (l.distance <= a.length - cut) kept.push_back(l);
          }
        }
        a.landmarks = kept;
        a.length -= cut;
        changed = true;
        break;
      }
      if (changed || zip_found) break;
    }
    if (zip_found) {
      // (Out of the loops over edges_: the merge re-attaches and erases edges.)
      if (also_merged != nullptr) also_merged->push_back(zip);
      mergeNodes(zip.first, zip.second, also_merged, max_zip_distance);
      changed = nodes_.count(n) > 0;  // n itself may have been zipped away further along
    }
  }
}

bool TopologicalMap::sameKind(uint32_t a, uint32_t b) const {
  const TopoNode* na = node(a);
  const TopoNode* nb = node(b);
  if (na == nullptr || nb == nullptr || na->type != nb->type) return false;
  if (na->openings.empty() || nb->openings.empty()) return na->openings.empty() && nb->openings.empty();
  // At least one opening on the same side (a door seen from both stretches).
  return std::any_of(na->openings.begin(), na->openings.end(), [&](const NodeOpening& o) {
    return std::any_of(nb->openings.begin(), nb->openings.end(), [&](const NodeOpening& k) {
      return bins_.sameWay(k.bearing, o.bearing);
    });
  });
}

const TopoNode* TopologicalMap::node(uint32_t id) const {
  auto it = nodes_.find(id);
  return it == nodes_.end() ? nullptr : &it->second;
}
TopoNode* TopologicalMap::node(uint32_t id) {
  auto it = nodes_.find(id);
  return it == nodes_.end() ? nullptr : &it->second;
}
const TopoEdge* TopologicalMap::edge(uint32_t id) const {
  auto it = edges_.find(id);
  return it == edges_.end() ? nullptr : &it->second;
}
TopoEdge* TopologicalMap::edge(uint32_t id) {
  auto it = edges_.find(id);
  return it == edges_.end() ? nullptr : &it->second;
}

std::vector<EdgeExit> TopologicalMap::exits(uint32_t node) const {
  std::vector<EdgeExit> out;
  for (const auto& entry : edges_) {
    const TopoEdge& e = entry.second;
    if (e.source == node) out.push_back({e.id, true, e.heading, e.target});
    if (e.target == node) out.push_back({e.id, false, normalizeAngle(e.heading + laser_features::kPi), e.source});
  }
  return out;
}

bool TopologicalMap::exitWithHeading(uint32_t node, double heading, double tolerance, EdgeExit* exit) const {
  double best = tolerance;
  bool found = false;
  for (const EdgeExit& x : exits(node)) {
    const double d = std::abs(normalizeAngle(x.heading - heading));
    if (d <= best) {
      best = d;
      *exit = x;
      found = true;
    }
  }
  return found;
}

bool TopologicalMap::hasOpeningToward(uint32_t node, double heading) const {
  const TopoNode* n = this->node(node);
  return n != nullptr && std::any_of(n->openings.begin(), n->openings.end(), [&](const NodeOpening& o) {
           return bins_.sameWay(o.bearing, heading);
         });
}

bool TopologicalMap::staggeredLink(double link_length, double link_heading, double heading,
                                   const laser_features::BuildingRules& rules) {
  const double angle = std::abs(normalizeAngle(link_heading - heading));
  return link_length < rules.hallway_min_width && angle > 0.25 * laser_features::kPi &&
         angle < 0.75 * laser_features::kPi;
}

bool TopologicalMap::wayOn(uint32_t node, double heading, double tolerance, EdgeExit* exit) const {
  if (exitWithHeading(node, heading, tolerance, exit)) return true;
  if (hasOpeningToward(node, heading)) return false;  // a branch of its own, not the neighbour's
  for (const EdgeExit& link : exits(node)) {
    const TopoEdge* e = edge(link.edge);
    if (e == nullptr || !staggeredLink(e->length, link.heading, heading, rules_)) continue;
    EdgeExit on;
    if (exitWithHeading(link.other, heading, tolerance, &on) && on.other != node) {
      *exit = on;
      return true;
    }
  }
  return false;
}

void TopologicalMap::assign(std::map<uint32_t, TopoNode> nodes, std::map<uint32_t, TopoEdge> edges,
                            uint32_t next_node_id, uint32_t next_edge_id) {
  nodes_ = std::move(nodes);
  edges_ = std::move(edges);
  next_node_id_ = next_node_id;
  next_edge_id_ = next_edge_id;
  ++revision_;
}

void TopologicalMap::clear() {
  nodes_.clear();
  edges_.clear();
  next_node_id_ = 0;
  next_edge_id_ = 0;
  ++revision_;
}

void TopologicalMap::setEdgeLength(uint32_t id, double length) {
  TopoEdge* e = edge(id);
  if (e == nullptr || !std::isfinite(length) || length < 0.0) return;
  e->length = length;
  ++revision_;
}

bool TopologicalMap::pointOnEdge(const TopoEdge& e, double d, Eigen::Vector2d* p) const {
  const TopoNode* a = node(e.source);
  const TopoNode* b = node(e.target);
  if (a == nullptr || b == nullptr) return false;
  *p = Eigen::Vector2d(a->pose.x, a->pose.y);
  if (e.length > 0.0) *p += (Eigen::Vector2d(b->pose.x, b->pose.y) - *p) * std::clamp(d / e.length, 0.0, 1.0);
  return true;
}

}  // namespace pomdp_topo
