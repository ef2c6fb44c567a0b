// libFuzzer target for the core extractor: any bytes become a ScanView, the extractor runs, and every
// output must be finite and within its documented range (a violation aborts).
//
//   clang++-14 -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -Iinclude -I/usr/include/eigen3 \
//       src/*.cpp test/fuzz_feature_extractor.cpp -o fuzz_feature_extractor
//   ./fuzz_feature_extractor -max_total_time=30 -max_len=16384 corpus/
//
// Built with -DLASER_FEATURES_FUZZ_STANDALONE (any compiler, no libFuzzer) it runs the files given on
// the command line, or a few thousand pseudo-random inputs when given none, so that ctest can run it.
//
// Input layout: byte 0 picks the decoder.
//  - even: raw. angle_min, angle_increment, range_min, range_max as 4 floats, then the ranges as
//    floats: reaches every validation branch and the arithmetic extremes.
//  - odd: structured. byte 1 the beam layout (full circle, 180 degrees, either direction, off by a
//    little), byte 2 angle_min, then ranges as uint16 millimetres (0xFFFF = +inf, 0xFFFE = NaN,
//    0xFFFD = -inf): reaches the extractors with plausible scans.
#include "laser_features/feature_extractor.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace laser_features;

void require(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz_feature_extractor: violated: %s\n", what);
  std::abort();
}

bool isAngle(double a) { return std::isfinite(a) && a > -kPi - 1e-12 && a <= kPi + 1e-12; }

void checkFeatures(const Features& f) {
  for (const LineSegment& s : f.lines) {
    require(isAngle(s.line.alpha), "line alpha in (-pi, pi]");
    require(std::isfinite(s.line.r) && s.line.r >= 0.0, "line r finite and >= 0");
    require(s.line.cov.allFinite() && s.line.cov(0, 0) >= 0.0 && s.line.cov(1, 1) >= 0.0, "line covariance");
    require(s.start.allFinite() && s.end.allFinite(), "line end points");
    require(s.num_points >= 2, "line points");
  }
  for (const Corner& c : f.corners) {
    require(c.position.allFinite() && isAngle(c.theta), "corner pose");
    require(c.cov.allFinite(), "corner covariance");
    require(c.confidence >= 0.0 && c.confidence <= 1.0, "corner confidence");
  }
  for (const Opening& o : f.openings) {
    require(o.left.allFinite() && o.right.allFinite() && o.center.allFinite(), "opening points");
    require(isAngle(o.theta) && std::isfinite(o.width) && o.width > 0.0, "opening theta and width");
    require(o.confidence >= 0.0 && o.confidence <= 1.0, "opening confidence");
  }
  require(f.place_confidence >= 0.0 && f.place_confidence <= 1.0, "place confidence");
  require(std::isfinite(f.place.axis) && std::isfinite(f.place.length) && std::isfinite(f.place.width), "place");
}

float readFloat(const uint8_t* p) {
  float value;
  std::memcpy(&value, p, sizeof(value));
  return value;
}

/// Decodes the input; false when it is too short to be a scan.
bool decode(const uint8_t* data, size_t size, ScanView* view, std::vector<float>* ranges) {
  if (size < 1) return false;
  if ((data[0] & 1) == 0) {
    if (size < 17) return false;
    view->angle_min = readFloat(data + 1);
    view->angle_increment = readFloat(data + 5);
    view->range_min = readFloat(data + 9);
    view->range_max = readFloat(data + 13);
    ranges->resize((size - 17) / 4);
    for (size_t i = 0; i < ranges->size(); ++i) (*ranges)[i] = readFloat(data + 17 + 4 * i);
  } else {
    if (size < 3) return false;
    const uint8_t layout = data[1];
    ranges->resize((size - 3) / 2);
    const double n = double(std::max<size_t>(ranges->size(), 2));
    const bool full = (layout & 1) != 0;
    const double nominal = full ? kTwoPi / n : kPi / (n - 1.0);
    const double stretch = 1.0 + (double((layout >> 2) & 0x3f) - 32.0) * 1e-3;  // +-3 %
    view->angle_increment = ((layout & 2) != 0 ? -nominal : nominal) * stretch;
    view->angle_min = (double(data[2]) - 128.0) / 128.0 * kPi;
    view->range_min = 0.05;
    view->range_max = 15.0;
    for (size_t i = 0; i < ranges->size(); ++i) {
      const uint16_t raw = uint16_t(data[3 + 2 * i] | (data[4 + 2 * i] << 8));
      (*ranges)[i] = raw == 0xFFFF   ? std::numeric_limits<float>::infinity()
                     : raw == 0xFFFE ? std::numeric_limits<float>::quiet_NaN()
                     : raw == 0xFFFD ? -std::numeric_limits<float>::infinity()
                                     : float(raw) / 1000.0f;
    }
  }
  view->ranges = ranges->data();
  view->size = ranges->size();
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // One extractor for all inputs, as in the node: state carried between scans must not break it.
  static FeatureExtractor extractor;
  static Features features;
  static std::vector<float> ranges;
  ScanView view;
  if (!decode(data, size, &view, &ranges)) return 0;
  std::string error;
  const bool ok = extractor.extract(view, &features, &error);
  require(ok == error.empty(), "an error string exactly when extraction fails");
  if (!ok) require(features.lines.empty() && features.corners.empty() && features.openings.empty(), "empty on error");
  checkFeatures(features);
  return 0;
}

#ifdef LASER_FEATURES_FUZZ_STANDALONE
int main(int argc, char** argv) {
  if (argc > 1) {
    for (int i = 1; i < argc; ++i) {
      std::FILE* file = std::fopen(argv[i], "rb");
      if (!file) continue;
      std::vector<uint8_t> bytes;
      for (int c; (c = std::fgetc(file)) != EOF;) bytes.push_back(uint8_t(c));
      std::fclose(file);
      LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
    }
    return 0;
  }
  uint32_t state = 12345;
  const auto next = [&]() { return state = state * 1664525u + 1013904223u; };
  for (int trial = 0; trial < 5000; ++trial) {
    std::vector<uint8_t> bytes(1 + next() % 6000);
    for (uint8_t& b : bytes) b = uint8_t(next() >> 24);
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  }
  std::printf("fuzz_feature_extractor: 5000 pseudo-random inputs, no violation\n");
  return 0;
}
#endif
