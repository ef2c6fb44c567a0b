#include "laser_features/odometry_consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace laser_features {
namespace {

double distanceToSegment(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - q).norm();
}

}  // namespace

OdometryConsistency::OdometryConsistency(const OdometryConsistencyParams& params) : params_(params) {}

OdometryConsistency::Verdict OdometryConsistency::compare(const ScanPoints& scan, const Eigen::Vector2d& q) const {
  const size_t n = scan.size();
  const size_t i = scan.indexOfBearing(std::atan2(q.y(), q.x()));
  if (i >= n) return Verdict::kNotCompared;  // outside the new field of view
  const BeamPoint& beam = scan[i];
  if (beam.status == BeamStatus::kInvalid) return Verdict::kNotCompared;  // the new beam says nothing
  const double tolerance = params_.tolerance + params_.tolerance_per_m * q.norm();
  if (beam.status == BeamStatus::kNoReturn)
    return q.norm() > scan.rangeMax() - tolerance ? Verdict::kAgrees : Verdict::kDisagrees;
  double best = (beam.p - q).norm();
  // The new scan's polyline two beams each side of the bearing (wrapping round a full circle).
  for (int k = -2; k < 2; ++k) {
    const long a = static_cast<long>(i) + k, b = a + 1;
    if (!scan.circular() && (a < 0 || b >= static_cast<long>(n))) continue;
    const BeamPoint& pa = scan[static_cast<size_t>((a + static_cast<long>(n)) % static_cast<long>(n))];
    const BeamPoint& pb = scan[static_cast<size_t>((b + static_cast<long>(n)) % static_cast<long>(n))];
    if (pa.status != BeamStatus::kValid || pb.status != BeamStatus::kValid) continue;
    if ((pa.p - pb.p).norm() > params_.max_gap) continue;
    best = std::min(best, distanceToSegment(q, pa.p, pb.p));
  }
  return best <= tolerance ? Verdict::kAgrees : Verdict::kDisagrees;
}

double OdometryConsistency::update(const ScanPoints& scan, const Pose2D& previous_in_current) {
  int compared[2] = {0, 0}, agreeing[2] = {0, 0};  // along, across the dominant wall direction
  for (size_t k = 0; k < previous_.size(); ++k) {
    const Verdict v = compare(scan, transformPoint(previous_in_current, previous_[k]));
    if (v == Verdict::kNotCompared) continue;
    ++compared[across_[k]];
    if (v == Verdict::kAgrees) ++agreeing[across_[k]];
  }
  double result = -1.0;
  if (compared[0] + compared[1] >= params_.min_points) {
    result = static_cast<double>(agreeing[0] + agreeing[1]) / (compared[0] + compared[1]);
    for (int c = 0; c < 2; ++c) {
      if (compared[c] >= params_.min_points / 2) result = std::min(result, static_cast<double>(agreeing[c]) / compared[c]);
    }
  }
  remember(scan);
  return result;
}

void OdometryConsistency::remember(const ScanPoints& scan) {
  previous_.clear();
  normals_.clear();
  const size_t n = scan.size();
  double c2 = 0.0, s2 = 0.0;  // the dominant normal direction, as a doubled angle (axial mean)
  for (size_t i = 0; i < n; ++i) {
    const BeamPoint& b = scan[i];
    if (b.status != BeamStatus::kValid || b.range > params_.max_range) continue;
    // The surface direction from the neighbours on the same surface; NaN where there are none.
    const BeamPoint& prev = scan[(i + n - 1) % n];
    const BeamPoint& next = scan[(i + 1) % n];
    const bool has_prev = (i > 0 || scan.circular()) && prev.status == BeamStatus::kValid && (prev.p - b.p).norm() < params_.max_gap;
    const bool has_next = (i + 1 < n || scan.circular()) && next.status == BeamStatus::kValid && (next.p - b.p).norm() < params_.max_gap;
    double normal = std::numeric_limits<double>::quiet_NaN();
    if (has_prev || has_next) {
      const Eigen::Vector2d d = (has_next ? next.p : b.p) - (has_prev ? prev.p : b.p);
      normal = std::atan2(d.x(), -d.y());  // the surface direction turned by 90 degrees
      c2 += std::cos(2 * normal);
      s2 += std::sin(2 * normal);
    }
    previous_.push_back(b.p);
    normals_.push_back(normal);
  }
  const double dominant = 0.5 * std::atan2(s2, c2);
  across_.resize(previous_.size());
  for (size_t k = 0; k < previous_.size(); ++k) {
    // |cos| of the angle between the normal and the dominant axis; a lone point counts as along.
    across_[k] = std::isfinite(normals_[k]) && std::abs(std::cos(normals_[k] - dominant)) < std::sqrt(0.5);
  }
}

}  // namespace laser_features
