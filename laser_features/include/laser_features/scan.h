// A non-owning view of a 2D laser scan (the fields of sensor_msgs/LaserScan that matter, without
// ROS), its validation, and ScanPoints: the scan converted once per call into counter-clockwise
// Cartesian points that every extractor reads.
#pragma once

#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace laser_features {

/// Beam i has bearing angle_min + i * angle_increment (either sign) and range ranges[i].
struct ScanView {
  double angle_min = 0.0;        // rad, bearing of ranges[0]
  double angle_increment = 0.0;  // rad, signed; negative for clockwise scanners
  double range_min = 0.0;        // m, shorter readings are invalid
  double range_max = std::numeric_limits<double>::infinity();  // m, longer readings mean no return
  const float* ranges = nullptr;  // not owned; must outlive the call that reads it
  size_t size = 0;
};

/// What one range reading says (REP 117).
enum class BeamStatus : uint8_t {
  kValid,     // a hit in [range_min, range_max]
  kNoReturn,  // +inf or beyond range_max: free space at least up to range_max
  kInvalid,   // NaN, -inf (too close), <= 0, or below range_min: no information
};

inline BeamStatus classifyRange(float range, double range_min, double range_max) {
  if (std::isnan(range) || range <= 0.0f || range < range_min) return BeamStatus::kInvalid;
  if (range > range_max || std::isinf(range)) return BeamStatus::kNoReturn;
  return BeamStatus::kValid;
}

/// Default limit on the beam count; longer scans are refused rather than processed slowly.
constexpr size_t kDefaultMaxBeams = 20000;

/// The angular gap (in increments) allowed between the last and the first beam of a scan that is
/// still treated as a full circle: a scan is circular when  n |increment| >= 2 pi - tolerance |increment|.
constexpr double kDefaultCircularToleranceBeams = 0.5;

/// True when the beams cover the full circle (the first beam follows the last one).
bool isCircularScan(const ScanView& scan, double tolerance_beams = kDefaultCircularToleranceBeams);

/// Checks a scan before extraction. Returns an empty string when the scan is usable, otherwise what
/// is wrong with it: no ranges; non-finite angle_min; zero, non-finite or > pi increment; more than
/// one revolution; more than `max_beams` beams; NaN or inconsistent range_min/range_max; no valid
/// beam at all. Cost: one pass over the ranges; allocates only when it reports an error.
std::string validateScan(const ScanView& scan, size_t max_beams = kDefaultMaxBeams);

/// Checks the redundant header fields of a sensor_msgs/LaserScan-like message (the node calls this
/// before building a ScanView): finite angles, a non-zero increment whose sign agrees with
/// angle_max - angle_min (so angle_max < angle_min with a positive increment is refused), and a
/// range count that agrees with (angle_max - angle_min) / angle_increment + 1 within one beam.
std::string validateScanHeader(double angle_min, double angle_max, double angle_increment,
                               size_t num_ranges);

/// One beam in counter-clockwise order.
struct BeamPoint {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();  // m, Cartesian point in the scan frame (0 if not valid)
  double range = 0.0;                           // m (0 if not valid)
  BeamStatus status = BeamStatus::kInvalid;
};

/// The scan as Cartesian points in counter-clockwise order (ascending bearing), whatever the sign of
/// the increment, so that downstream code can assume a positive increment. A circular scan that
/// covers more than one revolution keeps exactly one. Buffers (and the bearing table, rebuilt only
/// when the scan geometry changes) are reused across calls: no allocation once warmed up.
class ScanPoints {
 public:
  /// `scan` must have passed validateScan.
  void assign(const ScanView& scan, double circular_tolerance_beams = kDefaultCircularToleranceBeams);
  /// Pre-sizes the buffers for scans of up to `beams` beams.
  void reserve(size_t beams);

  size_t size() const { return points_.size(); }
  size_t numValid() const { return num_valid_; }
  bool circular() const { return circular_; }
  double increment() const { return increment_; }     // rad, > 0
  double rangeMax() const { return range_max_; }      // m, as in the scan
  double bearing(size_t i) const { return normalizeAngle(first_bearing_ + increment_ * double(i)); }
  const Eigen::Vector2d& unit(size_t i) const { return units_[i]; }  // (cos, sin) of the bearing
  const BeamPoint& operator[](size_t i) const { return points_[i]; }
  /// Index of internal beam i in ScanView::ranges.
  size_t sourceIndex(size_t i) const { return reversed_ ? points_.size() - 1 - i : i; }

  /// Wraps an index of the "virtual" sequence used to walk a circular scan through its seam
  /// (i in [0, 3 size)) back to [0, size).
  size_t wrap(size_t i) const {
    while (i >= points_.size() && !points_.empty()) i -= points_.size();
    return i;
  }
  /// Calls f(i, v) for the virtual indices v in [begin, end] (inclusive) in order, with i = wrap(v),
  /// walking contiguous stretches of the buffer (no wrapping per element).
  template <typename F>
  void forEachIndex(size_t begin, size_t end, F&& f) const {
    const size_t n = points_.size();
    for (size_t v = begin; v <= end && n > 0;) {
      const size_t first = wrap(v);
      const size_t count = std::min(end - v + 1, n - first);
      for (size_t k = 0; k < count; ++k) f(first + k, v + k);
      v += count;
    }
  }

  /// Internal index whose bearing is nearest to `bearing`, or size() when it is outside the scan.
  size_t indexOfBearing(double bearing) const;

 private:
  std::vector<BeamPoint> points_;
  std::vector<Eigen::Vector2d> units_;
  size_t num_valid_ = 0;
  bool circular_ = false;
  bool reversed_ = false;
  double first_bearing_ = 0.0;
  double increment_ = 0.0;
  double range_max_ = 0.0;
  // Key of the cached bearing table.
  double table_angle_min_ = std::numeric_limits<double>::quiet_NaN();
  double table_increment_ = std::numeric_limits<double>::quiet_NaN();
  size_t table_size_ = 0;
};

}  // namespace laser_features
