// Hallway or room, from the shape of the free space seen in one scan.
//
// Rule: the free-space polygon is the fan of the scan points around the sensor (no-return beams and
// long ranges clipped at `horizon`, invalid beams skipped, at most `max_vertices` beams; a scan
// narrower than 360 degrees is closed through the sensor). Its area-weighted second moments give the principal axes, and the
// equal-moment rectangle has length L = sqrt(12 lambda_1) and width W = sqrt(12 lambda_2). Beams
// through open doors widen W, so when a wall (a line of at least min_wall_length within
// wall_parallel_angle of the axis) is seen on each side of the sensor, W is the distance between
// the longest such wall on the left and on the right. A hallway is thin and long:
//     s_width = clamp((hallway_max_width + width_softness - W) / (2 width_softness), 0, 1)
//     s_long  = clamp((L/W - min_elongation) / (full_elongation - min_elongation), 0, 1)
//     s = s_width * s_long;   HALLWAY with confidence s when s >= 0.5, else ROOM with confidence 1 - s.
// Thin spikes (beams through doors) carry little area, so they move the moments little; the
// horizon bounds their effect.
#pragma once

#include "laser_features/line_extractor.h"
#include "laser_features/scan.h"

#include <cstdint>
#include <vector>

namespace laser_features {

enum class PlaceType : uint8_t { kUnknown = 0, kRoom = 1, kHallway = 2 };

struct PlaceEstimate {
  PlaceType type = PlaceType::kUnknown;
  double confidence = 0.0;  // [0, 1], of `type`
  double axis = 0.0;        // rad, direction of the long axis of the free space, in (-pi/2, pi/2]
  double length = 0.0;      // m, L of the equal-moment rectangle
  double width = 0.0;       // m, W of the equal-moment rectangle
};

/// Parameters of PlaceClassifier (each with its unit and default).
struct PlaceClassifierParams {
  double horizon = 8.0;            // m, ranges and no-return beams are clipped here
  double hallway_max_width = 3.5;  // m, free space wider than this (+ softness) is no hallway: the node
                                   // sets building/hallway_max_width - width_softness (the score is 0 at the widest hallway)
  double width_softness = 0.5;     // m, half-width of the soft width threshold
  double min_elongation = 2.0;     // -, L/W at which the hallway score starts to rise
  double full_elongation = 3.5;    // -, L/W at which the elongation score reaches 1
  size_t max_vertices = 180;       // -, the polygon uses at most this many beams, evenly spaced
  double wall_parallel_angle = 0.2618;  // rad (15 deg), walls this parallel to the long axis measure the width
  double min_wall_length = 1.0;    // m, shorter lines do not measure the width
};

class PlaceClassifier {
 public:
  using Params = PlaceClassifierParams;

  explicit PlaceClassifier(const Params& params = Params()) : params_(params) {}
  const Params& params() const { return params_; }

  /// `lines`: the scan's lines (may be empty: then the moment width is used).
  PlaceEstimate classify(const ScanPoints& points, const std::vector<LineSegment>& lines) const;

 private:
  // Distance between the longest walls within wall_parallel_angle of `axis` on the left and on the
  // right of the sensor; 0 when a side has none.
  double wallPairWidth(const std::vector<LineSegment>& lines, double axis) const;

  Params params_;
};

}  // namespace laser_features
