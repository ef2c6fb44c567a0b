// The weighted total least-squares fit of a line (alpha, r) to scan points, with its 2x2
// covariance propagated to first order from the range and bearing noise (Arras & Siegwart 1997,
// SPIE vol. 3210; Pfister et al. 2003, ICRA). LineExtractor fits its pieces with it.
//
// ROS-free, no allocation.
#pragma once

#include "laser_features/geometry.h"
#include "laser_features/scan.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace laser_features {

class WeightedLineFit {
 public:
  /// range_sigma (m, > 0) + range_sigma_per_meter (m/m, >= 0) * range is the range noise's
  /// standard deviation, bearing_sigma (rad, >= 0) the bearing's.
  WeightedLineFit(double range_sigma, double range_sigma_per_meter, double bearing_sigma);

  /// m, the range noise's standard deviation at `range`.
  double rangeSigma(double range) const { return range_sigma_ + range_sigma_per_meter_ * range; }
  /// Weight of a point in the fit, 1 / sigma_rho^2.
  double weight(double range) const {
    if (constant_weight_ > 0.0) return constant_weight_;
    const double sigma = rangeSigma(range);
    return 1.0 / (sigma * sigma);
  }
  /// Fits the valid points with virtual indices in [begin, end] (see ScanPoints::wrap), leaving out
  /// those flagged in `ignored` (per beam; null: none). False when fewer than two points or the fit
  /// is degenerate.
  bool fit(const ScanPoints& points, size_t begin, size_t end, const std::vector<uint8_t>* ignored, Line* line,
           uint32_t* num_points) const;

 private:
  double range_sigma_, range_sigma_per_meter_, bearing_sigma_;
  double constant_weight_ = 0.0;  // 1 / range_sigma^2 when the noise does not grow with range
};

}  // namespace laser_features
