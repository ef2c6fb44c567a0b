// Corners: two line segments of the scan that meet at their ends (Tomatis, Nourbakhsh & Siegwart 2001
// use them, with an extraction confidence p_c, as topological landmarks).
#pragma once

#include "laser_features/geometry.h"
#include "laser_features/line_extractor.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace laser_features {

struct Corner {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // m, intersection of the two lines, scan frame
  double theta = 0.0;     // rad, bisector of the two walls pointing into the free space (sensor side)
  bool convex = false;    // true: the corner juts into the free space (an edge of a pillar, a box or a
                          // jamb); false: an inner (concave) corner of a room
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // covariance of (x, y, theta)
  double confidence = 0.0;  // p_c in [0, 1]
  uint32_t line_a = 0;      // indices of the two lines in the line list
  uint32_t line_b = 0;
};

/// Parameters of CornerExtractor (each with its unit and default).
struct CornerExtractorParams {
  double min_angle = 0.5236;         // rad (30 deg), lines meeting at a smaller angle make no corner
  double max_end_distance = 0.2;     // m, both segment ends must lie this close to the intersection
  double min_line_distance = 0.05;   // m, lines through the sensor (r below this) have no free side
  double reference_length = 1.0;     // m, segments at least this long give full length support
  int reference_points = 15;         // -, segments with at least this many points give full support
};

class CornerExtractor {
 public:
  using Params = CornerExtractorParams;

  explicit CornerExtractor(const Params& params = Params()) : params_(params) {}
  const Params& params() const { return params_; }

  /// Fills `corners` (cleared first) with the corners formed by pairs of `lines`.
  void extract(const std::vector<LineSegment>& lines, std::vector<Corner>* corners) const;

  /// The corner of two segments, or false when they do not form one.
  bool makeCorner(const LineSegment& a, const LineSegment& b, Corner* corner) const;

 private:
  double support(const LineSegment& segment) const;
  Params params_;
};

}  // namespace laser_features
