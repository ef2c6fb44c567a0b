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

double OdometryConsistency::score(const Keyframe& frame, const ScanPoints& scan,
                                  const Pose2D& frame_in_current) const {
  int compared[2] = {0, 0}, agreeing[2] = {0, 0};  // along, across the dominant wall direction
  for (size_t k = 0; k < frame.points.size(); ++k) {
    const Verdict v = compare(scan, transformPoint(frame_in_current, frame.points[k]));
    if (v == Verdict::kNotCompared) continue;
    ++compared[frame.across[k]];
    if (v == Verdict::kAgrees) ++agreeing[frame.across[k]];
  }
  const int min_points = std::max(1, params_.min_points);
  if (compared[0] + compared[1] < min_points) return -1.0;
  double result = static_cast<double>(agreeing[0] + agreeing[1]) / (compared[0] + compared[1]);
  for (int c = 0; c < 2; ++c) {
    if (compared[c] >= min_points / 2) result = std::min(result, static_cast<double>(agreeing[c]) / compared[c]);
  }
  return result;
}

double OdometryConsistency::bestScore(const Keyframe& frame, const ScanPoints& scan,
                                      const Pose2D& sensor_in_odom) const {
  const Pose2D increment = compose(inverse(sensor_in_odom), frame.pose);  // the frame in this scan's
  double best = score(frame, scan, increment);
  // Real odometry is off by centimetres and a degree or two per step, more on long steps (logs
  // that hold a scan per metre): the best of a small grid of corrections around the increment
  // counts, two levels, coarse then fine. A kidnapping is metres off and stays low.
  if (best < 0.0 || best >= params_.good_enough) return best;
  double dxy = params_.search_xy + params_.search_xy_per_m * increment.translation().norm();
  double dth = params_.search_theta + params_.search_theta_per_rad * std::abs(increment.theta);
  Pose2D centre = increment;
  for (int level = 0; level < 2 && best < params_.good_enough; ++level) {
    Pose2D best_pose = centre;
    for (int i = -1; i <= 1; ++i) {
      for (int j = -1; j <= 1; ++j) {
        for (int k = -1; k <= 1; ++k) {
          if (i == 0 && j == 0 && k == 0) continue;
          // The correction acts in the current frame: a small pose error of the robot now.
          const Pose2D candidate = compose(Pose2D{i * dxy, j * dxy, k * dth}, centre);
          const double s = score(frame, scan, candidate);
          if (s > best) {
            best = s;
            best_pose = candidate;
          }
        }
      }
    }
    centre = best_pose;
    dxy /= 3.0;
    dth /= 3.0;
  }
  return best;
}

double OdometryConsistency::update(const ScanPoints& scan, const Pose2D& sensor_in_odom) {
  double result = -1.0;
  if (reference_.valid) {
    // The pair before was doubtful: does this scan agree with the scan from before it?
    result = bestScore(reference_, scan, sensor_in_odom);
    reference_.valid = false;
  } else if (previous_.valid) {
    result = bestScore(previous_, scan, sensor_in_odom);
    if (result >= 0.0 && result < params_.recheck_below) {
      std::swap(reference_, previous_);  // keep the scan before the doubtful pair; report later
      result = -1.0;
    }
  }
  remember(scan, sensor_in_odom, &previous_);
  return result;
}

void OdometryConsistency::remember(const ScanPoints& scan, const Pose2D& pose, Keyframe* frame) {
  frame->points.clear();
  frame->normals.clear();
  frame->pose = pose;
  frame->valid = true;
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
    frame->points.push_back(b.p);
    frame->normals.push_back(normal);
  }
  const double dominant = 0.5 * std::atan2(s2, c2);
  frame->across.resize(frame->points.size());
  for (size_t k = 0; k < frame->points.size(); ++k) {
    // |cos| of the angle between the normal and the dominant axis; a lone point counts as along.
    frame->across[k] = std::isfinite(frame->normals[k]) && std::abs(std::cos(frame->normals[k] - dominant)) < std::sqrt(0.5);
  }
}

}  // namespace laser_features
