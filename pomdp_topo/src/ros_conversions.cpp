#include "ros_conversions.h"

#include <cmath>

namespace pomdp_topo {

using laser_features::normalizeAngle;

namespace {

bool finite(std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

geometry_msgs::Point point(double x, double y, double z = 0.0) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

std_msgs::ColorRGBA color(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

// Landmarks coloured by orientation: the hue follows the angle.
std_msgs::ColorRGBA hue(double angle) {
  const double h = (normalizeAngle(angle) + M_PI) / (2.0 * M_PI) * 6.0;
  const int i = int(h) % 6;
  const float f = float(h - std::floor(h));
  switch (i) {
    case 0: return color(1, f, 0);
    case 1: return color(1 - f, 1, 0);
    case 2: return color(0, 1, f);
    case 3: return color(0, 1 - f, 1);
    case 4: return color(f, 0, 1);
    default: return color(1, 0, 1 - f);
  }
}

Eigen::Vector2d nodePosition(const TopologicalMap& map, uint32_t id) {
  const TopoNode* n = map.node(id);
  return n ? Eigen::Vector2d(n->pose.x, n->pose.y) : Eigen::Vector2d::Zero();
}

}  // namespace

void fromMsg(const hybrid_slam_msgs::LaserFeatures& msg, const Pose2D& s, std::vector<laser_features::LineSegment>* lines,
             std::vector<laser_features::Corner>* corners, std::vector<laser_features::Opening>* openings,
             size_t* dropped) {
  lines->clear();
  corners->clear();
  openings->clear();
  *dropped = 0;
  for (const auto& l : msg.lines) {
    if (!finite({l.alpha, l.r, l.covariance[0], l.start.x, l.start.y, l.end.x, l.end.y}) || l.covariance[0] < 0.0) {
      ++*dropped;
      continue;
    }
    laser_features::LineSegment seg;
    seg.line.alpha = l.alpha;
    seg.line.r = l.r;
    seg.line.cov << l.covariance[0], l.covariance[1], l.covariance[2], l.covariance[3];
    seg.line = laser_features::transformLineFromFrame(seg.line, s);
    seg.start = laser_features::transformPoint(s, Eigen::Vector2d(l.start.x, l.start.y));
    seg.end = laser_features::transformPoint(s, Eigen::Vector2d(l.end.x, l.end.y));
    seg.num_points = l.num_points;
    lines->push_back(seg);
  }
  for (const auto& c : msg.corners) {
    if (!finite({c.x, c.y, c.theta, c.confidence})) {
      ++*dropped;
      continue;
    }
    laser_features::Corner k;
    k.position = laser_features::transformPoint(s, Eigen::Vector2d(c.x, c.y));
    k.theta = normalizeAngle(c.theta + s.theta);
    k.convex = c.convex;
    k.confidence = c.confidence;
    corners->push_back(k);
  }
  for (const auto& o : msg.openings) {
    if (!finite({o.x, o.y, o.theta, o.width, o.confidence}) || o.width < 0.0) {
      ++*dropped;
      continue;
    }
    laser_features::Opening k;
    k.center = laser_features::transformPoint(s, Eigen::Vector2d(o.x, o.y));
    k.left = laser_features::transformPoint(s, Eigen::Vector2d(o.left.x, o.left.y));
    k.right = laser_features::transformPoint(s, Eigen::Vector2d(o.right.x, o.right.y));
    k.theta = normalizeAngle(o.theta + s.theta);
    k.width = o.width;
    k.confidence = o.confidence;
    k.room_behind = o.room_behind;
    openings->push_back(k);
  }
}

void toMsg(const TopologicalMap& map, const std_msgs::Header& header, hybrid_slam_msgs::TopologicalMap* msg) {
  msg->header = header;
  msg->nodes.clear();
  msg->edges.clear();
  for (const auto& entry : map.nodes()) {
    const TopoNode& n = entry.second;
    hybrid_slam_msgs::TopoNode m;
    m.id = n.id;
    m.type = uint8_t(n.type);
    m.pose.x = n.pose.x;
    m.pose.y = n.pose.y;
    m.pose.theta = n.pose.theta;
    for (const NodeOpening& o : n.openings) {
      hybrid_slam_msgs::TopoOpening mo;
      mo.bearing = o.direction();
      mo.bin_bearing = o.bearing;
      mo.offset = o.offset;
      mo.width = o.width;
      mo.explored = o.explored;
      mo.place_id = o.place_id;
      mo.door_in_place.x = o.door_in_place.x;
      mo.door_in_place.y = o.door_in_place.y;
      mo.door_in_place.theta = o.door_in_place.theta;
      m.openings.push_back(mo);
    }
    for (const FingerprintEntry& f : n.fingerprint.entries) {
      m.fingerprint_angles.push_back(f.bearing);
      m.fingerprint_types.push_back(uint8_t(f.kind));
    }
    m.explored = n.explored;
    msg->nodes.push_back(m);
  }
  for (const auto& entry : map.edges()) {
    const TopoEdge& e = entry.second;
    hybrid_slam_msgs::TopoEdge m;
    m.id = e.id;
    m.source = e.source;
    m.target = e.target;
    m.heading = e.heading;
    m.length = e.length;
    for (const EdgeLandmark& l : e.landmarks) {
      hybrid_slam_msgs::TopoLandmark ml;
      ml.type = uint8_t(l.type);
      ml.distance = l.distance;
      ml.orientation = l.orientation;
      ml.left = l.lateral >= 0.0;
      ml.lateral = l.lateral;
      ml.p_lmap = l.p_lmap;
      ml.observations = l.observations;
      m.landmarks.push_back(ml);
    }
    msg->edges.push_back(m);
  }
}

void toMsg(MapBuilder::Mode mode, bool confident, const Pose2D& pose, const std_msgs::Header& header,
           hybrid_slam_msgs::TopologicalState* msg) {
  using State = hybrid_slam_msgs::TopologicalState;
  msg->header = header;
  switch (mode) {
    case MapBuilder::Mode::Frontier: msg->mode = State::FRONTIER; break;
    case MapBuilder::Mode::Localized: msg->mode = State::LOCALIZED; break;
    case MapBuilder::Mode::LoopCheck: msg->mode = State::LOOP_CHECK; break;
  }
  msg->confident = confident;
  msg->heading = pose.theta;
  msg->x = pose.x;
  msg->y = pose.y;
}

void toMsg(const TopoEvent& event, const std_msgs::Header& header, hybrid_slam_msgs::TopoEvent* msg) {
  using Msg = hybrid_slam_msgs::TopoEvent;
  using Kind = TopoEvent::Kind;
  msg->header = header;
  switch (event.kind) {
    case Kind::NodeCreated: msg->kind = Msg::NODE_CREATED; break;
    case Kind::OpeningAdded: msg->kind = Msg::OPENING_ADDED; break;
    case Kind::LandmarkAdded: msg->kind = Msg::LANDMARK_ADDED; break;
    case Kind::LandmarkDeleted: msg->kind = Msg::LANDMARK_DELETED; break;
    case Kind::LoopHypothesis: msg->kind = Msg::LOOP_HYPOTHESIS; break;
    case Kind::LoopClosed: msg->kind = Msg::LOOP_CLOSED; break;
    case Kind::LoopRejected: msg->kind = Msg::LOOP_REJECTED; break;
    case Kind::NodesMerged: msg->kind = Msg::NODES_MERGED; break;
    case Kind::BeliefLost: msg->kind = Msg::BELIEF_LOST; break;
    case Kind::BeliefGated: msg->kind = Msg::BELIEF_GATED; break;
    case Kind::BeliefReset: msg->kind = Msg::BELIEF_RESET; break;
    case Kind::OdometryJump: msg->kind = Msg::ODOMETRY_JUMP; break;
    case Kind::Relocalized: msg->kind = Msg::RELOCALIZED; break;
    case Kind::NewStretch: msg->kind = Msg::NEW_STRETCH; break;
  }
  msg->node = event.node;
  msg->other_node = event.other_node;
  msg->edge = event.edge;
  msg->text = event.text;
}

void toMsg(const PomdpLocalizer& loc, const std_msgs::Header& header, hybrid_slam_msgs::TopologicalBelief* msg) {
  msg->header = header;
  const size_t n = loc.size();
  msg->state_edge.resize(n);
  msg->at_node.resize(n);
  msg->state_offset.resize(n);
  msg->state_heading.resize(n);
  msg->probability.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& s = loc.state(i);
    msg->state_edge[i] = s.id;
    msg->at_node[i] = s.kind == PomdpLocalizer::State::Node;
    msg->state_offset[i] = s.offset;
    msg->state_heading[i] = s.heading;
    msg->probability[i] = loc.belief()[i];
  }
  msg->entropy = loc.entropy();
  msg->entropy_max = loc.params().entropy_max;
  msg->confident = loc.confident();
  msg->most_likely = loc.mostLikely();
}

Eigen::Vector2d displayPosition(const TopologicalMap& map, const PomdpLocalizer::State& s) {
  if (s.kind == PomdpLocalizer::State::Node) return nodePosition(map, s.id);
  const TopoEdge* e = map.edge(s.id);
  if (e == nullptr) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d a = nodePosition(map, e->source), b = nodePosition(map, e->target);
  const double t = e->length > 1e-9 ? std::min(1.0, std::max(0.0, s.offset / e->length)) : 0.0;
  return a + t * (b - a);
}

void toMarkers(const TopologicalMap& map, const PomdpLocalizer& loc, const std_msgs::Header& header,
               visualization_msgs::MarkerArray* out) {
  out->markers.clear();
  auto make = [&](const std::string& ns, int type, double scale) {
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = ns;
    m.id = 0;
    m.type = type;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = scale;
    return m;
  };
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out->markers.push_back(clear);

  // Nodes: doors green, junctions blue, hallway ends grey, places orange, start white.
  auto nodes = make("nodes", visualization_msgs::Marker::SPHERE_LIST, 0.35);
  auto edges = make("edges", visualization_msgs::Marker::LINE_LIST, 0.06);
  edges.color = color(0.2f, 0.6f, 1.0f, 0.9f);
  auto landmarks = make("landmarks", visualization_msgs::Marker::CUBE_LIST, 0.18);
  auto openings = make("openings", visualization_msgs::Marker::LINE_LIST, 0.05);
  openings.color = color(0.1f, 0.9f, 0.3f);
  int text_id = 0;
  for (const auto& entry : map.nodes()) {
    const TopoNode& n = entry.second;
    nodes.points.push_back(point(n.pose.x, n.pose.y, 0.1));
    switch (n.type) {
      case NodeType::Door: nodes.colors.push_back(color(0.1f, 0.8f, 0.2f)); break;
      case NodeType::Junction: nodes.colors.push_back(color(0.2f, 0.3f, 1.0f)); break;
      case NodeType::HallwayEnd: nodes.colors.push_back(color(0.6f, 0.6f, 0.6f)); break;
      case NodeType::Place: nodes.colors.push_back(color(1.0f, 0.6f, 0.1f)); break;
      case NodeType::Start: nodes.colors.push_back(color(1.0f, 1.0f, 1.0f)); break;
    }
    for (const NodeOpening& o : n.openings) {
      const double len = std::max(0.5, o.offset);
      openings.points.push_back(point(n.pose.x, n.pose.y, 0.1));
      openings.points.push_back(point(n.pose.x + len * std::cos(o.direction()), n.pose.y + len * std::sin(o.direction()), 0.1));
    }
    auto text = make("node_ids", visualization_msgs::Marker::TEXT_VIEW_FACING, 0.4);
    text.id = text_id++;
    text.pose.position = point(n.pose.x, n.pose.y, 0.6);
    text.color = color(1, 1, 1);
    text.text = std::to_string(n.id);
    out->markers.push_back(text);
  }
  for (const auto& entry : map.edges()) {
    const TopoEdge& e = entry.second;
    const Eigen::Vector2d a = nodePosition(map, e.source), b = nodePosition(map, e.target);
    edges.points.push_back(point(a.x(), a.y(), 0.05));
    edges.points.push_back(point(b.x(), b.y(), 0.05));
    const Eigen::Vector2d u = laser_features::unitVector(e.heading);
    const Eigen::Vector2d left(-u.y(), u.x());
    for (const EdgeLandmark& l : e.landmarks) {
      const double t = e.length > 1e-9 ? l.distance / e.length : 0.0;
      const Eigen::Vector2d p = a + t * (b - a) + l.lateral * left;
      landmarks.points.push_back(point(p.x(), p.y(), 0.1));
      std_msgs::ColorRGBA c = hue(e.heading + l.orientation);
      c.a = float(0.3 + 0.7 * l.p_lmap);
      landmarks.colors.push_back(c);
    }
  }
  // The belief: one sphere per state above 0.5 %, its diameter growing with the probability.
  const auto& b = loc.belief();
  int belief_id = 0;
  for (size_t i = 0; i < loc.size() && belief_id < 300; ++i) {
    if (b[i] < 5e-3) continue;
    auto sphere = make("belief", visualization_msgs::Marker::SPHERE, 0.15 + 0.85 * std::sqrt(b[i]));
    sphere.id = belief_id++;
    const Eigen::Vector2d p = displayPosition(map, loc.state(i));
    sphere.pose.position = point(p.x(), p.y(), 0.3);
    sphere.color = color(1.0f, 0.1f, 0.6f, 0.6f);
    out->markers.push_back(sphere);
  }
  for (auto* m : {&nodes, &edges, &landmarks, &openings}) {
    if (!m->points.empty()) out->markers.push_back(*m);
  }
}

}  // namespace pomdp_topo
