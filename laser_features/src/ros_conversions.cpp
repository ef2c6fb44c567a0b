#include "ros_conversions.h"

#include <cmath>
#include <cstdio>

namespace laser_features {
namespace {

geometry_msgs::Point point(const Eigen::Vector2d& p, double z = 0.0) {
  geometry_msgs::Point out;
  out.x = p.x();
  out.y = p.y();
  out.z = z;
  return out;
}

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

uint8_t placeTypeMsg(PlaceType t) {
  switch (t) {
    case PlaceType::kHallway:
      return hybrid_slam_msgs::LaserFeatures::HALLWAY;
    case PlaceType::kRoom:
      return hybrid_slam_msgs::LaserFeatures::ROOM;
    default:
      return hybrid_slam_msgs::LaserFeatures::UNKNOWN;
  }
}

uint8_t openingKindMsg(OpeningKind k) {
  switch (k) {
    case OpeningKind::kDoor:
      return hybrid_slam_msgs::OpeningFeature::DOOR;
    case OpeningKind::kJunction:
      return hybrid_slam_msgs::OpeningFeature::JUNCTION;
    default:
      return hybrid_slam_msgs::OpeningFeature::UNKNOWN;
  }
}

uint8_t openingSourceMsg(OpeningSource s) {
  switch (s) {
    case OpeningSource::kCollinearGap:
      return hybrid_slam_msgs::OpeningFeature::COLLINEAR_GAP;
    case OpeningSource::kHallwayStep:
      return hybrid_slam_msgs::OpeningFeature::HALLWAY_STEP;
    default:
      return hybrid_slam_msgs::OpeningFeature::RANGE_DISCONTINUITY;
  }
}

}  // namespace

std::string toScanView(const sensor_msgs::LaserScan& scan, ScanView* view) {
  const std::string error = validateScanHeader(scan.angle_min, scan.angle_max, scan.angle_increment, scan.ranges.size());
  if (!error.empty()) return error;
  view->angle_min = scan.angle_min;
  view->angle_increment = scan.angle_increment;
  view->range_min = scan.range_min;
  view->range_max = scan.range_max;
  view->ranges = scan.ranges.data();
  view->size = scan.ranges.size();
  return "";
}

void toMsg(const Features& features, const std_msgs::Header& header, hybrid_slam_msgs::LaserFeatures* msg) {
  msg->header = header;
  msg->lines.resize(features.lines.size());
  for (size_t i = 0; i < features.lines.size(); ++i) {
    const LineSegment& s = features.lines[i];
    hybrid_slam_msgs::LineFeature& m = msg->lines[i];
    m.alpha = s.line.alpha;
    m.r = s.line.r;
    for (int k = 0; k < 4; ++k) m.covariance[k] = s.line.cov(k / 2, k % 2);
    m.start = point(s.start);
    m.end = point(s.end);
    m.num_points = s.num_points;
  }
  msg->corners.resize(features.corners.size());
  for (size_t i = 0; i < features.corners.size(); ++i) {
    const Corner& c = features.corners[i];
    hybrid_slam_msgs::CornerFeature& m = msg->corners[i];
    m.x = c.position.x();
    m.y = c.position.y();
    m.theta = c.theta;
    for (int k = 0; k < 9; ++k) m.covariance[k] = c.cov(k / 3, k % 3);
    m.convex = c.convex;
    m.confidence = c.confidence;
  }
  msg->openings.resize(features.openings.size());
  for (size_t i = 0; i < features.openings.size(); ++i) {
    const Opening& o = features.openings[i];
    hybrid_slam_msgs::OpeningFeature& m = msg->openings[i];
    m.left = point(o.left);
    m.right = point(o.right);
    m.x = o.center.x();
    m.y = o.center.y();
    m.theta = o.theta;
    m.width = o.width;
    m.kind = openingKindMsg(o.kind);
    m.source = openingSourceMsg(o.source);
    m.room_behind = o.room_behind;
    m.in_wall = o.in_wall;
    m.confidence = o.confidence;
  }
  msg->place_type = placeTypeMsg(features.place_type);
  msg->place_type_confidence = features.place_confidence;
}

void toMarkers(const Features& features, const std_msgs::Header& header, visualization_msgs::MarkerArray* markers) {
  markers->markers.clear();
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers->markers.push_back(clear);
  int id = 0;
  auto base = [&](const std::string& ns, int type) {
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = ns;
    m.id = id++;
    m.type = type;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    return m;
  };
  auto lines = base("lines", visualization_msgs::Marker::LINE_LIST);
  lines.scale.x = 0.05;
  lines.color = rgba(0.1f, 0.6f, 1.0f);
  for (const LineSegment& s : features.lines) {
    lines.points.push_back(point(s.start, 0.05));
    lines.points.push_back(point(s.end, 0.05));
  }
  if (!lines.points.empty()) markers->markers.push_back(lines);
  for (const Corner& c : features.corners) {
    auto arrow = base("corners", visualization_msgs::Marker::ARROW);
    arrow.scale.x = 0.04;
    arrow.scale.y = 0.1;
    arrow.scale.z = 0.1;
    arrow.color = c.convex ? rgba(1.0f, 0.2f, 0.2f) : rgba(0.2f, 1.0f, 0.3f);
    arrow.color.a = static_cast<float>(0.3 + 0.7 * c.confidence);
    arrow.points.push_back(point(c.position, 0.1));
    arrow.points.push_back(point(c.position + 0.4 * Eigen::Vector2d(std::cos(c.theta), std::sin(c.theta)), 0.1));
    markers->markers.push_back(arrow);
  }
  for (const Opening& o : features.openings) {
    auto bar = base("openings", visualization_msgs::Marker::LINE_LIST);
    bar.scale.x = 0.08;
    bar.color = o.kind == OpeningKind::kDoor ? rgba(1.0f, 0.6f, 0.0f) : rgba(1.0f, 0.9f, 0.1f);
    bar.points.push_back(point(o.left, 0.08));
    bar.points.push_back(point(o.right, 0.08));
    markers->markers.push_back(bar);
    auto through = base("openings", visualization_msgs::Marker::ARROW);
    through.scale.x = 0.04;
    through.scale.y = 0.1;
    through.scale.z = 0.1;
    through.color = bar.color;
    through.points.push_back(point(o.center, 0.08));
    through.points.push_back(point(o.center + 0.5 * Eigen::Vector2d(std::cos(o.theta), std::sin(o.theta)), 0.08));
    markers->markers.push_back(through);
  }
  auto text = base("place_type", visualization_msgs::Marker::TEXT_VIEW_FACING);
  text.pose.position.z = 1.0;
  text.scale.z = 0.35;
  text.color = rgba(1.0f, 1.0f, 1.0f);
  const char* name = features.place_type == PlaceType::kHallway ? "hallway"
                     : features.place_type == PlaceType::kRoom  ? "room"
                                                                : "unknown";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%s %.0f%%", name, 100.0 * features.place_confidence);
  text.text = buffer;
  markers->markers.push_back(text);
}

}  // namespace laser_features
