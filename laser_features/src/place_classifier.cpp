#include "laser_features/place_classifier.h"

#include <algorithm>
#include <cmath>

namespace laser_features {

namespace {

/// Area moments of a polygon given as a fan of triangles (0, a, b) around the origin.
struct FanMoments {
  double area = 0.0;
  double mx = 0.0, my = 0.0;             // first moments
  double mxx = 0.0, myy = 0.0, mxy = 0.0;  // second moments about the origin

  // Triangle (0, a, b) with signed area A = (a x b)/2:  int x dA = A (ax + bx)/3,
  // int x^2 dA = A/6 (ax^2 + ax bx + bx^2),  int xy dA = A/12 (2 ax ay + ax by + bx ay + 2 bx by).
  void addTriangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const double A = 0.5 * cross2(a, b);
    area += A;
    mx += A * (a.x() + b.x()) / 3.0;
    my += A * (a.y() + b.y()) / 3.0;
    mxx += A * (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) / 6.0;
    myy += A * (a.y() * a.y() + a.y() * b.y() + b.y() * b.y()) / 6.0;
    mxy += A * (2.0 * a.x() * a.y() + a.x() * b.y() + b.x() * a.y() + 2.0 * b.x() * b.y()) / 12.0;
  }
};

}  // namespace

double PlaceClassifier::wallPairWidth(const std::vector<LineSegment>& lines, double axis) const {
  // The longest wall nearly parallel to the axis on each side of the sensor; their distance apart.
  const double normal_angle = axis + 0.5 * kPi;
  const double parallel = std::cos(params_.wall_parallel_angle);
  double left_length = 0.0, right_length = 0.0, left = 0.0, right = 0.0;
  for (const LineSegment& s : lines) {
    const double length = s.length();
    if (length < params_.min_wall_length) continue;
    const double c = std::cos(s.line.alpha - normal_angle);  // the line's normal against the axis' normal
    if (std::abs(c) < parallel) continue;
    const double offset = s.line.r / std::abs(c);  // distance across the axis (r >= 0)
    if (c > 0 && length > left_length) left_length = length, left = offset;
    if (c < 0 && length > right_length) right_length = length, right = offset;
  }
  return left_length > 0.0 && right_length > 0.0 ? left + right : 0.0;
}

PlaceEstimate PlaceClassifier::classify(const ScanPoints& points, const std::vector<LineSegment>& lines) const {
  PlaceEstimate estimate;
  const double horizon = std::min(params_.horizon, points.rangeMax());
  if (!(horizon > 0.0)) return estimate;

  FanMoments moments;
  bool have_first = false, have_previous = false;
  Eigen::Vector2d first, previous;
  // The shape of the free space needs no more than max_vertices beams: take every stride-th.
  const size_t stride = std::max<size_t>(1, (points.size() + params_.max_vertices - 1) / std::max<size_t>(1, params_.max_vertices));
  for (size_t i = 0; i < points.size(); i += stride) {
    const BeamPoint& point = points[i];
    double range;
    if (point.status == BeamStatus::kValid) range = std::min(point.range, horizon);
    else if (point.status == BeamStatus::kNoReturn) range = horizon;
    else continue;
    const Eigen::Vector2d vertex = range * points.unit(i);
    if (have_previous) moments.addTriangle(previous, vertex);
    if (!have_first) first = vertex, have_first = true;
    previous = vertex;
    have_previous = true;
  }
  if (points.circular() && have_first) moments.addTriangle(previous, first);
  if (!(moments.area > 1e-6)) return estimate;

  // Central second moments per unit area and their eigen-decomposition.
  const double cx = moments.mx / moments.area, cy = moments.my / moments.area;
  const double sxx = moments.mxx / moments.area - cx * cx;
  const double syy = moments.myy / moments.area - cy * cy;
  const double sxy = moments.mxy / moments.area - cx * cy;
  const double half_trace = 0.5 * (sxx + syy);
  const double spread = std::hypot(0.5 * (sxx - syy), sxy);
  const double lambda_long = half_trace + spread;
  const double lambda_short = std::max(half_trace - spread, 1e-12);
  if (!std::isfinite(lambda_long) || !(lambda_long > 0.0)) return estimate;

  estimate.axis = normalizeAngle(0.5 * std::atan2(2.0 * sxy, sxx - syy));
  if (estimate.axis <= -0.5 * kPi) estimate.axis += kPi;
  else if (estimate.axis > 0.5 * kPi) estimate.axis -= kPi;
  estimate.length = std::sqrt(12.0 * lambda_long);
  estimate.width = std::sqrt(12.0 * lambda_short);
  // Beams through open doors and side branches widen the moment rectangle of a hallway; its walls'
  // distance apart does not: use it when a wall is seen on each side.
  const double walls = wallPairWidth(lines, estimate.axis);
  if (walls > 0.0) estimate.width = walls;

  const double softness = std::max(params_.width_softness, 1e-6);
  const double width_score = std::clamp(
      (params_.hallway_max_width + softness - estimate.width) / (2.0 * softness), 0.0, 1.0);
  const double elongation_span = std::max(params_.full_elongation - params_.min_elongation, 1e-6);
  const double long_score = std::clamp(
      (estimate.length / estimate.width - params_.min_elongation) / elongation_span, 0.0, 1.0);
  const double hallway_score = width_score * long_score;
  if (hallway_score >= 0.5) {
    estimate.type = PlaceType::kHallway;
    estimate.confidence = hallway_score;
  } else {
    estimate.type = PlaceType::kRoom;
    estimate.confidence = 1.0 - hallway_score;
  }
  return estimate;
}

}  // namespace laser_features
