#include "ros_conversions.h"

#include "laser_features/planar_covariance.h"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace ekf_local_map {

using laser_features::Pose2D;

void toObservations(const hybrid_slam_msgs::LaserFeatures& msg, std::vector<LineSegment>* out) {
  out->resize(msg.lines.size());
  for (size_t i = 0; i < msg.lines.size(); ++i) {
    const auto& m = msg.lines[i];
    LineSegment& s = (*out)[i];
    s.line.alpha = m.alpha;
    s.line.r = m.r;
    s.line.cov << m.covariance[0], m.covariance[1], m.covariance[2], m.covariance[3];
    s.start = {m.start.x, m.start.y};
    s.end = {m.end.x, m.end.y};
    s.num_points = m.num_points;
  }
}

Pose2D toPose(const geometry_msgs::Pose2D& p) { return {p.x, p.y, p.theta}; }

Pose2D toPose(const geometry_msgs::Transform& t) {
  const auto& q = t.rotation;
  return {t.translation.x, t.translation.y, std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))};
}

geometry_msgs::Transform toTransform(const Pose2D& p) {
  geometry_msgs::Transform t;
  t.translation.x = p.x;
  t.translation.y = p.y;
  t.rotation.z = std::sin(p.theta / 2);
  t.rotation.w = std::cos(p.theta / 2);
  return t;
}

void toPoseWithCovariance(const StochasticMap& map, geometry_msgs::PoseWithCovariance* out) {
  const Pose2D p = map.robotPose();
  out->pose.position.x = p.x;
  out->pose.position.y = p.y;
  out->pose.position.z = 0.0;
  out->pose.orientation.x = out->pose.orientation.y = 0.0;
  out->pose.orientation.z = std::sin(p.theta / 2);
  out->pose.orientation.w = std::cos(p.theta / 2);
  laser_features::setPlanarCovariance(map.robotCovariance(), &out->covariance);
}

void toLocalMap(const StochasticMap& map, int place_id, const std_msgs::Header& header,
                hybrid_slam_msgs::LocalMap* out) {
  out->header = header;
  out->place_id = place_id;
  toPoseWithCovariance(map, &out->robot);
  out->lines.resize(map.numLines());
  for (size_t i = 0; i < map.numLines(); ++i) {
    const MapLine l = map.line(i);
    auto& m = out->lines[i];
    m.alpha = l.line.alpha;
    m.r = l.line.r;
    for (int k = 0; k < 4; ++k) m.covariance[k] = l.line.cov(k / 2, k % 2);
    m.start.x = l.extent_start.x();
    m.start.y = l.extent_start.y();
    m.end.x = l.extent_end.x();
    m.end.y = l.extent_end.y();
    m.num_points = 0;
  }
  const Eigen::MatrixXd P = map.covariance();
  out->covariance.assign(P.data(), P.data() + P.size());  // symmetric: column- and row-major agree
}

void toMarkers(const StochasticMap& map, const std_msgs::Header& header, visualization_msgs::MarkerArray* out) {
  out->markers.clear();
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out->markers.push_back(clear);
  int id = 0;
  for (size_t i = 0; i < map.numLines(); ++i) {
    const MapLine l = map.line(i);
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = "lines";
    m.id = id++;
    m.type = visualization_msgs::Marker::LINE_LIST;
    m.pose.orientation.w = 1.0;
    // Width: 2 sigma of r, at least 3 cm so that it stays visible.
    m.scale.x = std::max(0.03, 2.0 * std::sqrt(std::max(0.0, l.line.cov(1, 1))));
    m.color.r = 0.1f;
    m.color.g = 0.8f;
    m.color.b = 1.0f;
    m.color.a = 1.0f;
    geometry_msgs::Point a, b;
    a.x = l.extent_start.x();
    a.y = l.extent_start.y();
    b.x = l.extent_end.x();
    b.y = l.extent_end.y();
    a.z = b.z = 0.1;
    m.points = {a, b};
    out->markers.push_back(m);
  }
  // Robot: 2-sigma ellipse of (x, y).
  const Pose2D p = map.robotPose();
  const Eigen::Matrix2d c = map.robotCovariance().topLeftCorner<2, 2>();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(c);
  visualization_msgs::Marker e;
  e.header = header;
  e.ns = "robot_covariance";
  e.id = id++;
  e.type = visualization_msgs::Marker::CYLINDER;
  e.pose.position.x = p.x;
  e.pose.position.y = p.y;
  const double yaw = std::atan2(eig.eigenvectors()(1, 1), eig.eigenvectors()(0, 1));
  e.pose.orientation.z = std::sin(yaw / 2);
  e.pose.orientation.w = std::cos(yaw / 2);
  e.scale.x = std::max(0.01, 4.0 * std::sqrt(std::max(0.0, eig.eigenvalues()(1))));
  e.scale.y = std::max(0.01, 4.0 * std::sqrt(std::max(0.0, eig.eigenvalues()(0))));
  e.scale.z = 0.02;
  e.color.r = 1.0f;
  e.color.g = 0.3f;
  e.color.b = 0.8f;
  e.color.a = 0.6f;
  out->markers.push_back(e);
}

}  // namespace ekf_local_map
