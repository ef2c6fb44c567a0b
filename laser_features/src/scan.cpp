#include "laser_features/scan.h"

#include <algorithm>
#include <cmath>

namespace laser_features {

namespace {

/// Beams kept from a scan: all of them, except that a circular scan keeps one revolution.
size_t beamsInOneRevolution(const ScanView& scan, bool circular) {
  if (!circular) return scan.size;
  const double per_revolution = std::round(kTwoPi / std::abs(scan.angle_increment));
  return std::min(scan.size, static_cast<size_t>(std::max(2.0, per_revolution)));
}

}  // namespace

bool isCircularScan(const ScanView& scan, double tolerance_beams) {
  const double step = std::abs(scan.angle_increment);
  return double(scan.size) * step >= kTwoPi - tolerance_beams * step;
}

std::string validateScan(const ScanView& scan, size_t max_beams) {
  if (scan.ranges == nullptr || scan.size == 0) return "empty scan: no ranges";
  if (!std::isfinite(scan.angle_min)) return "angle_min is not finite";
  const double step = std::abs(scan.angle_increment);
  if (!std::isfinite(scan.angle_increment) || step == 0.0)
    return "angle_increment is zero or not finite";
  if (step > kPi) return "angle_increment is larger than pi";
  if (scan.size > max_beams)
    return "scan has " + std::to_string(scan.size) + " beams, more than max_beams = " +
           std::to_string(max_beams);
  // One extra beam closing the circle (angle_max = angle_min + 2 pi) is common; more is not a scan.
  if (double(scan.size) * step > kTwoPi + 2.0 * step + 1e-9)
    return "beams cover more than one revolution (size * |angle_increment| > 2 pi)";
  if (std::isnan(scan.range_min) || std::isnan(scan.range_max) || !(scan.range_max > scan.range_min))
    return "range_min/range_max are NaN or range_max <= range_min";
  const bool any_valid = std::any_of(scan.ranges, scan.ranges + scan.size, [&](float range) {
    return classifyRange(range, scan.range_min, scan.range_max) == BeamStatus::kValid;
  });
  if (!any_valid) return "no valid range (all NaN, inf, <= 0 or outside [range_min, range_max])";
  return {};
}

std::string validateScanHeader(double angle_min, double angle_max, double angle_increment,
                               size_t num_ranges) {
  if (!std::isfinite(angle_min) || !std::isfinite(angle_max) || !std::isfinite(angle_increment))
    return "angle_min, angle_max or angle_increment is not finite";
  if (angle_increment == 0.0) return "angle_increment is zero";
  const double span = angle_max - angle_min;
  if (span != 0.0 && (span > 0.0) != (angle_increment > 0.0))
    return angle_increment > 0.0 ? "angle_max < angle_min with a positive angle_increment"
                                 : "angle_max > angle_min with a negative angle_increment";
  const double expected = span / angle_increment + 1.0;
  if (std::abs(expected - double(num_ranges)) > 1.5)
    return "ranges has " + std::to_string(num_ranges) +
           " values but angle_min/angle_max/angle_increment give " +
           std::to_string(static_cast<long long>(std::llround(expected)));
  return {};
}

void ScanPoints::reserve(size_t beams) {
  points_.reserve(beams);
  units_.reserve(beams);
}

void ScanPoints::assign(const ScanView& scan, double circular_tolerance_beams) {
  circular_ = isCircularScan(scan, circular_tolerance_beams);
  const size_t n = beamsInOneRevolution(scan, circular_);
  reversed_ = scan.angle_increment < 0.0;
  increment_ = std::abs(scan.angle_increment);
  range_max_ = scan.range_max;
  // Counter-clockwise order: a clockwise scan is read backwards, starting from its last beam.
  first_bearing_ = reversed_ ? scan.angle_min + double(n - 1) * scan.angle_increment : scan.angle_min;

  if (table_angle_min_ != scan.angle_min || table_increment_ != scan.angle_increment ||
      table_size_ != n) {
    units_.resize(n);
    for (size_t i = 0; i < n; ++i) units_[i] = unitVector(first_bearing_ + increment_ * double(i));
    table_angle_min_ = scan.angle_min;
    table_increment_ = scan.angle_increment;
    table_size_ = n;
  }

  points_.resize(n);
  num_valid_ = 0;
  for (size_t i = 0; i < n; ++i) {
    const float range = scan.ranges[reversed_ ? n - 1 - i : i];
    BeamPoint& point = points_[i];
    point.status = classifyRange(range, scan.range_min, scan.range_max);
    if (point.status == BeamStatus::kValid) {
      point.range = range;
      point.p = point.range * units_[i];
      ++num_valid_;
    } else {
      point.range = 0.0;
      point.p.setZero();
    }
  }
}

size_t ScanPoints::indexOfBearing(double bearing) const {
  const size_t n = points_.size();
  if (n == 0 || !std::isfinite(bearing)) return n;
  double offset = normalizeAngle(bearing - first_bearing_);
  if (offset < -0.5 * increment_) offset += kTwoPi;  // bearings just before the first beam round to it
  const double index = std::round(offset / increment_);
  if (circular_) return static_cast<size_t>(index) % n;
  return index < double(n) ? static_cast<size_t>(index) : n;
}

}  // namespace laser_features
