#include "laser_features/corner_extractor.h"

#include <algorithm>
#include <cmath>

namespace laser_features {

namespace {

/// The end of `segment` nearest to `p`, its distance to `p`, and the other (far) end.
struct NearEnd {
  double distance;
  Eigen::Vector2d far_end;
};

NearEnd nearEnd(const LineSegment& segment, const Eigen::Vector2d& p) {
  const double to_start = (segment.start - p).norm();
  const double to_end = (segment.end - p).norm();
  return to_start <= to_end ? NearEnd{to_start, segment.end} : NearEnd{to_end, segment.start};
}

}  // namespace

// How much a segment supports a corner: long segments with many points make sure corners.
double CornerExtractor::support(const LineSegment& segment) const {
  const double by_length = std::min(1.0, segment.length() / params_.reference_length);
  const double by_points = std::min(1.0, double(segment.num_points) / double(std::max(1, params_.reference_points)));
  return by_length * by_points;
}

bool CornerExtractor::makeCorner(const LineSegment& a, const LineSegment& b, Corner* corner) const {
  // Ends within max_end_distance of one point are within twice that of each other: a cheap first test.
  const double reach = 2.0 * params_.max_end_distance;
  const double closest_ends = std::min(std::min((a.start - b.start).squaredNorm(), (a.start - b.end).squaredNorm()),
                                       std::min((a.end - b.start).squaredNorm(), (a.end - b.end).squaredNorm()));
  if (!(closest_ends <= reach * reach)) return false;
  if (angleBetweenLines(a.line, b.line) < params_.min_angle) return false;
  if (a.line.r < params_.min_line_distance || b.line.r < params_.min_line_distance) return false;
  Eigen::Vector2d p;
  Matrix24d J_p;
  if (!intersectLines(a.line, b.line, &p, &J_p)) return false;
  const NearEnd end_a = nearEnd(a, p);
  const NearEnd end_b = nearEnd(b, p);
  const double worst_end = std::max(end_a.distance, end_b.distance);
  if (!(worst_end <= params_.max_end_distance)) return false;

  // Both normals point away from the sensor (r >= 0), so the sensor side of both walls, the free
  // space at the corner, is around -(n_a + n_b); its direction is (alpha_a + alpha_b)/2 + pi, which
  // gives d(theta)/d(alpha_a) = d(theta)/d(alpha_b) = 1/2.
  const Eigen::Vector2d free_direction = -(a.line.normal() + b.line.normal());
  if (!(free_direction.squaredNorm() > 1e-12)) return false;
  // The walls leave the corner along u_a and u_b; when the wedge between them is the free side the
  // corner is concave (a room's inner corner), otherwise the free space wraps around it: convex.
  const Eigen::Vector2d u_a = end_a.far_end - p;
  const Eigen::Vector2d u_b = end_b.far_end - p;
  const Eigen::Vector2d wedge = u_a.normalized() + u_b.normalized();

  Eigen::Matrix<double, 3, 4> J;
  J.topRows<2>() = J_p;
  J.row(2) << 0.5, 0.0, 0.5, 0.0;
  Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
  C.topLeftCorner<2, 2>() = a.line.cov;
  C.bottomRightCorner<2, 2>() = b.line.cov;

  corner->position = p;
  corner->theta = std::atan2(free_direction.y(), free_direction.x());
  corner->convex = wedge.dot(free_direction) < 0.0;
  corner->cov = J * C * J.transpose();
  // p_c: support of both segments times how well their ends close the corner.
  const double closeness = 1.0 - (worst_end / params_.max_end_distance) * (worst_end / params_.max_end_distance);
  corner->confidence = std::clamp(std::sqrt(support(a) * support(b)) * closeness, 0.0, 1.0);
  return corner->position.allFinite() && corner->cov.allFinite() && std::isfinite(corner->theta);
}

void CornerExtractor::extract(const std::vector<LineSegment>& lines, std::vector<Corner>* corners) const {
  corners->clear();
  Corner corner;
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = i + 1; j < lines.size(); ++j) {
      if (!makeCorner(lines[i], lines[j], &corner)) continue;
      corner.line_a = uint32_t(i);
      corner.line_b = uint32_t(j);
      corners->push_back(corner);
    }
  }
}

}  // namespace laser_features
