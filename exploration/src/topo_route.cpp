#include "exploration/topo_route.h"

#include "laser_features/geometry.h"

#include <cmath>
#include <limits>
#include <queue>
#include <set>
#include <utility>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;

void TopoGraph::clear() {
  nodes_.clear();
  edges_.clear();
}

void TopoGraph::addNode(const GraphNode& node) { nodes_[node.id] = node; }

void TopoGraph::addEdge(const GraphEdge& edge) {
  if (!nodes_.count(edge.source) || !nodes_.count(edge.target) || !std::isfinite(edge.length)) return;
  edges_[edge.id] = edge;
}

const GraphNode* TopoGraph::node(uint32_t id) const {
  auto it = nodes_.find(id);
  return it == nodes_.end() ? nullptr : &it->second;
}

const GraphEdge* TopoGraph::edge(uint32_t id) const {
  auto it = edges_.find(id);
  return it == edges_.end() ? nullptr : &it->second;
}

bool TopoGraph::hasExit(uint32_t node, double heading, double tolerance) const {
  for (const auto& entry : edges_) {
    const GraphEdge& e = entry.second;
    if (e.source == node && std::abs(normalizeAngle(e.heading - heading)) < tolerance) return true;
    if (e.target == node && std::abs(normalizeAngle(e.heading + kPi - heading)) < tolerance) return true;
  }
  return false;
}

std::optional<double> TopoGraph::headingAlongOpening(uint32_t node, double bearing) const {
  const double across = std::cos(0.25 * kPi);
  for (const auto& entry : edges_) {  // by id: the oldest first
    const GraphEdge& e = entry.second;
    if (e.source != node && e.target != node) continue;
    const double leave = e.source == node ? e.heading : normalizeAngle(e.heading + kPi);
    if (std::abs(std::cos(leave - bearing)) < across) return leave;
  }
  return std::nullopt;
}

std::vector<GraphOpening> TopoGraph::unexplored(uint32_t id) const {
  std::vector<GraphOpening> out;
  const GraphNode* n = node(id);
  if (n == nullptr) return out;
  for (const GraphOpening& o : n->openings) {
    if (!o.explored && !hasExit(id, o.bearing)) out.push_back(o);
  }
  return out;
}

size_t TopoGraph::unexploredCount() const {
  size_t count = 0;
  for (const auto& entry : nodes_) count += unexplored(entry.first).size();
  return count;
}

size_t TopoGraph::unexploredCount(const std::function<bool(uint32_t, const GraphOpening&)>& skip) const {
  size_t count = 0;
  for (const auto& entry : nodes_) {
    for (const GraphOpening& o : unexplored(entry.first)) count += skip(entry.first, o) ? 0 : 1;
  }
  return count;
}

size_t TopoGraph::exploredCount() const {
  size_t count = 0;
  for (const auto& entry : nodes_) {
    for (const GraphOpening& o : entry.second.openings) count += o.explored || hasExit(entry.first, o.bearing);
  }
  return count;
}

double TopoGraph::edgeLength() const {
  double length = 0.0;
  for (const auto& entry : edges_) length += entry.second.length;
  return length;
}

bool TopoGraph::adjacent(uint32_t a, uint32_t b) const {
  for (const auto& entry : edges_) {
    const GraphEdge& e = entry.second;
    if ((e.source == a && e.target == b) || (e.source == b && e.target == a)) return true;
  }
  return false;
}

double TopoGraph::distance(uint32_t a, uint32_t b) const {
  if (!node(a) || !node(b)) return std::numeric_limits<double>::infinity();
  std::map<uint32_t, double> dist{{a, 0.0}};
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  queue.push({0.0, a});
  while (!queue.empty()) {
    const Item top = queue.top();
    queue.pop();
    if (top.second == b) return top.first;
    if (top.first > dist[top.second]) continue;
    for (const auto& entry : edges_) {
      const GraphEdge& e = entry.second;
      if (e.source != top.second && e.target != top.second) continue;
      const uint32_t other = e.source == top.second ? e.target : e.source;
      const double d = top.first + e.length;
      auto it = dist.find(other);
      if (it == dist.end() || d < it->second) {
        dist[other] = d;
        queue.push({d, other});
      }
    }
  }
  return std::numeric_limits<double>::infinity();
}

std::set<int> TopoGraph::placeIds() const {
  std::set<int> ids;
  for (const auto& entry : nodes_) {
    for (const GraphOpening& o : entry.second.openings) {
      if (o.place_id >= 0) ids.insert(o.place_id);
    }
  }
  return ids;
}

int TopoGraph::nearestNode(const GraphPosition& pos) const {
  if (!pos.valid) return -1;
  if (pos.at_node) return node(pos.id) ? int(pos.id) : -1;
  const GraphEdge* e = edge(pos.id);
  if (e == nullptr) return -1;
  const bool forward = std::abs(normalizeAngle(pos.heading - e->heading)) < 0.5 * kPi;
  const double to_target = e->length - pos.offset;
  if (std::abs(to_target - pos.offset) < 1e-9) return int(forward ? e->target : e->source);
  return int(to_target < pos.offset ? e->target : e->source);
}

double TopoGraph::nearestNodeDistance(const GraphPosition& pos) const {
  const int n = nearestNode(pos);
  if (n < 0) return std::numeric_limits<double>::infinity();
  if (pos.at_node) return 0.0;
  const GraphEdge* e = edge(pos.id);
  return std::clamp(uint32_t(n) == e->target ? e->length - pos.offset : pos.offset, 0.0, e->length);
}

RouteStep TopoGraph::route(const GraphPosition& pos, double u_turn_cost,
                           const std::function<bool(uint32_t, const GraphOpening&)>& skip) const {
  return search(pos, u_turn_cost, [&](uint32_t n) {
    for (const GraphOpening& o : unexplored(n)) {
      if (!skip || !skip(n, o)) return std::optional<GraphOpening>(o);
    }
    return std::optional<GraphOpening>();
  });
}

RouteStep TopoGraph::routeTo(const GraphPosition& pos, uint32_t goal_node, const GraphOpening& opening,
                             double u_turn_cost) const {
  return search(pos, u_turn_cost, [&](uint32_t n) {
    return n == goal_node ? std::optional<GraphOpening>(opening) : std::optional<GraphOpening>();
  });
}

std::optional<PlaceDoor> TopoGraph::placeDoor(int place_id) const {
  if (place_id < 0) return std::nullopt;
  for (const auto& entry : nodes_) {
    for (const GraphOpening& o : entry.second.openings) {
      if (o.place_id != place_id) continue;
      return PlaceDoor{entry.first, o};
    }
  }
  return std::nullopt;
}

RouteStep TopoGraph::search(const GraphPosition& pos, double u_turn_cost,
                            const std::function<std::optional<GraphOpening>(uint32_t)>& goal_at) const {
  RouteStep step;
  if (!pos.valid) return step;
  // Dijkstra from the robot's position. prev[n]: the node before n on the best route and the
  // heading leaving it towards n (kStart: n is a first node, reached from the robot directly).
  constexpr uint32_t kStart = 0xffffffffu;
  std::map<uint32_t, double> dist;
  std::map<uint32_t, std::pair<uint32_t, double>> prev;
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  auto relax = [&](uint32_t n, double d, uint32_t from, double heading) {
    auto it = dist.find(n);
    if (it != dist.end() && it->second <= d) return;
    dist[n] = d;
    prev[n] = {from, heading};
    queue.push({d, n});
  };
  if (pos.at_node) {
    if (!node(pos.id)) return step;
    relax(pos.id, 0.0, kStart, pos.heading);
  } else {
    const GraphEdge* e = edge(pos.id);
    if (e == nullptr) return step;
    const bool forward = std::abs(normalizeAngle(pos.heading - e->heading)) < 0.5 * kPi;
    const double to_target = std::max(0.0, e->length - pos.offset);
    const double to_source = std::max(0.0, pos.offset);
    relax(e->target, to_target + (forward ? 0.0 : u_turn_cost), kStart, e->heading);
    relax(e->source, to_source + (forward ? u_turn_cost : 0.0), kStart, normalizeAngle(e->heading + kPi));
  }
  while (!queue.empty()) {
    const Item top = queue.top();
    queue.pop();
    if (top.first > dist[top.second]) continue;
    const uint32_t n = top.second;
    const std::optional<GraphOpening> goal = goal_at(n);
    if (goal) {
      step.found = true;
      step.goal_node = n;
      step.goal_bearing = goal->bearing;
      step.goal_width = goal->width;
      step.distance = top.first;
      // Back along the route to its first node: that node's heading is the one to travel now; the
      // heading leaving it is the next step's (or the opening's, at the goal).
      uint32_t first = n, after = n;
      double leave = step.goal_bearing;
      while (prev[first].first != kStart) {
        after = first;
        first = prev[first].first;
        leave = prev[after].second;
      }
      step.next_node = first;
      step.heading = pos.at_node && pos.id == first ? leave : prev[first].second;
      step.next_heading = first == n ? step.goal_bearing : leave;
      step.arrival_heading = prev[n].second;
      return step;
    }
    for (const auto& entry : edges_) {
      const GraphEdge& e = entry.second;
      if (e.source != n && e.target != n) continue;
      const bool out = e.source == n;
      relax(out ? e.target : e.source, top.first + e.length, n, out ? e.heading : normalizeAngle(e.heading + kPi));
    }
  }
  return step;
}

}  // namespace exploration
