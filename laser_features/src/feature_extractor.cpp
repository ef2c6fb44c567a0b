#include "laser_features/feature_extractor.h"

#include <algorithm>

namespace laser_features {

namespace {

bool isFinite(const LineSegment& s) {
  return std::isfinite(s.line.alpha) && std::isfinite(s.line.r) && s.line.cov.allFinite() &&
         s.start.allFinite() && s.end.allFinite();
}
bool isFinite(const Corner& c) {
  return c.position.allFinite() && std::isfinite(c.theta) && c.cov.allFinite() &&
         std::isfinite(c.confidence);
}
bool isFinite(const Opening& o) {
  return o.left.allFinite() && o.right.allFinite() && o.center.allFinite() && std::isfinite(o.theta) &&
         std::isfinite(o.width) && std::isfinite(o.confidence);
}

/// Last line of defence: the extractors already refuse non-finite results, this guarantees it.
template <typename T>
void eraseNonFinite(std::vector<T>* items) {
  items->erase(std::remove_if(items->begin(), items->end(), [](const T& item) { return !isFinite(item); }),
               items->end());
}

}  // namespace

void Features::clear() {
  lines.clear();
  corners.clear();
  openings.clear();
  place_type = PlaceType::kUnknown;
  place_confidence = 0.0;
  place = PlaceEstimate();
}

FeatureExtractor::FeatureExtractor(const Params& params)
    : params_(params),
      line_extractor_(params.lines),
      corner_extractor_(params.corners),
      opening_extractor_(params.openings),
      place_classifier_(params.place) {
  reserve(1024);
}

void FeatureExtractor::reserve(size_t beams) {
  points_.reserve(beams);
  line_extractor_.reserve(beams);
  opening_extractor_.reserve(beams);
}

bool FeatureExtractor::extract(const ScanView& scan, Features* features, std::string* error) {
  features->clear();
  // Capacity for a busy scan, so that steady-state extraction never grows the output vectors.
  features->lines.reserve(256);
  features->corners.reserve(128);
  features->openings.reserve(64);

  std::string problem = validateScan(scan, params_.max_beams);
  if (!problem.empty()) {
    if (error) *error = std::move(problem);
    return false;
  }
  points_.assign(scan, params_.circular_tolerance_beams);
  line_extractor_.extract(points_, &features->lines);
  eraseNonFinite(&features->lines);
  corner_extractor_.extract(features->lines, &features->corners);
  eraseNonFinite(&features->corners);
  features->place = place_classifier_.classify(points_, features->lines);
  if (!std::isfinite(features->place.confidence) || !std::isfinite(features->place.axis) ||
      !std::isfinite(features->place.length) || !std::isfinite(features->place.width))
    features->place = PlaceEstimate();
  features->place_type = features->place.type;
  features->place_confidence = features->place.confidence;
  opening_extractor_.extract(points_, features->lines, features->place, &features->openings);
  eraseNonFinite(&features->openings);
  return true;
}

}  // namespace laser_features
