// The whole extractor: bad input (each case its own test: an error or empty features, never a crash
// or a NaN), clockwise scanners, very long scans, garbage, determinism.
#include "laser_features/feature_extractor.h"

#include "synthetic_scan.h"
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <random>

namespace laser_features {
namespace {

using namespace synthetic;
using testing_helpers::allFinite;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

ScanView fullScan(const std::vector<float>& ranges) {
  ScanView view;
  view.angle_min = -kPi;
  view.angle_increment = ranges.empty() ? 0.01 : kTwoPi / double(ranges.size());
  view.range_min = 0.1;
  view.range_max = 15.0;
  view.ranges = ranges.data();
  view.size = ranges.size();
  return view;
}

/// Runs the extractor on a scan that must be refused; checks the error and the empty output.
void expectRefused(const ScanView& view, FeatureExtractor* extractor = nullptr) {
  FeatureExtractor default_extractor;
  if (!extractor) extractor = &default_extractor;
  Features features;
  features.lines.resize(3);  // stale content must be cleared
  features.place_type = PlaceType::kHallway;
  std::string error;
  EXPECT_FALSE(extractor->extract(view, &features, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_TRUE(features.lines.empty());
  EXPECT_TRUE(features.corners.empty());
  EXPECT_TRUE(features.openings.empty());
  EXPECT_EQ(features.place_type, PlaceType::kUnknown);
  EXPECT_TRUE(allFinite(features));
}

/// Runs the extractor on a scan that it may accept or refuse; the output must be finite either way.
Features expectNoNaN(const ScanView& view, FeatureExtractor* extractor = nullptr) {
  FeatureExtractor default_extractor;
  if (!extractor) extractor = &default_extractor;
  Features features;
  extractor->extract(view, &features);
  EXPECT_TRUE(allFinite(features));
  return features;
}

TEST(BadInput, EmptyScan) { expectRefused(fullScan({})); }

TEST(BadInput, NullRanges) {
  ScanView view = fullScan({});
  view.size = 100;
  expectRefused(view);
}

TEST(BadInput, AllNaN) { expectRefused(fullScan(std::vector<float>(720, kNaN))); }

TEST(BadInput, AllPositiveInfinity) { expectRefused(fullScan(std::vector<float>(720, kInf))); }

TEST(BadInput, AllNegativeInfinity) { expectRefused(fullScan(std::vector<float>(720, -kInf))); }

TEST(BadInput, EveryRangeZero) { expectRefused(fullScan(std::vector<float>(720, 0.0f))); }

TEST(BadInput, EveryRangeOutsideLimits) {
  expectRefused(fullScan(std::vector<float>(720, 0.05f)));   // below range_min
  expectRefused(fullScan(std::vector<float>(720, 20.0f)));   // beyond range_max
  expectRefused(fullScan(std::vector<float>(720, -1.0f)));   // negative
}

TEST(BadInput, SingleBeam) {
  const std::vector<float> ranges = {2.0f};
  ScanView view = fullScan(ranges);
  view.angle_increment = 0.01;
  const Features features = expectNoNaN(view);
  EXPECT_TRUE(features.lines.empty());
  EXPECT_TRUE(features.corners.empty());
  EXPECT_TRUE(features.openings.empty());
}

TEST(BadInput, ZeroIncrement) {
  const std::vector<float> ranges(720, 2.0f);
  ScanView view = fullScan(ranges);
  view.angle_increment = 0.0;
  expectRefused(view);
}

TEST(BadInput, NaNOrInfiniteIncrement) {
  const std::vector<float> ranges(720, 2.0f);
  ScanView view = fullScan(ranges);
  view.angle_increment = std::nan("");
  expectRefused(view);
  view.angle_increment = -std::numeric_limits<double>::infinity();
  expectRefused(view);
  view.angle_increment = 0.01;
  view.angle_min = std::nan("");
  expectRefused(view);
}

// A negative increment is a clockwise scanner, not an error: the same scene gives the same lines.
TEST(BadInput, NegativeIncrementIsAClockwiseScan) {
  const World room = roomWithDoor(2.5, 0.9);
  const Pose2D sensor{2.0, 2.0, 0.4};
  ScanSpec ccw = ScanSpec::full(720, -kPi);
  ScanSpec cw = ccw;
  cw.angle_min = kPi - ccw.angle_increment;  // the same beams in the opposite order
  cw.angle_increment = -ccw.angle_increment;
  const std::vector<float> ranges = simulateScan(room, sensor, ccw, 0.0, nullptr);
  const std::vector<float> reversed(ranges.rbegin(), ranges.rend());
  FeatureExtractor extractor;
  Features a, b;
  ASSERT_TRUE(extractor.extract(makeView(ccw, ranges), &a));
  ASSERT_TRUE(extractor.extract(makeView(cw, reversed), &b));
  ASSERT_EQ(a.lines.size(), b.lines.size());
  for (size_t i = 0; i < a.lines.size(); ++i) {
    EXPECT_NEAR(a.lines[i].line.alpha, b.lines[i].line.alpha, 1e-9);
    EXPECT_NEAR(a.lines[i].line.r, b.lines[i].line.r, 1e-9);
  }
  EXPECT_EQ(a.corners.size(), b.corners.size());
  EXPECT_EQ(a.openings.size(), b.openings.size());
}

TEST(BadInput, InconsistentAngles) {
  // angle_max < angle_min with a positive increment, and a range count that does not match.
  EXPECT_NE(validateScanHeader(1.0, -1.0, 0.01, 201), "");
  EXPECT_NE(validateScanHeader(-kPi, kPi, kTwoPi / 720, 360), "");
  // Beams that claim to cover two revolutions.
  const std::vector<float> ranges(720, 2.0f);
  ScanView view = fullScan(ranges);
  view.angle_increment = 2.0 * kTwoPi / 720;
  expectRefused(view);
}

TEST(BadInput, BadRangeLimits) {
  const std::vector<float> ranges(720, 2.0f);
  ScanView view = fullScan(ranges);
  view.range_max = std::nan("");
  expectRefused(view);
  view.range_max = 0.05;  // below range_min
  expectRefused(view);
}

TEST(BadInput, HundredThousandBeams) {
  std::vector<float> ranges(100000);
  for (size_t i = 0; i < ranges.size(); ++i) ranges[i] = 3.0f + 0.5f * std::sin(0.001f * float(i));
  // Refused by default (max_beams = 20000) ...
  expectRefused(fullScan(ranges));
  // ... and handled, in bounded time, when allowed.
  FeatureExtractor::Params params;
  params.max_beams = 100000;
  FeatureExtractor extractor(params);
  const auto start = std::chrono::steady_clock::now();
  expectNoNaN(fullScan(ranges), &extractor);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0);
}

TEST(BadInput, IsolatedValidBeams) {
  // Valid beams scattered among NaNs: too few for any line, no crash.
  std::vector<float> ranges(720, kNaN);
  for (size_t i = 0; i < ranges.size(); i += 37) ranges[i] = 2.0f;
  const Features features = expectNoNaN(fullScan(ranges));
  EXPECT_TRUE(features.lines.empty());
}

TEST(BadInput, RandomGarbageNeverGivesNaN) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const float specials[] = {kNaN, kInf, -kInf, 0.0f, -1.0f, 1e-30f, 1e30f, 3.4e38f, 1e-3f};
  FeatureExtractor extractor;
  for (int trial = 0; trial < 300; ++trial) {
    const size_t n = 1 + size_t(unit(rng) * 3000);
    std::vector<float> ranges(n);
    for (float& range : ranges) {
      const double u = unit(rng);
      range = u < 0.2 ? specials[size_t(unit(rng) * 9) % 9] : float(unit(rng) * 20.0);
    }
    ScanView view;
    view.angle_min = (unit(rng) - 0.5) * 20.0;
    view.angle_increment = (unit(rng) - 0.5) * 2.0 * (unit(rng) < 0.5 ? kTwoPi / double(n) : 0.1);
    view.range_min = unit(rng) < 0.5 ? 0.0 : 0.1;
    view.range_max = unit(rng) < 0.3 ? std::numeric_limits<double>::infinity() : 15.0;
    view.ranges = ranges.data();
    view.size = n;
    expectNoNaN(view, &extractor);
  }
}

TEST(FeatureExtractor, ReusedOutputIsClearedAfterAnError) {
  const World room = roomWithDoor(2.5, 0.9);
  const ScanSpec spec = ScanSpec::full(720);
  const std::vector<float> ranges = simulateScan(room, {2.0, 2.0, 0.0}, spec, 0.0, nullptr);
  FeatureExtractor extractor;
  Features features;
  ASSERT_TRUE(extractor.extract(makeView(spec, ranges), &features));
  EXPECT_FALSE(features.lines.empty());
  std::string error;
  EXPECT_FALSE(extractor.extract(fullScan(std::vector<float>(720, kNaN)), &features, &error));
  EXPECT_TRUE(features.lines.empty());
  EXPECT_TRUE(features.openings.empty());
}

TEST(FeatureExtractor, IsDeterministic) {
  std::mt19937 rng(5);
  const ScanSpec spec = ScanSpec::full(720);
  const std::vector<float> ranges = simulateScan(officeScene(), {3.5, 2.5, 0.2}, spec, 0.01, &rng);
  FeatureExtractor extractor;
  Features a, b;
  ASSERT_TRUE(extractor.extract(makeView(spec, ranges), &a));
  ASSERT_TRUE(extractor.extract(makeView(spec, ranges), &b));
  ASSERT_EQ(a.lines.size(), b.lines.size());
  for (size_t i = 0; i < a.lines.size(); ++i) EXPECT_EQ(a.lines[i].line.params(), b.lines[i].line.params());
  EXPECT_EQ(a.corners.size(), b.corners.size());
  EXPECT_EQ(a.openings.size(), b.openings.size());
  EXPECT_EQ(a.place_type, b.place_type);
}

TEST(FeatureExtractor, OfficeSceneAtEveryResolution) {
  std::mt19937 rng(6);
  for (const size_t beams : {361u, 720u, 1440u, 2880u}) {
    const ScanSpec spec = ScanSpec::full(beams);
    const std::vector<float> ranges = simulateScan(officeScene(), {3.5, 2.5, 0.2}, spec, 0.01, &rng);
    FeatureExtractor extractor;
    Features features;
    ASSERT_TRUE(extractor.extract(makeView(spec, ranges), &features));
    EXPECT_TRUE(allFinite(features));
    EXPECT_GE(features.lines.size(), 8u) << beams;
    EXPECT_EQ(features.place_type, PlaceType::kRoom) << beams;
    int doors = 0;
    for (const Opening& opening : features.openings) doors += opening.kind == OpeningKind::kDoor;
    EXPECT_EQ(doors, 2) << beams;  // the two doors of the office
  }
}

}  // namespace
}  // namespace laser_features
