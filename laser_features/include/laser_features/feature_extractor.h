// Everything laser_features extracts from one scan: lines with covariance, corners, openings and
// the place type. ROS-free; the node converts sensor_msgs/LaserScan to a ScanView and Features to
// hybrid_slam_msgs/LaserFeatures.
#pragma once

#include "laser_features/corner_extractor.h"
#include "laser_features/geometry.h"
#include "laser_features/line_extractor.h"
#include "laser_features/odometry_consistency.h"
#include "laser_features/opening_extractor.h"
#include "laser_features/place_classifier.h"
#include "laser_features/scan.h"

#include <string>
#include <vector>

namespace laser_features {

/// The features of one scan, in the scan's frame. Reuse one instance across calls: its vectors keep
/// their capacity, so extraction does not allocate once warmed up.
struct Features {
  std::vector<LineSegment> lines;  // counter-clockwise
  std::vector<Corner> corners;
  std::vector<Opening> openings;
  PlaceType place_type = PlaceType::kUnknown;
  double place_confidence = 0.0;  // [0, 1]
  PlaceEstimate place;            // place_type and place_confidence with the free-space axes

  void clear();
};

/// Parameters of FeatureExtractor (each with its unit and default).
struct FeatureExtractorParams {
  LineExtractor::Params lines;        // see line_extractor.h (units and defaults there)
  CornerExtractor::Params corners;    // see corner_extractor.h
  OpeningExtractor::Params openings;  // see opening_extractor.h
  PlaceClassifier::Params place;      // see place_classifier.h
  OdometryConsistencyParams odometry_consistency;  // see odometry_consistency.h (computed by the node)
  size_t max_beams = kDefaultMaxBeams;  // -, longer scans are refused (20000)
  double circular_tolerance_beams = kDefaultCircularToleranceBeams;  // beams (0.5): a scan is
                                      //   circular when n |increment| >= 2 pi - this * |increment|
};

class FeatureExtractor {
 public:
  using Params = FeatureExtractorParams;

  explicit FeatureExtractor(const Params& params = Params());
  const Params& params() const { return params_; }

  /// Pre-sizes all buffers for scans of up to `beams` beams (optional; otherwise the first scans
  /// grow them).
  void reserve(size_t beams);

  /// Extracts the features of `scan` into `features` (cleared first). Returns false and, when
  /// `error` is given, says why when the scan is unusable (see validateScan); `features` is then
  /// empty. Outputs never contain NaN or infinity.
  bool extract(const ScanView& scan, Features* features, std::string* error = nullptr);

  /// The points of the last scan, counter-clockwise (for visualization and tests).
  const ScanPoints& points() const { return points_; }

 private:
  Params params_;
  ScanPoints points_;
  LineExtractor line_extractor_;
  CornerExtractor corner_extractor_;
  OpeningExtractor opening_extractor_;
  PlaceClassifier place_classifier_;
};

}  // namespace laser_features
