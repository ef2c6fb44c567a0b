#include "ros_conversions.h"

#include <cmath>

namespace exploration {

using laser_features::Pose2D;

namespace {

Eigen::Vector2d apply(const Pose2D& f, double x, double y) { return laser_features::transformPoint(f, Eigen::Vector2d(x, y)); }

}  // namespace

void scanPoints(const sensor_msgs::LaserScan& scan, const Pose2D& sensor_in_robot, std::vector<Eigen::Vector2d>* points) {
  points->clear();
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r <= scan.range_min || r >= scan.range_max) continue;
    const double a = scan.angle_min + double(i) * scan.angle_increment;
    points->push_back(apply(sensor_in_robot, r * std::cos(a), r * std::sin(a)));
  }
}

void featuresInRobot(const hybrid_slam_msgs::LaserFeatures& msg, const Pose2D& s,
                     std::vector<laser_features::LineSegment>* lines, std::vector<laser_features::Opening>* openings,
                     size_t* dropped) {
  lines->clear();
  openings->clear();
  for (const auto& l : msg.lines) {
    if (!std::isfinite(l.start.x) || !std::isfinite(l.start.y) || !std::isfinite(l.end.x) || !std::isfinite(l.end.y)) {
      ++*dropped;
      continue;
    }
    laser_features::LineSegment seg;
    seg.start = apply(s, l.start.x, l.start.y);
    seg.end = apply(s, l.end.x, l.end.y);
    seg.num_points = l.num_points;
    lines->push_back(seg);  // only the end points are used (the hallway's walls)
  }
  for (const auto& o : msg.openings) {
    if (!std::isfinite(o.x) || !std::isfinite(o.y) || !std::isfinite(o.theta) || !std::isfinite(o.width) ||
        !std::isfinite(o.left.x) || !std::isfinite(o.left.y) || !std::isfinite(o.right.x) || !std::isfinite(o.right.y)) {
      ++*dropped;
      continue;
    }
    laser_features::Opening op;
    op.center = apply(s, o.x, o.y);
    op.left = apply(s, o.left.x, o.left.y);
    op.right = apply(s, o.right.x, o.right.y);
    op.theta = laser_features::normalizeAngle(o.theta + s.theta);
    op.width = o.width;
    op.confidence = o.confidence;
    op.room_behind = o.room_behind;
    op.in_wall = o.in_wall;
    op.kind = o.kind == hybrid_slam_msgs::OpeningFeature::DOOR       ? laser_features::OpeningKind::kDoor
              : o.kind == hybrid_slam_msgs::OpeningFeature::JUNCTION ? laser_features::OpeningKind::kJunction
                                                                     : laser_features::OpeningKind::kUnknown;
    op.source = o.source == hybrid_slam_msgs::OpeningFeature::COLLINEAR_GAP ? laser_features::OpeningSource::kCollinearGap
                : o.source == hybrid_slam_msgs::OpeningFeature::HALLWAY_STEP
                    ? laser_features::OpeningSource::kHallwayStep
                    : laser_features::OpeningSource::kRangeDiscontinuity;
    openings->push_back(op);
  }
}

TopoMode modeFromMsg(const hybrid_slam_msgs::TopologicalState& msg) {
  using State = hybrid_slam_msgs::TopologicalState;
  switch (msg.mode) {
    case State::FRONTIER: return TopoMode::Frontier;
    case State::LOCALIZED: return TopoMode::Localized;
    case State::LOOP_CHECK: return TopoMode::LoopCheck;
    default: return TopoMode::Unknown;
  }
}

void fromMsg(const hybrid_slam_msgs::TopologicalMap& msg, TopoGraph* graph) {
  graph->clear();
  for (const auto& n : msg.nodes) {
    GraphNode g;
    g.id = n.id;
    g.type = n.type;
    g.x = n.pose.x;
    g.y = n.pose.y;
    for (const auto& o : n.openings) {
      g.openings.push_back(GraphOpening{o.bin_bearing, o.width, bool(o.explored), o.place_id,
                                        {o.door_in_place.x, o.door_in_place.y, o.door_in_place.theta}});
    }
    graph->addNode(g);
  }
  for (const auto& e : msg.edges) graph->addEdge(GraphEdge{e.id, e.source, e.target, e.heading, e.length});
}

namespace {
geometry_msgs::Pose2D toPose2DMsg(const laser_features::Pose2D& p) {
  geometry_msgs::Pose2D m;
  m.x = p.x;
  m.y = p.y;
  m.theta = p.theta;
  return m;
}
}  // namespace

hybrid_slam_msgs::AddDoor::Request addDoorRequest(int door_id, const laser_features::Pose2D& door_in_robot) {
  hybrid_slam_msgs::AddDoor::Request r;
  r.door_id = door_id;
  r.door_in_robot = toPose2DMsg(door_in_robot);
  r.place_id = -1;
  return r;
}

hybrid_slam_msgs::AddDoor::Request addDoorInPlaceRequest(int place_id, int door_id, const laser_features::Pose2D& door_in_place) {
  hybrid_slam_msgs::AddDoor::Request r;
  r.door_id = door_id;
  r.place_id = place_id;
  r.door_in_place = toPose2DMsg(door_in_place);
  return r;
}

hybrid_slam_msgs::RelocateAtDoor::Request relocateRequest(int place_id, int door_id, const laser_features::Pose2D& robot_from_door,
                                                          double sigma_xy, double sigma_theta) {
  return relocateRequest(place_id, door_id, robot_from_door,
                         Eigen::Vector3d(sigma_xy * sigma_xy, sigma_xy * sigma_xy, sigma_theta * sigma_theta).asDiagonal());
}

hybrid_slam_msgs::RelocateAtDoor::Request relocateRequest(int place_id, int door_id, const laser_features::Pose2D& robot_from_door,
                                                          const Eigen::Matrix3d& covariance) {
  hybrid_slam_msgs::RelocateAtDoor::Request r;
  r.place_id = place_id;
  r.door_id = door_id;
  r.robot_from_door = toPose2DMsg(robot_from_door);
  for (int k = 0; k < 9; ++k) r.covariance[size_t(k)] = covariance(k / 3, k % 3);  // row-major
  return r;
}

GraphPosition fromMsg(const hybrid_slam_msgs::TopologicalBelief& msg) {
  GraphPosition p;
  const int i = msg.most_likely;
  if (i < 0 || size_t(i) >= msg.state_edge.size() || size_t(i) >= msg.at_node.size() ||
      size_t(i) >= msg.state_offset.size() || size_t(i) >= msg.state_heading.size())
    return p;
  p.valid = true;
  p.at_node = msg.at_node[size_t(i)];
  p.id = msg.state_edge[size_t(i)];
  p.offset = msg.state_offset[size_t(i)];
  p.heading = msg.state_heading[size_t(i)];
  return p;
}

void roomMarkers(const RoomExplorer& room, const std::string& frame, const ros::Time& stamp,
                 visualization_msgs::MarkerArray* markers) {
  markers->markers.clear();
  const OccupancyGrid& grid = room.grid();
  visualization_msgs::Marker occ;
  occ.header.frame_id = frame;
  occ.header.stamp = stamp;
  occ.ns = "room_grid";
  occ.id = 0;
  occ.type = visualization_msgs::Marker::CUBE_LIST;
  occ.action = visualization_msgs::Marker::ADD;
  occ.pose.orientation.w = 1.0;
  occ.scale.x = occ.scale.y = grid.resolution();
  occ.scale.z = 0.02;
  occ.color.r = 0.1f;
  occ.color.g = 0.1f;
  occ.color.b = 0.1f;
  occ.color.a = 0.8f;
  for (int y = grid.minY(); y < grid.minY() + grid.height(); ++y) {
    for (int x = grid.minX(); x < grid.minX() + grid.width(); ++x) {
      if (grid.cellState(x, y) != CellState::Occupied) continue;
      const Eigen::Vector2d c = grid.cellCenter(x, y);
      geometry_msgs::Point p;
      p.x = c.x();
      p.y = c.y();
      occ.points.push_back(p);
    }
  }
  markers->markers.push_back(occ);
}

visualization_msgs::Marker modeMarker(CoordinatorMode mode, const std::string& state, const std::string& robot_frame,
                                      const ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = robot_frame;
  m.header.stamp = stamp;
  m.ns = "mode";
  m.id = 0;
  m.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.position.z = 1.0;
  m.pose.orientation.w = 1.0;
  m.scale.z = 0.5;
  const bool metric = mode == CoordinatorMode::Metric;
  m.color.r = metric ? 0.3f : 1.0f;
  m.color.g = metric ? 1.0f : 0.8f;
  m.color.b = metric ? 0.3f : 0.2f;
  m.color.a = 1.0f;
  m.text = std::string(toString(mode)) + ": " + state;
  return m;
}

}  // namespace exploration
